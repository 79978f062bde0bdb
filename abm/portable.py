"""Elementary functions that give the same bits on every CPU, for the decisions of a run.

Two layers of a machine change the last bits of ``exp``, ``sin``, ``atan2`` and their kin:

- numpy picks a SIMD implementation of its transcendental ufuncs at import, by the CPU's
  features: with AVX-512 (``X86_V4``) ``np.exp``, ``np.log10``, ``np.power``, ``np.arctan2``,
  ``np.tan`` use vectorised approximations whose last bits differ from the C library's in a few
  percent of results (numpy 2.5.5: ``np.exp`` of 1,000 decay factors ``exp(-0.0123 k)``, 48
  differ), while an AVX2 machine gets the C library's;
- the C library (glibc) picks its own code by the CPU too: on a CPU without FMA its ``exp``,
  ``pow``, ``sin``, ``cos`` and ``atan2`` differ from the FMA code in 1 to 6 results in 5,000,
  and another C library (another glibc, macOS, Windows, musl) has other code altogether.

A last-bit difference that reaches a comparison (which pixel a robot is on, which beacon is
nearest, which particle survives resampling, whether a launch comes before a physics tick)
changes the run: on a 100 m hall the pheromone decay factor alone moved a landing
1.5 mm between two machines. So the functions here are written with IEEE-754 arithmetic only
(``+ - * /``, comparisons, ``floor``, ``frexp``/``ldexp``: each correctly rounded or exact on
every IEEE machine, x86-64 and ARM64 alike), compiled by numba, which never fuses a multiply
and an add unless asked for ``fastmath`` (this project never asks). They follow FreeBSD's
msun (fdlibm): argument reduction and minimax polynomials. Measured against glibc (itself
within about half an ulp of the exact value) on 200,000 arguments each: ``exp``, ``sin``,
``cos``, ``atan2`` within 1 ulp, ``log10`` within 2, ``tan`` within 3; ``power`` multiplies by
squaring for integral exponents up to 64 (within 2 ulp for y = -3), else is ``exp(y log x)``, whose
error grows with ``|y ln x|`` (tests allow ``4 + 4 |y ln x|`` ulp).

Use the ufuncs (``exp``, ``sin``, ...) on arrays and the ``*_scalar`` functions inside numba
kernels, wherever a value feeds a decision of the model. ``sqrt`` is correctly rounded
everywhere and needs no wrapper; ``math.hypot`` is CPython's own and numba's is the C
library's, which is the same on CPUs with and without FMA (measured; see
``docs/reproducibility.md``).
"""

import math
import threading
from collections.abc import Callable

import numpy as np
from numba import njit, vectorize

__all__ = [
    "PORTABLE_RANGE",
    "arctan2",
    "atan2_scalar",
    "cos",
    "cos_scalar",
    "exp",
    "exp_scalar",
    "log10",
    "log_scalar",
    "power",
    "sin",
    "sin_scalar",
    "tan",
]

#: |x| (rad) up to which sin, cos and tan reduce their argument with three-part Cody-Waite
#: constants (exact products); beyond it they return NaN rather than a machine's guess.
PORTABLE_RANGE = 2.0**19 * math.pi / 2

_ROUND = 6755399441055744.0  # 1.5 * 2**52: x + _ROUND - _ROUND rounds x to an integer
_INVPIO2 = 6.36619772367581382433e-01
_PIO2_1 = 1.57079632673412561417e00  # first 33 bits of pi/2
_PIO2_2 = 6.07710050630396597660e-11  # next 33 bits
_PIO2_2T = 2.02226624879595063154e-21
_PIO2_3 = 2.02226624871116645580e-21  # next 33 bits
_PIO2_3T = 8.47842766036889956997e-32

_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11


@njit(cache=True)
def _reduce(x):
    """``x = n pi/2 + (y0 + y1)`` with |y0 + y1| <= ~pi/4: returns ``n mod 4, y0, y1``."""
    fn = (x * _INVPIO2 + _ROUND) - _ROUND
    r = x - fn * _PIO2_1
    t = r
    w = fn * _PIO2_2
    r = t - w
    w = fn * _PIO2_2T - ((t - r) - w)
    t = r
    w = fn * _PIO2_3
    r = t - w
    w = fn * _PIO2_3T - ((t - r) - w)
    y0 = r - w
    y1 = (r - y0) - w
    return int(fn) & 3, y0, y1


