"""Shared helpers of the computation-graph tests: the symbolic graph of a launch file with its
model and hints, every product of the model, and each product's graph loaded directly."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from tvl_lsp.analysis.engine import ModelAnalysis
from tvl_lsp.graph import (Graph, GraphLogic, ProjectHints, build_graph, build_product_graph, parse_hints,
                           project)
from tvl_lsp.launch import analyse_launch, load_launch
from tvl_lsp.tvl import parse_model

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
GRAPH_WS = HERE / "data" / "graph" / "ws"
ROBOT_LAUNCH = GRAPH_WS / "src" / "robot" / "launch" / "robot.launch"
ROBOT_MODEL = GRAPH_WS / "src" / "robot" / "launch" / "robot.tvl"
ROBOT_PROJECT = GRAPH_WS / "haros.yaml"
EXAMPLES_WS = REPO / "examples" / "ws"
ORACLE = HERE / "data" / "graph" / "roslaunch_graph_oracle.py"

# the turtlerand hints the thesis's figures need (Listing 5.6 hints the turtlesim nodes only;
# the turtlerand nodes' topics come from their source code, Listings 2.4 and 2.7)
TURTLERAND_HINTS = """
nodes:
  turtlesim/turtlesim_node:
    subscribe:
      /turtle1/cmd_vel: geometry_msgs/Twist
  turtlesim/turtle_teleop_key:
    advertise:
      /turtle1/cmd_vel: geometry_msgs/Twist
  turtlerand/random_controller:
    advertise:
      cmd_vel: geometry_msgs/Twist
  turtlerand/multiplexer:
    advertise:
      cmd_vel: geometry_msgs/Twist
    subscribe:
      cmd_vel_low: geometry_msgs/Twist
      cmd_vel_high: geometry_msgs/Twist
"""


PAIRING = """project: turtlerand
configurations:
  {lf: turtlerand/launch/generic.launch, tvl: turtlerand/launch/generic.tvl}
"""


def turtlerand_ws(tmp_path: Path, hints: str = TURTLERAND_HINTS) -> Path:
    """A copy of examples/ws without its sources (what the nodes use comes from hints only) whose
    project file has the hints of every turtlerand node."""
    dst = tmp_path / "turtlerand_ws"
    shutil.copytree(EXAMPLES_WS, dst)
    shutil.rmtree(dst / "src" / "turtlerand" / "src")
    (dst / "src" / "turtlerand" / "CMakeLists.txt").unlink()
    (dst / "haros.yaml").write_text(PAIRING + hints)
    return dst


@dataclass
class Setup:
    launch: str
    analysis: object        # LaunchAnalysis
    model: ModelAnalysis
    hints: ProjectHints
    graph: Graph
    logic: GraphLogic
    features: list

    def project(self, decisions=None, count=False) -> Graph:
        return project(self.graph, self.logic, decisions or {}, count=count)

    def products(self) -> list[dict]:
        return list(self.model.enumerate(limit=None))

    def product_graph(self, product: dict) -> Graph:
        args = {k: "true" if v else "false" for k, v in product.items()}
        res = load_launch(self.launch, args)
        assert res.error is None, res.error
        return build_product_graph(res, self.hints, self.launch)


def setup(launch: Path, model: Path, project_file: Optional[Path]) -> Setup:
    launch = str(Path(launch).resolve())
    res = parse_model(Path(model).read_text(), str(model))
    ma = ModelAnalysis(res.model)
    enc = ma.encoding
    features = [enc.name_of(f) for f in enc.features]
    analysis = analyse_launch(Path(launch).read_text(), launch, features=features)
    hints = parse_hints(str(project_file), Path(project_file).read_text()) if project_file else ProjectHints()
    graph = build_graph(analysis, hints)
    return Setup(launch, analysis, ma, hints, graph, GraphLogic(enc, features, ma), features)


def links_of(g: Graph) -> set[tuple]:
    """(node name, kind, resource name, type) of every link."""
    return {(g.nodes[ln.node].name, ln.kind, g.resources[ln.resource].name, ln.type) for ln in g.links.values()}


def nodes_of(g: Graph) -> set[tuple]:
    return {(n.name, n.package, n.type) for n in g.nodes.values()}


def resources_of(g: Graph) -> set[tuple]:
    return {(r.kind, r.name) for r in g.resources.values()}


def roslaunch_available() -> bool:
    try:
        return subprocess.run(["/usr/bin/python3", "-c", "import roslaunch, rosgraph.names"],
                              capture_output=True, timeout=60).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


def oracle(package_path: Path, hints: ProjectHints, jobs: list[dict]) -> list[dict]:
    """The real roslaunch + rosgraph.names on each job (see data/graph/roslaunch_graph_oracle.py)."""
    data = {"package_path": str(package_path),
            "hints": {k: [[e.kind, e.name, e.type] for e in h.entries] for k, h in hints.by_type.items()},
            "jobs": jobs}
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    r = subprocess.run(["/usr/bin/python3", str(ORACLE)], input=json.dumps(data), capture_output=True, text=True,
                       timeout=600, env=env)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout)
