"""view.html: self-contained, drawn by a real browser, and the player and the
picking show the program line they name.

The truth for positions, feeds, tools and program lines is the program text itself,
read here by a small reference reader (absolute G90 moves, modal X/Y/Z/F, T.. M6); tool
sizes come from the example's job file; the page is rendered by Debian's chromium.
"""

from __future__ import annotations

import base64
import json
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.demo import example_jobs
from millpath.cli.main import cli

EXAMPLE = "features-pockets"          # three tools, three operations, ~1300 moves
BACKGROUND = (0xEE, 0xF0, 0xF3)
HIDE_OVERLAYS = "#panel, #labels, #selection, #player { display: none !important; }"


# --- reference reader of the posted program ------------------------------------------------

WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def reference_states(program: str):
    """Per 1-based line: (x, y, z) after the line, feed F in force, tool in the spindle,
    whether the line is a motion this reader can vouch for (G0-G3, not a canned cycle)
    and the motion mode in force (0, 1, 2, 3, 80-89)."""
    x = y = z = None
    feed = 0.0
    tool = 0
    pending = None
    motion_mode = None
    out = {}
    for n, raw in enumerate(program.splitlines(), start=1):
        code = re.sub(r"\([^)]*\)", "", raw.split(";", 1)[0]).upper()
        words = WORD.findall(code)
        gs = [float(v) for k, v in words if k == "G"]
        for g in gs:
            assert g not in (91.0, 92.0, 28.0, 30.0, 53.0), f"line {n}: the reader needs G90"
            if g in (0.0, 1.0, 2.0, 3.0, 80.0, 81.0, 82.0, 83.0, 73.0, 85.0, 89.0):
                motion_mode = g
        moved = False
        for k, v in words:
            if k == "X":
                x, moved = float(v), True
            elif k == "Y":
                y, moved = float(v), True
            elif k == "Z":
                z, moved = float(v), True
            elif k == "F":
                feed = float(v)
            elif k == "T":
                pending = int(float(v))
            elif k == "M" and float(v) == 6.0:
                tool = pending
        # a position this reader can vouch for: all three axes programmed since the start
        # (after a tool change the post rises in Z alone, from wherever the machine is)
        simple = moved and motion_mode in (0.0, 1.0, 2.0, 3.0) and None not in (x, y, z)
        out[n] = ((x, y, z), feed, tool, simple, motion_mode)
    return out


# --- fixtures ---------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def demo_run(tmp_path_factory):
    """``millpath demo -k features-pockets``: its output and folder."""
    out = tmp_path_factory.mktemp("demo")
    r = CliRunner().invoke(cli, ["demo", "-k", EXAMPLE, "-o", str(out)])
    assert r.exit_code == 0, r.output
    return r.output, out / EXAMPLE


@pytest.fixture(scope="module")
def job():
    path = next(j for j in example_jobs() if j.parent.name == EXAMPLE)
    return tomllib.loads(path.read_text())


def open_page(browser, html: Path, size=(1280, 800)):
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    log = {"console": [], "errors": [], "requests": []}
    page.on("console", lambda m: log["console"].append((m.type, m.text)))
    page.on("pageerror", lambda e: log["errors"].append(str(e)))
    page.on("request", lambda r: log["requests"].append(r.url))
    page.goto(html.resolve().as_uri())
    page.wait_for_function("window.millpathViewer && window.millpathViewer.ready",
                           timeout=120_000)
    return page, log


def screenshot(page, path: Path) -> np.ndarray:
    import matplotlib.image as mpimg
    page.evaluate("window.millpathViewer.nextFrame()")
    page.wait_for_timeout(100)
    page.screenshot(path=str(path))
    return (mpimg.imread(str(path))[:, :, :3] * 255).round().astype(int)


def off_background(img: np.ndarray, tol: int = 12) -> np.ndarray:
    return np.abs(img - np.array(BACKGROUND)).max(axis=2) > tol


def page_data(html: Path) -> dict:
    text = html.read_text()
    m = re.search(r'<script type="application/json" id="millpath-data">(.*?)</script>', text, re.S)
    return json.loads(m.group(1))


# --- the page is self-contained ---------------------------------------------------------------

def test_demo_prints_where_each_view_is(demo_run):
    output, folder = demo_run
    view = (folder / "view.html").resolve()
    assert view.is_file()
    assert f"{EXAMPLE}: {view}" in output.replace("\n", "")


