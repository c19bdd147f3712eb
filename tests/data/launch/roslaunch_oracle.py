"""Differential-test oracle: run Debian's real roslaunch (python3-roslaunch) on launch files.

Run with /usr/bin/python3 (not the venv). Reads a JSON list of jobs
``[{"file": PATH, "args": {name: value}, "package_path": DIR}]`` on stdin and prints a JSON
list of ``{"ok": bool, "nodes": [resolved names], "error": type, "message": str}``.
"""
import io
import json
import os
import sys


_ENV0 = dict(os.environ)


def run(job):
    os.environ.clear()
    os.environ.update(_ENV0)
    os.environ["ROS_PACKAGE_PATH"] = job.get("package_path", "")
    import itertools
    import rospkg
    import rosgraph.names
    import roslaunch.substitution_args as sa0
    counter = itertools.count(1)
    # deterministic anonymous names (tvl-lsp writes ID_anonN too)
    sa0.rosgraph.names.anonymous_name = lambda ident: "%s_anon%d" % (ident, next(counter))
    for k, v in job.get("env", {}).items():
        os.environ[k] = v
    import roslaunch.substitution_args as sa
    sa._rospack = rospkg.RosPack()  # fresh package cache per job
    from roslaunch.config import ROSLaunchConfig
    from roslaunch.xmlloader import XmlLoader
    argv = ["roslaunch", job["file"]] + ["%s:=%s" % kv for kv in sorted(job.get("args", {}).items())]
    cfg = ROSLaunchConfig()
    loader = XmlLoader()
    out, err = sys.stdout, sys.stderr
    sys.stdout = io.StringIO()
    sys.stderr = io.StringIO()
    try:
        loader.load(job["file"], cfg, argv=argv, verbose=False)
        nodes = sorted(n.namespace + n.name if n.name else "" for n in cfg.nodes)
        return {"ok": True, "nodes": nodes, "params": sorted(cfg.params), "warnings": list(cfg.config_errors)}
    except BaseException as e:  # noqa: roslaunch raises all sorts of things
        return {"ok": False, "error": type(e).__name__, "message": str(e)[:500]}
    finally:
        sys.stdout, sys.stderr = out, err


def main():
    jobs = json.load(sys.stdin)
    print(json.dumps([run(j) for j in jobs]))


if __name__ == "__main__":
    main()
