"""The tree-sitter side shared by the C++ and the Python extractors: one parser per language
(built on first use), and a source's facts from its tree, never raising on bad input."""

from __future__ import annotations

_PARSERS: dict = {}


def parser(language: str):
    """The tree-sitter parser of ``"cpp"`` or ``"python"``."""
    p = _PARSERS.get(language)
    if p is None:
        import importlib

        import tree_sitter as ts
        grammar = importlib.import_module(f"tree_sitter_{language}")
        p = _PARSERS[language] = ts.Parser(ts.Language(grammar.language()))
    return p


def facts(language: str, walker_class, src: bytes) -> dict:
    """``walker_class(src)`` walked over the source's tree: its facts (``.f``), with a note
    when the source nests too deeply or has syntax errors (read as far as tree-sitter could)."""
    tree = parser(language).parse(src)
    w = walker_class(src)
    try:
        w.walk(tree.root_node)
    except RecursionError:
        w.f["notes"].append("nested too deeply: read only in part")
    if tree.root_node.has_error:
        w.f["notes"].append("has syntax errors (read as far as tree-sitter could)")
    return w.f
