"""Saving a run and drawing it again from its files (analysis.run_folder, analysis.render)."""

import json
import shutil

import imageio.v3 as iio
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

from abm.errors import ConfigError
from abm.styles import Layer
from abm.viz.scene import WALL_COLOUR, view_of
from analysis.render import (
    RunFigure,
    RunReplay,
    render_animation,
    render_snapshots,
    snapshot_times,
)
from analysis.run_folder import RUN_FILES, RunFolderError, load_run, save_run
from models.beacon_explorer import BeaconExplorerModel
from models.flocking import FlockingModel
from models.hierarchy import HierarchyModel


@pytest.fixture(scope="module")
def model():
    return BeaconExplorerModel(n_robots=4, launch_period=4.0, time_limit=45.0, seed=3).run()


@pytest.fixture(scope="module")
def run_dir(model, tmp_path_factory):
    folder = tmp_path_factory.mktemp("run")
    written = save_run(model, folder)
    assert sorted(p.name for p in written) == sorted(RUN_FILES)
    return folder


def _pixels_near(image, colour, tol=12):
    rgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(image[..., :3].astype(int) - rgb).max(axis=-1) <= tol).sum())


def test_save_and_load_round_trip(model, run_dir):
    run = load_run(run_dir)
    assert np.array_equal(run.arena.free, model.arena.free)
    assert run.arena.resolution == model.arena.resolution
    assert run.states == model.STATES
    assert run.styles == model.state_styles
    assert run.end_time == pytest.approx(model.time)
    pd.testing.assert_frame_equal(run.positions, model.positions())
    assert run.summary["coverage_area"] == pytest.approx(model.summary()["coverage_area"])
    meta = json.loads((run_dir / "run.json").read_text())
    assert meta["model"] == "beacon-explorer"
    assert meta["target"] == "models.beacon_explorer.model:BeaconExplorerModel"
    assert meta["parameters"] == model.params.plain()
    assert meta["parameters"]["launch_period"] == 4.0
    assert meta["seed"] == 3
    assert meta["comm_range"] == 4.0


def test_replay_rebuilds_the_model_coverage_and_links(model, run_dir):
    run = load_run(run_dir)
    replay = RunReplay(run)
    final = replay.scene_at(run.end_time)
    assert np.array_equal(final.covered, model.coverage.covered)
    # Going back in time un-covers; coverage grows monotonically with time.
    early = replay.scene_at(0.0).covered.sum()
    assert 0 < early < final.covered.sum()
    times, percent = replay.coverage_history()
    assert np.all(np.diff(percent) > 0) and np.all(np.diff(times) > 0)
    assert percent[-1] == pytest.approx(100 * model.coverage.fraction)
    for t in (10.0, 25.0):  # the history and the scene agree at any time
        k = np.searchsorted(times, t, side="right") - 1
        shown = replay.scene_at(t).covered
        assert 100 * shown.sum() / model.coverage.free.sum() == pytest.approx(percent[k])
    # Links: the comm graph (range 4 m, line of sight) of the robots that were comm nodes.
    last = run.positions["time"].max()
    scene = replay.scene_at(last)
    lengths = np.hypot(*(scene.links[:, 0] - scene.links[:, 1]).T)
    assert np.all(lengths <= 4.0)
    sample = run.positions[run.positions["time"] == last]
    assert set(sample.loc[sample["comm"], "robot"]) == set(model.comms.graph)
    assert len(scene.links) == model.comms.graph.number_of_edges()


def test_snapshots_show_walls_and_robots(run_dir, tmp_path):
    run = load_run(run_dir)
    times = snapshot_times(run, 3)
    assert times[0] == 0.0 and times[-1] == pytest.approx(run.end_time)
    paths = render_snapshots(run, times, tmp_path)
    assert [p.name for p in paths] == [f"snapshot_{round(t):05d}s.png" for t in times]
    image = iio.imread(paths[-1])
    assert _pixels_near(image, WALL_COLOUR) > 0.05 * image.shape[0] * image.shape[1]
    beacon = load_run(run_dir).styles["beacon"].colour
    assert _pixels_near(image, beacon, tol=30) > 50


def test_gif_of_the_whole_run(run_dir, tmp_path):
    run = load_run(run_dir)
    path = render_animation(run, tmp_path / "anim.gif", frames=3, fps=4, dpi=40, progress=False)
    frames = iio.imread(path, index=None)
    assert frames.shape[0] == 3
    assert not np.array_equal(frames[0], frames[-1])


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not on PATH")
def test_mp4_when_ffmpeg_is_present(run_dir, tmp_path):
    path = render_animation(load_run(run_dir), tmp_path / "a.mp4", frames=3, dpi=40, progress=False)
    assert path.stat().st_size > 0


def test_mp4_without_ffmpeg_is_a_clear_error(run_dir, tmp_path, monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda _name: None)
    with pytest.raises(Exception, match="ffmpeg"):
        render_animation(load_run(run_dir), tmp_path / "a.mp4", frames=3, progress=False)


def test_bad_inputs_name_the_problem(run_dir, tmp_path):
    run = load_run(run_dir)
    with pytest.raises(ConfigError, match=r"times must lie within the run"):
        render_snapshots(run, [1e6], tmp_path)
    with pytest.raises(ConfigError, match=r"\.gif or \.mp4"):
        render_animation(run, tmp_path / "a.avi", progress=False)
    with pytest.raises(ConfigError, match="frames must be at least 2"):
        render_animation(run, tmp_path / "a.gif", frames=1, progress=False)
    with pytest.raises(ConfigError, match="at least 1"):
        snapshot_times(run, 0)


