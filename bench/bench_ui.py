"""The configurator in headless Chromium on a generated model: first paint and click latency.

    .venv/bin/python bench/bench_ui.py [--features 2000] [--nodes 150] [--runs 3]

Generates a workspace (bench/gen_model.py's model of N features; a generic launch file with one
<node> per feature for the first --nodes features), starts ``tvl-lsp ui`` on it, and measures,
from the browser (Debian's /usr/bin/chromium driven by Playwright):

- first paint: navigation -> the feature diagram drawn (state and decisions shown);
- graph: navigation -> the computation graph laid out (ELK, in a Web Worker);
- counts: navigation -> the remaining count shown;
- click: a click on an open feature's "+" -> the diagram shows the decision and what it implies
  (the server's propagation and the graph projection included);
- click -> counts: the same click -> the remaining count updated.

Each run starts a fresh server and a fresh page.  Times include Playwright's round trips.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gen_model import generate_model  # noqa: E402

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]


def make_ws(root: Path, n: int, nodes: int) -> Path:
    pkg = root / "src" / "robot"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package format=\"2\"><name>robot</name><version>0.0.0</version>"
                                     "<description>x</description><maintainer email=\"a@b.c\">a</maintainer>"
                                     "<license>MIT</license></package>\n")
    model = generate_model(n)
    (pkg / "launch" / "generic.tvl").write_text(model)
    names = ["Root"] + [f"F{i}" for i in range(1, n)]
    lines = ["<launch>"] + [f'  <arg name="{f}"/>' for f in names]
    for i, f in enumerate(names[1:nodes + 1]):
        lines.append(f'  <node pkg="robot" type="n{i % 17}" name="node_{f}" if="$(arg {f})">')
        lines.append(f'    <remap from="out" to="/topic_{i % 40}"/>')
        lines.append("  </node>")
    lines.append("</launch>")
    (pkg / "launch" / "generic.launch").write_text("\n".join(lines) + "\n")
    (root / ".catkin_workspace").write_text("")
    return root


def _wait(pg, selector: str, timeout: float = 90000) -> bool:
    try:
        pg.wait_for_selector(selector, timeout=timeout)
        return True
    except Exception:  # no count in time (today's counter on a loaded machine): not measured
        return False


def _post(url: str, op: str, body: dict) -> float:
    import json
    import urllib.request
    base, token = url.split("/?token=")
    req = urllib.request.Request(f"{base}/api/{op}", data=json.dumps(body).encode(),
                                 headers={"Content-Type": "application/json", "X-TVL-Token": token})
    t = time.perf_counter()
    urllib.request.urlopen(req, timeout=120).read()
    return time.perf_counter() - t


def one_run(ws: Path, chromium: str) -> dict:
    from playwright.sync_api import sync_playwright
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(ws), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    url = proc.stdout.readline().strip()
    out = {"server start (URL printed)": time.perf_counter() - t0}
    try:
        with sync_playwright() as p:
            b = p.chromium.launch(executable_path=chromium, args=FLAGS)
            pg = b.new_page(viewport={"width": 1440, "height": 900})
            t = time.perf_counter()
            pg.goto(url)
            pg.wait_for_selector("body[data-ready=diagram]", timeout=60000)
            out["first paint (diagram)"] = time.perf_counter() - t
            pg.wait_for_selector("body[data-graph=ready]", timeout=120000)
            out["graph laid out"] = time.perf_counter() - t
            if _wait(pg, "#remaining:not([data-remaining=''])"):
                out["remaining count shown"] = time.perf_counter() - t
            before = pg.locator("#remaining").get_attribute("data-remaining")
            # an open, visible feature
            fid = pg.evaluate("""() => [...document.querySelectorAll('g.feature[data-status=open]')]
                                 .map(g => g.dataset.feature).filter(f => f !== 'Root')[0]""")
            t = time.perf_counter()
            pg.locator(f'g.feature[data-feature="{fid}"] .btn-include').click()
            pg.wait_for_selector(f'g.feature[data-feature="{fid}"][data-status="user-in"]', timeout=60000)
            out["click answered (decision + propagation shown)"] = time.perf_counter() - t
            if _wait(pg, f"#remaining:not([data-remaining='{before}']):not([data-remaining='']):not(.pending)"):
                out["click -> remaining count updated"] = time.perf_counter() - t
            # the server alone: one decide request (propagation, graph and problem status)
            fid2 = pg.evaluate("""() => [...document.querySelectorAll('g.feature[data-status=open]')]
                                  .map(g => g.dataset.feature).filter(f => f !== 'Root')[0]""")
            out["server: decide request (HTTP)"] = _post(url, "decide", {"feature": fid2, "value": False})
            b.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--features", type=int, default=2000)
    ap.add_argument("--nodes", type=int, default=150)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--chromium", default=os.environ.get("TVL_CHROMIUM", "/usr/bin/chromium"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        ws = make_ws(Path(d) / "ws", args.features, args.nodes)
        runs = [one_run(ws, args.chromium) for _ in range(args.runs)]
    print(f"configurator UI, generated model: {args.features} features, {args.nodes} launch nodes; "
          f"{args.runs} runs (load average {os.getloadavg()[0]:.1f})")
    print(f"{'measure':48} {'min':>8} {'median':>8} {'max':>8}")
    keys = list(dict.fromkeys(k for r in runs for k in r))
    for k in keys:
        xs = [r[k] for r in runs if k in r]
        if len(xs) < len(runs):
            print(f"{k:48} answered in {len(xs)} of {len(runs)} runs")
        if not xs:
            continue
        print(f"{k:48} {min(xs) * 1000:7.0f}ms {statistics.median(xs) * 1000:7.0f}ms {max(xs) * 1000:7.0f}ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
