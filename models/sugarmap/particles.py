"""The base station's particle filters, one per explorer (Purohit et al. Sect. 3.3, eqs. 1-11).

A particle is one hypothesis of an explorer's whole coverage path: its position and heading,
its LocalMap (the cells it believes covered, eq. 4) and, for every signature the explorer
stored, where the particle was at that moment (eq. 7 compares a particle's position now with its
own past, so that history must travel with it). Each tick (Sect. 3.3):

- F1 predict (eqs. 3-6): every particle executes the explorer's command with its own draw of the
  actuation noise and marks its new cell;
- F2 correct (eqs. 7, 8, 11): if the explorer's RToF signature matches a stored one (a revisit:
  eq. 11's distance below SIG_TH), the particles now nearest to where they were at that
  signature weigh more (eq. 8) and are resampled with replacement, carrying their maps and
  memories; otherwise the signature is stored with every particle's position;
- F3/F4 merge: NodeMap = the particles' mean LocalMap (eq. 9); GlobalMap = 1 - prod(1 - NodeMap)
  over the explorers (eq. 10).

Everything over (explorers x particles) is one numpy operation or one compiled kernel
(:mod:`models.sugarmap.filterkernels`, the same arithmetic); Python loops run over explorers
only. Particles know no walls: the brain has no map (README "Choices": particles and walls).
Symbols: N particles, N_a anchors, n_e explorers, i particle, e explorer, j stored signature.
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from abm import portable
from abm.errors import ConfigError, check_choice, check_range
from abm.kinematics import wrap_degrees
from models.sugarmap import filterkernels

__all__ = ["MapGrid", "Match", "ParticleFilter", "calibrate_sig_th", "eq8_weights",
           "global_map", "signature_distance"]  # fmt: skip

HEADING_MODELS = ("literal", "accumulate")
WEIGHT_RULES = ("eq8", "gauss")
RESAMPLE_RULES = ("on_match", "every_tick")
SIG_NORMS = ("count", "rms")

#: Stored signatures the filter has room for before it first doubles its memories.
_INITIAL_CAPACITY = 64
#: Rounds of disc draws `calibrate_sig_th` tries before deciding a place has no free points.
_MAX_DRAW_ROUNDS = 1000


@dataclass(frozen=True)
class MapGrid:
    """The brain's estimate grid: square cells of side ``cell`` (m, the paper's D); cell
    (ix, iy) spans ``[origin_x + ix cell, origin_x + (ix + 1) cell)`` and likewise in y; row
    index iy grows north (README "Choices": heading frame).

    Attributes:
        origin: the south-west corner of cell (0, 0) in the brain frame (m).
        cell: D (m).
        shape: (rows, cols).

    """

    origin: tuple[float, float]
    cell: float
    shape: tuple[int, int]

    def __post_init__(self) -> None:
        check_range("cell", self.cell, 0.0, low_open=True)
        check_range("shape[0] (rows)", self.shape[0], 1, integer=True)
        check_range("shape[1] (cols)", self.shape[1], 1, integer=True)

    @classmethod
    def around(cls, width: float, height: float, cell: float, margin: int) -> "MapGrid":
        """A grid covering [0, width] x [0, height] m plus ``margin`` cells on every side.

        The paper's brain places the swarm "at the center of an infinite space" [Sect. 4.1];
        the margin stands in for that space where particles drift out of the arena (README
        "Choices": estimate map).
        """
        check_range("width", width, 0.0, low_open=True)
        check_range("height", height, 0.0, low_open=True)
        check_range("cell", cell, 0.0, low_open=True)
        check_range("margin", margin, 0, integer=True)
        cols = int(np.ceil(width / cell)) + 2 * int(margin)
        rows = int(np.ceil(height / cell)) + 2 * int(margin)
        return cls((-margin * cell, -margin * cell), float(cell), (rows, cols))

    def cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(ix, iy)`` integer cell indices of points ``(..., 2)`` (m), clipped into the grid
        (a particle beyond the margin marks the edge cell rather than failing).
        """
        points = np.asarray(points, dtype=float)
        ix = np.floor((points[..., 0] - self.origin[0]) / self.cell).astype(np.int64)
        iy = np.floor((points[..., 1] - self.origin[1]) / self.cell).astype(np.int64)
        # np.minimum/np.maximum, not np.clip: the same integers without clip's per-call cost
        return (
            np.minimum(np.maximum(ix, 0), self.shape[1] - 1),
            np.minimum(np.maximum(iy, 0), self.shape[0] - 1),
        )