def test_view_html_references_no_network(demo_run):
    _, folder = demo_run
    html = folder / "view.html"
    text = html.read_text()
    low = text.lower()
    assert "http://" not in low and "https://" not in low
    for pattern in (r"<link\b", r"\ssrc\s*=", r"\shref\s*=", r"url\(", r"@import", r"<iframe"):
        assert not re.search(pattern, low), pattern
    imap = json.loads(re.search(r'<script type="importmap">(.*?)</script>', text, re.S).group(1))
    assert set(imap["imports"]) == {"three", "three/core", "three/addons/OrbitControls"}
    allowed = {"http://www.w3.org/1999/xhtml",            # XHTML namespace (createElementNS)
               "https://jcgt.org/published/0007/04/01/"}   # citation inside a GLSL comment
    for name, url in imap["imports"].items():
        assert url.startswith("data:text/javascript;base64,"), name
        js = base64.b64decode(url.split(",", 1)[1]).decode()
        found = set(re.findall(r"https?://[^\s\"'`)\\]+", js))
        assert found <= allowed, (name, found - allowed)
        assert not re.search(r"""\bimport\s*\(?\s*["'](?!three)""", js), name
    # nor does the scene data once decoded (the JSON block writes "/" as "\/")
    data = page_data(html)
    strings = json.dumps([data["title"], data["program"], data["operations"], data["tools"]])
    assert not re.search(r"https?:", strings.lower())


# --- the page in a browser --------------------------------------------------------------------

def test_page_draws_toolpath_and_stock_without_errors(demo_run, browser, tmp_path):
    _, folder = demo_run
    page, log = open_page(browser, folder / "view.html")
    try:
        assert log["errors"] == []
        assert [m for m in log["console"] if m[0] == "error"] == []
        assert all(u.startswith(("file:", "data:")) for u in log["requests"]), log["requests"]
        full = screenshot(page, tmp_path / "full.png")
        page.add_style_tag(content=HIDE_OVERLAYS)
        # the tool path alone
        page.evaluate("""() => { for (const id of ['show-surface', 'show-box', 'show-tool',
                              'show-markers']) document.getElementById(id).click(); }""")
        path_img = screenshot(page, tmp_path / "path.png")
        path_only = off_background(path_img)
        # coloured by feed instead of by operation: the same pixels, other colours
        page.evaluate("() => document.querySelector('input[name=colour][value=feed]').click()")
        feed_img = screenshot(page, tmp_path / "path-feed.png")
        page.evaluate("() => document.querySelector('input[name=colour][value=operation]')"
                      ".click()")
        # every operation hidden in the operations list: no tool path left
        page.evaluate("() => document.querySelectorAll('#ops input').forEach(b => b.click())")
        ops_hidden = off_background(screenshot(page, tmp_path / "ops-hidden.png"))
        page.evaluate("() => document.querySelectorAll('#ops input').forEach(b => b.click())")
        # the stock alone
        page.evaluate("""() => { for (const id of ['show-surface', 'show-feeds', 'show-rapids'])
                              document.getElementById(id).click(); }""")
        stock_only = off_background(screenshot(page, tmp_path / "stock.png"))
        # nothing
        page.evaluate("() => document.getElementById('show-surface').click()")
        nothing = off_background(screenshot(page, tmp_path / "nothing.png"))
        page.evaluate("() => document.getElementById('show-surface').click()")
        assert not log["errors"] and not [m for m in log["console"] if m[0] == "error"]
    finally:
        page.close()
    h, w = nothing.shape
    assert nothing.sum() == 0
    assert path_only.sum() > 2000                      # lines: a few thousand pixels
    assert ops_hidden.sum() == 0
    changed = np.abs(feed_img - path_img).max(axis=2) > 30
    assert changed[path_only].mean() > 0.3 and not changed[~off_background(feed_img)
                                                           & ~path_only].any()
    assert stock_only.sum() > 0.15 * h * w             # the block fills a good part
    assert off_background(full).sum() > stock_only.sum()
    # the tool path is drawn where the stock is (same camera): mostly inside its picture
    ys, xs = np.nonzero(stock_only)
    inside = path_only[ys.min():ys.max() + 1, xs.min():xs.max() + 1].sum()
    assert inside > 0.8 * path_only.sum()


