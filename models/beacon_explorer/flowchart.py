"""The beacon controller of Stirling et al. (2010), Fig. 2, as one pure function.

:func:`decide` takes what a beacon has sensed and remembers (:class:`Sensing`) and returns its
decision (:class:`Decision`): the desired direction it signals, whether it is in the
redeployment phase, whether it is a frontier beacon, whether it may detach, and its updated
memory of searched directions. No clock, no network: the beacon network gathers the inputs,
calls this, and publishes the result.

1. Sensing: a corridor beacon counts a direction as searched when the neighbour there has a
   higher forwards hop count and signals a desired direction pointing back (the network keeps
   only directions whose neighbour detached in its memory, ``searched_follows_signal``). In
   corridors, searched directions and obstacles (a wall where no neighbour is) are blocked. A
   direction is empty when it holds no neighbour, no other beacon fills its spot, no wall and
   it is not searched (open-space beacons remember searched directions too; see the README).
2. Behaviour: a corridor beacon enters the redeployment phase in a dead end (enclosed, every
   neighbour lower) or when every higher-forwards neighbour is blocked, i.e. when each direction
   is blocked, taken by a beacon off its lattice, or holds a lower neighbour; an open-space
   beacon when its reverse hop count is 0. A beacon with an empty direction deploys.
3. Desired direction: while deploying, the first empty direction clockwise from North, else
   the unblocked neighbour with the highest hop count (forwards in corridors, reverse in open
   space); while redeploying (or with no such neighbour), the neighbour with the lowest forwards
   hop count.
4. A redeploying beacon (not the base) whose neighbours all have lower or equal forwards hop
   count may detach.
"""

from collections.abc import Mapping
from dataclasses import dataclass

__all__ = [
    "DIRECTIONS",
    "EAST",
    "NO_DIRECTION",
    "NORTH",
    "SOUTH",
    "WEST",
    "Decision",
    "Neighbour",
    "Sensing",
    "decide",
    "opposite",
]

NORTH, EAST, SOUTH, WEST = 0, 1, 2, 3
NO_DIRECTION = -1
DIRECTIONS = (NORTH, EAST, SOUTH, WEST)  # clockwise from North


def opposite(direction: int) -> int:
    """The direction pointing the other way."""
    return (direction + 2) % 4


@dataclass(frozen=True)
class Neighbour:
    """What a beacon reads from its lattice neighbour in one direction.

    Attributes:
        forwards: the neighbour's forwards hop count.
        reverse: the neighbour's reverse hop count.
        desired: the direction the neighbour signals (NO_DIRECTION for none).

    """

    forwards: int
    reverse: int
    desired: int


@dataclass(frozen=True)
class Sensing:
    """A beacon's inputs to the flowchart.

    Attributes:
        corridor: corridor beacon (else open-space).
        walls: obstacle sensed N, E, S, W.
        neighbours: direction -> the lattice neighbour there.
        taken: directions whose spot another sensed beacon (off the lattice) fills.
        searched: directions remembered as searched so far.
        forwards: the beacon's own forwards hop count.
        reverse: the beacon's own reverse hop count.
        is_base: the pre-deployed base beacon (never detaches).

    """

    corridor: bool
    walls: tuple[bool, bool, bool, bool]
    neighbours: Mapping[int, Neighbour]
    taken: frozenset[int]
    searched: frozenset[int]
    forwards: int
    reverse: int
    is_base: bool = False


@dataclass(frozen=True)
class Decision:
    """A beacon's outputs.

    Attributes:
        desired: the desired direction it signals (NO_DIRECTION for none).
        redeploying: in the redeployment phase.
        frontier: it has an empty direction (a source of the reverse gradient).
        may_detach: free to detach and redeploy.
        searched: the directions it counts as searched now (remembered ones and those whose
            neighbour signals back).

    """

    desired: int
    redeploying: bool
    frontier: bool
    may_detach: bool
    searched: frozenset[int]


def decide(s: Sensing) -> Decision:
    """Run the flowchart of Fig. 2 once (see the module docstring)."""
    nb = s.neighbours
    searched = set(s.searched)
    if s.corridor:
        for d, n in nb.items():
            if n.forwards > s.forwards and n.desired == opposite(d):
                searched.add(d)

    def blocked(d: int) -> bool:
        # Labels are exclusive (Fig. 3): a direction holding a beacon is "beacon", never
        # "obstacle", even when the distance sensor also sees a wall beside it.
        obstacle = s.walls[d] and d not in nb
        return s.corridor and (obstacle or d in searched)

    empty = [
        d
        for d in DIRECTIONS
        if d not in nb and d not in s.taken and not s.walls[d] and d not in searched
    ]
    if s.corridor:
        # A neighbour with an equal hop count (a diagonal link across a junction) is a way
        # onward, not a dead end; a way taken by a beacon off our lattice is that beacon's to
        # search, not ours.
        redeploying = not empty and all(
            blocked(d) or d in s.taken or (d in nb and nb[d].forwards < s.forwards)
            for d in DIRECTIONS
        )
    else:
        redeploying = not empty and s.reverse == 0
    if not redeploying and empty:
        desired = empty[0]
    else:
        desired = NO_DIRECTION
        if not redeploying:
            candidates = [
                (n.forwards if s.corridor else n.reverse, -d, d)
                for d, n in nb.items()
                if not blocked(d)
            ]
            if candidates:
                desired = max(candidates)[2]
        if desired == NO_DIRECTION and nb:
            desired = min((n.forwards, d) for d, n in nb.items())[1]
    may_detach = (
        redeploying
        and not s.is_base
        and s.forwards > 0
        and all(n.forwards <= s.forwards for n in nb.values())
    )
    return Decision(desired, redeploying, bool(empty), may_detach, frozenset(searched))
