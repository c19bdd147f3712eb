"""roslaunch 1's rules as data: the diagnostic codes of the launch front end, the analysis
limits, the tags and attributes roslaunch knows, and the name and value helpers every tag
rule shares (``ns_join``, ``canonicalize``, ``merge`` of guarded cases, ...)."""

from __future__ import annotations

import itertools
import re
from typing import Callable, Iterable, Optional

import yaml

from ...base.formula import FALSE, Formula, disj, evaluate, variables
from ...base.diagnostics import Severity, register


Cases = list  # list[tuple[Formula, str]]

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION


def _reg(code: str, sev: Severity, summary: str) -> str:
    return register(code, sev, summary, "launch")


UNDEFINED_ARG = _reg("undefined-arg", E, "A $(arg X) where X is not declared in scope.")
UNSET_ARG = _reg("unset-arg", W, "A $(arg X) where X is declared without a value and nothing sets it.")
DUPLICATE_ARG = _reg("duplicate-arg", E, "An <arg> is declared twice in the same scope.")
ARG_ALREADY_SET = _reg("arg-already-set", E, "An <arg value=...> for an arg that already has a value.")
ARG_VALUE_AND_DEFAULT = _reg("arg-value-and-default", E, "An <arg> with both value and default.")
INVALID_CONDITION = _reg("invalid-condition", E, "An if/unless condition does not evaluate to true/false/1/0.")
IF_AND_UNLESS = _reg("if-and-unless", E, "Both 'if' and 'unless' on the same tag.")
DUPLICATE_NODE = _reg("duplicate-node", E, "Two nodes with the same resolved name are loaded.")
MISSING_ATTRIBUTE = _reg("missing-attribute", E, "A required attribute is missing.")
UNKNOWN_ATTRIBUTE = _reg("unknown-attribute", W, "An attribute roslaunch does not know (it warns).")
UNKNOWN_TAG = _reg("unknown-tag", W, "A tag roslaunch does not know (it warns and ignores it).")
INVALID_VALUE = _reg("invalid-attribute-value", E, "An attribute value roslaunch rejects.")
NODE_NAME_NS = _reg("node-name-namespace", E, "A node name contains a namespace.")
ILLEGAL_NAME = _reg("illegal-node-name", W, "A node name that is not a legal ROS name.")
EMPTY_NS = _reg("empty-ns", E, "An empty 'ns' attribute.")
RESPAWN_REQUIRED = _reg("respawn-and-required", E, "Both respawn and required are true.")
PARAM_VALUE_COUNT = _reg("param-value-count", E, "A <param> without exactly one of value/textfile/binfile/command.")
PARAM_INVALID = _reg("invalid-param", E, "A <param> or <rosparam> roslaunch cannot load.")
COMMAND_NOT_FOUND = _reg("command-not-found", E, "A <param command=...> names a program that does not exist.")
FILE_NOT_FOUND = _reg("file-not-found", E, "A file a tag loads does not exist.")
SUBST_SYNTAX = _reg("substitution-syntax", E, "A malformed $(...) substitution.")
SUBST_UNKNOWN = _reg("unknown-substitution", E, "An unknown $(...) substitution command.")
SUBST_ARITY = _reg("substitution-arity", E, "Wrong number of arguments to a $(...) substitution.")
EVAL_ERROR = _reg("eval-error", E, "A $(eval ...) expression fails.")
ENV_NOT_SET = _reg("env-not-set", E, "A $(env X) where X is not set in tvl-lsp's environment.")
PACKAGE_NOT_FOUND = _reg("package-not-found", E, "A $(find pkg) of a package roslaunch cannot find.")
PACKAGE_AMBIGUOUS = _reg("package-ambiguous", I, "A $(find pkg) of a package name that several folders hold.")
CONDITION_NOT_ANALYSABLE = _reg("condition-not-analysable", I, "A condition tvl-lsp cannot translate to a formula.")
INCLUDE_NOT_FOUND = _reg("include-not-found", E, "An included file does not exist.")
INCLUDE_OUTSIDE = _reg("include-outside-workspace", W, "An included file outside the workspace: it is not read.")
INCLUDE_INVALID = _reg("include-invalid", E, "An included file is not a valid launch file.")
INCLUDE_CYCLE = _reg("include-cycle", E, "Files include each other in a cycle.")
INCLUDE_TOO_DEEP = _reg("include-too-deep", W, "Includes nested too deeply to follow.")
INCLUDE_ARG_NO_VALUE = _reg("include-arg-no-value", E, "An <arg> inside <include> without value or default.")
UNUSED_INCLUDE_ARG = _reg("unused-include-arg", E, "An arg passed to an include that it does not declare.")
NO_LAUNCH_ROOT = _reg("no-launch-root", E, "The file has no single <launch> element.")
LAUNCH_IF_UNLESS = _reg("launch-if-unless", W, "An if/unless on <launch> (roslaunch ignores it or crashes).")
MACHINE_INVALID = _reg("invalid-machine", E, "A <machine> roslaunch rejects.")
ENV_INVALID = _reg("invalid-env", E, "An <env> roslaunch rejects.")
REMAP_INVALID = _reg("invalid-remap", E, "A <remap> roslaunch rejects.")
TEST_INVALID = _reg("invalid-test", E, "A <test> roslaunch rejects.")
BUDGET = _reg("launch-analysis-budget", W, "The launch file is too large to analyse completely.")

