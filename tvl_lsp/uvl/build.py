"""UVL model building: imports, the feature tree, attributes and constraints -> the feature-model
objects of :mod:`tvl_lsp.tvl.model` (the ones the TVL front end builds), so that encoding,
anomalies, counts, hovers and the configurator work on UVL models unchanged.

Semantics (UVL's boolean level, as FeatureIDE / flamapy read it):

- the first feature under ``features`` is the root; every child implies its parent;
- each group block under a feature is one :class:`~tvl_lsp.tvl.model.Group` (a feature may
  have several): ``mandatory`` (all its features are selected with the parent), ``optional``
  (none is required), ``or`` (at least one), ``alternative`` (exactly one), ``[n..m]`` /
  ``[n]`` / ``[n..*]`` (between n and m);
- constraints (in ``constraints`` or in a feature's ``constraint`` / ``constraints``
  attribute) over ``! & | => <=>`` and feature names are global;
- ``imports path.to.file as alias`` reads ``path/to/file.uvl`` (relative to the importing file,
  else to the main model's folder); ``alias.Root`` in the tree puts the imported model's tree
  there, and the imported model's constraints apply; ``alias.Feature`` names its features.

What is read but not analysed -- attribute values, arithmetic and string constraints (``==``,
``<``, ``+``, ``sum(...)``, ``len(...)``, ...), feature types (``Integer price``), feature
cardinalities (``cardinality [1..3]``) -- is reported once as ``not-analysed`` (information) and
kept in ``Model.unanalysed`` for the converters; counts and anomalies are those of the boolean
part.  ``abstract`` is understood (it does not change the products).
"""

from __future__ import annotations

import difflib
import os
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..base.diagnostics import Diagnostic, Related, Severity, register
from ..base.files import inside, model_workspace
from ..base.text import LineIndex, Span, single_file_span as _single_file_span  # the hot-path Span maker
from ..tvl import model as M
from .fastpath import fast_parse
from .lexer import Tok, TooManyTokens, tokenize
from .parser import RawFeature, RawFile, RawImport, RawValue, StrLit, parse_lines, _unquote

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION

# codes shared with the TVL front end (same meaning; tvl_lsp/data/diagnostics.md says so)
C_SYNTAX = register("syntax-error", E, "The text does not follow the grammar of the model's language.", "tvl")
C_ILLEGAL = register("illegal-character", E, "A character that cannot appear in TVL.", "tvl")
C_UNTERM_COMMENT = register("unterminated-comment", E, "A /* comment is never closed.", "tvl")
C_UNTERM_STRING = register("unterminated-string", E, "A string is never closed.", "tvl")
C_TOO_LARGE = register("file-too-large", E, "A file too large to analyse.", "tvl")
C_UNKNOWN = register("unknown-name", E, "A name designates no feature, attribute, constant or type.", "tvl")
C_TYPE = register("type-error", E, "An expression has the wrong type.", "tvl")
C_CARD_BOUNDS = register("cardinality-bounds", E, "Invalid group cardinality bounds.", "tvl")
# UVL's own
C_NOT_ANALYSED = register(
    "not-analysed", I,
    "A UVL attribute, arithmetic or string constraint, feature type or feature cardinality is read but left out of the analyses.", "uvl")
C_DUP_NAME = register("duplicate-feature-name", E, "Two features of a UVL model have the same name.", "uvl")
C_IMPORT_MISSING = register("import-not-found", E, "A UVL import names a file that cannot be read.", "uvl")
C_IMPORT_CYCLE = register("import-cycle", E, "UVL models import each other in a cycle.", "uvl")
C_ROOTS = register("multiple-roots", E, "A UVL model declares more than one root feature.", "uvl")
C_IMPORT_UNUSED = register("import-unused", W, "An imported UVL model is never placed in the feature tree.", "uvl")

MAX_FILE_SIZE = 8 * 1024 * 1024
MAX_TOKENS = 2_000_000
MAX_IMPORT_DEPTH = 16
UNDERSTOOD_ATTRIBUTES = {"abstract"}

ReadFile = Callable[[str], Optional[str]]


