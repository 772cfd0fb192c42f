"""Closed forms of the block on the ground (docs/model.md §7, §14 B-D'): impact coefficients, free
rocking, rectangular, half-sine and full-sine pulses. Plain numpy/scipy, no isorock."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

G = 9.81
"""Gravity [m/s^2] (docs/model.md §1)."""

_EPS = float(np.finfo(float).eps)


# =================================================================================================
# geometry and impact (§1, §7)
# =================================================================================================
def block_geometry(lam: float, R: float) -> dict[str, float]:
    """Geometry of a block from its slenderness and size (§1).

    Parameters
    ----------
    lam : float
        Slenderness ``h/b`` [-].
    R : float
        Half-diagonal [m].

    Returns
    -------
    dict
        ``b, h`` [m], ``alpha`` [rad], ``p`` [rad/s]. Exact to round-off.
    """
    b = R / math.sqrt(1.0 + lam * lam)
    return {"b": b, "h": lam * b, "alpha": math.atan(1.0 / lam), "p": math.sqrt(3.0 * G / (4.0 * R))}


def housner_eps(alpha: float) -> float:
    """Housner's angular restitution ``1 - 1.5 sin^2 alpha`` [-] (§7). Exact to round-off."""
    return 1.0 - 1.5 * math.sin(alpha) ** 2


def impact_map_numeric(
    lam: float, R: float, rho: float, w_minus: float, v_minus: float
) -> tuple[float, float]:
    """Post-impact velocities from the impulse-momentum balances, solved as a 2x2 linear system.

    Solves Eq. 25, ``(4b^2+4h^2) th'+ + 3h u'+ = (4h^2-2b^2) th'- + 3h u'-``, together with Eq. 26,
    ``(m+m_b) u'+ + m h th'+ = (m+m_b) u'- + m h th'-`` (per unit ``m_b``: ``(rho+1)`` and ``rho``).
    This is independent of the closed forms for ``eps`` and ``beta1``.

    Parameters
    ----------
    lam, R, rho : float
        Slenderness [-], half-diagonal [m], mass ratio ``m/m_b`` [-].
    w_minus, v_minus : float
        Pre-impact ``theta'`` [rad/s] and ``u'`` [m/s].

    Returns
    -------
    w_plus, v_plus : float
        Post-impact ``theta'`` [rad/s] and ``u'`` [m/s] (rocking continues). Round-off accuracy.
    """
    g = block_geometry(lam, R)
    b, h = g["b"], g["h"]
    mat = np.array([[4 * b * b + 4 * h * h, 3 * h], [rho * h, rho + 1.0]])
    rhs = np.array(
        [(4 * h * h - 2 * b * b) * w_minus + 3 * h * v_minus, rho * h * w_minus + (rho + 1.0) * v_minus]
    )
    w_plus, v_plus = np.linalg.solve(mat, rhs)
    return float(w_plus), float(v_plus)


def impact_coefficients_closed(lam: float, R: float, rho: float) -> tuple[float, float, float]:
    """``eps``, ``beta1`` [m/rad], ``beta2`` [m/rad] of §7 (closed forms, round-off accuracy)."""
    h = block_geometry(lam, R)["h"]
    den = lam * lam * (rho + 4.0) + 4.0 * (rho + 1.0)
    return (lam * lam * (rho + 4.0) - 2.0 * (rho + 1.0)) / den, 6.0 * rho * h / den, rho * h / (rho + 1.0)


def impact_energy_loss(lam: float, R: float, rho: float, w_minus: float) -> float:
    """Kinetic energy change at an impact where rocking continues, per unit base mass [m^2/s^2] (§7).

    ``-2 rho b^2 theta'^2 (lam^2 (rho+4) + rho + 1) / (lam^2 (rho+4) + 4 (rho+1))`` (independent of
    ``u'-``). Divide by ``1 + rho`` for the change per unit total mass. Round-off accuracy.
    """
    b = block_geometry(lam, R)["b"]
    q = lam * lam * (rho + 4.0)
    return -2.0 * rho * b * b * w_minus * w_minus * (q + rho + 1.0) / (q + 4.0 * (rho + 1.0))


