"""What extraction finds: plain data, no tree-sitter objects (so that it can be cached on disk
and sent between processes).

An :class:`Endpoint` is one call site that makes a node use a graph resource: a publisher, a
subscription, a service server or client, an action server or client, or a parameter declared,
read, written, deleted or searched.  ``name`` is the name as the node asks for it, before the
launch file's namespace and remaps: the argument as the code writes it, composed with the
namespace of the ROS 1 ``NodeHandle`` it is called on (``ros::NodeHandle pn("~")`` makes
``pn.advertise("x")`` the private ``~x``).  A name the code computes from something not known
before run time (a parameter, a function argument, user input) is *dynamic*: its known parts are
kept and each unknown part is written ``{expression}`` (``{real_name}/cmd_vel``), and
``expression`` holds the argument's source text.  Nothing is guessed.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Optional

# extraction kinds, and the graph link kind each one makes (None: not a graph link)
KINDS = ("publish", "subscribe", "service", "client", "action_server", "action_client",
         "param_declare", "param_read", "param_write", "param_delete", "param_search")
LINK_OF_KIND = {
    "publish": "publish", "subscribe": "subscribe", "service": "service", "client": "client",
    "action_server": "action_server", "action_client": "action_client",
    "param_declare": "read", "param_read": "read", "param_write": "write", "param_delete": "write",
    "param_search": None,
}
RESOURCE_OF = {"publish": "topic", "subscribe": "topic", "service": "service", "client": "service",
               "action_server": "action", "action_client": "action"}


@dataclass
class Endpoint:
    """One call site (see the module doc).  ``line`` is 1-based, ``col`` / ``end_col`` 0-based
    code points; ``name_line`` / ``name_col`` / ``name_end`` locate the name argument (the
    string literal a hover points at) when there is one."""
    package: str
    executable: str
    kind: str
    name: str
    type: Optional[str]
    file: str
    line: int
    col: int = 0
    end_line: int = 0
    end_col: int = 0
    dynamic: bool = False
    expression: Optional[str] = None
    api: str = ""
    ros: int = 0                      # 1 or 2 (0: not known)
    default: Optional[str] = None     # a parameter's default value, as written
    type_expression: Optional[str] = None  # the type as written, when it could not be normalised
    name_line: Optional[int] = None
    name_col: Optional[int] = None
    name_end: Optional[int] = None

    def key(self) -> tuple:
        return (self.package, self.executable, self.file, self.line, self.col, self.kind, self.name)

    def row(self) -> dict:
        d = asdict(self)
        return {k: v for k, v in d.items() if v is not None}


@dataclass
class Executable:
    """A program a launch file can start (``pkg`` / ``type`` in ROS 1, ``pkg`` / ``exec`` in ROS 2),
    or a component (``kind == "component"``: a plugin class a container loads; ``name`` is the
    class, ``pkg::Class``) or a library no executable of its package links (``kind ==
    "library"``: its endpoints are still listed, under the library's target name)."""
    package: str
    name: str
    kind: str                  # executable | component | script | console_script | library | test
    language: str              # cpp | python
    sources: list[str] = field(default_factory=list)
    endpoints: list[Endpoint] = field(default_factory=list)
    # the launch names this program is started by, besides ``name`` (a component's executable)
    aliases: list[str] = field(default_factory=list)

    @property
    def id(self) -> str:
        return f"{self.package}/{self.name}"


@dataclass
class Package:
    name: str
    folder: str
    build_type: Optional[str]
    ros: int                   # 1 or 2 (0: not known)


@dataclass
class Extraction:
    """Everything read from some packages."""
    packages: list[Package] = field(default_factory=list)
    executables: list[Executable] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    files_read: int = 0        # source files looked at
    files_parsed: int = 0      # of which parsed now (the others came from the cache)

    def endpoints(self) -> list[Endpoint]:
        out = [e for x in self.executables for e in x.endpoints]
        out.sort(key=lambda e: (e.package, e.executable, e.file, e.line, e.col, e.kind, e.name))
        return out

    def by_node_type(self) -> dict[str, Executable]:
        """``pkg/executable`` (and ``pkg/alias``) -> the executable, for the graph."""
        out: dict[str, Executable] = {}
        for x in self.executables:
            if x.kind in ("library", "test"):
                continue
            out.setdefault(x.id, x)
            for a in x.aliases:
                out.setdefault(f"{x.package}/{a}", x)
        return out
