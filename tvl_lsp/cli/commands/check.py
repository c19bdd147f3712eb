"""``tvl-lsp --check [PATH ...]``: check models, launch files and HAROS project files (for CI).

Exit status: 0 when no error was found, 1 when there are errors (or warnings with
``--strict``), 2 on a usage error or an internal failure.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from typing import Optional

from ...project.budget import CHECK_CPU_SECONDS, CHECK_MEMORY_BYTES

FIX_SECONDS = 60.0

EPILOG = """\
formats:
  text    path:line:col: severity[code] message   (1-based line and column)
  json    a list of {path, range, severity, code, message, related, witness}; 0-based LSP
          positions, character in UTF-16 code units; witness: feature -> true/false
  sarif   SARIF 2.1.0 (GitHub code scanning, VS Code SARIF viewer, ...)
  github  GitHub Actions workflow commands (::error file=...,line=...::message)

--fix shows the quick fixes of model anomalies as a unified diff (tvl-lsp --check --fix models/ |
git apply); --fix --apply writes them and reports what is left.  --select / --ignore choose the
codes fixed.

Pairing a launch file with its model: a HAROS project file (configurations: {lf: ..., tvl: ...}),
else a marker comment <!-- tvl-lsp: model=path/to/model.tvl --> in the launch file, else a .tvl
with the same name in the same folder.  `tvl-lsp --explain CODE` documents each code.
"""


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # exit 2 with our own message, never SystemExit from deep inside
        raise _UsageError(message)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="tvl-lsp --check", description="Check TVL models and the launch files they configure.",
                epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("paths", nargs="*", metavar="PATH", help="files or folders (default: .)")
    p.add_argument("--format", "-f", choices=("text", "json", "sarif", "github"), default="text")
    p.add_argument("--select", action="append", default=[], metavar="CODE[,CODE...]",
                   help="report only these codes (repeatable)")
    p.add_argument("--ignore", action="append", default=[], metavar="CODE[,CODE...]",
                   help="do not report these codes (repeatable)")
    p.add_argument("--strict", action="store_true",
                   help="warnings, and files named on the command line that are not checked, "
                        "also make the exit status 1")
    p.add_argument("--output", "-o", metavar="FILE", help="write the report to FILE instead of stdout")
    p.add_argument("--jobs", "-j", type=int, default=None, metavar="N",
                   help="parallel processes (default: one per CPU; 1: no processes)")
    p.add_argument("--quiet", "-q", action="store_true", help="no summary line on stderr")
    p.add_argument("--budget", type=float, default=None, metavar="SECONDS",
                   help="CPU seconds one file's check may use (default: %g; 0: no limit); past it the file "
                        "gets analysis-budget-exceeded and what was finished (e.g. its syntax and type checks)"
                        % CHECK_CPU_SECONDS)
    p.add_argument("--memory", type=int, default=None, metavar="MB",
                   help="memory the check may allocate, in MB (default: %d)" % (CHECK_MEMORY_BYTES // 1024 ** 2))
    p.add_argument("--fix", action="store_true",
                   help="fix the anomalies of TVL and UVL models (void model, dead and false-optional features, "
                        "redundant and always-false constraints), each fix checked to remove its finding and add "
                        "none: prints a unified diff and writes nothing (exit 1 when there is something to fix)")
    p.add_argument("--apply", action="store_true",
                   help="with --fix: write the fixed models, then check as usual")
    p.add_argument("--fix-budget", type=float, default=FIX_SECONDS, metavar="SECONDS",
                   help="seconds the fixes of one model may take (default: %g)" % FIX_SECONDS)
    return p


def _codes(values: list[str]) -> set[str]:
    out = set()
    for v in values:
        for c in v.split(","):
            c = c.strip()
            if c:
                out.add(c)
    return out


def main(argv: Optional[list[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        if "-h" in argv or "--help" in argv:
            parser.print_help()
            return 0
        ns = parser.parse_args(argv)
        from ...project import check
        from ...base.diagnostics import CODES, Severity
        from ...project.workspace import discover_files
        from ..output import render
        from ...project.workspace import default_read_file
        select, ignore = _codes(ns.select), _codes(ns.ignore)
        from .explain import load_codes
        load_codes()   # the front ends register their codes when imported (SARIF's rules use them)
        unknown = sorted((select | ignore) - set(CODES))
        if unknown:
            import difflib
            hints = []
            for u in unknown:
                m = difflib.get_close_matches(u, sorted(CODES), n=1)
                hints.append(f"`{u}`" + (f" (did you mean `{m[0]}`?)" if m else ""))
            raise _UsageError("unknown diagnostic code " + ", ".join(hints) + "; `tvl-lsp --explain` lists them")
        paths = ns.paths or ["."]
        missing = [p for p in paths if not os.path.exists(p)]
        if missing:
            raise _UsageError("no such file or folder: " + ", ".join(missing))
        if ns.jobs is not None and ns.jobs < 1:
            raise _UsageError("--jobs must be at least 1")
        if ns.budget is not None and not ns.budget >= 0:
            raise _UsageError("--budget must be a number of seconds, 0 or more")
        if ns.memory is not None and ns.memory < 64:
            raise _UsageError("--memory must be at least 64 (MB)")
        if ns.apply and not ns.fix:
            raise _UsageError("--apply goes with --fix (tvl-lsp --check --fix --apply)")
        if not ns.fix_budget > 0:
            raise _UsageError("--fix-budget must be a number of seconds above 0")
    except _UsageError as exc:
        print(f"tvl-lsp --check: error: {exc}", file=sys.stderr)
        return 2

    if ns.fix:
        from ...project.fixes import ANOMALY_CODES
        from .. import fix
        codes = (set(ANOMALY_CODES) & select if select else set(ANOMALY_CODES)) - ignore
        try:
            from ...project.budget import cap_memory
            from ...project import supervise as sv
            args = (paths, codes, ns.apply, ns.fix_budget, ns.quiet, None if ns.apply else ns.output)
            with cap_memory(CHECK_MEMORY_BYTES if ns.memory is None else ns.memory * 1024 ** 2):
                # in a watched worker where there are: at the memory limit a process can spin
                # for ever or abort (project.supervise)
                made, failed = sv.call(fix.run, *args) if sv.available() else fix.run(*args)
        except MemoryError:
            print("tvl-lsp --check --fix: error: the fixes needed more memory than --memory allows",
                  file=sys.stderr)
            return 2
        except BrokenPipeError:
            raise
        except Exception as exc:
            print("tvl-lsp --check --fix: internal error (please report it):", file=sys.stderr)
            if isinstance(exc, RuntimeError) and str(exc).startswith("Traceback"):
                print(str(exc).rstrip(), file=sys.stderr)  # (the worker's)
            else:
                traceback.print_exc()
            return 2
        if failed:
            return 2
        if not ns.apply:
            return 1 if made else 0

    from ...project.workspace import explicit_skip_reason
    # a file named explicitly that is not checked gets a diagnostic of the report
    # (file-not-checked: project.check.check_paths), not silence
    skipped = [(p, r) for p in paths if os.path.lexists(p) and not os.path.isdir(p)
               and (r := explicit_skip_reason(p)) is not None]

    try:
        from ...project.budget import cap_memory
        memory = CHECK_MEMORY_BYTES if ns.memory is None else ns.memory * 1024 ** 2
        seconds = CHECK_CPU_SECONDS if ns.budget is None else (ns.budget if ns.budget < 1e6 else 0)
        with cap_memory(memory):  # past it an allocation fails and that file gets analysis-budget-exceeded
            diags = check.check_paths(paths, jobs=ns.jobs, cpu_budget=seconds, supervise=True)
        if select:
            diags = [d for d in diags if d.code in select]
        if ignore:
            diags = [d for d in diags if d.code not in ignore]
        text = render(ns.format, diags, default_read_file)
        if ns.output:
            from ...base.safewrite import write_output
            try:  # atomic, never through a link; a full disk is one line, not a traceback
                write_output(ns.output, text)
            except OSError as ex:
                print(f"tvl-lsp --check: {ex}", file=sys.stderr)
                return 2
        else:
            sys.stdout.write(text)
            sys.stdout.flush()
    except BrokenPipeError:
        raise
    except Exception:
        print("tvl-lsp --check: internal error (please report it):", file=sys.stderr)
        traceback.print_exc()
        return 2

    n_err = sum(1 for d in diags if d.severity == Severity.ERROR)
    n_warn = sum(1 for d in diags if d.severity == Severity.WARNING)
    n_other = len(diags) - n_err - n_warn
    if not ns.quiet:
        files = len({d.path for d in diags})
        found = discover_files(paths)
        not_checked = {os.path.abspath(p) for p, _ in skipped}
        checked = sum(1 for f in found.models + found.launches + found.yamls if f not in not_checked)
        other_xml = sum(1 for f in found.skipped_xml if f not in not_checked)
        print(f"{n_err} error(s), {n_warn} warning(s), {n_other} note(s) in {files} file(s); "
              f"{checked} file(s) checked" + (f", {len(skipped)} named file(s) not checked" if skipped else "")
              + (f"; {other_xml} XML file(s) skipped: their root element is not <launch>" if other_xml else ""),
              file=sys.stderr)
    if n_err or (ns.strict and (n_warn or skipped)):
        return 1
    return 0
