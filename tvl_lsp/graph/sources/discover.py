"""Packages and their programs: which sources make which executable.

- packages: every folder with a ``package.xml`` under the given paths (colcon's rules: the search
  stops at a package; ``COLCON_IGNORE`` / ``AMENT_IGNORE`` / ``CATKIN_IGNORE`` hide a folder; build,
  install, log and hidden folders are skipped), or the package a given path lies in; its build
  type (``launch.ros2.ament.read_manifest``) says ROS 1 (catkin) or ROS 2 (ament);
- C++ programs from ``CMakeLists.txt`` (:mod:`.cmake`): an executable's sources, those of the
  package's libraries it links, and the package's headers they include; components registered
  with ``rclcpp_components_register_node(s)``; libraries no program links (plugins) and sources
  no target names are listed too, under their own name, so that nothing is missed;
- Python programs: scripts installed by ``catkin_install_python`` / ``install(PROGRAMS)`` /
  ``setup.py`` ``scripts``, executable files with a Python shebang (``rosrun`` finds those),
  ``console_scripts`` entry points of ``setup.py`` / ``setup.cfg``; each with the modules of its
  package it imports (a node spread over modules).

Every read goes through the bounded reader; walks are bounded.
"""

from __future__ import annotations

import ast
import os
import re
import stat
from dataclasses import dataclass, field
from typing import Callable, Optional

from ...base.files import read_head_text
from ...launch.ros2.ament import read_manifest
from .cmake import CMakeInfo, read_cmake
from .model import Package

SKIP = {".git", "build", "install", "log", "devel", "node_modules", ".venv", "__pycache__", ".hg", ".svn",
        ".tox", "site-packages"}
IGNORE_MARKERS = ("COLCON_IGNORE", "AMENT_IGNORE", "CATKIN_IGNORE")
MAX_DIRS = 20000
MAX_FILES_PER_PACKAGE = 6000
MAX_CLOSURE = 400
CPP_EXT = (".cpp", ".cc", ".cxx", ".c++", ".cu")
HDR_EXT = (".h", ".hpp", ".hh", ".hxx", ".h++", ".ipp", ".tpp", ".inl")
PY_EXT = (".py",)

Read = Callable[[str], Optional[str]]


@dataclass
class Program:
    name: str
    kind: str                 # executable | component | script | console_script | library | test | source
    language: str             # cpp | python
    files: list[str] = field(default_factory=list)
    only_class: Optional[str] = None   # a component in a library of several: its class
    aliases: list[str] = field(default_factory=list)
    skip_classes: frozenset = frozenset()   # a library's rest: the calls of these classes are the components'


@dataclass
class PackageFiles:
    package: Package
    cpp: list[str] = field(default_factory=list)      # .cpp and headers
    python: list[str] = field(default_factory=list)   # .py and Python scripts without suffix
    interfaces: set = field(default_factory=set)      # msg / srv / action names it defines
    cmake: Optional[CMakeInfo] = None
    notes: list[str] = field(default_factory=list)


# ------------------------------------------------------------------ packages

def _manifest(folder: str) -> Optional[Package]:
    head = read_head_text(os.path.join(folder, "package.xml"), 200_000)
    if head is None:
        return None
    m = read_manifest(head, folder)
    bt = m.build_type or ""
    ros = 1 if bt == "catkin" else 2 if bt.startswith("ament") else 0
    if ros == 0:
        if re.search(r"<buildtool_depend>\s*catkin\s*</buildtool_depend>", head):
            ros = 1
        elif re.search(r"ament_|rclcpp|rclpy", head):
            ros = 2
        elif re.search(r"\b(roscpp|rospy)\b", head):
            ros = 1
    return Package(m.name, os.path.normpath(folder), m.build_type, ros)


def find_packages(paths: list[str]) -> list[Package]:
    """The packages under (or around) ``paths``, each once, sorted by name."""
    out: dict[str, Package] = {}
    count = 0
    for p in paths:
        p = os.path.abspath(p)
        if os.path.isfile(p):
            p = os.path.dirname(p)
        # a path inside a package: that package
        d = p
        for _ in range(40):
            if os.path.isfile(os.path.join(d, "package.xml")):
                pkg = _manifest(d)
                if pkg is not None:
                    out.setdefault(pkg.folder, pkg)
                break
            nd = os.path.dirname(d)
            if nd == d:
                break
            d = nd
        else:
            pass
        if os.path.isfile(os.path.join(p, "package.xml")):
            continue
        for dirpath, dirnames, filenames in os.walk(p):
            count += 1
            if count > MAX_DIRS:
                break
            dirnames[:] = sorted(x for x in dirnames if x not in SKIP and not x.startswith("."))
            if any(m in filenames for m in IGNORE_MARKERS):
                dirnames[:] = []
                continue
            if "package.xml" in filenames:
                dirnames[:] = []
                pkg = _manifest(dirpath)
                if pkg is not None:
                    out.setdefault(pkg.folder, pkg)
    return sorted(out.values(), key=lambda x: (x.name, x.folder))


