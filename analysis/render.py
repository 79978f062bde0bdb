"""Pictures of a saved run, rebuilt from its recorded files without re-running the model.

At time t the picture shows what the run folder (see :mod:`analysis.run_folder`) records, for any
model:

- walls: the saved arena grid;
- robots and their states, in the model's styles: the latest position sample at or before t;
- comm links: between the robots that were comm-network nodes at that sample, within the comm
  range and in line of sight (as :class:`abm.comms.CommNetwork` links them);
- covered area: the pixels first covered at or before t (the model's own raster records when),
  so the last frame is the model's final raster;
- the model's layers (:meth:`abm.model.SwarmModel.layers`): the run folder keeps them as they
  were at the end of the run, so a layer the model declares still (``Layer.still``, such as the
  base beacon's star) is drawn at every time, and any other (a belief map, particles, bubbles)
  only at the run's end time, the one time it is known;
- arrows (e.g. beacons' desired directions) are not recorded, so renders leave them out (the
  live ``abm viz`` page shows them).

Beside the arena: robots per state and, for a model that covers, coverage over the whole run,
with a cursor at t.
"""

import shutil
import subprocess
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from tqdm import tqdm

from abm.errors import ABMError, ConfigError
from abm.viz.scene import COVERED_COLOUR, Scene, SceneView
from analysis.run_folder import SavedRun

__all__ = ["RunReplay", "RunFigure", "render_animation", "render_snapshots", "snapshot_times"]


class RunReplay:
    """Rebuilds the scene of a saved run at any time.

    Args:
        run: the loaded run folder.

    """

    def __init__(self, run: SavedRun) -> None:
        self.run = run
        positions = run.positions.sort_values(["time", "robot"], kind="stable")
        self._times = positions["time"].to_numpy(float)
        self._xy = positions[["x", "y"]].to_numpy(float)
        self._states = positions["state"].to_numpy(object)
        self._comm = positions["comm"].to_numpy(bool)
        self.sample_times = np.unique(self._times)
        self.comm_range = float(run.meta["comm_range"])
        self.still_layers = [layer for layer in run.layers if layer.still]
        self.first_covered = run.first_covered
        self._n_free = None
        if self.first_covered is not None:
            fine = run.first_covered.shape[0] // run.arena.rows
            free = np.repeat(np.repeat(run.arena.free, fine, axis=0), fine, axis=1)
            self._n_free = int(free.sum())

    @property
    def pixel(self) -> float | None:
        """Side of a coverage pixel (m), or None without coverage."""
        return self.run.coverage_pixel

    def coverage_history(self) -> tuple[np.ndarray, np.ndarray]:
        """Coverage (% of free area) after each time a pixel was first covered."""
        if self.first_covered is None:
            return np.zeros(0), np.zeros(0)
        times = np.sort(self.first_covered[np.isfinite(self.first_covered)])
        changes = np.nonzero(np.append(np.diff(times) > 0, True))[0]
        return times[changes], 100.0 * (changes + 1) / self._n_free

    def scene_at(self, time: float) -> Scene:
        """The scene at simulated time ``time`` (s)."""
        k = int(np.searchsorted(self.sample_times, time, side="right")) - 1
        if k >= 0:
            rows = self._times == self.sample_times[k]
            xy, states, comm = self._xy[rows], self._states[rows], self._comm[rows]
        else:
            xy, states, comm = np.zeros((0, 2)), np.zeros(0, dtype=object), np.zeros(0, bool)
        return Scene(
            time=float(time),
            positions=xy,
            states=states,
            links=self._links(xy[comm]),
            covered=None if self.first_covered is None else self.first_covered <= time,
            layers=self.run.layers if time >= self.run.end_time else self.still_layers,
        )

    def _links(self, nodes: np.ndarray) -> np.ndarray:
        if len(nodes) < 2:
            return np.zeros((0, 2, 2))
        i, j = np.triu_indices(len(nodes), k=1)
        near = np.hypot(*(nodes[i] - nodes[j]).T) <= self.comm_range
        i, j = i[near], j[near]
        if len(i):
            seen = self.run.arena.line_of_sight(nodes[i], nodes[j])
            i, j = i[seen], j[seen]
        return np.stack([nodes[i], nodes[j]], axis=1)


