"""A small, bounded reader of a package's ``CMakeLists.txt``: which programs it builds from which
sources.  Nothing is executed; the commands are read in order with their arguments and
variables (``set``, ``list(APPEND)``, ``${PROJECT_NAME}``, ``foreach``, ``file(GLOB)``,
``add_subdirectory``, user ``function`` / ``macro`` calls).  Both branches of an ``if`` are read
(what some configuration builds is built).

What it records (:class:`CMakeInfo`):

- ``add_executable`` / ``ament_auto_add_executable`` / ``cuda_add_executable``: a program and its
  sources (``target_sources`` adds to them);
- ``add_library`` / ``ament_auto_add_library``: a library and its sources;
  ``target_link_libraries`` which libraries a target links (the package's own libraries' sources
  belong to the programs that link them);
- ``rclcpp_components_register_node(lib PLUGIN "pkg::Class" EXECUTABLE name)``: a program
  ``name`` running the component; ``rclcpp_components_register_nodes(lib "pkg::Class" ...)``:
  components a container loads;
- ``catkin_install_python(PROGRAMS ...)`` and ``install(PROGRAMS ...)``: Python (or other)
  scripts installed as programs;
- ``catkin_add_gtest`` / ``ament_add_gtest`` / ``add_rostest_gtest``: test programs.
"""

from __future__ import annotations

import fnmatch
import os
import re
from dataclasses import dataclass, field
from typing import Callable, Optional

MAX_COMMANDS = 20000       # commands executed (loops and calls included)
MAX_FILES = 64             # CMakeLists.txt files read (add_subdirectory)
MAX_DEPTH = 16             # nested calls / subdirectories
MAX_VALUE = 100_000        # characters in one variable
MAX_GLOB = 2000            # files one file(GLOB) may list

SOURCE_EXT = (".cpp", ".cc", ".cxx", ".c++", ".c", ".cu", ".h", ".hpp", ".hh", ".hxx", ".h++", ".ipp", ".tpp")


@dataclass
class Target:
    name: str
    kind: str                  # executable | library | test
    sources: list[str] = field(default_factory=list)   # absolute paths
    links: list[str] = field(default_factory=list)     # target names (and other libraries)
    line: int = 0


@dataclass
class CMakeInfo:
    targets: dict[str, Target] = field(default_factory=dict)
    # component executables: executable name -> (library target, "pkg::Class")
    component_execs: dict[str, tuple[str, str]] = field(default_factory=dict)
    # components: "pkg::Class" -> library target
    components: dict[str, str] = field(default_factory=dict)
    programs: list[str] = field(default_factory=list)   # installed scripts (absolute paths)
    project: Optional[str] = None
    files: list[str] = field(default_factory=list)      # the CMakeLists.txt read
    notes: list[str] = field(default_factory=list)


# ------------------------------------------------------------------ lexing

_TOKEN = re.compile(r'''
    (?P<ws>[ \t\r\n]+)
  | (?P<bcomment>\#\[(?P<beq>=*)\[.*?\](?P=beq)\])
  | (?P<comment>\#[^\n]*)
  | (?P<bracket>\[(?P<eq>=*)\[.*?\](?P=eq)\])
  | (?P<quoted>"(?:\\.|[^"\\])*")
  | (?P<lp>\()
  | (?P<rp>\))
  | (?P<unquoted>(?:\\.|\$\{[^}\n]*\}|[^\s()#"\\])+(?:"(?:\\.|[^"\\])*")?)
''', re.S | re.X)

_CMD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass
class Command:
    name: str
    args: list[tuple[str, bool]]   # (text, quoted)
    line: int


