"""Parameters of the block and of its isolation system.

All physical quantities are in SI units (m, s, rad) unless stated. The absolute
masses never enter the model: the block-to-base mass ratio ``rho = m / m_b`` is
the only inertia parameter (see ``docs/model.md`` §1). A parameter out of its range raises
:class:`~isorock.errors.ParameterError` (a ``ValueError``) naming it and its valid range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

from isorock.constants import ISOLATION_KINDS, G
from isorock.errors import ParameterError
from isorock.physics.body import RigidBody, _check

__all__ = [
    "G",
    "Block",
    "Body",
    "RigidBody",
    "NoIsolation",
    "LinearIsolation",
    "FPIsolation",
    "Isolation",
    "System",
    "housner_restitution",
    "impact_coefficients",
    "make_isolation",
    "isolation_params",
]


def housner_restitution(alpha: float) -> float:
    """Housner's angular coefficient of restitution of a block on a rigid base.

    Parameters
    ----------
    alpha : float
        Slenderness angle ``atan(b/h)`` [rad].

    Returns
    -------
    float
        ``1 - 1.5 sin^2(alpha)`` [-].
    """
    return 1.0 - 1.5 * math.sin(alpha) ** 2


def impact_coefficients(lam: float, h: float, rho: float) -> tuple[float, float, float]:
    """Impact map coefficients of the isolated block (docs/model.md §7, paper Eqs. 29, 30).

    Parameters
    ----------
    lam : float
        Slenderness ``h/b`` [-].
    h : float
        Half-height of the block [m].
    rho : float
        Block-to-base mass ratio ``m/m_b`` [-].

    Returns
    -------
    eps : float
        Angular restitution ``theta'+ / theta'-`` [-].
    beta1 : float
        Base-velocity jump per unit pre-impact angular velocity when rocking continues [m/rad].
    beta2 : float
        Same when rocking ceases, ``rho h / (rho + 1)`` [m/rad].
    """
    den = lam * lam * (rho + 4.0) + 4.0 * (rho + 1.0)
    eps = (lam * lam * (rho + 4.0) - 2.0 * (rho + 1.0)) / den
    beta1 = 6.0 * rho * h / den
    beta2 = rho * h / (rho + 1.0)
    return eps, beta1, beta2


@dataclass(frozen=True)
class Block:
    """Rectangular rigid block.

    Parameters
    ----------
    b : float
        Half-width [m] (block width ``B = 2b``).
    h : float
        Half-height [m] (block height ``H = 2h``).
    """

    b: float
    h: float

    def __post_init__(self) -> None:
        _check("b", self.b, self.b > 0, "b > 0 m (half-width)")
        _check("h", self.h, self.h > 0, "h > 0 m (half-height)")

    @classmethod
    def from_lambda_R(cls, lam: float, R: float) -> Block:
        """Block from slenderness ``lam = h/b`` [-] and half-diagonal ``R`` [m]."""
        _check("lambda", lam, lam > 0, "lambda = h/b > 0")
        _check("R", R, R > 0, "R > 0 m (half-diagonal)")
        b = R / math.sqrt(1.0 + lam * lam)
        return cls(b=b, h=lam * b)

    @property
    def R(self) -> float:
        """Half-diagonal ``sqrt(b^2 + h^2)`` [m]."""
        return math.hypot(self.b, self.h)

    @property
    def lam(self) -> float:
        """Slenderness ``h/b`` [-]."""
        return self.h / self.b

    @property
    def alpha(self) -> float:
        """Slenderness angle ``atan(b/h)`` [rad]."""
        return math.atan2(self.b, self.h)

    @property
    def tan_alpha(self) -> float:
        """``b/h`` [-]: uplift acceleration of the non-isolated block in units of g."""
        return self.b / self.h

    @property
    def p(self) -> float:
        """Frequency parameter ``sqrt(3 g / (4 R))`` [rad/s]."""
        return math.sqrt(3.0 * G / (4.0 * self.R))

    @property
    def eps_housner(self) -> float:
        """Housner's coefficient of restitution on a rigid base [-]."""
        return housner_restitution(self.alpha)


@dataclass(frozen=True)
class NoIsolation:
    """Block standing directly on the ground (no isolation)."""

    kind: Literal["none"] = field(default="none", init=False)
    rho: float = field(default=0.0, init=False)


