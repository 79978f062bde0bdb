"""Sensitivity designs: a sweep's ``[design]`` table, sampled with SALib into the sweep's points.

A design names a ``kind`` (``"sobol"``, ``"morris"`` or ``"lhs"``), the parameters it varies
(each a range ``[low, high]`` or ``{choices = [...]}``), a size ``n`` and a ``seed`` (default:
the sweep's). SALib draws the sample matrix once from that seed; each row becomes one point of
the sweep, so the design's runs are planned, seeded, stored, resumed and checked exactly like
a grid's (:mod:`analysis.sweep.seeding`, :mod:`analysis.sweep.membership`).

Sizes, as SALib's samplers give them (D = number of parameters):

- ``sobol``: Saltelli's scheme (SALib ``sample.sobol``, no second-order terms), ``n`` base
  points (a power of two) and ``n * (D + 2)`` rows;
- ``morris``: ``n`` trajectories of ``D + 1`` rows on a :data:`MORRIS_LEVELS`-level grid;
- ``lhs``: ``n`` rows of a Latin hypercube.

Whole-number parameters and choices are sampled as a continuous value and rounded: a
parameter taking the whole numbers ``low..high`` (a choice: its index ``0..k-1``) is drawn on
``[low - 0.5, high + 0.5]`` and rounded to ``floor(x + 0.5)``, clipped to ``[low, high]``, so
under a uniform design every value gets the same share. Rows that round to the same point are
one run of the plan (the analysis reads its result for each of them).
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from abm.errors import ConfigError, check_seed
from abm.params import check_value, field_rule, param_fields

__all__ = [
    "DESIGN_KEYS",
    "KINDS",
    "MIN_N",
    "MORRIS_LEVELS",
    "Design",
    "DesignParameter",
    "check_design",
]

#: The kinds of design and what each is for.
KINDS = ("sobol", "morris", "lhs")
#: Keys a ``[design]`` table may hold.
DESIGN_KEYS = ("kind", "n", "seed", "parameters")
#: Smallest ``n`` of each kind, and why: Sobol' needs a power of two (the scrambled Sobol'
#: sequence is balanced at powers of two) and at least 8 base points (on the Ishigami function 4
#: gave bootstrap intervals of +-40 around indices that lie in [0, 1]); Morris' sigma (a
#: standard deviation of elementary effects) needs two trajectories; RBD-FAST on a Latin
#: hypercube (M = 10 harmonics) reads the first M non-zero frequencies of a periodogram, which
#: has rows // 2 of them: with no more than M, S1 is 1 whatever the model. Its bootstrap draws
#: half the rows, so each half needs 2M + 2: n >= 44 (below, every resample gave S1 = 1 and
#: each interval was 0, at n = 21 the indices themselves were all 1, and at 40-41 SALib divided
#: by zero).
MIN_N = {"sobol": 8, "morris": 2, "lhs": 44}
#: Grid levels of a Morris design (SALib's default, Saltelli et al. 2008's p = 4).
MORRIS_LEVELS = 4


@dataclass(frozen=True)
class DesignParameter:
    """One parameter a design varies.

    Attributes:
        name: the model parameter.
        low: the smallest value (a choice: 0, the first index).
        high: the largest value (a choice: its last index).
        integer: the values are whole numbers (sampled and rounded, see the module's text).
        choices: the values of a categorical parameter, in order (None for a range).

    """

    name: str
    low: float
    high: float
    integer: bool = False
    choices: tuple | None = None

    @property
    def bounds(self) -> list[float]:
        """The interval SALib samples on."""
        if self.integer:
            return [self.low - 0.5, self.high + 0.5]
        return [self.low, self.high]

    def value(self, x: float) -> object:
        """The parameter value of the sampled number ``x`` (rounded for whole numbers), inside
        ``[low, high]``: SALib scales its unit samples as ``low + u * (high - low)``, which can
        land one rounding step above ``high``.
        """
        if not self.integer:
            return float(min(max(x, self.low), self.high))
        k = int(min(max(math.floor(x + 0.5), self.low), self.high))
        return self.choices[k] if self.choices is not None else k

    def manifest(self) -> dict:
        """JSON-able description (``sweep.json``)."""
        if self.choices is not None:
            return {"choices": list(self.choices)}
        return {"range": [self.low, self.high], "integer": self.integer}


@dataclass(frozen=True)
class Design:
    """A sensitivity design over some of a model's parameters (see the module's text).

    Attributes:
        kind: "sobol", "morris" or "lhs".
        parameters: the varied parameters, in the file's order.
        n: base points (sobol), trajectories (morris) or rows (lhs).
        seed: the seed of SALib's sampler.

    """

    kind: str
    parameters: tuple[DesignParameter, ...]
    n: int
    seed: int

    @property
    def names(self) -> list[str]:
        """The varied parameters' names."""
        return [p.name for p in self.parameters]

    def problem(self) -> dict:
        """SALib's problem definition."""
        return {
            "num_vars": len(self.parameters),
            "names": self.names,
            "bounds": [p.bounds for p in self.parameters],
        }

    def matrix(self) -> np.ndarray:
        """SALib's sample (one row per design row, before rounding), from :attr:`seed`."""
        from SALib.sample import latin, morris, sobol

        problem = self.problem()
        if self.kind == "sobol":
            return sobol.sample(problem, self.n, calc_second_order=False, seed=self.seed)
        if self.kind == "morris":
            return morris.sample(problem, self.n, num_levels=MORRIS_LEVELS, seed=self.seed)
        return latin.sample(problem, self.n, seed=self.seed)

    def rows(self, matrix: np.ndarray | None = None) -> list[dict]:
        """Each design row as parameter values (rounded where whole), in sample order."""
        matrix = self.matrix() if matrix is None else matrix
        return [
            {p.name: p.value(x) for p, x in zip(self.parameters, row, strict=True)}
            for row in matrix
        ]

    @property
    def n_rows(self) -> int:
        """Rows of the sample (runs before replications, counting repeated points)."""
        d = len(self.parameters)
        return self.n * {"sobol": d + 2, "morris": d + 1, "lhs": 1}[self.kind]

    def manifest(self) -> dict:
        """JSON-able description (``sweep.json``): enough to draw the same sample again."""
        return {
            "kind": self.kind,
            "n": self.n,
            "seed": self.seed,
            "parameters": {p.name: p.manifest() for p in self.parameters},
        }

    @classmethod
    def from_manifest(cls, data: Mapping) -> "Design":
        """The design a ``sweep.json`` records (what :meth:`manifest` wrote)."""
        params = []
        for name, spec in data["parameters"].items():
            if "choices" in spec:
                choices = tuple(spec["choices"])
                params.append(DesignParameter(name, 0, len(choices) - 1, True, choices))
            else:
                low, high = spec["range"]
                params.append(DesignParameter(name, low, high, bool(spec.get("integer"))))
        return cls(str(data["kind"]), tuple(params), int(data["n"]), int(data["seed"]))


