"""Taylor-series step of the friction-pendulum isolator in full contact under a linear-in-time input.

In full contact the base of a friction pendulum obeys (per unit total mass, docs/model.md §2, §4)::

    u' = v,    v' = -(a0 + c1 tau) - kb u - mu g Z,    Z' = (v / Y) (1 - q Z^2)

with ``q = beta + gamma sign(v Z)``: ``beta + gamma`` while ``v Z > 0`` (loading) and ``beta - gamma``
while ``v Z < 0`` (unloading, up to ``Z = 0``), the law whose closed form is
:func:`isorock.physics.engine._model.bw_phi`. On a piece where ``q`` is constant the right-hand side is a
polynomial, so the Taylor coefficients of ``(u, v, Z)`` at the start of a step follow from a
recurrence (automatic differentiation: ``Z^2`` and ``v Z^2`` by Cauchy products) without a single
transcendental function, and one polynomial gives the motion over the whole step: the step can be as
long as a record sample, where the Dormand-Prince path had to resolve the pre-yield oscillation of the
isolator (``sqrt(mu g / Y)``, about 60 rad/s) with several steps of six stages each.

The step is cut where ``v`` reverses and where ``Z`` crosses zero (where ``q`` changes); its length
is chosen so that the last term of every series, which bounds the truncation error of a series
within its radius of convergence from above, stays within the integrator's tolerances
(``atol + rtol |y|``, as in the Dormand-Prince error control). The Bouc-Wen variable at the end of a
step is then taken from its exact closed form (:func:`isorock.physics.engine._model.bw_phi`), so that ``Z``
never drifts off the hysteresis law.
"""

from __future__ import annotations

from isorock.physics.engine._layout import P_ATOL, P_BWB, P_BWG, P_G, P_KB, P_MU, P_RTOL, P_Y, njit_inner

NT = 10
"""Order of the series (terms 0..NT)."""
Z_ZERO = 1e-9
"""A Bouc-Wen variable this close to zero starts the loading branch."""
_INV = tuple(1.0 / (k + 1) for k in range(NT))  # 1 / (k + 1): no division in the recurrence


@njit_inner(forceinline=True)
def poly(c, tau):
    """Value at ``tau`` of the series ``c`` (a row of the coefficient array; Horner)."""
    x = c[NT]
    for k in range(NT - 1, -1, -1):
        x = x * tau + c[k]
    return x


@njit_inner(forceinline=True)
def poly2(C, tau):
    """Values at ``tau`` of the series of ``u`` and ``v`` (rows 0 and 1), by two Horner chains at once."""
    x = C[0, NT]
    y = C[1, NT]
    for k in range(NT - 1, -1, -1):
        x = x * tau + C[0, k]
        y = y * tau + C[1, k]
    return x, y


@njit_inner(forceinline=True)
def dpoly(c, tau):
    """Derivative with respect to ``tau`` of :func:`poly`."""
    x = NT * c[NT]
    for k in range(NT - 1, 0, -1):
        x = x * tau + k * c[k]
    return x