@dataclass(frozen=True)
class Match:
    """The revisit test of one tick (F2).

    Attributes:
        matched: the nearest stored signature is closer than SIG_TH (eq. 11).
        index: j, the stored signature matched; None without a match.
        distance: the nearest eligible stored signature's eq. 11 distance, matched or not; inf
            if nothing is stored, nothing is old enough or no anchor is in common.

    """

    matched: bool
    index: int | None
    distance: float


def _eq11(a: np.ndarray, b: np.ndarray, norm: str) -> np.ndarray:
    """Eq. 11 between signatures broadcast over leading axes (the last axis is the anchor)."""
    common = ~(np.isnan(a) | np.isnan(b))
    n = common.sum(axis=-1)
    length = np.sqrt((np.where(common, a - b, 0.0) ** 2).sum(axis=-1))
    scale = n if norm == "count" else np.sqrt(n)
    return np.where(n > 0, length / np.maximum(scale, 1), np.inf)


def signature_distance(
    signature: np.ndarray, stored: np.ndarray, norm: str = "count"
) -> np.ndarray:
    """Eq. 11, the distance of one signature to each stored one [Sect. 4.3.6].

    ``f = ||s - s_j||`` over the anchors visible in both, divided by their number ("count",
    the paper's formula, so f falls like 1/sqrt(N_a) for equal per-anchor differences,
    README "Choices": eq. 11's normaliser) or by its square root ("rms"); +inf where no anchor is in
    common.

    Args:
        signature: ``(N_a,)`` RToF values; NaN where the anchor was not visible.
        stored: ``(S, N_a)`` stored signatures, NaN likewise.
        norm: "count" or "rms".

    Returns:
        ``(S,)`` distances.

    """
    check_choice("norm", norm, SIG_NORMS)
    signature = np.asarray(signature, dtype=float)
    stored = np.asarray(stored, dtype=float)
    if signature.ndim != 1 or stored.ndim != 2 or stored.shape[1] != signature.shape[0]:
        raise ConfigError(
            f"signature must be (N_a,) and stored (S, N_a), got {signature.shape} and "
            f"{stored.shape}"
        )
    return _eq11(signature[None, :], stored, norm)


def eq8_weights(delta: np.ndarray) -> np.ndarray:
    """Eq. 8, normalised: ``w_i = (sum_l delta_l - delta_i) / sum_l delta_l`` [Sect. 3.3.2].

    The raw weights sum to N - 1, so they are divided by N - 1. When every delta is 0 (0/0) or N = 1
    (w = 0) the weights are uniform (README "Choices": eq. 8's weights). A smaller delta never gets
    a smaller weight, but the rule is flat: one perfect particle among nine equal ones weighs only
    9/8 of the others.

    Args:
        delta: ``(N,)`` eq. 7 distances (m), each >= 0.

    Returns:
        ``(N,)`` weights summing to 1.

    """
    delta = np.asarray(delta, dtype=float)
    if delta.ndim != 1 or len(delta) == 0 or not np.all((delta >= 0) & np.isfinite(delta)):
        raise ConfigError(f"delta must be a non-empty 1-D array of finite values >= 0, got {delta}")
    return filterkernels.eq8_weights(delta)


def _gauss_weights(delta: np.ndarray, sigma_m: float) -> np.ndarray:
    """The Gaussian option for eq. 8, ``exp(-delta^2 / 2 sigma_m^2)`` normalised (README "Choices":
    eq. 8's weights).

    Computed relative to the smallest delta, which leaves the normalised weights unchanged but
    keeps them from all underflowing to 0 when every particle is many sigma_m away.
    """
    w = portable.exp(-(delta**2 - np.min(delta) ** 2) / (2.0 * sigma_m**2))
    return w / w.sum()


