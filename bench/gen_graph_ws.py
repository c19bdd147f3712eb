"""Generate a large hinted workspace for ``bench_graph.py``: a generic launch file over a given
TVL model's features (groups with namespaces and conditions, nodes with conditional remaps) and
a HAROS project file with ``nodes:`` hints for every node type (random topics and types, so
there are many findings).

    .venv/bin/python bench/gen_graph_ws.py OUT --model MODEL.tvl [--groups 30] [--nodes 8] [--seed 1]
"""

from __future__ import annotations

import argparse
import random
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--model", required=True)
    ap.add_argument("--groups", type=int, default=30)
    ap.add_argument("--nodes", type=int, default=8)
    ap.add_argument("--types", type=int, default=40)
    ap.add_argument("--topics", type=int, default=60)
    ap.add_argument("--seed", type=int, default=1)
    ns = ap.parse_args()
    sys.path.insert(0, str(ROOT))
    from tvl_lsp.analysis.engine import ModelAnalysis
    from tvl_lsp.tvl import parse_model
    rnd = random.Random(ns.seed)
    model = Path(ns.model)
    enc = ModelAnalysis(parse_model(model.read_text(), str(model)).model).encoding
    feats = [enc.name_of(f) for f in enc.features]
    out = Path(ns.out)
    launch_dir = out / "src" / "synth" / "launch"
    launch_dir.mkdir(parents=True, exist_ok=True)
    shutil.copy(model, launch_dir / "synth.tvl")
    (out / "src" / "synth" / "package.xml").write_text(
        '<package format="2"><name>synth</name><version>0.0.0</version><description>generated</description>'
        '<maintainer email="a@b.c">a</maintainer><license>MIT</license></package>\n')
    lines = ["<launch>"] + [f'  <arg name="{f}"/>' for f in feats]
    for g in range(ns.groups):
        f1, f2 = rnd.sample(feats, 2)
        lines.append(f'  <group if="$(arg {f1})" ns="ns{g % 5}">')
        lines.append(f'    <remap from="topic{rnd.randrange(ns.topics)}" to="/global{rnd.randrange(20)}" '
                     f'unless="$(arg {f2})"/>')
        for n in range(ns.nodes):
            lines.append(f'    <node pkg="pkg" type="t{rnd.randrange(ns.types)}" name="n{g}_{n}" '
                         f'if="$(arg {rnd.choice(feats)})">')
            lines.append(f'      <remap from="topic{rnd.randrange(ns.topics)}" to="topic{rnd.randrange(ns.topics)}" '
                         f'if="$(arg {rnd.choice(feats)})"/>')
            lines.append("    </node>")
        lines.append("  </group>")
    lines.append("</launch>")
    (launch_dir / "synth.launch").write_text("\n".join(lines) + "\n")
    hints = ["project: synth", "packages: [synth]", "configurations:",
             "  {lf: synth/launch/synth.launch, tvl: synth/launch/synth.tvl}", "nodes:"]
    for i in range(ns.types):
        hints += [f"  pkg/t{i}:", "    advertise:"]
        hints += [f"      topic{rnd.randrange(ns.topics)}: msg/T{rnd.randrange(3)}" for _ in range(3)]
        hints += ["    subscribe:"]
        hints += [f"      topic{rnd.randrange(ns.topics)}: msg/T{rnd.randrange(3)}" for _ in range(3)]
    (out / "haros.yaml").write_text("\n".join(hints) + "\n")
    print(f"{out}: {ns.groups * ns.nodes} nodes over {len(feats)} features")
    return 0


if __name__ == "__main__":
    sys.exit(main())