def test_slider_puts_the_tool_at_the_move_it_names(demo_run, browser, job):
    _, folder = demo_run
    program = (folder / "program.ngc").read_text()
    lines = program.splitlines()
    ref = reference_states(program)
    tools = {t["number"]: t for t in job["tools"]}
    page, log = open_page(browser, folder / "view.html")
    try:
        moves = page.evaluate("window.millpathViewer.moves")
        assert moves > 1000
        rng = np.random.default_rng(22)
        picks = sorted({0, moves - 1, *rng.integers(0, moves, 25).tolist()})
        checked = 0
        tools_seen = set()
        for k in picks:
            page.locator("#slider").fill(str(k))
            assert page.evaluate("window.millpathViewer.move") == k
            assert page.locator("#move-no").inner_text() == f"{k + 1} / {moves}"
            line = int(page.locator("#line-no").inner_text())
            assert page.locator("#line-text").inner_text().strip() == lines[line - 1].strip()
            pos, feed, tool, simple, _ = ref[line]
            assert page.evaluate("window.millpathViewer.shownTool") == tool
            if not simple:
                continue
            tip = page.evaluate("window.millpathViewer.toolTip()")
            assert np.allclose(tip, pos, atol=1e-4), (k, line, lines[line - 1], tip, pos)
            checked += 1
            # the tool drawn is the job's tool: cutter D/2 wide and flute_length tall,
            # the holder stack on top up to stickout + holder lengths
            box = page.evaluate("window.millpathViewer.toolBox()")
            t = tools[tool]
            (c0, c1), (a0, a1) = box["cutter"], box["all"]
            assert c1[0] == pytest.approx(t["diameter"] / 2, abs=1e-3)
            assert c0[2] == pytest.approx(0.0, abs=1e-6)
            assert c1[2] == pytest.approx(t["flute_length"], abs=1e-3)
            top = t["stickout"] + sum(l for _, l in t["holder"])
            assert a1[2] == pytest.approx(top, abs=1e-3)
            widest = max([t["diameter"]] + [d for d, _ in t["holder"]]) / 2
            assert a1[0] == pytest.approx(widest, abs=1e-3)
            tools_seen.add(tool)
        assert checked >= 20
        assert len(tools_seen) >= 2
        # Play runs the program from the start, move by move, with the tool following
        page.locator("#slider").fill("0")
        page.select_option("#speed", "50")
        page.locator("#play").click()
        page.wait_for_function("window.millpathViewer.move >= 5", timeout=60_000)
        page.locator("#play").click()
        k = page.evaluate("window.millpathViewer.move")
        assert 5 <= k < moves - 1
        page.wait_for_timeout(300)
        assert page.evaluate("window.millpathViewer.move") == k           # paused
        line = int(page.locator("#line-no").inner_text())
        assert page.evaluate(f"window.millpathViewer.motionLine({k})") == line
        pos, _, _, simple, _ = ref[line]
        if simple:
            assert np.allclose(page.evaluate("window.millpathViewer.toolTip()"), pos, atol=1e-4)
        assert not log["errors"] and not [m for m in log["console"] if m[0] == "error"]
    finally:
        page.close()


def test_clicking_a_move_selects_it_and_shows_line_and_feed(demo_run, browser):
    _, folder = demo_run
    program = (folder / "program.ngc").read_text()
    lines = program.splitlines()
    ref = reference_states(program)
    page, log = open_page(browser, folder / "view.html")
    try:
        page.add_style_tag(content="#panel { display: none !important; }")
        page.evaluate("() => { document.getElementById('show-rapids').click();"
                      " window.millpathViewer.fit('top'); }")
        page.evaluate("window.millpathViewer.nextFrame()")
        # a long straight feed move whose middle no other feed move at its height or
        # above passes near (in XY): from the top, the click can only be on it
        feeds = []
        prev = None
        for n in range(1, len(lines) + 1):
            pos, feed, tool, simple, mode = ref[n]
            if simple and mode == 1.0 and prev is not None and None not in pos + prev:
                feeds.append((n, np.array(prev), np.array(pos)))
            if None not in pos:
                prev = pos
        a = np.array([s[1][:2] for s in feeds])
        b = np.array([s[2][:2] for s in feeds])
        ztop = np.array([max(s[1][2], s[2][2]) for s in feeds])
        zlow = np.array([min(s[1][2], s[2][2]) for s in feeds])
        length = np.linalg.norm(b - a, axis=1)
        target = None
        for i in np.argsort(-length)[:40]:
            mid = (a[i] + b[i]) / 2
            d = a - mid
            ab = b - a
            t = np.clip((d * -ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-12), 0, 1)
            dist = np.linalg.norm(a + ab * t[:, None] - mid, axis=1)
            dist[i] = np.inf
            dist[ztop < zlow[i] - 1e-6] = np.inf          # below it: hidden behind it
            if dist.min() > 2.0:
                target = feeds[i]
                break
        assert target is not None
        line = target[0]
        k = page.evaluate(f"""() => {{ const v = window.millpathViewer;
            for (let k = 0; k < v.moves; k++) if (v.motionLine(k) === {line}) return k;
            return -1; }}""")
        assert k >= 0
        x, y = page.evaluate(f"window.millpathViewer.screenOf({k})")
        page.mouse.click(x, y)
        assert page.evaluate("window.millpathViewer.selected") == k, (
            x, y, line, lines[line - 1], page.evaluate(f"window.millpathViewer.pickAt({x}, {y})"),
            page.evaluate(f"document.elementFromPoint({x}, {y}).id"))
        assert page.locator("#selection").is_visible()
        assert int(page.locator("#sel-line").inner_text()) == line
        assert page.locator("#sel-text").inner_text().strip() == lines[line - 1].strip()
        feed = ref[line][1]
        info = page.locator("#sel-info").inner_text()
        got = float(re.search(r"F ([0-9.eE+-]+)", info).group(1))
        assert got == pytest.approx(feed, rel=1e-6)
        assert not log["errors"] and not [m for m in log["console"] if m[0] == "error"]
    finally:
        page.close()