def parse(text: str) -> list[Command]:
    """The commands of a CMake file (bad syntax ends the file where it is)."""
    out: list[Command] = []
    i = 0
    n = len(text)
    line = 1
    while i < n:
        m = _TOKEN.match(text, i)
        if m is None:
            # something odd: skip to the next line
            j = text.find("\n", i)
            if j < 0:
                break
            line += 1
            i = j + 1
            continue
        kind = m.lastgroup
        if kind in ("ws", "comment", "bcomment", "beq"):
            line += m.group(0).count("\n")
            i = m.end()
            continue
        word = m.group(0)
        if kind == "unquoted" and _CMD.fullmatch(word):
            # a command: name, then ( args )
            j = m.end()
            while j < n and text[j] in " \t":
                j += 1
            if j >= n or text[j] != "(":
                i = m.end()
                continue
            cmd_line = line
            depth = 1
            k = j + 1
            args: list[tuple[str, bool]] = []
            while k < n and depth > 0:
                t = _TOKEN.match(text, k)
                if t is None:
                    k += 1
                    continue
                tk = t.lastgroup
                s = t.group(0)
                line += s.count("\n")
                if tk == "lp":
                    depth += 1
                    args.append(("(", False))
                elif tk == "rp":
                    depth -= 1
                    if depth > 0:
                        args.append((")", False))
                elif tk == "quoted":
                    args.append((s[1:-1], True))
                elif tk == "bracket":
                    eq = t.group("eq") or ""
                    args.append((s[2 + len(eq):-(2 + len(eq))].lstrip("\n"), True))
                elif tk == "unquoted":
                    args.append((s, False))
                k = t.end()
            out.append(Command(word.lower(), args, cmd_line))
            i = k
            continue
        line += word.count("\n")
        i = m.end()
    return out


# ------------------------------------------------------------------ evaluation

_VAR = re.compile(r"\$\{([^${}]*)\}")
_ESC = re.compile(r"\\(.)")


class _Limit(Exception):
    pass


