"""What the tests may rely on: the in-repository workspace, and probes for the optional
external programs (with skip reasons that say how to install them).

The workspace the end-to-end tests run on is ``examples/ws`` (the turtlerand robot a user sees)
with ``tests/data/ws`` laid over it: two more robots (scout: one package, model and launch file
side by side; crawler: the model in one package, the generic launch file in another, paired by a
HAROS project file) and turtlerand's variants (an alternative model paired by name, a model split
into reopenings, a nested launch file without a model, a plain HAROS project, a configuration
launch file).  ``make_ws`` writes that union into a scratch folder; see tests/data/ws/README.md
for what each file is for.
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DATA = REPO / "tests" / "data"
EXAMPLE_WS = REPO / "examples" / "ws"
OVERLAY_WS = DATA / "ws"

SYS_PY = "/usr/bin/python3"
ROSLAUNCH_MISSING = ("Debian's roslaunch is not installed for /usr/bin/python3 "
                     "(apt-get install python3-roslaunch; .ci/run installs it)")


def make_ws(dst: Path) -> Path:
    """A writable copy of the test workspace (examples/ws + tests/data/ws) at ``dst``."""
    shutil.copytree(EXAMPLE_WS, dst)
    shutil.copytree(OVERLAY_WS, dst, dirs_exist_ok=True, ignore=shutil.ignore_patterns("README.md"))
    for p in [dst, *dst.rglob("*")]:
        p.chmod(p.stat().st_mode | stat.S_IWUSR)
    return dst


_roslaunch: bool | None = None


def have_roslaunch() -> bool:
    """Debian's python3-roslaunch, importable by /usr/bin/python3 (the real roslaunch 1.15)."""
    global _roslaunch
    if _roslaunch is None:
        _roslaunch = False
        if os.path.exists(SYS_PY):
            try:
                _roslaunch = subprocess.run(
                    [SYS_PY, "-c", "import roslaunch.xmlloader, roslaunch.config, rospkg"],
                    capture_output=True, timeout=60).returncode == 0
            except (OSError, subprocess.SubprocessError):
                _roslaunch = False
    return _roslaunch
