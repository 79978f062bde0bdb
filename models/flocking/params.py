"""Parameters of the flocking model: the ABMFrameworksComparison Flocking declaration.

Every constant of the declaration (JuliaDynamics/ABMFrameworksComparison, ``Flocking/
DECLARATION.md``, "Technical implementation") is a field; the defaults are its *small* case
(200 birds, 100 x 100, visual distance 5). :data:`LARGE` holds its *large* case.
"""

from dataclasses import dataclass

from abm.errors import ConfigError
from abm.params import SwarmParams, param

__all__ = ["LARGE", "SMALL", "FlockingParams"]


@dataclass(frozen=True)
class FlockingParams(SwarmParams):
    """Boids on a periodic square, updated one by one in a new random order each step.

    Lengths are in metres and one update step takes ``dt`` seconds, so the declaration's
    "moves ``speed`` along its velocity each step" is a move of ``speed * dt``; with the
    default ``dt`` = 1 s one step is one second of the SimPy clock.

    Attributes:
        birds: number of birds N (declaration: 200 small, 400 large).
        extent: side of the periodic square space (m; declaration: 100 small, 150 large).
        visual_distance: radius within which a bird sees its neighbours (m, distance <= it
            counts; declaration: 5 small, 15 large).
        speed: distance a bird moves per second along its unit velocity (m/s; declaration 1.0
            per step).
        separation: neighbours closer than this are pushed away from (m; declaration 1.0).
        cohere_factor: weight of the mean offset to the neighbours (declaration 0.03).
        separate_factor: weight of minus the mean offset to neighbours closer than separation
            (declaration 0.015).
        match_factor: weight of the neighbours' mean velocity (declaration 0.05).
        steps: update steps in one run (declaration: exactly 100).
        dt: simulated time of one update step, one tick of the SimPy clock (s; ours).
        step_duration: simulated time one Mesa ``step()`` advances (s; one update step).
        time_limit: the run ends at this simulated time at the latest (s; ``steps * dt``
            ends it first with the defaults).
        trace_interval: how often bird positions are sampled for rendering (s); None: never
            (the timing benchmark runs without it, as the comparison records nothing).

    """

    birds: int = param(200, low=1, high=1_000_000, integer=True, shown=(10, 1000))
    extent: float = param(100.0, low=0.0, low_open=True, shown=(60.0, 300.0))
    visual_distance: float = param(5.0, low=0.0, low_open=True, shown=(1.0, 30.0))
    speed: float = param(1.0, low=0.0)
    separation: float = param(1.0, low=0.0)
    cohere_factor: float = param(0.03, low=0.0, shown=(0.0, 0.3))
    separate_factor: float = param(0.015, low=0.0, shown=(0.0, 0.3))
    match_factor: float = param(0.05, low=0.0, shown=(0.0, 0.5))
    steps: int = param(100, low=1, integer=True)
    dt: float = param(1.0, low=0.0, low_open=True)
    step_duration: float = param(1.0, low=0.0, low_open=True)
    time_limit: float = param(1.0e6, low=0.0, low_open=True)
    trace_interval: float | None = param(1.0, low=0.0, low_open=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        # On a torus a bird at more than half the side away is nearer through the other
        # edge: a larger radius would see one neighbour twice (the declaration's cases are
        # 5 of 100 and 15 of 150).
        if self.visual_distance > self.extent / 2:
            raise ConfigError(
                f"visual_distance must be at most extent / 2 = {self.extent / 2:g} m on the "
                f"periodic square, got {self.visual_distance!r}"
            )


#: The declaration's small case (the defaults).
SMALL = {"birds": 200, "extent": 100.0, "visual_distance": 5.0}
#: The declaration's large case.
LARGE = {"birds": 400, "extent": 150.0, "visual_distance": 15.0}
