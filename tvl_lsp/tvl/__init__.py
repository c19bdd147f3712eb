"""TVL front end: grammar, parser, resolver and checks.  Pure: no LSP here.

    parse_model(text, path, read_file=None) -> TvlResult(model, diagnostics)

``read_file(abs_path) -> str | None`` supplies included files (default: read from disk).
The model is always built, possibly partially, whatever the input.
"""

from __future__ import annotations

import gc
import os
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..base.diagnostics import Diagnostic, Fix, Severity, TextEdit, register
from ..base.files import inside, model_workspace, read_text_or_none, unreadable_reason
from . import model
from .model import Model
from .codes import C_REF_REJECTS

# the lexer and the parser (lark's LALR table, built on first use) are imported when a TVL text
# is parsed: a UVL or DIMACS model needs only the model classes (0.03 s of every cold start)

__all__ = ["parse_model", "TvlResult", "Model", "model", "MAX_FILE_SIZE", "MAX_TOKENS"]

E, W = Severity.ERROR, Severity.WARNING
C_SYNTAX = register("syntax-error", E, "The text does not follow the grammar of the model's language.", "tvl")
C_ILLEGAL = register("illegal-character", E, "A character that cannot appear in TVL.", "tvl")
C_UNTERM_COMMENT = register("unterminated-comment", E, "A /* comment is never closed.", "tvl")
C_UNTERM_STRING = register("unterminated-string", E, "A string is never closed.", "tvl")
C_INFIX = register("infix-and-or", E, "The words 'and' / 'or' used as infix operators (TVL writes && and ||).", "tvl")
C_CONSTANT_KW = register("constant-keyword", E, "The keyword 'constant' for a constant declaration (TVL's keyword is 'const').", "tvl")
C_INC_MISSING = register("include-missing", E, "An included file cannot be read.", "tvl")
C_INC_CYCLE = register("include-cycle", E, "Files include each other in a cycle.", "tvl")
C_TOO_DEEP = register("nesting-too-deep", E, "Nesting deeper than the checker analyses.", "tvl")
C_TOO_LARGE = register("file-too-large", E, "A file too large to analyse.", "tvl")

MAX_FILE_SIZE = 5 * 1024 * 1024  # ~400,000 lines of a typical model; parsing it takes seconds
MAX_TOKENS = 1_000_000  # ~400,000 lines of a typical model; more would take too long
MAX_INCLUDE_DEPTH = 32
_TYPE_KWS = {"INTK", "REALK", "BOOL", "ENUM"}


@dataclass
class TvlResult:
    model: Model
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == Severity.ERROR]


def _default_read(path: str) -> Optional[str]:
    return read_text_or_none(path)  # regular files within the size cap only


def parse_model(text: str, path: str, read_file: Callable[[str], Optional[str]] | None = None) -> TvlResult:
    """Parse and check a TVL model; never raises on bad input."""
    # The front end allocates many small objects and no garbage cycles worth collecting while it
    # runs; the cyclic collector would otherwise rescan the growing heap again and again.
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        return _parse_model(text, path, read_file)
    finally:
        if was_enabled:
            gc.enable()


def _parse_model(text: str, path: str, read_file) -> TvlResult:
    from .lexer import TooManyTokens
    from .parser import SourceMap, parse_tokens
    read = read_file or _default_read
    path = str(path)
    mdl = Model(path=path)
    diags: list[Diagnostic] = []
    smap = SourceMap()
    mdl.sources[path] = text
    toks: list = []
    try:
        _load(text, path, smap, toks, diags, mdl, read, [os.path.abspath(path)], 0)
    except TooManyTokens:
        return TvlResult(mdl, diags)
    _departures(toks, smap, diags)
    items, issues = parse_tokens(toks, smap)
    for iss in issues:
        if iss.code == "reference-rejects":
            diags.append(Diagnostic(C_REF_REJECTS, Severity.WARNING, smap.path(iss.start),
                                    smap.span(iss.start, iss.end), iss.message))
            continue
        code = C_TOO_DEEP if iss.code == "nesting-too-deep" else C_SYNTAX
        diags.append(Diagnostic(code, E, smap.path(iss.start), smap.span(iss.start, iss.end), iss.message))
    from .build import ModelBuilder
    try:
        ModelBuilder(smap, items, mdl, diags).run()
    except RecursionError:  # pragma: no cover - depth is bounded by the parser
        diags.append(Diagnostic(C_TOO_DEEP, E, path, smap.span(0, 0), "model nested too deeply to analyse"))
    diags.sort(key=lambda d: d.sort_key())
    return TvlResult(mdl, _dedupe(diags))


def _dedupe(diags: list[Diagnostic]) -> list[Diagnostic]:
    seen = set()
    out = []
    for d in diags:
        k = (d.code, d.path, d.span, d.message)
        if k in seen:
            continue
        seen.add(k)
        out.append(d)
    return out


