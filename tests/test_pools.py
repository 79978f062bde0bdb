"""A pool worker settles its heap before each run (``abm.pools.settle_worker_heap``): what
lives on between runs is frozen out of the cyclic collector's sight. Runs in such a worker
must decide what they decide anywhere else, and the frozen set must stop growing (a run's own
objects must not pile up there).
"""

import gc
import importlib.util
from pathlib import Path

from abm.pools import process_pool, settle_worker_heap
from analysis.runner import run_model

_SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "event_digests.py"
_spec = importlib.util.spec_from_file_location("event_digests", _SCRIPT)
event_digests = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(event_digests)

#: Quick cases of three models, the hierarchy's first: its run leaves the most behind for the
#: next settling to collect and freeze.
CASES = ("hierarchy-1", "be-corridor-high-3", "flocking-small-1")


def _fingerprints_after_settling(cases: tuple[str, ...]) -> list[tuple[dict, dict, int]]:
    """In a pool worker: each case's digests and floats, the heap settled before each (as
    ``run_one`` does), and the number of objects frozen at that point.
    """
    out = []
    for case in cases:
        settle_worker_heap()
        out.append((*event_digests.fingerprint(case), gc.get_freeze_count()))
    return out


#: Models a run kept alive on purpose (the leak the frozen heap must show).
_KEPT: list = []


def _frozen_after_each_run(runs: int, keep_models: bool = False) -> list[int]:
    """In a pool worker: how many objects are frozen after settling before each of ``runs``
    small hierarchy runs; with ``keep_models`` each run's model is kept alive (a leak).
    """
    from models.hierarchy.model import HierarchyModel

    frozen = []
    for seed in range(runs):
        settle_worker_heap()
        frozen.append(gc.get_freeze_count())
        if keep_models:
            _KEPT.append(HierarchyModel(seed=seed, workers=2, scouts_per_worker=2).run())
        else:
            run_model("hierarchy", {"workers": 2, "scouts_per_worker": 2}, seed)
    return frozen


#: A few objects come and go from run to run (a cache filled in one run and emptied in a
#: later one: [61441, 206543, 206540, 206540, 206545, 206540] in a fresh clone, 2026-12-02);
#: a run whose model stays alive adds about 280 (``test_a_kept_model_shows_in_the_frozen_heap``).
FROZEN_SLACK = 32


def _stops_growing(frozen: list[int]) -> bool:
    """After the imports and the compiled functions (the first two runs), the frozen heap
    gains at most :data:`FROZEN_SLACK` objects over the later runs.
    """
    later = frozen[2:]
    return max(later) - later[0] <= FROZEN_SLACK


def test_runs_in_a_settled_worker_give_the_digests_on_file():
    on_file, floats_on_file = event_digests.stored(), event_digests.load_floats()
    with process_pool(1) as pool:
        results = pool.submit(_fingerprints_after_settling, CASES).result()
    for case, (digests, floats, frozen) in zip(CASES, results, strict=True):
        assert frozen > 10_000, "the worker froze nothing: the settling did not run"
        assert digests == {k: on_file[case][k] for k in digests}, case
        prefix = f"{case}/"
        stored = {k[len(prefix) :]: v for k, v in floats_on_file.items() if k.startswith(prefix)}
        assert event_digests.compare(floats, stored) == [], case


def test_the_frozen_heap_stops_growing_from_run_to_run():
    with process_pool(1) as pool:
        frozen = pool.submit(_frozen_after_each_run, 6).result()
    assert frozen[0] > 10_000
    assert _stops_growing(frozen), frozen


def test_a_kept_model_shows_in_the_frozen_heap():
    """The check above fails for runs that leak: each run's model kept alive."""
    with process_pool(1) as pool:
        frozen = pool.submit(_frozen_after_each_run, 6, True).result()
    assert not _stops_growing(frozen), frozen


def test_outside_a_pool_worker_the_heap_is_left_alone():
    before = gc.get_freeze_count()
    settle_worker_heap()
    assert gc.get_freeze_count() == before
