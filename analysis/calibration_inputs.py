"""What ``abm calibrate`` is given, checked before any run: priors, target and output folder.

* A prior (``--free``) is ``NAME=LOW:HIGH`` (uniform) or ``NAME=log:LOW:HIGH`` (log-uniform,
  ``0 < LOW``): a real-valued parameter of the model whose ``Params`` accept both ends (the
  same check as a sensitivity design's ranges, :func:`abm.params.check_value`).
* A target is measured numbers: a CSV with columns ``metric, value, sd`` (a metric is a key of
  the model's summary, ``sd > 0`` the spread that scales its distance) and optional further
  columns naming parameters, which fix the condition of each row; or ``published``, the
  model's own ``PUBLISHED`` level records with a spread (:func:`published_target`).
* The output folder is the calibration's alone: new, empty, or one holding the same
  calibration (its ``calibration.json``), which is then resumed.
"""

import json
import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from abm.errors import ConfigError, OutputError
from abm.params import check_value, field_rule, param_fields

__all__ = [
    "MANIFEST",
    "Prior",
    "Target",
    "check_folder",
    "check_metrics",
    "parse_prior",
    "published_target",
    "read_target",
]

#: The file that says which calibration a folder holds.
MANIFEST = "calibration.json"
#: The target's required columns.
COLUMNS = ("metric", "value", "sd")


@dataclass(frozen=True)
class Prior:
    """The prior of one free parameter: uniform on ``[low, high]``, or uniform in log."""

    name: str
    low: float
    high: float
    log: bool = False

    def manifest(self) -> dict:
        """JSON-able description (compared when a folder is resumed)."""
        return {"name": self.name, "low": self.low, "high": self.high, "log": self.log}


def parse_prior(model_cls: type, text: str, fixed: Mapping = ()) -> Prior:
    """``NAME=LOW:HIGH`` or ``NAME=log:LOW:HIGH`` checked against the model's ``Params``.

    Raises:
        ConfigError: one line naming the option and what is accepted.

    """
    name, sep, spec = text.partition("=")
    name = name.strip().replace("-", "_")
    parts = spec.split(":")
    log = bool(parts) and parts[0].strip().lower() == "log"
    if log:
        parts = parts[1:]
    if not sep or not name or len(parts) != 2:
        raise ConfigError(f"--free {text!r}: expected NAME=LOW:HIGH or NAME=log:LOW:HIGH")
    fields = {f.name: f for f in param_fields(model_cls.Params)}
    if name not in fields or name in ("seed", "rng"):
        raise ConfigError(
            f"--free {text!r}: {name!r} is not a parameter of {model_cls.__name__}; "
            f"accepted: {', '.join(fields)}"
        )
    if name in fixed:
        raise ConfigError(f"--free {name}: also fixed with --set; give it once")
    rule = field_rule(fields[name])
    if rule.get("integer") or rule.get("choices") or fields[name].type not in (float, "float"):
        raise ConfigError(
            f"--free {name}: only real-valued parameters can be calibrated "
            f"({name} is {fields[name].type}); fix it with --set"
        )
    try:
        low, high = float(parts[0]), float(parts[1])
    except ValueError as exc:
        raise ConfigError(f"--free {text!r}: LOW and HIGH must be numbers") from exc
    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise ConfigError(f"--free {name}: range {low:g}:{high:g} must be finite with LOW < HIGH")
    if log and low <= 0:
        raise ConfigError(f"--free {name}: a log-uniform range needs LOW > 0, got {low:g}")
    for end in (low, high):
        try:
            check_value(model_cls.Params, name, end)
        except ConfigError as exc:
            raise ConfigError(f"--free {name} range {low:g}:{high:g}: {exc}") from exc
    return Prior(name, low, high, log)


@dataclass(frozen=True)
class Target:
    """Measured numbers: one row per number (``metric, value, sd``, condition columns).

    Attributes:
        rows: the table (columns ``metric``, ``value``, ``sd`` then the condition columns).
        conditions: the condition columns (parameters), possibly none.
        source: where it came from (a file, or the model's published records).
        skipped: published records left out, each with why.

    """

    rows: pd.DataFrame
    conditions: tuple[str, ...]
    source: str
    skipped: tuple[str, ...] = ()

    def condition_list(self) -> list[dict]:
        """The distinct conditions, in the order they first appear ({} without columns)."""
        if not self.conditions:
            return [{}]
        seen: list[dict] = []
        for _, row in self.rows.iterrows():
            cond = {c: _plain(row[c]) for c in self.conditions if not _missing(row[c])}
            if cond not in seen:
                seen.append(cond)
        return seen

    def condition_of(self, i: int) -> dict:
        """The condition of row ``i``."""
        row = self.rows.iloc[i]
        return {c: _plain(row[c]) for c in self.conditions if not _missing(row[c])}

    def manifest(self) -> list[dict]:
        """JSON-able rows (compared when a folder is resumed)."""
        return json.loads(self.rows.to_json(orient="records"))


def _missing(value: object) -> bool:
    return value is None or (isinstance(value, float) and math.isnan(value))


def _plain(value: object) -> object:
    return value.item() if hasattr(value, "item") else value


