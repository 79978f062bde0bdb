"""The paper's parameter tuples Psi and Gamma, and how we read them.

Source: Arnaldo, Suarez, Rodriguez, Moreno (2018), "A swarm behaviour for multi-rotor UAV
deployment using virtual stigmergy" (title abridged), PLOS ONE 13(1): e0190692, Sect.
"Pheromone radius C_rb". The text of the tuples is garbled in extraction; our reading:

    Psi   = (C_dw, C_db, C_eps, C_rw, C_rb, l_i)
          = (0.03, (swarmsize - robotId) / swarmsize, 0.0001, C_rb / 2, C_rb, C_rb)
    Gamma = (r_u, ?, eta, p0, a1, a2, a3, a4)
          = (5, 5, 0.01, (5, 80), 0.2, 0.4, 0.4, 0.4)

* ``eta = 0.01`` is read *per model step of 0.5 s* (the macroscopic model's alpha5 = 0.01):
  one new robot every 50 s, which Table 1 confirms (w + b = 1 + t / 50, e.g. 239 robots at
  t = 11875 s). Read per second it would be one robot per 100 s, which Table 1 contradicts.
* The second entry of Gamma (5) has no symbol in the definition Gamma = (r_u, eta, p0, a1..a4)
  and no role in the behaviour; it is not a parameter here.
* ``swarmsize`` is the most robots a run can hold: 1 + floor(time_limit / launch period) = 301.
* The decay rate C_eps is exponential: intensity x exp(-C_eps t).
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from abm.arena import Arena
from abm.errors import ConfigError
from abm.params import SwarmParams, param

__all__ = ["DEFAULTS", "LINK_MODELS", "P0", "StigmergyParams"]

#: How a wander reads "its link quality to the swarm" (see ``link_model``).
LINK_MODELS = ("distance", "radio")
#: The radio reading's parameters and their defaults (accepted only with ``link_model="radio"``).
_RADIO_DEFAULTS = {"link_exponent": 2.0, "link_wall_loss": 0.0, "link_fading_sd": 0.0}

#: p0 of Gamma: the launch point (m) on every map of the paper.
P0 = (5.0, 80.0)


@dataclass(frozen=True)
class StigmergyParams(SwarmParams):
    """Everything a stigmergy run can vary (SI units), the paper's values unless marked "ours".

    Attributes:
        map: a built-in map name (``models.environments.MAPS``), a bitmap file (PNG/PGM/BMP/NPY,
            black = not navigable), a boolean array (True = free) or an :class:`Arena`.
        pheromone_radius: C_rb, the beacon footprint radius (m).
        wander_radius: C_rw, the radius a flying robot deposits on (m); None: C_rb / 2.
        wander_intensity: C_dw, pheromone a flying robot deposits per model step.
        decay: C_eps, exponential pheromone decay rate (1/s).
        link_threshold: l_i: a wander lands when no beacon is closer (m); None: C_rb.
        landing_offset: delta, a wander lands at l_i = C_rb - delta (m; ours, 0: the paper's
            l_i = C_rb). Table 1's beacon counts at C_rb = 10 m imply wanders land nearer the
            swarm than C_rb; this is the one number that reading needs, calibrated against
            Table 1 in the README. Excludes ``link_threshold``; must be below C_rb.
        link_model: how a wander reads its link quality to the swarm (ours; the paper says
            only that it lands when "its quality of communication with the swarm decreases
            from the established thresholds", l_i = C_rb). ``"distance"``: the nearest
            beacon's Euclidean distance reaches l_i. ``"radio"``: a received-power margin
            over the threshold, ``q = max_j [10 n log10(l_i / d_j) - L w_j] + X`` (d_j: the
            distance to beacon j, w_j: metres of wall on the line to it, X ~ N(0, sd^2) dB
            drawn per robot and check); it lands when q <= 0. With L = 0 and sd = 0 it is
            the distance rule.
        link_exponent: n, the radio's path-loss exponent (ours; ``link_model="radio"``).
        link_wall_loss: L, attenuation per metre of wall crossed (dB/m; ours, radio only).
        link_fading_sd: sd of the radio's log-normal fading (dB; ours, radio only).
        obstacle_range: r_u, obstacle detection radius (m).
        obstacle_beams: range sensors in f2's ring (ours; at most 360, one a degree); 0: every
            wall pixel within r_u pushes.
        launch_rate: eta = alpha5, new robots per model step (one per 50 s at 0.01).
        model_step: the paper's model step: headings, deposits and landing checks (s).
        start: p0, the launch point (m); None: the map's default ((5, 80) for every built-in
            map).
        a1: weight of f1, towards less pheromone.
        a2: weight of f2, away from obstacles.
        a3: weight of f3, the random walk.
        a4: size of the random increment of f3.
        f1_falloff: a pheromone reading's importance in f1 falls as 1 / distance^f1_falloff.
            The text says "decreases with the square of the distance" (2); the formula
            v / |v|^2 read literally gives 1 / distance (1).
        f1_relative: f1 reads only free pixels, each relative to the pheromone under the robot
            (ours; the paper is silent on walls). False: walls and the map's outside read as
            zero pheromone, which pulls wanders into walls and corners.
        f1_line_of_sight: f1 reads only the pixels the robot sees (walls block the pheromone
            sensor; ours, the paper is silent). False: pheromone is read through walls.
        deposit_line_of_sight: pheromone is laid only where the robot sees (walls stop it;
            ours).
        swarm_size: swarmsize in C_db; None: 1 + time_limit / launch period.
        max_speed: UAV speed (m/s).
        detection_range: sensing radius of the coverage metrics ca, cb (m).
        coverage_target: the run ends when ca reaches this fraction.
        coverage_interval: how often the wanders' views are added to ca (s; ours).
        coverage_line_of_sight: walls block the view of the coverage sensor (ours).
        ca_sample_period: spacing of the ca time series (``samples()``; s; ours), read after
            the run from when each pixel was first seen, so it costs the run nothing.
        map_resolution: metres per pixel of a map file or array; None: 1 m (the paper's). An
            error for a built-in map (1 m per pixel).
        body_radius: half-width of a UAV for contacts (m; ours: the paper's <= 0.5 m UAV does
            not fit the physics' 1 m grid check, see README).
        body_noise: std of the per-tick body displacement (m; ours).
        time_limit: longest run (s), Table 1.
        step_duration: simulated time one Mesa ``step()`` advances: one model step (s).
        dt: physics tick (s; ours: the largest divisor of the 0.5 s step the grid check
            allows).
        trace_interval: how often positions are sampled for rendering (s); None: never (the
            default: sweeps of hundreds of long runs do not need it).

    """

    map: str | Path | Arena | np.ndarray = "hall100"
    pheromone_radius: float = param(20.0, low=0.0, low_open=True, shown=(5.0, 60.0))
    wander_radius: float | None = param(None, low=0.0)
    wander_intensity: float = param(0.03, low=0.0)
    decay: float = param(0.0001, low=0.0)
    link_threshold: float | None = param(None, low=0.0, low_open=True)
    landing_offset: float = param(0.0, low=0.0)
    link_model: str = param("distance", choices=LINK_MODELS)
    link_exponent: float = param(_RADIO_DEFAULTS["link_exponent"], low=0.0, low_open=True)
    link_wall_loss: float = param(_RADIO_DEFAULTS["link_wall_loss"], low=0.0)
    link_fading_sd: float = param(_RADIO_DEFAULTS["link_fading_sd"], low=0.0)
    obstacle_range: float = param(5.0, low=0.0, low_open=True)
    obstacle_beams: int = param(8, low=0, high=360, integer=True)
    launch_rate: float = param(0.01, low=0.0, high=1.0, low_open=True, shown=(0.005, 0.1))
    model_step: float = param(0.5, low=0.0, low_open=True, period=True)
    start: tuple[float, float] | None = None
    a1: float = param(0.2, low=0.0)
    a2: float = param(0.4, low=0.0)
    a3: float = param(0.4, low=0.0)
    a4: float = param(0.4, low=0.0)
    f1_falloff: float = param(2.0, low=0.0)
    f1_relative: bool = True
    f1_line_of_sight: bool = False
    deposit_line_of_sight: bool = True
    swarm_size: int | None = param(None, low=1, integer=True)
    max_speed: float = param(2.0, low=0.0, low_open=True, shown=(0.5, 5.0))
    detection_range: float = param(10.0, low=0.0, low_open=True)
    coverage_target: float = param(0.95, low=0.0, high=1.0, low_open=True)
    coverage_interval: float = param(1.0, low=0.0, low_open=True, period=True)
    coverage_line_of_sight: bool = True
    ca_sample_period: float = param(10.0, low=0.0, low_open=True)
    map_resolution: float | None = param(None, low=0.0, low_open=True)
    body_radius: float = param(0.15, low=0.0, low_open=True)
    body_noise: float = param(0.025, low=0.0)
    time_limit: float = param(15000.0, low=0.0, low_open=True)
    step_duration: float = param(0.5, low=0.0, low_open=True)
    dt: float = param(0.25, low=0.0, low_open=True)
    trace_interval: float | None = param(None, low=0.0, low_open=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.landing_offset > 0 and self.link_threshold is not None:
            raise ConfigError(
                f"landing_offset={self.landing_offset!r} and link_threshold="
                f"{self.link_threshold!r} both set l_i: give one of them"
            )
        if self.landing_offset >= self.pheromone_radius:
            raise ConfigError(
                f"landing_offset must be below pheromone_radius (l_i = C_rb - delta > 0), "
                f"got {self.landing_offset!r} >= {self.pheromone_radius!r}"
            )
        if self.link_model != "radio":
            for name, default in _RADIO_DEFAULTS.items():
                if getattr(self, name) != default:
                    raise ConfigError(
                        f"{name} applies to link_model='radio' only; with "
                        f"link_model={self.link_model!r} it must stay {default!r}, "
                        f"got {getattr(self, name)!r}"
                    )

    @property
    def launch_period(self) -> float:
        """Time between two launches (s): model_step / eta."""
        return self.model_step / self.launch_rate

    @property
    def c_rw(self) -> float:
        """C_rw in effect (m)."""
        return self.pheromone_radius / 2 if self.wander_radius is None else self.wander_radius

    @property
    def l_i(self) -> float:
        """l_i in effect (m): ``link_threshold``, or C_rb - ``landing_offset``."""
        if self.link_threshold is not None:
            return self.link_threshold
        return self.pheromone_radius - self.landing_offset

    @property
    def swarmsize(self) -> int:
        """Swarmsize in effect: the most robots a run can hold."""
        if self.swarm_size is not None:
            return self.swarm_size
        return 1 + int(self.time_limit // self.launch_period)


DEFAULTS = StigmergyParams()
