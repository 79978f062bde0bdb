"""The SolaraViz page of a swarm model: the arena with robots, and live plots.

Generic over :class:`abm.model.SwarmModel`: it reads only the model contract's hooks (states
and their styles, coverage, arrows, params). Mesa's own space drawers know nothing of walls,
comm links or coverage rasters, so the space is drawn by :class:`abm.viz.scene.SceneView`
inside a small Solara component; the plots show robots per state (from the model's exact
state-count series) and DataCollector reporters against simulated time (s).

Needs the ``viz`` extra (solara, Mesa's visualisation); nothing here is imported by ``abm``.
"""

from collections.abc import Callable, Mapping

import numpy as np
import solara
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from mesa.visualization import SolaraViz
from mesa.visualization.utils import update_counter

from abm.scene import scene_of
from abm.viz.controls import default_controls, default_series, initial_kwargs
from abm.viz.scene import view_of

__all__ = ["SwarmPlots", "SwarmSpace", "make_page"]

#: Colour of reporter curves (coverage, energy, ...).
SERIES_COLOUR = "#009E73"


@solara.component
def SwarmSpace(model, shown: tuple[str, ...] = ()):  # noqa: N802
    """The arena: walls, covered area, comm links, robots by state and the model's arrows.

    Args:
        model: the running SwarmModel.
        shown: names of parameters (the sliders') whose values are listed under the title.

    """
    update_counter.get()
    fig = Figure(figsize=(7.0, 6.0), layout="constrained")
    ax = fig.add_subplot()
    view = view_of(model, ax)
    view.update(scene_of(model))
    status = "" if model.running else " (run over)"
    params = model.params.as_dict()
    values = [
        f"{key} = {_short(params[key])}"
        for key in shown
        if isinstance(params.get(key), bool | int | float | str)
    ]
    caption = "\n" + ", ".join(values) if values else ""
    ax.set_title(f"{model.arena.name}: t = {model.time:.0f} s{status}{caption}", fontsize=10)
    fig.legend(
        handles=view.legend_handles(),
        loc="outside lower center",
        ncols=3,
        frameon=False,
        fontsize=9,
    )
    solara.FigureMatplotlib(fig, format="png", bbox_inches="tight")


@solara.component
def SwarmPlots(model, series: Mapping[str, str]):  # noqa: N802
    """Live plots against simulated time: robots per state, then each reporter in ``series``.

    Args:
        model: the running SwarmModel.
        series: DataCollector column -> y-axis label with unit, e.g.
            ``{"coverage": "coverage (% of free area)"}``.

    """
    update_counter.get()
    n = 1 + len(series)
    fig = Figure(figsize=(6.0, 2.0 * n + 0.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, sharex=True))
    now = float(model.time)
    counts = model.state_counts()
    ax = axes[0]
    for state, style in model.state_styles.items():
        t = np.append(counts["time"].to_numpy(), now)
        y = counts[state].to_numpy()
        if len(y):
            y = np.append(y, y[-1])
            ax.step(t, y, where="post", color=style.colour, lw=2, label=style.label or state)
    ax.set_ylabel("robots")
    ax.set_title("robots per state", fontsize=10)
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9)
    frame = model.datacollector.get_model_vars_dataframe()
    times = np.minimum((np.arange(len(frame)) + 1) * model.step_duration, now)
    for ax, (column, label) in zip(axes[1:], series.items(), strict=True):
        if column in frame and len(frame):
            ax.plot(times, frame[column].to_numpy(float), color=SERIES_COLOUR, lw=2, marker=".")
        else:
            ax.text(
                0.5,
                0.5,
                "press Step or \u25b6 to run",
                ha="center",
                va="center",
                transform=ax.transAxes,
                color="#666666",
            )
        ax.set_ylabel(label)
        ax.set_title(label.split(" (")[0], fontsize=10)
        if "%" in label:
            ax.set_ylim(0.0, 100.0)
        elif "fraction" in label:
            ax.set_ylim(0.0, 1.0)
    axes[-1].set_xlabel("simulated time (s)")
    axes[-1].set_xlim(0.0, max(now, 1.0))
    for ax in axes:
        ax.grid(alpha=0.3)
    solara.FigureMatplotlib(fig, format="png", bbox_inches="tight")


def _short(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def make_page(
    model_class: Callable,
    model_params: Mapping[str, object] | None = None,
    *,
    name: str | None = None,
    series: Mapping[str, str] | None = None,
    play_interval: int = 150,
):
    """A Solara ``Page`` component showing a SwarmModel with sliders and live plots.

    Each browser session gets its own model, built from the inputs' initial values.

    Args:
        model_class: a SwarmModel subclass.
        model_params: SolaraViz model parameters: input specs such as ``{"type": "SliderFloat",
            "value": 6.0, "min": 1.0, "max": 30.0, "step": 1.0, "label": "..."}`` or fixed values.
            None: a slider, checkbox or select for each simple parameter of ``model_class``
            (:func:`abm.viz.controls.default_controls`).
        name: title of the page (default: the class name).
        series: DataCollector column -> axis label with unit, plotted live under the counts;
            None: coverage and energy when the model has them.
        play_interval: pause between steps while playing (ms).

    """
    if model_params is None:
        model_params = default_controls(model_class)
    kwargs = initial_kwargs(model_params)
    title = name or getattr(model_class, "__name__", "swarm model")
    shown = tuple(key for key, spec in model_params.items() if isinstance(spec, dict))
    cache: dict[str, Mapping[str, str]] = {}

    def space(model):
        return SwarmSpace(model, shown)

    def plots(model):
        if "series" not in cache:
            cache["series"] = default_series(model) if series is None else dict(series)
        return SwarmPlots(model, cache["series"])

    @solara.component
    def Page():  # noqa: N802
        model = solara.use_memo(lambda: model_class(**kwargs), [])
        return SolaraViz(
            model,
            components=[(space, 0), (plots, 0)],
            model_params=dict(model_params),
            name=title,
            play_interval=play_interval,
        )

    return Page
