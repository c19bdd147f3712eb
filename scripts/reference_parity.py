"""Accept/reject parity of tvl-lsp's TVL front end with the reference parser (TVLParser v20100804).

    TVL_REFERENCE_DIR=/path/to/jars .venv/bin/python scripts/reference_parity.py [FILE.tvl | DIR ...]
    TVL_REFERENCE_DIR=... .venv/bin/python scripts/reference_parity.py --generate 300 --seed 7

Runs ``../shared/reference/tvl-reference`` (or ``--reference PATH``) on each model and compares its
verdict ("Feature model valid" or not) with tvl-lsp's (no error diagnostic from ``parse_model``);
prints every disagreement and a summary.  ``--generate N`` writes N random small models (groups of
every kind, attributes with domains, enum and number comparisons, qualified and unqualified names,
data blocks, an occasional missing ';') into a temporary folder and checks those.  Needs Java and the
reference's jars (see ../shared/reference/README.md); the test suite records verdicts instead.
"""

from __future__ import annotations

import argparse
import os
import random
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def reference_verdict(ref: str, path: Path) -> tuple[str, str]:
    try:
        r = subprocess.run([ref, str(path)], capture_output=True, text=True, timeout=60, env=os.environ)
    except subprocess.TimeoutExpired:
        return "reject", "timeout"
    lines = (r.stdout + r.stderr).splitlines()
    i = next((k for k, ln in enumerate(lines) if "Feature model" in ln), None)
    if i is None:
        return "reject", (lines or ["no output"])[0]
    ok = "Feature model valid" in lines[i]
    return ("accept" if ok else "reject"), (lines[i + 1].strip() if i + 1 < len(lines) else lines[i])


def our_verdict(path: Path) -> tuple[str, list[str]]:
    from tvl_lsp.base.diagnostics import Severity
    from tvl_lsp.tvl import parse_model
    res = parse_model(path.read_text(encoding="utf-8", errors="replace"), str(path))
    errs = [d for d in res.diagnostics if d.severity == Severity.ERROR]
    lenient = [d for d in res.diagnostics if d.code == "reference-rejects"]
    return ("reject" if errs else "accept"), [f"{d.span.start} {d.code}: {d.message}" for d in (errs or lenient)[:3]]


def generate(rng: random.Random) -> str:
    enums = ["red", "green", "blue"]
    head = []
    if rng.random() < 0.3:
        head.append(f"enum col in {{{', '.join(rng.sample(enums, rng.randint(1, 3)))}}};")
    if rng.random() < 0.2:
        head.append(f"int num in {{{', '.join(str(x) for x in rng.sample(range(0, 5), rng.randint(1, 3)))}}};")

    def attribute():
        k = rng.random()
        if k < 0.3:
            return f"enum color in {{{', '.join(rng.sample(enums, rng.randint(1, 3)))}}};"
        if k < 0.5:
            dom = rng.choice(["{1, 2}", "{0, 3}", "[1..4]", "{2}", ""])
            tail = rng.choice(["", ", ifin: is 1", ", ifin: in {1}"]) if dom else rng.choice(["", ", ifin: is 1", " is 2"])
            return f"int price{(' in ' + dom) if dom else ''}{tail};"
        if k < 0.6:
            return f"bool used is {rng.choice(['true', 'false'])};"
        if k < 0.7 and head and head[0].startswith("enum col"):
            return "col color;"
        return None

    def constraint():
        a, b = rng.sample(["A", "B", "C", "D", "E"], 2)
        if rng.random() < 0.6:
            return rng.choice([f"{a} -> {b};", f"ifIn: {a} || !{b};", f"ifOut: !{a};", f"{a} <-> !{b};",
                               f"this.color == {rng.choice(enums)};", f"price <= {rng.choice(['1', '2'])};",
                               f"parent.price == {rng.choice(['1', '2', 'price'])};"])
        return rng.choice([
            f"{rng.choice(['color', 'parent.color', 'this.color'])} == {rng.choice(enums + ['color', 'parent.color'])};",
            f"{rng.choice(['price', 'parent.price'])} {rng.choice(['==', '<=', '>', '!='])} "
            f"{rng.choice(['1', '2', '5', '0', 'price', 'parent.price'])};",
            f"{rng.choice(['price', '1'])} + 1 {rng.choice(['==', '<='])} {rng.choice(['2', 'price'])};",
            f"{a} && {b}" + rng.choice([";", ";", ";", ""])])

    out = []
    for f, kids in (("A", ["B", "C"]), ("B", ["D"]), ("C", ["E"])):
        items = [f"group {rng.choice(['allOf', 'oneOf', 'someOf', '[1..2]', '[0..1]'])} {{ "
                 + ", ".join(("opt " if rng.random() < 0.4 else "") + k for k in kids) + " }"]
        items += [a for a in (attribute() for _ in range(rng.randint(0, 2))) if a]
        items += [constraint() for _ in range(rng.randint(0, 2))]
        if rng.random() < 0.1:
            items.append(rng.choice(['data { "k" "v" }', 'data { "k" "v"; }', 'data { "a" "b"; "c" "d" }']))
        out.append(("root A" if f == "A" else f) + " {\n  " + "\n  ".join(items) + "\n}")
    return "\n".join(head + out) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("paths", nargs="*")
    ap.add_argument("--reference", default=str(ROOT.parent / "shared" / "reference" / "tvl-reference"))
    ap.add_argument("--generate", type=int, default=0, metavar="N")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    files: list[Path] = []
    for p in args.paths:
        pp = Path(p)
        files += sorted(pp.rglob("*.tvl")) if pp.is_dir() else [pp]
    tmp = None
    if args.generate:
        tmp = tempfile.TemporaryDirectory()
        rng = random.Random(args.seed)
        for i in range(args.generate):
            f = Path(tmp.name) / f"gen{args.seed}_{i:04d}.tvl"
            f.write_text(generate(rng))
            files.append(f)
    bad = accepted = known = 0
    for f in files:
        rv, rmsg = reference_verdict(args.reference, f)
        ov, omsgs = our_verdict(f)
        accepted += rv == "accept"
        if rv != ov:
            bad += 1
            known += any("reference-rejects" in m for m in omsgs)  # a deliberate, warned leniency
            print(f"DIFFERENT {f}: reference {rv} ({rmsg[:160]}); tvl-lsp {ov} {omsgs}")
    print(f"{len(files)} models, {accepted} accepted by the reference, {bad} verdicts differ"
          + (f" ({known} of them deliberate leniencies warned as reference-rejects)" if known else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