def read_target(model_cls: type, path: Path, fixed: Mapping = (), free: Sequence = ()) -> Target:
    """A target CSV, checked: its columns, a positive ``sd`` on every row, the condition
    columns as parameters of the model with values it accepts.

    Raises:
        ConfigError: one line naming the file, the row or column and what is accepted.

    """
    try:
        frame = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: not a readable CSV ({exc})") from exc
    missing = [c for c in COLUMNS if c not in frame.columns]
    if missing:
        raise ConfigError(
            f"{path}: no column {missing[0]!r}; a target needs columns metric, value, sd "
            "(and optional parameter columns fixing each row's condition)"
        )
    if frame.empty:
        raise ConfigError(f"{path}: no rows; give one measured number per row")
    for col in ("value", "sd"):
        numbers = pd.to_numeric(frame[col], errors="coerce")
        for i, (raw, x) in enumerate(zip(frame[col], numbers, strict=True)):
            if not math.isfinite(x) or (col == "sd" and x <= 0):
                what = "a spread > 0 (the distance divides by it)" if col == "sd" else "a number"
                got = "nothing" if _missing(raw) else repr(raw)
                raise ConfigError(f"{path} row {i + 2}: {col} must be {what}, got {got}")
        frame[col] = numbers.astype(float)
    conditions = tuple(c for c in frame.columns if c not in COLUMNS)
    for col in conditions:
        if col in free:
            raise ConfigError(f"{path}: column {col!r} fixes a parameter that --free calibrates")
        if col in fixed:
            raise ConfigError(f"{path}: column {col!r} is also set with --set; give it once")
        for i, value in enumerate(frame[col]):
            if _missing(value):
                continue
            try:
                check_value(model_cls.Params, col, _plain(value))
            except ConfigError as exc:
                raise ConfigError(f"{path} row {i + 2}, column {col!r}: {exc}") from exc
    frame["metric"] = frame["metric"].astype(str)
    return Target(frame.reset_index(drop=True), conditions, str(path))


def published_target(model_cls: type, free: Sequence = ()) -> Target:
    """The model's own ``PUBLISHED`` levels with a spread: a record is used when it is a
    "level" with a numeric value and a spread, and its condition does not fix a free parameter.
    The others are listed in :attr:`Target.skipped`, each with why.

    Raises:
        ConfigError: the model has no usable record.

    """
    rows, skipped = [], []
    records = list(model_cls.PUBLISHED)
    for rec in records:
        label = f"{rec.section}: {rec.quantity} ({rec.source or 'no source'})"
        if rec.kind != "level":
            skipped.append(f"{label}: not a level (kind {rec.kind})")
        elif isinstance(rec.value, str) or rec.spread is None:
            skipped.append(f"{label}: no published spread")
        elif set(rec.condition) & set(free):
            skipped.append(f"{label}: its condition fixes a free parameter")
        else:
            rows.append({"metric": rec.metric, "value": float(rec.value), "sd": rec.spread,
                         **rec.condition})  # fmt: skip
    if not rows:
        why = Counter(line.rpartition(": ")[2] for line in skipped)
        counts = "; ".join(f"{n} {reason}" for reason, n in why.most_common()) or "none"
        raise ConfigError(
            f"{model_cls.__name__} has no published level with a spread to calibrate against "
            f"({len(records)} records: {counts}); give measured numbers with --target FILE"
        )
    frame = pd.DataFrame(rows)
    conditions = tuple(c for c in frame.columns if c not in COLUMNS)
    return Target(frame, conditions, "published", tuple(skipped))


def check_metrics(model_cls: type, target: Target, fixed: Mapping) -> None:
    """Refuse a target metric the model's summary does not hold (one dry build, run to time 0,
    gives the summary's keys).
    """
    keys = model_cls(seed=0, **dict(fixed)).run(until=0.0).summary()
    numeric = [k for k, v in keys.items() if isinstance(v, int | float) and not isinstance(v, bool)]
    for metric in dict.fromkeys(target.rows["metric"]):
        if metric not in numeric:
            raise ConfigError(
                f"target metric {metric!r} is not a numeric key of {model_cls.__name__}'s "
                f"summary; accepted: {', '.join(numeric)}"
            )


def check_folder(out: Path, manifest: Mapping) -> bool:
    """Whether ``out`` holds this calibration already (then it is resumed).

    Raises:
        OutputError: ``out`` is a file, holds other files, or holds another calibration.

    """
    if out.exists() and not out.is_dir():
        raise OutputError(f"{out} is a file, not a folder: choose a folder (--out)")
    if not out.is_dir():
        return False
    path = out / MANIFEST
    if path.is_file():
        try:
            old = json.loads(path.read_text())
        except (ValueError, UnicodeDecodeError) as exc:
            raise OutputError(f"{path} is damaged ({exc}); choose another folder (--out)") from exc
        if old != json.loads(json.dumps(manifest)):
            changed = sorted(k for k in {*old, *manifest} if old.get(k) != manifest.get(k))
            raise OutputError(
                f"{out} holds another calibration (its {', '.join(changed)} differ); "
                "choose another folder (--out) or give the same model, target and priors"
            )
        return True
    foreign = [p.name for p in sorted(out.iterdir()) if not p.name.startswith(".lock")]
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise OutputError(
            f"{out} is not a calibration folder (no {MANIFEST}) and holds {shown}: a "
            "calibration writes only into a new or empty folder or its own; choose another "
            "folder (--out)"
        )
    return False