@njit(cache=True)
def _ksin(x, y):
    """sin(x + y) for |x + y| <= ~pi/4, y the tail of x (msun's __kernel_sin)."""
    z = x * x
    w = z * z
    r = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
    v = z * x
    return x - ((z * (0.5 * y - v * r) - y) - v * _S1)


@njit(cache=True)
def _kcos(x, y):
    """cos(x + y) for |x + y| <= ~pi/4, y the tail of x (msun's __kernel_cos)."""
    z = x * x
    w = z * z
    r = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
    hz = 0.5 * z
    w = 1.0 - hz
    return w + (((1.0 - w) - hz) + (z * r - x * y))


@njit(cache=True)
def _sincos(x):
    if not abs(x) <= PORTABLE_RANGE:
        return math.nan, math.nan
    if abs(x) <= 0.7853981633974483:
        return _ksin(x, 0.0), _kcos(x, 0.0)
    n, y0, y1 = _reduce(x)
    s, c = _ksin(y0, y1), _kcos(y0, y1)
    if n == 0:
        return s, c
    if n == 1:
        return c, -s
    if n == 2:
        return -s, -c
    return -c, s


@njit(cache=True)
def sin_scalar(x: float) -> float:
    """Sine of ``x`` (rad), |x| <= :data:`PORTABLE_RANGE` (NaN beyond)."""
    return _sincos(x)[0]


@njit(cache=True)
def cos_scalar(x: float) -> float:
    """Cosine of ``x`` (rad), |x| <= :data:`PORTABLE_RANGE` (NaN beyond)."""
    return _sincos(x)[1]


_ATANHI = (4.63647609000806093515e-01, 7.85398163397448278999e-01, 9.82793723247329054082e-01)
_ATANLO = (2.26987774529616870924e-17, 3.06161699786838301793e-17, 1.39033110312309984516e-17)
_ATANHI3, _ATANLO3 = 1.57079632679489655800e00, 6.12323399573676603587e-17
_AT0, _AT1 = 3.33333333333329318027e-01, -1.99999999998764832476e-01
_AT2, _AT3 = 1.42857142725034663711e-01, -1.11111104054623557880e-01
_AT4, _AT5 = 9.09088713343650656196e-02, -7.69187620504482999495e-02
_AT6, _AT7 = 6.66107313738753120669e-02, -5.83357013379057348645e-02
_AT8 = 4.97687799461593236017e-02
_AT9, _AT10 = -3.65315727442169155270e-02, 1.62858201153657823623e-02


@njit(cache=True)
def _atan(x):
    """atan(x) (msun's s_atan.c)."""
    ax = abs(x)
    if ax != ax:
        return x
    if ax >= 2.0**66:
        return math.copysign(_ATANHI3 + _ATANLO3, x)
    k = -1
    if ax < 0.4375:
        if ax < 2.0**-27:
            return x
        t = x
    elif ax < 1.1875:
        if ax < 0.6875:
            k, t = 0, (2.0 * ax - 1.0) / (2.0 + ax)
        else:
            k, t = 1, (ax - 1.0) / (ax + 1.0)
    elif ax < 2.4375:
        k, t = 2, (ax - 1.5) / (1.0 + 1.5 * ax)
    else:
        k, t = 3, -1.0 / ax
    z = t * t
    w = z * z
    s1 = z * (_AT0 + w * (_AT2 + w * (_AT4 + w * (_AT6 + w * (_AT8 + w * _AT10)))))
    s2 = w * (_AT1 + w * (_AT3 + w * (_AT5 + w * (_AT7 + w * _AT9))))
    if k < 0:
        return t - t * (s1 + s2)
    hi = _ATANHI3 if k == 3 else _ATANHI[k]
    lo = _ATANLO3 if k == 3 else _ATANLO[k]
    z = hi - ((t * (s1 + s2) - lo) - t)
    return -z if x < 0 else z


