"""``abm run MODEL``: one run of any registered model; prints its summary, saves the run folder
``abm render`` draws from and a PNG of the final state.

Every field of the model's params is a flag (``abm run MODEL --help`` lists them). Each run gets
a folder of its own, ``out/runs/<model>-<time>-<seed>/``, unless ``--out`` names one. Every
input (the seed, the parameters, the output folder) is checked before the run starts, and a
finished run is never lost to a failure while saving (see :func:`save_or_rescue`).
"""

import argparse
import dataclasses
import math
import re
import shlex
import sys
import tempfile
from contextlib import nullcontext
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from abm.png_process import PngProcess

VERB = "run"
HELP = "run one simulation of a model, print its summary, save the run folder and a PNG"
EXAMPLE = "abm run beacon-explorer --world corridor --complexity high --launch-period 6 --seed 1"

#: Where a run's folder goes unless ``--out`` names one.
RUNS = Path("out/runs")
#: Position sampling (s) of a run whose model samples none by default (fast sweeps): `abm
#: render` draws from the samples.
RUN_TRACE_INTERVAL = 1.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm run``: the model, then its own flags (parsed once the model is known)."""
    from abm.registry import model_names

    parser.add_argument(
        "model", nargs="?", help=f"the model: {', '.join(model_names())} (or module:Class)"
    )
    parser.add_argument(
        "options",
        nargs=argparse.REMAINDER,
        help="--seed N, --out DIR and the model's parameters (see: abm run MODEL --help)",
    )


def model_parser(name: str, params_cls: type, description: str) -> argparse.ArgumentParser:
    """The parser of ``abm run NAME ...``: seed, output folder, progress, one flag per parameter.

    Args:
        name: the model as the user named it.
        params_cls: the model's ``Params`` (:func:`abm.registry.declared`).
        description: what the model is, the first line of its class's docstring.

    """
    from analysis.cli import OneLineParser
    from analysis.cli.flags import add_param_flags, seed_argument

    parser = OneLineParser(prog=f"abm run {name}", description=description)
    parser.add_argument(
        "--seed",
        type=seed_argument,
        default=1,
        help="the model's seed, an integer in [0, 2**63 - 1] [1]",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help=f"the run folder: new, or holding this same run [a new {RUNS}/<model>-<time>-<seed>]",
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="a progress line on stderr once the run takes more than a few seconds [yes]",
    )
    add_param_flags(parser, params_cls)
    trace = parser._option_string_actions.get("--trace-interval")
    default = {f.name: f.default for f in dataclasses.fields(params_cls)}.get("trace_interval")
    if trace is not None and default is None:  # main() samples anyway, for abm render
        trace.help = trace.help.replace(
            "[none]", f"[{RUN_TRACE_INTERVAL:g} here; none in sweeps and from Python]"
        )
    return parser


def main(args: argparse.Namespace) -> int:
    """Check every input, build, run, print, save.

    The parameters are checked against the model's ``Params`` read without importing the
    model's module (:func:`abm.registry.declared`), and what only a run needs (the model
    class, the drawing, the run folder's writer, the progress line) is imported after, so
    ``--help`` and a bad parameter answer at once. The PNG is drawn by a process started once
    the parameters are accepted, which loads matplotlib while this one loads the model and
    runs it (:mod:`abm.png_process`).
    """
    from abm.errors import ConfigError
    from abm.params import make_params
    from abm.registry import declared, model_class, model_names, name_of
    from analysis.cli.flags import given_params

    if args.model is None:
        raise ConfigError(
            f"name a model: {', '.join(model_names())} (abm run MODEL --help lists its flags)"
        )
    model = declared(args.model)
    if args.model in model_names():
        name = args.model
    else:  # "module:Class": the name it is registered under, if any
        name = name_of(model_class(args.model)) or args.model
    options = model_parser(name, model.params, model.description).parse_args(args.options)
    params = given_params(options)
    # `abm render` draws from the sampled positions: sample them even where the model's
    # default (fast sweeps) is not to.
    params.setdefault("trace_interval", model.params().trace_interval or RUN_TRACE_INTERVAL)
    planned = make_params(model.params, params)  # every parameter checked before the run
    from abm.png_process import PngProcess

    with PngProcess() as drawer:  # loads matplotlib on the other core meanwhile
        return _run_and_save(args, name, options, params, planned, drawer)


def _run_and_save(
    args: argparse.Namespace,
    name: str,
    options: argparse.Namespace,
    params: dict,
    planned,
    drawer: "PngProcess",
) -> int:
    """Import the model, check the output folder, run, print, save the run folder and its
    PNG (drawn by ``drawer``, an :class:`abm.png_process.PngProcess`).
    """
    from abm.registry import model_class
    from abm.scene import picture_of
    from analysis.cli.progress import RunProgress

    cls = model_class(args.model)
    if options.out is not None:
        from analysis.run_folder import check_run_target

        check_run_target(options.out)
        _check_same_run(options.out, cls, options.seed, planned)
        out, made = _prepare(options.out)
    else:
        out, made = _prepare(None, name, options.seed)
    try:
        model = cls(seed=options.seed, **params)
        progress = RunProgress(model) if options.progress else None
        with progress or nullcontext():
            model.run()
        summary = model.summary()
        print(f"{name}, seed {options.seed}:")
        print(format_summary(summary), flush=True)
        if progress is not None and progress.shown:  # a long run: its files take a while too
            print(f"saving the run in {out} ...", file=sys.stderr)
        again = shlex.join(["abm", "run", name, *args.options])
        written = save_or_rescue(model, out, again)
    except BaseException:
        if made and out.is_dir() and not any(out.iterdir()):
            out.rmdir()  # the folder made for this run stays only with the run in it
        raise
    print()
    for path in written:
        print(f"wrote {path}")
    png = drawer.save(picture_of(model, _title(name, summary)), out / "final.png")
    print(f"wrote {png}")
    print(f"next: abm render {out}")
    return 0


def _prepare(out: Path | None, name: str = "", seed: int = 0) -> tuple[Path, bool]:
    """Make the run's folder before the run (``out``, or a new one under :data:`RUNS`) and
    check that files can be written in it; return it and whether it was made here.

    Any place that cannot take the run (read-only, no permission, a name too long, a full
    disk) is refused now rather than after the run.

    Raises:
        OutputError: naming the folder, the reason and what to do.

    """
    from abm.errors import OutputError

    try:
        if out is None:
            out, made = new_run_folder(name, seed, datetime.now()), True
        else:
            made = not out.exists()
            out.mkdir(parents=True, exist_ok=True)
        Path(tempfile.mkdtemp(prefix=".abm-check-", dir=out)).rmdir()
    except OSError as exc:
        if out is not None and made and out.is_dir() and not any(out.iterdir()):
            out.rmdir()
        if isinstance(exc, OutputError):
            raise
        raise OutputError(exc.errno, exc.strerror or str(exc), exc.filename or str(out)) from exc
    return out, made


def new_run_folder(name: str, seed: int, started: datetime, root: Path = RUNS) -> Path:
    """Make and return a new, empty folder ``root/<name>-<YYYYmmdd-HHMMSS>-<seed>``.

    A run started in the same second with the same model and seed gets ``-2``, ``-3``, ...: a
    run folder is never shared (creating it is the reservation, so parallel runs cannot meet).
    """
    stem = _stem(name, seed, started)
    root.mkdir(parents=True, exist_ok=True)
    for n in range(1, 10_000):
        folder = root / (stem if n == 1 else f"{stem}-{n}")
        try:
            folder.mkdir()
        except FileExistsError:
            continue
        return folder
    raise FileExistsError(f"{root / stem}-*: 10,000 folders of this name already exist")


def _stem(name: str, seed: int, started: datetime) -> str:
    """``<name>-<YYYYmmdd-HHMMSS>-<seed>``, the name kept to letters, digits and ``_.-``."""
    return f"{re.sub(r'[^A-Za-z0-9_.-]+', '_', name)}-{started:%Y%m%d-%H%M%S}-{seed}"


def _check_same_run(out: Path, cls: type, seed: int, params) -> None:
    """Refuse an ``--out`` folder that holds anything but this same run (model, seed and
    parameters): two runs in one folder would mix their files and renders.
    """
    import json

    from abm.errors import OutputError

    if not out.is_dir() or not any(out.iterdir()):
        return
    meta_file = out / "run.json"
    if not meta_file.is_file():
        raise OutputError(
            f"--out {str(out)!r} holds other files and is not a run folder; give a new or empty "
            f"folder (or leave --out out: each run gets a new folder under {RUNS}/)"
        )
    try:
        meta = json.loads(meta_file.read_text(encoding="utf-8"))
        same = (
            meta.get("target") == f"{cls.__module__}:{cls.__qualname__}"
            and meta.get("seed") == seed
            and meta.get("parameters") == json.loads(json.dumps(params.plain()))
        )
    except (ValueError, AttributeError):
        meta, same = {}, False
    if not same:
        other = f"{meta.get('model', 'unknown model')}, seed {meta.get('seed', '?')}"
        raise OutputError(
            f"--out {str(out)!r} holds another run ({other}); give a new folder (or leave --out "
            f"out: each run gets a new folder under {RUNS}/), or delete that one first"
        )


def save_or_rescue(model, out: Path, again: str) -> list:
    """Save the finished run to ``out``; if that fails, save it to a new folder in the system's
    temporary folder instead and say both, so the finished simulation is not lost.

    The data written to ``out`` is removed on failure (no half-written run folder, its space
    given back; see :func:`analysis.run_folder.save_run`).

    Raises:
        OutputError: always when ``out`` failed: naming the file that could not be written,
            what to do, and where the run was saved instead, or, when that failed too, the
            command that reproduces the run event for event (same seed, same parameters).

    """
    from abm.errors import OutputError
    from analysis.cli import one_line
    from analysis.run_folder import save_run

    try:
        return save_run(model, out)
    except OSError as exc:
        failed = one_line(exc, advice=False)
        first = exc
    try:
        rescue = Path(tempfile.mkdtemp(prefix="abm-rescued-")) / out.name
        save_run(model, rescue)
    except OSError as exc:
        also = one_line(exc, advice=False)
        raise OutputError(
            f"{failed}; saving it to the temporary folder failed too ({also}): the run is not "
            f"saved; its summary is above, and `{again}` repeats it event for event"
        ) from first
    raise OutputError(
        f"{failed}; the finished run was saved to {rescue} instead: `mv {rescue} {out}` "
        f"once the problem is fixed (`abm render {rescue}` draws it where it is)"
    ) from first


def _title(name: str, summary: dict) -> str:
    parts = [name, f"t = {summary['time']:.0f} s ({summary['end_reason'].split(':')[0]})"]
    if "coverage_area" in summary:
        parts.append(f"coverage {summary['coverage_area']:.1f} %")
    return ", ".join(parts)


def unit_of(key: str) -> str:
    """The unit of a summary key as the framework (``abm.units.COMMON``) or the model
    (``SUMMARY_UNITS``) declares it; nothing for names, identifiers, true/false keys, counts
    and plain numbers.
    """
    from abm.units import unit_of as declared

    unit = declared(key)
    return "" if unit in ("text", "id", "flag", "count", "1") else unit


def format_summary(summary: dict) -> str:
    """A two-column table of a run's summary, with units; a value the run could not measure
    (NaN: no swap to resolve, no failure to time) reads "none", without a unit.
    """
    lines = []
    for key, value in summary.items():
        unit = "" if _missing(value) else unit_of(key)
        lines.append(f"  {key:<18} {_shown(value):>14} {unit}".rstrip())
    return "\n".join(lines)


def _missing(value: object) -> bool:
    """Whether a summary value is NaN: nothing measured."""
    return isinstance(value, float) and math.isnan(value)


def _shown(value: object) -> str:
    """A summary value as printed: floats of 10 or more to one decimal, smaller ones to three
    significant digits (a mean speed of 0.676 m/s would read 0.7 to one decimal).
    """
    if not isinstance(value, float):
        return str(value)
    if _missing(value):
        return "none"
    return f"{value:,.1f}" if abs(value) >= 10 or not math.isfinite(value) else f"{value:.3g}"