def global_map(node_maps: np.ndarray) -> np.ndarray:
    """Eq. 10: ``G = 1 - prod_e (1 - NodeMap_e)``, the probability that some explorer covered
    each cell, taking the explorers as independent.

    Args:
        node_maps: ``(n_e, H, W)`` NodeMaps in [0, 1] (explorers only, README "Choices":
            eq. 10's n).

    Returns:
        ``(H, W)`` GlobalMap.

    """
    node_maps = np.asarray(node_maps, dtype=float)
    if node_maps.ndim != 3:
        raise ConfigError(f"node_maps must be (n_e, H, W), got shape {node_maps.shape}")
    return 1.0 - np.prod(1.0 - node_maps, axis=0)


class ParticleFilter:
    """The particles of every explorer, as arrays over (explorers, particles).

    Args:
        starts: ``(n_e, 2)`` each explorer's known start position (m, brain frame). F0: every
            particle starts there facing north (phi = 0), with weight 1/N, its start cell
            marked in its LocalMap, and no signature stored [Sect. 3.3.1; README "Choices": initial
            particles].
        n_particles: N per explorer.
        n_anchors: N_a, the length of a signature.
        grid: the estimate grid of the LocalMaps.
        sig_th: SIG_TH, the eq. 11 distance below which a signature matches a stored one.
        heading_model: "literal" (H-lit, eq. 6 as printed: the commanded absolute heading plus
            fresh noise, errors do not accumulate) or "accumulate" (H-acc: the particle's own
            heading plus the commanded turn plus noise, gyro-style) (README "Choices": heading
            errors).
        turn_noise: SD of n_phi as a share of the commanded turn |Delta_k| (0.20, Sect. 4.3.7).
        speed_noise: SD of n_v as a share of the commanded speed v_k (0.15, Sect. 4.3.7).
        weights: "eq8" (eq. 8 normalised) or "gauss" (exp(-delta^2 / 2 sigma_m^2)) (README
            "Choices": eq. 8's weights).
        sigma_m: the Gaussian weights' length (m; ours: D).
        resample: "on_match" (only after a match) or "every_tick" (also uniformly without
            one, as the generic filter of Sect. 3.3.1 does) (README "Choices": resampling).
        resample_noise: SD (m, per axis) of the Gaussian jitter added to every particle's
            position after each resampling ("roughening"; 0, the paper's reading: none, and no
            draw).
        min_match_age: stored signatures younger than this (s) cannot match, so a match means a
            loop closure rather than the last few ticks (README "Choices": match; 0 = off).
        sig_norm: eq. 11's normaliser, "count" (literal) or "rms" (README "Choices": eq. 11's
            normaliser).

    Attributes:
        pos: ``(n_e, N, 2)`` particle positions (m, brain frame).
        phi: ``(n_e, N)`` particle headings (deg clockwise from north, not wrapped).
        localmap: ``(n_e, N, H, W)`` bool, eq. 4's LocalMap (index [iy, ix]).
        weights: ``(n_e, N)`` weights; rows sum to 1.
        store: ``(n_e, N, capacity, 2)`` Store_i[j], particle i's position when signature j
            was stored; valid for ``j < n_stored[e]``.
        signatures: ``(n_e, capacity, N_a)`` the stored signatures S (NaN: not visible).
        stored_at: ``(n_e, capacity)`` when each was stored (s).
        n_stored: ``(n_e,)`` signatures stored per explorer.
        n_matches: ``(n_e,)`` matches so far per explorer.

    """

    def __init__(
        self,
        starts: np.ndarray,
        n_particles: int,
        n_anchors: int,
        grid: MapGrid,
        *,
        sig_th: float,
        heading_model: str = "literal",
        turn_noise: float = 0.20,
        speed_noise: float = 0.15,
        weights: str = "eq8",
        sigma_m: float = 0.5,
        resample: str = "on_match",
        resample_noise: float = 0.0,
        min_match_age: float = 0.0,
        sig_norm: str = "count",
    ) -> None:
        check_range("n_particles", n_particles, 1, integer=True)
        check_range("n_anchors", n_anchors, 1, integer=True)
        check_range("sig_th", sig_th, 0.0, low_open=True)
        check_choice("heading_model", heading_model, HEADING_MODELS)
        check_range("turn_noise", turn_noise, 0.0)
        check_range("speed_noise", speed_noise, 0.0)
        check_choice("weights", weights, WEIGHT_RULES)
        check_range("sigma_m", sigma_m, 0.0, low_open=True)
        check_choice("resample", resample, RESAMPLE_RULES)
        check_range("resample_noise", resample_noise, 0.0)
        check_range("min_match_age", min_match_age, 0.0)
        check_choice("sig_norm", sig_norm, SIG_NORMS)
        if not isinstance(grid, MapGrid):
            raise ConfigError(f"grid must be a MapGrid, got {grid!r}")
        starts = np.asarray(starts, dtype=float)
        if starts.ndim != 2 or starts.shape[0] < 1 or starts.shape[1] != 2:
            raise ConfigError(f"starts must be (n_e, 2) with n_e >= 1, got shape {starts.shape}")
        if not np.all(np.isfinite(starts)):
            raise ConfigError(f"starts must be finite, got {starts}")
        self.grid = grid
        self.sig_th = float(sig_th)
        self.heading_model = heading_model
        self.turn_noise, self.speed_noise = float(turn_noise), float(speed_noise)
        self.weight_rule, self.sigma_m = weights, float(sigma_m)
        self.resample, self.min_match_age = resample, float(min_match_age)
        self.resample_noise = float(resample_noise)
        self.sig_norm = sig_norm
        self._init_particles(starts, int(n_particles))
        self._init_memory(len(starts), int(n_particles), int(n_anchors))

    def _init_particles(self, starts: np.ndarray, n: int) -> None:
        """F0: all particles at the start, facing north, equal weights, start cell marked."""
        e = len(starts)
        self.pos = np.repeat(starts[:, None, :], n, axis=1)
        self.phi = np.zeros((e, n))
        self.weights = np.full((e, n), 1.0 / n)
        self.localmap = np.zeros((e, n, *self.grid.shape), dtype=bool)
        # How many of an explorer's particles have marked each cell: N x NodeMap, kept up to
        # date so eq. 9 costs nothing per tick (the smallest type that holds N sums fastest).
        self._counts = np.zeros((e, *self.grid.shape), dtype=np.min_scalar_type(n))
        self._mark()

    def _init_memory(self, e: int, n: int, n_anchors: int) -> None:
        """The empty signature set S of each explorer, with room to grow."""
        self.store = np.zeros((e, n, _INITIAL_CAPACITY, 2))
        self.signatures = np.full((e, _INITIAL_CAPACITY, n_anchors), np.nan)
        self.stored_at = np.zeros((e, _INITIAL_CAPACITY))
        self.n_stored = np.zeros(e, dtype=np.int64)
        self.n_matches = np.zeros(e, dtype=np.int64)

    @property
    def n_explorers(self) -> int:
        """n_e."""
        return self.pos.shape[0]

    @property
    def n_particles(self) -> int:
        """N."""
        return self.pos.shape[1]

    @property
    def n_anchors(self) -> int:
        """N_a."""
        return self.signatures.shape[2]

    def _per_explorer(self, name: str, values: np.ndarray, dtype: type = float) -> np.ndarray:
        """``values`` as an ``(n_e,)`` array, or ConfigError naming the argument."""
        values = np.asarray(values, dtype=dtype)
        if values.shape != (self.n_explorers,):
            raise ConfigError(
                f"{name} must have shape ({self.n_explorers},) (one per explorer), "
                f"got {values.shape}"
            )
        return values

    def predict(
        self,
        rng: np.random.Generator,
        heading: np.ndarray,
        turn: np.ndarray,
        speed: np.ndarray,
        moved: np.ndarray,
        dt: float = 1.0,
    ) -> None:
        """F1 (eqs. 3-6) for every explorer and particle at once.

        Draws the turn noise ``n_phi ~ Normal(0, (turn_noise |Delta_k|)^2)`` ``(n_e, N)``
        first, then the speed noise ``n_v ~ Normal(0, (speed_noise v_k)^2)`` ``(n_e, N)``,
        always both, so the draw order does not depend on the commands. Headings:
        H-lit ``phi_i = phi_k + n_phi`` (eq. 6), H-acc ``phi_i += Delta_k + n_phi``. Where the
        explorer moved, each particle flies ``v_i dt`` with ``v_i = v_k + n_v`` (eq. 5; an
        executed speed is never negative, as in the truth model) along
        ``(sin phi_i, cos phi_i)`` (eq. 3), then marks its cell in its LocalMap (eq. 4).

        Args:
            rng: the model's generator.
            heading: ``(n_e,)`` commanded absolute heading phi_k (deg clockwise from north).
            turn: ``(n_e,)`` commanded turn Delta_k (deg; wrapped here to (-180, 180], so a
                reversal has the 36 deg SD of README "Choices": actuation noise, whatever the
                caller's convention).
            speed: ``(n_e,)`` commanded speed v_k (m/s, >= 0).
            moved: ``(n_e,)`` bool; False where the explorer reported blocked or is inactive:
                no translation this tick, but headings still update.
            dt: the command's duration delta-t (s).

        """
        heading = self._per_explorer("heading", heading)
        turn = wrap_degrees(self._per_explorer("turn", turn))
        speed = self._per_explorer("speed", speed)
        moved = self._per_explorer("moved", moved, bool)
        check_range("dt", dt, 0.0, low_open=True)
        if not np.all(speed >= 0):
            raise ConfigError(f"speed must be >= 0 m/s, got {speed}")
        z_phi = rng.standard_normal(self.phi.shape)
        z_v = rng.standard_normal(self.phi.shape)
        accumulate = self.heading_model == "accumulate"
        filterkernels.predict(
            z_phi,
            z_v,
            heading,
            turn,
            speed,
            moved,
            float(dt),
            self.turn_noise,
            self.speed_noise,
            accumulate,
            self.phi,
            self.pos,
        )
        self._mark()

    def _mark(self) -> None:
        """Eq. 4: every particle marks the cell it is in; the per-cell counts behind eq. 9
        follow.
        """
        (x0, y0), cell = self.grid.origin, self.grid.cell
        filterkernels.mark(self.pos, self.localmap, self._counts, x0, y0, cell)

    def correct(
        self, rng: np.random.Generator, explorer: int, signature: np.ndarray, now: float
    ) -> Match:
        """F2 for one explorer with this tick's signature (Sect. 3.3, eqs. 7, 8, 11).

        The nearest stored signature at least ``min_match_age`` old (README "Choices": match)
        matches if its eq. 11 distance is below SIG_TH. Then each particle's eq. 7 distance
        ``delta_i = ||pos_i - Store_i[j]||`` sets its weight (eq. 8 or Gaussian) and the particles
        are resampled with replacement; the matched signature is not stored (README "Choices":
        match). Without a match the signature joins S with every particle's position (and with
        ``resample="every_tick"`` the particles are resampled uniformly).

        Args:
            rng: the model's generator (drawn from only when resampling).
            explorer: e, the explorer's index.
            signature: ``(N_a,)`` RToF signature s^k measured this tick (NaN: not visible).
            now: the time (s), to date the stored signature and apply ``min_match_age``.

        Returns:
            The revisit test's outcome.

        """
        e = self._explorer(explorer)
        signature = np.asarray(signature, dtype=float)
        if signature.shape != (self.n_anchors,):
            raise ConfigError(
                f"signature must have shape ({self.n_anchors},), got {signature.shape}"
            )
        j, distance = self._nearest(e, signature, now)
        if distance < self.sig_th:
            self._reweight(e, j)
            self._resample(rng, e)
            self.n_matches[e] += 1
            return Match(True, j, distance)
        self._store(e, signature, now)
        if self.resample == "every_tick":
            self._resample(rng, e)
        return Match(False, None, distance)

    def _explorer(self, explorer: int) -> int:
        """The explorer index, checked."""
        if not 0 <= explorer < self.n_explorers or int(explorer) != explorer:
            raise ConfigError(
                f"explorer must be an integer in [0, {self.n_explorers - 1}], got {explorer!r}"
            )
        return int(explorer)

    def _nearest(self, e: int, signature: np.ndarray, now: float) -> tuple[int, float]:
        """``(j, f)``: the nearest stored signature old enough to match (README "Choices": match)
        and its eq. 11 distance; ``(-1, inf)`` when there is none.
        """
        s = int(self.n_stored[e])
        if s == 0:
            return -1, np.inf
        j, distance = filterkernels.nearest_signature(
            signature,
            self.signatures[e, :s],
            self.stored_at[e, :s],
            float(now),
            self.min_match_age,
            self.sig_norm == "rms",
        )
        return int(j), float(distance)

    def _reweight(self, e: int, j: int) -> None:
        """Eqs. 7 and 8: weights from each particle's distance to its own Store_i[j]."""
        delta = filterkernels.eq7_distances(self.pos[e], self.store[e], j)
        if self.weight_rule == "eq8":
            self.weights[e] = filterkernels.eq8_weights(delta)
        else:
            self.weights[e] = _gauss_weights(delta, self.sigma_m)

    def _resample(self, rng: np.random.Generator, e: int) -> None:
        """Multinomial resampling with replacement [Sect. 3.3.2]: a particle's position,
        heading, LocalMap and Store travel together (README "Choices": resampling); the weights are
        reset to 1/N. With ``resample_noise`` > 0 every position then moves by a Gaussian
        jitter of that SD per axis (drawn after the picks), so copies of one particle part; the
        jitter marks no cell until the next prediction.
        """
        n = self.n_particles
        # N independent draws from the weights by inverse CDF: what Generator.choice(n, n,
        # p=w) computes, without its per-call validation.
        filterkernels.resample(
            self.weights[e],
            rng.random(n),
            self.pos[e],
            self.phi[e],
            self.localmap[e],
            self.store[e],
            int(self.n_stored[e]),
            self._counts[e],
        )
        if self.resample_noise > 0:
            self.pos[e] += rng.normal(0.0, self.resample_noise, (n, 2))
        self.weights[e] = 1.0 / n

    def _store(self, e: int, signature: np.ndarray, now: float) -> None:
        """Append s^k to S with every particle's position (its Store_i row), growing the
        memories by doubling when full.
        """
        s = int(self.n_stored[e])
        if s == self.signatures.shape[1]:
            self.store = np.concatenate([self.store, np.zeros_like(self.store)], axis=2)
            self.signatures = np.concatenate(
                [self.signatures, np.full_like(self.signatures, np.nan)], axis=1
            )
            self.stored_at = np.concatenate([self.stored_at, np.zeros_like(self.stored_at)], 1)
        self.signatures[e, s] = signature
        self.store[e, :, s] = self.pos[e]
        self.stored_at[e, s] = now
        self.n_stored[e] += 1

    def node_maps(self) -> np.ndarray:
        """Eq. 9 (F3): each explorer's NodeMap, the mean of its particles' LocalMaps.

        The mean is unweighted because the weights are uniform whenever the filter is at rest
        (they are reset on resampling).

        Returns:
            ``(n_e, H, W)`` float in [0, 1].

        """
        return self._counts / self.n_particles

    def global_map(self) -> np.ndarray:
        """Eq. 10 over this filter's explorers: :func:`global_map` of :meth:`node_maps`, the
        same values in one compiled pass over eq. 9's per-cell counts.

        Returns:
            ``(H, W)`` GlobalMap.

        """
        return filterkernels.global_map(self._counts, self.n_particles)

    def mean_positions(self) -> np.ndarray:
        """Each explorer's weighted mean particle position ``(n_e, 2)`` (m, brain frame)."""
        return np.einsum("en,enk->ek", self.weights, self.pos)


