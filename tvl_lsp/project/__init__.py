"""Project layer: everything about a workspace of files, shared by the CLI and the server.

- ``workspace``: file discovery, ROS packages, pairing of launch files with models;
- ``check``: the check pipeline (``check_paths`` for ``tvl-lsp --check``, ``check_document``
  for the editor): front ends, model analysis and cross-check for each pairing;
- ``generate``: configuration launch files for products of a model;
- ``facts``: model facts (counts, anomalies), look-ups in parsed models and launch files, and
  the configurator's queries, as plain functions the hosts run in worker processes.

Pure: no LSP, no CLI.
"""
