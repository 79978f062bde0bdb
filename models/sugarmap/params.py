"""Parameters of the SugarMap model, with the paper's values and our readings.

Source: Purohit, Sun, Zhang (2013), "SugarMap: Location-less Coverage for Micro-Aerial Sensing
Swarms", IPSN'13. The paper publishes the cell size D = 0.5 m, speeds 0.25-0.45 m/s, the
1 s time step, the actuation noise (turn 20 %, velocity 15 %), SIG_TH = 1.2 (in its lab's
units), COVER_TH = 0.95, a path-loss exponent of 3 and the experiments' swarm sizes; everything
else is ours and marked so (the model's README, "Choices").
"""

import math
from dataclasses import dataclass
from pathlib import Path

from abm.errors import ConfigError
from abm.params import SwarmParams, param

__all__ = ["ALGORITHMS", "DEFAULTS", "SUGARMAP_ONLY", "SugarMapParams"]

#: The coverage algorithms a run can use.
ALGORITHMS = ("sugarmap", "random_walk", "omstc")

#: Parameters only the SugarMap algorithm uses (anchors, particles, signatures, its planner);
#: a baseline run refuses them rather than ignoring them.
SUGARMAP_ONLY = (
    "n_anchors",
    "n_particles",
    "sig_th",
    "weights",
    "sigma_m",
    "resample",
    "resample_noise",
    "min_match_age",
    "sig_norm",
    "planner_pose",
    "backtrack",
    "beta",
    "blocked_ttl",
    "pick",
    "self_cover",
    "proximity",
    "anchor_placement",
)


