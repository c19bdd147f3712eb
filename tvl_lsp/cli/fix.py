"""``tvl-lsp --check --fix``: the quick fixes of model anomalies (:mod:`tvl_lsp.project.fixes`, the
function the editor's code actions call) applied to every TVL / UVL model under the paths.

Dry run by default: a unified diff per model on stdout (``git apply`` / ``patch -p1`` read it),
what each fix does on stderr, and the exit status 1 when there is something to fix.  With
``--apply`` the fixed models are written (atomically, never through a link, and only when the
file still holds the text that was fixed), then the check runs as usual on the result.
"""

from __future__ import annotations

import difflib
import os
import sys
from typing import Optional


def unified_diff(old: str, new: str, name: str) -> str:
    """``diff -u`` of two texts, as ``a/NAME`` and ``b/NAME`` (a missing final newline marked
    the way ``diff`` and ``git`` mark it)."""
    a, b = old.splitlines(True), new.splitlines(True)
    out = []
    for line in difflib.unified_diff(a, b, f"a/{name}", f"b/{name}"):
        if line.startswith(("---", "+++")):
            out.append(line.rstrip("\n") + "\n")
        elif not line.endswith(("\n", "\r")):
            out.append(line + "\n\\ No newline at end of file\n")
        else:
            out.append(line)
    return "".join(out)


def _display(path: str) -> str:
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return path
    return path if rel.startswith("..") else rel


def _write(path: str, text: str, expected: str) -> Optional[str]:
    """Write ``text`` over ``path`` (the project's safe writer: atomic, never through a link, the
    file's permissions kept) if the file still holds ``expected``; None, or why not."""
    from ..base.files import read_bytes
    from ..base.safewrite import write_file
    try:
        raw = read_bytes(path)
        now = raw.decode("utf-8")
    except UnicodeDecodeError:
        return "it is not valid UTF-8 (rewriting it would replace the bytes that are not)"
    except (OSError, ValueError) as exc:
        return f"it cannot be read again ({exc})"
    if now != expected:
        return "the file changed while it was being fixed"
    try:
        write_file(path, text)
    except OSError as exc:
        return str(exc)
    return None


def run(paths: list[str], codes: set[str], apply: bool, budget: Optional[float], quiet: bool,
        output: Optional[str]) -> tuple[int, int]:
    """Fix the models under ``paths``; returns (fixes made or proposed, files that could not be
    written).  Prints the diff (dry run) and what each fix does."""
    from ..analysis.formats import model_format
    from ..project.fixes import fix_file
    from ..project.workspace import default_read_file, discover_files
    found = discover_files(paths)
    models = sorted(m for m in found.models if model_format(m) in ("tvl", "uvl"))
    diffs: list[str] = []
    fixes = files = failed = 0
    for m in models:
        text = default_read_file(m)
        if text is None:
            continue
        run = fix_file(m, text, default_read_file, codes, budget)
        name = _display(m)
        for _, title in run.applied:
            print(f"{name}: {title}", file=sys.stderr)
        if not quiet:
            for d in run.unfixed:
                p = d.span.start
                print(f"{name}:{p.line + 1}:{p.col + 1}: no fix found for [{d.code}] {d.message}", file=sys.stderr)
            if run.unreached:
                print(f"{name}: the fixes stopped at their time budget ({budget:g} s, --fix-budget) with "
                      f"{len(run.left)} finding(s) not reached; run again to go on", file=sys.stderr)
        if run.text == text:
            continue
        fixes += len(run.applied)
        files += 1
        if apply:
            why = _write(m, run.text, text)
            if why is not None:
                failed += 1
                print(f"tvl-lsp --check --fix: error: {name} not written: {why}", file=sys.stderr)
        else:
            diffs.append(unified_diff(text, run.text, name))
    if not apply:
        out = "".join(diffs)
        if output:
            why = _write_report(output, out)
            if why:
                print(f"tvl-lsp --check --fix: error: {why}", file=sys.stderr)
                failed += 1
        else:
            sys.stdout.write(out)
            sys.stdout.flush()
    if not quiet:
        verb = "made" if apply else "proposed (nothing written: --apply writes them)"
        print(f"{fixes} fix(es) in {files} model(s) {verb}", file=sys.stderr)
    return fixes, failed


def _write_report(path: str, text: str) -> Optional[str]:
    from ..base.safewrite import write_output
    try:
        write_output(path, text)
    except OSError as exc:
        return str(exc)
    return None
