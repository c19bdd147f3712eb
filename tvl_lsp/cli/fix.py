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
    """Write ``text`` over ``path`` if the file still holds ``expected``; None, or why not."""
    from ..base.files import read_text_or_none
    if read_text_or_none(path) != expected:
        return "the file changed while it was being fixed"
    try:
        from ..base import safewrite  # (the project's safe writer, #28)
    except ImportError:
        safewrite = None
    if safewrite is not None:
        try:
            safewrite.write_file(path, text)
        except OSError as exc:
            return str(exc)
        return None
    return _atomic_write(path, text)


def _atomic_write(path: str, text: str) -> Optional[str]:
    """A new file beside ``path`` renamed over it: atomic, never through a link."""
    import tempfile
    if os.path.islink(path) or not os.path.isfile(path):
        return "it is not a regular file (a link or a special file is never written through)"
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".tvl-lsp-", suffix=".tmp", dir=folder)
    try:
        data = text.encode("utf-8", "surrogatepass")
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        os.fsync(fd)
        os.close(fd)
        fd = -1
        os.chmod(tmp, os.stat(path).st_mode & 0o7777)
        os.replace(tmp, path)
        tmp = ""
    except OSError as exc:
        return f"cannot write it: {exc.strerror or exc}"
    finally:
        if fd >= 0:
            os.close(fd)
        if tmp:
            try:
                os.unlink(tmp)
            except OSError:
                pass
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
    try:
        from ..base import safewrite
    except ImportError:
        safewrite = None
    try:
        if safewrite is not None:
            safewrite.write_output(path, text)
        else:
            with open(path, "w", encoding="utf-8", newline="") as fh:
                fh.write(text)
    except OSError as exc:
        return str(exc)
    return None