class RunFigure:
    """A figure of a saved run: the arena on the left, counts and coverage on the right.

    Args:
        run: the loaded run folder.
        figsize: inches.

    """

    def __init__(self, run: SavedRun, figsize: tuple[float, float] = (12.0, 6.6)) -> None:
        self.run = run
        self.replay = RunReplay(run)
        self.fig = Figure(figsize=figsize, layout="constrained")
        FigureCanvasAgg(self.fig)
        grid = self.fig.add_gridspec(2, 2, width_ratios=[1.2, 1.0])
        self.ax_map = self.fig.add_subplot(grid[:, 0])
        ax_counts = self.fig.add_subplot(grid[0, 1])
        ax_cover = self.fig.add_subplot(grid[1, 1], sharex=ax_counts)
        arena = run.arena
        self.view = SceneView(
            self.ax_map, arena.free, arena.resolution, run.styles, pixel=self.replay.pixel
        )
        end = max(run.end_time, 1.0)
        counts = run.state_counts
        for state, style in run.styles.items():
            t = np.append(counts["time"].to_numpy(float), run.end_time)
            y = counts[state].to_numpy(float)
            if len(y):
                ax_counts.step(
                    t,
                    np.append(y, y[-1]),
                    where="post",
                    lw=2,
                    color=style.colour,
                    label=style.label or state,
                )
        ax_counts.set_ylabel("robots")
        ax_counts.set_title("robots per state", fontsize=10)
        ax_counts.yaxis.set_major_locator(MaxNLocator(integer=True))
        ax_counts.legend(loc="center left", frameon=False, fontsize=9)
        ax_counts.tick_params(labelbottom=False)
        times, percent = self.replay.coverage_history()
        if len(times):
            ax_cover.step(
                np.append(times, run.end_time),
                np.append(percent, percent[-1]),
                where="post",
                lw=2,
                color="#009E73",
            )
            ax_cover.fill_between(
                np.append(times, run.end_time),
                np.append(percent, percent[-1]),
                step="post",
                color=COVERED_COLOUR,
                alpha=0.5,
            )
        else:
            ax_cover.text(
                0.5, 0.5, "no coverage recorded", ha="center", transform=ax_cover.transAxes
            )
        ax_cover.set_ylim(0, 100)
        ax_cover.set_ylabel("coverage (% of free area)")
        ax_cover.set_title("covered area", fontsize=10)
        ax_cover.set_xlabel("simulated time (s)")
        ax_cover.set_xlim(0, end)
        self._cursors = []
        for ax in (ax_counts, ax_cover):
            ax.grid(alpha=0.3)
            self._cursors.append(ax.axvline(0.0, color="black", lw=1.2, ls="--"))
        self._legend = None

    def _headline(self, time: float) -> str:
        meta = self.run.meta
        parts = [str(meta["model"]), self.run.arena.name]
        if meta.get("seed") is not None:
            parts.append(f"seed {meta['seed']}")
        return ", ".join(parts) + f"  |  t = {time:.0f} s of {self.run.end_time:.0f} s"

    def draw(self, time: float) -> None:
        """Show the run at simulated time ``time`` (s)."""
        self.view.update(self.replay.scene_at(time))
        for cursor in self._cursors:
            cursor.set_xdata([time, time])
        if self._legend is not None:
            self._legend.remove()
        self._legend = self.fig.legend(
            handles=self.view.legend_handles(),
            loc="outside lower center",
            ncols=6,
            frameon=False,
            fontsize=9,
        )
        self.fig.suptitle(self._headline(time), fontsize=11)

    def rgb(self) -> np.ndarray:
        """The figure as an ``(h, w, 3)`` uint8 image."""
        self.fig.canvas.draw()
        self.freeze_layout()
        return np.asarray(self.fig.canvas.buffer_rgba())[..., :3].copy()

    def freeze_layout(self) -> None:
        """Keep the current layout for later frames (constrained layout is slow to redo)."""
        self.fig.set_layout_engine("none")


