"""ROS name resolution for the computation graph: global / relative / private names, remaps
resolved in the node's namespace, the last remap of a name winning -- checked against the real
``rosgraph.names`` where it is installed."""

from __future__ import annotations

import json
import subprocess

import pytest

from tvl_lsp.base.formula import FALSE, TRUE, Var, evaluate, neg
from tvl_lsp.graph.names import canonical, namespace_of, remap_cases, resolve, resolve_remapped

CASES = [
    # name, node, expected
    ("/x", "/ns/talker", "/x"),
    ("x", "/ns/talker", "/ns/x"),
    ("x/y", "/ns/talker", "/ns/x/y"),
    ("~x", "/ns/talker", "/ns/talker/x"),
    ("~x/y", "/a/b/talker", "/a/b/talker/x/y"),
    ("x", "/talker", "/x"),
    ("~x", "/talker", "/talker/x"),
    ("//x//y/", "/ns/talker", "/x/y"),
    ("x//y", "/ns/talker", "/ns/x/y"),
    ("", "/ns/talker", "/ns/"),
]


@pytest.mark.parametrize("name,node,expected", CASES)
def test_resolve(name, node, expected):
    assert resolve(name, node) == expected


def test_canonical_and_namespace():
    assert canonical("/a//b/") == "/a/b"
    assert canonical("a//b") == "a/b"
    assert namespace_of("/a/b/c") == "/a/b/"
    assert namespace_of("/c") == "/"


REMAP_CASES = [
    # name, node, remaps (roslaunch order), expected
    ("cmd_vel", "/Random", [("cmd_vel", "/turtle1/cmd_vel")], "/turtle1/cmd_vel"),
    ("cmd_vel", "/base/driver", [("odom", "/robot/odom")], "/base/cmd_vel"),
    ("odom", "/base/driver", [("odom", "/robot/odom")], "/robot/odom"),
    # the remap's relative `from` resolves in the node's namespace
    ("/base/odom", "/base/driver", [("odom", "x")], "/base/x"),
    ("/odom", "/base/driver", [("odom", "x")], "/odom"),
    # private names on both sides
    ("~cmd_vel", "/teleop", [("~cmd_vel", "/base/cmd_vel")], "/base/cmd_vel"),
    ("out", "/ns/n", [("out", "~private")], "/ns/n/private"),
    # two spellings of one name: the last remapping wins
    ("cmd_vel", "/n", [("cmd_vel", "/a"), ("/cmd_vel", "/b")], "/b"),
    # one step, no chains
    ("a", "/n", [("a", "b"), ("b", "c")], "/b"),
    ("image", "/sensors/compressor", [("image", "camera/image_raw")], "/sensors/camera/image_raw"),
]


@pytest.mark.parametrize("name,node,remaps,expected", REMAP_CASES)
def test_resolve_remapped(name, node, remaps, expected):
    assert resolve_remapped(name, node, remaps) == expected


def _rosgraph_available() -> bool:
    try:
        return subprocess.run(["/usr/bin/python3", "-c", "import rosgraph.names"], capture_output=True,
                              timeout=30).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


@pytest.mark.skipif(not _rosgraph_available(), reason="Debian's python3-rosgraph is not installed (apt-get install python3-rosgraph)")
def test_same_resolution_as_rosgraph():
    """rosgraph.names (rospy's table: both sides of each remap resolved against the node name)."""
    probe = r"""
import json, sys
import rosgraph.names as names
out = []
for name, node, remaps in json.load(sys.stdin):
    table = {}
    for f, t in names.load_mappings(["%s:=%s" % (f, t) for f, t in remaps]).items():
        table[names.resolve_name(f, node)] = names.resolve_name(t, node)
    out.append(names.resolve_name(name, node, table))
print(json.dumps(out))
"""
    jobs = [(n, node, []) for n, node, _ in CASES if n] + [(n, node, r) for n, node, r, _ in REMAP_CASES
                                                           if len({f for f, _ in r}) == len(r)]
    got = subprocess.run(["/usr/bin/python3", "-c", probe], input=json.dumps(jobs), capture_output=True,
                         text=True, timeout=60, check=True)
    expected = json.loads(got.stdout)
    ours = [resolve_remapped(n, node, r) for n, node, r in jobs]
    assert ours == expected


def test_remap_cases_partition_the_products():
    """Conditional remaps (Listing 5.4's Random node): each product gets exactly one name, the
    one the concrete remapping gives."""
    M, T = Var("Multiplexer"), Var("Teleop")
    # roslaunch's list: a later remap of the same `from` replaced the earlier where both hold
    remaps = [("cmd_vel", "cmd_vel_low", M, "low"),
              ("cmd_vel", "/turtle1/cmd_vel", neg(M), "direct"),
              ("other", "x", T, "unrelated")]
    cases = remap_cases("cmd_vel", "/Random", remaps)
    for m in (False, True):
        for t in (False, True):
            env = {"Multiplexer": m, "Teleop": t}
            hits = [(name, origin) for c, name, origin in cases if evaluate(c, env)]
            assert len(hits) == 1
            concrete = [(f, to) for f, to, c, _ in remaps if evaluate(c, env)]
            assert hits[0][0] == resolve_remapped("cmd_vel", "/Random", concrete)
    assert {(str(c), n) for c, n, _ in cases} == {("Multiplexer", "/cmd_vel_low"),
                                                 ("!Multiplexer", "/turtle1/cmd_vel")}


def test_remap_cases_last_wins_and_unconditional():
    A = Var("A")
    cases = remap_cases("x", "/n", [("x", "a", TRUE, 1), ("/x", "b", A, 2)])
    assert sorted((str(c), n, o) for c, n, o in cases) == [("!A", "/a", 1), ("A", "/b", 2)]
    assert remap_cases("x", "/n", [("x", "a", TRUE, 1)]) == [(TRUE, "/a", 1)]
    assert remap_cases("x", "/n", [("y", "a", TRUE, 1)]) == [(TRUE, "/x", None)]
    assert remap_cases("x", "/n", [("x", "a", FALSE, 1)]) == [(TRUE, "/x", None)]
