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
from collections.abc import Iterator
from pathlib import Path

import matplotlib.image
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from tqdm import tqdm

from abm.errors import ABMError, ConfigError
from abm.scene import Scene
from abm.viz.scene import COVERED_COLOUR, SceneView
from analysis.blit import FrameBlitter
from analysis.gif import write_gif
from analysis.run_folder import SavedRun

__all__ = [
    "RunFigure",
    "RunReplay",
    "animation_frames",
    "check_animation",
    "render_animation",
    "render_snapshots",
    "snapshot_times",
]


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
        self._title = None
        #: whether the layout is kept (set at the first frame drawn)
        self.laid_out = False
        self._blitter = FrameBlitter(self.fig, self._changing)

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
        handles = self.view.legend_handles()
        self._legend = self.fig.legend(
            handles=handles,
            loc="outside lower center",
            ncols=_legend_columns([h.get_label() for h in handles]),
            frameon=False,
            fontsize=9,
        )
        self._title = self.fig.suptitle(self._headline(time), fontsize=11)

    def _changing(self) -> list:
        """What :meth:`draw` changes: the scene's artists, the cursors, the legend, the title."""
        parts = [*self.view.changing_artists(), *self._cursors, self._legend, self._title]
        return [artist for artist in parts if artist is not None]

    def rgba(self) -> np.ndarray:
        """The figure as an ``(h, w, 4)`` uint8 view of the canvas, valid until the next
        frame; the first call lays the figure out (constrained layout) and keeps that layout.

        Only what :meth:`draw` changes is drawn again (see :class:`analysis.blit.FrameBlitter`),
        which gives the pixels of a full draw.
        """
        image = self._blitter.render()
        self.freeze_layout()
        return image

    def rgb(self) -> np.ndarray:
        """The figure as an ``(h, w, 3)`` uint8 image (see :meth:`rgba`)."""
        return self.rgba()[..., :3].copy()

    def layout_key(self) -> tuple[float, float]:
        """Heights (pixels) of the legend and the title: all constrained layout reads of them."""
        renderer = self.fig.canvas.get_renderer()
        return (
            self._legend.get_tightbbox(renderer).height,
            self._title.get_tightbbox(renderer).height,
        )

    def title_height(self) -> float:
        """Where the title stands (figure fraction; constrained layout moves it)."""
        return float(self._title.get_position()[1])

    def set_title_height(self, y: float) -> None:
        """Put the title at ``y`` (figure fraction), where a layout once put it."""
        self._title.set_y(y)

    def freeze_layout(self) -> None:
        """Keep the current layout for later frames (constrained layout is slow to redo)."""
        self.fig.set_layout_engine("none")
        self.laid_out = True


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


class _SnapshotFigures:
    """Figures for snapshots at one dpi, each laid out as ``savefig`` lays out a new figure.

    Constrained layout reaches its result in steps, from where the axes stand: a figure
    saved again and again drifts by a fraction of a pixel. So each snapshot is drawn as on a
    new figure (what ``savefig`` of a new :class:`RunFigure` gives, pixel for pixel), and a
    figure is kept for every layout met: the layout depends on the frame only through the
    heights of the legend and of the title (constrained layout reserves their heights and
    nothing else of them, and puts the title at a height of its own), so a snapshot whose
    legend and title are as tall as an earlier one's is drawn on that figure, with the title
    where the layout put it, redrawing only what changed.
    """

    def __init__(self, run: SavedRun, dpi: int) -> None:
        self.run = run
        self.dpi = dpi
        self._figures: dict[tuple[float, float], tuple[RunFigure, float]] = {}
        self._probe: RunFigure | None = None

    def rgba(self, time: float) -> np.ndarray:
        """The snapshot at ``time`` (s) as an ``(h, w, 4)`` view, valid until the next one."""
        probe = self._probe
        if probe is None or probe.laid_out:
            probe = self._new_figure()
        probe.draw(time)
        key = probe.layout_key()
        if key not in self._figures:  # a layout not met yet: the probe is a new figure
            image = probe.rgba()
            self._figures[key] = (probe, probe.title_height())
            self._probe = None
            return image
        figure, title_y = self._figures[key]
        self._probe = probe  # kept for the next snapshot
        figure.draw(time)
        figure.set_title_height(title_y)
        return figure.rgba()

    def _new_figure(self) -> "RunFigure":
        figure = RunFigure(self.run)
        figure.fig.set_dpi(self.dpi)
        return figure


#: Characters of 9-point legend text one row of the 12-inch-wide figure holds, each entry's
#: marker and padding counted as 6 more.
_LEGEND_ROW = 170


def _legend_columns(labels: list[str]) -> int:
    """Legend columns (at most 6) whose widest entries still fit the figure's width: six
    columns of tangible PSO's "virtual MAV: stopped by a swarm constraint (61)" ran off both
    edges of the picture.
    """
    widest = max((len(label) for label in labels), default=1) + 6
    return max(1, min(6, _LEGEND_ROW // widest))


def render_snapshots(
    run: SavedRun, times, out_dir: str | Path, dpi: int = 110, progress: bool = False
) -> list[Path]:
    """Save one PNG per time (s) as ``out_dir/snapshot_<t>s.png`` (t rounded); return the paths.

    Each PNG is what ``savefig`` writes for a new figure of that snapshot.
    """
    times = _check_times(run, times)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    figures = _SnapshotFigures(run, dpi)
    paths = []
    for time in tqdm(sorted(times), desc="snapshots", unit="png", disable=not progress):
        path = out / f"snapshot_{round(time):05d}s.png"
        if path in paths:
            path = out / f"snapshot_{round(time):05d}s_{len(paths)}.png"
        # as savefig writes it (FigureCanvasAgg.print_png)
        matplotlib.image.imsave(path, figures.rgba(time), format="png", origin="upper", dpi=dpi)
        paths.append(path)
    return paths


def animation_frames(run: SavedRun, frames: int, dpi: int = 80) -> Iterator[np.ndarray]:
    """The ``(h, w, 3)`` uint8 frames of an animation: ``frames`` times evenly spaced over the
    run, on one figure laid out at the first frame.
    """
    figure = RunFigure(run)
    figure.fig.set_dpi(dpi)
    for time in np.linspace(0.0, run.end_time, frames):
        figure.draw(float(time))
        yield figure.rgb()


def check_animation(frames: int, fps: float) -> None:
    """Refuse an animation of fewer than two frames or a frame rate that is not positive
    (ConfigError), before anything is drawn.
    """
    if frames < 2:
        raise ConfigError(f"frames must be at least 2, got {frames}")
    if not fps > 0:
        raise ConfigError(f"fps must be positive, got {fps}")


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
    check_animation(frames, fps)
    ffmpeg = shutil.which("ffmpeg")
    if kind == ".mp4" and ffmpeg is None:
        raise ABMError("MP4 needs ffmpeg on PATH (apt-get install -y ffmpeg); write a .gif instead")
    path.parent.mkdir(parents=True, exist_ok=True)
    images = tqdm(
        animation_frames(run, frames, dpi),
        total=frames,
        desc="frames",
        unit="frame",
        disable=not progress,
    )
    if kind == ".gif":
        write_gif(images, path, fps)
    else:
        _write_mp4(ffmpeg, list(images), path, fps)
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
