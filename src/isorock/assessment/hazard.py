"""The site's hazard and the risk integral: from a fragility to the mean annual frequency of failure.

A hazard curve gives, for levels ``x_i`` of the stripes' intensity measure (PGA in g by default), the
mean annual frequency ``H(x_i)`` with which ``x_i`` is exceeded at the site (from a national hazard
model, or a site-specific study; :mod:`isorock.assessment.hazard_files` reads OpenQuake's and the USGS
hazard service's files). Between its points it is interpolated log-log (a power law on each
interval: ``H(x) = H_i (x / x_i)^(-k_i)``, the usual form of hazard curves).

The mean annual frequency of a damage state is the PBEE risk integral (Cornell & Krawinkler 2000;
Baker 2015 §6)

    lambda_D = integral of P(D | x) |dH(x)| ,

computed on each power-law interval by Gauss-Legendre quadrature in ``ln x`` (exact to the
quadrature's order for the smooth integrand). The curve's points bound the integral, and nothing is
extrapolated silently beyond them:

* above the last point ``x_n`` the exceedances ``H(x_n)`` are counted with ``P(D | x_n)``: the
  *truncated* value, a lower bound (the fragility increases); the upper bound counts them with
  ``P = 1`` (:attr:`RiskIntegral.upper`, the truncated value plus
  :attr:`RiskIntegral.above_last_max` ``= H(x_n) (1 - P(D | x_n))``). Both are reported, and said to
  differ when the bound exceeds the truncated value by more than :data:`TAIL_TOLERANCE` (a strong
  object whose median lies beyond the curve's last point: theta 1.5 g, beta 0.4 on a power-law curve of
  slope 2.5 ending at 1 g loses half of the closed form to the truncation);
* below the first point the fragility is taken as negligible, and ``P(D | x_1)`` is reported
  (:attr:`RiskIntegral.p_at_first`) so that the user sees whether the curve starts low enough (said
  when it exceeds :data:`FIRST_POINT_TOLERANCE`).

A level may also be read off the curve: the PGA whose return period is ``T`` years
(:meth:`HazardCurve.level_at_return_period`, the same log-log interpolation, inside the curve only).

The probability of at least one occurrence in ``t`` years (Poisson) is ``1 - exp(-lambda_D t)``.

Closed form (tests): a lognormal fragility ``(theta, beta)`` and a power-law hazard ``H = k0 x^-k``
over all ``x > 0`` give ``lambda_D = k0 theta^-k exp(k^2 beta^2 / 2)``.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from isorock.errors import ConfigError

__all__ = [
    "TAIL_TOLERANCE",
    "FIRST_POINT_TOLERANCE",
    "HazardCurve",
    "RiskIntegral",
    "quadrature",
    "risk_integral",
    "lognormal_powerlaw_rate",
    "probability_in",
]

_GL_X, _GL_W = np.polynomial.legendre.leggauss(24)
#: the two tails of the risk integral differ when the upper bound exceeds the truncated value by this
TAIL_TOLERANCE = 0.10
#: ``P(D | x_1)`` above this at the curve's first level: the levels below it may matter
FIRST_POINT_TOLERANCE = 0.01


@dataclass(frozen=True)
class HazardCurve:
    """A hazard curve: levels of the intensity measure and their annual frequencies of exceedance.

    Parameters
    ----------
    levels : numpy.ndarray
        Increasing levels (> 0), in the stripes' unit (g for PGA).
    annual_rate : numpy.ndarray
        Mean annual frequency of exceeding each level [1/yr], decreasing, > 0.
    source : str
        Where it comes from: ``inline`` or the file read.
    imt : str
        The intensity measure of the levels, OpenQuake's canonical string (``PGA``, ``PGV``, ``SA(1.0)``:
        :func:`isorock.processing.imt.parse_imt`); PGA and SA in g, PGV in cm/s.
    component_definition : str
        Which horizontal value the levels are (``RotD50``, ``RotD100``, ``analysed``): RotD50 for the
        current ground-motion models and the USGS maps.
    kind : str
        The statistic of the curve in its model: OpenQuake's ``mean``, ``quantile-0.84``, ``rlz-000``;
        the USGS service's component ``Total``; empty when the file does not say.
    site : str
        The site in words (``site 3 (lon 10.05, lat 45.2)``; ``lon -122.3, lat 47.6``); empty for a
        curve given without one.
    vs30_m_s : float or None
        The site's Vs30 the curve was computed for [m/s], where the file gives it (USGS).
    notes : tuple of str
        What the reader changed (levels dropped at the ends of the curve, and why).
    origin : str
        The reader: ``openquake``, ``usgs``, ``csv`` or ``inline`` (empty: built directly; as inline).
    component_stated : bool
        Whether ``component_definition`` was given (``assessment.hazard.component_definition``); False:
        RotD50 is assumed (neither OpenQuake's nor the USGS service's files state it), and the output
        says so.
    """

    levels: np.ndarray
    annual_rate: np.ndarray
    source: str = "inline"
    imt: str = "PGA"
    component_definition: str = "RotD50"
    kind: str = ""
    site: str = ""
    vs30_m_s: float | None = None
    notes: tuple[str, ...] = ()
    origin: str = ""
    component_stated: bool = False

    def __post_init__(self) -> None:
        x = np.asarray(self.levels, dtype=float)
        h = np.asarray(self.annual_rate, dtype=float)
        where = f"assessment.hazard ({self.source})"
        if x.ndim != 1 or x.size < 3 or h.shape != x.shape:
            raise ConfigError(f"{where}: at least 3 pairs of level and annual rate are needed")
        if not (np.all(np.isfinite(x)) and np.all(x > 0) and np.all(np.diff(x) > 0)):
            raise ConfigError(f"{where}: the levels must be positive and increase")
        if not (np.all(np.isfinite(h)) and np.all(h > 0) and np.all(np.diff(h) < 0)):
            raise ConfigError(f"{where}: the annual rates must be positive and decrease as the level rises")
        object.__setattr__(self, "levels", x)
        object.__setattr__(self, "annual_rate", h)

    @classmethod
    def from_csv(cls, path: str | Path) -> HazardCurve:
        """Read a CSV file with the header ``level,annual_rate``."""
        p = Path(path)
        try:
            text = p.read_text()
        except OSError as exc:
            raise ConfigError(f"{p}: cannot read the hazard curve: {exc.strerror or exc}") from None
        rows = list(csv.reader(text.splitlines()))
        if not rows or [c.strip() for c in rows[0]] != ["level", "annual_rate"]:
            raise ConfigError(f"{p}:1: the header must be 'level,annual_rate'")
        x, h = [], []
        for i, row in enumerate(rows[1:], start=2):
            if not row or not "".join(row).strip():
                continue
            try:
                a, b = (float(v) for v in row)
            except ValueError:
                raise ConfigError(
                    f"{p}:{i}: expected two numbers 'level,annual_rate', got {','.join(row)!r}"
                ) from None
            x.append(a)
            h.append(b)
        return cls(np.array(x), np.array(h), str(p), origin="csv")

    def rate(self, x: float | np.ndarray) -> np.ndarray:
        """``H(x)`` [1/yr], log-log interpolated; NaN outside the curve's range (not extrapolated)."""
        lx = np.log(np.asarray(x, dtype=float))
        out = np.exp(np.interp(lx, np.log(self.levels), np.log(self.annual_rate)))
        return np.where((lx < math.log(self.levels[0])) | (lx > math.log(self.levels[-1])), np.nan, out)

    def level_at_return_period(self, years: float, what: str = "return period") -> float:
        """The level [g] whose annual frequency of exceedance is ``1 / years``, log-log interpolated.

        Raises
        ------
        ConfigError
            A return period outside the curve's range (``what`` names the key): not extrapolated.
        """
        rate = 1.0 / float(years)
        h, x = self.annual_rate, self.levels
        if not h[-1] <= rate <= h[0]:
            raise ConfigError(
                f"assessment.{what}: {years:g} years (annual rate {rate:.3g}) is outside the hazard curve "
                f"({1.0 / h[0]:.4g} to {1.0 / h[-1]:.4g} years, {x[0]:g} to {x[-1]:g} g): a level is not "
                "extrapolated; extend the curve or give the level in g"
            )
        return float(np.exp(np.interp(math.log(rate), np.log(h[::-1]), np.log(x[::-1]))))

    def describe(self) -> str:
        """One phrase naming the curve, for a verdict to quote: "OpenQuake's mean curve at site 3 (lon
        10.05, lat 45.2), file hazard_curve-mean_SA(0.2).csv", "the USGS hazard service's Total curve at
        lon -122.294, lat 37.86, Vs30 537 m/s, file dwight_7th.json", "file my-site.csv", "the curve
        given inline"."""
        name = Path(self.source).name
        if self.origin == "openquake":
            kind = f"{self.kind} " if self.kind else ""
            at = f" at {self.site}" if self.site else ""
            return f"OpenQuake's {kind}curve{at}, file {name}"
        if self.origin == "usgs":
            kind = f"{self.kind} " if self.kind else ""
            parts = [self.site] if self.site else []
            if self.vs30_m_s is not None:
                parts.append(f"Vs30 {self.vs30_m_s:g} m/s")
            at = f" at {', '.join(parts)}" if parts else ""
            return f"the USGS hazard service's {kind}curve{at}, file {name}"
        if self.origin == "csv" or (self.origin == "" and self.source != "inline"):
            return f"file {name}"
        return "the curve given inline"

    def to_dict(self) -> dict:
        return {
            "levels": self.levels.tolist(),
            "annual_rate": self.annual_rate.tolist(),
            "source": self.source,
            "imt": self.imt,
            "component_definition": self.component_definition,
            "kind": self.kind,
            "site": self.site,
            "vs30_m_s": self.vs30_m_s,
            "notes": list(self.notes),
            "origin": self.origin,
            "component_stated": self.component_stated,
        }