class _Interp:
    def __init__(self, package_folder: str, read: Callable[[str], Optional[str]],
                 listdir: Callable[[str], list[str]]):
        self.root = package_folder
        self.read = read
        self.listdir = listdir
        self.info = CMakeInfo()
        self.steps = 0
        self.functions: dict[str, tuple[list[str], list[Command], bool, str]] = {}

    # values
    def expand(self, s: str, scope: dict[str, str]) -> str:
        for _ in range(20):
            m = _VAR.search(s)
            if m is None:
                break
            s = s[:m.start()] + scope.get(m.group(1), "") + s[m.end():]
            if len(s) > MAX_VALUE:
                raise _Limit()
        s = re.sub(r"\$ENV\{[^}]*\}", "", s)
        s = re.sub(r"\$<[^>]*>", "", s)  # generator expressions
        return s

    def values(self, args: list[tuple[str, bool]], scope: dict[str, str]) -> list[str]:
        out: list[str] = []
        for a, quoted in args:
            v = self.expand(a, scope)
            if quoted:
                out.append(_ESC.sub(r"\1", v))
            else:
                out.extend(x for x in v.split(";") if x != "")
        return out

    def run_file(self, path: str, scope: dict[str, str], depth: int) -> None:
        if len(self.info.files) >= MAX_FILES or depth > MAX_DEPTH:
            return
        text = self.read(path)
        if text is None:
            return
        self.info.files.append(path)
        folder = os.path.dirname(path)
        scope["CMAKE_CURRENT_SOURCE_DIR"] = folder
        scope["CMAKE_CURRENT_LIST_DIR"] = folder
        self.run(parse(text), scope, folder, depth)

    def run(self, cmds: list[Command], scope: dict[str, str], folder: str, depth: int) -> None:
        i = 0
        while i < len(cmds):
            c = cmds[i]
            self.steps += 1
            if self.steps > MAX_COMMANDS:
                raise _Limit()
            if c.name in ("foreach", "function", "macro", "while"):
                end = {"foreach": "endforeach", "function": "endfunction", "macro": "endmacro",
                       "while": "endwhile"}[c.name]
                j = _block_end(cmds, i, c.name, end)
                body = cmds[i + 1:j]
                if c.name == "foreach":
                    self.foreach(c, body, scope, folder, depth)
                elif c.name in ("function", "macro"):
                    vals = self.values(c.args, scope)
                    if vals:
                        self.functions[vals[0].lower()] = (vals[1:], body, c.name == "macro", folder)
                else:
                    self.run(body, scope, folder, depth)  # a while loop: its body once
                i = j + 1
                continue
            try:
                self.command(c, scope, folder, depth)
            except _Limit:
                raise
            except Exception:  # a command we misread never stops the rest
                pass
            i += 1

    def foreach(self, c: Command, body: list[Command], scope: dict[str, str], folder: str, depth: int) -> None:
        vals = self.values(c.args, scope)
        if not vals:
            return
        var, items = vals[0], vals[1:]
        if items and items[0] == "RANGE":
            nums = [int(x) for x in items[1:] if re.fullmatch(r"-?\d+", x)]
            if len(nums) == 1:
                items = [str(k) for k in range(0, min(nums[0], 100) + 1)]
            elif len(nums) >= 2:
                items = [str(k) for k in range(nums[0], min(nums[1], nums[0] + 100) + 1)]
            else:
                items = []
        elif items and items[0] == "IN":
            rest: list[str] = []
            mode = None
            for x in items[1:]:
                if x in ("LISTS", "ITEMS", "ZIP_LISTS"):
                    mode = x
                elif mode == "LISTS" or mode == "ZIP_LISTS":
                    rest.extend(v for v in scope.get(x, "").split(";") if v)
                else:
                    rest.append(x)
            items = rest
        for it in items[:500]:
            scope[var] = it
            self.run(body, scope, folder, depth)

    def command(self, c: Command, scope: dict[str, str], folder: str, depth: int) -> None:
        name = c.name
        if name in self.functions:
            params, body, is_macro, def_folder = self.functions[name]
            if depth >= MAX_DEPTH:
                return
            vals = self.values(c.args, scope)
            inner = scope if is_macro else dict(scope)
            saved = {k: scope.get(k) for k in params + ["ARGN", "ARGV", "ARGC"]} if is_macro else {}
            for k, p in enumerate(params):
                inner[p] = vals[k] if k < len(vals) else ""
            inner["ARGN"] = ";".join(vals[len(params):])
            inner["ARGV"] = ";".join(vals)
            inner["ARGC"] = str(len(vals))
            for k, v in enumerate(vals[:20]):
                inner[f"ARGV{k}"] = v
            self.run(body, inner, folder, depth + 1)
            if is_macro:
                for k, v in saved.items():
                    if v is None:
                        scope.pop(k, None)
                    else:
                        scope[k] = v
            return
        vals = self.values(c.args, scope)
        if name == "project" and vals:
            scope["PROJECT_NAME"] = vals[0]
            scope.setdefault("CMAKE_PROJECT_NAME", vals[0])
            if self.info.project is None:
                self.info.project = vals[0]
            scope["PROJECT_SOURCE_DIR"] = folder
            scope["CMAKE_SOURCE_DIR"] = scope.get("CMAKE_SOURCE_DIR", folder)
        elif name == "set" and vals:
            items = vals[1:]
            for stop in ("CACHE", "PARENT_SCOPE"):
                if stop in items:
                    items = items[: items.index(stop)]
            scope[vals[0]] = ";".join(items)
        elif name == "unset" and vals:
            scope.pop(vals[0], None)
        elif name == "list" and len(vals) >= 2:
            op, var = vals[0].upper(), vals[1]
            cur = [x for x in scope.get(var, "").split(";") if x]
            if op in ("APPEND", "PREPEND"):
                cur = cur + vals[2:] if op == "APPEND" else vals[2:] + cur
            elif op == "REMOVE_ITEM":
                cur = [x for x in cur if x not in vals[2:]]
            elif op == "REMOVE_DUPLICATES":
                cur = list(dict.fromkeys(cur))
            elif op == "FILTER" and len(vals) >= 5:
                rx = vals[4]
                try:
                    r = re.compile(rx)
                    keep = vals[2] == "INCLUDE"
                    cur = [x for x in cur if bool(r.search(x)) == keep]
                except re.error:
                    pass
            else:
                return
            scope[var] = ";".join(cur)
        elif name == "file" and len(vals) >= 3 and vals[0] in ("GLOB", "GLOB_RECURSE"):
            self.glob(vals, scope, folder)
        elif name == "add_subdirectory" and vals:
            sub = os.path.normpath(os.path.join(folder, vals[0]))
            if sub.startswith(self.root):
                child = dict(scope)
                self.run_file(os.path.join(sub, "CMakeLists.txt"), child, depth + 1)
        elif name in ("add_executable", "cuda_add_executable", "ament_auto_add_executable",
                      "catkin_add_gtest", "ament_add_gtest", "catkin_add_gmock", "ament_add_gmock",
                      "add_rostest_gtest", "ament_add_gtest_executable", "catkin_add_executable_with_gtest",
                      "catkin_add_nosetests", "qt5_add_executable"):
            if not vals or "IMPORTED" in vals or "ALIAS" in vals:
                return
            kind = "test" if ("test" in name or "gmock" in name) else "executable"
            srcs = vals[1:]
            if name == "add_rostest_gtest":
                srcs = srcs[1:]  # the .test file
            self.target(vals[0], kind, srcs, folder, c.line)
        elif name in ("add_library", "cuda_add_library", "ament_auto_add_library"):
            if not vals or "IMPORTED" in vals or "ALIAS" in vals or "INTERFACE" in vals[1:2]:
                return
            self.target(vals[0], "library", vals[1:], folder, c.line)
        elif name == "target_sources" and vals:
            t = self.info.targets.get(vals[0])
            if t is not None:
                t.sources += self.sources(vals[1:], folder)
        elif name in ("target_link_libraries", "ament_target_dependencies", "add_dependencies") and vals:
            t = self.info.targets.get(vals[0])
            if t is not None and name == "target_link_libraries":
                t.links += [v for v in vals[1:] if v not in ("PUBLIC", "PRIVATE", "INTERFACE", "debug",
                                                            "optimized", "general")]
        elif name == "rclcpp_components_register_nodes" and len(vals) >= 2:
            for cls in vals[1:]:
                if cls not in ("RESOURCE_INDEX",):
                    self.info.components.setdefault(cls, vals[0])
        elif name == "rclcpp_components_register_node" and len(vals) >= 2:
            plugin = _after(vals, "PLUGIN")
            exe = _after(vals, "EXECUTABLE")
            if plugin:
                self.info.components.setdefault(plugin, vals[0])
                if exe:
                    self.info.component_execs[exe] = (vals[0], plugin)
        elif name == "catkin_install_python" or (name == "install" and vals and vals[0] == "PROGRAMS"):
            for v in vals[1:]:
                if v == "DESTINATION":
                    break
                if v in ("PROGRAMS", "USE_SOURCE_PERMISSIONS", "OPTIONAL"):
                    continue
                p = os.path.normpath(os.path.join(folder, v))
                if p.startswith(self.root) and p not in self.info.programs:
                    self.info.programs.append(p)

    def target(self, name: str, kind: str, args: list[str], folder: str, line: int) -> None:
        srcs = [a for a in args if a not in ("WIN32", "MACOSX_BUNDLE", "EXCLUDE_FROM_ALL", "STATIC", "SHARED",
                                             "MODULE", "OBJECT", "DIRECTORY", "NO_TARGET_LINK_LIBRARIES")]
        t = self.info.targets.get(name)
        if t is None:
            t = self.info.targets[name] = Target(name, kind, [], [], line)
        t.sources += self.sources(srcs, folder)

    def sources(self, args: list[str], folder: str) -> list[str]:
        out = []
        for a in args:
            if a in ("PUBLIC", "PRIVATE", "INTERFACE"):
                continue
            if not a.lower().endswith(SOURCE_EXT):
                continue
            p = os.path.normpath(a if os.path.isabs(a) else os.path.join(folder, a))
            out.append(p)
        return out

    def glob(self, vals: list[str], scope: dict[str, str], folder: str) -> None:
        recurse = vals[0] == "GLOB_RECURSE"
        var = vals[1]
        rel = None
        pats: list[str] = []
        k = 2
        while k < len(vals):
            v = vals[k]
            if v == "RELATIVE" and k + 1 < len(vals):
                rel = vals[k + 1]
                k += 2
                continue
            if v in ("CONFIGURE_DEPENDS", "LIST_DIRECTORIES", "FOLLOW_SYMLINKS", "true", "false"):
                k += 1
                continue
            pats.append(v if os.path.isabs(v) else os.path.join(folder, v))
            k += 1
        found: list[str] = []
        for pat in pats:
            pat = os.path.normpath(pat)
            base = pat
            while any(ch in os.path.basename(base) for ch in "*?[") and base != os.path.dirname(base):
                base = os.path.dirname(base)
            if not base.startswith(self.root):
                continue
            for p in self.walk(base, recurse or "**" in pat):
                if fnmatch.fnmatch(p, pat) or (recurse and fnmatch.fnmatch(os.path.basename(p), os.path.basename(pat))
                                               and p.startswith(os.path.dirname(pat))):
                    found.append(os.path.relpath(p, rel) if rel else p)
                if len(found) > MAX_GLOB:
                    break
        scope[var] = ";".join(sorted(set(found)))

    def walk(self, base: str, recurse: bool) -> list[str]:
        out = []
        stack = [base]
        seen = 0
        while stack:
            d = stack.pop()
            seen += 1
            if seen > 500:
                break
            for name in self.listdir(d):
                p = os.path.join(d, name)
                if os.path.isdir(p):
                    if recurse and not name.startswith(".") and name not in ("build", "install", "devel", "log"):
                        stack.append(p)
                else:
                    out.append(p)
        return out


