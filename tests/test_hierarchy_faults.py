"""The hierarchical swarm with failing workers: the failed worker does nothing more, its
orphaned scouts re-attach to the queen through the tree's links, every message still travels
over a parent/child link of the tree as it stood when it was sent, and the coverage goes on."""

import pandas as pd
import pytest

from abm.errors import ConfigError
from models.hierarchy import HierarchyModel
from models.hierarchy.agents import Scout, Worker
from models.hierarchy.params import WORKER_STATES

#: The contract tests' small set-up: 2 workers x 2 scouts in a 4 m room (about 120 s).
SMALL = {"workers": 2, "scouts_per_worker": 2, "world_size": 4.0, "worker_spacing": 1.6}


def _run(seed: int, **faults) -> HierarchyModel:
    return HierarchyModel(seed=seed, **SMALL, **faults).run()


def _tree_edges_at_start(model: HierarchyModel) -> tuple[set, pd.DataFrame]:
    """The tree's links at the start (the operator's START to the queen included), and the
    re-attachments (time, robot, old parent) that changed it."""
    events = model.events()
    moves = events.loc[events["event"] == "reattach", ["time", "robot", "old_parent"]]
    workers = model.agents_by_type[Worker]
    start = {("operator", "queen")} | {("queen", str(w.id)) for w in workers}
    for w in workers:
        left = moves.loc[moves["old_parent"] == w.id, "robot"].astype(int).tolist()
        start |= {(str(w.id), str(s)) for s in [*model.tree.children(w.id), *left]}
    return start, moves


@pytest.mark.parametrize("at", [20.0, 60.0])
def test_every_message_uses_a_tree_link_of_its_time_and_orphans_join_the_queen(at):
    m = _run(1, fault_times=(at,), fault_states=WORKER_STATES)
    start, moves = _tree_edges_at_start(m)
    assert len(moves) == SMALL["scouts_per_worker"]
    joined = {str(int(r)): t for r, t in zip(moves["robot"], moves["time"], strict=True)}
    left = {str(int(r)): str(o) for r, o in zip(moves["robot"], moves["old_parent"], strict=True)}
    log = m.comms.log.frame()
    assert len(log) > 0
    for t, src, dst in zip(
        log["time"], log["src"].astype(str), log["dst"].astype(str), strict=True
    ):
        pair = {src, dst}
        legal_then = {frozenset(e) for e in start}
        for scout, when in joined.items():
            if t > when:
                legal_then.discard(frozenset((left[scout], scout)))
            if t >= when:
                legal_then.add(frozenset(("queen", scout)))
        assert frozenset(pair) in legal_then, (t, src, dst)
    # after re-attaching, the queen places the orphans herself
    bubbles = m.events()
    placed = bubbles[(bubbles["event"] == "bubble") & (bubbles["director"] == "queen")]
    assert set(joined) <= set(placed["child"].astype(str))


def test_the_failed_worker_does_nothing_more_and_the_coverage_goes_on():
    m = _run(2, fault_times=(30.0,))
    events = m.events()
    (worker,) = events.loc[events["event"] == "fault", "robot"].astype(int)
    fault_row = events.index[(events["event"] == "fault")][0]
    after = events.loc[fault_row + 1 :]
    mine = after[after["robot"] == worker]
    assert mine[~((mine["event"] == "state") & (mine["state"] == "failed"))].empty
    log = m.comms.log.frame()
    assert not ((log["src"] == worker) & (log["time"] > 30.0)).any()
    s = m.summary()
    assert s["end_reason"] in ("complete", "cannot_complete")
    assert s["known_free_fraction"] >= 0.995
    assert s["workers_failed"] == 1 and s["reattached"] == SMALL["scouts_per_worker"]


@pytest.mark.parametrize("seed", [3, 4])
def test_counts_are_conserved_under_random_worker_failures(seed):
    m = _run(seed, fault_rate=0.02)  # a scout is exempt: only workers fail
    assert not any(s.failed for s in m.agents_by_type[Scout])
    counts = m.state_counts()
    robots = SMALL["workers"] * (1 + SMALL["scouts_per_worker"])
    assert (counts[list(m.STATES)].sum(axis=1) == robots).all()
    assert counts["failed"].iloc[-1] == m.summary()["workers_failed"] > 0


def test_same_seed_with_faults_gives_the_same_event_and_message_logs():
    a, b = _run(5, fault_rate=0.02), _run(5, fault_rate=0.02)
    assert a.summary()["workers_failed"] > 0
    pd.testing.assert_frame_equal(a.events(), b.events())
    pd.testing.assert_frame_equal(a.comms.log.frame(), b.comms.log.frame())


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"fault_rate": 1e-3, "fault_states": ("scout_idle",)}, "fault_states"),
        ({"fault_rate": 1e-3, "fault_states": WORKER_STATES, "topology": "ring"}, "topology"),
        ({"heartbeat_timeout": 0.0}, "heartbeat_timeout"),
    ],
)
def test_faults_the_model_does_not_handle_are_refused(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        HierarchyModel(**kwargs)
