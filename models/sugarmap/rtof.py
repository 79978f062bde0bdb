"""Round-trip time-of-flight signatures in metre-equivalents (our reading, README "Choices": RToF
model).

The paper gives no RToF model, unit or noise: only that single values vary a lot while the
combined vector (the signature) is stable and location-specific (Sect. 3.1, 4.4, Fig. 14). We
measure in metres: the RToF of anchor a at point x is ``|x - x_a| + b_a(x) + eps`` with eps ~
Normal(0, sigma_eps^2) per measurement and b_a a static multipath bias field per anchor, smooth
over about 1 m (a Gaussian value on a 1 m lattice, interpolated bilinearly), fixed for the run.
An anchor the explorer cannot reach (its radio link is down) is missing: NaN.
"""

import numpy as np

from abm.errors import check_range

__all__ = ["RToF"]


class RToF:
    """The RToF signatures of the landed anchors, as explorers measure them.

    Args:
        anchors: ``(N_a, 2)`` anchor positions (m).
        noise: sigma_eps, SD of one measurement (m).
        bias: sigma_b, SD of the static bias fields (m); 0: none.
        extent: ``(width, height)`` of the arena (m), which the bias fields cover.
        rng: the model's generator (the bias fields are drawn here when ``bias > 0``).
        spacing: the bias fields' lattice (m).

    """

    def __init__(
        self,
        anchors: np.ndarray,
        noise: float,
        bias: float,
        extent: tuple[float, float],
        rng: np.random.Generator,
        spacing: float = 1.0,
    ) -> None:
        check_range("noise", noise, 0.0)
        check_range("bias", bias, 0.0)
        self.anchors = np.asarray(anchors, dtype=float).reshape(-1, 2)
        self.noise = float(noise)
        self.bias = float(bias)
        self.spacing = float(spacing)
        shape = (
            len(self.anchors),
            int(np.ceil(extent[1] / spacing)) + 2,
            int(np.ceil(extent[0] / spacing)) + 2,
        )
        self._fields = rng.normal(0.0, bias, shape) if bias > 0 else None

    def measure(
        self, points: np.ndarray, visible: np.ndarray, rng: np.random.Generator
    ) -> np.ndarray:
        """Signatures ``(k, N_a)`` at ``points`` ``(k, 2)``; NaN where ``visible`` is False.

        Draws one Normal per point and anchor (visible or not), so the draw count does not
        depend on the links.
        """
        points = np.atleast_2d(np.asarray(points, dtype=float))
        rtof = np.hypot(*(points[:, None, :] - self.anchors[None, :, :]).transpose(2, 0, 1))
        if self._fields is not None:
            rtof = rtof + self._bias_at(points)
        if self.noise > 0:
            rtof = rtof + rng.normal(0.0, self.noise, rtof.shape)
        return np.where(visible, rtof, np.nan)

    def _bias_at(self, points: np.ndarray) -> np.ndarray:
        """Bilinear interpolation of every anchor's bias field at the points, ``(k, N_a)``."""
        fields = self._fields
        gx = np.clip(points[:, 0] / self.spacing, 0.0, fields.shape[2] - 1.001)
        gy = np.clip(points[:, 1] / self.spacing, 0.0, fields.shape[1] - 1.001)
        ix, iy = gx.astype(int), gy.astype(int)
        fx, fy = (gx - ix)[:, None], (gy - iy)[:, None]
        f = fields.transpose(1, 2, 0)  # (rows, cols, N_a)
        return (
            f[iy, ix] * (1 - fx) * (1 - fy)
            + f[iy, ix + 1] * fx * (1 - fy)
            + f[iy + 1, ix] * (1 - fx) * fy
            + f[iy + 1, ix + 1] * fx * fy
        )
