"""The computation graph read from the package sources (issue #26): each program's publishers,
subscriptions, services, actions and parameters, with their types, for ROS 1 and ROS 2, C++ and
Python, read with tree-sitter (no compiler, no headers, no ``compile_commands.json``).

    ex = extract(["ws/src"])              # Extraction: packages, executables, endpoints, notes
    ex.endpoints()                        # every call site (Endpoint), sorted
    ex.by_node_type()["turtlesim/turtlesim_node"].endpoints

Pure: files are read through the bounded reader; facts are cached by content
(:mod:`.cache`); ``texts`` gives unsaved editor contents.  The graph (:mod:`tvl_lsp.graph.build`)
resolves the names of each launched node against its namespace and remaps.
"""

from __future__ import annotations

import copy
import os
from typing import Mapping, Optional

from ...base.files import read_text_or_none
from . import cache
from .discover import (PackageFiles, Program, cpp_programs, find_packages, interfaces_of, package_files,
                       python_programs)
from .link import dedupe, link_cpp, link_py
from .model import KINDS, LINK_OF_KIND, RESOURCE_OF, Endpoint, Executable, Extraction, Package

__all__ = ["extract", "Extraction", "Executable", "Endpoint", "Package", "KINDS", "LINK_OF_KIND", "RESOURCE_OF",
           "source_language"]

_API_CLASSES = ("ActionServer", "ActionClient", "Subscriber", "SubscriberFilter", "ServiceClient")
# program -> (the facts it was linked from, its endpoints): linking again only when a file changed
_LINK_MEMO: dict[tuple, tuple[list, list]] = {}


def source_language(path: str) -> Optional[str]:
    """``cpp`` / ``python`` for a source extraction reads, else None."""
    low = path.lower()
    if low.endswith((".cpp", ".cc", ".cxx", ".c++", ".cu", ".h", ".hpp", ".hh", ".hxx", ".h++", ".ipp", ".tpp")):
        return "cpp"
    if low.endswith(".py"):
        return "python"
    return None


def extract(paths, texts: Optional[Mapping[str, str]] = None, disk: bool = True,
            only: Optional[set] = None) -> Extraction:
    """Every package under (or around) ``paths``: its programs and their endpoints (``only``:
    just the packages of these names; the others still say which messages they define)."""
    texts = {os.path.normpath(os.path.abspath(k)): v for k, v in (texts or {}).items()}

    def read(p: str) -> Optional[str]:
        p = os.path.normpath(p)
        if p in texts:
            return texts[p]
        return read_text_or_none(p, 4 * 1024 * 1024)

    ex = Extraction()
    stats = cache.Stats()
    pkgs = find_packages([os.path.abspath(p) for p in paths])
    if not pkgs:
        # sources without a package.xml (a bare folder of nodes): read as one package named
        # after the folder, its ROS version from the calls
        pkgs = [Package(os.path.basename(os.path.normpath(p)) or "sources", os.path.normpath(p), None, 0)
                for p in (os.path.abspath(x) for x in paths) if os.path.isdir(p)]
    pfs: list[PackageFiles] = []
    known: dict[str, set] = {}
    cmake_edited = any(os.path.basename(k) in ("CMakeLists.txt", "setup.py", "setup.cfg") for k in texts)
    for pkg in pkgs:
        if only is not None and pkg.name not in only:
            known[pkg.name] = interfaces_of(pkg.folder)
            continue
        pf = package_files(pkg, read, memo=not cmake_edited)
        pfs.append(pf)
        known[pkg.name] = pf.interfaces
        ex.notes += pf.notes
    known_sig = hash(tuple(sorted((k, tuple(sorted(v))) for k, v in known.items())))
    facts_memo: dict[str, Optional[dict]] = {}

    def facts(path: str, lang: str) -> Optional[dict]:
        if path in facts_memo:
            return facts_memo[path]
        f, note = cache.facts_for(path, lang, texts.get(path), stats, disk)
        if note and "syntax errors" not in note:
            ex.notes.append(f"{path}: {note}")
        facts_memo[path] = f
        return f

    def includes_of(path: str) -> list[str]:
        f = facts(path, "cpp")
        return f.get("includes", []) if f else []

    def imports_of(path: str) -> list:
        f = facts(path, "python")
        return f.get("imports", []) if f else []

    def has_calls(lang: str):
        def test(path: str) -> bool:
            f = facts(path, lang)
            if not f:
                return False
            if f.get("calls"):
                return True
            return any(any(k in (c.get("t") or "") for k in _API_CLASSES) for c in f.get("ctors", []))
        return test

    for pf in pfs:
        pkg = pf.package
        ex.packages.append(pkg)
        progs: list[Program] = cpp_programs(pf, includes_of, has_calls("cpp"))
        progs += python_programs(pf, read, imports_of, has_calls("python"))
        ros = pkg.ros or _guess_ros(pf, facts)
        for prog in progs:
            lang = prog.language
            files = [(f, facts(f, lang)) for f in prog.files]
            files = [(f, x) for f, x in files if x]
            key = (pkg.name, prog.name, prog.kind, prog.only_class, prog.skip_classes, ros, known_sig,
                   tuple(f for f, _ in files))
            hit = _LINK_MEMO.get(key)
            if hit is not None and len(hit[0]) == len(files) and all(a is b for a, (_, b) in zip(hit[0], files)):
                eps = [copy.copy(e) for e in hit[1]]
            else:
                if lang == "cpp":
                    eps = link_cpp(pkg.name, prog.name, ros, files, known, prog.only_class, prog.skip_classes)
                else:
                    eps = link_py(pkg.name, prog.name, ros, files, known)
                eps = dedupe(eps)
                eps.sort(key=lambda e: (e.file, e.line, e.col, e.kind, e.name))
                if len(_LINK_MEMO) > 5000:
                    _LINK_MEMO.clear()
                _LINK_MEMO[key] = ([x for _, x in files], [copy.copy(e) for e in eps])
            ex.executables.append(Executable(pkg.name, prog.name, prog.kind, lang, list(prog.files), eps,
                                             list(prog.aliases)))
    ex.files_read = stats.read
    ex.files_parsed = stats.parsed
    if disk:
        cache.flush()
    ex.executables.sort(key=lambda x: (x.package, x.name, x.kind))
    return ex


def _guess_ros(pf: PackageFiles, facts) -> int:
    votes = {1: 0, 2: 0}
    for f in pf.cpp[:200]:
        x = facts(f, "cpp")
        for c in (x or {}).get("calls", []):
            if c.get("ros") in votes:
                votes[c["ros"]] += 1
    for f in pf.python[:200]:
        x = facts(f, "python")
        for c in (x or {}).get("calls", []):
            if c.get("ros") in votes:
                votes[c["ros"]] += 1
    if votes[1] == votes[2]:
        return 0
    return 1 if votes[1] > votes[2] else 2