# =================================================================================================
# (B) free rocking from rest, non-isolated
# =================================================================================================
def free_impact_velocity0(alpha: float, p: float, theta0: float) -> float:
    """``|theta'|`` at the first impact after release from rest at ``theta0`` [rad/s] (exact).

    ``p sqrt(2 [cos(alpha - theta0) - cos(alpha)])``, written without cancellation. Round-off accuracy.
    """
    # cos(alpha - t0) - cos(alpha) = 2 sin(alpha - t0/2) sin(t0/2)
    return p * math.sqrt(4.0 * math.sin(alpha - 0.5 * theta0) * math.sin(0.5 * theta0))


def free_impact_velocity0_linear(alpha: float, p: float, theta0: float) -> float:
    """Linearised first impact velocity ``p sqrt(theta0 (2 alpha - theta0))`` [rad/s] (error O(alpha^2))."""
    return p * math.sqrt(theta0 * (2.0 * alpha - theta0))


def amplitude_after_impact(alpha: float, p: float, w_after: float) -> float:
    """Amplitude reached from ``theta = 0`` with speed ``|w_after|`` [rad] (exact, round-off accuracy).

    Solves ``cos(alpha - theta_a) = cos(alpha) + w^2 / (2 p^2)``; NaN if the block passes ``alpha``.
    """
    c = math.cos(alpha) + w_after * w_after / (2.0 * p * p)
    if c >= 1.0:
        return math.nan
    return alpha - math.acos(c)


def quarter_time_exact(alpha: float, p: float, theta_a: float) -> float:
    """Time from rest at amplitude ``theta_a`` to ``theta = 0`` [s], exact nonlinear.

    ``t_q = int_{chi0}^{alpha} dchi / (p sqrt(2 (cos chi0 - cos chi)))``, ``chi0 = alpha - theta_a``,
    with ``chi = chi0 + w^2``: the integrand ``2 / (p sqrt(2 (cos chi0 - cos chi) / w^2))`` is smooth.
    Accuracy: ~1e-13 relative (adaptive Gauss-Kronrod on a smooth integrand).
    """
    chi0 = alpha - theta_a

    def f(w: float) -> float:
        if w == 0.0:
            return 2.0 / (p * math.sqrt(2.0 * math.sin(chi0)))
        x = 0.5 * w * w
        # (cos chi0 - cos(chi0 + w^2)) / w^2 = 2 sin(chi0 + w^2/2) sin(w^2/2) / w^2
        ratio = math.sin(chi0 + x) * (math.sin(x) / x)
        return 2.0 / (p * math.sqrt(2.0 * ratio))

    val, _ = quad(f, 0.0, math.sqrt(theta_a), epsabs=0.0, epsrel=2e-14, limit=200)
    return val


def quarter_time_linear(alpha: float, p: float, theta_a: float) -> float:
    """Housner's linearised ``t_q = acosh(1 / (1 - theta_a/alpha)) / p`` [s] (relative error O(alpha^2))."""
    return math.acosh(1.0 / (1.0 - theta_a / alpha)) / p


def free_period_linear(alpha: float, p: float, theta0: float) -> float:
    """Linearised free period without impact loss ``4/p acosh(1/(1 - theta0/alpha))`` [s].

    Relative error O(alpha^2).
    """
    return 4.0 * quarter_time_linear(alpha, p, theta0)


def next_impact_delay_linear(alpha: float, p: float, v: float) -> float:
    """Linearised time to the next impact after leaving ``theta = 0`` with speed ``v`` [s].

    ``2/p atanh(v / (p alpha))``; requires ``v < p alpha``. Relative error O(alpha^2).
    """
    return 2.0 / p * math.atanh(abs(v) / (p * alpha))