MAX_CASES = 64
MAX_INCLUDE_DEPTH = 12
MAX_VISITS = 20_000  # elements visited (includes expanded) per analysis: a file has at most 10,000
MAX_WALK_DEPTH = 150
UNRESOLVED = "\x01"  # marks text produced by an unresolved $(find pkg)
# the value of an arg whose value/default failed to evaluate (the failure is already reported;
# uses of the arg are not reported again)
POISON = UNRESOLVED + "?" + UNRESOLVED

NAME_LEGAL = re.compile(r"^[~/A-Za-z][\w/]*$")

LAUNCH_CHILD_TAGS = {"arg", "group", "node", "test", "param", "remap", "machine", "rosparam", "master",
                     "include", "env"}
NODE_ATTRS = ("pkg", "type", "machine", "name", "args", "output", "respawn", "respawn_delay", "cwd", "ns",
              "clear_params", "launch-prefix", "required")
TAG_ATTRS = {
    "node": NODE_ATTRS,
    "test": NODE_ATTRS + ("test-name", "time-limit", "retry"),
    "param": ("name", "value", "type", "textfile", "binfile", "command"),
    "rosparam": ("command", "ns", "file", "param", "subst_value"),
    "arg": ("name", "value", "default", "doc"),
    "machine": ("name", "address", "env-loader", "ssh-port", "user", "password", "default", "timeout",
                "ros-root", "ros-package-path", "ros-ip", "ros-hostname"),
    "remap": ("from", "to"),
    "env": ("name", "value"),
    "include": ("file", "ns", "clear_params", "pass_all_args"),
    "group": ("ns", "clear_params"),
    "launch": ("deprecated",),
    "master": ("auto",),
}


# ------------------------------------------------------------------ helpers

def ns_join(ns: str, name: str) -> str:
    if name and name[0] in "~/":
        return name
    if ns == "~":
        return "~" + name
    if not ns:
        return name
    if ns[-1] == "/":
        return ns + name
    return ns + "/" + name


def make_global_ns(name: str) -> str:
    if not name.startswith("/"):
        name = "/" + name
    if not name.endswith("/"):
        name += "/"
    return name


def canonicalize(name: str) -> str:
    if not name or name == "/":
        return name
    if name[0] == "/":
        return "/" + "/".join(x for x in name.split("/") if x)
    return "/".join(x for x in name.split("/") if x)


def is_legal_name(name: str) -> bool:
    if name == "":
        return True
    return bool(NAME_LEGAL.match(name)) and "//" not in name


OPAQUE = "\x05"  # after UNRESOLVED: a value tvl-lsp cannot compute (an $(eval) it does not evaluate)
_MARKED = re.compile(UNRESOLVED + r"([^" + UNRESOLVED + r"]*)" + UNRESOLVED)


# rosgraph.names.REMAP_PATTERN: roslaunch reads the command line as ROS remappings
# (rosgraph.names.load_mappings), so it takes ``name:=value`` only for such names
_REMAP_PATTERN = re.compile(r"^([~/A-Za-z]|_|__)[\w/]*:=.*")


