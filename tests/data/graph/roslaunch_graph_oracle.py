"""Graph oracle: the real roslaunch (Debian's python3-roslaunch) loads one product, and the real
``rosgraph.names`` resolves the hinted names of each node it loads, as rospy does.

Run with /usr/bin/python3 (not the venv).  Reads JSON from stdin::

    {"package_path": DIR, "hints": {"pkg/type": [[kind, name, type], ...]},
     "jobs": [{"file": PATH, "args": {name: value}}, ...]}

and prints a JSON list, one per job: ``{"ok": true, "nodes": [[name, pkg, type], ...],
"links": [[node, kind, resolved name, type], ...]}`` or ``{"ok": false, "error": ...}``.

Name resolution as rospy's ``rospy.names.initialize_mappings`` builds its table: the node's
``from:=to`` arguments (``rosgraph.names.load_mappings``), both sides resolved with
``rosgraph.names.resolve_name`` against the node's name; then each hinted name through
``rosgraph.names.resolve_name(name, caller_id, table)``.
"""
import io
import json
import os
import sys


def run(job, hints):
    import rosgraph.names as names
    import rospkg
    import roslaunch.substitution_args as sa
    from roslaunch.config import ROSLaunchConfig
    from roslaunch.xmlloader import XmlLoader
    sa._rospack = rospkg.RosPack()
    argv = ["roslaunch", job["file"]] + ["%s:=%s" % kv for kv in sorted(job.get("args", {}).items())]
    cfg = ROSLaunchConfig()
    out, err = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = io.StringIO(), io.StringIO()
    try:
        XmlLoader().load(job["file"], cfg, argv=argv, verbose=False)
    except BaseException as e:  # noqa: roslaunch raises all sorts of things
        return {"ok": False, "error": "%s: %s" % (type(e).__name__, str(e)[:300])}
    finally:
        sys.stdout, sys.stderr = out, err
    nodes, links = [], []
    for n in cfg.nodes:
        caller_id = names.ns_join(n.namespace, n.name)
        nodes.append([caller_id, n.package, n.type])
        mappings = names.load_mappings(["%s:=%s" % (f, t) for f, t in n.remap_args])
        table = {}
        for f, t in mappings.items():
            table[names.resolve_name(f, caller_id)] = names.resolve_name(t, caller_id)
        for kind, name, typ in hints.get("%s/%s" % (n.package, n.type), []):
            links.append([caller_id, kind, names.resolve_name(name, caller_id, table), typ])
    return {"ok": True, "nodes": sorted(nodes), "links": sorted(links)}


def main():
    data = json.load(sys.stdin)
    os.environ["ROS_PACKAGE_PATH"] = data["package_path"]
    print(json.dumps([run(j, data["hints"]) for j in data["jobs"]]))


if __name__ == "__main__":
    main()