def snapshot_times(run: SavedRun, n: int = 4) -> list[float]:
    """``n`` evenly spaced times from the start to the end of the run (s)."""
    if n < 1:
        raise ConfigError(f"the number of snapshots must be at least 1, got {n}")
    return [float(t) for t in np.linspace(0.0, run.end_time, n)]


def _check_times(run: SavedRun, times) -> list[float]:
    times = [float(t) for t in times]
    bad = [t for t in times if not 0.0 <= t <= run.end_time]
    if bad:
        raise ConfigError(
            f"times must lie within the run, [0, {run.end_time:g}] s; "
            f"got {', '.join(f'{t:g}' for t in bad)}"
        )
    return times


def render_snapshots(
    run: SavedRun, times, out_dir: str | Path, dpi: int = 110, progress: bool = False
) -> list[Path]:
    """Save one PNG per time (s) as ``out_dir/snapshot_<t>s.png`` (t rounded); return the paths."""
    times = _check_times(run, times)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    figure = RunFigure(run)
    paths = []
    for time in tqdm(sorted(times), desc="snapshots", unit="png", disable=not progress):
        figure.draw(time)
        path = out / f"snapshot_{round(time):05d}s.png"
        if path in paths:
            path = out / f"snapshot_{round(time):05d}s_{len(paths)}.png"
        figure.fig.savefig(path, dpi=dpi)
        paths.append(path)
    return paths


def render_animation(
    run: SavedRun,
    path: str | Path,
    frames: int = 80,
    fps: float = 8.0,
    dpi: int = 80,
    progress: bool = True,
) -> Path:
    """Save an animation of the whole run: GIF, or MP4 when ``path`` ends in ``.mp4``.

    Args:
        run: the loaded run folder.
        path: the output file (``.gif`` or ``.mp4``; MP4 needs ffmpeg on PATH).
        frames: at most this many frames, evenly spaced over the run.
        fps: frames per second of the animation.
        dpi: resolution (dots per inch of the 12 x 6.6 inch figure).
        progress: show a progress bar.

    """
    path = Path(path)
    kind = path.suffix.lower()
    if kind not in (".gif", ".mp4"):
        raise ConfigError(f"animation file must end in .gif or .mp4, got {str(path)!r}")
    if frames < 2:
        raise ConfigError(f"frames must be at least 2, got {frames}")
    if fps <= 0:
        raise ConfigError(f"fps must be positive, got {fps}")
    ffmpeg = shutil.which("ffmpeg")
    if kind == ".mp4" and ffmpeg is None:
        raise ABMError("MP4 needs ffmpeg on PATH (apt-get install -y ffmpeg); write a .gif instead")
    path.parent.mkdir(parents=True, exist_ok=True)
    figure = RunFigure(run)
    figure.fig.set_dpi(dpi)
    images = []
    for time in tqdm(
        np.linspace(0.0, run.end_time, frames), desc="frames", unit="frame", disable=not progress
    ):
        figure.draw(float(time))
        images.append(figure.rgb())
    if kind == ".gif":
        import imageio.v3 as iio

        iio.imwrite(path, np.stack(images), duration=1000.0 / fps, loop=0)
    else:
        _write_mp4(ffmpeg, images, path, fps)
    return path


def _write_mp4(ffmpeg: str, images: list[np.ndarray], path: Path, fps: float) -> None:
    h, w = images[0].shape[:2]
    h2, w2 = h - h % 2, w - w % 2  # H.264 wants even sizes
    command = [
        ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
        "-s", f"{w2}x{h2}", "-r", f"{fps:g}", "-i", "-",
        "-pix_fmt", "yuv420p", "-vcodec", "libx264", str(path),
    ]  # fmt: skip
    data = b"".join(np.ascontiguousarray(image[:h2, :w2]).tobytes() for image in images)
    result = subprocess.run(command, input=data, capture_output=True, check=False)
    if result.returncode != 0:
        raise ABMError(f"ffmpeg failed writing {path}: {result.stderr.decode().strip()[-300:]}")