@dataclass(frozen=True)
class LinearIsolation:
    """Linear visco-elastic isolator (paper §2.2.1).

    Parameters
    ----------
    Tb : float
        Isolation period ``2 pi sqrt((m + m_b)/k_b)`` [s].
    xi_b : float
        Isolation damping ratio [-], ``0 <= xi_b < 1``.
    rho : float
        Block-to-base mass ratio ``m/m_b`` [-].
    """

    Tb: float
    xi_b: float
    rho: float
    kind: Literal["linear"] = field(default="linear", init=False)

    def __post_init__(self) -> None:
        _check("Tb", self.Tb, self.Tb > 0, "Tb > 0 s")
        _check("xi_b", self.xi_b, 0.0 <= self.xi_b < 1.0, "0 <= xi_b < 1 (under-damped isolator)")
        _check("rho", self.rho, self.rho > 0, "rho = m/m_b > 0")

    @property
    def omega_b(self) -> float:
        """Isolation circular frequency ``2 pi / Tb`` [rad/s]."""
        return 2.0 * math.pi / self.Tb

    @property
    def kb(self) -> float:
        """Isolator stiffness per unit total mass ``k_b/(m+m_b) = omega_b^2`` [1/s^2]."""
        return self.omega_b**2

    @property
    def cb(self) -> float:
        """Isolator damping per unit total mass ``c_b/(m+m_b) = 2 xi_b omega_b`` [1/s]."""
        return 2.0 * self.xi_b * self.omega_b


@dataclass(frozen=True)
class FPIsolation:
    """Friction-pendulum isolator with Bouc-Wen hysteresis (paper §2.2.2).

    Parameters
    ----------
    mu_b : float
        Friction coefficient [-].
    R_b : float
        Radius of curvature [m]; ``Tb = 2 pi sqrt(R_b/g)``.
    rho : float
        Block-to-base mass ratio ``m/m_b`` [-].
    Y : float
        Bouc-Wen yield displacement [m] (default 0.3 mm).
    beta, gamma : float
        Bouc-Wen shape parameters [-] (defaults 0.1 and 0.9); ``gamma >= |beta|`` keeps ``|Z|`` bounded.
    """

    mu_b: float
    R_b: float
    rho: float
    Y: float = 3.0e-4
    beta: float = 0.1
    gamma: float = 0.9
    kind: Literal["fp"] = field(default="fp", init=False)

    def __post_init__(self) -> None:
        _check("mu_b", self.mu_b, self.mu_b >= 0, "mu_b >= 0")
        _check("R_b", self.R_b, self.R_b > 0, "R_b > 0 m")
        _check("rho", self.rho, self.rho > 0, "rho = m/m_b > 0")
        _check("Y", self.Y, self.Y > 0, "Y > 0 m (Bouc-Wen yield displacement)")
        _check("gamma", self.gamma, self.gamma > 0, "gamma > 0")
        _check("beta", self.beta, abs(self.beta) <= self.gamma, "|beta| <= gamma")

    @classmethod
    def from_period(cls, mu_b: float, Tb: float, rho: float, **kw: float) -> FPIsolation:
        """FP isolator whose pendulum period is ``Tb`` [s]: ``R_b = g (Tb / 2 pi)^2``."""
        _check("Tb", Tb, Tb > 0, "Tb > 0 s")
        return cls(mu_b=mu_b, R_b=G * (Tb / (2.0 * math.pi)) ** 2, rho=rho, **kw)

    @property
    def Tb(self) -> float:
        """Pendulum period ``2 pi sqrt(R_b/g)`` [s]."""
        return 2.0 * math.pi * math.sqrt(self.R_b / G)

    @property
    def omega_b(self) -> float:
        """Pendulum circular frequency ``sqrt(g/R_b)`` [rad/s]."""
        return math.sqrt(G / self.R_b)

    @property
    def kb(self) -> float:
        """Post-yield stiffness per unit total mass ``g/R_b`` [1/s^2]."""
        return G / self.R_b

    @property
    def cb(self) -> float:
        """No viscous damping: 0 [1/s]."""
        return 0.0


Isolation = NoIsolation | LinearIsolation | FPIsolation

Body = Block | RigidBody
"""A free-standing object: the uniform block of the paper, or a rigid body of measured geometry
(:class:`~isorock.physics.body.RigidBody`, docs/model.md §18)."""


