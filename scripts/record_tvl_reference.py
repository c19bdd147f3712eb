#!/usr/bin/env python3
"""Record what the TVL reference parser says about our own TVL fixtures.

    TVL_REFERENCE_DIR=/path/to/TVLParser-20100804 python3 scripts/record_tvl_reference.py [--check]

Runs TVLParser v20100804 (the library the HAROS-TVL thesis used; its jars are third-party and
are never part of this repository: see docs/testing.md, "The TVL reference parser") on every
``tests/data/tvl/reference/*.tvl`` and writes its verdict, message and error position into
``tests/data/tvl_reference_fixtures.json``, keeping what we wrote there by hand: the code and line
of the error tvl-lsp must report on a rejected file (``code``, ``line``), and for a file where
tvl-lsp deliberately answers otherwise, its verdict and why (``tvl_lsp``, ``divergence``).
``tests/test_tvl_reference.py`` compares tvl-lsp with that record, without the reference.
``--check`` only compares the reference's answers with the record (exit 1 on a difference).

Needs Java 8+ and the reference's four jars in TVL_REFERENCE_DIR (TVLParser.jar,
java-cup-11a-runtime.jar, JFlex.jar, org.sat4j.core.jar; TVL_REFERENCE_JAVA names another java).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
FIXTURES = REPO / "tests" / "data" / "tvl" / "reference"
RECORD = REPO / "tests" / "data" / "tvl_reference_fixtures.json"
JARS = ("TVLParser.jar", "java-cup-11a-runtime.jar", "JFlex.jar", "org.sat4j.core.jar")
ABOUT = ("What TVLParser v20100804 (the TVL reference parser) answers on each of tests/data/tvl/reference/*.tvl, "
         "recorded by scripts/record_tvl_reference.py: reference = accept|reject, verdict = its verdict line, "
         "message = its message, at = the line and column it names (syntax errors). Written by hand: code and "
         "line = the first error tvl-lsp must report on a rejected file; tvl_lsp and divergence = where tvl-lsp "
         "deliberately answers otherwise, and why.")


def jar_folder(folder: str) -> Path:
    d = Path(folder)
    missing = [j for j in JARS if not (d / j).is_file() and not (d / "libs" / j).is_file()]
    if missing:
        sys.exit(f"record_tvl_reference: {', '.join(missing)} not found in {d} (or {d / 'libs'})")
    return d


def run_reference(folder: Path, model: Path) -> dict:
    cp = os.pathsep.join(str(folder / j) if (folder / j).is_file() else str(folder / "libs" / j) for j in JARS)
    java = os.environ.get("TVL_REFERENCE_JAVA", "java")
    proc = subprocess.run([java, "-cp", cp, "be.ac.info.fundp.TVLParser.Launcher", "-s", model.name],
                          cwd=model.parent, capture_output=True, text=True, timeout=120)
    lines = [ln.rstrip() for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()]
    verdict = next((ln for ln in lines if ln.startswith("Feature model")), None)
    if verdict is None:
        raise RuntimeError(f"no verdict from the reference on {model.name}:\n" + "\n".join(lines[:20]))
    out: dict = {"reference": "accept" if verdict.startswith("Feature model valid") else "reject",
                 "verdict": verdict}
    if out["reference"] == "reject":
        i = lines.index(verdict)
        msg = lines[i + 1].strip() if i + 1 < len(lines) else ""
        out["message"] = msg.strip("'").strip()
        m = re.search(r"line (\d+), column (\d+)", out["message"])
        if m:
            out["at"] = [int(m.group(1)), int(m.group(2))]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="compare with the record instead of writing it")
    ns = ap.parse_args(argv)
    folder = os.environ.get("TVL_REFERENCE_DIR")
    if not folder:
        sys.exit("record_tvl_reference: set TVL_REFERENCE_DIR to the folder holding TVLParser.jar")
    folder = jar_folder(folder)
    old = json.loads(RECORD.read_text()) if RECORD.is_file() else {"models": {}}
    models = {}
    differ = []
    for model in sorted(FIXTURES.glob("*.tvl")):
        got = run_reference(folder, model)
        entry = dict(old["models"].get(model.name, {}))
        recorded = {k: entry.get(k) for k in ("reference", "verdict", "message", "at") if k in entry}
        if {k: v for k, v in got.items()} != recorded:
            differ.append((model.name, recorded, got))
        for k in ("message", "at"):
            entry.pop(k, None)
        entry.update(got)
        models[model.name] = {k: entry[k] for k in ("reference", "verdict", "message", "at", "code", "line",
                                                    "tvl_lsp", "divergence") if k in entry}
        print(f"{model.name}: {got['reference']}" + (f" ({got['message'][:100]})" if "message" in got else ""))
    gone = sorted(set(old["models"]) - set(models))
    if ns.check:
        for name, was, now in differ:
            print(f"DIFFERS {name}: recorded {was}, the reference now says {now}", file=sys.stderr)
        for name in gone:
            print(f"DIFFERS {name}: recorded, but the fixture is gone", file=sys.stderr)
        return 1 if differ or gone else 0
    RECORD.write_text(json.dumps({"_about": ABOUT, "models": models}, indent=1, ensure_ascii=False) + "\n")
    print(f"wrote {RECORD.relative_to(REPO)} ({len(models)} models, {len(differ)} changed)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
