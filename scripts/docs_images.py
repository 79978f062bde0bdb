"""Regenerate the README's pictures in docs/images/ with the real command line.

Runs the commands the README's tour shows (`abm run`, `abm render`, `abm sweep` + `abm report`,
`abm fit`, `abm viz`) into out/docs-images/, then shrinks what they wrote to small PNGs and a GIF.
The report and the live page are photographed in Debian's chromium through playwright (the viz
extra: `make viz-setup`); without them those two pictures are left as they are.

    .venv/bin/python scripts/docs_images.py
"""

import base64
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

from PIL import Image, ImageSequence

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "out" / "docs-images"
IMAGES = ROOT / "docs" / "images"
#: The `abm` command of the interpreter running this script (the project's .venv).
ABM = [str(Path(sys.executable).parent / "abm")]
CHROMIUM = "/usr/bin/chromium"
PORT = 8791


def abm(*args: str) -> None:
    """Run one `abm` command as the README shows it, failing loudly."""
    print("abm", *args, flush=True)
    subprocess.run([*ABM, *args], cwd=ROOT, check=True)


def shrink(source: Path, target: Path, width: int, crop: tuple | None = None) -> None:
    """Save ``source`` as a small palette PNG ``width`` pixels wide."""
    image = Image.open(source).convert("RGB")
    if crop:
        image = image.crop(crop)
    height = round(image.height * width / image.width)
    small = image.resize((width, height), Image.LANCZOS)
    small.quantize(colors=128, method=Image.MEDIANCUT).save(target, optimize=True)
    print("wrote", target.relative_to(ROOT))


def shrink_gif(source: Path, target: Path, width: int) -> None:
    """Every other frame of ``source``, ``width`` pixels wide, on one shared 64-colour palette."""
    frames = [f.convert("RGB") for f in ImageSequence.Iterator(Image.open(source))][::2]
    frames = [f.resize((width, round(f.height * width / f.width)), Image.LANCZOS) for f in frames]
    sample = Image.new("RGB", (width, frames[0].height * 3))
    for i, k in enumerate((0, len(frames) // 2, -1)):
        sample.paste(frames[k], (0, i * frames[0].height))
    palette = sample.quantize(colors=64, method=Image.MEDIANCUT)
    small = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    small[0].save(target, save_all=True, append_images=small[1:], duration=250, loop=0)
    print("wrote", target.relative_to(ROOT))


def photograph(url: str, target: Path, size: tuple[int, int], play_seconds: float = 0) -> bool:
    """Screenshot ``url`` in headless chromium (pressing ▶ first for ``play_seconds``)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        print("playwright is not installed (make viz-setup): left", target.name, "as it is")
        return False
    if not Path(CHROMIUM).exists():
        print("no", CHROMIUM, "(apt-get install -y chromium): left", target.name, "as it is")
        return False
    args = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=args)
        page = browser.new_page(viewport={"width": size[0], "height": size[1]})
        page.goto(url)
        page.wait_for_timeout(12000 if play_seconds else 800)
        if play_seconds:
            page.get_by_role("button", name="▶").click()
            page.wait_for_timeout(int(play_seconds * 1000))
        page.screenshot(path=str(target))
        browser.close()
    return True


def main() -> None:
    """Run the tour's commands and refresh every picture of the README."""
    shutil.rmtree(OUT, ignore_errors=True)
    OUT.mkdir(parents=True)
    run = OUT / "run"
    abm(
        "run", "beacon-explorer", "--world", "corridor", "--complexity", "high",
        "--launch-period", "6", "--seed", "1", "--out", str(run), "--no-progress",
    )  # fmt: skip
    abm("render", str(run), "--snapshots", "2", "--frames", "30")
    shrink(run / "final.png", IMAGES / "run.png", 560)
    shrink_gif(run / "render" / "run.gif", IMAGES / "render.gif", 560)

    sweep = OUT / "corridor-try"
    abm("sweep", "experiments/corridor.toml", "--replications", "5", "--out", str(sweep))
    abm("report", str(sweep))
    shot = OUT / "report.png"
    if photograph((sweep / "report.html").as_uri(), shot, (1100, 900)):
        shrink(shot, IMAGES / "report.png", 760, crop=(0, 0, 1100, 720))

    fit = OUT / "fit"
    abm(
        "fit",
        "beacon-explorer",
        "--grid",
        "launch_period=6,12,24",
        "--runs",
        "2",
        "--out",
        str(fit),
    )
    html = (fit / "fit_report.html").read_text(encoding="utf-8")
    first = re.search(r'<img alt="launch_period=6[^"]*" src="data:image/png;base64,([^"]+)"', html)
    curve = OUT / "fit.png"
    curve.write_bytes(base64.b64decode(first.group(1)))
    shrink(curve, IMAGES / "fit.png", 560)

    server = subprocess.Popen([*ABM, "viz", "beacon-explorer", "--port", str(PORT)], cwd=ROOT)
    try:
        time.sleep(20)
        shot = OUT / "viz.png"
        if photograph(f"http://localhost:{PORT}/", shot, (1280, 720), play_seconds=45):
            shrink(shot, IMAGES / "viz.png", 760, crop=(0, 0, 1280, 640))
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    main()