@dataclass(frozen=True)
class System:
    """A block on its base: the full set of model parameters.

    Parameters
    ----------
    block : Block or RigidBody
        The object: a uniform block, or a rigid body of measured geometry (docs/model.md §18).
    isolation : NoIsolation | LinearIsolation | FPIsolation
        The isolation system (``NoIsolation()`` for a block on the ground).
    sliding_only : bool
        The object's friction is below ``tan(alpha)``: it slides and never rocks (docs/model.md §16),
        so it never meets the impact of §7 and the no-bounce limit does not apply; such a system is
        analysed only in the sliding mode (``simulate(..., friction=...)``).

    Raises
    ------
    ParameterError
        If the block would bounce at impact (``eps <= 0``), i.e. ``lambda^2 <= 2(rho+1)/(rho+4)``, and
        it may rock (for a rigid body: the restitution of either side at or below 0).
    """

    block: Body
    isolation: Isolation = field(default_factory=NoIsolation)
    sliding_only: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.block, RigidBody):
            if self.sliding_only:
                return
            for s, onto in ((1.0, "left"), (-1.0, "right")):
                eps = self.block.impact(s, self.kappa)[0]
                if not eps > 0.0:
                    raise ParameterError(
                        f"the body would bounce landing on its {onto} edge (restitution {eps:.4g} <= 0 "
                        f"for rho={self.isolation.rho:g}): the model holds for bodies that rock without "
                        "bouncing; an object whose friction is below tan(alpha) slides and never rocks: "
                        "give its friction to analyse its sliding"
                    )
            return
        lim = self.lambda_min
        if not self.block.lam > lim and not self.sliding_only:
            raise ParameterError(
                f"lambda={self.block.lam:.6g} is out of range: valid lambda > {lim:.6g} "
                f"(no-bounce limit sqrt(2(rho+1)/(rho+4)) for rho={self.isolation.rho:g}); an object "
                "whose friction is below tan(alpha) slides and never rocks: give its friction "
                "(--friction, or friction of an assessed object) to analyse its sliding"
            )

    @property
    def isolated(self) -> bool:
        """True for a linear or FP isolator."""
        return self.isolation.kind != "none"

    @property
    def lambda_min(self) -> float:
        """Smallest slenderness of a uniform block for which impacts do not bounce (``eps > 0``) [-]."""
        rho = self.isolation.rho
        return math.sqrt(2.0 * (rho + 1.0) / (rho + 4.0))

    @property
    def kappa(self) -> float:
        """``m/(m+m_b) = rho/(1+rho)`` [-] (0 for the non-isolated block)."""
        rho = self.isolation.rho
        return rho / (1.0 + rho)

    @property
    def alpha(self) -> float:
        """Slenderness angle [rad]."""
        return self.block.alpha

    @property
    def p(self) -> float:
        """Frequency parameter of the block [rad/s]."""
        return self.block.p

    @property
    def eps(self) -> float:
        """Angular coefficient of restitution [-] (Housner's for the non-isolated block; for a rigid body
        the smaller of its two sides')."""
        if isinstance(self.block, RigidBody):
            return min(self.block.impact(s, self.kappa)[0] for s in (1.0, -1.0))
        if not self.isolated:
            return self.block.eps_housner
        return impact_coefficients(self.block.lam, self.block.h, self.isolation.rho)[0]

    @property
    def beta1(self) -> float:
        """Base-velocity jump coefficient when rocking continues [m/rad] (0 if non-isolated; a uniform
        block's: a rigid body has one per side, :meth:`RigidBody.impact`)."""
        if not self.isolated:
            return 0.0
        if isinstance(self.block, RigidBody):
            raise ParameterError("a rigid body has a beta1 per side: use system.block.impact(s, kappa)")
        return impact_coefficients(self.block.lam, self.block.h, self.isolation.rho)[1]

    @property
    def beta2(self) -> float:
        """Base-velocity jump coefficient when rocking ceases [m/rad] (0 if non-isolated)."""
        if not self.isolated:
            return 0.0
        if isinstance(self.block, RigidBody):
            return self.kappa * self.block.h_cg
        return impact_coefficients(self.block.lam, self.block.h, self.isolation.rho)[2]

    @property
    def kb(self) -> float:
        """Isolator stiffness per unit total mass [1/s^2] (0 if non-isolated)."""
        return getattr(self.isolation, "kb", 0.0)

    @property
    def cb(self) -> float:
        """Isolator damping per unit total mass [1/s] (0 if non-isolated)."""
        return getattr(self.isolation, "cb", 0.0)

    @property
    def uplift_acc(self) -> float:
        """Total base acceleration at which rocking starts, ``g tan(alpha)`` [m/s^2] (for a rigid body,
        on its weaker side)."""
        return G * self.block.tan_alpha

    @property
    def tail(self) -> float:
        """Free-vibration tail simulated after the excitation [s]: 2 Tb isolated, 5 s otherwise."""
        return 2.0 * self.isolation.Tb if self.isolated else 5.0


