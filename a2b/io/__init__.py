"""Reading pose files and writing trajectory files.

``readers`` turns JSON or YAML into validated robotics-layout matrices and motion parameters,
with errors that name the file, the key and the line. ``writers`` turns sampled motions into
CSV layouts, TUM, KITTI and MCAP. ``atomic`` puts output in place only when it is complete.
"""
