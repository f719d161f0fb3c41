"""Reading pose files and writing trajectory files.

``documents`` parses JSON or YAML with line:column positions; ``poseschema`` turns them into
validated robotics-layout matrices and motion parameters, with errors that name the file, the
key and the line; ``jobfiles`` reads jobs files in blocks, and ``jobscan`` scans JSON Lines
line by line, the common forms fast, from the same schema; ``trajectories`` reads the
trajectory files users keep, one module per format (``tum``, ``kitti``, ``euroc``,
``csvtable`` on ``textrows`` and ``trajectory``; MCAP through its indexes, ``mcapreader``).
``writers`` turns samples (:class:`a2b.samples.Samples`) into CSV layouts, TUM, KITTI and
MCAP, with numbers formatted by ``floatrepr`` and built into MCAP by ``mcapwriter``, on a second
thread (``parallel``); which writer serves which format is the table :mod:`a2b.formats`, and
:mod:`a2b.output` is the pipeline that calls them; ``ros2`` holds ROS 2's message definitions,
names and CDR, written and read with numpy. ``atomic`` puts output in place only when it is
complete.
"""
