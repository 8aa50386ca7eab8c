"""How fast view.html is written and opens: a bundled example run, then its page loaded
in headless Chromium (Debian's chromium, software WebGL through SwiftShader).

Figures: the CPU seconds millpath spends writing view.html inside ``millpath run``
(process time of :func:`millpath.report.viewer.write_view`), the page's size, and for
the page in Chromium: wall seconds from navigation to the first frame drawn (best of
``--repeat``) with the page's own phase timings, and the seconds the renderer's main
thread is busy (DevTools Performance metrics TaskDuration / ScriptDuration; SwiftShader's
drawing in the GPU process is not in them), side by side with an empty page, and the
time per frame while orbiting (``orbit_frame_ms``: ten frames, each drawn and read back). The machine's load average is printed:
SwiftShader draws on the CPU, so on a shared machine wall times grow with the load; a
browser with a GPU draws the surface far faster.

    python bench/viewer_load.py [--example surface-cavity] [--html PATH] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

FLAGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader",
         "--enable-unsafe-swiftshader", "--disable-background-networking",
         "--disable-component-update", "--no-first-run"]
CHROMIUM = "/usr/bin/chromium"


def run_example(name: str, out: Path) -> tuple[Path, float, float]:
    """Run the example; returns (view.html, CPU s of write_view, wall s of the run)."""
    import millpath.report.viewer as viewer
    from millpath.cli.demo import example_jobs
    from millpath.pipeline import run_job
    job = next(j for j in example_jobs() if j.parent.name == name)
    spent = []
    inner = viewer.write_view

    def timed(*a, **kw):
        t = time.process_time()
        try:
            return inner(*a, **kw)
        finally:
            spent.append(time.process_time() - t)
    viewer.write_view = timed
    try:
        t0 = time.perf_counter()
        run_job(job, out)
        wall = time.perf_counter() - t0
    finally:
        viewer.write_view = inner
    return out / "view.html", sum(spent), wall


def page_load(url: str, repeat: int) -> tuple[float, dict, dict]:
    """Best wall seconds from navigation to the first frame, the page's phase timings
    and the renderer's main-thread busy seconds (Chrome DevTools Performance metrics
    TaskDuration and ScriptDuration) of that load."""
    from playwright.sync_api import sync_playwright
    best, timings, busy = float("inf"), {}, {}
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS, headless=True)
        for _ in range(repeat):
            page = b.new_page(viewport={"width": 1280, "height": 800})
            cdp = page.context.new_cdp_session(page)
            cdp.send("Performance.enable")
            errors = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            t0 = time.perf_counter()
            page.goto(url)
            page.wait_for_function("window.millpathViewer && window.millpathViewer.ready",
                                   timeout=300_000)
            wall = time.perf_counter() - t0
            if errors:
                raise SystemExit(f"page errors: {errors}")
            if wall < best:
                best = wall
                timings = page.evaluate("window.millpathViewer.timings")
                m = {x["name"]: x["value"] for x in cdp.send("Performance.getMetrics")["metrics"]}
                busy = {k: round(m[k], 2) for k in ("TaskDuration", "ScriptDuration") if k in m}
                if page.evaluate("typeof window.millpathViewer.frameMs") == "function":
                    timings["orbit_frame_ms"] = round(
                        page.evaluate("window.millpathViewer.frameMs(10)"), 1)
            page.close()
        b.close()
    return best, timings, busy


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--example", default="surface-cavity")
    ap.add_argument("--html", type=Path, default=None, help="an existing view.html")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    if a.html is None:
        out = Path(tempfile.mkdtemp(prefix="viewer-bench-"))
        html, cpu, wall = run_example(a.example, out)
        print(f"{a.example}: millpath run {wall:.1f} s wall, of which write_view "
              f"{cpu:.2f} CPU s")
    else:
        html = a.html
    print(f"view.html: {html.stat().st_size / 1e6:.2f} MB")
    url = html.resolve().as_uri()
    with tempfile.TemporaryDirectory() as d:
        blank = Path(d) / "blank.html"
        blank.write_text("<!doctype html><title>blank</title><p>blank</p><script>"
                         "window.millpathViewer = {ready: true, timings: {}};</script>")
        bwall, _, bbusy = page_load(blank.as_uri(), 1)
    print(f"empty page: {bwall:.2f} s wall, renderer main thread busy {bbusy}")
    wall, timings, busy = page_load(url, a.repeat)
    print(f"view.html: open to first frame (best of {a.repeat}) {wall:.2f} s wall, renderer "
          f"main thread busy {busy} s")
    print(f"  phases (ms from the viewer script's start): {timings}")
    print(f"load average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
