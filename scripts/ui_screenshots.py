"""The configurator's screenshots in docs/images, taken in headless Chromium from the repository's
own examples and test fixtures (and a generated model for the tree view).

    .venv/bin/python scripts/ui_screenshots.py [--out docs/images]

Each picture shows one view at 1280x800 (or the 560x800 of a VS Code panel beside the editor).
When Pillow is importable (here or in /usr/bin/python3) the PNGs are reduced to 256 colours.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "tests"))
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]


def serve(path: Path, *extra: str, env=None):
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(path), "--no-browser", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
    return proc, proc.stdout.readline().strip()


def page(browser, url, width=1280, height=800, counts=True):
    pg = browser.new_page(viewport={"width": width, "height": height})
    pg.goto(url)
    pg.wait_for_selector("body[data-ready]", timeout=60000)
    if counts:
        pg.wait_for_selector("#remaining:not([data-remaining=''])", timeout=120000)
    return pg


def settle(pg, ms=700):
    pg.wait_for_timeout(ms)


def shrink(path: Path) -> None:
    code = ("import sys; from PIL import Image; im = Image.open(sys.argv[1]).convert('RGB');"
            "im.quantize(256, method=Image.Quantize.MEDIANCUT).save(sys.argv[1], optimize=True)")
    for py in (sys.executable, "/usr/bin/python3"):
        if subprocess.run([py, "-c", code, str(path)], capture_output=True).returncode == 0:
            return


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", type=Path, default=REPO / "docs" / "images")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright
    from model_gen import generated_model

    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix="tvl-shots-"))
    env = dict(os.environ, TVL_LSP_CACHE_DIR=str(tmp / "cache"))
    ws = tmp / "ws"
    shutil.copytree(REPO / "examples" / "ws", ws)
    robot = tmp / "robot_ws"
    shutil.copytree(REPO / "tests" / "data" / "configurator" / "robot_ws", robot)
    big = tmp / "big" / "src" / "big" / "launch"
    big.mkdir(parents=True)
    (tmp / "big" / ".catkin_workspace").write_text("")
    (big / "big.tvl").write_text(generated_model(1500, seed=1))
    procs = []
    shots: list[Path] = []

    def shot(pg, name):
        p = out / name
        pg.screenshot(path=str(p))
        shots.append(p)

    try:
        with sync_playwright() as p:
            b = p.chromium.launch(executable_path=os.environ.get("TVL_CHROMIUM", "/usr/bin/chromium"), args=FLAGS)

            # the thesis's turtlerand: diagram, graph, an implied feature explained
            proc, url = serve(ws, "--project", str(ws / "turtlerand_nodes.yaml"), env=env)
            procs.append(proc)
            pg = page(b, url)
            pg.wait_for_selector("body[data-graph=ready]", timeout=60000)
            pg.locator('g.feature[data-feature="Random"] .btn-include').click()
            pg.wait_for_selector("#remaining[data-remaining='2']")
            pg.locator('g.feature[data-feature="Vel"] rect.box').click()
            pg.locator("#details .why").wait_for()
            settle(pg)
            shot(pg, "configurator.png")
            pg.close()

            # the robot fixture: graph linked with the features, rules in the problems, decisions
            proc, url = serve(robot / "src" / "nav" / "launch" / "nav.tvl", "--limit", "4", env=env)
            procs.append(proc)
            pg = page(b, url)
            pg.wait_for_selector("body[data-graph=ready]", timeout=60000)
            for f, what in (("Amcl", "include"), ("Camera", "exclude")):
                pg.locator(f'g.feature[data-feature="{f}"] .btn-{what}').click()
                pg.wait_for_selector(f'g.feature[data-feature="{f}"][data-status="user-{"in" if what == "include" else "out"}"]')
            pg.locator("#group-ns").check()
            pg.wait_for_selector("g.namespace")
            pg.locator('g.element[data-id="node:/lidar"]').click()
            settle(pg)
            shot(pg, "configurator-graph.png")
            pg.locator("#tab-decisions").click()
            settle(pg, 300)
            shot(pg, "configurator-decisions.png")
            pg.locator("#configuration").click()
            pg.locator('[data-action="save"]').click()
            pg.locator("#save-format").select_option("featureide")
            settle(pg, 300)
            shot(pg, "configurator-save.png")
            pg.keyboard.press("Escape")
            pg.locator("#configuration").click()
            pg.locator('[data-action="reset"]').click()
            pg.wait_for_selector('g.feature[data-feature="Amcl"][data-status="open"]')
            pg.locator("#generate").click()
            pg.locator('[data-mode="all"]').click()
            pg.locator(".generated").wait_for()
            settle(pg, 300)
            shot(pg, "configurator-generate.png")
            pg.close()
            # the same at the size of a VS Code panel beside the editor
            pg = page(b, url, 560, 800)
            pg.locator('g.feature[data-feature="Lidar"] rect.box').click()
            settle(pg)
            shot(pg, "configurator-panel.png")
            pg.locator('.pane-switch [data-pane=graph]').click()
            settle(pg)
            shot(pg, "configurator-panel-graph.png")
            pg.close()
            pg = page(b, url.split("?")[0] + "?" + url.split("?")[1])
            pg.locator("#model-picker").select_option(str(robot / "src" / "nav" / "launch" / "spare.tvl"))
            pg.locator("#pair-launch").wait_for()
            settle(pg, 300)
            shot(pg, "configurator-pair.png")
            pg.close()

            # a model of 1,500 features: the tree
            proc, url = serve(big / "big.tvl", env=env)
            procs.append(proc)
            pg = page(b, url)
            pg.locator("#search").fill("F1188")
            pg.locator("#search").press("Enter")
            pg.wait_for_selector('.tree-row.selected[data-feature="F1188"]')
            fid = pg.evaluate("[...document.querySelectorAll('.tree-row[data-status=open]')].map(r => r.dataset.feature)"
                              ".filter(f => f !== 'F1188')[3]")
            pg.locator(f'.tree-row[data-feature="{fid}"] [data-act=include]').click()
            pg.wait_for_selector(f'.tree-row[data-feature="{fid}"][data-status="user-in"]')
            settle(pg)
            shot(pg, "configurator-tree.png")
            pg.close()

            # counts that give up after the compile budget
            proc, url = serve(big / "big.tvl", "--count-budget", "0.01", env=dict(env, TVL_LSP_CACHE_DIR=str(tmp / "c2")))
            procs.append(proc)
            pg = page(b, url, counts=False)
            pg.wait_for_selector("body[data-counts=gave-up]", timeout=60000)
            settle(pg, 300)
            shot(pg, "configurator-gave-up.png")
            pg.close()
            b.close()
    finally:
        for proc in procs:
            proc.terminate()
            proc.wait(timeout=30)
        shutil.rmtree(tmp, ignore_errors=True)
    for s in shots:
        shrink(s)
        print(f"{s.relative_to(REPO) if s.is_relative_to(REPO) else s}  {s.stat().st_size // 1024} KB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
