"""Differential-test oracle: run Debian's real roslaunch (python3-roslaunch) on launch files.

Run with /usr/bin/python3 (not the venv). Reads a JSON list of jobs
``[{"file": PATH, "args": {name: value}, "package_path": DIR, "env": {...}}]`` on stdin and
prints a JSON list of ``{"ok": bool, "nodes": [resolved names], "params": [names],
"values": {name: value}, "error": type, "message": str}``.

``values`` are the parameter values roslaunch would set, made JSON-safe: ``Binary`` ->
``{"__binary__": length}``, dates -> ``{"__date__": iso}``, other objects -> ``{"__repr__": repr}``;
non-finite floats as ``{"__float__": "nan" | "inf" | "-inf"}``.

With ``--serve`` it reads one JSON list of jobs per line and answers each with one line (a
long-lived oracle for property tests).

A job with ``"commands": "check"`` does not run the programs of ``<param command=...>``: it checks
that the program exists (as roslaunch's ``no such command`` error does) and sets the parameter to
``"$(command ...)"``; used on third-party repositories, whose commands (xacro, scripts) are not
run here.  Package look-ups are cached per ``package_path``.
"""
import io
import json
import os
import sys


_ENV0 = dict(os.environ)
_RP = {}
_REAL_PARAM_VALUE = []


def _checked_param_value(self, verbose, name, ptype, value, textfile, binfile, command):
    if command is None:
        return _REAL_PARAM_VALUE[0](self, verbose, name, ptype, value, textfile, binfile, command)
    import shlex
    import shutil
    words = shlex.split(command)
    prog = words[0] if words else ""
    found = os.path.isfile(prog) if "/" in prog else shutil.which(prog) is not None
    if not found:
        raise ValueError("Cannot load command parameter [%s]: no such command [%s]" % (name, words))
    return "$(command %s)" % command


def jsonable(v):
    import datetime
    import math
    if isinstance(v, bool) or v is None or isinstance(v, (int, str)):
        return v
    if isinstance(v, float):
        return v if math.isfinite(v) else {"__float__": repr(v)}
    if isinstance(v, (list, tuple)):
        return [jsonable(x) for x in v]
    if isinstance(v, dict):
        return {str(k): jsonable(x) for k, x in v.items()}
    if isinstance(v, (datetime.date, datetime.datetime)):
        return {"__date__": v.isoformat()}
    if type(v).__name__ == "Binary":
        return {"__binary__": len(v.data)}
    return {"__repr__": repr(v)}


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
    import roslaunch.loader as rl_loader
    pp = job.get("package_path", "")
    if pp not in _RP:
        _RP[pp] = rospkg.RosPack()
    sa._rospack = _RP[pp]
    if not _REAL_PARAM_VALUE:
        _REAL_PARAM_VALUE.append(rl_loader.Loader.param_value)
    rl_loader.Loader.param_value = (_checked_param_value if job.get("commands") == "check"
                                    else _REAL_PARAM_VALUE[0])
    from roslaunch.config import ROSLaunchConfig
    from roslaunch.xmlloader import XmlLoader
    argv = ["roslaunch", job["file"]] + ["%s:=%s" % kv for kv in sorted(job.get("args", {}).items())]
    cfg = ROSLaunchConfig()
    loader = XmlLoader()
    loader.ignore_unset_args = False  # as roslaunch.config.load_config_default sets it
    out, err = sys.stdout, sys.stderr
    sys.stdout = io.StringIO()
    sys.stderr = io.StringIO()
    try:
        loader.load(job["file"], cfg, argv=argv, verbose=False)
        nodes = sorted(n.namespace + n.name if n.name else "" for n in cfg.nodes)
        values = {k: jsonable(p.value) for k, p in cfg.params.items()}
        return {"ok": True, "nodes": nodes, "params": sorted(cfg.params), "values": values,
                "warnings": list(cfg.config_errors)}
    except BaseException as e:  # noqa: roslaunch raises all sorts of things
        return {"ok": False, "error": type(e).__name__, "message": str(e)[:500]}
    finally:
        sys.stdout, sys.stderr = out, err


def main():
    if "--serve" in sys.argv:
        # one JSON list of jobs per input line, one JSON list of results per output line
        for line in sys.stdin:
            if line.strip():
                sys.stdout.write(json.dumps([run(j) for j in json.loads(line)]) + "\n")
                sys.stdout.flush()
        return
    jobs = json.load(sys.stdin)
    print(json.dumps([run(j) for j in jobs]))


if __name__ == "__main__":
    main()
