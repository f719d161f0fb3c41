"""Reading pose files and writing trajectory files.

``readers`` turns JSON or YAML into validated robotics-layout matrices and motion parameters,
with errors that name the file, the key and the line; ``jobscan`` scans JSON Lines jobs files
line by line, the common forms fast. ``writers`` turns sampled motions into CSV layouts, TUM,
KITTI and MCAP, with numbers formatted by ``floatrepr`` and built into MCAP by
``mcapwriter``, on a second thread (``parallel``). ``atomic`` puts output in place only when
it is complete.
"""