def test_a_bar_stock_is_drawn_as_its_circles(browser, tmp_path):
    """Cylindrical stock: the stock outline is the bar (two circles), drawn
    without errors; seen from above it is round: the outline's pixels lie on a ring."""
    from millpath.interpret import interpret
    from millpath.model import Stock
    from millpath.model.tool import Tool
    from millpath.report.viewer.scene import write_view
    from millpath.simulate import simulate_motions
    program = ("G21 G90 G17\nT1 M6\nG43 H1\nS1000 M3\nG0 X-5 Y10 Z5\nG1 Z-1 F100\n"
               "G1 X25 F300\nG0 Z5\nM2\n")
    tools = {1: Tool(1, "flat", 4.0, flute_length=20, stickout=30)}
    stock = Stock.from_cylinder(10.0, 10.0, 8.0, -5.0, 0.0)
    motions = interpret(program, tools, machine_units="mm")
    sim = simulate_motions(motions, tools, stock, resolution=0.1)
    html = write_view(tmp_path / "bar.html", program=program, motions=motions, tools=tools,
                      stock=stock, units="mm", sim=sim)
    page, log = open_page(browser, html, size=(800, 800))
    try:
        page.add_style_tag(content=HIDE_OVERLAYS)
        page.evaluate("""() => { for (const id of ['show-surface', 'show-feeds', 'show-rapids',
                              'show-tool', 'show-markers']) document.getElementById(id).click(); }""")
        page.evaluate("() => document.getElementById('view-top').click()")
        rgb = screenshot(page, tmp_path / "bar.png")
        img = rgb.max(axis=2) < 150          # the stock's dark grey lines, not the axes
        assert not log["errors"] and not [m for m in log["console"] if m[0] == "error"]
    finally:
        page.close()
    assert img.sum() > 200
    ys, xs = np.nonzero(img)
    d = np.hypot(xs - xs.mean(), ys - ys.mean())
    assert d.max() / d.min() < 1.15           # rings (a square outline gives 1.41)


def test_page_shows_the_proofs_figures(demo_run, browser):
    """The panel's max gouge and max left are report.json's exact figures, labelled as
    exact; the stock model's own (cell-bound) figures appear only labelled as such."""
    _, folder = demo_run
    ver = json.loads((folder / "report.json").read_text())["verification"]
    data = page_data(folder / "view.html")
    assert data["exact"]["max_gouge"] == pytest.approx(ver["max_gouge"], abs=1e-6)
    assert data["exact"]["max_left"] == pytest.approx(ver["max_left"], abs=1e-6)
    page, log = open_page(browser, folder / "view.html")
    try:
        rows = dict(zip(page.locator("#summary th").all_inner_texts(),
                        page.locator("#summary td").all_inner_texts()))
    finally:
        page.close()
    for key in ("max gouge", "max left"):
        value, label = rows[key].split(" ", 1)
        want = ver[key.replace(" ", "_")]
        assert float(value) == pytest.approx(want, rel=1e-3, abs=1e-6)
        assert "exact" in label