def calibrate_sig_th(
    measure: Callable[[np.random.Generator, np.ndarray], np.ndarray],
    sample_free: Callable[[np.random.Generator, int], np.ndarray],
    rng: np.random.Generator,
    locations: int = 5,
    per_location: int = 20,
    radius: float = 2.0,
    norm: str = "count",
    *,
    is_free: Callable[[np.ndarray], np.ndarray],
) -> float:
    """SIG_TH by the paper's procedure [Sect. 4.3.6], as README "Choices": SIG_TH states it.

    At ``locations`` random navigable places, draw ``per_location`` points uniformly in a disc
    of ``radius`` m around each (points that are not navigable are dropped and more are drawn
    until there are enough), take one signature at each point, and average eq. 11 over all
    pairs at the place (190 pairs for 20 points; pairs with no common anchor have no distance
    and are left out). SIG_TH is the mean over the places. The draw order is fixed: all the
    places first, then per place its disc points and its signatures.

    Args:
        measure: ``measure(rng, points)``: signatures ``(k, N_a)`` (NaN: anchor not visible)
            at points ``(k, 2)`` m, drawing any measurement noise from ``rng``.
        sample_free: ``sample_free(rng, k)``: ``(k, 2)`` random navigable points (m).
        rng: the generator of every draw.
        locations: how many places (5 in the paper).
        per_location: signatures per place (20 in the paper).
        radius: the disc's radius (m; 2 in the paper).
        norm: eq. 11's normaliser, "count" or "rms".
        is_free: ``is_free(points)``: ``(k,)`` bool, which points ``(k, 2)`` are navigable.

    Returns:
        SIG_TH in the units of the signatures.

    """
    check_range("locations", locations, 1, integer=True)
    check_range("per_location", per_location, 2, integer=True)
    check_range("radius", radius, 0.0, low_open=True)
    check_choice("norm", norm, SIG_NORMS)
    centres = np.asarray(sample_free(rng, int(locations)), dtype=float).reshape(-1, 2)
    means = []
    for centre in centres:
        points = _free_disc_points(rng, centre, int(per_location), float(radius), is_free)
        means.append(_mean_pair_distance(np.asarray(measure(rng, points), dtype=float), norm))
    return float(np.mean(means))


