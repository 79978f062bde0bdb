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
* The second entry of Gamma (5) has no symbol in the definition Gamma = (r_u, eta, p0, a1..a4);
  we keep it as ``gamma_unlabelled`` and it changes nothing.
* ``swarmsize`` is the most robots a run can hold: 1 + floor(time_limit / launch_period) = 301.
* The decay rate C_eps is exponential: intensity x exp(-C_eps t).
"""

from dataclasses import dataclass

__all__ = ["StigmergyParams", "DEFAULTS", "PAPER_LAMBDAS", "PAPER_TABLE1", "PAPER_TABLE2"]


@dataclass(frozen=True)
class StigmergyParams:
    """Defaults of :class:`StigmergyModel` (SI units), the paper's values unless marked "ours".

    Attributes:
        wander_intensity: C_dw, pheromone a flying robot deposits per step.
        decay: C_eps, pheromone decay rate (1/s).
        obstacle_range: r_u, obstacle detection radius (m).
        gamma_unlabelled: the unlabelled second entry of Gamma (unused).
        launch_rate: eta = alpha5, new robots per model step.
        step: the paper's model step (s).
        start: p0, launch point (m).
        a1: weight of f1 (towards less pheromone).
        a2: weight of f2 (obstacle repulsion).
        a3: weight of f3 (random walk).
        a4: size of the random increment of f3.
        f1_falloff: the importance of a pheromone reading in f1 falls as 1 / distance^f1_falloff.
            The text says "decreases with the square of the distance" (2); the formula
            ``v / |v|^2`` read literally gives 1 / distance (1).
        max_speed: UAV speed (m/s).
        detection_range: sensing radius of the coverage metrics ca, cb (m).
        coverage_target: the run ends when ca reaches this fraction.
        time_limit: longest run (s).
        body_radius: half-width of a UAV for contacts (m; ours: the paper's <= 0.5 m UAV does
            not fit the physics' 1 m grid check, see README).
        body_noise: std of the per-tick body displacement (m; ours).
        dt: physics tick (s; ours: the largest divisor of the 0.5 s step the grid check allows).

    """

    wander_intensity: float = 0.03
    decay: float = 0.0001
    obstacle_range: float = 5.0
    gamma_unlabelled: float = 5.0
    launch_rate: float = 0.01
    step: float = 0.5
    start: tuple[float, float] = (5.0, 80.0)
    a1: float = 0.2
    a2: float = 0.4
    a3: float = 0.4
    a4: float = 0.4
    f1_falloff: float = 2.0
    max_speed: float = 2.0
    detection_range: float = 10.0
    coverage_target: float = 0.95
    time_limit: float = 15000.0
    body_radius: float = 0.15
    body_noise: float = 0.025
    dt: float = 0.25


DEFAULTS = StigmergyParams()

#: The published regression coefficients of the macroscopic model (Sect. "Obtaining a0 and
#: alpha6"). The extracted text shows l1 = 2.5e-5, l2 = 2.5e-6, which make alpha6 > 1 (a_t
#: would grow without bound); the minus signs of the exponents' neighbours were lost in
#: extraction and Table 1's predicted counts are reproduced only with l1, l2 < 0, so we use
#: the negative signs (checked in tests/test_macro.py).
PAPER_LAMBDAS = {
    "l0": 1.0,
    "l1": -2.5e-5,
    "l2": -2.5e-6,
    "l3": 9.5e-2,
    "l4": 1.0 / 60.0,
    "l5": 5.4e-6,
}

#: Table 1: (map id, C_rb) -> (w, b, w_hat, b_hat, t, ca, cb, rmsd_w, rmsd_b).
PAPER_TABLE1 = {
    (1, 10): (5.60, 233.40, 0.50, 237.99, 11875, 96.75, 100.00, 2.772, 2.458),
    (1, 20): (1.20, 27.80, 1.85, 27.14, 1400, 94.03, 14.80, 0.4869, 0.6688),
    (1, 30): (3.20, 12.80, 3.13, 12.86, 750, 92.44, 8.16, 0.5095, 0.6684),
    (1, 40): (7.80, 8.20, 7.33, 8.41, 738, 93.96, 8.16, 0.6403, 0.7511),
    (2, 10): (8.00, 293.00, 8.82, 292.17, 15000, 98.63, 100.00, 2.293, 1.967),
    (2, 20): (3.20, 57.80, 2.00, 58.74, 2988, 93.38, 31.12, 1.162, 0.8114),
    (2, 30): (4.20, 23.80, 3.76, 23.98, 1338, 92.99, 14.29, 0.7449, 0.4387),
    (2, 40): (7.20, 14.80, 8.38, 13.61, 1050, 92.01, 11.22, 0.8336, 0.7567),
    (3, 10): (41.00, 247.00, 58.66, 228.83, 14325, 95.87, 100.00, 5.13, 5.075),
    (3, 20): (15.20, 27.80, 15.70, 26.54, 2062, 88.06, 21.94, 1.016, 0.937),
    (3, 30): (10.20, 11.80, 8.51, 13.48, 1050, 89.06, 11.22, 1.33, 1.066),
    (3, 40): (15.20, 7.80, 15.43, 7.31, 1088, 94.28, 11.73, 0.6473, 0.4651),
    (4, 10): (59.00, 242.00, 63.69, 237.30, 15000, 95.33, 100.00, 5.999, 5.716),
    (4, 20): (40.40, 30.60, 42.88, 27.61, 3475, 91.35, 36.22, 1.595, 1.386),
    (4, 30): (31.00, 13.00, 31.60, 11.89, 2125, 93.20, 22.45, 0.7561, 0.5267),
    (4, 40): (16.00, 7.00, 17.04, 5.45, 1075, 87.27, 11.73, 0.9312, 1.199),
}

#: Table 2 (10 maps): mean (std) RMSD of w and b.
PAPER_TABLE2 = {"rmsd_w": (1.6429, 1.4356), "rmsd_b": (1.5501, 1.4677)}