@njit_inner()
def fp_coefficients_reference(u0, v0, z0, a0, c1, direction, C, P):
    """Taylor coefficients of ``u, v, Z`` (rows 0, 1, 2 of ``C``, ``NT + 1`` columns each): the
    recurrence written as loops, the definition that :func:`fp_coefficients` unrolls (tested equal).

    Parameters
    ----------
    u0, v0 : float
        Base displacement [m] and velocity [m/s] at the start of the step.
    z0 : float
        Bouc-Wen variable [-] at the start.
    a0, c1 : float
        Ground acceleration [m/s^2] at the start and its slope [m/s^3].
    direction : float
        Sign of the base motion over the step (+1 or -1): picks the branch of the hysteresis law.
    C : numpy.ndarray
        Work array (5 x (NT + 1)); rows 3 and 4 hold ``Z^2`` and ``v Z^2``.
    P : tuple of float
        Parameter vector.
    """
    kb = P[P_KB]
    mug = P[P_MU] * P[P_G]
    iy = 1.0 / P[P_Y]
    # loading (v Z > 0) or unloading; Z = 0 starts loading (Z moves with v), and so does a Z within
    # Z_ZERO of zero on the unloading side (the round-off left where a step was cut at Z = 0: the two
    # laws differ by (gamma - beta) Z^2 there, far below the tolerances)
    q = P[P_BWB] + P[P_BWG] if direction * z0 >= -Z_ZERO else P[P_BWB] - P[P_BWG]
    C[0, 0] = u0
    C[1, 0] = v0
    C[2, 0] = z0
    for k in range(NT):
        # (Z^2)_k by the symmetric Cauchy product, then (v Z^2)_k; two partial sums each, which
        # halves the chain of dependent additions that bounds the cost of the recurrence
        w0 = 0.0
        w1 = 0.0
        m = (k + 1) // 2
        i = 0
        while i + 1 < m:
            w0 += C[2, i] * C[2, k - i]
            w1 += C[2, i + 1] * C[2, k - i - 1]
            i += 2
        if i < m:
            w0 += C[2, i] * C[2, k - i]
        w = 2.0 * (w0 + w1)
        if k % 2 == 0:
            w += C[2, k // 2] * C[2, k // 2]
        C[3, k] = w
        p0 = 0.0
        p1 = 0.0
        i = 0
        while i < k:
            p0 += C[1, i] * C[3, k - i]
            p1 += C[1, i + 1] * C[3, k - i - 1]
            i += 2
        if i == k:
            p0 += C[1, k] * C[3, 0]
        p = p0 + p1
        C[4, k] = p
        inv = _INV[k]
        C[0, k + 1] = C[1, k] * inv
        f = -kb * C[0, k] - mug * C[2, k]
        if k == 0:
            f -= a0
        elif k == 1:
            f -= c1
        C[1, k + 1] = f * inv
        C[2, k + 1] = (C[1, k] - q * p) * inv * iy


@njit_inner()
def fp_coefficients(u0, v0, z0, a0, c1, direction, C, P):
    """Taylor coefficients of ``u, v, Z`` (rows 0, 1, 2 of ``C``, ``NT + 1`` columns each).

    The recurrence of :func:`fp_coefficients_reference` unrolled for ``NT = 10`` (straight-line code:
    the loops' short, varying trip counts cost as much as the arithmetic). Regenerate it with
    ``python -m isorock.physics.engine._series`` after changing ``NT``.

    Parameters
    ----------
    u0, v0 : float
        Base displacement [m] and velocity [m/s] at the start of the step.
    z0 : float
        Bouc-Wen variable [-] at the start.
    a0, c1 : float
        Ground acceleration [m/s^2] at the start and its slope [m/s^3].
    direction : float
        Sign of the base motion over the step (+1 or -1): picks the branch of the hysteresis law.
    C : numpy.ndarray
        Output array (at least 3 x (NT + 1)).
    P : tuple of float
        Parameter vector.
    """
    kb = P[P_KB]
    mug = P[P_MU] * P[P_G]
    iy = 1.0 / P[P_Y]
    q = P[P_BWB] + P[P_BWG] if direction * z0 >= -Z_ZERO else P[P_BWB] - P[P_BWG]
    u_0 = u0
    v_0 = v0
    z_0 = z0
    w_0 = z_0 * z_0
    p_0 = v_0 * w_0
    u_1 = v_0 * 1.0
    v_1 = (-kb * u_0 - mug * z_0 - a0) * 1.0
    z_1 = (v_0 - q * p_0) * (1.0 * iy)
    w_1 = 2.0 * (z_0 * z_1)
    p_1 = v_0 * w_1 + v_1 * w_0
    u_2 = v_1 * 0.5
    v_2 = (-kb * u_1 - mug * z_1 - c1) * 0.5
    z_2 = (v_1 - q * p_1) * (0.5 * iy)
    w_2 = 2.0 * (z_0 * z_2) + z_1 * z_1
    p_2 = v_0 * w_2 + v_1 * w_1 + v_2 * w_0
    u_3 = v_2 * 0.3333333333333333
    v_3 = (-kb * u_2 - mug * z_2) * 0.3333333333333333
    z_3 = (v_2 - q * p_2) * (0.3333333333333333 * iy)
    w_3 = 2.0 * (z_0 * z_3 + z_1 * z_2)
    p_3 = v_0 * w_3 + v_1 * w_2 + v_2 * w_1 + v_3 * w_0
    u_4 = v_3 * 0.25
    v_4 = (-kb * u_3 - mug * z_3) * 0.25
    z_4 = (v_3 - q * p_3) * (0.25 * iy)
    w_4 = 2.0 * (z_0 * z_4 + z_1 * z_3) + z_2 * z_2
    p_4 = v_0 * w_4 + v_1 * w_3 + v_2 * w_2 + v_3 * w_1 + v_4 * w_0
    u_5 = v_4 * 0.2
    v_5 = (-kb * u_4 - mug * z_4) * 0.2
    z_5 = (v_4 - q * p_4) * (0.2 * iy)
    w_5 = 2.0 * (z_0 * z_5 + z_1 * z_4 + z_2 * z_3)
    p_5a = v_0 * w_5 + v_1 * w_4 + v_2 * w_3
    p_5b = v_3 * w_2 + v_4 * w_1 + v_5 * w_0
    p_5 = p_5a + p_5b
    u_6 = v_5 * 0.16666666666666666
    v_6 = (-kb * u_5 - mug * z_5) * 0.16666666666666666
    z_6 = (v_5 - q * p_5) * (0.16666666666666666 * iy)
    w_6 = 2.0 * (z_0 * z_6 + z_1 * z_5 + z_2 * z_4) + z_3 * z_3
    p_6a = v_0 * w_6 + v_1 * w_5 + v_2 * w_4 + v_3 * w_3
    p_6b = v_4 * w_2 + v_5 * w_1 + v_6 * w_0
    p_6 = p_6a + p_6b
    u_7 = v_6 * 0.14285714285714285
    v_7 = (-kb * u_6 - mug * z_6) * 0.14285714285714285
    z_7 = (v_6 - q * p_6) * (0.14285714285714285 * iy)
    w_7 = 2.0 * (z_0 * z_7 + z_1 * z_6 + z_2 * z_5 + z_3 * z_4)
    p_7a = v_0 * w_7 + v_1 * w_6 + v_2 * w_5 + v_3 * w_4
    p_7b = v_4 * w_3 + v_5 * w_2 + v_6 * w_1 + v_7 * w_0
    p_7 = p_7a + p_7b
    u_8 = v_7 * 0.125
    v_8 = (-kb * u_7 - mug * z_7) * 0.125
    z_8 = (v_7 - q * p_7) * (0.125 * iy)
    w_8 = 2.0 * (z_0 * z_8 + z_1 * z_7 + z_2 * z_6 + z_3 * z_5) + z_4 * z_4
    p_8a = v_0 * w_8 + v_1 * w_7 + v_2 * w_6 + v_3 * w_5 + v_4 * w_4
    p_8b = v_5 * w_3 + v_6 * w_2 + v_7 * w_1 + v_8 * w_0
    p_8 = p_8a + p_8b
    u_9 = v_8 * 0.1111111111111111
    v_9 = (-kb * u_8 - mug * z_8) * 0.1111111111111111
    z_9 = (v_8 - q * p_8) * (0.1111111111111111 * iy)
    w_9 = 2.0 * (z_0 * z_9 + z_1 * z_8 + z_2 * z_7 + z_3 * z_6 + z_4 * z_5)
    p_9a = v_0 * w_9 + v_1 * w_8 + v_2 * w_7 + v_3 * w_6 + v_4 * w_5
    p_9b = v_5 * w_4 + v_6 * w_3 + v_7 * w_2 + v_8 * w_1 + v_9 * w_0
    p_9 = p_9a + p_9b
    u_10 = v_9 * 0.1
    v_10 = (-kb * u_9 - mug * z_9) * 0.1
    z_10 = (v_9 - q * p_9) * (0.1 * iy)
    C[0, 0] = u_0
    C[0, 1] = u_1
    C[0, 2] = u_2
    C[0, 3] = u_3
    C[0, 4] = u_4
    C[0, 5] = u_5
    C[0, 6] = u_6
    C[0, 7] = u_7
    C[0, 8] = u_8
    C[0, 9] = u_9
    C[0, 10] = u_10
    C[1, 0] = v_0
    C[1, 1] = v_1
    C[1, 2] = v_2
    C[1, 3] = v_3
    C[1, 4] = v_4
    C[1, 5] = v_5
    C[1, 6] = v_6
    C[1, 7] = v_7
    C[1, 8] = v_8
    C[1, 9] = v_9
    C[1, 10] = v_10
    C[2, 0] = z_0
    C[2, 1] = z_1
    C[2, 2] = z_2
    C[2, 3] = z_3
    C[2, 4] = z_4
    C[2, 5] = z_5
    C[2, 6] = z_6
    C[2, 7] = z_7
    C[2, 8] = z_8
    C[2, 9] = z_9
    C[2, 10] = z_10


@njit_inner()
def fp_step_length(C, hmax, P):
    """Longest step [s], at most ``hmax``, whose last series terms stay within the tolerances."""
    rtol = P[P_RTOL]
    atol = P[P_ATOL]
    # the largest ratio of a last term at hmax to its tolerance (scaled by the start values)
    hn = 1.0
    for _ in range(NT):
        hn *= hmax
    err = 0.0
    for r in range(3):
        e = abs(C[r, NT]) * hn / (atol + rtol * abs(C[r, 0]))
        if e > err:
            err = e
    if err <= 1.0:
        return hmax
    return hmax * 0.9 * err ** (-1.0 / NT)


@njit_inner()
def first_root(c, h):
    """First ``tau`` in (0, h] where the series ``c`` (a row of the coefficients) changes sign from
    its start (``h`` if it has not changed sign at any of 4 points up to ``h``). A 4-point scan
    brackets it (a step spans at most about a ninth of the isolator's pre-yield period, too short for
    a value to cross zero and back between two of them), then safeguarded Newton; the point returned
    is on the far side of the crossing (the sign has changed there) and within a few ``1e-15 h`` of it."""
    s0 = c[0]
    if s0 == 0.0:
        s0 = c[1]
    lo = 0.0
    hi = h
    found = False
    for j in range(1, 5):
        tau = h * j / 4.0
        if poly(c, tau) * s0 <= 0.0:
            hi = tau
            found = True
            break
        lo = tau
    if not found:
        return h
    x = 0.5 * (lo + hi)
    for _ in range(60):
        q = poly(c, x)
        if q * s0 > 0.0:
            lo = x
        else:
            hi = x
        dq = dpoly(c, x)
        xn = x - q / dq if dq != 0.0 else 0.5 * (lo + hi)
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 1e-15 * h or hi - lo <= 1e-15 * h:
            x = xn
            break
        x = xn
    # Newton converges to the root from one side and leaves the other end of the bracket where the
    # scan put it (up to a quarter of the step beyond the root): close the bracket around the root by
    # probes on both sides, widened only where round-off hides the sign at the root
    dx = 1e-15 * h
    for _ in range(60):
        if hi - lo <= 4.0 * dx:
            break
        if lo < x - dx and poly(c, x - dx) * s0 > 0.0:
            lo = x - dx
        if x + dx < hi and poly(c, x + dx) * s0 <= 0.0:
            hi = x + dx
        dx *= 2.0
    # the far side of the crossing: the sign has changed there
    return hi if poly(c, lo) * s0 > 0.0 else lo


@njit_inner()
def fp_direction(v0, a0):
    """Sign of the base motion over a step that starts with velocity ``v0`` [m/s] and acceleration
    ``a0`` [m/s^2]: that of ``v0``, or of ``a0`` when ``v0`` is zero or a round-off remainder of a
    reversal (it would change sign within 1e-9 s)."""
    if v0 == 0.0 or (v0 * a0 < 0.0 and abs(v0) < 1e-9 * abs(a0)):
        return 1.0 if a0 >= 0.0 else -1.0
    return 1.0 if v0 > 0.0 else -1.0


def _sum_lines(name: str, terms: list[str]) -> list[str]:
    """``name = sum of terms`` as lines of at most 5 terms (two partial sums beyond 5)."""
    if len(terms) <= 5:
        return [f"    {name} = {' + '.join(terms)}"]
    half = (len(terms) + 1) // 2
    return [
        f"    {name}a = {' + '.join(terms[:half])}",
        f"    {name}b = {' + '.join(terms[half:])}",
        f"    {name} = {name}a + {name}b",
    ]


def _unrolled_source(nt: int = NT) -> str:
    """Source of the body of :func:`fp_coefficients` for order ``nt`` (printed by ``python -m``)."""
    lines = [
        "    kb = P[P_KB]",
        "    mug = P[P_MU] * P[P_G]",
        "    iy = 1.0 / P[P_Y]",
        "    q = P[P_BWB] + P[P_BWG] if direction * z0 >= -Z_ZERO else P[P_BWB] - P[P_BWG]",
        "    u_0 = u0",
        "    v_0 = v0",
        "    z_0 = z0",
    ]
    for k in range(nt):
        m = (k + 1) // 2
        w = f"2.0 * ({' + '.join(f'z_{i} * z_{k - i}' for i in range(m))})" if m else ""
        if k % 2 == 0:
            w = (w + " + " if w else "") + f"z_{k // 2} * z_{k // 2}"
        inv = repr(1.0 / (k + 1))
        force = f"-kb * u_{k} - mug * z_{k}" + (" - a0" if k == 0 else " - c1" if k == 1 else "")
        lines += [
            f"    w_{k} = {w}",
            *_sum_lines(f"p_{k}", [f"v_{i} * w_{k - i}" for i in range(k + 1)]),
            f"    u_{k + 1} = v_{k} * {inv}",
            f"    v_{k + 1} = ({force}) * {inv}",
            f"    z_{k + 1} = (v_{k} - q * p_{k}) * ({inv} * iy)",
        ]
    for r, n in ((0, "u"), (1, "v"), (2, "z")):
        lines += [f"    C[{r}, {k}] = {n}_{k}" for k in range(nt + 1)]
    return "\n".join(lines)


if __name__ == "__main__":
    print(_unrolled_source())
