"""Message, service and action types written in C++ or Python, normalised to ``pkg/Name``.

``std_msgs::msg::String``, ``std_msgs::String``, ``::std_msgs::String_<Alloc>``,
``const std_msgs::msg::String::SharedPtr``, ``boost::shared_ptr<std_msgs::String const>``,
``std_msgs::StringConstPtr``, ``std_msgs.msg.String`` and ``String`` imported with ``from
std_msgs.msg import String`` are all ``std_msgs/String``.  A service's ``Request`` / ``Response``
(``pkg::srv::X::Request``, ROS 1's ``pkg::XRequest``) is the service ``pkg/X``; an action's
``pkg::action::X``, ROS 1's ``pkg::XAction`` (and its ``Goal`` / ``ActionGoal`` ... messages in an
action context) is ``pkg/X``, the name of its ``.action`` file.

Names the code does not qualify are looked up as C++ and Python look them up: aliases
(``using``, ``typedef``, ``namespace a = b``), using-declarations, the enclosing namespaces (when
they name a package that has such a message), using-directives.  A type that stays unknown is
``None`` (its text is reported as written, never guessed).
"""

from __future__ import annotations

import re
from typing import Iterable, Mapping, Optional

# wrappers whose (first) template argument is the message
_WRAPPERS = ("shared_ptr", "unique_ptr", "weak_ptr", "MessageEvent", "ConstPtr", "SharedPtr",
             "ServerGoalHandle", "ClientGoalHandle", "SimpleActionServer", "SimpleActionClient",
             "ActionServer", "ActionClient", "Subscriber", "Publisher", "Server", "Client",
             "SubscriberFilter", "TimeSynchronizer", "ServiceEvent", "reference_wrapper", "optional",
             "Event", "LoanedMessage", "MessageInfo", "GoalHandle")
_PTR_SUFFIXES = ("ConstSharedPtr", "SharedPtr", "ConstPtr", "UniquePtr", "WeakPtr", "Ptr")
_QUALIFIERS = re.compile(r"\b(const|volatile|typename|struct|class|mutable|constexpr)\b")
_INTERFACE_NS = ("msg", "srv", "action")
_PRIMITIVE = {"bool", "int", "double", "float", "char", "void", "auto", "long", "short", "unsigned",
              "signed", "size_t", "int8_t", "uint8_t", "int16_t", "uint16_t", "int32_t", "uint32_t",
              "int64_t", "uint64_t", "string", "std"}
# the ROS 1 generated suffixes of an action's messages
_ACTION_SUFFIXES = ("ActionGoal", "ActionResult", "ActionFeedback", "Action")
_SERVICE_SUFFIXES = ("Request", "Response")


def split_template(text: str) -> tuple[str, list[str]]:
    """``a::b<c, d<e>>::f`` -> (``a::b::f`` without the arguments, [``c``, ``d<e>``]) for the first
    template argument list only."""
    i = text.find("<")
    if i < 0:
        return text, []
    depth = 0
    args: list[str] = []
    start = i + 1
    for j in range(i, len(text)):
        ch = text[j]
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
            if depth == 0:
                args.append(text[start:j].strip())
                rest = text[j + 1:]
                return text[:i] + rest, [a for a in args if a]
        elif ch == "," and depth == 1:
            args.append(text[start:j].strip())
            start = j + 1
    return text[:i], [a.strip() for a in args if a.strip()]


def strip_cpp(text: str) -> str:
    """The message class a parameter or template type designates: wrappers, pointers,
    references, qualifiers and ``::ConstPtr`` / ``ConstPtr`` suffixes removed."""
    t = _QUALIFIERS.sub(" ", text or "")
    t = t.replace("&", " ").replace("*", " ").strip()
    for _ in range(6):
        base, args = split_template(t)
        last = base.rstrip(": ").split("::")[-1].strip()
        if args and last in ("TypeAdapter", "as") and len(args) >= 2:
            t = args[-1]  # rclcpp::TypeAdapter<Custom, ros_msgs::msg::X>: the ROS type
            continue
        if args and (last in _WRAPPERS or last.endswith(("_ptr", "Event", "Handle", "Ptr"))):
            t = _QUALIFIERS.sub(" ", args[0]).replace("&", " ").replace("*", " ").strip()
            continue
        if args and last.endswith("_") and base.count("::"):  # std_msgs::String_<std::allocator<void>>
            t = base.rstrip(": ").rstrip("_")
            continue
        if args:
            # X<...>::SharedPtr and friends: the wrapped X is the type itself
            t = base
        break
    t = " ".join(t.split()).replace(" ", "")
    t = t.lstrip(":")
    parts = t.split("::")
    while len(parts) > 1 and parts[-1] in _PTR_SUFFIXES + ("element_type",):
        parts.pop()
    if parts:
        last = parts[-1]
        for suf in _PTR_SUFFIXES:
            if last.endswith(suf) and len(last) > len(suf) and last[: -len(suf)][-1:].isalnum():
                parts[-1] = last[: -len(suf)]
                break
    return "::".join(p for p in parts if p)