def check_design(model_cls: type, raw: object, sweep_seed: int, fixed: Mapping = ()) -> Design:
    """The ``[design]`` table ``raw`` checked against the model's parameters.

    Args:
        model_cls: the model (its ``Params`` know each parameter's accepted range).
        raw: the table as read from TOML (or a :class:`Design`, returned as is once checked).
        sweep_seed: the sweep's seed, the design's seed when the table gives none.
        fixed: the parameters the sweep's grid sets (a design may not vary them too).

    Raises:
        ConfigError: one line naming what is wrong and what is accepted.

    """
    if isinstance(raw, Design):
        raw = {**raw.manifest(), "parameters": _as_table(raw)}
    if not isinstance(raw, Mapping):
        raise ConfigError(f"design must be a table ([design]), got {raw!r}")
    unknown = [k for k in raw if k not in DESIGN_KEYS]
    if unknown:
        raise ConfigError(
            f"design: unknown key {unknown[0]!r}; accepted keys: {', '.join(DESIGN_KEYS)}"
        )
    kind = raw.get("kind")
    if kind not in KINDS:
        raise ConfigError(f"design: kind must be one of {', '.join(KINDS)}; got {kind!r}")
    n = raw.get("n")
    if isinstance(n, bool) or not isinstance(n, int) or n < MIN_N[kind]:
        raise ConfigError(
            f"design: n must be an integer >= {MIN_N[kind]} for a {kind} design, got {n!r}"
        )
    if kind == "sobol" and n & (n - 1):
        raise ConfigError(f"design: n must be a power of two for a sobol design, got {n}")
    seed = check_seed(raw.get("seed", sweep_seed), "design seed", allow_none=False)
    table = raw.get("parameters")
    if not isinstance(table, Mapping) or not table:
        raise ConfigError(
            "design: parameters must be a non-empty table ([design.parameters]) of "
            "name = [low, high] or name = {choices = [...]}"
        )
    fields = {f.name: f for f in param_fields(model_cls.Params)}
    params = []
    for name, spec in table.items():
        if name in ("seed", "rng"):
            raise ConfigError(
                f"design parameter {name!r} is not allowed: per-run seeds are spawned from "
                "the sweep seed"
            )
        if name not in fields:
            raise ConfigError(
                f"design parameter {name!r} is not a parameter of {model_cls.__name__}; "
                f"accepted: {', '.join(fields)}"
            )
        if name in fixed:
            raise ConfigError(f"design parameter {name!r} is also set in [grid]: set it once")
        params.append(_parameter(model_cls, fields[name], spec))
    return Design(kind, tuple(params), n, seed)


