"""The configurator in a real browser: headless Chromium (Debian's /usr/bin/chromium) driven by
Playwright, clicking through ``tvl-lsp ui`` as a user would.

Screenshots of failures go to ``.artifacts/ui/`` at the repository root (or ``$TVL_UI_ARTIFACTS``);
``TVL_UI_SHOTS=1`` keeps them for passing tests too.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
CHROMIUM = os.environ.get("TVL_CHROMIUM", "/usr/bin/chromium")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]
ARTIFACTS = Path(os.environ.get("TVL_UI_ARTIFACTS", REPO / ".artifacts" / "ui"))

if not os.path.exists(CHROMIUM) or not shutil.which(CHROMIUM):
    if os.environ.get("CI"):
        raise RuntimeError(f"CI needs Chromium at {CHROMIUM} (apt-get install chromium)")
    pytest.skip(f"no Chromium at {CHROMIUM} (apt-get install chromium)", allow_module_level=True)
sync_api = pytest.importorskip("playwright.sync_api")


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        yield b
        b.close()


@pytest.fixture()
def ws(tmp_path):
    d = tmp_path / "ws"
    shutil.copytree(REPO / "examples" / "ws", d)
    return d


@pytest.fixture()
def ui(ws):
    # the node hints of turtlerand (what each node publishes / subscribes): topics in the graph
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(ws), "--no-browser",
                             "--project", str(ws / "turtlerand_nodes.yaml")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    url = proc.stdout.readline().strip()
    assert url.startswith("http://127.0.0.1:"), proc.stderr.read()
    yield url
    proc.terminate()
    proc.wait(timeout=20)


@pytest.fixture()
def page(browser, request):
    ctx = browser.new_context(viewport={"width": 1440, "height": 900})
    pg = ctx.new_page()
    errors: list[str] = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.on("console", lambda m: m.type == "error" and errors.append(m.text))
    failed_before = request.session.testsfailed
    yield pg
    failed = request.session.testsfailed > failed_before
    if failed or os.environ.get("TVL_UI_SHOTS"):
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        shot = ARTIFACTS / f"{request.node.name}.png"
        try:
            pg.screenshot(path=str(shot), full_page=True)
            print(f"screenshot: {shot}")
        except Exception as e:  # the page may be gone
            print(f"no screenshot: {e}")
    ctx.close()
    assert not errors, errors


def open_ui(page, url):
    page.goto(url)
    page.wait_for_selector("body[data-graph=ready]", timeout=30000)
    page.wait_for_selector("#remaining:not([data-remaining=''])", timeout=30000)
    page.wait_for_selector("body[data-problems=ready]", timeout=30000)


def feature(page, name):
    return page.locator(f'g.feature[data-feature="{name}"]')


def remaining(page):
    return page.locator("#remaining").get_attribute("data-remaining")


def positions(page):
    return page.evaluate("""() => Object.fromEntries([...document.querySelectorAll('g.element')]
        .map(g => [g.dataset.id, g.getAttribute('transform')]))""")


def click(page, name, what):
    page.locator(f'g.feature[data-feature="{name}"] .btn-{what}').click()


def wait_until(page, ok, timeout=15.0):
    """Poll ``ok()`` (the page's CSP refuses wait_for_function's string evaluation)."""
    import time
    end = time.monotonic() + timeout
    while not ok():
        assert time.monotonic() < end, "timed out"
        page.wait_for_timeout(50)


def wait_counts(page, n):
    page.wait_for_selector(f"#remaining[data-remaining='{n}']", timeout=30000)


def test_include_random(page, ui):
    open_ui(page, ui)
    assert remaining(page) == "4"
    assert page.locator("#total").text_content() == "4"
    assert feature(page, "Random").get_attribute("data-status") == "open"
    assert feature(page, "Turtlesim").get_attribute("data-status") == "implied-in"
    rnd = page.locator('g.element[data-id="node:/Random"]')
    assert rnd.get_attribute("data-status") == "possible"
    dash = "getComputedStyle(document.querySelector('g.element[data-id=\"node:/Random\"] .shape')).strokeDasharray"
    assert page.evaluate(dash) not in ("none", "")
    before = positions(page)
    assert len(before) >= 6

    click(page, "Random", "include")
    wait_counts(page, "2")
    assert feature(page, "Random").get_attribute("data-status") == "user-in"
    assert feature(page, "Vel").get_attribute("data-status") == "implied-in"     # propagated, shown apart
    assert feature(page, "Teleop").get_attribute("data-status") == "open"        # still open
    assert "in 1 (50 %)" in feature(page, "Teleop").locator("text.count").text_content()
    assert rnd.get_attribute("data-status") == "certain"
    assert page.evaluate(dash) in ("none", "")                                     # solid now
    assert positions(page) == before                                              # nothing moved
    # the user's decision and the implied one look different
    fill = "n => getComputedStyle(document.querySelector(`g.feature[data-feature='${n}'] rect.box`)).fill"
    assert page.evaluate(fill, "Random") != page.evaluate(fill, "Vel")

    # excluding Random hides its node and its parameter; still nothing moves
    click(page, "Random", "exclude")
    page.wait_for_selector("g.feature[data-feature='Random'][data-status='user-out']", timeout=15000)
    wait_counts(page, "2")
    page.wait_for_selector('g.element[data-id="node:/Random"][data-status="absent"]', timeout=15000)
    assert page.locator('g.element[data-id="param:/vel"]').get_attribute("data-status") == "absent"
    sync_api.expect(rnd).to_have_css("opacity", "0")
    assert positions(page) == before
    # undo: clicking your own decision again resets it
    click(page, "Random", "exclude")
    wait_counts(page, "4")
    assert feature(page, "Random").get_attribute("data-status") == "open"


def test_conflicting_exclusion_is_refused(page, ui):
    open_ui(page, ui)
    click(page, "Random", "include")
    wait_counts(page, "2")
    click(page, "Vel", "exclude")
    toast = page.locator(".toast.refusal")
    toast.wait_for(timeout=15000)
    text = toast.text_content()
    assert "Exclude Vel: refused" in text
    assert "include Random" in text and "Vel is mandatory in Random" in text
    assert feature(page, "Vel").get_attribute("data-status") == "implied-in"
    assert remaining(page) == "2"
    # the reason links to the model
    toast.locator("a.loc").first.click()
    modal = page.locator(".modal .excerpt")
    modal.wait_for(timeout=15000)
    assert "Vel" in modal.locator(".line.target").text_content()


def test_generate_the_current_product(page, ui, ws):
    open_ui(page, ui)
    page.locator("#generate").click()
    assert page.locator('[data-mode="current"]').is_disabled()
    page.keyboard.press("Escape")
    for name, what in (("Random", "include"), ("Teleop", "exclude"), ("Multiplexer", "exclude")):
        click(page, name, what)
        page.wait_for_selector(f"g.feature[data-feature='{name}'][data-status='user-{'in' if what == 'include' else 'out'}']",
                               timeout=15000)
    wait_counts(page, "1")
    page.wait_for_selector("body[data-complete=true]")
    page.locator("#generate").click()
    page.locator('[data-mode="current"]').click()
    done = page.locator(".generated")
    done.wait_for(timeout=30000)
    assert done.get_attribute("data-count") == "1"
    path = Path(done.locator("li[data-path]").first.get_attribute("data-path"))
    assert path.is_file() and ws in path.parents
    text = path.read_text()
    assert '<arg name="Random" value="true"/>' in text and '<arg name="Teleop" value="false"/>' in text
    assert '<include file="$(find turtlerand)/launch/generic.launch">' in text


def test_select_graph_element_shows_condition_and_source(page, ui):
    open_ui(page, ui)
    page.locator('g.element[data-id="node:/Random"]').click()
    d = page.locator("#details")
    assert d.locator('[data-field="condition"]').text_content() == "Random"
    assert d.locator('[data-field="location"]').text_content() == "src/turtlerand/launch/generic.launch:22:3"
    links = d.locator('[data-field="links"]').text_content()
    assert "publish /cmd_vel_low" in links and "read /vel" in links
    d.locator('[data-field="location"] a').click()
    page.locator(".modal .line.target").wait_for(timeout=15000)
    assert "random_controller" in page.locator(".modal .line.target").text_content()


def test_search_and_collapse(page, ui):
    open_ui(page, ui)
    page.keyboard.press("/")
    page.keyboard.type("vel")
    page.locator('#search-results li[data-feature="Vel"]').wait_for()
    page.keyboard.press("Enter")
    assert "highlight" in feature(page, "Vel").get_attribute("class")
    # collapsing a feature hides its subtree, showing how many children are hidden
    feature(page, "Turtlesim").locator("rect.box").click()
    assert feature(page, "Teleop").count() == 0
    assert "3" in feature(page, "Turtlesim").locator("text.more").text_content()
    feature(page, "Turtlesim").locator("rect.box").click()
    assert feature(page, "Teleop").count() == 1


def test_problems_follow_the_decisions(page, tmp_path):
    """A problem that only some products have disappears once the decisions rule it out."""
    ws = tmp_path / "bot"
    shutil.copytree(REPO / "tests" / "data" / "configurator" / "ws", ws)
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(ws), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        open_ui(page, proc.stdout.readline().strip())
        dup = page.locator('.problem[data-code="duplicate-node"]')
        assert dup.count() == 1 and dup.get_attribute("data-status") == "possible"
        page.locator('g.feature[data-feature="Sensors"] rect.box').click() if feature(page, "Camera").count() == 0 else None
        click(page, "Camera", "exclude")
        page.wait_for_selector("#problem-count[data-ruled-out='1']", timeout=15000)
        assert page.locator('.problem[data-code="duplicate-node"]').count() == 0
        page.locator("#show-ruled-out").check()
        assert page.locator('.problem.ruled-out[data-code="duplicate-node"]').count() == 1
    finally:
        proc.terminate()
        proc.wait(timeout=20)


COUNT_STATES = """
(() => {
  window.__countStates = [];
  new MutationObserver(() => {
    const s = document.body && document.body.dataset.counts;
    const last = window.__countStates[window.__countStates.length - 1];
    if (s && s !== last) {
      window.__countStates.push(s);
      const rem = document.getElementById('remaining');
      window.__countShown = window.__countShown || [];
      window.__countShown.push([s, rem ? rem.dataset.remaining : null,
        [...document.querySelectorAll('g.feature text.count, .tree-row .count')].map(t => t.textContent).slice(0, 5)]);
    }
  }).observe(document, {attributes: true, subtree: true, attributeFilter: ['data-counts']});
})();
"""


def test_counts_are_pending_until_the_model_is_compiled(page, tmp_path):
    """A model is compiled once, in the background (d4 in its own process): until it is ready the
    page shows the counts as pending (the diagram stays usable), then the exact counts appear."""
    from model_gen import generated_model
    ws = tmp_path / "ws"
    shutil.copytree(REPO / "examples" / "ws", ws)
    big = ws / "src" / "big" / "launch"
    big.mkdir(parents=True)
    (big / "big.tvl").write_text(generated_model(400))
    env = dict(os.environ, TVL_LSP_CACHE_DIR=str(tmp_path / "cache"))
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(ws), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        url = proc.stdout.readline().strip()
        page.add_init_script(COUNT_STATES)
        open_ui(page, url)
        # another model of the workspace: nothing compiled it yet
        page.locator("#model-picker").select_option(str(big / "big.tvl"))
        import time
        deadline = time.monotonic() + 120
        while page.evaluate("window.__countStates.filter(s => s === 'ready').length") < 2:
            assert time.monotonic() < deadline, page.evaluate("window.__countStates")
            page.wait_for_timeout(50)
        states = page.evaluate("window.__countStates")
        # the second model's states, after the first model's ready
        second = states[states.index("ready") + 1:]
        assert second == ["pending", "compiling", "ready"], states
        shown = page.evaluate("window.__countShown")
        compiling = [x for x in shown if x[0] == "compiling"]
        assert compiling and all(x[1] == "" for x in compiling)         # no count while compiling
        assert all(t in ("…", "") for x in compiling for t in x[2])      # features: pending marks
        from tvl_lsp.analysis.engine import ModelAnalysis
        from tvl_lsp.tvl import parse_model
        n = ModelAnalysis(parse_model((big / "big.tvl").read_text(), "big.tvl").model).count()
        assert remaining(page) == str(n)
        assert page.locator("#count-status").get_attribute("title").startswith("counted by d4")
        # 400 features: the tree is shown first; every row on screen has its count
        assert page.evaluate("document.body.dataset.view") == "tree"
        counted = page.locator(".tree-row .count").all_text_contents()
        assert counted and all("%" in t for t in counted), counted
        # a click after compilation: counts come back at once, never pending again
        fid = page.evaluate("""() => [...document.querySelectorAll('.tree-row[data-status=open]')]
            .map(g => g.dataset.feature).filter(f => f !== 'Root')[0]""")
        assert fid, "no open feature on screen"

        before = len(page.evaluate("window.__countStates"))
        page.locator(f'.tree-row[data-feature="{fid}"] [data-act=include]').click()
        page.wait_for_selector(f"#remaining:not([data-remaining='{n}'])", timeout=30000)
        page.wait_for_selector("body[data-counts=ready]", timeout=30000)
        assert "compiling" not in page.evaluate("window.__countStates")[before:]
        page.goto("about:blank")
    finally:
        proc.terminate()
        proc.wait(timeout=20)


# What the VS Code extension does for its webview (editors/vscode/src/configurator.ts), emulated
# in the page: requests posted by the UI are answered through the HTTP API here (in VS Code, by
# the language server's tvl-lsp.configurator command, tested in test_server_configurator.py).
FAKE_VSCODE = """
(() => {
  const token = new URLSearchParams(location.search).get('token');
  window.__posted = [];
  window.acquireVsCodeApi = () => ({
    postMessage: async (m) => {
      window.__posted.push(m);
      if (m.type !== 'request') return;
      const r = await fetch('api/' + m.op, {method: 'POST', headers: {'Content-Type': 'application/json',
        'X-TVL-Token': token}, body: JSON.stringify(m.params || {})});
      const body = await r.json();
      window.postMessage(r.ok ? {type: 'response', id: m.id, result: body}
                              : {type: 'response', id: m.id, error: body.error}, '*');
    },
  });
  document.addEventListener('DOMContentLoaded', () => {
    const meta = document.createElement('meta');
    meta.name = 'tvl-elk-worker';
    meta.content = 'static/elk-worker.js?token=' + token;
    document.head.append(meta);
  });
})();
"""


def test_webview_transport(browser, ui):
    """The page in a VS Code webview: requests and answers as messages, reveal asked of the host,
    the layout worker started from a blob, a refresh from the host re-reads the state."""
    ctx = browser.new_context(viewport={"width": 1200, "height": 800}, bypass_csp=True)
    try:
        pg = ctx.new_page()
        pg.add_init_script(FAKE_VSCODE)
        open_ui(pg, ui)
        assert remaining(pg) == "4"
        click(pg, "Random", "include")
        wait_counts(pg, "2")
        pg.locator('g.element[data-id="node:/Random"]').click()
        pg.locator('#details [data-field="location"] a').click()
        posted = pg.evaluate("window.__posted")
        assert [m["op"] for m in posted if m["type"] == "request"][:1] == ["model"]
        reveal = [m for m in posted if m["type"] == "reveal"]
        assert reveal and reveal[0]["location"]["line"] == 21 and reveal[0]["location"]["path"].endswith("generic.launch")
        assert pg.locator(".modal").count() == 0          # VS Code reveals it: no excerpt in the page
        # the palette changed the decisions: the host says refresh
        url = ui.split("?")[0]
        token = ui.split("token=")[1]
        import json, urllib.request
        req = urllib.request.Request(url + "api/decide", data=json.dumps({"feature": "Teleop", "value": False}).encode(),
                                     headers={"Content-Type": "application/json", "X-TVL-Token": token})
        urllib.request.urlopen(req).read()
        pg.evaluate("window.postMessage({type: 'refresh', reload: false}, '*')")
        pg.wait_for_selector("g.feature[data-feature='Teleop'][data-status='user-out']", timeout=15000)
        wait_counts(pg, "1")
    finally:
        ctx.close()


def test_a_flat_model_draws_its_first_children_and_more_on_demand(page, tmp_path):
    """A root with 130 children (industrial models converted from DIMACS look like this): 40 are
    drawn with "••• 90 more", a click on it draws the rest, a searched feature is drawn wherever
    it is, and a click on a drawn feature is answered with its count."""
    ws = tmp_path / "ws" / "src" / "flat" / "launch"
    ws.mkdir(parents=True)
    names = [f"Opt{i}" for i in range(130)]
    (ws / "flat.tvl").write_text("root Flat {\n  group [0..*] {\n" + ",\n".join(f"    opt {n}" for n in names)
                                 + "\n  }\n  Opt1 -> Opt2;\n}\n")
    (tmp_path / "ws" / ".catkin_workspace").write_text("")
    env = dict(os.environ, TVL_LSP_CACHE_DIR=str(tmp_path / "cache"))
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(tmp_path / "ws"), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        url = proc.stdout.readline().strip()
        page.goto(url)
        page.wait_for_selector("body[data-ready=diagram]", timeout=30000)
        page.wait_for_selector("#remaining:not([data-remaining=''])", timeout=60000)
        # 131 features: the tree is shown first (every child of the root a row); the diagram on demand
        assert page.evaluate("document.body.dataset.view") == "tree"
        assert page.locator('.tree-row[data-feature="Opt0"]').count() == 1
        page.locator(".segmented [data-view=diagram]").click()
        page.wait_for_selector("body[data-view=diagram]")
        assert page.locator("g.feature").count() == 41
        more = page.locator('g.feature[data-feature="Flat"] text.more')
        assert more.text_content() == "••• 90 more"
        assert feature(page, "Opt100").count() == 0
        more.click()
        wait_until(page, lambda: page.locator("g.feature").count() == 131)
        assert more.text_content() == ""
        page.locator("#collapse-all").click()
        wait_until(page, lambda: page.locator("g.feature").count() == 41)
        # a feature found by the search box is drawn although it is beyond the first 40
        page.locator("#search").fill("Opt117")
        page.locator("#search").press("Enter")
        page.wait_for_selector('g.feature[data-feature="Opt117"]', timeout=10000)
        assert page.locator("g.feature").count() == 42
        total = 2 ** 130 * 3 // 4
        assert remaining(page) == str(total)
        page.wait_for_timeout(400)  # the reveal's transition
        click(page, "Opt117", "include")
        wait_counts(page, str(total // 2))
        assert feature(page, "Opt117").get_attribute("data-status") == "user-in"
        page.screenshot(path=str(REPO / ".artifacts" / "ui" / "flat-model.png"))
    finally:
        # leave the page before the server stops: a poll in flight would otherwise end in
        # ERR_EMPTY_RESPONSE, which the page fixture counts as a console error
        page.goto("about:blank")
        proc.terminate()
        proc.wait(timeout=20)


def test_a_wide_tree_shows_its_whole_first_level_readable(page, tmp_path):
    """A model as wide as the thesis's lizi (two groups, eleven leaves) in a half-screen panel:
    fitting it whole drew the names 4 px high.  The first view shows the root and its whole first
    level, fitted and readable (names >= 9 px), the deeper levels folded ("••• 4"); a click on a
    folded feature unfolds it, and fit / zoom work with buttons and keys."""
    ws = tmp_path / "ws" / "src" / "wide" / "launch"
    ws.mkdir(parents=True)
    left = [f"Sensor{i}" for i in range(4)]
    right = [f"Planner{i}" for i in range(7)]
    (ws / "wide.tvl").write_text(
        "root Wide {\n  group allOf { opt Hw, opt Navigation, opt Speech, opt State, opt Sim }\n}\n"
        "Hw { group someOf { " + ", ".join(left) + " } }\n"
        "Navigation { group someOf { " + ", ".join(right) + " } }\n")
    (tmp_path / "ws" / ".catkin_workspace").write_text("")
    env = dict(os.environ, TVL_LSP_CACHE_DIR=str(tmp_path / "cache"))
    proc = subprocess.Popen([sys.executable, "-m", "tvl_lsp", "ui", str(tmp_path / "ws"), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        page.goto(proc.stdout.readline().strip())
        page.wait_for_selector("body[data-ready=diagram]", timeout=30000)
        page.wait_for_selector("#remaining:not([data-remaining=''])", timeout=60000)
        assert page.evaluate("document.body.dataset.view") == "diagram"
        first = ["Wide", "Hw", "Navigation", "Speech", "State", "Sim"]
        assert sorted(page.evaluate("[...document.querySelectorAll('g.feature')].map(g => g.dataset.feature)")) == sorted(first)
        heights = page.evaluate("""() => [...document.querySelectorAll('g.feature text.name')]
            .map(t => t.getBoundingClientRect().height)""")
        assert min(heights) >= 9, heights
        for n in first:
            assert page.evaluate(VISIBLE, n), n
        assert "4" in feature(page, "Hw").locator("text.more").text_content()
        feature(page, "Navigation").locator("rect.box").click()
        page.wait_for_selector('g.feature[data-feature="Planner6"]')
        page.locator("#details h3").filter(has_text="Navigation").wait_for()
        # zoom in with the button, fit with the key: the whole of it in the panel again
        page.locator("#diagram .zoom-in").click()
        page.wait_for_timeout(300)
        page.locator("svg.diagram").focus()
        page.keyboard.press("f")
        # (the fit is a transition: its last frame comes late on a loaded machine)
        wait_until(page, lambda: all(page.evaluate(VISIBLE, n) for n in first + right))
    finally:
        page.goto("about:blank")
        proc.terminate()
        proc.wait(timeout=20)


VISIBLE = """n => { const g = document.querySelector(`g.feature[data-feature='${n}']`);
    if (!g) return false;
    const r = g.querySelector('.btn-include').getBoundingClientRect();
    const hit = document.elementFromPoint(r.x + r.width / 2, r.y + r.height / 2);
    return !!hit && g.contains(hit); }"""


def test_a_narrow_window_shows_one_pane_at_a_time(browser, ui):
    """In a window as narrow as a VS Code panel beside the editor, the features and the graph
    each take the full width, one at a time (switched in the header), with the details under
    them; nothing overflows the window and the first level is readable."""
    ctx = browser.new_context(viewport={"width": 560, "height": 800})
    try:
        pg = ctx.new_page()
        open_ui(pg, ui)
        assert pg.evaluate("document.documentElement.scrollWidth") <= 560
        box = pg.locator("#diagram").bounding_box()
        assert box["width"] >= 540 and box["height"] >= 250, box
        assert not pg.locator("#graph").is_visible()
        heights = pg.evaluate("[...document.querySelectorAll('g.feature text.name')].map(t => t.getBoundingClientRect().height)")
        assert min(heights) >= 9, heights
        click(pg, "Random", "include")
        wait_counts(pg, "2")
        assert "Random" in pg.locator("#details h3").text_content()
        pg.locator('.pane-switch [data-pane=graph]').click()
        assert pg.locator("#graph").is_visible() and not pg.locator("#diagram").is_visible()
        assert pg.locator("#graph").bounding_box()["width"] >= 540
        pg.locator('g.element[data-id="node:/Random"]').click()
        assert pg.locator('#details [data-field="condition"]').text_content() == "Random"
        main = pg.locator("main").bounding_box()
        assert main["y"] + main["height"] <= pg.locator("#bottom").bounding_box()["y"] + 1
    finally:
        ctx.close()
