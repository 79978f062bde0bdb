"""Fuzzing sweep files: malformed TOML, wrong keys, wrong types, empty and huge grids, names,
encodings and ``module:Class`` targets. Each file must load and plan (and its first run build
and run briefly), or raise ConfigError naming the file; an accepted name is a plain folder name
and a refused target is never imported.
"""

import json
import math
import os
import string
import sys
from pathlib import Path

import pytest
from fuzzing import case, examples
from hypothesis import given
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.params import field_rule, param_fields
from abm.registry import model_class, model_names
from analysis.sweep import load_sweep, plan
from analysis.sweep.spec import MAX_RUNS, TOML_KEYS

#: Simulated time the first run of an accepted file runs (s).
SHORT = 2.0
#: Accepted files with at most this many runs are planned in full (planning takes ~0.1 ms a run).
PLANNED = 2000

FIELDS = sorted({f.name for m in model_names() for f in param_fields(model_class(m).Params)})
CHOICES = sorted({c for m in model_names() for f in param_fields(model_class(m).Params)
                  for c in (field_rule(f).get("choices") or ()) if c is not None})  # fmt: skip


def toml_value(value) -> str:
    """``value`` written as TOML (strings as JSON strings, which TOML reads the same)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(
            value) else repr(value)  # fmt: skip
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, dict):  # an inline table (a design's parameters)
        return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    return "[" + ", ".join(toml_value(v) for v in value) + "]"


def toml_text(doc: dict) -> str:
    """A document of scalars, lists, one ``[grid]`` table and ``[[points]]`` tables."""
    lines = []
    tables = {}
    for key, value in doc.items():
        if isinstance(value, dict) or (isinstance(value, list) and value and
                                       all(isinstance(v, dict) for v in value)):  # fmt: skip
            tables[key] = value
        else:
            lines.append(f"{json.dumps(key)} = {toml_value(value)}")
    for key, value in tables.items():
        for table in value if isinstance(value, list) else [value]:
            lines.append(f"[[{json.dumps(key)}]]" if isinstance(value, list) else f"[{key}]")
            lines += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


SCALARS = st.one_of(
    st.booleans(),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.integers(min_value=-2, max_value=40),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=0.0, max_value=100.0),
    st.text(max_size=6),
    st.sampled_from(["corridor", "open", "hall100", "", *CHOICES]),
)
VALUES = st.one_of(
    SCALARS,
    st.lists(SCALARS, max_size=4),
    st.lists(st.floats(0.5, 1e4), min_size=20, max_size=60, unique=True),  # huge grids
)
KEYS = st.one_of(st.sampled_from(FIELDS), st.sampled_from(["seed", "rng", "wings"]),
                 st.text(string.ascii_lowercase + "_", min_size=1, max_size=8))  # fmt: skip
GRID = st.dictionaries(KEYS, VALUES, max_size=5)
#: Targets whose import would print (``this``), open a browser (``antigravity``) or fail.
TARGETS = ["this:X", "antigravity:X", "no.such.module:X", "models.beacon_explorer:Nope", ":X",
           "x:", "models.beacon_explorer:BeaconExplorerModel", "os.path:join.x"]  # fmt: skip
#: A ``[design]`` table: kinds, sizes, seeds and parameters (ranges, choices, junk).
DESIGN = st.fixed_dictionaries(
    {},
    optional={
        "kind": st.one_of(st.sampled_from(["sobol", "morris", "lhs"]), SCALARS),
        "n": st.one_of(st.integers(0, 40), SCALARS),
        "seed": SCALARS,
        "parameters": st.one_of(
            st.dictionaries(KEYS, st.one_of(VALUES, st.fixed_dictionaries({"choices": VALUES})),
                            max_size=4),
            SCALARS,
        ),
        "levels": SCALARS,
    },
)  # fmt: skip
DOCS = st.fixed_dictionaries(
    {},
    optional={
        "model": st.one_of(st.sampled_from(model_names()), st.sampled_from(TARGETS), SCALARS),
        "seed": SCALARS,
        "replications": st.one_of(SCALARS, st.integers(1, 3)),
        "name": SCALARS,
        "description": SCALARS,
        "time_series": SCALARS,
        "grid": st.one_of(GRID, SCALARS),
        "points": st.one_of(st.lists(GRID, max_size=3), SCALARS),
        "design": st.one_of(DESIGN, SCALARS),
        **{k: SCALARS for k in ("replication", "grids", "models")},
    },
)


def _plausible(field) -> st.SearchStrategy:
    """Values a user would likely write for ``field``: its default, its choices, numbers near
    the default, small numbers."""
    default = field.default
    near = []
    if isinstance(default, int | float) and not isinstance(default, bool):
        near = [st.sampled_from([default * 0.5, default * 2.0, default + 1])]
    choices = [c for c in (field_rule(field).get("choices") or ()) if c is not None]
    own = [st.sampled_from(choices)] if choices else []
    plain = [st.just(default)] if isinstance(default, bool | int | float | str) else []
    return st.one_of(*plain, *own, *near, st.integers(0, 5), st.floats(0.0, 10.0))


def _plausible_doc(model: str) -> st.SearchStrategy:
    fields = {f.name: f for f in param_fields(model_class(model).Params)}
    keys = st.lists(st.sampled_from(sorted(fields)), min_size=1, max_size=3, unique=True)
    grid = keys.flatmap(lambda ks: st.fixed_dictionaries(
        {k: st.lists(_plausible(fields[k]), min_size=1, max_size=3) for k in ks}))  # fmt: skip
    return st.fixed_dictionaries(
        {"model": st.just(model), "grid": grid},
        optional={"seed": st.integers(0, 100), "replications": st.integers(1, 3),
                  "time_series": st.booleans()},
    )  # fmt: skip


PLAUSIBLE = st.sampled_from(model_names()).flatmap(_plausible_doc)


def _damaged(text: str, cut: int, junk: str) -> str:
    """``text`` cut short at ``cut`` and ``junk`` spliced in there."""
    return text[: cut % (len(text) + 1)] + junk


def _check_file(path: Path, target: str = "sweep-file") -> None:
    names = [str(path)]
    with case(target, names):
        sweep = load_sweep(path)
        names += [*sweep.grid, *(k for p in sweep.points for k in p)]  # a run's error names one
        if sweep.n_runs <= PLANNED:
            specs = plan(sweep)
            assert len(specs) == sweep.n_runs and len({s.run_id for s in specs}) == len(specs)
            first = sweep.model_cls(seed=specs[0].seed, **specs[0].params)
            first.run(until=min(SHORT, first.params.time_limit))


@examples(150)
@given(doc=DOCS)
def test_fuzzed_sweep_files_load_or_raise_config_error_naming_the_file(tmp_path_factory, doc):
    path = tmp_path_factory.mktemp("toml") / "fuzzed.toml"
    path.write_text(toml_text(doc))
    _check_file(path)


@examples(120)
@given(doc=PLAUSIBLE)
def test_plausible_sweep_files_load_or_raise_config_error_naming_the_file(tmp_path_factory, doc):
    path = tmp_path_factory.mktemp("toml") / "plausible.toml"
    path.write_text(toml_text(doc))
    _check_file(path)


SMOKE = (
    'model = "beacon-explorer"\nseed = 7\nreplications = 2\n[grid]\nworld = ["corridor"]\n'
    'complexity = ["low", "high"]\nlaunch_period = [6.0, 24.0]\ntime_limit = [60.0]\n'
)


@examples(60)
@given(cut=st.integers(0, 10**4), junk=st.text(max_size=12))
def test_cut_and_spliced_sweep_files_load_or_raise_config_error(tmp_path_factory, cut, junk):
    path = tmp_path_factory.mktemp("toml") / "damaged.toml"
    path.write_text(_damaged(SMOKE, cut, junk))
    _check_file(path)


# Regression tests: one per defect the fuzzing found.
@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('model = "beacon-explorer"\nreplications = 1000000000000\n[grid]\nworld = ["open"]\n',
         "at most 1e\\+06 in one sweep"),
        ('model = "beacon-explorer"\n[grid]\n'
         + "".join(f"{k} = {list(range(1, 40))}\n" for k in ("n_robots", "stall_collisions",
                                                            "reverse_start", "forwards_start")),
         "at most 1e\\+06 in one sweep"),
        ('model = "beacon-explorer"\n[grid]\n'
         + "".join(f"{k} = {[float(v) for v in range(1, 61)]}\n" for k in (
             "interspace", "sensor_range", "reference_range", "comm_range", "obstacle_threshold",
             "open_diagonal", "spot_taken", "attach_eps", "attach_speed", "filter_time",
             "slow_radius")),
         "the sweep has 3.63e\\+19 runs"),  # np.prod overflowed int64 here
    ],
)  # fmt: skip
def test_fuzz_findings_in_sweep_files(tmp_path, text, match):
    path = tmp_path / "found.toml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match):
        load_sweep(path)


def test_the_largest_sweep_allowed_is_accepted(tmp_path):
    path = tmp_path / "big.toml"
    path.write_text(f'model = "beacon-explorer"\nreplications = {MAX_RUNS}\n[grid]\n'
                    'world = ["open"]\n')  # fmt: skip
    assert load_sweep(path).n_runs == MAX_RUNS


#: Names a user might try, traversal included.
NAMES = st.one_of(
    st.text(max_size=12),
    st.text(string.ascii_letters + string.digits + "-_./\\~ ", max_size=12),
    st.sampled_from(["", ".", "..", "/tmp/x", "../../../tmp/x", "a/../b", "~", "-", "a..b",
                     "x" * 100, "x" * 101, "C:\\x", "name\u00e9"]),
)  # fmt: skip


@examples(150)
@given(name=NAMES)
def test_fuzzed_sweep_names_are_plain_folder_names_or_refused(tmp_path_factory, name):
    path = tmp_path_factory.mktemp("toml") / "named.toml"
    path.write_text(f"name = {json.dumps(name)}\n" + SMOKE)
    with case("sweep-name", [str(path)]):
        sweep = load_sweep(path)
        base = "/base/out/sweeps"
        folder = os.path.normpath(os.path.join(base, sweep.name))
        assert os.path.dirname(folder) == base and not sweep.name.startswith(".")


ENCODINGS = ["utf-8", "utf-8-sig", "utf-16", "utf-32", "latin-1", "cp1252", "shift_jis"]


@examples(100)
@given(text=st.text(max_size=16), encoding=st.sampled_from(ENCODINGS),
       junk=st.binary(max_size=6), at=st.integers(0, 300))  # fmt: skip
def test_sweep_files_in_any_encoding_load_or_raise_config_error(
    tmp_path_factory, text, encoding, junk, at
):
    doc = f"description = {json.dumps(text, ensure_ascii=False)}\n" + SMOKE
    data = doc.encode(encoding, errors="replace")
    path = tmp_path_factory.mktemp("toml") / "encoded.toml"
    path.write_bytes(data[:at] + junk + data[at:])
    _check_file(path, "sweep-encoding")


def test_refused_targets_were_never_imported():
    assert "this" not in sys.modules and "antigravity" not in sys.modules


def test_every_sweep_file_key_is_fuzzed():
    assert set(TOML_KEYS) <= set(DOCS.wrapped_strategy.optional) | {"grid", "points"}
