"""Base layer: what every other layer shares and nothing here imports.

- ``text``: positions and spans (0-based lines, code-point columns), line indexes, encodings;
- ``diagnostics``: the one ``Diagnostic`` type and the code registry (``register``, ``CODES``);
- ``formula``: boolean formulas over names (presence conditions, queries).
"""
