"""Parameters of the hierarchical swarm (HST) model, with the report's values and our readings.

Source: Alunni, Goloski, Haggerty, Jones, *Hierarchical Swarm Robotics*, WPI MQP GSF113 (2011);
the report's sections are cited by title (it numbers none). [R] marks a value the report states,
"ours" a reading where it is silent; every "ours" is listed in the model's README.
"""

from dataclasses import dataclass
from pathlib import Path

from abm.errors import ConfigError
from abm.params import SwarmParams, param

__all__ = ["PACKING_RATIO", "WORKER_STATES", "WORLDS", "HierarchyParams"]

#: rho(S): radius of the smallest circle enclosing S unit discs (optimal circle packing), S=1..8.
PACKING_RATIO = (1.0, 2.0, 2.1547, 2.4142, 2.7013, 3.0, 3.0, 3.3048)

#: The states in which a worker may fail.
WORKER_STATES = ("worker_idle", "worker_driving", "worker_directing")

#: Built-in worlds: the square room of "Data Collection" (empty unless ``boxes`` > 0).
WORLDS = ("room",)


@dataclass(frozen=True)
class HierarchyParams(SwarmParams):
    """Everything an HST run can vary (SI units: metres, seconds).

    Attributes:
        workers: W, level-1 robots under the queen (2-7 in the scaling experiment, "Data
            Collection").
        scouts_per_worker: S, level-2 robots under each worker (2-8 in the experiment); 1-8,
            the counts whose circle-packing ratio sets the worker's minimum bubble.
        world: "room" (the 20 m x 20 m room of "Data Collection", empty unless ``boxes`` > 0) or a
            bitmap file (PNG/PGM/BMP/NPY, dark = obstacle) of ``world_pixel`` m pixels.
        world_size: side of the square room (m; 20 m [R], "Data Collection").
        world_pixel: pixel of the ground-truth world (m; ours: 0.2 m, the finest grid the
            framework's physics accepts for a 15.24 cm robot body).
        boxes: number of random axis-aligned boxes in the room (ours: 0, the report does not
            describe its map; the obstacle variant is a robustness study).
        box_size: side of each box (m; ours).
        start_layout: "row" (workers ``worker_spacing`` apart 1 m from the south wall) or
            "centre" (the same groups around the map centre), ours (README "Choices": start layout).
        worker_spacing: distance between neighbouring workers at the start (m; ours: 2 m).
        scout_ring: radius of the circle a worker's scouts start on (m; ours: 0.6 m, so that
            8 scouts start >= 0.3 m apart after snapping to cells, a 0.4 m ring cannot).
        start_jitter: each group (a worker and its scouts) is shifted by up to this much per
            axis before snapping to cell centres (m; ours, README "Choices": start jitter).
        cell_size: side of a ProbMap cell (m; ours: 0.10 m, README "Choices": cell size).
        scout_r_min: a scout's minimum bubble radius, the IR range's near end (m; 0.10 [R]).
        scout_r_max: a scout's maximum bubble radius, the IR range (m; 0.80 [R]).
        worker_r_max: a worker's maximum bubble radius, the XBee range (m; ~400 [R]).
        worker_r_min: a worker's minimum bubble radius (m); None: rho(S) x ``scout_r_min``
            (optimal circle packing, ours, README "Choices": worker r_min).
        radius_decay: factor of the radius schedule r_{k+1} = decay r_k (0.9 [R]).
        alpha: alpha of V = alpha C - beta D, weight of the cells revealed (1 [R]).
        beta: beta of V, weight of the cells driven (3 [R]).
        blocked_threshold: tau, a cell with blocked >= tau counts as an obstacle (ours: 0.5).
        reset_radius_after_removal: after the closest-robot removal, restart the radius
            schedule at the maximum (ours; False keeps the pseudo-code's floor, README "Choices":
            common radius of mixed children).
        drop_unreachable_first: at the minimum radius, first remove a child that can reach no
            VALID cell (lowest local number), then apply the closest-robot rule (ours: a
            reading of H2, "as many bubbles as possible"; False: the literal pseudo-code).
        wave_generator: stagger children whose padded paths cross into waves (Fig. 33 [R]);
            False sends every move at once (the counterfactual of claim C12).
        subtree_transits: how the queen sends her placed workers' subtrees into their new
            bubbles: "together" (every worker gets its MOVE by waves, then its SCAN, and each
            moves its scouts in at once: the report's, "Queen / Worker") or "staggered" (one
            subtree at a time: worker k drives, gets its SCAN, moves its scouts into the new
            bubble and answers SETTLED before worker k + 1 gets its order; ours, issue 30,
            for claim C12's contacts between scouts of different workers). "staggered" needs
            ``topology="hst"`` (other topologies have no subtrees).
        speed: driving speed (m/s; 0.3048, the 1 ft/s design target [R]).
        scan_time: duration of one stationary sensor sweep (s; ours, the report gives none).
        scan_step: angle between two IR rays of a sweep (degrees; ours: 1, README "Choices": scan).
        sigma_sensor: sigma the scout reports with each obstacle point (m; ours: 0, the
            report's simulation had perfect localisation).
        stamp: how a reported point is stamped into the map: "mass" (probability mass of
            the Gaussian per cell) or "peak" (peak-normalised kernel), ours, README "Choices": point
            stamping.
        dedupe_points_per_cell: a scout sends one POINT per hit cell instead of one per ray
            hit (ours, for message studies; the report's scout "forgets").
        worker_report: "batch" (a worker sends its points in one MAP_REPORT when its bubble
            is done) or "relay" (it forwards each accepted POINT as it arrives), README "Choices":
            worker report.
        combine_move_scan: send MOVE and SCAN as one ASSIGN message (ours, README "Choices": MOVE
            and SCAN).
        los_hint_separate: the scout's line-of-sight hint is its own LOS_HINT message instead
            of a flag on SCAN_COMPLETE (ours, README "Choices": line-of-sight hint).
        latency: delay of one message (s; ours: 0, the report's simulator used direct buffers).
        message_loss: probability one transmission attempt is lost (a lost message arrives
            on a later attempt, so loss is delay; ours: 0, the XBees were "highly reliable").
        comm_range: radio range of every node (m; the XBee's ~400 m [R]).
        dt: physics tick (s; ours: 0.15, the longest on which a 0.3048 m/s robot still moves
            less than its clearance on the 0.2 m world grid).
        step_duration: simulated time one Mesa ``step()`` (a frame of the page, a row of the
            DataCollector) advances (s; ours: 10 s, runs last hours of simulated time).
        time_limit: the run ends at this simulated time at the latest (s).
        trace_interval: how often robot positions are sampled for pictures (s).
        topology: "hst" (queen, workers, scouts: the report's tree), or an arm of the topology
            comparison (README, "The message comparison") with the same W S scouts: "star" (the
            queen directs every scout, a tree of depth 1), "fc" / "ring" (a map holder and the
            scouts with replicated planning on a complete graph / a ring); ours.
        max_rounds: a director that needs more coverage rounds than this fails loudly (ours,
            README "Choices": no-progress guard).
        heartbeat_timeout: time after a worker fails until its parent and its scouts notice
            (s; ours: the report's "Node Failure Detection" heartbeat gives no value). Acts
            only when robots fail (``fault_rate`` or ``fault_times``); only workers fail
            (``fault_states``, if given, names worker states).

    """

    workers: int = param(2, low=1, high=50, integer=True, shown=(1, 7))
    scouts_per_worker: int = param(4, low=1, high=8, integer=True)
    world: str = "room"
    world_size: float = param(20.0, low=2.0, high=200.0, shown=(4.0, 20.0))
    world_pixel: float = param(0.2, low=0.16, high=1.0)
    boxes: int = param(0, low=0, high=200, integer=True, shown=(0, 20))
    box_size: float = param(1.0, low=0.2, high=5.0)
    start_layout: str = param("row", choices=("row", "centre"))
    worker_spacing: float = param(2.0, low=0.6, high=10.0)
    scout_ring: float = param(0.6, low=0.3, high=2.0)
    start_jitter: float = param(0.05, low=0.0, high=0.1)
    cell_size: float = param(0.10, low=0.02, high=0.5)
    scout_r_min: float = param(0.10, low=0.0, low_open=True)
    scout_r_max: float = param(0.80, low=0.0, low_open=True)
    worker_r_max: float = param(400.0, low=0.0, low_open=True)
    worker_r_min: float | None = param(None, low=0.0, low_open=True)
    radius_decay: float = param(0.9, low=0.0, high=1.0, low_open=True)
    alpha: float = param(1.0, low=0.0)
    beta: float = param(3.0, low=0.0)
    blocked_threshold: float = param(0.5, low=0.0, high=1.0, low_open=True)
    reset_radius_after_removal: bool = False
    drop_unreachable_first: bool = True
    wave_generator: bool = True
    subtree_transits: str = param("together", choices=("together", "staggered"))
    speed: float = param(0.3048, low=0.0, high=1.0, low_open=True)
    scan_time: float = param(2.0, low=0.0)
    scan_step: float = param(1.0, low=0.05, high=30.0)
    sigma_sensor: float = param(0.0, low=0.0, high=1.0)
    stamp: str = param("mass", choices=("mass", "peak"))
    dedupe_points_per_cell: bool = False
    worker_report: str = param("batch", choices=("batch", "relay"))
    combine_move_scan: bool = False
    los_hint_separate: bool = False
    latency: float = param(0.0, low=0.0)
    message_loss: float = param(0.0, low=0.0, high=0.99)
    comm_range: float = param(400.0, low=0.0, low_open=True)
    topology: str = param("hst", choices=("hst", "star", "fc", "ring"))
    max_rounds: int = param(5000, low=1, integer=True)
    heartbeat_timeout: float = param(5.0, low=0.0, low_open=True)
    time_limit: float = param(50000.0, low=0.0, low_open=True)
    trace_interval: float | None = param(5.0, low=0.0, low_open=True)
    step_duration: float = param(10.0, low=0.0, low_open=True)
    dt: float = param(0.15, low=0.0, high=0.15, low_open=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.world not in WORLDS and Path(str(self.world)).suffix.lower() not in (
            ".png",
            ".pgm",
            ".bmp",
            ".npy",
        ):
            raise ConfigError(
                f"world must be one of {', '.join(WORLDS)} or a bitmap file "
                f"(.png, .pgm, .bmp, .npy), got {self.world!r}"
            )
        if self.world not in WORLDS:
            for name, default in (("world_size", 20.0), ("boxes", 0), ("box_size", 1.0)):
                if getattr(self, name) != default:
                    raise ConfigError(
                        f"{name} shapes the built-in room only; with the bitmap world "
                        f"{self.world!r} leave it at {default}, got {getattr(self, name)}"
                    )
        elif self.boxes == 0 and self.box_size != 1.0:
            raise ConfigError(
                f"box_size is the side of the room's boxes, and boxes=0 places none; give "
                f"boxes > 0 or leave box_size at 1.0, got box_size={self.box_size}"
            )
        if self.radius_decay == 1.0:
            raise ConfigError(
                "radius_decay must be in (0, 1): at 1 the radius schedule r_{k+1} = decay r_k "
                "never shrinks, got 1.0"
            )
        if self.scout_r_min >= self.scout_r_max:
            raise ConfigError(
                f"scout_r_min must be below scout_r_max ({self.scout_r_max}), "
                f"got {self.scout_r_min}"
            )
        if self.worker_r_min_value >= self.worker_r_max:
            raise ConfigError(
                f"worker_r_min must be below worker_r_max ({self.worker_r_max}), "
                f"got {self.worker_r_min_value}"
            )
        if self.topology in ("fc", "ring") and (self.latency > 0 or self.message_loss > 0):
            raise ConfigError(
                f"topology={self.topology!r} is modelled with reliable zero-latency delivery "
                "(replicas stay identical); set latency=0 and message_loss=0"
            )
        if self.subtree_transits == "staggered" and self.topology != "hst":
            raise ConfigError(
                "subtree_transits='staggered' needs topology='hst' (the other topologies have "
                f"no subtrees to stagger), got topology={self.topology!r}"
            )
        if "robot" in self.fault_kinds:
            if self.topology != "hst":
                raise ConfigError(
                    f"robot faults are modelled for topology='hst' (a worker fails, its scouts "
                    f"re-attach to the queen), got topology={self.topology!r}"
                )
            if not set(self.fault_states) <= set(WORKER_STATES):
                raise ConfigError(
                    f"fault_states must name worker states among {WORKER_STATES} (only "
                    f"workers fail in this model), got {self.fault_states!r}"
                )
        if self.stamp == "peak" and self.sigma_sensor == 0:
            raise ConfigError(
                "stamp='peak' needs sigma_sensor > 0 (with sigma 0 both stamps mark the "
                "containing cell, so the choice would be ignored), got sigma_sensor=0"
            )

    @property
    def worker_r_min_value(self) -> float:
        """The worker's minimum bubble radius (m): the override or rho(S) x scout r_min."""
        if self.worker_r_min is not None:
            return self.worker_r_min
        return PACKING_RATIO[self.scouts_per_worker - 1] * self.scout_r_min

    @property
    def total_robots(self) -> int:
        """N = 1 + W + W S, the queen included (README "Choices": robots counted)."""
        return 1 + self.workers + self.workers * self.scouts_per_worker
