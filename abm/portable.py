"""Elementary functions that give the same bits on every CPU, for the decisions of a run.

numpy picks a SIMD implementation of its transcendental ufuncs at import, by the CPU's
features: with AVX-512 (``X86_V4``) ``np.exp``, ``np.log10``, ``np.power``, ``np.arctan2``,
``np.tan`` and others use vectorised approximations whose last bits differ from the scalar C
library's in a few percent of results (measured on numpy 2.5.5: ``np.exp`` on 1,000 decay
factors ``exp(-0.0123 k)``, 48 differ), while a machine with AVX2 only gets the C library's.
A last-bit difference that reaches a comparison (which pixel a robot is on, which beacon is
nearest, which particle survives resampling) changes the run; on Arnaldo et al.'s hall the
pheromone decay factor alone moved a landing by 1.5 mm between two machines.

These ufuncs are compiled by numba as scalar loops over the C library's function (no
vectorised maths library: numba uses Intel SVML only with ``fastmath``, which this project
never sets), so they return what ``math.exp`` etc. return, whatever numpy's dispatch: use them
wherever a value feeds a decision of the model. Arithmetic (``+ - * /``, ``sqrt``) is IEEE-754
correctly rounded everywhere and needs no wrapper; ``np.hypot`` does not dispatch either.

The C library itself (glibc >= 2.28) is the same code on every x86-64 CPU with FMA
(x86-64-v3, every Intel since Haswell, every AMD since Zen), and aarch64 builds the same
sources; see ``docs/reproducibility.md`` for what that covers.
"""

import math

from numba import vectorize

__all__ = ["arctan2", "cos", "exp", "log10", "power", "sin", "tan"]

_UNARY = ["float64(float64)"]
_BINARY = ["float64(float64, float64)"]


@vectorize(_UNARY, cache=True)
def exp(x):
    """``e**x`` (the C library's ``exp``), element-wise."""
    return math.exp(x)


@vectorize(_UNARY, cache=True)
def log10(x):
    """Base-10 logarithm (the C library's ``log10``), element-wise; ``-inf`` at 0."""
    if x == 0.0:
        return -math.inf
    if x < 0.0:
        return math.nan
    return math.log10(x)


@vectorize(_BINARY, cache=True)
def power(x, y):
    """``x**y`` (the C library's ``pow``), element-wise."""
    return math.pow(x, y)


@vectorize(_BINARY, cache=True)
def arctan2(y, x):
    """Angle of the point ``(x, y)`` (rad, in [-pi, pi]; the C library's ``atan2``)."""
    return math.atan2(y, x)


@vectorize(_UNARY, cache=True)
def sin(x):
    """Sine of ``x`` (rad; the C library's ``sin``), element-wise."""
    return math.sin(x)


@vectorize(_UNARY, cache=True)
def cos(x):
    """Cosine of ``x`` (rad; the C library's ``cos``), element-wise."""
    return math.cos(x)


@vectorize(_UNARY, cache=True)
def tan(x):
    """Tangent of ``x`` (rad; the C library's ``tan``), element-wise."""
    return math.tan(x)