def _is_python_script(path: str, name: str, mode: int) -> bool:
    if name.endswith(PY_EXT):
        return True
    if "." in name or not (mode & stat.S_IXUSR):
        return False
    head = read_head_text(path, 256)
    return bool(head) and head.startswith("#!") and "python" in head.split("\n", 1)[0]


def package_files(pkg: Package, read: Read, memo: bool = True) -> PackageFiles:
    """The sources of a package (bounded), its interfaces and its CMake targets (``memo``: reuse
    what its unchanged CMake files said last time)."""
    pf = PackageFiles(pkg)
    n = 0
    for dirpath, dirnames, filenames in os.walk(pkg.folder):
        dirnames[:] = sorted(x for x in dirnames if x not in SKIP and not x.startswith(".")
                             and not os.path.isfile(os.path.join(dirpath, x, "package.xml")))
        if any(m in filenames for m in IGNORE_MARKERS) and dirpath != pkg.folder:
            dirnames[:] = []
            continue
        base = os.path.basename(dirpath)
        for fn in sorted(filenames):
            p = os.path.join(dirpath, fn)
            if base in ("msg", "srv", "action") and fn.endswith((".msg", ".srv", ".action")):
                pf.interfaces.add(fn.rsplit(".", 1)[0])
                continue
            low = fn.lower()
            if low.endswith(CPP_EXT + HDR_EXT):
                pf.cpp.append(p)
                n += 1
            elif low.endswith(PY_EXT) or "." not in fn:
                try:
                    st = os.stat(p)
                except OSError:
                    continue
                if not stat.S_ISREG(st.st_mode):
                    continue
                if _is_python_script(p, fn, st.st_mode):
                    pf.python.append(p)
                    n += 1
            if n > MAX_FILES_PER_PACKAGE:
                pf.notes.append(f"{pkg.name}: more than {MAX_FILES_PER_PACKAGE} sources; the rest is not read")
                return pf
    if os.path.isfile(os.path.join(pkg.folder, "CMakeLists.txt")):
        pf.cmake = _cmake(pkg.folder, read, memo, tuple(pf.cpp) + tuple(pf.python))
        if pf.cmake is not None:
            pf.notes += pf.cmake.notes
    return pf


_CMAKE_MEMO: dict[str, tuple[tuple, Optional[CMakeInfo]]] = {}


def _stat_sig(files, sources: tuple) -> tuple:
    out = []
    for f in files:
        try:
            st = os.stat(f)
            out.append((f, st.st_mtime_ns, st.st_size))
        except OSError:
            out.append((f, None, None))
    return (tuple(out), hash(sources))


def _cmake(folder: str, read: Read, memo: bool, sources: tuple) -> Optional[CMakeInfo]:
    """read_cmake, kept while the CMake files it read and the package's sources are the same."""
    hit = _CMAKE_MEMO.get(folder) if memo else None
    if hit is not None and hit[1] is not None and _stat_sig(hit[1].files, sources) == hit[0]:
        return hit[1]
    info = read_cmake(folder, read)
    if memo and info is not None:
        if len(_CMAKE_MEMO) > 2000:
            _CMAKE_MEMO.clear()
        _CMAKE_MEMO[folder] = (_stat_sig(info.files, sources), info)
    return info


def interfaces_of(folder: str) -> set:
    """The message, service and action names a package defines (its msg/, srv/, action/)."""
    out = set()
    for sub in ("msg", "srv", "action"):
        try:
            names = os.listdir(os.path.join(folder, sub))
        except OSError:
            continue
        out.update(n.rsplit(".", 1)[0] for n in names if n.endswith((".msg", ".srv", ".action")))
    return out


# ------------------------------------------------------------------ C++ programs