def free_rocking_exact(alpha: float, p: float, theta0: float, eps: float, n: int) -> dict[str, np.ndarray]:
    """Exact nonlinear free rocking of the non-isolated block released from rest at ``theta0``.

    Parameters
    ----------
    alpha, p : float
        Slenderness angle [rad] and frequency parameter [rad/s].
    theta0 : float
        Initial rotation, ``0 < theta0 < alpha`` [rad].
    eps : float
        Angular restitution (Housner's ``1 - 1.5 sin^2 alpha`` on a rigid base) [-].
    n : int
        Number of impacts.

    Returns
    -------
    dict
        ``w_minus`` (n,): ``|theta'|`` before impact k [rad/s] (``eps^k |theta'_0|``);
        ``amp`` (n+1,): amplitude before impact k (``amp[0] = theta0``) [rad];
        ``t`` (n,): impact instants [s] (``t_0 = t_q(theta0)``, ``t_{k+1} = t_k + 2 t_q(amp[k+1])``).
        Accuracy ~1e-13 relative (quadrature).
    """
    w0 = free_impact_velocity0(alpha, p, theta0)
    w = w0 * eps ** np.arange(n)
    amp = np.empty(n + 1)
    amp[0] = theta0
    for k in range(n):
        amp[k + 1] = amplitude_after_impact(alpha, p, eps * w[k])
    t = np.empty(n)
    t[0] = quarter_time_exact(alpha, p, theta0)
    for k in range(1, n):
        t[k] = t[k - 1] + 2.0 * quarter_time_exact(alpha, p, amp[k])
    return {"w_minus": w, "amp": amp, "t": t}


def free_rocking_linear(alpha: float, p: float, theta0: float, eps: float, n: int) -> dict[str, np.ndarray]:
    """Housner's linearised free rocking: impact velocities and instants (error O(alpha^2)).

    ``|theta'_k| = eps^k p sqrt(theta0 (2 alpha - theta0))``; ``t_0 = acosh(1/(1-theta0/alpha))/p``,
    ``t_{k+1} = t_k + 2/p atanh(eps |theta'_k| / (p alpha))``.

    Returns
    -------
    dict
        ``w_minus`` (n,) [rad/s], ``t`` (n,) [s].
    """
    w = free_impact_velocity0_linear(alpha, p, theta0) * eps ** np.arange(n)
    t = np.empty(n)
    t[0] = quarter_time_linear(alpha, p, theta0)
    for k in range(1, n):
        t[k] = t[k - 1] + next_impact_delay_linear(alpha, p, eps * w[k - 1])
    return {"w_minus": w, "t": t}


# =================================================================================================
# (C) rectangular pulse, non-isolated
# =================================================================================================
def rect_min_overturn_linear(p: float, td: float) -> float:
    """Linearised minimum overturning amplitude of a rectangular pulse, ``A_min/(g alpha)`` [-].

    ``1 / (1 - exp(-p td))``. Error O(alpha^2): 0.3-0.4 % below the exact value at lambda = 10.
    """
    return 1.0 / (-math.expm1(-p * td))


def _rect_time_to(alpha: float, p: float, a: float, phi: float) -> float:
    """Time to rotate from 0 to ``phi = -theta`` under a constant ``x_g'' = a g`` [s] (exact).

    ``int_0^phi dphi / (p sqrt(2 W))`` with ``phi = xi^2``: the integrand
    ``2 / (p sqrt(2 W(xi^2) / xi^2))`` is smooth. Accuracy ~1e-13 relative.
    """

    def f(xi: float) -> float:
        x = 0.5 * xi * xi  # phi / 2
        sinc = math.sin(x) / x if x > 0 else 1.0
        # W / phi = (sin(phi/2)/(phi/2)) [a cos(alpha - phi/2) - sin(alpha - phi/2)]
        wr = sinc * (a * math.cos(alpha - x) - math.sin(alpha - x))
        return 2.0 / (p * math.sqrt(2.0 * wr))

    val, _ = quad(f, 0.0, math.sqrt(phi), epsabs=0.0, epsrel=2e-14, limit=200)
    return val