def _parameter(model_cls: type, f, spec: object) -> DesignParameter:
    """One ``name = [low, high]`` or ``name = {choices = [...]}`` entry, checked."""
    name = f.name
    if isinstance(spec, Mapping):
        if set(spec) != {"choices"}:
            raise ConfigError(
                f"design parameter {name!r}: a table must be {{choices = [...]}}, got {spec!r}"
            )
        choices = spec["choices"]
        if isinstance(choices, str) or not isinstance(choices, list) or len(choices) < 2:
            raise ConfigError(
                f"design parameter {name!r}: choices must list at least two values, got {choices!r}"
            )
        clean = tuple(_checked(model_cls, name, v, "choice") for v in choices)
        if len(set(map(repr, clean))) != len(clean):
            raise ConfigError(f"design parameter {name!r} repeats a choice: {choices!r}")
        return DesignParameter(name, 0, len(clean) - 1, True, clean)
    numbers = isinstance(spec, list) and len(spec) == 2
    numbers = numbers and all(isinstance(v, int | float) and not isinstance(v, bool) for v in spec)
    if not numbers:
        raise ConfigError(
            f"design parameter {name!r}: give a range [low, high] of two numbers or "
            f"{{choices = [...]}}, got {spec!r}"
        )
    low, high = spec
    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise ConfigError(
            f"design parameter {name!r}: range [{low}, {high}] must be finite with low < high"
        )
    integer = bool(field_rule(f).get("integer"))
    for end in (low, high):
        _checked(model_cls, name, end, f"range [{low}, {high}]")
    return DesignParameter(
        name, int(low) if integer else float(low), int(high) if integer else float(high), integer
    )


def _checked(model_cls: type, name: str, value: object, what: str) -> object:
    """``value`` as the parameter accepts it, else one line naming the design entry."""
    try:
        return check_value(model_cls.Params, name, value)
    except ConfigError as exc:
        raise ConfigError(f"design parameter {name!r} {what}: {exc}") from exc


def _as_table(design: Design) -> dict:
    """A :class:`Design`'s parameters as a ``[design.parameters]`` table."""
    return {
        p.name: {"choices": list(p.choices)} if p.choices is not None else [p.low, p.high]
        for p in design.parameters
    }
