"""What the beacon/explorer swarm does when a robot fails or a link goes down (issue 13).

The framework (:mod:`abm.faults`) has already taken a failed robot out of the air, the comm
network and the counts; here the swarm's own structures follow. A failed beacon leaves the
beacon network, whose hop-count gradients re-flood over the surviving lattice (the paper's
self-healing, App. A). With ``repair`` on, its neighbours advertise its spot as empty again
(it is not searched: the beacon did not leave because its area was done), so the next
explorer -- one still on the ground, or a beacon redeploying from a searched area -- fills the
hole; off, the neighbours take the area beyond it as searched, as for any neighbour that
leaves in the paper's controller.
"""

from models.beacon_explorer.beacon import BeaconNetwork

__all__ = ["link_fault", "robot_failed"]


def robot_failed(network: BeaconNetwork, robot: int, repair: bool) -> None:
    """Drop a failed robot from the beacon network (if it was a beacon); ``repair`` says
    whether its neighbours advertise its spot again or take the area beyond it as searched.
    """
    if robot in network.beacons:
        network.detach(robot, searched=not repair)


def link_fault(network: BeaconNetwork, a: object, b: object) -> None:
    """A link between two beacons went down or came back: the lattice follows the radio."""
    if a in network.beacons and b in network.beacons:
        network.links_changed()