def cmdline_arg(name: str, value: str) -> tuple[Optional[tuple[str, str]], Optional[str]]:
    """How roslaunch reads ``name:=value`` from its command line (``load_sysargs_into_context``):
    ``((name, value), None)`` stripped as it stores it, or ``(None, why it is ignored)``."""
    text = f"{name}:={value}"
    m = _REMAP_PATTERN.match(text)
    if m is None or m.group(0) != text:
        return None, (f"roslaunch ignores '{text}' on its command line: an arg given there must be a legal "
                      "ROS name (a letter, '_', '/' or '~' first, then letters, digits, '_' and '/')")
    parts = text.split(":=")
    if len(parts) != 2:
        return None, f"roslaunch ignores '{text}' on its command line (Invalid remapping argument: ':=' twice)"
    src, dst = parts[0].strip(), parts[1].strip()
    if not src or not dst:
        return None, f"roslaunch ignores '{text}' on its command line: the value is empty"
    if len(src) > 1 and src[0] == "_" and src[1] != "_":
        return None, (f"roslaunch ignores '{text}' on its command line: '_{src[1:]}:=' sets the private "
                      "parameter of a node, not an arg")
    return (src, dst), None


def cmdline_settable(name: str) -> bool:
    """Whether roslaunch's command line can give the arg ``name`` a value."""
    return cmdline_arg(name, "x")[0] is not None


def opaque(value: str) -> str:
    """A value tvl-lsp cannot compute, e.g. ``$(eval ...)`` beyond its interpreter: it is
    treated like the path of a package outside the workspace (no check looks into it) and
    printed back as written.  (The leading ``$`` is dropped inside the marker so that the
    value is never taken for a substitution again.)"""
    return UNRESOLVED + OPAQUE + (value[1:] if value.startswith("$") else value) + UNRESOLVED


def shown(s: str) -> str:
    """A value for messages: unresolved $(find) markers and opaque values printed back as
    written."""
    s = s.replace(POISON, "<error>")
    return _MARKED.sub(lambda m: "$" + m.group(1)[1:] if m.group(1).startswith(OPAQUE)
                       else f"$(find {m.group(1)})", s)


def merge(cases: Iterable[tuple[Formula, str]]) -> Cases:
    out: dict[str, Formula] = {}
    for c, v in cases:
        if c == FALSE:
            continue
        out[v] = disj([out[v], c]) if v in out else c
    return [(c, v) for v, c in out.items()]


def when(cases: Cases, pred: Callable[[str], bool]) -> Formula:
    return disj(c for c, v in cases if pred(v))


def _bool_val(v: str) -> Optional[bool]:
    lv = v.lower().strip()
    if lv in ("true", "1"):
        return True
    if lv in ("false", "0"):
        return False
    return None


def _attr_bool(v: str) -> Optional[bool]:
    lv = v.lower()
    if lv == "true":
        return True
    if lv == "false":
        return False
    return None


def _is_float(v: str) -> bool:
    try:
        float(v)
        return True
    except ValueError:
        return False


def convert_value(value: str, ptype: str):
    """roslaunch's ``convert_value(value, type)`` (loader.py): the typed value, or raises
    ``ValueError`` with roslaunch's message (``yaml``: rosparam's YAML, see :mod:`.rosyaml`)."""
    ptype = ptype.lower()
    if ptype == "auto":
        try:
            if "." in value:
                return float(value)
            if "_" not in value:
                return int(value)
        except ValueError:
            pass
        lv = value.lower()
        if lv in ("true", "false"):
            return lv == "true"
        return value
    if ptype in ("str", "string"):
        return value
    if ptype == "int":
        return int(value)
    if ptype == "double":
        return float(value)
    if ptype in ("bool", "boolean"):
        lv = value.lower().strip()
        if lv in ("true", "1"):
            return True
        if lv in ("false", "0"):
            return False
        raise ValueError(f"{lv} is not a '{ptype}' type")
    if ptype == "yaml":
        from . import rosyaml
        try:
            return rosyaml.load(value)
        except yaml.YAMLError as e:
            raise ValueError(str(e)[:200]) from None
    raise ValueError(f"Unknown type '{ptype}'")


def _convert_error(value: str, ptype: str) -> Optional[str]:
    if "$(" in value or UNRESOLVED in value:
        return None
    try:
        convert_value(value, ptype)
    except ValueError as e:
        return str(e)
    return None


def _satisfiable(f: Formula, limit: int = 14) -> Optional[dict[str, bool]]:
    """A satisfying assignment (brute force over the formula's variables), or None."""
    if f == FALSE:
        return None
    vs = sorted(variables(f))
    if len(vs) > limit:
        return {}
    for bits in itertools.product((False, True), repeat=len(vs)):
        env = dict(zip(vs, bits))
        if evaluate(f, env):
            return env
    return None
