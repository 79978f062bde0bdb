"""`abm viz` in a real browser: the page loads offline and draws the arena and the robots.

Starts `abm viz beacon-explorer` on a free localhost port, loads it in headless Chromium
(Debian's `chromium`, driven by playwright without any browser download), and checks the pixels
of the space image: walls, the base beacon and, after a few Step clicks, a flying explorer.
Skips (with the reason) when chromium, playwright, the viz extra or Solara's offline browser
files are missing.
"""

import io
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("solara", reason="the viz extra is not installed (pip install -e '.[viz]')")
sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
Image = pytest.importorskip("PIL.Image")

from abm.draw import STATE_COLOURS  # noqa: E402
from abm.viz.page import SERIES_COLOUR  # noqa: E402
from abm.viz.scene import WALL_COLOUR  # noqa: E402

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ROOT = Path(__file__).resolve().parents[1]


def _cache_filled() -> bool:
    import solara.server.settings as settings

    return any(Path(settings.assets.proxy_cache_dir).glob("@widgetti/solara-vuetify-app@*"))


pytestmark = [
    pytest.mark.skipif(
        not Path(CHROMIUM).exists(), reason="chromium is missing (apt-get install -y chromium)"
    ),
    pytest.mark.skipif(
        not _cache_filled(),
        reason="Solara's browser files are missing: sh scripts/solara_assets.sh",
    ),
    pytest.mark.timeout(150),
]


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


@pytest.fixture(scope="module")
def viz_url():
    port = _free_port()
    command = [
        sys.executable, "-c", "import sys; from analysis.cli import main; sys.exit(main())",
        "viz", "beacon-explorer", "--port", str(port), "--host", "127.0.0.1",
    ]  # fmt: skip
    process = subprocess.Popen(
        command,
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    lines = []
    try:
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline:
            line = process.stdout.readline()
            if not line and process.poll() is not None:
                break
            lines.append(line)
            if line.startswith("serving the beacon-explorer page at http://"):
                break
        else:
            pytest.fail("abm viz did not start in 90 s:\n" + "".join(lines))
        assert lines and lines[-1].startswith("serving"), "".join(lines)
        url = lines[-1].split(" at ", 1)[1].strip()
        assert url == f"http://127.0.0.1:{port}/"
        yield url
    finally:
        # End the verb's process group (the verb and the Solara server it started).
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGINT)
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()


def _pixels_near(image: np.ndarray, colour: str, tol: int = 30) -> int:
    rgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(image[..., :3].astype(int) - rgb).max(axis=-1) <= tol).sum())


def _space_image(page) -> np.ndarray:
    png = page.locator("img").first.screenshot()
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def test_page_draws_arena_robots_and_plots(viz_url, tmp_path):
    problems = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=CHROMIUM,
            args=["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"],
        )
        try:
            page = browser.new_page(viewport={"width": 1500, "height": 1000})
            page.on("pageerror", lambda exc: problems.append(str(exc)))
            page.goto(viz_url)
            # Solara builds the page over a websocket: wait for both figures (space, plots).
            page.wait_for_function(
                "document.querySelectorAll('img').length >= 2 && "
                "[...document.querySelectorAll('img')]"
                ".every(i => i.complete && i.naturalWidth > 200)",
                timeout=90_000,
            )
            page.screenshot(path=str(tmp_path / "viz_start.png"), full_page=True)
            start = _space_image(page)
            assert start.shape[0] > 300 and start.shape[1] > 300
            walls = _pixels_near(start, WALL_COLOUR, tol=12)
            assert walls > 0.05 * start.shape[0] * start.shape[1], "no arena walls drawn"
            assert _pixels_near(start, STATE_COLOURS["beacon"]) > 20, "base beacon not drawn"
            assert _pixels_near(start, STATE_COLOURS["ground"], tol=12) > 20, "ground robots"
            assert page.get_by_text("launch period t (s)").count() == 1, "sliders missing"

            step = page.get_by_role("button", name="Step")
            for _ in range(9):  # explorer 1 takes off at t = 6 s (launch period 6 s)
                step.click()
                page.wait_for_timeout(250)
            page.wait_for_function("document.body.innerText.includes('Time: 9')", timeout=30_000)
            page.wait_for_timeout(1500)
            page.screenshot(path=str(tmp_path / "viz_after_steps.png"), full_page=True)
            after = _space_image(page)
            assert _pixels_near(after, STATE_COLOURS["explorer"]) > 20, "no explorer drawn"
            plots = page.locator("img").nth(1).screenshot()
            plots = np.asarray(Image.open(io.BytesIO(plots)).convert("RGB"))
            assert _pixels_near(plots, SERIES_COLOUR) > 100, "coverage/energy curves not drawn"
            assert _pixels_near(plots, STATE_COLOURS["ground"], tol=12) > 100, "no count curves"
        finally:
            browser.close()
    assert not problems, problems
