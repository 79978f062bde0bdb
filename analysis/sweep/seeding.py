"""Run identities and per-run seeds of a sweep.

The ``run_id`` is a hash of the run's parameters and replication index, so a restarted sweep
recognises (and skips) runs already on disk. The per-run seed is drawn from
``numpy.random.SeedSequence(seed)`` with the spawn key ``(condition key, replication)``:
independent streams, the same for a run whatever executor runs it, unchanged when the grid
grows.

A sweep with a sensitivity design uses common random numbers instead: replication ``rep`` of
every design point runs with the same seed (spawn key ``(2**32, rep)``, outside the range of
condition keys). Two design points then differ only by their parameters, not by a fresh
random environment each (a new corridor map, new noise), which would add the model's whole
run-to-run spread to every elementary effect and every variance share.
"""

import hashlib
import json
from collections.abc import Iterator, Mapping

import numpy as np

from analysis.runner import RunSpec
from analysis.sweep.spec import Sweep

__all__ = ["COMMON_KEY", "common_seed", "iter_plan", "plan", "run_id", "spawned_seed"]

#: First spawn-key entry of a design sweep's common seeds: 2**32 is no condition key (those
#: are 32-bit hashes), so a common seed never repeats a grid run's seed.
COMMON_KEY = 2**32


def _condition_key(params: Mapping) -> str:
    return json.dumps(params, sort_keys=True, default=str)


def run_id(params: Mapping, rep: int) -> str:
    """The identity of replication ``rep`` of the grid point ``params``."""
    text = f"{_condition_key(params)}#{rep}"
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def spawned_seed(sweep_seed: int, params: Mapping, rep: int) -> tuple[int, tuple[int, int]]:
    """The run's seed: ``SeedSequence(sweep_seed)`` spawned at ``(condition key, rep)``."""
    digest = hashlib.sha256(_condition_key(params).encode()).digest()
    key = (int.from_bytes(digest[:4], "little"), int(rep))
    child = np.random.SeedSequence(sweep_seed, spawn_key=key)
    return int(child.generate_state(1, np.uint64)[0] >> np.uint64(1)), key


def common_seed(sweep_seed: int, rep: int) -> tuple[int, tuple[int, int]]:
    """The seed of replication ``rep`` of every point of a design sweep (common random
    numbers): ``SeedSequence(sweep_seed)`` spawned at ``(COMMON_KEY, rep)``.
    """
    key = (COMMON_KEY, int(rep))
    child = np.random.SeedSequence(sweep_seed, spawn_key=key)
    return int(child.generate_state(1, np.uint64)[0] >> np.uint64(1)), key


def plan(sweep: Sweep) -> list[RunSpec]:
    """Every run of the sweep, grid point by grid point, replications innermost."""
    return list(iter_plan(sweep))


def iter_plan(sweep: Sweep) -> Iterator[RunSpec]:
    """The runs of :func:`plan` one at a time (~0.1 ms each): a sweep at the 1e6-run limit
    starts its first run at once instead of planning for minutes first.
    """
    target = sweep.target
    for params in sweep.iter_conditions():
        for rep in range(sweep.replications):
            if sweep.design is not None:
                seed, key = common_seed(sweep.seed, rep)
            else:
                seed, key = spawned_seed(sweep.seed, params, rep)
            yield RunSpec(target, params, rep, seed, key, run_id(params, rep), sweep.time_series)
