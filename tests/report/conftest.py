"""Headless Chromium for the view.html tests: Debian's ``chromium`` (software WebGL via
SwiftShader) driven by Playwright. Skips with a reason on a user's machine without it,
fails under CI=true."""

from __future__ import annotations

import os
import shutil

import pytest

CHROMIUM_FLAGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader",
                  "--enable-unsafe-swiftshader", "--disable-background-networking",
                  "--disable-component-update", "--no-first-run"]


def _missing(msg: str):
    if os.environ.get("CI") == "true":
        pytest.fail(msg)
    pytest.skip(msg)


@pytest.fixture(scope="session")
def chromium() -> str:
    """Path of Debian's chromium."""
    exe = shutil.which("chromium") or ("/usr/bin/chromium"
                                       if os.path.exists("/usr/bin/chromium") else None)
    if exe is None:
        _missing("chromium is not installed: apt-get install -y chromium")
    return exe


@pytest.fixture(scope="session")
def browser(chromium):
    """A Playwright Browser on that chromium (never a downloaded one)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _missing("playwright is not installed: pip install 'millpath[test]'")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium, args=CHROMIUM_FLAGS, headless=True)
        yield b
        b.close()