def _lib_sources(cm: CMakeInfo, target: str, seen: set) -> list[str]:
    if target in seen:
        return []
    seen.add(target)
    t = cm.targets.get(target)
    if t is None:
        return []
    out = list(t.sources)
    for ln in t.links:
        lt = cm.targets.get(ln)
        if lt is not None and lt.kind == "library":
            out += _lib_sources(cm, ln, seen)
    return out


def include_closure(files: list[str], includes_of: Callable[[str], list[str]], pkg_folder: str,
                    headers: dict[str, list[str]], memo: Optional[dict] = None) -> list[str]:
    """``files`` and the package headers they include (transitively, bounded); ``memo`` keeps
    what each file's includes resolve to."""
    out = list(dict.fromkeys(files))
    seen = set(out)
    memo = {} if memo is None else memo
    i = 0
    while i < len(out) and len(out) < MAX_CLOSURE:
        f = out[i]
        i += 1
        found = memo.get(f)
        if found is None:
            found = memo[f] = [h for h in (resolve_include(inc, f, pkg_folder, headers) for inc in includes_of(f))
                               if h is not None]
        for h in found:
            if h not in seen:
                seen.add(h)
                out.append(h)
    return out


def resolve_include(inc: str, from_file: str, pkg_folder: str, headers: dict[str, list[str]]) -> Optional[str]:
    """The package header an ``#include`` names (by its path's tail), or None."""
    inc = inc.strip().replace("\\", "/")
    base = os.path.basename(inc)
    cands = headers.get(base)
    if not cands:
        return None
    local = os.path.normpath(os.path.join(os.path.dirname(from_file), inc))
    if local in cands:
        return local
    tail = "/" + inc.lstrip("./")
    best = [c for c in cands if c.replace(os.sep, "/").endswith(tail)]
    if best:
        return sorted(best, key=len)[0]
    return None


def cpp_programs(pf: PackageFiles, includes_of: Callable[[str], list[str]], has_calls: Callable[[str], bool]
                 ) -> list[Program]:
    pkg = pf.package
    headers: dict[str, list[str]] = {}
    for f in pf.cpp:
        if f.lower().endswith(HDR_EXT):
            headers.setdefault(os.path.basename(f), []).append(f)
    existing = set(pf.cpp)
    out: list[Program] = []
    covered: set[str] = set()
    cm = pf.cmake

    memo: dict = {}

    def closure(srcs: list[str]) -> list[str]:
        srcs = [s for s in srcs if s in existing]
        return include_closure(srcs, includes_of, pkg.folder, headers, memo)

    if cm is not None:
        linked: set[str] = set()
        for t in cm.targets.values():
            if t.kind in ("executable", "test"):
                seen: set = set()
                srcs = _lib_sources(cm, t.name, seen)
                linked |= seen - {t.name}
                files = closure(srcs)
                covered.update(files)
                out.append(Program(t.name, t.kind, "cpp", files))
        comp_libs: dict[str, list[str]] = {}
        for cls, lib in cm.components.items():
            comp_libs.setdefault(lib, []).append(cls)
        execs_of: dict[str, list[str]] = {}
        for exe, (lib, cls) in cm.component_execs.items():
            execs_of.setdefault(cls, []).append(exe)
        for cls, lib in sorted(cm.components.items()):
            files = closure(_lib_sources(cm, lib, set()))
            covered.update(files)
            linked.add(lib)
            only = cls.split("::")[-1] if len(comp_libs.get(lib, [])) > 1 else None
            exes = sorted(execs_of.get(cls, []))
            if exes:
                out.append(Program(exes[0], "executable", "cpp", files, only, [cls] + exes[1:]))
            else:
                out.append(Program(cls, "component", "cpp", files, only))
        for lib, classes in sorted(comp_libs.items()):
            if len(classes) > 1 and lib in cm.targets:
                # the calls of the library's other classes (a component CMake does not register,
                # a helper class): listed under the library
                files = closure(_lib_sources(cm, lib, set()))
                out.append(Program(lib, "library", "cpp", files, None, [],
                                   frozenset(c.split("::")[-1] for c in classes)))
        for t in cm.targets.values():
            if t.kind == "library":
                # a library another library links (a nodelet's or plugin's helper library): its
                # calls are read with the linking library's, where its functions are called
                seen = set()
                _lib_sources(cm, t.name, seen)
                linked |= seen - {t.name}
        for t in cm.targets.values():
            if t.kind == "library" and t.name not in linked:
                files = closure(_lib_sources(cm, t.name, set()))
                covered.update(files)
                out.append(Program(t.name, "library", "cpp", files))
    # sources no target names (a CMakeLists.txt we could not read in full, a plain Makefile...)
    rest = [f for f in pf.cpp if f not in covered and f.lower().endswith(CPP_EXT)]
    for f in rest:
        if not has_calls(f):
            continue
        files = closure([f])
        covered.update(files)
        out.append(Program(_stem(f), "source", "cpp", files))
    for f in pf.cpp:
        if f not in covered and f.lower().endswith(HDR_EXT) and has_calls(f):
            out.append(Program(_stem(f), "source", "cpp", [f]))
    return out


