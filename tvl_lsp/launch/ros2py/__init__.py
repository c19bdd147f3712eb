"""ROS 2 Python launch files (``.launch.py``, ``*_launch.py``), analysed statically.

The file is parsed with Python's ``ast`` and interpreted (:mod:`.interp`, :mod:`.library`,
:mod:`.launchapi`) -- never imported, never run -- and the launch description it builds is
turned into the actions of the ROS 2 walker (:mod:`.convert`, :mod:`.params`), so that the
walker of :mod:`tvl_lsp.launch.ros2` gives launch's semantics for Python files as it does for
XML and YAML: the symbolic analysis (presence conditions over the arguments), the concrete load,
includes across the three dialects.  What cannot be known is an explicit unknown; where it
decides what the launch does, the analysis declines there (``launch-not-analysable``, with the
construct's range) instead of guessing.

The walker reaches this package through :func:`.frontend.load_unit` (for a ``.py`` unit) and
the ``walk`` methods of the Python-only actions (:mod:`.actions`).
"""
