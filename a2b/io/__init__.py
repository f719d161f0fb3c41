"""Reading pose files and writing trajectory files.

``readers`` turns JSON or YAML into validated robotics-layout matrices and motion parameters,
with errors that name the file, the key and the line; ``jobscan`` scans JSON Lines jobs files
without numpy, in a helper process for ``a2b batch``. ``writers`` turns sampled motions into
CSV layouts, TUM, KITTI and MCAP, with numbers formatted by ``floatrepr`` and built into MCAP
by ``mcapwriter``, on every idle core (``parallel``). ``atomic`` puts output in place only when
it is complete.
"""
