"""The Mavroeidis-Papageorgiou (2003) velocity pulse: the model, its analytic derivative and integral,
and the least-squares fit to a record (see :mod:`isorock.pulse` for the fitting rules)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import least_squares

from isorock.errors import IsorockError

__all__ = ["MPParameters", "MPFit", "mp_velocity", "mp_acceleration", "mp_displacement", "fit_mp"]


@dataclass(frozen=True)
class MPParameters:
    """Parameters of the Mavroeidis-Papageorgiou (2003) velocity pulse.

    Parameters
    ----------
    A : float
        Amplitude of the velocity envelope [m/s] (``A >= 0``; the sign is in ``nu``).
    fp : float
        Prevailing frequency [Hz]; the pulse period is ``1 / fp``.
    nu : float
        Phase angle [rad], in [0, 2 pi).
    gamma : float
        Oscillatory character (number of half-cycles, roughly) [-], > 1.
    t0 : float
        Time of the envelope peak [s] from the first sample of the record.
    """

    A: float
    fp: float
    nu: float
    gamma: float
    t0: float

    @property
    def Tp(self) -> float:
        """Pulse period ``1 / fp`` [s]."""
        return 1.0 / self.fp

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """Pulse velocity [m/s] at times ``t`` [s]."""
        return mp_velocity(t, self.A, self.fp, self.nu, self.gamma, self.t0)

    def acceleration(self, t: np.ndarray) -> np.ndarray:
        """Pulse acceleration [m/s^2] at times ``t`` [s] (analytic derivative of :meth:`velocity`)."""
        return mp_acceleration(t, self.A, self.fp, self.nu, self.gamma, self.t0)

    def displacement(self, t: np.ndarray) -> np.ndarray:
        """Pulse displacement [m] at times ``t`` [s] (analytic integral of :meth:`velocity`, zero
        before the pulse)."""
        return mp_displacement(t, self.A, self.fp, self.nu, self.gamma, self.t0)


@dataclass(frozen=True)
class MPFit:
    """Result of :func:`fit_mp`.

    Parameters
    ----------
    params : MPParameters
        Best-fitting MP parameters.
    v_rms_ratio : float
        RMS of (record - model) velocity over the RMS of the record velocity, in the fit
        window [-] (0: perfect fit).
    d_rms_ratio : float
        The same for the displacement, each taken about its mean over the window [-].
    t_start, t_end : float
        Fit window [s].
    """

    params: MPParameters
    v_rms_ratio: float
    d_rms_ratio: float
    t_start: float
    t_end: float


def mp_velocity(t: np.ndarray, A: float, fp: float, nu: float, gamma: float, t0: float) -> np.ndarray:
    """Mavroeidis-Papageorgiou (2003) velocity pulse [m/s].

    Parameters
    ----------
    t : numpy.ndarray
        Times [s].
    A : float
        Envelope amplitude [m/s].
    fp : float
        Prevailing frequency [Hz].
    nu : float
        Phase [rad].
    gamma : float
        Oscillatory character [-].
    t0 : float
        Time of the envelope peak [s].
    """
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi * fp
    inside = np.abs(tau) <= gamma / (2.0 * fp)
    v = 0.5 * A * (1.0 + np.cos(w * tau / gamma)) * np.cos(w * tau + nu)
    return np.where(inside, v, 0.0)


def mp_acceleration(t: np.ndarray, A: float, fp: float, nu: float, gamma: float, t0: float) -> np.ndarray:
    """Time derivative of :func:`mp_velocity` [m/s^2] (same parameters)."""
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi * fp
    inside = np.abs(tau) <= gamma / (2.0 * fp)
    a = (
        -0.5
        * A
        * (
            (w / gamma) * np.sin(w * tau / gamma) * np.cos(w * tau + nu)
            + (1.0 + np.cos(w * tau / gamma)) * w * np.sin(w * tau + nu)
        )
    )
    return np.where(inside, a, 0.0)


def mp_displacement(t: np.ndarray, A: float, fp: float, nu: float, gamma: float, t0: float) -> np.ndarray:
    """Displacement of the MP pulse [m]: the integral of :func:`mp_velocity` from the start of the pulse.

    With ``w = 2 pi fp``, ``w1 = w (1 + 1/gamma)``, ``w2 = w (1 - 1/gamma)`` and the pulse
    start ``ts = -gamma / (2 fp)`` (times ``tau = t - t0``), the velocity is
    ``A/2 cos(w tau + nu) + A/4 [cos(w1 tau + nu) + cos(w2 tau + nu)]``, so the displacement is
    ``A/(2w) [sin(w tau + nu)]_ts^tau + A/(4 w1) [sin(w1 tau + nu)]_ts^tau
    + A/(4 w2) [sin(w2 tau + nu)]_ts^tau`` (the last term is ``A/4 cos(nu) (tau - ts)`` for
    ``gamma = 1``); zero before the pulse, constant (the residual displacement) after it.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s].
    A, fp, nu, gamma, t0 : float
        MP parameters, as in :func:`mp_velocity`.
    """
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi * fp
    ts = -gamma / (2.0 * fp)
    tt = np.clip(tau, ts, -ts)

    def term(om: float) -> np.ndarray:
        if abs(om * ts) < 1e-7:  # gamma = 1 (w2 = 0): the limit, to O((om ts)^2)
            return math.cos(nu) * (tt - ts)
        return (np.sin(om * tt + nu) - math.sin(om * ts + nu)) / om

    w2 = w * (1.0 - 1.0 / gamma)
    return 0.5 * A * term(w) + 0.25 * A * term(w * (1.0 + 1.0 / gamma)) + 0.25 * A * term(w2)


def fit_mp(
    t: np.ndarray,
    v: np.ndarray,
    tp0: float,
    t_center: float,
    amp0: float | None = None,
    gamma_bounds: tuple[float, float] = (1.0, 3.0),
    n_polish: int = 2,
    *,
    displacement: bool = True,
) -> MPFit:
    """Least-squares fit of the MP pulse to the velocity (and displacement) of a record.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s], uniformly spaced.
    v : numpy.ndarray
        Velocity [m/s].
    tp0 : float
        Starting pulse period [s] (the wavelet estimate); ``fp`` is bounded to
        ``[1/(2 tp0), 2/tp0]``.
    t_center : float
        Centre of the fit window [s] (the energy centroid of the wavelet pulse).
    amp0 : float, optional
        Starting amplitude [m/s] (default: the largest ``|v|`` in the window).
    gamma_bounds : tuple of float
        Bounds of ``gamma`` [-]; the window is ``t_center +- gamma_bounds[1] * tp0 / 2``
        (clipped to the record).
    n_polish : int
        Number of starts refined by least squares per trial frequency [-]: of the 672 grid
        starts (8 phases, 4 ``gamma``, 7 frequencies, 3 times), the ``n_polish`` best of each
        of the 7 frequencies (so that every period range gets its own local optimum).
    displacement : bool
        Fit the displacement too (record and model displacement taken about their means over
        the window, velocity and displacement residuals each divided by the record's largest
        absolute value in the window, equal weights); velocity only when false.

    Returns
    -------
    MPFit
        Best parameters, fit quality and window.
    """
    t = np.asarray(t, dtype=float)
    v = np.asarray(v, dtype=float)
    if t.size < 4 or v.shape != t.shape:
        raise IsorockError("fit_mp needs matching time and velocity arrays of 4 samples or more")
    dt = float(t[1] - t[0])
    fp0 = 1.0 / tp0
    glo, ghi = gamma_bounds
    half = 0.5 * ghi * tp0
    ta, tb = max(t[0], t_center - half), min(t[-1], t_center + half)
    sel = (t >= ta) & (t <= tb)
    if np.count_nonzero(sel) < 4:
        sel = np.ones(t.size, dtype=bool)
        ta, tb = float(t[0]), float(t[-1])
    d = cumulative_trapezoid(v, dx=dt, initial=0.0)
    # fit on a grid of >= 40 samples per shortest admissible period (the pulse is smooth)
    step = max(1, int(0.5 * tp0 / 40.0 / dt))
    ts, vs = t[sel][::step], v[sel][::step]
    ds = d[sel][::step]
    ds = ds - ds.mean()
    vn = float(np.max(np.abs(vs))) or 1.0
    dn = float(np.max(np.abs(ds))) or 1.0
    norm = 1.0 / math.sqrt(ts.size)
    lb = np.array([0.0, 0.5 * fp0, -2.0 * math.pi, glo, ta])
    ub = np.array([3.0 * vn, 2.0 * fp0, 4.0 * math.pi, ghi, tb])

    def resid(p: np.ndarray) -> np.ndarray:
        rv = (mp_velocity(ts, *p) - vs) / vn
        if not displacement:
            return rv * norm
        dm = mp_displacement(ts, *p)
        rd = (dm - dm.mean() - ds) / dn
        return np.concatenate([rv, rd]) * norm

    # many cheap starts (phase, oscillation, frequency, time), the best few polished by least squares
    a0 = vn if amp0 is None else float(amp0)
    gammas = glo + (ghi - glo) * np.array([0.125, 0.375, 0.625, 0.875])
    fmuls = (0.6, 0.75, 0.87, 1.0, 1.15, 1.3, 1.5)
    starts: dict[float, list[tuple[float, np.ndarray]]] = {f: [] for f in fmuls}
    for nu in np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False):
        for gamma in gammas:
            for fmul in fmuls:
                for dt0 in (-0.25, 0.0, 0.25):
                    p0 = np.clip([a0, fp0 * fmul, nu, gamma, t_center + dt0 * tp0], lb, ub)
                    starts[fmul].append((float(np.sum(resid(p0) ** 2)), p0))
    chosen = [p0 for f in fmuls for _c, p0 in sorted(starts[f], key=lambda s: s[0])[:n_polish]]
    best = None
    for p0 in chosen:
        sol = least_squares(resid, p0, bounds=(lb, ub), x_scale=[vn, fp0, 1.0, 1.0, tp0], max_nfev=300)
        if best is None or sol.cost < best.cost:
            best = sol
    assert best is not None
    A, fp, nu, gamma, t0 = (float(x) for x in best.x)
    mp = MPParameters(A=A, fp=fp, nu=float(nu % (2.0 * math.pi)), gamma=gamma, t0=t0)
    tw, vw, dw = t[sel], v[sel], d[sel] - d[sel].mean()
    mv = mp.velocity(tw)
    md = mp.displacement(tw)
    md = md - md.mean()

    def ratio(x: np.ndarray, y: np.ndarray) -> float:
        den = float(np.sqrt(np.mean(y**2)))
        return float(np.sqrt(np.mean((x - y) ** 2))) / den if den > 0 else math.nan

    return MPFit(params=mp, v_rms_ratio=ratio(mv, vw), d_rms_ratio=ratio(md, dw), t_start=ta, t_end=tb)
