"""Fuzzing what a run is given besides its parameters: seeds (to a model, and as command-line
text) and ``abm run --out`` targets (names in any script or in no encoding, files, folders of
other runs or other files).

A model either takes a seed or refuses it with a ConfigError naming ``seed`` and the range; the
command either runs and saves the run where it was told, or ends in one line (exit 2, no
traceback) before the run, leaving every file that was there as it was. The counts of cases
tried are printed at the end of the test session (see ``fuzzing.py``).
"""

import contextlib
import io
import os
import tempfile
from pathlib import Path

import numpy as np
import pytest
from fuzzing import COUNTS, case, examples
from hypothesis import given
from hypothesis import strategies as st

from abm.errors import SEED_MAX
from analysis.cli import main
from analysis.run_folder import load_run

TINY = ["run", "tiny", "--time-limit", "2", "--no-progress"]

_NEAR_EDGES = st.sampled_from([0, 1, SEED_MAX, SEED_MAX + 1, 2**64, -1, -(2**63)])
_INTEGERS = st.one_of(
    _NEAR_EDGES, st.integers(), st.integers(-(2**80), 2**80), st.integers(SEED_MAX - 5, 2**64)
)
_SEEDS = st.one_of(
    _INTEGERS,
    st.integers(-(2**63), 2**63 - 1).map(np.int64),
    st.integers(0, 2**64 - 1).map(np.uint64),
    st.floats(allow_nan=True),
    st.booleans(),
    st.none(),
    st.text(max_size=6),
    st.tuples(st.integers(0, 9)),
)


def _accepted(seed: object) -> bool:
    """The rule: None, or an integer (numpy's too, never a bool) in [0, 2**63 - 1]."""
    if seed is None:
        return True
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
        return False
    return 0 <= int(seed) <= SEED_MAX


@examples(300)
@given(seed=_SEEDS)
def test_fuzz_model_seeds(seed, tiny_package):
    from tiny_model import TinyModel

    with case("model seed", ["seed must be an integer in [0, 2**63 - 1] or None"]):
        try:
            model = TinyModel(seed=seed, time_limit=2.0)
        except Exception:
            assert not _accepted(seed), f"seed {seed!r} refused"
            raise
        assert _accepted(seed), f"seed {seed!r} taken"
        if seed is not None:
            assert model.seed == int(seed) and type(model.seed) is int
            expected = np.random.default_rng(int(seed)).random()
            assert np.random.default_rng(model.seed).random() == expected


_SEED_TEXT = st.one_of(
    _INTEGERS.map(str),
    st.integers(0, 2**63 - 1).map(lambda n: f" {n}"),
    st.floats().map(repr),
    st.text(max_size=8),
    st.text(alphabet="0123456789-+_ e.", min_size=1, max_size=25),
)


def _abm(args: list[str]) -> tuple[int, str, list[str]]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(args)
    return rc, out.getvalue(), err.getvalue().strip().splitlines()


def _valid_text(text: str) -> bool:
    try:
        value = int(text.strip(), 10)
    except ValueError:
        return False
    return 0 <= value <= SEED_MAX and not text.lstrip().startswith("-")


@pytest.mark.slow
@examples(40)
@given(text=_SEED_TEXT)
def test_fuzz_cli_seed_text(text, tiny_package):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        rc, printed, err = _abm([*TINY, "--out", str(out), "--seed", text])
        if rc == 0:
            assert _valid_text(text), f"--seed {text!r} taken"
            assert load_run(out).meta["seed"] == int(text)
            COUNTS["abm run --seed TEXT"]["ok"] += 1
        else:
            assert not _valid_text(text), f"--seed {text!r} refused"
            assert rc == 2 and len(err) == 1 and err[0].startswith("abm run: error: ")
            assert "--seed" in err[0] or "seed" in err[0]
            assert printed == "" and not out.exists()  # refused before the run
            COUNTS["abm run --seed TEXT"]["rejected"] += 1


#: Kinds of --out target and whether a run must be saved there.
_KINDS = {
    "new": True,
    "nested new": True,
    "empty folder": True,
    "this same run": True,
    "a file": False,
    "under a file": False,
    "another run": False,
    "other files": False,
    "name too long": False,
}
_NAMES = st.one_of(
    st.text(
        st.characters(exclude_characters="/\x00", exclude_categories=["Cs"]),
        min_size=1,
        max_size=12,
    ),  # fmt: skip
    st.binary(min_size=1, max_size=12).map(lambda b: b.replace(b"/", b"_").replace(b"\x00", b"_")),
).filter(lambda n: n not in (".", "..", b".", b".."))


def _tree(root: Path) -> dict[str, bytes | None]:
    """Every path under ``root`` and its bytes (None for a folder)."""
    return {
        os.fsencode(p.relative_to(root)).decode("latin-1"): None if p.is_dir() else p.read_bytes()
        for p in root.rglob("*")
    }


@pytest.mark.slow
@examples(40)
@given(kind=st.sampled_from(sorted(_KINDS)), name=_NAMES)
def test_fuzz_out_targets(kind, name, tiny_package):
    name = os.fsdecode(name) if isinstance(name, bytes) else name
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        target = root / name
        if kind == "nested new":
            target = root / name / name / "run"
        elif kind == "empty folder":
            target.mkdir()
        elif kind in ("this same run", "another run"):
            seed = "5" if kind == "this same run" else "6"
            assert _abm([*TINY, "--seed", seed, "--out", str(target)])[0] == 0
        elif kind == "a file":
            target.write_bytes(b"keep me")
        elif kind == "under a file":
            (root / name).write_bytes(b"keep me")
            target = root / name / "run"
        elif kind == "other files":
            target.mkdir()
            (target / "notes.txt").write_bytes(b"keep me")
        elif kind == "name too long":
            target = root / (name * 300)
        before = _tree(root)
        rc, printed, err = _abm([*TINY, "--seed", "5", "--out", str(target)])
        if _KINDS[kind]:
            assert rc == 0, f"{kind}: {err}"
            assert load_run(target).meta["seed"] == 5
            assert not [p for p in root.rglob(".*partial*")]  # no temporary folder left
            COUNTS["abm run --out TARGET"]["ok"] += 1
        else:
            assert rc == 2 and len(err) == 1 and err[0].startswith("abm run: error: "), err
            assert "Traceback" not in "".join(err)
            assert printed == "", f"{kind}: refused only after the run"
            assert _tree(root) == before, f"{kind}: files changed"
            COUNTS["abm run --out TARGET"]["rejected"] += 1