def rect_overturns_exact(alpha: float, p: float, td: float, a: float) -> bool:
    """Whether a rectangular pulse of amplitude ``a`` [g] and duration ``td`` [s] overturns the block.

    Exact nonlinear, first excursion (§14 C): with ``phi = -theta``, ``phi'^2/2 = p^2 W(phi)`` during the
    pulse, ``W = 2 sin(phi/2) [a cos(alpha - phi/2) - sin(alpha - phi/2)]``; the block overturns iff it
    reaches ``phi = alpha`` during the pulse or ``W(phi1) + cos(alpha - phi1) >= 1`` at its end.
    Exact up to the quadrature accuracy (~1e-14).
    """
    if not a > math.tan(alpha):
        return False
    if _rect_time_to(alpha, p, a, alpha) <= td:
        return True
    phi1 = brentq(lambda ph: _rect_time_to(alpha, p, a, ph) - td, 0.0, alpha, xtol=1e-16, rtol=4 * _EPS)
    w = 2.0 * math.sin(0.5 * phi1) * (a * math.cos(alpha - 0.5 * phi1) - math.sin(alpha - 0.5 * phi1))
    return w + math.cos(alpha - phi1) >= 1.0


def rect_min_overturn_exact(alpha: float, p: float, td: float) -> float:
    """Exact minimum overturning amplitude of a rectangular pulse, ``A_min/g`` [-] (not normalised).

    Bisection on :func:`rect_overturns_exact` (monotone in amplitude) down to adjacent floats.
    Accuracy ~1e-13 relative (limited by the quadratures).
    """
    lo = math.tan(alpha)
    hi = 2.0 * lo
    while not rect_overturns_exact(alpha, p, td, hi):
        lo, hi = hi, 2.0 * hi
    while hi - lo > 2.0 * _EPS * hi:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if rect_overturns_exact(alpha, p, td, mid):
            hi = mid
        else:
            lo = mid
    return hi


# =================================================================================================
# (D) half-sine pulse, linearised
# =================================================================================================
def halfsine_criterion_linear(ptd: float, ahat: float) -> float:
    """Left minus right side of the linearised half-sine overturning criterion (§14 D) [-].

    ``sqrt(ahat^2 - 1) + ahat exp[-p td (1 - asin(1/ahat)/pi)] - pi/(p td)``; the block overturns in
    the first excursion iff this is ``>= 0``. ``ahat = A_g0/(g alpha) > 1``, ``ptd = p t_d`` [-].
    Exact for the linearised model (error of the model O(alpha^2)).
    """
    if ahat <= 1.0:
        return -math.pi / ptd
    return (
        math.sqrt(ahat * ahat - 1.0)
        + ahat * math.exp(-ptd * (1.0 - math.asin(1.0 / ahat) / math.pi))
        - math.pi / ptd
    )


def halfsine_min_overturn_linear(ptd: float) -> float:
    """Minimal root of :func:`halfsine_criterion_linear`: ``A_min/(g alpha)`` of the half-sine [-].

    Geometric scan from 1 (factor 1.0005) then Brent to round-off. Accuracy ~1e-14 relative
    (for the linearised model; 0.3-0.4 % below the exact nonlinear minimum at lambda = 10).
    """
    lo = 1.0
    hi = 1.0005
    while halfsine_criterion_linear(ptd, hi) < 0.0:
        lo, hi = hi, hi * 1.0005
    return brentq(lambda x: halfsine_criterion_linear(ptd, x), lo, hi, xtol=1e-16, rtol=4 * _EPS)


def halfsine_impulse_limit(ptd: float) -> float:
    """Impulse limit ``pi / (2 p td)`` of the half-sine minimum ``A_min/(g alpha)`` for ``p td -> 0`` [-].

    Exact as a limit; the linearised minimum exceeds it by a relative O(p td).
    """
    return math.pi / (2.0 * ptd)