_PI = 3.1415926535897931160e00
_PI_LO = 1.2246467991473531772e-16
_PI_O_2 = 1.5707963267948965580e00
_PI_O_4 = 7.8539816339744827900e-01


@njit(cache=True)
def atan2_scalar(y: float, x: float) -> float:
    """Angle of the point ``(x, y)`` (rad, in [-pi, pi]), with C's signed-zero and infinity
    conventions (msun's e_atan2.c).
    """
    if x != x or y != y:
        return x + y
    if x == 1.0:
        return _atan(y)
    m = (1 if math.copysign(1.0, y) < 0 else 0) + (2 if math.copysign(1.0, x) < 0 else 0)
    if y == 0.0:
        return (y, y, _PI, -_PI)[m]
    if x == 0.0:
        return -_PI_O_2 if y < 0 else _PI_O_2
    if math.isinf(x):
        if math.isinf(y):
            return (_PI_O_4, -_PI_O_4, 3.0 * _PI_O_4, -3.0 * _PI_O_4)[m]
        return (0.0, -0.0, _PI, -_PI)[m]
    if math.isinf(y):
        return -_PI_O_2 if y < 0 else _PI_O_2
    k = math.frexp(y)[1] - math.frexp(x)[1]
    if k > 60:
        z = _PI_O_2 + 0.5 * _PI_LO
        m &= 1
    elif x < 0 and k < -60:
        z = 0.0
    else:
        z = _atan(abs(y / x))
    if m == 0:
        return z
    if m == 1:
        return -z
    if m == 2:
        return _PI - (z - _PI_LO)
    return (z - _PI_LO) - _PI


_LN2_HI, _LN2_LO = 6.93147180369123816490e-01, 1.90821492927058770002e-10
_INVLN2 = 1.44269504088896338700e00
_P1, _P2, _P3 = 1.66666666666666019037e-01, -2.77777777770155933842e-03, 6.61375632143793436117e-05
_P4, _P5 = -1.65339022054652515390e-06, 4.13813679705723846039e-08


@njit(cache=True)
def exp_scalar(x: float) -> float:
    """``e**x`` (msun's e_exp.c)."""
    if x != x:
        return x
    if x > 7.09782712893383973096e02:
        return math.inf
    if x < -7.45133219101941108420e02:
        return 0.0
    ax = abs(x)
    hi = x
    lo = 0.0
    k = 0
    if ax > 0.5 * 0.6931471805599453:
        if ax < 1.5 * 0.6931471805599453:
            k = -1 if x < 0 else 1
            hi = x - k * _LN2_HI
            lo = k * _LN2_LO
        else:
            k = int(_INVLN2 * x + (-0.5 if x < 0 else 0.5))
            hi = x - k * _LN2_HI
            lo = k * _LN2_LO
        x = hi - lo
    elif ax < 2.0**-28:
        return 1.0 + x
    t = x * x
    c = x - t * (_P1 + t * (_P2 + t * (_P3 + t * (_P4 + t * _P5))))
    if k == 0:
        return 1.0 - ((x * c) / (c - 2.0) - x)
    return math.ldexp(1.0 - ((lo - (x * c) / (2.0 - c)) - hi), k)


_LG1, _LG2, _LG3 = 6.666666666666735130e-01, 3.999999999940941908e-01, 2.857142874366239149e-01
_LG4, _LG5, _LG6 = 2.222219843214978396e-01, 1.818357216161805012e-01, 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01


@njit(cache=True)
def log_scalar(x: float) -> float:
    """Natural logarithm (msun's e_log.c; ``-inf`` at 0, NaN below)."""
    if x != x or x == math.inf:
        return x
    if x <= 0.0:
        return -math.inf if x == 0.0 else math.nan
    m, k = math.frexp(x)
    if m < 0.7071067811865476:
        m *= 2.0
        k -= 1
    f = m - 1.0
    dk = float(k)
    if f == 0.0:
        return dk * _LN2_HI + dk * _LN2_LO
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    r = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7))) + w * (_LG2 + w * (_LG4 + w * _LG6))
    hfsq = 0.5 * f * f
    return dk * _LN2_HI - ((hfsq - (s * (hfsq + r) + dk * _LN2_LO)) - f)