def _stem(path: str) -> str:
    b = os.path.basename(path)
    return b.rsplit(".", 1)[0] if "." in b else b


# ------------------------------------------------------------------ Python programs

def _setup_entries(folder: str, read: Read) -> tuple[list[tuple[str, str]], list[str], list[str]]:
    """(console_scripts (name, "module:function"), scripts, package source roots) of a setup.py /
    setup.cfg, read without running them."""
    scripts: list[str] = []
    entries: list[tuple[str, str]] = []
    roots: list[str] = []
    text = read(os.path.join(folder, "setup.py"))
    if text:
        try:
            tree = ast.parse(text)
        except (SyntaxError, ValueError, RecursionError, MemoryError):
            tree = None
        if tree is not None:
            env: dict = {}
            for node in tree.body:
                if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
                    v = _lit(node.value, env)
                    if v is not None:
                        env[node.targets[0].id] = v
            for node in ast.walk(tree):
                if not isinstance(node, ast.Call):
                    continue
                fname = getattr(node.func, "id", None) or getattr(node.func, "attr", None)
                if fname not in ("setup", "generate_distutils_setup"):
                    continue
                for kw in node.keywords:
                    v = _lit(kw.value, env)
                    if kw.arg == "entry_points" and isinstance(v, dict):
                        for s in v.get("console_scripts", []) or []:
                            if isinstance(s, str) and "=" in s:
                                a, b = s.split("=", 1)
                                entries.append((a.strip(), b.strip()))
                    elif kw.arg == "scripts" and isinstance(v, list):
                        scripts += [os.path.normpath(os.path.join(folder, s)) for s in v if isinstance(s, str)]
                    elif kw.arg == "package_dir" and isinstance(v, dict):
                        for s in v.values():
                            if isinstance(s, str):
                                roots.append(os.path.normpath(os.path.join(folder, s)))
    cfg = read(os.path.join(folder, "setup.cfg"))
    if cfg:
        sec = None
        key = None
        for line in cfg.splitlines():
            m = re.match(r"^\s*\[([^\]]+)\]\s*$", line)
            if m:
                sec = m.group(1).strip()
                key = None
                continue
            if sec != "options.entry_points":
                continue
            m = re.match(r"^(\S[^=]*)=\s*(.*)$", line)
            if m and not line[:1].isspace():
                key = m.group(1).strip()
                rest = m.group(2).strip()
                if key == "console_scripts" and rest and "=" in rest:
                    a, b = rest.split("=", 1)
                    entries.append((a.strip(), b.strip()))
                continue
            if key == "console_scripts" and "=" in line:
                a, b = line.strip().split("=", 1)
                entries.append((a.strip(), b.strip()))
    return entries, scripts, roots


def _lit(node, env: dict, depth: int = 0):
    """A literal Python value (str, list, dict, with names of earlier module assignments,
    ``+`` and f-strings), or None."""
    if depth > 20:
        return None
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.Name):
        return env.get(node.id)
    if isinstance(node, (ast.List, ast.Tuple)):
        vals = [_lit(x, env, depth + 1) for x in node.elts]
        return [v for v in vals if v is not None]
    if isinstance(node, ast.Dict):
        out = {}
        for k, v in zip(node.keys, node.values):
            kk = _lit(k, env, depth + 1) if k is not None else None
            if isinstance(kk, str):
                out[kk] = _lit(v, env, depth + 1)
        return out
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        a, b = _lit(node.left, env, depth + 1), _lit(node.right, env, depth + 1)
        if isinstance(a, str) and isinstance(b, str) or isinstance(a, list) and isinstance(b, list):
            return a + b
        return None
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod):
        a, b = _lit(node.left, env, depth + 1), _lit(node.right, env, depth + 1)
        try:
            return a % (tuple(b) if isinstance(b, list) else b) if isinstance(a, str) and b is not None else None
        except (TypeError, ValueError):
            return None
    if isinstance(node, ast.JoinedStr):
        parts = []
        for v in node.values:
            if isinstance(v, ast.Constant):
                parts.append(str(v.value))
            elif isinstance(v, ast.FormattedValue):
                x = _lit(v.value, env, depth + 1)
                if not isinstance(x, str):
                    return None
                parts.append(x)
        return "".join(parts)
    if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "format" and \
            isinstance(node.func, ast.Attribute):
        base = _lit(node.func.value, env, depth + 1)
        args = [_lit(a, env, depth + 1) for a in node.args]
        if isinstance(base, str) and all(isinstance(a, str) for a in args):
            try:
                return base.format(*args)
            except (IndexError, KeyError, ValueError):
                return None
    return None