def to_ros(qualified: str, context: str = "msg") -> Optional[str]:
    """``pkg::msg::X`` / ``pkg::X`` (or dotted) -> ``pkg/X``; None when it has no package part.
    ``context``: ``msg``, ``srv`` or ``action``: what suffixes (``Request``, ``Action``) mean."""
    q = qualified.replace(".", "::").strip(":")
    parts = [p for p in q.split("::") if p]
    if len(parts) < 2:
        return None
    if context == "srv" and parts[-1] in _SERVICE_SUFFIXES and len(parts) >= 3:
        parts.pop()  # pkg::srv::X::Request
    if context == "action" and parts[-1] in ("Goal", "Result", "Feedback", "Impl") and len(parts) >= 3 \
            and parts[-2][:1].isupper():
        parts.pop()
    name = parts[-1]
    pkg_parts = parts[:-1]
    while pkg_parts and pkg_parts[-1] in _INTERFACE_NS:
        pkg_parts.pop()
    if not pkg_parts:
        return None
    pkg = pkg_parts[-1]
    # a ROS package name is lower case (REP 144): ServiceT::Request is a template parameter's
    if not re.fullmatch(r"[a-z][a-z0-9_]*", pkg) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        return None
    if pkg in ("std", "boost", "ros", "rclcpp", "rclpy", "rospy", "actionlib", "rclcpp_action", "this"):
        return None
    for suf in ("_Request", "_Response", "_Goal", "_Result", "_Feedback", "_Event"):
        if name.endswith(suf) and len(name) > len(suf):
            name = name[: -len(suf)]
            break
    if context == "srv":
        for suf in _SERVICE_SUFFIXES:
            if name.endswith(suf) and len(name) > len(suf) and "srv" not in parts[:-1]:
                name = name[: -len(suf)]
                break
    elif context == "action":
        for suf in _ACTION_SUFFIXES + ("Goal", "Result", "Feedback"):
            if name.endswith(suf) and len(name) > len(suf) and "action" not in parts[:-1]:
                name = name[: -len(suf)]
                break
    if not name[:1].isalpha():
        return None
    return f"{pkg}/{name}"


class CppScope:
    """What an unqualified type name means at one place of a C++ file: ``alias(name)`` gives
    what an alias (``using X = ...``, ``typedef``, ``namespace a = b``) or using-declaration
    names there, or None."""

    def __init__(self, alias, using_ns: Iterable[str], namespaces: Iterable[str] = (),
                 known: Optional[Mapping[str, set]] = None):
        self.alias = alias
        self.using_ns = list(using_ns)    # using namespace a::b;
        self.namespaces = list(namespaces)  # enclosing namespaces, outermost first
        self.known = known or {}          # package -> interface names it defines (msg/srv/action)

    def expand(self, text: str) -> str:
        """``text`` with aliases and using-declarations applied to its first name component."""
        t = strip_cpp(text)
        seen = set()
        for _ in range(10):
            head, _, rest = t.partition("::")
            target = self.alias(head) if head not in seen else None
            if target is None:
                break
            seen.add(head)
            t2 = strip_cpp(target) + ("::" + rest if rest else "")
            if t2 == t:
                break
            t = strip_cpp(t2)
        return t

    def normalise(self, text: Optional[str], context: str = "msg") -> Optional[str]:
        if not text:
            return None
        t = self.expand(text)
        if not t or t.split("::")[-1] in _PRIMITIVE:
            return None
        r = to_ros(t, context)
        if r is not None:
            pkg = r.split("/", 1)[0]
            if pkg in self.namespaces and len(t.split("::")) == 2 and pkg not in self.known \
                    and not _looks_like_interface_pkg(pkg):
                return None  # ns::Class of the code's own namespace: not a message
            return r
        # an unqualified name: the enclosing namespaces, then using-directives, when they are
        # (or contain) a package that defines such an interface
        name = t
        inner = [ns for ns in reversed(self.namespaces)]
        for i, c in enumerate([n + "::" + name for n in inner] + [n + "::" + name for n in self.using_ns]):
            r = to_ros(c, context)
            if r is None:
                continue
            pkg, base = r.split("/", 1)
            defined = self.known.get(pkg)
            if defined is not None:
                if base in defined or name in defined:
                    return r
                continue
            if i >= len(inner) and _looks_like_interface_pkg(pkg):
                return r  # using namespace std_msgs::msg; ... String
        return None


def _looks_like_interface_pkg(pkg: str) -> bool:
    return pkg.endswith(("_msgs", "_srvs", "_interfaces", "_actions", "msgs", "_srv", "_msg"))


def python_type(expr: Optional[str], imports: Mapping[str, str], context: str = "msg") -> Optional[str]:
    """A Python type expression (``String``, ``std_msgs.msg.String``, ``msg.String``) -> ``pkg/X``
    with the module's imports (local name -> dotted path: ``String`` -> ``std_msgs.msg.String``,
    ``m`` -> ``std_msgs.msg``)."""
    if not expr:
        return None
    e = expr.strip()
    if not re.fullmatch(r"[A-Za-z_][\w.]*", e):
        return None
    head, _, rest = e.partition(".")
    if head in imports:
        e = imports[head] + ("." + rest if rest else "")
    parts = e.split(".")
    if len(parts) < 2:
        return None
    if parts[-2] not in _INTERFACE_NS and not _looks_like_interface_pkg(parts[-2]) and len(parts) == 2:
        # pkg.X without .msg: only for packages that look like interface packages
        return None
    return to_ros("::".join(parts), context)
