"""Make the documentation's pictures (run from the checkout's root, after the demo
command): each operation page's tool path from its example's ``preview.png``, and the
README's first job: its ``deviation.png`` and a screenshot of its ``view.html`` in
headless Chromium (Playwright on Debian's chromium, as the viewer tests use).

    .venv/bin/python docs/pictures.py
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from millpath.pipeline import run_job

ROOT = Path(__file__).resolve().parents[1]
IMG = ROOT / "docs" / "img"
#: operation page -> the example whose tool path it shows
PAGES = {"grid-pocket": "pocket-thesis", "die-cavity": "die-blanking",
         "features": "features-plate", "pocket": "pocket-dxf-adaptive",
         "profile": "profile-plate", "surface-rough": "surface-cavity",
         "surface-finish": "surface-mould"}
FIRST_JOB = "profile-plate"


def screenshot(html: Path, png: Path) -> None:
    from playwright.sync_api import sync_playwright
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=shutil.which("chromium"), args=[
            "--headless=new", "--no-sandbox", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader"])
        page = b.new_page(viewport={"width": 1100, "height": 700})
        page.goto(html.as_uri())
        page.wait_for_function("window.millpathViewer && window.millpathViewer.ready",
                               timeout=120000)
        page.wait_for_timeout(500)
        page.screenshot(path=str(png))
        b.close()


def main() -> None:
    IMG.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for example in sorted(set(PAGES.values())):
            out = Path(tmp) / example
            run_job(ROOT / "millpath" / "examples" / example / "job.toml", out)
            shutil.copy(out / "preview.png", IMG / f"{example}.png")
            if example == FIRST_JOB:
                shutil.copy(out / "deviation.png", IMG / "first-job-deviation.png")
                screenshot(out / "view.html", IMG / "first-job-view.png")
            print(example)


if __name__ == "__main__":
    main()
