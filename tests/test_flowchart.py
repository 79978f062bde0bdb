"""The beacon controller of Fig. 2 as a pure function: hand-made sensings, no SimPy."""

from hypothesis import given, settings
from hypothesis import strategies as st

from models.beacon_explorer.flowchart import (
    DIRECTIONS,
    EAST,
    NO_DIRECTION,
    NORTH,
    SOUTH,
    WEST,
    Neighbour,
    Sensing,
    decide,
)

CORRIDOR_EW = (True, False, True, False)  # walls north and south: an east-west corridor


def sensing(**kw) -> Sensing:
    base = {"corridor": True, "walls": CORRIDOR_EW, "neighbours": {}, "taken": frozenset(),
            "searched": frozenset(), "forwards": 3, "reverse": 0, "is_base": False}  # fmt: skip
    return Sensing(**{**base, **kw})


def test_a_deploying_beacon_points_to_the_first_empty_direction_clockwise_from_north():
    d = decide(sensing(neighbours={WEST: Neighbour(2, 0, EAST)}))
    assert d.desired == EAST and d.frontier and not d.redeploying and not d.may_detach
    d = decide(sensing(corridor=False, walls=(False,) * 4, neighbours={}))
    assert d.desired == NORTH and d.frontier


def test_a_dead_end_redeploys_and_may_detach_back_towards_the_base():
    dead_end = (True, True, True, False)  # only west open, where the lower neighbour is
    d = decide(sensing(walls=dead_end, neighbours={WEST: Neighbour(2, 0, EAST)}))
    assert d.redeploying and not d.frontier and d.may_detach
    assert d.desired == WEST  # redeployment: the neighbour with the lowest forwards count


def test_the_base_never_detaches_and_a_higher_neighbour_keeps_a_beacon():
    dead_end = (True, True, True, False)
    d = decide(sensing(walls=dead_end, neighbours={WEST: Neighbour(2, 0, EAST)}, is_base=True))
    assert d.redeploying and not d.may_detach
    d = decide(sensing(walls=dead_end, neighbours={WEST: Neighbour(4, 0, NO_DIRECTION)}))
    assert not d.redeploying  # a way onward (higher neighbour, not blocked) is still open
    assert d.desired == WEST


def test_a_corridor_beacon_remembers_a_searched_branch():
    """The neighbour east is higher and points back west: the branch beyond it is searched."""
    nb = {WEST: Neighbour(2, 0, EAST), EAST: Neighbour(4, 0, WEST)}
    d = decide(sensing(neighbours=nb))
    assert EAST in d.searched and d.redeploying and d.may_detach is False  # east is higher
    assert d.desired == WEST


def test_a_spot_another_beacon_fills_is_not_advertised():
    open_room = (False,) * 4
    d = decide(sensing(corridor=False, walls=open_room, taken=frozenset({NORTH, EAST})))
    assert d.desired == SOUTH and d.frontier


def test_open_space_redeploys_on_a_zero_reverse_count_only():
    nb = {SOUTH: Neighbour(2, 5, NORTH)}
    room = (False, True, False, True)
    searched = frozenset({NORTH})
    assert decide(sensing(corridor=False, walls=room, neighbours=nb, searched=searched,
                          reverse=0)).redeploying  # fmt: skip
    kept = decide(sensing(corridor=False, walls=room, neighbours=nb, searched=searched, reverse=4))
    assert not kept.redeploying and kept.desired == SOUTH  # towards the higher reverse count


@settings(max_examples=300, deadline=None)
@given(
    corridor=st.booleans(),
    walls=st.tuples(*[st.booleans()] * 4),
    present=st.sets(st.sampled_from(DIRECTIONS)),
    counts=st.lists(
        st.tuples(st.integers(0, 9), st.integers(0, 9), st.integers(-1, 3)), min_size=4, max_size=4
    ),  # fmt: skip
    taken=st.sets(st.sampled_from(DIRECTIONS)),
    searched=st.sets(st.sampled_from(DIRECTIONS)),
    forwards=st.integers(0, 9),
    reverse=st.integers(0, 9),
    is_base=st.booleans(),
)
def test_decisions_keep_the_flowcharts_invariants(
    corridor, walls, present, counts, taken, searched, forwards, reverse, is_base
):
    nb = {d: Neighbour(*counts[d]) for d in present}
    s = Sensing(corridor, walls, nb, frozenset(taken), frozenset(searched), forwards, reverse,
                is_base)  # fmt: skip
    d = decide(s)
    assert set(searched) <= d.searched  # memory only grows
    assert d.desired in (NO_DIRECTION, *DIRECTIONS)
    assert not (d.redeploying and d.frontier)  # an empty direction means deployment
    if d.may_detach:
        assert d.redeploying and not is_base and all(n.forwards <= forwards for n in nb.values())
    if d.frontier:  # it points at an empty direction
        assert d.desired not in nb and d.desired not in taken and not walls[d.desired]
    elif d.desired != NO_DIRECTION:
        assert d.desired in nb  # otherwise it can only point at a neighbour
    assert decide(s) == d  # pure: the same inputs, the same decision
