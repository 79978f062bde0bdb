"""``abm render`` draws only what changes per frame: the pictures must stay those of a full draw.

The reference ("old path") is how ``abm render`` drew before: a full ``canvas.draw()`` of the
figure per animation frame (layout computed at the first frame, then kept), and
``savefig`` of a new figure per snapshot. Pixels are compared exactly (no tolerance).
"""

import io

import imageio.v3 as iio
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from analysis.blit import FrameBlitter
from analysis.render import (
    RunFigure,
    animation_frames,
    render_animation,
    render_snapshots,
    snapshot_times,
)
from analysis.run_folder import load_run, save_run
from models.beacon_explorer import BeaconExplorerModel
from models.hierarchy import HierarchyModel

MODELS = {
    "beacon-explorer": lambda: BeaconExplorerModel(
        n_robots=4, launch_period=4.0, time_limit=45.0, seed=3
    ),
    "hierarchy": lambda: HierarchyModel(seed=1, **HierarchyModel.QUICK),
}


@pytest.fixture(scope="module", params=sorted(MODELS))
def run(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp(request.param)
    save_run(MODELS[request.param]().run(), folder)
    return load_run(folder)


def _full_draw_frames(run, frames, dpi):
    """The frames as drawn before: the whole figure drawn for every frame."""
    figure = RunFigure(run)
    figure.fig.set_dpi(dpi)
    out = []
    for time in np.linspace(0.0, run.end_time, frames):
        figure.draw(float(time))
        figure.fig.canvas.draw()
        figure.freeze_layout()
        out.append(np.asarray(figure.fig.canvas.buffer_rgba())[..., :3].copy())
    return out


def _differing_pixels(a, b):
    assert a.shape == b.shape
    return int((a != b).any(axis=-1).sum())


def test_animation_frames_are_the_full_draws_pixels(run):
    new = list(animation_frames(run, 5, dpi=50))
    old = _full_draw_frames(run, 5, dpi=50)
    assert [_differing_pixels(a, b) for a, b in zip(new, old, strict=True)] == [0] * 5
    assert not np.array_equal(new[1], new[-1])  # the frames do show the run moving


def test_snapshots_are_what_savefig_writes_for_each(run, tmp_path):
    times = snapshot_times(run, 3)
    paths = render_snapshots(run, times, tmp_path, dpi=60)
    for time, path in zip(times, paths, strict=True):
        figure = RunFigure(run)
        figure.draw(time)
        saved = io.BytesIO()
        figure.fig.savefig(saved, dpi=60, format="png")
        assert _differing_pixels(iio.imread(path), iio.imread(saved.getvalue())) == 0, path.name


def test_the_gif_has_the_requested_frames_and_the_full_draws_bytes(run, tmp_path):
    path = render_animation(run, tmp_path / "a.gif", frames=4, fps=5, dpi=40, progress=False)
    assert iio.imread(path, index=None).shape[0] == 4
    old = tmp_path / "old.gif"
    iio.imwrite(old, np.stack(_full_draw_frames(run, 4, dpi=40)), duration=200.0, loop=0)
    assert path.read_bytes() == old.read_bytes()


def test_most_frames_redraw_only_what_changes(run):
    figure = RunFigure(run)
    figure.fig.set_dpi(40)
    for time in np.linspace(0.0, run.end_time, 6):
        figure.draw(float(time))
        figure.rgba()
    # the first frame lays the figure out; the second draws the background once more, without
    # the layout engine; a layer the run knows only at its end adds one at the last frame
    assert figure._blitter.background_draws <= 3


def test_the_blitter_refuses_overlapping_axes():
    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.1, 0.1, 0.6, 0.6))
    inset = fig.add_axes((0.4, 0.4, 0.5, 0.5))
    (line,) = ax.plot([0, 1], [0, 1])
    inset.plot([0, 1], [1, 0])
    with pytest.raises(ValueError, match="axes that do not overlap"):
        FrameBlitter(fig, lambda: [line]).render()