@dataclass(frozen=True)
class SugarMapParams(SwarmParams):
    """Everything a SugarMap run can vary (SI units; angles in degrees as the paper's commands).

    Attributes:
        algorithm: "sugarmap" (anchors, RToF signatures, particle filters, the planner of
            Fig. 4), "random_walk" or "omstc" (spanning-tree coverage with true positions, the
            paper's ideal reference), Sect. 4.2.
        arena: a built-in arena ("open" 20 m x 20 m square, "open10" 10 m x 10 m (ours, for claim
            C22), "circle", "ushape", "serpentine", "corridor": Fig. 10's geometries as we read
            them, README "Choices": arenas; "testbed" 5 m x 3 m, Sect. 4.4) or a bitmap file of 0.5
            m cells (dark = wall or obstacle).
        entrance: the point (x, y) (m) where the swarm enters the arena; the nodes start on
            its cell and the free cells nearest to it. None: the lowest row's first free
            cells, a corner as in the testbed (README "Choices": start).
        n_explorers: explorers covering the arena (4 in Fig. 5).
        n_anchors: anchors dispersed before coverage (Figs. 6, 8 vary it); None: 6 (ours: the
            value Figs. 7 and 9 use). SugarMap only.
        n_particles: particles per explorer (10 in Fig. 6); None: 10. SugarMap only.
        horizon: length of the coverage phase tau after deployment (s): 3000 in Fig. 5.
        speed: v_cmd, the commanded speed (m/s; ours: 0.35, the middle of the paper's
            0.25-0.45 m/s, which 15 % velocity noise spreads over that range).
        turn_noise: SD of the executed turn as a share of the commanded turn, Sect. 4.3.7.
        speed_noise: SD of the executed speed as a share of the commanded speed, Sect. 4.3.7.
        noise_scale: a factor on both noises, for the truth and the particles alike (ours:
            the paper's "larger sensor noise" comparisons).
        heading_model: "literal": the executed heading is the commanded absolute heading plus
            this tick's noise (eqs. 3 and 6 read literally); "accumulate": heading errors add
            up from tick to tick (gyro-style). Truth and particles alike (README "Choices": heading
            errors).
        radio_range: R, the nominal radio range (m): a link at R is up with probability 1/2
            (ours: 30 m, so every node stays in range as the paper's evaluation assumes).
        path_loss_exponent: n of the log-normal shadowing link model, Sect. 4.1.
        shadowing_sd: sigma of the shadowing (dB; ours: 0, a disc of radius R).
        rtof_noise: sigma_epsilon, the SD of one RToF measurement in metre-equivalents (m;
            ours: the paper gives no unit or value).
        rtof_bias: sigma_b, the SD of a static multipath bias field per anchor, smooth over
            about 1 m (m; ours: 0).
        sig_th: SIG_TH, the signature distance below which a signature matches a stored one
            (eq. 11); None: 0.75, what the paper's calibration procedure gives in our
            metre-equivalent units on the reference set-up (open square, 6 anchors, RToF noise
            1 m: 0.753, SD 0.027 over 20 deployments, `python -m models.sugarmap.calibrate`);
            the paper's 1.2 is in its lab's units. SugarMap only.
        cover_th: COVER_TH: a cell counts as covered when the GlobalMap says so with at least
            this probability, Sect. 4.3.6.
        weights: how a revisit reweights the particles: "eq8" (eq. 8, normalised) or "gauss"
            (exp(-delta^2 / 2 sigma_m^2); ours). None: "eq8". SugarMap only.
        sigma_m: the Gaussian weights' length (m); None: D. SugarMap only.
        resample: "on_match" (after a revisit) or "every_tick"; None: "on_match". SugarMap
            only.
        resample_noise: the SD of the Gaussian jitter (per axis, m) each particle's position
            gets at every resampling ("roughening", ours: the paper adds none); None: 0.
            SugarMap only.
        min_match_age: stored signatures younger than this are not matched (s); None: 0.
            SugarMap only.
        sig_norm: eq. 11 divides by the number of common anchors ("count", literal) or its
            square root ("rms"); None: "count". SugarMap only.
        planner_pose: the cell the planner starts from: "particles" (the mean particle) or
            "presumed" (command-integrated); None: "particles". SugarMap only.
        backtrack: "soft" (the tree parent's weight raised by beta), "hard" (strict DFS) or
            "frontier" (ours: toward the nearest uncovered cell through covered ones); None:
            "soft". SugarMap only.
        beta: the soft backtracking bonus; None: 1. SugarMap only.
        blocked_ttl: how long a bumped cell stays blocked for the planner (s); None: 30.
            SugarMap only.
        pick: a candidate cell's weight: "one_minus" (1 - P) or "inverse" (1 / P); None:
            "one_minus". SugarMap only.
        self_cover: what counts as "covered by itself" for an explorer's planner (Sect. 3.2):
            "map" (only the GlobalMap at COVER_TH, as for the other explorers' cells) or
            "tree" (also every cell its own spanning tree has stood in, by its pose estimate;
            ours); None: "map". SugarMap only.
        proximity: T_p, the dispersion's proximity threshold (m); None: half the spacing of a
            square lattice of the anchors over the free area, 0.5 sqrt(A / N_a). SugarMap
            only.
        anchor_placement: "disperse" (Fig. 3's dispersion) or "spread" (ours, a control: the
            anchors land at once on free cells spread by greedy farthest-point sampling from
            the entrance, what an ideal dispersion would reach); None: "disperse". SugarMap
            only.
        init_cutoff: InitCutoff: anchors still flying then land where they are (s; ours).
        dispersion_period: P_d, the flight leg between two RToF checks of a dispersing anchor
            (s; ours).
        random_walk: "lattice" (a random cardinal turn every tick) or "bounce" (straight until
            a bump, then a random heading); None: "lattice". Random walk only.
        margin: cells of the brain's estimate map beyond the arena on every side (the brain
            knows no walls).
        dt: delta t, the simulation time step and shortest command (s), Sect. 4.1.
        step_duration: simulated time one Mesa step() advances (s).
        time_limit: hard cap on the whole run, deployment included (s).
        trace_interval: how often positions are sampled for rendering (s); None: never (the
            sweeps' default, for speed).

    """

    algorithm: str = param("sugarmap", choices=ALGORITHMS)
    arena: str | Path = "open"
    entrance: tuple[float, float] | None = None
    n_explorers: int = param(4, low=1, high=100, integer=True, shown=(1, 8))
    n_anchors: int | None = param(None, low=1, high=100, integer=True, shown=(1, 12))
    n_particles: int | None = param(None, low=1, high=10_000, integer=True, shown=(1, 100))
    horizon: float = param(3000.0, low=0.0, low_open=True)
    speed: float = param(0.35, low=0.0, high=0.45, low_open=True)
    turn_noise: float = param(0.20, low=0.0, high=1.0)
    speed_noise: float = param(0.15, low=0.0, high=1.0)
    noise_scale: float = param(1.0, low=0.0, high=5.0)
    heading_model: str = param("literal", choices=("literal", "accumulate"))
    radio_range: float = param(30.0, low=0.0, low_open=True)
    path_loss_exponent: float = param(3.0, low=0.0, low_open=True)
    shadowing_sd: float = param(0.0, low=0.0, high=20.0)
    rtof_noise: float = param(1.0, low=0.0)
    rtof_bias: float = param(0.0, low=0.0)
    sig_th: float | None = param(None, low=0.0, low_open=True)
    cover_th: float = param(0.95, low=0.0, high=1.0, low_open=True)
    weights: str | None = param(None, choices=("eq8", "gauss"))
    sigma_m: float | None = param(None, low=0.0, low_open=True)
    resample: str | None = param(None, choices=("on_match", "every_tick"))
    resample_noise: float | None = param(None, low=0.0, shown=(0.0, 1.0))
    min_match_age: float | None = param(None, low=0.0)
    sig_norm: str | None = param(None, choices=("count", "rms"))
    planner_pose: str | None = param(None, choices=("particles", "presumed"))
    backtrack: str | None = param(None, choices=("soft", "hard", "frontier"))
    beta: float | None = param(None, low=0.0)
    blocked_ttl: float | None = param(None, low=0.0)
    pick: str | None = param(None, choices=("one_minus", "inverse"))
    self_cover: str | None = param(None, choices=("map", "tree"))
    proximity: float | None = param(None, low=0.0, low_open=True)
    anchor_placement: str | None = param(None, choices=("disperse", "spread"))
    init_cutoff: float = param(600.0, low=0.0)
    dispersion_period: float = param(5.0, low=0.0, low_open=True)
    random_walk: str | None = param(None, choices=("lattice", "bounce"))
    margin: int = param(20, low=0, high=200, integer=True)
    dt: float = param(1.0, low=0.0, low_open=True)
    step_duration: float = param(1.0, low=0.0, low_open=True)
    time_limit: float = param(1e6, low=0.0, low_open=True)
    trace_interval: float | None = param(None, low=0.0, low_open=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.algorithm != "sugarmap":
            for name in SUGARMAP_ONLY:
                if getattr(self, name) is not None:
                    raise ConfigError(
                        f"{name} applies to algorithm='sugarmap' only; algorithm="
                        f"{self.algorithm!r} uses no anchors, particles or signatures"
                    )
        if self.algorithm != "random_walk" and self.random_walk is not None:
            raise ConfigError(
                f"random_walk applies to algorithm='random_walk' only, got algorithm="
                f"{self.algorithm!r}"
            )
        if self.sigma_m is not None and self.resolved("weights") != "gauss":
            raise ConfigError(
                f"sigma_m is the length of the Gaussian weights: it applies to weights='gauss' "
                f"only, got weights={self.resolved('weights')!r}"
            )
        if self.dt > self.horizon:
            raise ConfigError(
                f"dt ({self.dt:g} s) must not exceed the horizon ({self.horizon:g} s): one step "
                "would overrun the whole coverage phase"
            )

    # the defaults of the algorithm-specific parameters, resolved
    @property
    def anchors(self) -> int:
        """Anchors deployed (0 for the baselines)."""
        if self.algorithm != "sugarmap":
            return 0
        return 6 if self.n_anchors is None else self.n_anchors

    @property
    def particles(self) -> int:
        """Particles per explorer."""
        return 10 if self.n_particles is None else self.n_particles

    @property
    def signature_threshold(self) -> float:
        """SIG_TH in effect."""
        return CALIBRATED_SIG_TH if self.sig_th is None else self.sig_th

    def proximity_for(self, free_area: float) -> float:
        """T_p in effect for an arena of ``free_area`` m^2."""
        if self.proximity is not None:
            return self.proximity
        return 0.5 * math.sqrt(free_area / max(self.anchors, 1))

    def resolved(self, name: str) -> object:
        """An algorithm-specific parameter's value, its default filled in."""
        value = getattr(self, name)
        return RESOLVED[name] if value is None else value


#: SIG_TH calibrated by the paper's procedure on the reference set-up (see ``sig_th``), as
#: ``python -m models.sugarmap.calibrate`` prints it (0.753, SD 0.027 over 20 deployments).
CALIBRATED_SIG_TH = 0.75

#: The defaults of the algorithm-specific parameters left None.
RESOLVED = {
    "weights": "eq8",
    "sigma_m": 0.5,
    "resample": "on_match",
    "resample_noise": 0.0,
    "min_match_age": 0.0,
    "sig_norm": "count",
    "planner_pose": "particles",
    "backtrack": "soft",
    "beta": 1.0,
    "blocked_ttl": 30.0,
    "pick": "one_minus",
    "self_cover": "map",
    "anchor_placement": "disperse",
    "random_walk": "lattice",
}

DEFAULTS = SugarMapParams()