@dataclass
class _File:
    path: str
    text: str
    idx: LineIndex
    raw: RawFile
    fast_span: object = None
    # alias (tuple of parts) -> _File or None (failed import)
    imports: dict[tuple, Optional["_File"]] = field(default_factory=dict)
    import_decl: dict[tuple, RawImport] = field(default_factory=dict)
    features: dict[str, M.Feature] = field(default_factory=dict)
    root: Optional[M.Feature] = None
    used: bool = False

    def span(self, s: int, e: int) -> Span:
        return self.fast_span(s, e)


class UvlBuilder:
    def __init__(self, text: str, path: str, read_file: ReadFile):
        self.path = path
        self.read = read_file
        self.diags: list[Diagnostic] = []
        self.model = M.Model(path=path, format="uvl")
        self.files: dict[str, _File] = {}
        self.attr_keys: dict[tuple[str, str], list[tuple[str, Span]]] = {}
        self.pending: list[tuple[_File, M.Expr, M.Feature]] = []
        self._src: Optional[tuple] = None  # set by _feature: (file, raw feature, feature) of its subtree
        self.main = self._load(text, path, [os.path.abspath(path)], 0)

    # ------------------------------------------------------------ diagnostics
    def diag(self, code: str, path: str, span: Span, msg: str, sev: Optional[Severity] = None,
             related=None, data=None, fixes=None) -> None:
        from ..base.diagnostics import CODES
        self.diags.append(Diagnostic(code, sev if sev is not None else CODES[code].severity, path, span, msg,
                                     related=list(related or []), data=data, fixes=list(fixes or [])))

    # ------------------------------------------------------------ files
    def _load(self, text: str, path: str, stack: list[str], depth: int) -> Optional[_File]:
        self.model.sources[path] = text
        idx = LineIndex(text)
        if len(text) > MAX_FILE_SIZE:
            self.diag(C_TOO_LARGE, path, idx.span(0, 0),
                      f"file is {len(text) // (1024 * 1024)} MB; UVL models larger than "
                      f"{MAX_FILE_SIZE // (1024 * 1024)} MB are not analysed")
            return None
        try:
            lines, lex_errors = tokenize(text, max_tokens=MAX_TOKENS)
        except TooManyTokens:
            self.diag(C_TOO_LARGE, path, idx.span(0, 0),
                      f"the model has more than {MAX_TOKENS:,} tokens; it is not analysed")
            return None
        for le in lex_errors[:50]:
            sp = idx.span(le.start, le.end)
            if le.kind == "illegal-character":
                self.diag(C_ILLEGAL, path, sp, f"illegal character(s) {_show(le.text)} in a UVL model")
            elif le.kind == "unterminated-comment":
                self.diag(C_UNTERM_COMMENT, path, sp, "this /* comment is never closed: the rest of the file is ignored")
            else:
                self.diag(C_UNTERM_STRING, path, sp, "this string is never closed on its line")
        span = _single_file_span(idx)
        raw = fast_parse(lines, len(text), span, path) if not lex_errors else None
        if raw is not None:
            issues = []
        else:
            raw, issues = parse_lines(lines, text, len(text), span, path, tuple(le.start for le in lex_errors))
        for iss in issues:
            self.diag(C_SYNTAX, path, span(iss.start, iss.end), iss.message)
        f = _File(path, text, idx, raw, span)
        self.files[path] = f
        here = os.path.dirname(os.path.abspath(path))
        main_dir = os.path.dirname(os.path.abspath(self.path))
        for imp in raw.imports:
            alias = tuple(_unquote(t) for t in (imp.alias or imp.ref).parts)
            rel = os.path.join(*[_unquote(t) for t in imp.ref.parts]) + ".uvl"
            sp = f.span(imp.start, imp.end)
            if alias in f.import_decl:
                self.diag(C_SYNTAX, path, sp, f"'{'.'.join(alias)}' is imported twice")
                continue
            f.import_decl[alias] = imp
            cands = [os.path.normpath(os.path.join(here, rel))]
            if main_dir != here:
                cands.append(os.path.normpath(os.path.join(main_dir, rel)))
            home = model_workspace(self.path)
            if not any(inside(c, [home]) for c in cands):  # never read a file outside the workspace
                self.diag(C_IMPORT_MISSING, path, f.span(imp.ref.start, imp.ref.end),
                          f"the imported model '{imp.ref.text}' is outside the model's workspace ({home}): "
                          "it is not read", data={"target": cands[0]})
                f.imports[alias] = None
                continue
            cands = [c for c in cands if inside(c, [home])]
            target = None
            sub = None
            for c in cands:
                if c in stack:
                    chain = " -> ".join(os.path.basename(p) for p in stack[stack.index(c):] + [c])
                    self.diag(C_IMPORT_CYCLE, path, sp, f"import cycle: {chain}")
                    target = ""
                    break
                try:
                    sub = self.read(c)
                except Exception:
                    sub = None
                if sub is not None:
                    target = c
                    break
            if target == "":
                f.imports[alias] = None
                continue
            if target is None:
                self.diag(C_IMPORT_MISSING, path, f.span(imp.ref.start, imp.ref.end),
                          f"cannot read the imported model '{imp.ref.text}' ({cands[0]})",
                          data={"target": cands[0]})
                f.imports[alias] = None
                continue
            if depth >= MAX_IMPORT_DEPTH:
                self.diag(C_IMPORT_CYCLE, path, sp, "imports nested too deeply")
                f.imports[alias] = None
                continue
            if target in self.files:
                f.imports[alias] = self.files[target]
                continue
            f.imports[alias] = self._load(sub, target, stack + [target], depth + 1)
        return f

    # ------------------------------------------------------------ building
    def run(self) -> M.Model:
        main = self.main
        if main is None:
            return self.model
        raw = main.raw
        if raw.roots:
            self.model.root = self._tree(main, raw.roots[0], None)
            for extra in raw.roots[1:]:
                self.diag(C_ROOTS, main.path, main.span(extra.ref.start, extra.ref.end),
                          f"a UVL model has one root feature, '{main.root.name if main.root else '?'}': "
                          f"'{extra.ref.text}' and what is below it are not read (indent it under a feature)")
                raw.broken_names.update(self._subtree_names(extra))
        for f, e, owner in self.pending:
            self._constraint(f, e, owner, e._s, e._e)
        for f in self.files.values():
            if f.root is not None or f is main:
                self._constraints(f)
        for f in self.files.values():
            for alias, sub in f.imports.items():
                if sub is not None and sub.root is None and f.root is not None:
                    imp = f.import_decl[alias]
                    self.diag(C_IMPORT_UNUSED, f.path, f.span(imp.start, imp.end),
                              f"the imported model '{'.'.join(alias)}' is never placed in the feature tree "
                              f"(write '{'.'.join(alias)}.<its root feature>' under a group): it is not analysed")
        self._report_attributes()
        return self.model

    @staticmethod
    def _subtree_names(rf: RawFeature) -> set[str]:
        out = set()
        stack = [rf]
        while stack:
            x = stack.pop()
            out.add(x.ref.text)
            for g in x.groups:
                stack.extend(g.features)
        return out

    def _resolve_alias(self, f: _File, parts: list[str]) -> tuple[Optional[_File], int, bool]:
        """Follow import aliases at the start of ``parts``: (scope, index of the first part not
        consumed, failed-import)."""
        sc = f
        i = 0
        while i < len(parts) - 1:
            hit = None
            for k in range(len(parts) - 1 - i, 0, -1):
                key = tuple(parts[i:i + k])
                if key in sc.imports:
                    hit = (key, k)
                    break
            if hit is None:
                break
            nxt = sc.imports[hit[0]]
            if nxt is None:
                return None, i + hit[1], True
            sc = nxt
            i += hit[1]
        return sc, i, False

    def _tree(self, f: _File, rf: RawFeature, parent: Optional[M.Feature]) -> Optional[M.Feature]:
        """Build ``rf`` and everything below it, without recursion: the features in source
        order first, then their groups."""
        built: list[tuple[_File, RawFeature, M.Feature]] = []
        stack = [(f, rf, parent)]
        feature = self._feature
        pop = stack.pop
        push = stack.append
        add_feature = self.model.features.append
        new_feature = M.Feature
        while stack:
            ff, r, par = pop()
            parts = r.ref.parts
            if r.type_tok is None and r.card is None and not r.attrs and len(parts) == 1 and parts[0].type == "ID":
                # the common line, a plain name: what _feature does for it
                tok = parts[0]
                name = tok.value
                span = ff.fast_span
                path = ff.path
                s = tok.start
                e = tok.end
                nsp = span(s, e)
                # (spans are immutable values: a line that is only the name shares one)
                feat = new_feature(name, nsp if r.start == s and r.end == e else span(r.start, r.end), nsp, path,
                                   par, is_root=par is None)
                feat.decl_spans.append((path, nsp))
                features = ff.features
                if name in features:
                    self._duplicate(feat, features[name])
                else:
                    features[name] = feat
                if par is None and ff.root is None:
                    ff.root = feat
                add_feature(feat)
                r.built = feat
                if r.groups:
                    built.append((ff, r, feat))
                    for rg in reversed(r.groups):
                        for child in reversed(rg.features):
                            push((ff, child, feat))
                continue
            feat = feature(ff, r, par)
            src = self._src
            self._src = None
            if feat is None:
                continue
            r.built = feat
            if src is None:
                continue
            built.append(src)
            sf, sr, _ = src
            for rg in reversed(sr.groups):
                for child in reversed(rg.features):
                    push((sf, child, feat))
        child_of = M.GroupChild
        for ff, r, feat in built:
            for rg in r.groups:
                g = self._group(ff, rg, feat)
                opt = rg.kw.type == "OPTIONAL"
                children = g.children
                for child in rg.features:
                    cf = child.built
                    if cf is not None:
                        children.append(child_of(cf, opt, False, cf.name_span, cf.path))
                if g.kind == "allOf":
                    g.lo = g.hi = len(children)
        return rf.built

    def _duplicate(self, feat: M.Feature, prev: M.Feature) -> None:
        self.diag(C_DUP_NAME, feat.path, feat.name_span,
                  f"two features are named '{feat.name}': constraints cannot tell them apart (rename one)",
                  related=[Related(prev.path, prev.name_span, "the other one")])

    def _feature(self, f: _File, rf: RawFeature, parent: Optional[M.Feature]) -> Optional[M.Feature]:
        """The feature a tree line declares (an import reference brings the imported tree)."""
        parts = [_unquote(t) for t in rf.ref.parts]
        if len(parts) > 1:
            sc, i, failed = self._resolve_alias(f, parts)
            if failed:
                return None
            if sc is f or i != len(parts) - 1:
                bad = rf.ref.parts[1]
                self.diag(C_SYNTAX, f.path, f.span(rf.ref.parts[0].start, rf.ref.end),
                          f"'{rf.ref.text}' is not a feature name: a '.' separates an import's name from its "
                          f"root feature, and no import is named '{'.'.join(parts[:-1])}'"
                          + (" (quote a name with spaces or dashes: \"My-Feature\")" if bad else ""))
                return None
            sub = sc
            if sub.root is not None:
                self.diag(C_SYNTAX, f.path, f.span(rf.ref.start, rf.ref.end),
                          f"the imported model '{'.'.join(parts[:-1])}' is placed in the tree twice")
                return None
            sroots = sub.raw.roots
            if not sroots:
                self.diag(C_UNKNOWN, f.path, f.span(rf.ref.start, rf.ref.end),
                          f"the imported model '{'.'.join(parts[:-1])}' has no features")
                return None
            if _unquote(sroots[0].ref.parts[-1]) != parts[-1] or len(sroots[0].ref.parts) != 1:
                self.diag(C_UNKNOWN, f.path, f.span(rf.ref.parts[-1].start, rf.ref.end),
                          f"the root of the imported model '{'.'.join(parts[:-1])}' is "
                          f"'{sroots[0].ref.text}', not '{parts[-1]}'",
                          data={"suggestions": [sroots[0].ref.text]})
                return None
            feat = self._feature(sub, sroots[0], parent)
            if feat is None:
                return None
            sub.root = feat
            sub.used = True
            feat.decl_spans.append((f.path, f.span(rf.ref.start, rf.ref.end)))
            self._attributes(f, rf, feat)  # attributes written at the reference
            for extra in sroots[1:]:
                self.diag(C_ROOTS, sub.path, sub.span(extra.ref.start, extra.ref.end),
                          f"a UVL model has one root feature: '{extra.ref.text}' is not read")
            return feat
        name = parts[0]
        tok = rf.ref.parts[0]
        if tok.type == "QID" and "." in name:
            self.diag(C_SYNTAX, f.path, f.span(tok.start, tok.end),
                      "a quoted feature name cannot contain '.' (it separates an import's name from its features)")
        nsp = f.span(rf.ref.start, rf.ref.end)
        feat = M.Feature(name=name, span=f.span(rf.start, rf.end), name_span=nsp, path=f.path, parent=parent,
                         is_root=parent is None)
        feat.decl_spans.append((f.path, nsp))
        if name in f.features:
            self._duplicate(feat, f.features[name])
        else:
            f.features[name] = feat
        if parent is None and f.root is None:
            f.root = feat
        self.model.features.append(feat)
        if rf.type_tok is not None:
            self._unanalysed(f, "feature-type", rf.type_tok.start, rf.ref.end, feat, "a typed feature",
                             f"'{rf.type_tok.value} {name}' is a typed feature (UVL's type level): its value is "
                             "not analysed, only whether it is selected")
        if rf.card is not None:
            self._card_spaces(f, rf.card)
            self._unanalysed(f, "feature-cardinality", rf.card.start, rf.card.end, feat, "a feature cardinality",
                             f"the feature cardinality {rf.card.value} of '{name}' (several instances) is not "
                             "analysed: the feature is analysed as one feature, selected or not")
        self._attributes(f, rf, feat)
        self._src = (f, rf, feat)  # its subtree, built by _tree's loop
        return feat

    def _group(self, f: _File, rg, owner: M.Feature) -> M.Group:
        kw = rg.kw
        sp = f.span(rg.start, rg.end)
        ksp = f.span(kw.start, kw.end)
        if kw.type == "OR_G":
            g = M.Group("someOf", owner, sp, ksp, f.path, lo=1, hi=None, keyword="or")
        elif kw.type == "ALTERNATIVE":
            g = M.Group("oneOf", owner, sp, ksp, f.path, lo=1, hi=1, keyword="alternative")
        elif kw.type in ("MANDATORY", "OPTIONAL"):
            g = M.Group("allOf", owner, sp, ksp, f.path, lo=0, hi=None, keyword=kw.value)
        else:
            self._card_spaces(f, kw)
            inner = kw.value.strip()[1:-1].replace(" ", "").replace("\t", "")
            lo_s, _, hi_s = inner.partition("..")
            lo = int(lo_s)
            hi = lo if not _ else (None if hi_s == "*" else int(hi_s))
            keyword = f"[{lo}..{'*' if hi is None else hi}]" if _ else f"[{lo}]"
            g = M.Group("card", owner, sp, ksp, f.path, lo=lo, hi=hi, keyword=keyword)
            if hi is not None and hi < lo:
                self.diag(C_CARD_BOUNDS, f.path, ksp,
                          f"the group cardinality {keyword} has its upper bound below its lower bound: "
                          f"no product can select {owner.name}")
        if owner.group is None:
            owner.group = g
        else:
            owner.extra_groups.append(g)
        return g

    def _card_spaces(self, f: _File, tok: Tok) -> None:
        if " " in tok.value or "\t" in tok.value:
            from ..base.diagnostics import Fix, TextEdit
            tight = "".join(tok.value.split())
            sp = f.span(tok.start, tok.end)
            self.diag(C_SYNTAX, f.path, sp, f"UVL writes a cardinality without spaces: {tight}",
                      fixes=[Fix(f"Write {tight}", (TextEdit(f.path, sp, tight),), True)])

    # ------------------------------------------------------------ attributes
    def _attributes(self, f: _File, rf: RawFeature, feat: M.Feature) -> None:
        for a in rf.attrs:
            if a.kind in ("constraint", "constraints"):
                # resolved once the whole tree is known (they may name later features)
                self.pending.extend((f, e, feat) for e in a.constraints)
                continue
            key = _unquote(a.key)
            if key in UNDERSTOOD_ATTRIBUTES and a.value is not None and a.value.kind == "bool":
                feat.abstract = bool(a.value.value)
                continue
            attr = M.Attribute(name=key, type=_uvl_type(a.value), span=f.span(a.start, a.end),
                               name_span=f.span(a.key.start, a.key.end), path=f.path, owner=feat)
            attr.value = _value_expr(a.value, f)
            attr.uvl_value = a.value
            attr.uvl_text = f.text[a.start:a.end]
            feat.attributes.append(attr)
            self.model.unanalysed.append(M.Unanalysed("attribute", attr.uvl_text, attr.span, f.path, feat,
                                                      "attribute values are not analysed"))
            self.attr_keys.setdefault((f.path, key), []).append((feat.name, attr.name_span))

    def _report_attributes(self) -> None:
        for (path, key), uses in self.attr_keys.items():
            name, sp = uses[0]
            n = len(uses)
            more = f" (and on {n - 1} other feature{'s' if n > 2 else ''})" if n > 1 else ""
            rel = [Related(path, s, f"'{key}' of {nm}") for nm, s in uses[1:4]]
            self.diag(C_NOT_ANALYSED, path, sp,
                      f"attribute '{key}' of {name}{more} is read but not analysed: attribute values take no "
                      "part in product counts and anomalies", related=rel)

    def _unanalysed(self, f: _File, kind: str, s: int, e: int, owner, reason: str, msg: str) -> None:
        sp = f.span(s, e)
        self.model.unanalysed.append(M.Unanalysed(kind, f.text[s:e], sp, f.path, owner, reason))
        self.diag(C_NOT_ANALYSED, f.path, sp, msg)

    # ------------------------------------------------------------ constraints
    def _constraints(self, f: _File) -> None:
        for rc in f.raw.constraints:
            self._constraint(f, rc.expr, None, rc.start, rc.end)

    def _constraint(self, f: _File, e: M.Expr, owner: Optional[M.Feature], s: int, end: int) -> None:
        owner = owner or f.root or self.model.root
        sp = f.span(s, end)
        verdict = self._check(f, e)
        if verdict == "error":
            return
        if verdict == "broken":
            return
        if verdict != "bool":
            self._unanalysed(f, "constraint", s, end, owner, verdict,
                             f"this constraint is not analysed: {verdict}; product counts and anomalies "
                             "ignore it")
            return
        if owner is None:
            return
        owner.constraints.append(M.Constraint(e, "plain", owner, sp, f.path))

    def _check(self, f: _File, e: M.Expr) -> str:
        """Resolve names and check types: "bool" (analysed), a reason it is not analysed,
        "error" (reported) or "broken" (names a feature a syntax error dropped)."""
        reason = None
        errors = 0
        broken = False
        # (node, context): context "bool" = a boolean is expected, "term" = a value
        stack = [(e, "bool")]
        while stack:
            x, ctx = stack.pop()
            if getattr(x, "too_deep", False):
                reason = reason or "it is nested too deeply"
                continue
            if isinstance(x, M.Name):
                r = self._name(f, x, ctx)
                if r == "error":
                    errors += 1
                elif r == "broken":
                    broken = True
                elif r != "bool" and ctx == "bool":
                    reason = reason or r
                x.type = "bool" if r == "bool" else None
                continue
            if isinstance(x, M.Unary):
                if ctx != "bool":
                    errors += self._type_error(f, x, "'!' gives a boolean, not a value")
                    continue
                x.type = "bool"
                stack.append((x.operand, "bool"))
                continue
            if isinstance(x, M.Binary):
                if x.op in ("&&", "||", "->", "<->"):
                    if ctx != "bool":
                        errors += self._type_error(f, x, f"'{_UVL_OP[x.op]}' gives a boolean, not a value")
                        continue
                    x.type = "bool"
                    stack.append((x.right, "bool"))
                    stack.append((x.left, "bool"))
                elif x.op in ("==", "!=", "<", ">", "<=", ">="):
                    if ctx != "bool":
                        errors += self._type_error(f, x, "a comparison gives a boolean, not a value")
                        continue
                    reason = reason or "it compares values (UVL's arithmetic / type level)"
                    stack.append((x.right, "term"))
                    stack.append((x.left, "term"))
                else:
                    if ctx == "bool":
                        errors += self._type_error(f, x, f"'{x.op}' gives a number, not a boolean: compare it "
                                                         "(==, <, ...) to make a constraint")
                        continue
                    stack.append((x.right, "term"))
                    stack.append((x.left, "term"))
                continue
            if isinstance(x, M.Aggregate):
                if ctx == "bool":
                    errors += self._type_error(f, x, f"{x.func}(...) gives a value, not a boolean")
                    continue
                reason = reason or f"it uses {x.func}(...)"
                continue
            if isinstance(x, (M.IntLit, M.RealLit, StrLit)):
                if ctx == "bool":
                    what = "a string" if isinstance(x, StrLit) else "a number"
                    errors += self._type_error(f, x, f"{what} is not a boolean")
                continue
        if errors:
            return "error"
        if broken:
            return "broken"
        return reason or "bool"

    def _type_error(self, f: _File, x: M.Expr, msg: str) -> int:
        self.diag(C_TYPE, f.path, f.span(x._s, x._e), msg)
        return 1

    def _name(self, f: _File, x: M.Name, ctx: str) -> str:
        parts = x.parts
        sc, i, failed = self._resolve_alias(f, parts)
        if failed:
            return "broken"
        name = parts[i]
        feat = sc.features.get(name)
        if feat is None:
            if sc is f and name in f.raw.broken_names:
                return "broken"
            cands = list(sc.features)
            close = difflib.get_close_matches(name, cands, n=3, cutoff=0.6)
            hint = (" Did you mean " + " or ".join(f"'{c}'" for c in close) + "?") if close else ""
            where = f" in '{'.'.join(parts[:i])}'" if i else ""
            sp = x.part_spans[min(i, len(x.part_spans) - 1)]
            self.diag(C_UNKNOWN, f.path, sp, f"no feature named '{name}'{where}.{hint}",
                      data={"suggestions": close} if close else None)
            return "error"
        x.part_targets = [None] * i + [feat]
        rest = parts[i + 1:]
        if not rest:
            x.target = feat
            return "bool"
        # Feature.attribute
        x.feature = feat
        attr = next((a for a in feat.attributes if a.name == rest[0]), None)
        x.target = attr
        x.part_targets.append(attr)
        if attr is None and rest[0] not in UNDERSTOOD_ATTRIBUTES:
            # (attributes are not analysed: say it, but it is no error of the boolean model)
            names = [a.name for a in feat.attributes]
            close = difflib.get_close_matches(rest[0], names, n=1, cutoff=0.6)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            return f"it uses {feat.name}.{rest[0]}, and {feat.name} declares no attribute '{rest[0]}'{hint}"
        return f"it uses the attribute {feat.name}.{rest[0]}"


def _show(text: str) -> str:
    import unicodedata
    if text.isprintable() and not text.isspace() and len(text) <= 20:
        return f"'{text}'"
    c = text[0]
    return f"U+{ord(c):04X} ({unicodedata.name(c, 'control character').lower()})" + (" …" if len(text) > 1 else "")


_UVL_OP = {"&&": "&", "||": "|", "->": "=>", "<->": "<=>"}


def _uvl_type(v: Optional[RawValue]) -> str:
    if v is None:
        return "Boolean"
    return {"bool": "Boolean", "int": "Integer", "float": "Real", "string": "String", "attrs": "Attributes",
            "vector": "Vector"}.get(v.kind, "String")


def _value_expr(v: Optional[RawValue], f: _File) -> Optional[M.Expr]:
    if v is None:
        return None
    sp = f.span(v.start, v.end)
    if v.kind == "bool":
        return M.BoolLit(bool(v.value), span=sp, path=f.path)
    if v.kind == "int":
        return M.IntLit(int(v.value), span=sp, path=f.path)
    if v.kind == "float":
        return M.RealLit(float(v.value), text=f.text[v.start:v.end], span=sp, path=f.path)
    if v.kind == "string":
        return StrLit(v.value, span=sp, path=f.path)
    return None