def _free_disc_points(
    rng: np.random.Generator,
    centre: np.ndarray,
    k: int,
    radius: float,
    is_free: Callable[[np.ndarray], np.ndarray],
) -> np.ndarray:
    """``k`` navigable points uniform in the disc of ``radius`` around ``centre``, drawn k at a
    time (uniform in area: r = radius sqrt(u)) until enough are navigable.
    """
    kept = np.zeros((0, 2))
    for _ in range(_MAX_DRAW_ROUNDS):
        r = radius * np.sqrt(rng.random(k))
        a = rng.uniform(0.0, 2.0 * np.pi, k)
        draw = centre + np.stack([r * portable.sin(a), r * portable.cos(a)], axis=1)
        kept = np.vstack([kept, draw[np.asarray(is_free(draw), dtype=bool)]])
        if len(kept) >= k:
            return kept[:k]
    raise ConfigError(
        f"is_free accepted {len(kept)} of {_MAX_DRAW_ROUNDS * k} points in the {radius:g} m "
        f"disc around {centre.tolist()}; sample_free must return navigable points"
    )


def _mean_pair_distance(signatures: np.ndarray, norm: str) -> float:
    """Mean eq. 11 distance over all pairs of ``(k, N_a)`` signatures that share an anchor."""
    i, j = np.triu_indices(len(signatures), k=1)
    distance = _eq11(signatures[i], signatures[j], norm)
    finite = distance[np.isfinite(distance)]
    if len(finite) == 0:
        raise ConfigError("measure returned no two signatures with an anchor in common")
    return float(finite.mean())
