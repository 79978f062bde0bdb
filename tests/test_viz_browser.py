"""`abm viz` in a real browser, for every model: the page loads offline and draws the arena
and the robots.

Starts `abm viz MODEL` on a free localhost port for each registered model and the tiny model of
the tests (whose page is the default one), loads it in headless Chromium (Debian's `chromium`,
driven by playwright without any browser download), takes a screenshot, and checks the pixels
of the space image: walls, and after a few Step clicks the robots in their declared colours.
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

from abm.registry import model_class, model_names  # noqa: E402
from abm.styles import resolve_styles  # noqa: E402
from abm.viz.page import SERIES_COLOUR  # noqa: E402
from abm.viz.scene import WALL_COLOUR  # noqa: E402

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ROOT = Path(__file__).resolve().parents[1]


def _cache_filled() -> bool:
    import solara.server.settings as settings

    return any(Path(settings.assets.proxy_cache_dir).glob("@widgetti/solara-vuetify-app@*"))


pytestmark = [
    pytest.mark.slow,  # a browser session per model (6-30 s each): the full tier, make test-all
    pytest.mark.skipif(
        not Path(CHROMIUM).exists(), reason="chromium is missing (apt-get install -y chromium)"
    ),
    pytest.mark.skipif(
        not _cache_filled(),
        reason="Solara's browser files are missing: sh scripts/solara_assets.sh",
    ),
    pytest.mark.timeout(200),
]

#: Per model: Step clicks, the model time then, the states whose robots must be drawn by then,
#: a slider label its page shows and the colours of its layers that must be drawn too. A
#: registered model missing here gets the generic checks (arena drawn, no page error, the clock
#: advances, "seed" slider).
CASES = {
    "beacon-explorer": (9, "9.0", ("beacon", "ground", "explorer"), "launch period t (s)", ()),
    "stigmergy": (2, "1.0", ("beacon",), "pheromone radius C_rb (m)", ()),
    "tiny": (8, "8.0", ("walking",), "launch_period (s)", ()),
    # the testbed's anchors land by 35 s (seed 1); then particle clouds and the GlobalMap
    "sugarmap": (45, "45.0", ("anchor", "exploring"), "particles per explorer", ("#E69F00",)),
    # two 10 s steps fly a few PSO transitions; the best swarm b_g is drawn in black
    "tangible-pso": (2, "20.0", ("free",), "required neighbours k", ("#000000",)),
    # 10 m room, W = S = 3: by 30 s the workers direct their scouts over the queen's known map
    "hierarchy": (3, "30.0", ("worker_directing",), "workers W", ("#009E73",)),
    # 200 birds on the periodic square, each drawn in the bird colour after two updates
    "flocking": (2, "2.0", ("flying",), "visual distance (m)", ()),
}


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


#: JavaScript: the "Time: ..." the page shows ('' before there is one).
SHOWN_TIME = "(document.body.innerText.match(/Time: \\S+/) || [''])[0]"


def _case(name: str) -> tuple:
    if name in CASES:
        return CASES[name]
    step = model_class(name).Params().step_duration
    return (2, f"{2 * step:.1f}", (), "seed", ())


@pytest.fixture(params=sorted({*model_names(), *CASES}))
def viz_url(request, tiny_package):
    name = request.param
    port = _free_port()
    command = [
        sys.executable, "-c", "import sys; from analysis.cli import main; sys.exit(main())",
        "viz", name, "--port", str(port), "--host", "127.0.0.1",
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
            if line.startswith(f"serving the {name} page at http://"):
                break
        else:
            pytest.fail("abm viz did not start in 90 s:\n" + "".join(lines))
        assert lines and lines[-1].startswith("serving"), "".join(lines)
        url = lines[-1].split(" at ", 1)[1].strip()
        assert url == f"http://127.0.0.1:{port}/"
        yield name, url
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


def _walls_drawn(image: np.ndarray) -> bool:
    return _pixels_near(image, WALL_COLOUR, tol=12) > 0.01 * image.shape[0] * image.shape[1]


def _settled_space_image(page, attempts: int = 20) -> np.ndarray:
    """The space figure once its arena is drawn: Solara may swap a first paint for the full
    figure after the images report complete (seen once in a full-suite run), so look again
    for up to 10 s before judging."""
    image = _space_image(page)
    for _ in range(attempts):
        if _walls_drawn(image):
            break
        page.wait_for_timeout(500)
        image = _space_image(page)
    return image


def test_page_draws_arena_robots_and_plots(viz_url, tmp_path):
    name, url = viz_url
    steps, time_text, states, slider, colours = _case(name)
    cls = model_class(name)
    styles = resolve_styles(cls.STATES, cls.STATE_STYLES)
    problems = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=CHROMIUM,
            args=["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"],
        )
        try:
            page = browser.new_page(viewport={"width": 1500, "height": 1000})
            page.on("pageerror", lambda exc: problems.append(str(exc)))
            page.goto(url)
            # Solara builds the page over a websocket: wait for both figures (space, plots).
            page.wait_for_function(
                "document.querySelectorAll('img').length >= 2 && "
                "[...document.querySelectorAll('img')]"
                ".every(i => i.complete && i.naturalWidth > 200)",
                timeout=90_000,
            )
            page.screenshot(path=str(tmp_path / f"viz_{name}_start.png"), full_page=True)
            if cls(seed=1).arena.free.all():  # a wall-free world (the periodic square)
                start = _space_image(page)
            else:
                start = _settled_space_image(page)
                assert _walls_drawn(start), "no arena walls drawn"
            assert start.shape[0] > 300 and start.shape[1] > 300
            assert page.get_by_text(slider).count() >= 1, "sliders missing"

            step = page.get_by_role("button", name="Step")
            # Each click once the page shows the step before it done: on a slow machine a
            # click sent while the server was still drawing the last step was lost.
            for _ in range(steps):
                shown = page.evaluate(SHOWN_TIME)
                step.click()
                page.wait_for_function(f"arg => ({SHOWN_TIME}) !== arg", arg=shown, timeout=30_000)
            page.wait_for_function(
                f"document.body.innerText.includes('Time: {time_text}')", timeout=30_000
            )
            page.wait_for_timeout(1500)
            page.screenshot(path=str(tmp_path / f"viz_{name}_after.png"), full_page=True)
            after = _space_image(page)
            for state in states:
                assert _pixels_near(after, styles[state].colour) > 20, f"no {state} robot drawn"
            for colour in colours:
                assert _pixels_near(after, colour, tol=20) > 20, f"no layer in {colour} drawn"
            plots = page.locator("img").nth(1).screenshot()
            plots = np.asarray(Image.open(io.BytesIO(plots)).convert("RGB"))
            first = styles[states[0] if states else cls.STATES[0]]
            assert _pixels_near(plots, first.colour) > 100, "no count curves"
            if cls(seed=1).coverage is not None:
                assert _pixels_near(plots, SERIES_COLOUR) > 100, "no coverage curve"
        finally:
            browser.close()
    assert not problems, problems
