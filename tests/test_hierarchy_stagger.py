"""Staggered subtree transits (``subtree_transits``, issue 30): the queen sends her workers'
subtrees into their new bubbles one at a time, read from the message log in the order it was
sent; the default keeps the report's order (every subtree at once); a bad value is refused."""

import pandas as pd
import pytest

from abm.errors import ConfigError
from analysis.cli import main
from models.hierarchy import HierarchyModel
from models.hierarchy.model import QUEEN

#: Three workers of three scouts in a 6 m room: a few seconds per run, several queen rounds.
SMALL = dict(workers=3, scouts_per_worker=3, world_size=6.0, worker_spacing=1.6)


@pytest.fixture(scope="module", params=["together", "staggered"])
def run(request):
    return HierarchyModel(seed=830101, subtree_transits=request.param, **SMALL).run()


def transits(log: pd.DataFrame) -> list[tuple[object, int, int]]:
    """Every subtree transit as (worker, first row, last row) of the message log: from the
    queen's SCAN to the worker until the worker first orders a scout to scan (its scouts have
    driven into the new bubble) or reports the bubble done without a round.
    """
    log = log.reset_index(drop=True)
    out = []
    for row in log.index[(log["src"] == QUEEN) & (log["kind"] == "SCAN")]:
        worker = log.at[row, "dst"]
        after = log.loc[row + 1 :]
        ends = after[
            (after["src"] == worker)
            & (
                ((after["kind"] == "SCAN") & (after["dst"] != QUEEN))
                | (after["kind"] == "MAP_REPORT")
            )
        ]
        out.append((worker, row, int(ends.index[0])))
    return out


def overlapping(spans: list[tuple[object, int, int]]) -> int:
    """Pairs of transits of different workers whose spans of log rows overlap."""
    return sum(
        a[0] != b[0] and a[1] < b[2] and b[1] < a[2]
        for i, a in enumerate(spans)
        for b in spans[i + 1 :]
    )


def test_staggered_transits_never_overlap_while_the_reports_do(run):
    log = run.comms.log.frame()
    spans = transits(log)
    assert len(spans) >= 6  # several queen rounds of three workers
    if run.params.subtree_transits == "staggered":
        assert overlapping(spans) == 0
        # the queen moves no other worker while a subtree transits
        moves = log.reset_index(drop=True)
        moves = moves.index[(moves["src"] == QUEEN) & (moves["kind"] == "MOVE")]
        assert not any(a < m < b for _, a, b in spans for m in moves)
    else:
        assert overlapping(spans) > 0


def test_each_worker_bubble_is_answered_by_one_settled_only_when_staggered(run):
    log = run.comms.log.frame()
    scans = log[(log["src"] == QUEEN) & (log["kind"] == "SCAN")]
    settled = log[log["kind"] == "SETTLED"]
    summary = run.summary()
    if run.params.subtree_transits == "staggered":
        assert (settled["dst"] == QUEEN).all()
        assert settled["src"].value_counts().to_dict() == scans["dst"].value_counts().to_dict()
        assert summary["msg_SETTLED"] == len(settled)
    else:
        assert settled.empty and "msg_SETTLED" not in summary


def test_staggered_transits_do_the_same_work_to_completion(run):
    summary = run.summary()
    assert summary["end_reason"] in ("complete", "cannot_complete")
    assert summary["known_free_fraction"] > 0.99


def test_a_bad_value_or_a_topology_without_subtrees_is_refused(capsys):
    with pytest.raises(ConfigError, match="subtree_transits"):
        HierarchyModel(subtree_transits="serial")
    with pytest.raises(ConfigError, match="subtree_transits='staggered' needs topology='hst'"):
        HierarchyModel(subtree_transits="staggered", topology="star")
    assert main(["run", "hierarchy", "--subtree-transits", "serial"]) != 0
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--subtree-transits" in err and "staggered" in err


def test_with_assign_the_queen_waits_for_each_settled_before_the_next_order():
    m = HierarchyModel(seed=830102, subtree_transits="staggered", combine_move_scan=True, **SMALL)
    log = m.run().comms.log.frame()
    orders = log[(log["src"] == QUEEN) & log["kind"].isin(["ASSIGN", "SCAN"])]
    assert (orders["kind"] == "ASSIGN").sum() > 3
    waiting = None  # the worker whose SETTLED the queen waits for
    for src, dst, kind in zip(log["src"], log["dst"], log["kind"], strict=True):
        if src == QUEEN and kind in ("ASSIGN", "SCAN", "MOVE"):
            assert waiting in (None, dst), f"{kind} to {dst} while {waiting} transits"
            waiting = dst if kind != "MOVE" else waiting
        if kind == "SETTLED":
            assert src == waiting
            waiting = None
