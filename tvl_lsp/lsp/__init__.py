"""The LSP host (pygls): a thin layer that converts between LSP and the core's results.

``server`` (the server object and start-up), ``settings``, ``documents`` (the document
store), ``scheduler`` (background checks and counts), ``workers`` (thread and process pools,
progress), ``checks`` (entry into ``project.check``), ``convert`` (positions, ranges,
diagnostics, edits), ``features/`` (one module per LSP feature).
"""