def module_file(module: str, roots: list[str], files: Optional[set] = None) -> Optional[str]:
    """The file of a module under one of ``roots`` (looked up in ``files`` when given, else on
    the disk)."""
    rel = module.replace(".", os.sep)
    for r in roots:
        for cand in (os.path.join(r, rel + ".py"), os.path.join(r, rel, "__init__.py")):
            cand = os.path.normpath(cand)
            if (cand in files) if files is not None else os.path.isfile(cand):
                return cand
    return None


def python_roots(pf: PackageFiles, extra: list[str]) -> list[str]:
    folder = pf.package.folder
    roots = list(extra) + [folder, os.path.join(folder, "src"), os.path.join(folder, "scripts"),
                           os.path.join(folder, "nodes"), os.path.join(folder, "lib")]
    return [r for r in dict.fromkeys(roots) if os.path.isdir(r)]


def import_closure(start: list[str], imports_of: Callable[[str], list], roots: list[str],
                   allowed: set[str]) -> list[str]:
    """``start`` and the modules of the package they import (transitively, bounded)."""
    out = list(dict.fromkeys(start))
    seen = set(out)
    i = 0
    while i < len(out) and len(out) < MAX_CLOSURE:
        f = out[i]
        i += 1
        here = os.path.dirname(f)
        for mod, level, names in imports_of(f):
            cands = []
            if level:
                base = here
                for _ in range(level - 1):
                    base = os.path.dirname(base)
                rroots = [base]
                cands.append(mod)
                cands += [(mod + "." if mod else "") + nm for nm in names if nm != "*"]
            else:
                rroots = [here] + roots
                cands.append(mod)
                cands += [mod + "." + nm for nm in names if nm != "*"]
            for c in cands:
                if not c:
                    continue
                p = module_file(c, rroots, allowed)
                if p is not None and p not in seen:
                    seen.add(p)
                    out.append(p)
    return out


def python_programs(pf: PackageFiles, read: Read, imports_of: Callable[[str], list],
                    has_calls: Callable[[str], bool]) -> list[Program]:
    pkg = pf.package
    entries, scripts, roots_extra = _setup_entries(pkg.folder, read)
    roots = python_roots(pf, roots_extra)
    allowed = set(pf.python)
    progs: list[Program] = []
    covered: set[str] = set()
    named: dict[str, str] = {}   # program name -> file
    for p in (pf.cmake.programs if pf.cmake else []) + scripts:
        if p in allowed:
            named.setdefault(os.path.basename(p), p)
    for p in pf.python:
        b = os.path.basename(p)
        try:
            st = os.stat(p)
        except OSError:
            continue
        if st.st_mode & stat.S_IXUSR and b not in named:
            head = read_head_text(p, 256) or ""
            if head.startswith("#!") and "python" in head.split("\n", 1)[0]:
                named[b] = p
    for name, f in sorted(named.items()):
        files = import_closure([f], imports_of, roots, allowed)
        covered.update(files)
        progs.append(Program(name, "script", "python", files))
    for name, target in entries:
        mod = target.split(":", 1)[0].strip()
        f = module_file(mod, roots)
        if f is None or f not in allowed:
            continue
        files = import_closure([f], imports_of, roots, allowed)
        covered.update(files)
        progs.append(Program(name, "console_script", "python", files))
    for f in pf.python:
        if f in covered or not has_calls(f):
            continue
        files = import_closure([f], imports_of, roots, allowed)
        progs.append(Program(_stem(f), "source", "python", files))
    return progs