@dataclass(frozen=True)
class RiskIntegral:
    """The mean annual frequency of a damage state and what bounds it.

    Attributes
    ----------
    annual_rate : float
        ``lambda_D`` over the curve's range plus the exceedances of its last level at ``P(D | x_n)``
        [1/yr].
    above_last_max : float
        The most the levels above the curve's last point could add [1/yr].
    p_at_first : float
        ``P(D | x_1)`` at the curve's first level [-]: the integral leaves out the levels below it.
    """

    annual_rate: float
    above_last_max: float
    p_at_first: float

    @property
    def upper(self) -> float:
        """The upper bound [1/yr]: the exceedances above the curve's last point counted with ``P = 1``."""
        return self.annual_rate + self.above_last_max

    @property
    def tails_differ(self) -> bool:
        """The upper bound exceeds the truncated value by more than :data:`TAIL_TOLERANCE`."""
        return self.upper > (1.0 + TAIL_TOLERANCE) * self.annual_rate


def quadrature(hazard: HazardCurve) -> tuple[np.ndarray, np.ndarray]:
    """Nodes ``x_i`` and weights ``w_i`` [1/yr] with ``lambda_D = sum w_i P(D | x_i)`` (see the module
    docstring): Gauss-Legendre in ``ln x`` on each interval of the curve, and its last point with the
    weight ``H(x_n)`` (the exceedances above it, counted at ``P(D | x_n)``)."""
    x, h = hazard.levels, hazard.annual_rate
    nodes, weights = [], []
    for i in range(x.size - 1):
        l0, l1 = math.log(x[i]), math.log(x[i + 1])
        k = -(math.log(h[i + 1]) - math.log(h[i])) / (l1 - l0)  # H = h_i exp(-k (ln x - l0))
        lx = 0.5 * (l1 - l0) * _GL_X + 0.5 * (l1 + l0)
        nodes.append(np.exp(lx))
        weights.append(0.5 * (l1 - l0) * _GL_W * k * h[i] * np.exp(-k * (lx - l0)))  # -dH/dlnx
    nodes.append(np.array([x[-1]]))
    weights.append(np.array([h[-1]]))
    return np.concatenate(nodes), np.concatenate(weights)


