"""The robots of the beacon/explorer swarm (Stirling et al. 2010, Sect. 3.2).

"All robots operate in one of two control states: beacons and explorers." One robot flies as
an explorer, attaches and serves as a beacon, and may detach and explore again, so one class,
:class:`SwarmRobot`, holds both roles' behaviour and its ``state`` ("ground", "explorer",
"beacon") says which role it plays now. The pre-deployed base beacon is a class of its own,
:class:`BaseBeacon`: it is powered, never moves, never fails, and the forwards hop counts start
from it.

What every robot does at each control step is vectorised over all of them: the explorers'
steering (Fig. 4) in :mod:`models.beacon_explorer.explorer`, the beacons' flowchart (Fig. 2)
in :mod:`models.beacon_explorer.beacon`. Here is each robot's story between those steps.
"""

from collections.abc import Generator
from typing import TYPE_CHECKING

import numpy as np
import simpy

from abm.robot import Robot

if TYPE_CHECKING:
    from models.beacon_explorer.model import BeaconExplorerModel

__all__ = ["BaseBeacon", "SwarmRobot"]

#: A robot behaviour: a SimPy generator of the events it waits on.
Behaviour = Generator[simpy.Event, object, None]


class BaseBeacon(Robot):
    """The pre-deployed base beacon at the entrance (Sect. 3.2): a beacon from the start.

    It is the powered base station: no battery limit (see ``battery_capacity``) and exempt
    from faults. It has no behaviour of its own: the beacon network runs its flowchart.

    Args:
        model: the swarm.
        position: where it hangs (m); the explorers wait on the ground below it.

    """

    def __init__(self, model: "BeaconExplorerModel", position: np.ndarray) -> None:
        super().__init__(model, position, "beacon", model.beacon_mode)
        if model.battery is not None:
            model.battery.exempt(self.unique_id)
        model.faults.exempt(self)


class SwarmRobot(Robot):
    """One of the N searching robots: an explorer that becomes a beacon, and may redeploy.

    Attributes:
        index: its ID i in 1..N (Sect. 3.4.1): it takes off at i times the inter-launch
            period t.
        guide: robot id of the beacon whose advertised spot it last stopped at to attach (set
            by the explorer controller; None before its first stop).

    Args:
        model: the swarm.
        position: where it waits on the ground (below the base beacon, m).
        index: its ID i in 1..N.

    """

    def __init__(self, model: "BeaconExplorerModel", position: np.ndarray, index: int) -> None:
        super().__init__(model, position, "ground", "ground")
        self.index = index
        self.guide: int | None = None

    def search(self) -> Behaviour:
        """The robot's whole story: take off, then explore and serve as a beacon in turn.

        Sect. 3.4 and Fig. 4 (explorers), Sect. 3.3 "Redeployment phase" (beacons revert to
        explorers). A failure or a flat battery ends it wherever it is (``Robot.start``).
        """
        yield from self.take_off()
        model = self.model
        position = model.world.start + model.rng.normal(0.0, 0.1, 2)
        position = np.where(model.arena.is_free(position[None])[0], position, model.world.start)
        while True:
            position = yield from self.explore(position)
            yield from self.serve_as_beacon(position)

    def take_off(self) -> Behaviour:
        """Temporal incremental deployment (Sect. 3.4.1): wait on the ground until i * t,
        then take off and ascend to the flying altitude.
        """
        model = self.model
        yield self.env.timeout(self.index * model.launch_period)
        self.set_state("explorer")
        self.set_mode("flight")
        model.recorder.log("launch", self.unique_id)
        yield self.env.timeout(model.params.climb_time)

    def explore(self, position: np.ndarray) -> Generator[simpy.Event, object, np.ndarray]:
        """Fly from ``position`` following the beacons' desired directions (Fig. 4) until
        |T| <= eps at a spot no other beacon holds; returns that spot.

        The steering itself is the explorer controller's, for all flyers at once; it ends
        this robot's flight at a spot where a beacon is required. The robot then ascends to
        the ceiling (``attach_time``); when another beacon already holds the spot (one
        attached first, or its advertiser cannot see it behind a pillar) it tells the
        advertiser (``report_taken``) and flies on.
        """
        model = self.model
        p = model.params
        while True:
            yield model.physics.fly(self.unique_id, position)
            position = self.position.copy()
            yield self.env.timeout(p.attach_time)
            if not self._beacon_near(position, p.interspace / 2):
                return position
            if p.report_taken:
                model.beacons.spot_reported_taken(self.guide, position)

    def serve_as_beacon(self, position: np.ndarray) -> Behaviour:
        """Attach at ``position`` and serve as a beacon until free to redeploy, then detach
        and be an explorer again (Sect. 3.3, "Redeployment phase").

        A beacon in the redeployment phase may detach once all its neighbours have a lower or
        equal forwards hop count; it then waits one inter-launch period and detaches only if
        it is still free to and no explorer is near (else it waits again).
        """
        model = self.model
        network = model.beacons
        self.set_state("beacon")
        self.set_mode(model.beacon_mode)
        model.beacon_attached(self, position)
        while True:
            yield network.free_to_detach(self.unique_id)
            yield self.env.timeout(model.launch_period)
            beacon = network.beacons[self.unique_id]
            if beacon.may_detach and not self._explorer_near(beacon.position):
                break
        network.detach(self.unique_id)
        self.set_state("explorer")
        self.set_mode("flight")
        model.recorder.log("detach", self.unique_id)

    def _beacon_near(self, position: np.ndarray, radius: float) -> bool:
        """Some beacon hangs within ``radius`` (m) of ``position``."""
        _ids, pos, _vectors, _to_empty = self.model.beacons.signals()
        return bool((np.hypot(*(pos - position).T) < radius).any())

    def _explorer_near(self, position: np.ndarray) -> bool:
        """Some explorer flies within I_r of ``position`` (a detaching beacon would risk a
        collision with it).
        """
        physics = self.model.physics
        if physics.n_flying == 0:
            return False
        d = np.hypot(*(physics.pos - position).T)
        return bool((d < self.model.params.interspace).any())