def test_missing_or_incomplete_run_folder(run_dir, tmp_path):
    with pytest.raises(RunFolderError, match="does not exist"):
        load_run(tmp_path / "nothing")
    partial = tmp_path / "partial"
    partial.mkdir()
    shutil.copy(run_dir / "events.parquet", partial)
    with pytest.raises(RunFolderError, match="lacks positions.parquet"):
        load_run(partial)


def test_the_legend_names_walls_only_where_the_arena_has_some(model):
    def labels(m):
        fig, ax = plt.subplots()
        try:
            return [h.get_label() for h in view_of(m, ax).legend_handles()]
        finally:
            plt.close(fig)

    assert "wall" in labels(model)
    assert "wall" not in labels(FlockingModel(seed=1))  # a periodic square without walls


#: The base beacon's star (models/beacon_explorer: Layer "base beacon ...", colour #E69F00).
STAR = "#E69F00"


def _arena_part(image):
    """The arena panel of a RunFigure image (left of the plots, above the legend)."""
    h, w = image.shape[:2]
    return image[: int(0.85 * h), : int(0.45 * w)]


def test_the_run_folder_keeps_the_models_layers(model, run_dir):
    (base,) = load_run(run_dir).layers
    (want,) = model.layers()
    assert base.label == want.label and base.still
    assert np.array_equal(base.points, [model.base.pos])
    look = ("colour", "marker", "size", "layer")
    assert [getattr(base, k) for k in look] == [getattr(want, k) for k in look]


def test_every_frame_marks_the_base_beacon(run_dir, tmp_path):
    run = load_run(run_dir)
    times = [0.0, run.end_time / 2, run.end_time]
    for path in render_snapshots(run, times, tmp_path):
        assert _pixels_near(_arena_part(iio.imread(path)), STAR) > 15, path.name
    frames = iio.imread(render_animation(run, tmp_path / "a.gif", frames=3, progress=False))
    for frame in frames:
        assert _pixels_near(_arena_part(frame), STAR, tol=30) > 10
    figure = RunFigure(run)
    figure.draw(run.end_time / 2)
    labels = [h.get_label() for h in figure.view.legend_handles()]
    assert "base beacon (robots = n_robots + 1)" in labels


def test_a_layer_that_changes_is_drawn_only_at_the_end(run_dir):
    """A saved run knows a changing layer (particles, a belief map) only at its end."""
    run = load_run(run_dir)
    cloud = Layer("cloud", points=np.array([[5.0, 5.0], [6.0, 6.0]]), colour="#F0E442")
    run.layers.append(cloud)
    replay = RunReplay(run)
    assert [layer.label for layer in replay.scene_at(run.end_time).layers][-1] == "cloud"
    assert "cloud" not in [layer.label for layer in replay.scene_at(run.end_time / 2).layers]
    figure = RunFigure(run)
    figure.draw(run.end_time)
    assert "cloud" in [h.get_label() for h in figure.view.legend_handles()]
    figure.draw(0.0)  # back in time: hidden again, and out of the legend
    assert "cloud" not in [h.get_label() for h in figure.view.legend_handles()]
    drawn = [np.asarray(c.get_offsets()) for c in figure.ax_map.collections]
    (artist,) = [c for c, xy in zip(figure.ax_map.collections, drawn, strict=True)
                 if xy.shape == cloud.points.shape and np.allclose(xy, cloud.points)]  # fmt: skip
    assert not artist.get_visible()


def test_rasters_and_points_of_layers_survive_the_folder(tmp_path):
    model = HierarchyModel(seed=1, **HierarchyModel.QUICK).run()
    save_run(model, tmp_path / "h")
    saved = load_run(tmp_path / "h").layers
    want = model.layers()
    assert [layer.label for layer in saved] == [layer.label for layer in want]
    assert any(layer.raster is not None for layer in want)
    for got, layer in zip(saved, want, strict=True):
        for part in ("points", "raster"):
            a, b = getattr(got, part), getattr(layer, part)
            assert (a is None) == (b is None) and (a is None or np.array_equal(a, b)), part
        assert got.extent == (None if layer.extent is None else tuple(layer.extent))
        assert not got.still


def test_a_folder_saved_before_layers_loads_without_them(run_dir, tmp_path):
    old = tmp_path / "old"
    shutil.copytree(run_dir, old)
    meta = json.loads((old / "run.json").read_text())
    meta.pop("layers")
    (old / "run.json").write_text(json.dumps(meta))
    assert load_run(old).layers == []
    meta["layers"] = "star"
    (old / "run.json").write_text(json.dumps(meta))
    with pytest.raises(RunFolderError, match="layers are not a list of objects"):
        load_run(old)


def test_the_last_position_sample_is_the_runs_end_so_the_last_snapshot_is_its_final_picture():
    # the run ends at 109.2 s, between two 1 s samples: without a sample at the end the last
    # snapshot drew the swarm of 109.0 s, before the last iteration (another state count)
    from models.tangible_pso import TangiblePSOModel

    model = TangiblePSOModel(seed=1, trace_interval=1.0, particles=10, iterations=12).run()
    positions = model.positions()
    assert model.env.now % 1.0 > 0 and positions["time"].max() == model.env.now
    last = positions[positions["time"] == model.env.now]
    states = last["state"].value_counts().to_dict()
    live = {s: n for s, n in model.recorder.counts.items() if n}
    assert {s: states.get(s, 0) for s in live} == live


def test_a_legend_of_long_labels_takes_fewer_columns_so_it_stays_inside_the_picture():
    from analysis.render import _legend_columns

    short = ["ground (3)", "explorer (12)", "beacon (21)", "comm link", "wall"]
    long = ["virtual MAV: stopped by a swarm constraint (61)", "virtual MAV: free (59)"]
    assert _legend_columns(short) == 6
    assert _legend_columns(long) == 3  # six columns of these ran off both edges
    assert _legend_columns(["x" * 400]) == 1