_INVLN10 = 0.4342944819032518


@njit(cache=True)
def _pow(x, y):
    if y == 0.0 or x == 1.0:
        return 1.0
    if x != x or y != y:
        return math.nan
    sign = 1.0
    if x < 0.0:
        if math.isinf(y) or y != math.floor(y):
            return math.nan
        x = -x
        sign = -1.0 if 0.5 * y != math.floor(0.5 * y) else 1.0
    if x == 0.0:
        return sign * (math.inf if y < 0 else 0.0)
    if math.isinf(x):
        return sign * (math.inf if y > 0 else 0.0)
    if y == math.floor(y) and abs(y) <= 64.0:  # by squaring (y = -3: within 2 ulp, measured)
        n = int(abs(y))
        result = 1.0
        base = x
        while True:
            if n & 1:
                result *= base
            n >>= 1
            if not n:  # no square past the last bit: it could overflow (a spurious flag)
                break
            base *= base
        return sign * (1.0 / result if y < 0 else result)
    return sign * exp_scalar(y * log_scalar(x))


def _exp(x):
    """``e**x``, element-wise."""
    return exp_scalar(x)


def _log10(x):
    """Base-10 logarithm, element-wise (``-inf`` at 0, NaN below)."""
    return log_scalar(x) * _INVLN10


def _power(x, y):
    """``x**y``, element-wise: by squaring for integral ``|y| <= 64``, else ``exp(y log x)``;
    negative x only with integral y (NaN otherwise).
    """
    return _pow(x, y)


def _arctan2(y, x):
    """Angle of the point ``(x, y)`` (rad, in [-pi, pi]), element-wise."""
    return atan2_scalar(y, x)


def _sin(x):
    """Sine (rad), element-wise; NaN beyond :data:`PORTABLE_RANGE`."""
    return _sincos(x)[0]


def _cos(x):
    """Cosine (rad), element-wise; NaN beyond :data:`PORTABLE_RANGE`."""
    return _sincos(x)[1]


def _tan(x):
    """Tangent (rad), element-wise, as sine over cosine; NaN beyond :data:`PORTABLE_RANGE`."""
    s, c = _sincos(x)
    return s / c


#: The element-wise ufuncs by name: each one's numba signature and scalar kernel. They are
#: compiled (or loaded from numba's cache) on first use, by :func:`__getattr__`, not at import:
#: building all seven took about 0.3 s, which every command paid, ``abm run MODEL --help``
#: included, though only a running model evaluates them.
_UFUNCS = {
    "exp": ("float64(float64)", _exp),
    "log10": ("float64(float64)", _log10),
    "power": ("float64(float64, float64)", _power),
    "arctan2": ("float64(float64, float64)", _arctan2),
    "sin": ("float64(float64)", _sin),
    "cos": ("float64(float64)", _cos),
    "tan": ("float64(float64)", _tan),
}
_BUILD = threading.Lock()

# The ufuncs' names, declared (no value: a module attribute is made only by __getattr__).
exp: Callable[..., np.ndarray]
log10: Callable[..., np.ndarray]
power: Callable[..., np.ndarray]
arctan2: Callable[..., np.ndarray]
sin: Callable[..., np.ndarray]
cos: Callable[..., np.ndarray]
tan: Callable[..., np.ndarray]


def __getattr__(name: str):
    """The ufunc ``name`` (``exp``, ``sin``, ...), built by numba's ``vectorize`` on first use
    and kept as the module's attribute, so every later ``portable.name`` is the same ufunc.
    """
    if name not in _UFUNCS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    with _BUILD:
        if name not in globals():
            signature, kernel = _UFUNCS[name]
            kernel.__name__ = kernel.__qualname__ = name  # the ufunc's name and cache file
            globals()[name] = vectorize([signature], cache=True)(kernel)
    return globals()[name]


def __dir__() -> list[str]:
    """The module's names, the ufuncs not built yet included."""
    return sorted(set(globals()) | set(_UFUNCS))