def _load(text, path, smap, out: list, diags, mdl: Model, read, stack: list[str], depth: int):
    from .lexer import TooManyTokens, tokenize
    base = smap.add(path, text)
    if len(text) > MAX_FILE_SIZE:
        diags.append(Diagnostic(C_TOO_LARGE, E, path, smap.span(base, base),
                                f"file is {len(text) // (1024 * 1024)} MB; models larger than "
                                f"{MAX_FILE_SIZE // (1024 * 1024)} MB are not analysed"))
        return
    try:
        toks, lex_errors = tokenize(text, max_tokens=max(0, MAX_TOKENS - len(out)))
    except TooManyTokens:
        diags.append(Diagnostic(C_TOO_LARGE, E, path, smap.span(base, base),
                                f"the model has more than {MAX_TOKENS:,} tokens; it is not analysed"))
        raise
    for le in lex_errors[:50]:
        s, e = base + le.start, base + le.end
        if le.kind == "illegal-character":
            shown = le.text if le.text.isprintable() and len(le.text) <= 20 else repr(le.text[:20])
            diags.append(Diagnostic(C_ILLEGAL, E, path, smap.span(s, e), f"illegal character(s) {shown} in a TVL model"))
        elif le.kind == "unterminated-comment":
            diags.append(Diagnostic(C_UNTERM_COMMENT, E, path, smap.span(s, e),
                                    "this /* comment is never closed: the rest of the file is ignored"))
        else:
            diags.append(Diagnostic(C_UNTERM_STRING, E, path, smap.span(s, e), "this string is never closed"))
    if len(lex_errors) > 50:
        diags.append(Diagnostic(C_ILLEGAL, E, path, smap.span(base, base),
                                f"{len(lex_errors)} lexical errors: is this a TVL file?"))
    for t in toks:
        if t.type == "INCLUDE":
            s, e = base + t.start, base + t.end
            inc_text = t.value
            here = os.path.dirname(os.path.abspath(path))
            target = inc_text if os.path.isabs(inc_text) else os.path.normpath(os.path.join(here, inc_text))
            inc = model.Include(inc_text, smap.span(s, e), path)
            mdl.includes.append(inc)
            if target in stack:
                chain = " -> ".join(os.path.basename(p) for p in stack[stack.index(target):] + [target])
                diags.append(Diagnostic(C_INC_CYCLE, E, path, smap.span(s, e), f"include cycle: {chain}"))
                continue
            if depth >= MAX_INCLUDE_DEPTH:
                diags.append(Diagnostic(C_INC_CYCLE, E, path, smap.span(s, e), "includes nested too deeply"))
                continue
            home = model_workspace(stack[0])
            if not inside(target, [home]):
                # never read (nor quote in a diagnostic) a file outside the model's workspace
                diags.append(Diagnostic(C_INC_MISSING, E, path, smap.span(s, e),
                                        f"included file '{inc_text}' is outside the model's workspace ({home}): "
                                        "it is not read", data={"target": target}))
                continue
            try:
                sub = read(target)
            except Exception:
                sub = None
            if sub is None:
                why = unreadable_reason(target)
                diags.append(Diagnostic(C_INC_MISSING, E, path, smap.span(s, e),
                                        f"cannot read included file '{inc_text}' ({target})"
                                        + (f": {why}" if why and os.path.lexists(target) else ""),
                                        data={"target": target}))
                continue
            inc.resolved = target
            mdl.sources[target] = sub
            _load(sub, target, smap, out, diags, mdl, read, stack + [target], depth + 1)
            continue
        t.start += base
        t.end += base
        out.append(t)


def _departures(toks: list, smap, diags: list[Diagnostic]) -> None:
    """The thesis's listings write infix ``and``/``or`` and ``constant``; the reference rejects
    both.  Report them with the replacement and read them as meant, so the rest is checked."""
    n = len(toks)
    for i, t in enumerate(toks):
        if t.type in ("ANDAGG", "ORAGG"):
            prev = toks[i - 1].type if i > 0 else None
            # after an operand, 'and'/'or' can only be meant as infix operators (an aggregate
            # call there would be a syntax error anyway): 'A and (B || C)' included
            nxt = toks[i + 1].type if i + 1 < n else None
            if (prev in ("ID", "RPAR", "RBRACK", "INT", "REAL", "TRUE", "FALSE", "THIS", "PARENT", "ROOT")
                    or (prev == "RBRACE" and nxt != "LPAR")):  # '}' ends a set, or a block
                rep = "&&" if t.type == "ANDAGG" else "||"
                sp = smap.span(t.start, t.end)
                p = smap.path(t.start)
                diags.append(Diagnostic(
                    C_INFIX, E, p, sp,
                    f"TVL has no infix '{t.value}' (only the aggregate function {t.value}(...)); write '{rep}'",
                    fixes=[Fix(f"Replace '{t.value}' with '{rep}'", (TextEdit(p, sp, rep),), True)],
                    data={"replacement": rep}))
                t.type = "AND" if t.type == "ANDAGG" else "OR"
                t.value = rep
        elif t.type == "ID" and t.value == "constant":
            prev = toks[i - 1].type if i > 0 else None
            nxt = toks[i + 1].type if i + 1 < n else None
            if prev in (None, "SEMI", "RBRACE", "LBRACE") and nxt in _TYPE_KWS:
                sp = smap.span(t.start, t.end)
                p = smap.path(t.start)
                diags.append(Diagnostic(
                    C_CONSTANT_KW, E, p, sp, "TVL declares constants with 'const', not 'constant'",
                    fixes=[Fix("Replace 'constant' with 'const'", (TextEdit(p, sp, "const"),), True)],
                    data={"replacement": "const"}))
                t.type = "CONST"
                t.value = "const"