# =================================================================================================
# (D') full-sine pulse, linearised, piecewise closed form
# =================================================================================================
def fullsine_response_linear(
    alpha: float, p: float, td: float, a: float, eps: float, eta: float = 1e-4, max_impacts: int = 100000
) -> dict:
    """Linearised response of the non-isolated block to a full-sine pulse (§14 D'), piecewise closed form.

    On side ``s`` while the pulse acts, ``psi = theta - s alpha`` is
    ``K sin(w t) + c1 cosh p(t - t0) + c2 sinh p(t - t0)``, ``K = p^2 a/(p^2 + w^2)``, ``w = pi/td``.
    Uplift when ``a |sin w t| > alpha`` (``s = -sgn sin``); impacts (``theta = 0``) are located by Brent's
    method on this expression and mapped with ``eps``; the cease rule of §8 (``eta``) is applied,
    followed by the uplift test.  After ``2 td`` the free motion is decided exactly (§14 D').

    Parameters
    ----------
    alpha, p, td : float
        Slenderness [rad], frequency parameter [rad/s], half-cycle duration [s].
    a : float
        Amplitude ``A_g0 / g`` [-].
    eps : float
        Angular restitution [-].
    eta : float
        Cease parameter [-].
    max_impacts : int
        Safety limit on the number of impacts during the pulse.

    Returns
    -------
    dict
        ``overturn`` (bool), ``impacts`` (list of impact times during the pulse [s]),
        ``t_uplift`` [s] or None, ``max_theta`` (max ``|theta|`` during the pulse [rad]).
        Accuracy: impact instants to ~1e-13 s; the decision is exact for the linearised model unless an
        excursion shorter than ~1e-9 td is missed by the root bracketing.
    """
    w = math.pi / td
    t_end = 2.0 * td
    K = p * p * a / (p * p + w * w)
    out: dict = {"overturn": False, "impacts": [], "t_uplift": None, "max_theta": 0.0}

    def next_uplift(t0: float) -> tuple[float, int] | None:
        """First instant >= t0 in the pulse where a|sin wt| > alpha (strictly just after)."""
        if a <= alpha:
            return None
        c = math.asin(alpha / a) / w  # first-half crossing
        cands = [(c, -1), (td + c, 1)]  # a sin > alpha on (c, td - c), a sin < -alpha on (td + c, 2td - c)
        for tc, s in cands:
            if t0 <= tc:
                return tc, s
            if t0 < tc + (td - 2 * c):  # inside the window already
                return t0, s
        return None

    t, s = 0.0, 0
    psi0 = dpsi0 = 0.0
    in_contact = True
    n_imp = 0
    while True:
        if in_contact:
            nu = next_uplift(t)
            if nu is None:
                return out  # pulse ends in full contact: no overturning
            t, s = nu
            if out["t_uplift"] is None:
                out["t_uplift"] = t
            psi0, dpsi0 = -s * alpha, 0.0
            in_contact = False
        t0 = t
        c1 = psi0 - K * math.sin(w * t0)
        c2 = (dpsi0 - K * w * math.cos(w * t0)) / p

        th0 = psi0 + s * alpha  # 0 at every start (uplift or impact)

        def theta(tt: float, t0: float = t0, c1: float = c1, c2: float = c2, th0: float = th0) -> float:
            # psi(t) - psi(t0) written without cancellation for small t - t0
            tau = tt - t0
            return (
                th0
                + 2.0 * K * math.cos(0.5 * w * (tt + t0)) * math.sin(0.5 * w * tau)
                + 2.0 * c1 * math.sinh(0.5 * p * tau) ** 2
                + c2 * math.sinh(p * tau)
            )

        def psi(tt: float, s: int = s) -> float:
            return theta(tt) - s * alpha

        def dpsi(tt: float, t0: float = t0, c1: float = c1, c2: float = c2) -> float:
            tau = tt - t0
            return K * w * math.cos(w * tt) + p * (c1 * math.sinh(p * tau) + c2 * math.cosh(p * tau))

        def sth(tt: float, s: int = s) -> float:  # s theta
            return s * theta(tt)

        # bracket the first return to theta = 0: geometric grid near t0 (after an impact), then uniform
        h = min(td, 1.0 / p) / 400.0
        span = t_end - t0
        pieces = [t0 + h * np.arange(1, int(span / h) + 2)]
        if dpsi0 != 0.0:
            tau_min = 1e-3 * abs(dpsi0) / (p * p * (alpha + a))
            if tau_min < h:
                pieces.append(t0 + np.geomspace(tau_min, h, 40))
        grid = np.unique(np.concatenate(pieces))
        grid = grid[grid <= t_end]
        if grid.size == 0 or grid[-1] < t_end:
            grid = np.append(grid, t_end)
        vals = np.array([sth(x) for x in grid])
        neg = np.flatnonzero(vals <= 0.0)
        out["max_theta"] = max(out["max_theta"], float(np.max(np.abs(vals))))
        if neg.size == 0:
            # excursion still going at the end of the pulse: free motion decides
            psi_e, dpsi_e = psi(t_end), dpsi(t_end)
            out["overturn"] = _free_linear_overturns(alpha, p, eps, s, psi_e, dpsi_e)
            return out
        j = neg[0]
        tlo = t0 if j == 0 else grid[j - 1]
        ti = brentq(sth, tlo, grid[j], xtol=1e-15, rtol=4 * _EPS) if vals[j] < 0.0 else grid[j]
        wi = dpsi(ti)  # theta' before impact
        if ti >= t_end:  # lands at the end of the pulse: the free motion after this impact decides
            out["impacts"].append(ti)
            out["overturn"] = eps * abs(wi) > p * alpha
            return out
        n_imp += 1
        out["impacts"].append(ti)
        if n_imp > max_impacts:
            raise RuntimeError("fullsine_response_linear: too many impacts")
        wp = eps * wi
        t = ti
        if abs(wp) < eta * p * alpha:
            in_contact = True  # ceases; re-check uplift at once (next_uplift includes t)
            continue
        s = -s
        psi0, dpsi0 = -s * alpha, wp


