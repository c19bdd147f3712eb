"""``tvl-lsp count MODEL [--include F]... [--exclude F]... [--per-feature] [--json] [--timeout S]``

Prints the exact number of products of a TVL model (``.tvl``), a UVL model (``.uvl``, its boolean
part: see ``not-analysed``) or of a DIMACS CNF
(``.dimacs`` / ``.cnf``, every variable a feature, names from ``c <index> <name>``
comments) on its last line; with ``--per-feature``, one line ``name<TAB>count`` per feature
before it (every feature's count comes from one pass over the compiled model).

``--json`` prints one object::

    {"model": ..., "count": N, "count_text": "N", "digits": 211, "engine": "d4", ...,
     "features": {"name": n, ...}}          # "features" with --per-feature only

Counts are exact integers of any size, written as JSON numbers: Python's ``json`` (and any
reader with big integers) reads them exactly; JavaScript's ``JSON.parse`` rounds numbers
beyond 2^53, so ``count_text`` repeats the total as a decimal string.  ``engine`` says which
counter answered (``d4``: the compiled d-DNNF; ``pyganak``: projected counting, used when
the model's attribute values are not determined by its features or d4 failed).

Exit code 0 on success, 2 on usage errors, unreadable input or timeout.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time


class _DimacsModel:
    """A DIMACS CNF counted as it is: variable ``i`` is the feature named by its comment.
    The flat TVL model ``tvl-lsp`` imports a DIMACS file as adds a root feature selected in
    every product; it is reported here too, so both give the same answers."""

    def __init__(self, path: str, text: str):
        from ...analysis.counting import CNFCounter
        from ...analysis.dimacs_read import parse_dimacs
        from ...analysis.dimacs_read import MAX_VARIABLES
        nvars, clauses, names, _ = parse_dimacs(text)
        self.n = max([nvars] + [abs(x) for c in clauses for x in c] + list(names))
        if self.n > MAX_VARIABLES:
            raise ValueError(f"the model has {self.n:,} variables: models of more than {MAX_VARIABLES:,} "
                             "variables are not analysed")
        stem = re.sub(r"\W", "_", os.path.splitext(os.path.basename(path))[0]) or "model"
        if stem[0].isdigit():
            stem = "_" + stem
        taken = set(names.values())
        root = stem
        while root in taken:
            root = "_" + root
        self.root = root
        self.names: list[str] = []
        for i in range(1, self.n + 1):
            name = names.get(i)
            if name is None:
                name = f"_{i}"
                while name in taken:
                    name = "_" + name
            self.names.append(name)
        self.var = {name: i + 1 for i, name in enumerate(self.names)}
        self.unique = len(self.var) == len(self.names)
        self.counter = CNFCounter(self.n, clauses, self.n, determined=True, label=root, inprocess=True)

    def known(self, name: str) -> bool:
        return name == self.root or name in self.var

    def lits(self, include, exclude):
        out = []
        for n in include:
            if n != self.root:
                out.append(self.var[n])
        for n in exclude:
            if n == self.root:
                return None  # no product lacks the root
            out.append(-self.var[n])
        return out

    def count(self, include, exclude, timeout):
        from ...analysis.counting import Count
        lits = self.lits(include, exclude)
        if lits is None:
            return Count(0, "trivial")
        return self.counter.count(lits, timeout=timeout)

    def per_feature(self, include, exclude, timeout):
        lits = self.lits(include, exclude)
        if lits is None:
            return 0, {self.root: 0, **{n: 0 for n in self.names}}, "trivial"
        r = self.counter.feature_counts(lits, timeout=timeout)
        out = {self.root: r.total}
        for i, n in enumerate(self.names):
            if r.counts[i + 1] is not None:
                out[n] = r.counts[i + 1]
        return r.total, out, r.engine


class _PlainModel:
    """A plain UVL model (no errors by construction): its features by name and the counting
    service over :func:`tvl_lsp.analysis.plaincnf.encode_plain`'s CNF, the encoding's own."""

    def __init__(self, p):
        from ...analysis.counting import CNFCounter
        from ...analysis.plaincnf import encode_plain
        cnf = encode_plain(p)
        self.names = p.names
        self.n = cnf.n_features
        self.var = {name: i + 1 for i, name in enumerate(self.names)}
        # as ModelAnalysis.counter: no attribute variables, so the auxiliaries are determined
        self.counter = CNFCounter(cnf.nvars, cnf.clauses, cnf.n_features, determined=True, label=self.names[0])

    def known(self, name: str) -> bool:
        return name in self.var

    def lits(self, include, exclude):
        return [self.var[n] for n in include] + [-self.var[n] for n in exclude]

    def count(self, include, exclude, timeout):
        return self.counter.count(self.lits(include, exclude), timeout=timeout)

    def per_feature(self, include, exclude, timeout):
        r = self.counter.feature_counts(self.lits(include, exclude), timeout=timeout)
        out = {}
        for i, name in enumerate(self.names):
            if r.counts[i + 1] is not None:
                out[name] = r.counts[i + 1]
        return r.total, out, r.engine


class _TvlModel:
    def __init__(self, analysis):
        self.a = analysis
        self.enc = analysis.encoding
        self.n = self.enc.n_features

    def known(self, name: str) -> bool:
        return self.enc.feature_by_name(name) is not None

    def count(self, include, exclude, timeout):
        return self.a.count_result(include=include, exclude=exclude, timeout=timeout)

    def per_feature(self, include, exclude, timeout):
        r = self.a.feature_counts_result(include, exclude, timeout=timeout)
        out = {}
        for f, v in self.enc.var_of_feature.items():
            if r.counts[v] is not None:
                out[self.a.name(f)] = r.counts[v]
        return r.total, out, r.engine


def load(path: str, need_unique_names: bool = True, plain: bool = True):
    """(model, parse errors) for a ``.tvl`` / ``.uvl`` model or a DIMACS CNF.  Raises OSError or
    ValueError.  A plain UVL model (:mod:`tvl_lsp.uvl.plain`) is read without the full front end
    unless ``plain`` is False."""
    from ...base.files import read_text  # regular files only, within the size cap
    text = read_text(path)
    if path.endswith((".dimacs", ".cnf")):
        m = _DimacsModel(path, text)
        if m.unique or not need_unique_names:
            return m, []
        from ...analysis.engine import ModelAnalysis
        return _TvlModel(ModelAnalysis.from_dimacs(text, path)), []
    if path.endswith(".uvl") and plain:
        from ...uvl.plain import read_plain
        p = read_plain(text)
        if p is not None:  # plain UVL: its CNF without the model (the same clauses)
            return _PlainModel(p), []
    from ...analysis.engine import ModelAnalysis
    from ...analysis.formats import parse_any_model
    res = parse_any_model(text, path)
    if res.model is None:
        raise ValueError("no model could be read")
    return _TvlModel(ModelAnalysis(res.model)), res.errors


def report_errors(prog: str, path: str, model, errors) -> None:
    if errors:
        for d in errors:
            print(f"{d.path}:{d.span.start}: error: {d.message} [{d.code}]", file=sys.stderr)
        print(f"{prog}: {path} has errors; the answer below is for what could be read", file=sys.stderr)
    if isinstance(model, _TvlModel):
        for d in model.enc.diagnostics():
            print(f"{d.path}:{d.span.start}: info: {d.message} [{d.code}]", file=sys.stderr)


def main(argv: list[str]) -> int:
    import gc
    frozen = gc.get_freeze_count()
    try:
        return _main(argv)
    finally:
        if gc.get_freeze_count() != frozen:
            gc.unfreeze()  # (called in-process: the model's objects are collectable again)


def _main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="tvl-lsp count", description="Exact number of products of a feature model.")
    ap.add_argument("model", help="a .tvl or .uvl model, or a .dimacs CNF")
    ap.add_argument("--include", "-i", action="append", default=[], metavar="F", help="count only products with F")
    ap.add_argument("--exclude", "-x", action="append", default=[], metavar="F", help="count only products without F")
    ap.add_argument("--per-feature", action="store_true", help="also the number of products with each feature")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--timeout", type=float, default=None, metavar="S", help="give up after S seconds")
    try:
        args = ap.parse_args(argv)
    except SystemExit as ex:
        return 2 if ex.code else 0
    from ...analysis.counting import CountTimeout
    t0 = time.monotonic()
    # the model's objects live until the process ends: no cyclic garbage collection while they
    # are made (a 640 KB UVL model: 0.15 s of collections that free nothing)
    import gc
    collecting = gc.isenabled()
    gc.disable()
    try:
        # (a dotted name, "Root.A.B", is a long name: the full model knows those)
        m, errors = load(args.model, plain=not any("." in x for x in args.include + args.exclude))
        if isinstance(m, _TvlModel):
            m.a.counter  # (encoded here, collections still off)
    except OSError as ex:
        print(f"tvl-lsp count: cannot read {args.model}: {getattr(ex, 'reason', None) or ex.strerror}", file=sys.stderr)
        return 2
    except ValueError as ex:
        print(f"tvl-lsp count: {args.model}: {ex}", file=sys.stderr)
        return 2
    finally:
        if collecting:
            # ... nor after: they move to the permanent generation, which the collector does not
            # scan (re-enabled with millions of young objects, it spent 0.05 s on the first
            # collection and more on later ones: embtoolkit.uvl)
            if not gc.get_freeze_count():
                gc.freeze()
            gc.enable()
    report_errors("tvl-lsp count", args.model, m, errors)
    if isinstance(m, (_TvlModel, _PlainModel)) and args.timeout is None:
        # as for a DIMACS file: d4 in this process (a child costs its start-up; Ctrl-C still
        # ends the command)
        (m.a.counter if isinstance(m, _TvlModel) else m.counter).inprocess = True
    for name in args.include + args.exclude:
        if not m.known(name):
            print(f"tvl-lsp count: no feature named {name!r} in {args.model}", file=sys.stderr)
            return 2
    per = None
    try:
        if args.per_feature:
            n, per, engine = m.per_feature(args.include, args.exclude, args.timeout)
        else:
            c = m.count(args.include, args.exclude, args.timeout)
            n, engine = c.value, c.engine
            if c.note and engine == "pyganak":
                print(f"tvl-lsp count: counted with pyganak ({c.note})", file=sys.stderr)
    except MemoryError:
        print(f"tvl-lsp count: not enough memory to count {args.model} (a memory limit: ulimit -v?)", file=sys.stderr)
        return 2
    except CountTimeout:
        if args.json:
            print(json.dumps({"model": args.model, "count": None, "timeout": True}))
        print(f"tvl-lsp count: no answer within {args.timeout:g} s", file=sys.stderr)
        return 2
    dt = time.monotonic() - t0
    from ...base.bignum import decimal  # (counts of more than 4,300 digits: str() refuses them)
    text = decimal(n)
    if args.json:
        out = {"model": args.model, "count": _Raw(text), "count_text": text, "digits": len(text),
               "engine": engine, "include": args.include, "exclude": args.exclude,
               "n_features": m.n + (1 if isinstance(m, _DimacsModel) else 0), "seconds": round(dt, 3)}
        if per is not None:
            out["features"] = {k: _Raw(decimal(v)) for k, v in per.items()}
            out["complete"] = len(per) == out["n_features"]
        print(_dumps(out))
    else:
        if per is not None:
            for name, k in per.items():
                print(f"{name}\t{decimal(k)}")
        print(text)
    return 0


class _Raw(str):
    """A number already written in decimal, put in the JSON text as it is."""


def _dumps(obj) -> str:
    """``json.dumps`` with :class:`_Raw` numbers written as JSON numbers of any size."""
    raws: list[str] = []

    def swap(o):
        if isinstance(o, _Raw):
            raws.append(str(o))
            return f"\0{len(raws) - 1}\0"
        if isinstance(o, dict):
            return {k: swap(v) for k, v in o.items()}
        return o
    text = json.dumps(swap(obj))
    return re.sub(r'"\\u0000(\d+)\\u0000"', lambda m: raws[int(m.group(1))], text)