def _after(vals: list[str], key: str) -> Optional[str]:
    if key in vals:
        k = vals.index(key)
        if k + 1 < len(vals):
            return vals[k + 1]
    return None


def _block_end(cmds: list[Command], i: int, start: str, end: str) -> int:
    depth = 0
    for j in range(i, len(cmds)):
        if cmds[j].name == start:
            depth += 1
        elif cmds[j].name == end:
            depth -= 1
            if depth == 0:
                return j
    return len(cmds) - 1


def _listdir(d: str) -> list[str]:
    try:
        return sorted(os.listdir(d))
    except OSError:
        return []


def read_cmake(package_folder: str, read: Callable[[str], Optional[str]],
               listdir: Callable[[str], list[str]] = _listdir) -> Optional[CMakeInfo]:
    """What the package's ``CMakeLists.txt`` builds (None when it has none)."""
    path = os.path.join(package_folder, "CMakeLists.txt")
    interp = _Interp(os.path.normpath(package_folder), read, listdir)
    scope = {"CMAKE_SOURCE_DIR": package_folder, "PROJECT_SOURCE_DIR": package_folder,
             "CMAKE_CURRENT_BINARY_DIR": os.path.join(package_folder, "build"),
             "CATKIN_PACKAGE_BIN_DESTINATION": "lib", "CATKIN_PACKAGE_LIB_DESTINATION": "lib",
             "CATKIN_PACKAGE_SHARE_DESTINATION": "share", "CATKIN_PACKAGE_PYTHON_DESTINATION": "lib"}
    try:
        interp.run_file(path, scope, 0)
    except _Limit:
        interp.info.notes.append(f"{path}: read only in part (it runs past the reader's bounds)")
    except RecursionError:
        interp.info.notes.append(f"{path}: read only in part (nesting too deep)")
    if not interp.info.files:
        return None
    return interp.info