def _free_linear_overturns(alpha: float, p: float, eps: float, s: int, psi: float, dpsi: float) -> bool:
    """Linearised free rocking (no input) from ``psi = theta - s alpha``, ``psi'``: does it overturn?

    ``psi = A e^{p tau} + B e^{-p tau}``. If ``theta = 0`` is reached first, the impact speed
    ``sqrt(theta'^2 - p^2 psi^2 + p^2 alpha^2)`` times ``eps`` decides (overturns iff ``> p alpha``);
    otherwise the block overturns iff ``s A > 0``. Exact for the linearised model.
    """
    A = 0.5 * (psi + dpsi / p)
    B = 0.5 * (psi - dpsi / p)
    # theta = 0  <=>  A x + B / x = -s alpha,  x = e^{p tau} >= 1
    roots = np.roots([A, s * alpha, B]) if A != 0.0 else np.array([-B / (s * alpha)])
    hits = [r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 * max(1.0, abs(r)) and r.real > 1.0]
    if hits:
        wi2 = dpsi * dpsi - p * p * psi * psi + p * p * alpha * alpha
        return eps * math.sqrt(max(wi2, 0.0)) > p * alpha
    return s * A > 0.0


def fullsine_min_overturn_linear(
    alpha: float, p: float, td: float, eps: float, rel: float = 1e-9, kmax: int = 5000
) -> float:
    """Minimum overturning amplitude of the full-sine pulse, linearised, by the protocol of §13.

    Scan ``a_k = alpha 1.005^k`` (the linearised uplift amplitude is ``alpha``) up to the first
    overturning amplitude, then bisect between it and the previous grid point to relative width ``rel``.

    Returns
    -------
    float
        ``A_min/(g alpha)`` [-]. Agrees with the exact nonlinear model to about 0.1 % (lambda = 20) to
        1.4 % (lambda = 10) for ``omega_p/p <~ 12`` (docs/model.md §14 D').
    """

    def ot(a: float) -> bool:
        return fullsine_response_linear(alpha, p, td, a, eps)["overturn"]

    prev = alpha
    for k in range(1, kmax):
        a = alpha * 1.005**k
        if ot(a):
            lo, hi = prev, a
            while hi - lo > rel * hi:
                mid = 0.5 * (lo + hi)
                if ot(mid):
                    hi = mid
                else:
                    lo = mid
            return hi / alpha
        prev = a
    raise RuntimeError("fullsine_min_overturn_linear: no overturning amplitude found")
