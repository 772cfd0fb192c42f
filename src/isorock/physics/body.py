"""A free-standing object of measured geometry: the rigid body of docs/model.md §18.

The uniform rectangular block (:class:`~isorock.physics.model.Block`) has its centre of mass at mid-height
over
the middle of its footprint and the inertia ``m (b^2 + h^2) / 3``. A statue, a vase or a cabinet has
neither: :class:`RigidBody` takes, in the plane of the motion, the horizontal distances from the centre
of mass to the two edges of the footprint (``b_left``, ``b_right``), the height of the centre of mass
(``h_cg``) and the radius of gyration about it (``r_gyration``), or builds them from rectangular parts
(:meth:`RigidBody.from_parts`). Each side ``s`` then has its own ``R_s``, ``alpha_s``, moment of inertia
about its edge and coefficient of restitution (:class:`Side`, :func:`restitution`).

Sides: ``s = +1`` rocks about the right edge (``theta > 0``, the body leans to ``+x``), ``s = -1``
about the left edge. A positive total base acceleration tips the body onto its left edge.
All lengths in m, angles in rad.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from isorock.constants import G
from isorock.errors import ParameterError

__all__ = ["RigidBody", "Side", "Part", "restitution", "parts_from_config"]


def _check(name: str, value: float, ok: bool, valid: str) -> None:
    """Raise :class:`~isorock.errors.ParameterError` unless ``value`` is a finite number and ``ok`` (the
    model's parameters are checked by it too, :mod:`isorock.physics.model`)."""
    if not (isinstance(value, (int, float)) and math.isfinite(value) and ok):
        raise ParameterError(f"{name}={value!r} is out of range: valid {valid}")


@dataclass(frozen=True)
class Side:
    """The geometry of one side of a body: rocking about the edge at ``b`` from the centre of mass.

    Attributes
    ----------
    b : float
        Horizontal distance from the centre of mass to the edge [m].
    h : float
        Height of the centre of mass above the base [m].
    R : float
        Distance from the edge to the centre of mass, ``sqrt(b^2 + h^2)`` [m].
    alpha : float
        ``atan(b / h)`` [rad]: the rotation at which the centre of mass is over the edge.
    inertia : float
        Moment of inertia about the edge per unit mass, ``r^2 + R^2`` [m^2].
    """

    b: float
    h: float
    R: float
    alpha: float
    inertia: float

    @property
    def tan_alpha(self) -> float:
        """``b / h`` [-]: the ground acceleration, in g, that lifts the body onto this edge (fixed base)."""
        return self.b / self.h

    @property
    def p(self) -> float:
        """Frequency parameter ``sqrt(g R / I)`` [rad/s] (``sqrt(3 g / 4R)`` for a uniform block)."""
        return math.sqrt(G * self.R / self.inertia)


def restitution(r2: float, h: float, b_old: float, b_new: float, kappa: float = 0.0) -> float:
    """Coefficient of restitution ``theta'+ / theta'-`` of an impact of a general rigid body.

    The body rocks about the edge at ``b_old`` from its centre of mass and lands on the edge at
    ``b_new`` on the other side. The impulse acts at the new edge only: the body's angular momentum
    about that edge is conserved, ``(r^2 + h^2 + b_new^2) theta'+ + h u'+ = (r^2 + h^2 - b_old b_new)
    theta'- + h u'-`` (per unit mass), and on an isolated base so is the horizontal momentum of body
    and base, ``u'+ = u'- + kappa h (theta'- - theta'+)``. Hence

    ``eps = (r^2 + h^2 - b_old b_new - kappa h^2) / (r^2 + h^2 + b_new^2 - kappa h^2)``,

    Housner's ``1 - 1.5 sin^2 alpha`` for a uniform block on a fixed base (``kappa = 0``) and the
    paper's Eq. 29 on an isolated one (docs/model.md §7, §18).

    Parameters
    ----------
    r2 : float
        Squared radius of gyration about the centre of mass [m^2].
    h : float
        Height of the centre of mass [m].
    b_old, b_new : float
        Distances from the centre of mass to the edge left and to the edge landed on [m].
    kappa : float
        ``m / (m + m_b)`` [-]; 0 on a fixed base.
    """
    num = r2 + h * h - b_old * b_new - kappa * h * h
    den = r2 + h * h + b_new * b_new - kappa * h * h
    return num / den


@dataclass(frozen=True)
class Part:
    """A rectangle of a body built from parts, in the plane of the motion.

    Parameters
    ----------
    width_m, height_m : float
        Its width and height [m].
    x_m : float
        Horizontal position of its centre line [m], from any origin common to the parts.
    y_m : float
        Height of its bottom above the base the object stands on [m] (0: it stands on the base and
        makes the footprint).
    mass_kg : float
        Its mass [kg].
    """

    width_m: float
    height_m: float
    x_m: float
    y_m: float
    mass_kg: float

    def __post_init__(self) -> None:
        _check("width_m", self.width_m, self.width_m > 0, "width_m > 0 m")
        _check("height_m", self.height_m, self.height_m > 0, "height_m > 0 m")
        _check("x_m", self.x_m, True, "a finite number of m")
        _check("y_m", self.y_m, self.y_m >= 0, "y_m >= 0 m (height of its bottom above the base)")
        _check("mass_kg", self.mass_kg, self.mass_kg > 0, "mass_kg > 0 kg")


@dataclass(frozen=True)
class RigidBody:
    """A free-standing rigid body of measured geometry (docs/model.md §18).

    Parameters
    ----------
    b_left, b_right : float
        Horizontal distances from the centre of mass to the left and the right edge of the footprint [m].
    h_cg : float
        Height of the centre of mass above the base [m].
    r_gyration : float
        Radius of gyration about the centre of mass, ``sqrt(I_c / m)`` [m] (``sqrt((b^2 + h^2) / 3)``
        for a uniform block of half-width ``b``, half-height ``h``).
    restitution : float, optional
        A coefficient of restitution measured for the object [-], in (0, 1]; it replaces the one of
        angular momentum (:func:`restitution`) at every impact, both sides. None: from the geometry.

    Examples
    --------
    >>> body = RigidBody(b_left=0.25, b_right=0.25, h_cg=0.7, r_gyration=0.45)
    >>> round(body.left.tan_alpha, 4), round(body.right.tan_alpha, 4)
    (0.3571, 0.3571)
    """

    b_left: float
    b_right: float
    h_cg: float
    r_gyration: float
    restitution: float | None = None

    def __post_init__(self) -> None:
        _check("b_left", self.b_left, self.b_left > 0, "b_left > 0 m (centre of mass inside the footprint)")
        _check(
            "b_right", self.b_right, self.b_right > 0, "b_right > 0 m (centre of mass inside the footprint)"
        )
        _check("h_cg", self.h_cg, self.h_cg > 0, "h_cg > 0 m")
        _check("r_gyration", self.r_gyration, self.r_gyration > 0, "r_gyration > 0 m")
        if self.restitution is not None:
            _check("restitution", self.restitution, 0 < self.restitution <= 1, "0 < restitution <= 1")

    # ------------------------------------------------------------ construction
    @classmethod
    def uniform(cls, width: float, height: float) -> RigidBody:
        """The uniform rectangular block of a width and a height [m] as a general body."""
        _check("width", width, width > 0, "width > 0 m")
        _check("height", height, height > 0, "height > 0 m")
        b, h = width / 2.0, height / 2.0
        return cls(b, b, h, math.sqrt((b * b + h * h) / 3.0))

    @classmethod
    def from_inertia(
        cls, b_left: float, b_right: float, h_cg: float, inertia_kgm2: float, mass_kg: float, **kw
    ) -> RigidBody:
        """A body whose moment of inertia about its centre of mass [kg m^2] and mass [kg] are known."""
        _check("inertia_kgm2", inertia_kgm2, inertia_kgm2 > 0, "inertia_kgm2 > 0 kg m^2")
        _check("mass_kg", mass_kg, mass_kg > 0, "mass_kg > 0 kg")
        return cls(b_left, b_right, h_cg, math.sqrt(inertia_kgm2 / mass_kg), **kw)

    @classmethod
    def from_parts(cls, parts: Iterable[Part], **kw) -> RigidBody:
        """The body made of rectangles: its centre of mass, footprint and inertia.

        The footprint spans the parts that stand on the base (``y_m == 0``); every part is a uniform
        rectangle (its own inertia ``m (w^2 + h^2) / 12`` plus the parallel-axis term).

        Raises
        ------
        ParameterError
            No part, no part on the base, or a centre of mass outside the footprint (the object would
            not stand).
        """
        ps = list(parts)
        if not ps:
            raise ParameterError("parts: give at least one part")
        base = [p for p in ps if p.y_m == 0.0]
        if not base:
            raise ParameterError("parts: no part stands on the base (y_m = 0): the footprint is not defined")
        m = sum(p.mass_kg for p in ps)
        xc = sum(p.mass_kg * p.x_m for p in ps) / m
        yc = sum(p.mass_kg * (p.y_m + p.height_m / 2.0) for p in ps) / m
        ic = sum(
            p.mass_kg
            * ((p.width_m**2 + p.height_m**2) / 12.0 + (p.x_m - xc) ** 2 + (p.y_m + p.height_m / 2 - yc) ** 2)
            for p in ps
        )
        left = min(p.x_m - p.width_m / 2.0 for p in base)
        right = max(p.x_m + p.width_m / 2.0 for p in base)
        if not left < xc < right:
            raise ParameterError(
                f"parts: the centre of mass (x = {xc:.4g} m) is outside the footprint [{left:.4g}, "
                f"{right:.4g}] m: the object does not stand by itself"
            )
        return cls(xc - left, right - xc, yc, math.sqrt(ic / m), **kw)

    # ------------------------------------------------------------ geometry
    def side(self, s: float) -> Side:
        """The side ``s``: ``+1`` rocks about the right edge, ``-1`` about the left one."""
        b = self.b_right if s > 0 else self.b_left
        R = math.hypot(b, self.h_cg)
        return Side(b, self.h_cg, R, math.atan2(b, self.h_cg), self.r_gyration**2 + R * R)

    @property
    def left(self) -> Side:
        """Rocking about the left edge (``theta < 0``; lifted by a positive base acceleration)."""
        return self.side(-1.0)

    @property
    def right(self) -> Side:
        """Rocking about the right edge (``theta > 0``; lifted by a negative base acceleration)."""
        return self.side(1.0)

    @property
    def width(self) -> float:
        """Width of the footprint ``b_left + b_right`` [m]."""
        return self.b_left + self.b_right

    @property
    def tan_alpha(self) -> float:
        """The smaller ``tan(alpha_s)`` [-]: the ground acceleration, in g, of the first uplift on a fixed
        base, on the body's weaker side (compare the sliding friction with it)."""
        return min(self.left.tan_alpha, self.right.tan_alpha)

    @property
    def lam(self) -> float:
        """``h_cg / b`` of the weaker side [-] (the slenderness ``h/b`` of a uniform block)."""
        return 1.0 / self.tan_alpha

    @property
    def alpha(self) -> float:
        """The smaller slenderness angle [rad]."""
        return min(self.left.alpha, self.right.alpha)

    @property
    def p(self) -> float:
        """The larger frequency parameter of the two sides [rad/s]."""
        return max(self.left.p, self.right.p)

    @property
    def symmetric(self) -> bool:
        """Both edges at the same distance from the centre of mass: no direction is weaker."""
        return self.b_left == self.b_right

    def impact(self, s: float, kappa: float = 0.0) -> tuple[float, float]:
        """Impact landing from side ``s`` onto the other edge: ``(eps, beta1)``.

        ``theta'+ = eps theta'-`` [-] and ``u'+ = u'- + beta1 theta'-`` [m/rad] with ``beta1 = kappa h
        (1 - eps)`` from the horizontal momentum of body and base (0 on a fixed base). The object's own
        :attr:`restitution`, when given, replaces ``eps``.
        """
        old, new = self.side(s), self.side(-s)
        eps = self.restitution
        if eps is None:
            eps = restitution(self.r_gyration**2, self.h_cg, old.b, new.b, kappa)
        return eps, kappa * self.h_cg * (1.0 - eps)

    def describe(self) -> str:
        """One line with the geometry and what it implies, for the user to check."""
        lt, rt = self.left, self.right
        return (
            f"rigid body: centre of mass {self.h_cg:.4g} m high, {self.b_left:.4g} m from the left edge "
            f"and {self.b_right:.4g} m from the right one, radius of gyration {self.r_gyration:.4g} m; "
            f"uplift at {lt.tan_alpha:.4g} g onto the left edge, {rt.tan_alpha:.4g} g onto the right one; "
            f"restitution {self.impact(1.0)[0]:.4g} landing on the left edge, {self.impact(-1.0)[0]:.4g} "
            "on the right one (fixed base)"
        )

    def as_dict(self) -> dict:
        """The defining values, named as the configuration and the JSON name them."""
        out = {
            "b_left_m": self.b_left,
            "b_right_m": self.b_right,
            "h_cg_m": self.h_cg,
            "r_gyration_m": self.r_gyration,
        }
        if self.restitution is not None:
            out["restitution"] = self.restitution
        return out


def parts_from_config(items: object, where: str) -> list[Part]:
    """The parts of a configuration (``[{width_m, height_m, x_m, y_m, mass_kg}, ...]``).

    Raises
    ------
    ParameterError
        Naming ``where`` (e.g. ``assessment.objects[1].parts[2]``) and the key at fault.
    """
    if not isinstance(items, list) or not items:
        raise ParameterError(f"{where}: give a list of parts, each {{width_m, height_m, x_m, y_m, mass_kg}}")
    out = []
    keys = ("width_m", "height_m", "x_m", "y_m", "mass_kg")
    for i, it in enumerate(items):
        if not isinstance(it, Mapping):
            raise ParameterError(
                f"{where}[{i}]: a part is a mapping {{width_m, height_m, x_m, y_m, mass_kg}}"
            )
        missing = [k for k in keys if k not in it]
        unknown = sorted(set(it) - set(keys))
        if missing or unknown:
            what = f"missing {', '.join(missing)}" if missing else f"unknown {', '.join(unknown)}"
            raise ParameterError(f"{where}[{i}]: {what} (a part has width_m, height_m, x_m, y_m, mass_kg)")
        try:
            out.append(Part(**{k: float(it[k]) for k in keys}))
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"{where}[{i}]: {exc}") from None
    return out
