"""The second-order recursive filter of the response spectrum, compiled: the arithmetic of
:func:`scipy.signal.lfilter`.

:func:`isorock.processing.intensity.displacement_history` runs the exact recurrence of a linear
oscillator (Nigam & Jennings 1969) as a recursive filter of three coefficients. scipy's
:func:`~scipy.signal.lfilter` does it in C, but ``import scipy.signal`` costs a job about half a second
(most of it the parsing of its docstrings), once in every job of the assessment that computes a
spectral acceleration. This kernel is that filter, the transposed direct form II of scipy's
``_linear_filter`` (``scipy/signal/_lfilter.c``) operation for operation, in the same order, so that
it returns the same numbers (``tests/processing/test_intensity.py`` compares the two, bit for bit):

    y[k]  = z0 + b0 x[k]
    z0    = (z1 + x[k] b1) - y[k] a1
    z1    = x[k] b2 - y[k] a2

with ``a0 = 1`` (scipy divides the coefficients by ``a0``; here it is 1, and the division changes
nothing). numba compiles it without ``fastmath``: LLVM neither reorders nor fuses these operations.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def second_order_filter(b, a, x, z0, z1):  # pragma: no cover - compiled
    y = np.empty(x.size)
    for k in range(x.size):
        xn = x[k]
        yn = z0 + b[0] * xn
        z0 = z1 + xn * b[1] - yn * a[1]
        z1 = xn * b[2] - yn * a[2]
        y[k] = yn
    return y
