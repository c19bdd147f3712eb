"""Click -> updated count in the configurator, in headless Chromium, on any model.

    .venv/bin/python bench/bench_configurator.py MODEL [--clicks 40] [--view tree|diagram]
                                                 [--width 1280 --height 800] [--cold]

Starts ``tvl-lsp ui MODEL`` (a .tvl or .uvl model, or a workspace folder), opens it in Debian's
/usr/bin/chromium (Playwright), waits until the counts are shown, then clicks, as a person would,
the "include" box (tree) or "+" button (diagram) of an open feature on screen, and again to undo
it, and so on.  For each click it measures, in the page's own clock, the time from the click event
to the header's remaining count showing the new number (the decide request, the propagation, the
redraw and the counts request included), and from the click to the clicked feature's new status
(the details panel is redrawn in the same task).  ``--cold`` starts with an empty counting cache
(the first counts then wait for d4); by default the cache is the user's, as a returning user has it.

Prints min / median / p95 / max of each measure and the load average; exits 1 when the p95 of
click -> count is above --budget (default 150 ms).
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]

PROBE = """(() => {
  window.__clicks = [];
  document.addEventListener('click', (ev) => {
    if (ev.target.closest && ev.target.closest('[data-act=include], .btn-include')) {
      window.__clicks.push({t0: performance.now(), before: window.__nextBefore, count: null});
    }
  }, true);
  new MutationObserver(() => {
    const c = window.__clicks[window.__clicks.length - 1];
    if (!c) return;
    const rem = document.getElementById('remaining');
    if (c.count === null && rem && !rem.classList.contains('pending') && rem.dataset.remaining &&
        rem.dataset.remaining !== c.before) {
      c.count = performance.now() - c.t0;
    }
  }).observe(document, {attributes: true, subtree: true, characterData: true, childList: true});
})();"""

# an open feature whose include control a person can see (not covered by another panel)
VISIBLE_OPEN = """() => [...document.querySelectorAll(
      '.tree-row[data-status=open] [data-act=include], g.feature[data-status=open] .btn-include')]
    .filter(b => { const r = b.getBoundingClientRect();
                   if (!r.width) return false;
                   const hit = document.elementFromPoint(r.x + r.width / 2, r.y + r.height / 2);
                   return hit && (b === hit || b.contains(hit)); })
    .map(b => b.closest('[data-feature]').dataset.feature)"""


def pct(xs: list[float], p: float) -> float:
    xs = sorted(xs)
    k = max(0, min(len(xs) - 1, int(round(p / 100 * (len(xs) - 1)))))
    return xs[k]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model", type=Path)
    ap.add_argument("--clicks", type=int, default=40)
    ap.add_argument("--view", choices=("tree", "diagram"), help="the feature view (default: the page's choice)")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=800)
    ap.add_argument("--cold", action="store_true", help="an empty counting cache")
    ap.add_argument("--budget", type=float, default=150.0, help="ms: the p95 click -> count must not exceed it")
    ap.add_argument("--chromium", default=os.environ.get("TVL_CHROMIUM", "/usr/bin/chromium"))
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    env = dict(os.environ)
    cache = None
    if args.cold:
        cache = tempfile.mkdtemp(prefix="bench-cfg-cache-")
        env["TVL_LSP_CACHE_DIR"] = cache
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(args.model), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
    url = proc.stdout.readline().strip()
    out: dict[str, list[float]] = {}
    try:
        with sync_playwright() as p:
            b = p.chromium.launch(executable_path=args.chromium, args=FLAGS)
            pg = b.new_page(viewport={"width": args.width, "height": args.height})
            pg.add_init_script(PROBE)
            t = time.perf_counter()
            pg.goto(url)
            pg.wait_for_selector("body[data-ready]", timeout=120000)
            out["page -> features drawn (ms)"] = [(time.perf_counter() - t) * 1000]
            pg.wait_for_selector("#remaining:not([data-remaining=''])", timeout=600000)
            out["page -> counts shown (ms)"] = [(time.perf_counter() - t) * 1000]
            out["server start -> counts shown (ms)"] = [(time.perf_counter() - t0) * 1000]
            if args.view:
                pg.locator(f".segmented [data-view={args.view}]").click()
                pg.wait_for_timeout(300)
            view = pg.evaluate("document.body.dataset.view")
            fid = None
            for k in range(args.clicks):
                undo = k % 2 == 1
                if not undo:
                    fid = next(iter(pg.evaluate(VISIBLE_OPEN)), None)
                    if fid is None:
                        print("no open feature on screen: stopping", file=sys.stderr)
                        break
                before = pg.locator("#remaining").get_attribute("data-remaining")
                pg.evaluate("b => { window.__nextBefore = b; }", before)
                sel = (f'.tree-row[data-feature="{fid}"] [data-act=include]' if view == "tree"
                       else f'g.feature[data-feature="{fid}"] .btn-include')
                w = time.perf_counter()
                pg.locator(sel).first.click()
                want = "open" if undo else "user-in"
                pg.wait_for_selector(f'[data-feature="{fid}"][data-status="{want}"]', timeout=60000)
                pg.wait_for_function("() => { const c = window.__clicks[window.__clicks.length - 1];"
                                     " return c && c.count !== null; }", timeout=60000)
                out.setdefault("click -> status drawn, Playwright wall (ms)", []).append((time.perf_counter() - w) * 1000)
                c = pg.evaluate("window.__clicks[window.__clicks.length - 1]")
                out.setdefault("click -> updated count, in page (ms)", []).append(c["count"])
            b.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
        if cache:
            shutil.rmtree(cache, ignore_errors=True)
    print(f"configurator: {args.model} ({args.width}x{args.height}, view {view}); "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"{'measure':48} {'n':>3} {'min':>8} {'median':>8} {'p95':>8} {'max':>8}")
    for k, xs in out.items():
        print(f"{k:48} {len(xs):3} {min(xs):8.0f} {statistics.median(xs):8.0f} {pct(xs, 95):8.0f} {max(xs):8.0f}")
    clicks = out.get("click -> updated count, in page (ms)", [])
    if clicks and pct(clicks, 95) > args.budget:
        print(f"p95 click -> count {pct(clicks, 95):.0f} ms is above the budget of {args.budget:g} ms")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