def make_isolation(
    kind: str,
    *,
    rho: float | None = None,
    Tb_s: float | None = None,
    xi_b: float | None = None,
    mu_b: float | None = None,
    R_b_m: float | None = None,
    Y_m: float | None = None,
    bw_beta: float | None = None,
    bw_gamma: float | None = None,
    names: dict[str, str] | None = None,
) -> Isolation:
    """The isolation object of a kind and its parameters: the one place where a name becomes a model.

    Parameters
    ----------
    kind : {"none", "linear", "fp"}
        Isolation model.
    rho : float
        Block-to-base mass ratio ``m/m_b`` [-] (linear and fp).
    Tb_s : float
        Linear isolator period [s]; for ``fp`` the pendulum period, used when ``R_b_m`` is not given.
    xi_b : float
        Linear isolator damping ratio [-].
    mu_b : float
        FP friction coefficient [-].
    R_b_m : float
        FP radius of curvature [m].
    Y_m, bw_beta, bw_gamma : float, optional
        Bouc-Wen yield displacement [m] and shape parameters [-] of the FP isolator (model defaults
        when None).
    names : dict, optional
        How the caller names the parameters (e.g. ``{"Tb_s": "--Tb"}``), for the error messages.

    Raises
    ------
    ParameterError
        Unknown kind, a missing parameter (named with its unit) or a value out of range.
    """

    def name(key: str) -> str:
        return (names or {}).get(key, key)

    def need(key: str, value: float | None, what: str) -> float:
        if value is None:
            raise ParameterError(f"isolation {kind} needs {name(key)} ({what})")
        return float(value)

    # every parameter the kind needs and lacks, named at once
    needs = {
        "linear": (
            ("Tb_s", Tb_s, "isolation period, s"),
            ("xi_b", xi_b, "damping ratio"),
            ("rho", rho, "mass ratio m/m_b"),
        ),
        "fp": (("mu_b", mu_b, "friction coefficient"), ("rho", rho, "mass ratio m/m_b")),
    }.get(kind, ())
    missing = [f"{name(k)} ({what})" for k, v, what in needs if v is None]
    if kind == "fp" and R_b_m is None and Tb_s is None:
        missing.append(f"{name('R_b_m')} (radius of curvature, m) or {name('Tb_s')} (period, s)")
    if missing:
        raise ParameterError(f"isolation {kind} needs {', '.join(missing)}")
    if kind == "none":
        return NoIsolation()
    if kind == "linear":
        return LinearIsolation(
            Tb=need("Tb_s", Tb_s, "isolation period, s"),
            xi_b=need("xi_b", xi_b, "damping ratio"),
            rho=need("rho", rho, "mass ratio m/m_b"),
        )
    if kind == "fp":
        bw: dict[str, Any] = {
            k: float(v) for k, v in (("Y", Y_m), ("beta", bw_beta), ("gamma", bw_gamma)) if v is not None
        }
        mu = need("mu_b", mu_b, "friction coefficient")
        r = need("rho", rho, "mass ratio m/m_b")
        if R_b_m is not None:
            return FPIsolation(mu_b=mu, R_b=float(R_b_m), rho=r, **bw)
        if Tb_s is not None:
            return FPIsolation.from_period(mu_b=mu, Tb=float(Tb_s), rho=r, **bw)
        raise ParameterError(
            f"isolation fp needs {name('R_b_m')} (radius of curvature, m) or {name('Tb_s')} (period, s)"
        )
    raise ParameterError(f"isolation kind {kind!r} is not known: valid {', '.join(ISOLATION_KINDS)}")


def isolation_params(iso: Isolation) -> dict[str, float]:
    """The parameters of an isolation object, named as :func:`make_isolation` takes them.

    ``make_isolation(iso.kind, **isolation_params(iso))`` rebuilds ``iso``. Units in the names:
    ``Tb_s`` [s], ``R_b_m`` [m], ``Y_m`` [m]; ``xi_b``, ``rho``, ``mu_b``, ``bw_beta``, ``bw_gamma`` [-].
    """
    if iso.kind == "linear":
        return {"Tb_s": iso.Tb, "xi_b": iso.xi_b, "rho": iso.rho}
    if iso.kind == "fp":
        return {
            "mu_b": iso.mu_b,
            "R_b_m": iso.R_b,
            "rho": iso.rho,
            "Y_m": iso.Y,
            "bw_beta": iso.beta,
            "bw_gamma": iso.gamma,
        }
    return {}
