"""The configurator in headless Chromium on a generated model: first paint and click latency.

    .venv/bin/python bench/bench_ui.py [--features 2000] [--nodes 150] [--runs 3]

Generates a workspace (bench/gen_model.py's model of N features; a generic launch file with one
<node> per feature for the first --nodes features), starts ``tvl-lsp ui`` on it, and measures,
from the browser (Debian's /usr/bin/chromium driven by Playwright):

- first paint: navigation -> the feature diagram drawn (state and decisions shown);
- graph: navigation -> the computation graph laid out (ELK, in a Web Worker);
- counts: navigation -> the remaining count shown;
- counts pending: navigation -> the counts shown as pending while d4 compiles the model in the
  background (the diagram is usable meanwhile);
- click: a click on a visible open feature's "+" (then again, to undo it, and so on: --clicks)
  -> the diagram shows the decision and what it implies (the server's propagation and the graph
  projection included);
- click -> counts: the same click -> the remaining count and every feature's count updated (one
  pass over the compiled model).

Each run starts a fresh server with an empty counting cache and a fresh page.  Times include
Playwright's round trips.
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
from typing import Optional

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gen_model import generate_model  # noqa: E402

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]


def make_ws(root: Path, n: int, nodes: int, model_file: Optional[Path] = None) -> Path:
    pkg = root / "src" / "robot"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package format=\"2\"><name>robot</name><version>0.0.0</version>"
                                     "<description>x</description><maintainer email=\"a@b.c\">a</maintainer>"
                                     "<license>MIT</license></package>\n")
    if model_file is not None:  # a real model: its features' names from our parser
        from tvl_lsp.tvl import parse_model
        model = model_file.read_text()
        names = [f.name for f in parse_model(model, str(model_file)).model.features]
    else:
        model = generate_model(n)
        names = ["Root"] + [f"F{i}" for i in range(1, n)]
    (pkg / "launch" / "generic.tvl").write_text(model)
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


COUNT_STATES = """(() => {
  window.__countStates = [];
  new MutationObserver(() => {
    const s = document.body && document.body.dataset.counts;
    const log = window.__countStates;
    if (s && (!log.length || log[log.length - 1][0] !== s)) log.push([s, performance.now()]);
  }).observe(document, {attributes: true, subtree: true, attributeFilter: ['data-counts']});
})();"""

# an open feature whose include control (the diagram's "+", the tree's box) a person can see
VISIBLE_OPEN = """() => [...document.querySelectorAll(
      'g.feature[data-status=open] .btn-include, .tree-row[data-status=open] [data-act=include]')]
    .filter(b => { const r = b.getBoundingClientRect();
                   const hit = document.elementFromPoint(r.x + r.width / 2, r.y + r.height / 2);
                   return hit && (b === hit || b.contains(hit)); })
    .map(b => b.closest('[data-feature]').dataset.feature).filter(f => f !== 'Root')"""
INCLUDE = ('g.feature[data-feature="{f}"] .btn-include, .tree-row[data-feature="{f}"] [data-act=include]')


def one_run(ws: Path, chromium: str, clicks: int, shot: Optional[Path]) -> dict:
    from playwright.sync_api import sync_playwright
    cache = tempfile.mkdtemp(prefix="bench-ui-cache-")  # a cold start: nothing compiled yet
    env = dict(os.environ, TVL_LSP_CACHE_DIR=cache)
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(ws), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
    url = proc.stdout.readline().strip()
    out: dict[str, list[float]] = {"server start (URL printed)": [time.perf_counter() - t0]}
    try:
        with sync_playwright() as p:
            b = p.chromium.launch(executable_path=chromium, args=FLAGS)
            pg = b.new_page(viewport={"width": 1440, "height": 900})
            pg.add_init_script(COUNT_STATES)
            t = time.perf_counter()
            pg.goto(url)
            pg.wait_for_selector("body[data-ready=diagram]", timeout=60000)
            out["first paint (diagram)"] = [time.perf_counter() - t]
            if _wait(pg, "#remaining:not([data-remaining=''])"):
                out["remaining count shown (model compiled)"] = [time.perf_counter() - t]
            # when the page showed the counts as pending (the page's own clock, from navigation)
            for state, ms in pg.evaluate("window.__countStates"):
                if state == "compiling":
                    out["counts shown pending (d4 compiling)"] = [ms / 1000]
                    break
            pg.wait_for_selector("body[data-graph=ready]", timeout=120000)
            out["graph laid out"] = [time.perf_counter() - t]
            pg.wait_for_selector("body[data-problems=ready]", timeout=120000)
            # clicks on open features a person can see: include one, then undo it, ...
            for k in range(clicks):
                before = pg.locator("#remaining").get_attribute("data-remaining")
                if k % 2 == 0:
                    fid = pg.evaluate(VISIBLE_OPEN)[k // 2]
                    want = "user-in"
                else:
                    want = "open"
                t = time.perf_counter()
                pg.locator(INCLUDE.format(f=fid)).first.click()
                pg.wait_for_selector(f'[data-feature="{fid}"][data-status="{want}"]', timeout=60000)
                out.setdefault("click -> decision + propagation drawn", []).append(time.perf_counter() - t)
                if _wait(pg, f"#remaining:not([data-remaining='{before}']):not([data-remaining='']):not(.pending)"):
                    out.setdefault("click -> every count updated", []).append(time.perf_counter() - t)
            # the server alone: one decide request (propagation, graph and problem status), then
            # the counts under it (one pass over the compiled model)
            fid2 = pg.evaluate(VISIBLE_OPEN)[0]
            out["server: decide request (HTTP)"] = [_post(url, "decide", {"feature": fid2, "value": False})]
            out["server: counts request, every feature (HTTP)"] = [
                _post(url, "counts", {"decisions": {fid2: False}, "wait": 0})]
            if shot is not None:
                pg.screenshot(path=str(shot))
            b.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
        import shutil
        shutil.rmtree(cache, ignore_errors=True)
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--features", type=int, default=2000)
    ap.add_argument("--nodes", type=int, default=150)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--chromium", default=os.environ.get("TVL_CHROMIUM", "/usr/bin/chromium"))
    ap.add_argument("--model", type=Path, help="a TVL model to configure instead of a generated one "
                    "(e.g. automotive01 converted by bench_hover_counts.py's dimacs_to_tvl)")
    ap.add_argument("--clicks", type=int, default=6, help="clicks per run (include, undo, ...)")
    ap.add_argument("--screenshot", type=Path, help="save the page after the last run's clicks")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        ws = make_ws(Path(d) / "ws", args.features, args.nodes, args.model)
        runs = [one_run(ws, args.chromium, args.clicks, args.screenshot if i == args.runs - 1 else None)
                for i in range(args.runs)]
    print(f"configurator UI, {args.model or 'generated model'}: {'' if args.model else args.features} features, {args.nodes} launch nodes; "
          f"{args.runs} runs, {args.clicks} clicks each (load average {os.getloadavg()[0]:.1f})")
    print(f"{'measure':48} {'n':>3} {'min':>9} {'median':>9} {'max':>9}")
    keys = list(dict.fromkeys(k for r in runs for k in r))
    for k in keys:
        xs = [x for r in runs for x in r.get(k, [])]
        if not xs:
            print(f"{k:48} not answered")
            continue
        print(f"{k:48} {len(xs):3} {min(xs) * 1000:7.0f}ms {statistics.median(xs) * 1000:7.0f}ms "
              f"{max(xs) * 1000:7.0f}ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
