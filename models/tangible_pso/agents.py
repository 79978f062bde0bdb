"""The MAVs of Tangible PSO (Saska et al. 2016): the virtual MAVs of the particles and the
real swarm that flies the solution.

- A :class:`VirtualMAV` is one MAV of one particle's virtual swarm (Sect. 4.2, Fig. 4: a
  particle encodes the 3D positions of all n_r MAVs). Its motion is the optimiser's: every
  iteration the model moves all virtual swarms at once (eqs. 2-6 over arrays, the tangible step
  of Sect. 5 / Fig. 6), and the MAV enters the state the feasibility check gave it ("free",
  "stopped" by a swarm constraint, "blocked" at a no-fly zone). It knows its row of the model's
  arrays. Virtual MAVs never fail: they are a simulation inside the planner.
- An :class:`MAV` is one MAV of the real swarm, created when the optimisation is over if the
  model deploys (README "MAV failure during the deployment"). Its behaviour,
  :meth:`MAV.deploy`, is to fly its part of the plan with the swarm, then hover at its place.
"""

from collections.abc import Generator
from typing import TYPE_CHECKING

import numpy as np
import simpy

from abm.robot import Robot

if TYPE_CHECKING:
    from models.tangible_pso.model import TangiblePSOModel

__all__ = ["MAV", "VirtualMAV"]


class VirtualMAV(Robot):
    """MAV ``index`` (i) of the virtual swarm of particle ``particle`` (j) (Sect. 4.2, Fig. 4).

    Attributes:
        particle: j, the particle (virtual swarm) it belongs to.
        index: i, its MAV in that swarm (0 .. n_r - 1).
        row: ``j * n_r + i``, its row of the model's particle arrays flattened to MAVs
            (``model.x.reshape(-1, 3)``); the virtual MAVs are created in row order.

    Args:
        model: the tangible-PSO model.
        particle: j.
        index: i.
        position: where it starts (x, y) (m); its altitude is the model's (``model.x``).

    """

    def __init__(
        self, model: "TangiblePSOModel", particle: int, index: int, position: np.ndarray
    ) -> None:
        super().__init__(model, position, "free", "fly")
        self.particle = particle
        self.index = index
        self.row = particle * model.params.n_mavs + index
        model.faults.exempt(self)  # a simulated MAV inside the planner: only real MAVs fail


class MAV(Robot):
    """MAV ``row`` (i) of the real swarm, deployed after the optimisation (Sect. 5-6).

    Attributes:
        row: i, its MAV of the best particle: its column of the plan (``model.history[t][g][i]``)
            and its row of the deployment's arrays (``model.deployed``, the trace's positions).

    Args:
        model: the tangible-PSO model.
        row: i.
        position: where it starts (x, y) (m): the best particle's first position of MAV i.

    """

    def __init__(self, model: "TangiblePSOModel", row: int, position: np.ndarray) -> None:
        super().__init__(model, position, "deploying", "fly")
        self.row = row

    def deploy(self, flight: simpy.Process) -> Generator:
        """Fly its part of the plan with the swarm, then hover at its place: "deployed".

        The plan is the best particle's history, a feasible trajectory for every MAV (Sect. 5);
        each MAV's position controller follows its own (Sect. 6, Fig. 7). The swarm flies the
        transitions together (``flight``, the model's process: one leg per transition for the
        whole swarm, and one stop and replanning for all when an MAV fails,
        :mod:`models.tangible_pso.deployment`), so the MAV's own story is to stay with it until
        every transition is flown. A failure ends this behaviour where the MAV is (the fault
        injector interrupts it): a failed MAV does nothing more.

        Args:
            flight: the swarm's flight of the plan.

        """
        yield flight
        self.set_state("deployed")
