"""`abm run`'s PNG is drawn by a child process started before the run (abm/png_process.py):
the same picture, byte for byte, as one drawn in the run's own process; the run's process never
loads matplotlib; and whatever goes wrong with the child (it cannot start, it dies, it cannot
draw the picture), the PNG is still drawn, or the drawing's own error raised, here.
"""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from abm import registry
from abm.draw import save_picture
from abm.png_process import PngProcess
from abm.scene import Picture, Scene, picture_of

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def picture() -> Picture:
    """A beacon/explorer run's picture: robots in several states, links, the covered area,
    the beacons' arrows and the base beacon's layer (everything a picture can hold)."""
    cls = registry.model_class("beacon-explorer")
    model = cls(seed=1, **dict(cls.QUICK)).run(until=20.0)
    drawn = picture_of(model, "a beacon/explorer run at 20 s")
    assert len(drawn.scene.links) and drawn.scene.arrows is not None and drawn.scene.layers
    return drawn


def test_the_child_draws_the_same_png_as_this_process(picture, tmp_path):
    with PngProcess() as drawer:
        by_child = drawer.save(picture, tmp_path / "child.png")
    here = save_picture(picture, tmp_path / "here.png")
    assert by_child.read_bytes() == here.read_bytes()


def test_abm_run_leaves_matplotlib_to_the_child(tmp_path):
    """In a fresh interpreter, a whole ``abm run`` writes its PNG without matplotlib ever
    being imported there: the child drew it (and the run took no time to load it)."""
    run = ["run", "flocking", "--time-limit", "5", "--out", str(tmp_path / "run")]
    probe = (
        f"import sys\nfrom analysis.cli import main\ncode = main({run!r})\n"
        "print(code, any(m.split('.')[0] == 'matplotlib' for m in sys.modules))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "0 False"
    assert f"wrote {tmp_path / 'run' / 'final.png'}" in done.stdout
    assert (tmp_path / "run" / "final.png").stat().st_size > 10_000


def test_a_child_that_cannot_start_leaves_the_drawing_to_this_process(
    picture, tmp_path, monkeypatch
):
    monkeypatch.setattr(sys, "executable", str(tmp_path / "no-such-python"))
    with PngProcess() as drawer:
        drawn = drawer.save(picture, tmp_path / "a.png")
    assert drawn.read_bytes() == save_picture(picture, tmp_path / "b.png").read_bytes()


def test_a_child_that_died_leaves_the_drawing_to_this_process(picture, tmp_path):
    with PngProcess() as drawer:
        drawer._child.kill()
        drawer._child.wait()
        drawn = drawer.save(picture, tmp_path / "a.png")
    assert drawn.read_bytes() == save_picture(picture, tmp_path / "b.png").read_bytes()


def test_a_picture_the_child_cannot_draw_raises_its_own_error_here(picture, tmp_path):
    unknown = np.array(["no such state"], dtype=object)
    wrong = Picture(picture.backdrop, Scene(0.0, np.zeros((1, 2)), unknown), "wrong")
    with PngProcess() as drawer, pytest.raises(ValueError, match="no such state"):
        drawer.save(wrong, tmp_path / "wrong.png")


def test_a_child_given_no_picture_is_stopped_with_the_command():
    with PngProcess() as drawer:
        child = drawer._child
        assert child.poll() is None  # waiting for a picture
    assert child.returncode is not None