def risk_integral(fragility: Callable[[np.ndarray], np.ndarray], hazard: HazardCurve) -> RiskIntegral:
    """``lambda_D = integral P(D | x) |dH(x)|`` over the hazard curve (see the module docstring).

    Parameters
    ----------
    fragility : callable
        ``P(D | x)`` [-] for an array of levels (same unit as the curve).
    hazard : HazardCurve

    Returns
    -------
    RiskIntegral
    """
    xq, wq = quadrature(hazard)
    p = np.asarray(fragility(xq), dtype=float)
    p_last, p_first = float(p[-1]), float(np.asarray(fragility(hazard.levels[:1]), dtype=float)[0])
    return RiskIntegral(float(np.sum(wq * p)), float(hazard.annual_rate[-1] * (1.0 - p_last)), p_first)


def lognormal_powerlaw_rate(theta: float, beta: float, k0: float, k: float) -> float:
    """Closed form of the risk integral for a lognormal fragility ``(theta, beta)`` and the hazard
    ``H(x) = k0 x^-k`` over all ``x > 0`` [1/yr]."""
    return k0 * theta ** (-k) * math.exp(0.5 * (k * beta) ** 2)


def probability_in(annual_rate: float, years: float = 50.0) -> float:
    """Probability of at least one occurrence in ``years`` of a Poisson process of ``annual_rate`` [-]."""
    return -math.expm1(-annual_rate * years)
