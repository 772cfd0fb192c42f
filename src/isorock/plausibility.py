"""Plausibility of what a user types: values that the model accepts but that are almost surely a slip.

The model takes any positive size and friction (:mod:`isorock.physics.model`): the paper's regime maps go up
to
R = 15 m. But an *object* described by its height and width is a statue, a cabinet, a piece of
equipment: a height of 180 m is a height of 180 cm typed in the wrong unit, and an assessment of it
would be silently wrong. These checks refuse such values with both readings of them and what to write
instead; the command line (``--height``, ``--width``, ``--mu``, ``--Tb``, ``--td`` ...) and the
configuration (objects, isolation cases, the grids of the studies, the design grid) apply the same ones
(:func:`check_finite`, :func:`check_object`, :func:`check_isolator`, :func:`check_duration`). An object
that really is that large is given by its slenderness and size (``lambda`` and ``R_m``, ``--lambda``
and ``--R``), which are only checked to be finite and > 0.

The bounds, one set for both (docs/assessment.md §8 states them for users):

=============================================  ================  =============================================
value                                          accepted          why
=============================================  ================  =============================================
every number                                   finite            NaN, infinity are no values (YAML ``.nan``)
object height, width [m]                       <= 10, <= 5       larger reads like centimetres
object friction [-]                            (0, 1]            rubber on concrete is about 1
friction-pendulum friction ``mu_b`` [-]        (0, 0.3]          products 0.02 to 0.2
mass ratio ``rho = m/m_b`` [-]                 (0, 10]           pedestals and floors 0.1 to 2
damping ratio ``xi_b`` [-]                     [0, 1)            isolators 0.02 to 0.5
isolator period ``Tb`` (FP: 2 pi sqrt(R_b/g))  0.05 to 20 s      isolators 1.5 to 6 s
pulse duration ``td``, pulse period ``Tp``     0.05 to 20 s      recorded pulses 0.3 to 15 s
=============================================  ================  =============================================
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from isorock.constants import G
from isorock.errors import ParameterError

__all__ = [
    "HEIGHT_MAX_M",
    "WIDTH_MAX_M",
    "FRICTION_MAX",
    "MU_B_MAX",
    "RHO_MAX",
    "XI_MAX",
    "PERIOD_MIN_S",
    "PERIOD_MAX_S",
    "BOUNDS_TEXT",
    "check_finite",
    "check_object",
    "check_isolator",
    "check_duration",
]

#: an object's full height above this reads like centimetres [m]
HEIGHT_MAX_M = 10.0
#: an object's full width above this reads like centimetres [m]
WIDTH_MAX_M = 5.0
#: an object's friction coefficient above this is no real interface (rubber on concrete reaches about 1)
FRICTION_MAX = 1.0
#: a friction-pendulum isolator's friction coefficient above this is no isolator (products: 0.02 to 0.2)
MU_B_MAX = 0.3
#: a block-to-base mass ratio m/m_b above this is no isolated floor or pedestal (they have 0.1 to 2) [-]
RHO_MAX = 10.0
#: a damping ratio is below this (an over-damped isolator does not oscillate) [-]
XI_MAX = 1.0
#: shortest duration or period of a pulse (td, Tp) or an isolator (Tb) [s]: 20 Hz, above any earthquake pulse
PERIOD_MIN_S = 0.05
#: longest duration or period of a pulse (td, Tp) or an isolator (Tb) [s]: recorded velocity pulses reach
#: about 15 s, isolators 6 s
PERIOD_MAX_S = 20.0

#: largest peak ground acceleration tried by a search or a pulse study [g]: recorded PGAs stay below
#: about 4 g; a block that has not overturned at 50 g is counted as not overturning
AMP_MAX_G = 50.0
#: largest block half-diagonal R of the grids [m]: the paper's maps go to 15 m; 100 m is a tower
R_MAX_M = 100.0

#: the bounds in words, for help texts
BOUNDS_TEXT = (
    f"durations and periods (td, Tp, Tb) {PERIOD_MIN_S:g} to {PERIOD_MAX_S:g} s; FP friction "
    f"(0, {MU_B_MAX:g}]; object friction (0, {FRICTION_MAX:g}]; rho (0, {RHO_MAX:g}]; xi [0, {XI_MAX:g})"
)


def _name(names: Mapping[str, str] | None, key: str) -> str:
    return (names or {}).get(key, key)


def check_finite(values: Mapping[str, float | None], *, names: Mapping[str, str] | None = None) -> None:
    """Refuse a value that is not a finite number (NaN, an infinity: ``--td nan``, YAML ``.inf``).

    Parameters
    ----------
    values : mapping
        Key -> value (None: not given, not checked).
    names : mapping, optional
        How the caller spells the keys (``{"td": "--td"}``), for the message.

    Raises
    ------
    ParameterError
        One line naming the first such value.
    """
    for key, v in values.items():
        if v is not None and not math.isfinite(float(v)):
            raise ParameterError(f"{_name(names, key)} {v} is not a finite number: give a number")


def _outside(n: str, v: float, lo: float, hi: float, unit: str, why: str) -> ParameterError:
    return ParameterError(f"{n} {v:g} is outside {lo:g} to {hi:g}{unit}: {why}")


def check_duration(
    value: float | None, key: str = "td", *, names: Mapping[str, str] | None = None, what: str = "pulse"
) -> None:
    """Refuse a pulse duration or period [s] outside :data:`PERIOD_MIN_S` to :data:`PERIOD_MAX_S`.

    Parameters
    ----------
    value : float or None
        The half-cycle duration ``td`` or the period ``Tp`` [s] (None: not checked).
    key : str
        Its name, for the message (``names`` may respell it).
    names : mapping, optional
        How the caller spells the keys.
    what : str
        What it is the duration of (for the message).

    Raises
    ------
    ParameterError
        Not finite, or outside the bounds (one line with the bounds and why).
    """
    if value is None:
        return
    check_finite({key: value}, names=names)
    if not PERIOD_MIN_S <= value <= PERIOD_MAX_S:
        raise _outside(
            _name(names, key),
            value,
            PERIOD_MIN_S,
            PERIOD_MAX_S,
            " s",
            f"a {what}'s duration or period must be within them (recorded velocity pulses: 0.3 to "
            f"15 s; below {PERIOD_MIN_S:g} s is above 20 Hz, no ground-motion pulse)"
            + (
                f"; if it is milliseconds, {value:g} ms would be {value / 1000:g} s"
                if PERIOD_MIN_S <= value / 1000 <= PERIOD_MAX_S
                else ""
            ),
        )


def check_object(
    height_m: float | None = None,
    width_m: float | None = None,
    friction: float | None = None,
    *,
    names: Mapping[str, str] | None = None,
) -> None:
    """Refuse an object whose height [m], width [m] or friction [-] is implausible.

    Parameters
    ----------
    height_m, width_m : float, optional
        Full height and width [m], as the user gave them.
    friction : float, optional
        Friction coefficient against its floor [-], in (0, :data:`FRICTION_MAX`].
    names : mapping, optional
        How the caller spells the keys (``{"height_m": "--height"}``), for the messages.

    Raises
    ------
    ParameterError
        One line naming every such value, both readings of it and what to write instead.
    """
    check_finite({"height_m": height_m, "width_m": width_m, "friction": friction}, names=names)
    problems = []
    for key, v, top in (("height_m", height_m, HEIGHT_MAX_M), ("width_m", width_m, WIDTH_MAX_M)):
        if v is not None and v > top:
            n = _name(names, key)
            problems.append(
                f"{n} {v:g} reads like centimetres: {v:g} m is above {top:g} m for an object's "
                f"{'height' if key == 'height_m' else 'width'}, while {v:g} cm would be {v / 100:g} m; "
                f"give metres ({n} {v / 100:g})"
            )
    if problems:
        problems[-1] += ", or, for an object really this large, its lambda and R_m"
    if friction is not None and friction > FRICTION_MAX:
        n = _name(names, "friction")
        problems.append(
            f"{n} {friction:g} is above {FRICTION_MAX:g}: no floor grips an object that hard (rubber on "
            f"concrete is about 1, stone on stone 0.6-0.7); if it is a percentage, {friction:g} % would "
            f"be {friction / 100:g}"
        )
    elif friction is not None and not friction > 0:
        problems.append(
            f"{_name(names, 'friction')} {friction:g} must be > 0 and <= {FRICTION_MAX:g} (stone on stone "
            "0.6-0.7, steel on steel about 0.2)"
        )
    if problems:
        raise ParameterError("; ".join(problems))


def check_isolator(
    kind: str,
    mu_b: float | None = None,
    *,
    Tb_s: float | None = None,
    xi_b: float | None = None,
    rho: float | None = None,
    R_b_m: float | None = None,
    names: Mapping[str, str] | None = None,
) -> None:
    """Refuse an isolator whose parameters are not finite or outside the bounds of real isolators.

    Parameters
    ----------
    kind : {"none", "linear", "fp"}
        Isolation model (``none``: nothing is checked).
    mu_b : float, optional
        Friction-pendulum friction coefficient [-], in (0, :data:`MU_B_MAX`].
    Tb_s : float, optional
        Isolator period [s], within :data:`PERIOD_MIN_S` to :data:`PERIOD_MAX_S`.
    xi_b : float, optional
        Damping ratio [-], in [0, :data:`XI_MAX`).
    rho : float, optional
        Block-to-base mass ratio ``m/m_b`` [-], in (0, :data:`RHO_MAX`].
    R_b_m : float, optional
        Friction-pendulum radius [m]: its period ``2 pi sqrt(R_b/g)`` within the period bounds.
    names : mapping, optional
        How the caller spells the keys (``{"mu_b": "--mu"}``), for the messages.

    Raises
    ------
    ParameterError
        One line naming the first such value, the range of real isolators and what to write instead.
    """
    if kind == "none":
        return
    given = {"mu_b": mu_b, "Tb_s": Tb_s, "xi_b": xi_b, "rho": rho, "R_b_m": R_b_m}
    check_finite(given, names=names)
    if kind == "fp" and mu_b is not None:
        n = _name(names, "mu_b")
        if mu_b > MU_B_MAX:
            raise ParameterError(
                f"{n} {mu_b:g} is above {MU_B_MAX:g}: friction pendulum isolators have 0.02 to 0.2 (above "
                f"{MU_B_MAX:g} the slider hardly moves: no isolation); if it is a percentage, {mu_b:g} % "
                f"would be {mu_b / 100:g}"
            )
        if not mu_b > 0:
            raise ParameterError(
                f"{n} {mu_b:g} must be > 0 and <= {MU_B_MAX:g}: friction pendulum isolators have 0.02 to 0.2"
            )
    if Tb_s is not None and not PERIOD_MIN_S <= Tb_s <= PERIOD_MAX_S:
        raise _outside(
            _name(names, "Tb_s"),
            Tb_s,
            PERIOD_MIN_S,
            PERIOD_MAX_S,
            " s",
            "an isolator's period must be within them (isolators: 1.5 to 6 s)",
        )
    if kind == "fp" and R_b_m is not None and R_b_m > 0:
        tb = 2.0 * math.pi * math.sqrt(R_b_m / G)
        if not PERIOD_MIN_S <= tb <= PERIOD_MAX_S:
            cm = (
                f"; if it is centimetres, {R_b_m:g} cm would be {R_b_m / 100:g} m"
                if tb > PERIOD_MAX_S and PERIOD_MIN_S <= tb / 10 <= PERIOD_MAX_S  # that reading accepted
                else ""
            )
            raise ParameterError(
                f"{_name(names, 'R_b_m')} {R_b_m:g} gives a pendulum period 2 pi sqrt(R_b/g) of {tb:.3g} s, "
                f"outside {PERIOD_MIN_S:g} to {PERIOD_MAX_S:g} s (friction pendulums: R_b 1 to 6 m){cm}"
            )
    if xi_b is not None and not 0.0 <= xi_b < XI_MAX:
        pct = f"; if it is a percentage, {xi_b:g} % would be {xi_b / 100:g}" if 1 <= xi_b < 100 else ""
        raise ParameterError(
            f"{_name(names, 'xi_b')} {xi_b:g} is out of range: a damping ratio is >= 0 and < {XI_MAX:g} "
            f"(isolators: 0.02 to 0.5){pct}"
        )
    if rho is not None and not 0.0 < rho <= RHO_MAX:
        pct = f"; if it is a percentage, {rho:g} % would be {rho / 100:g}" if RHO_MAX < rho <= 100 else ""
        raise ParameterError(
            f"{_name(names, 'rho')} {rho:g} is out of range: the block-to-base mass ratio m/m_b is > 0 and "
            f"<= {RHO_MAX:g} (isolated floors and pedestals: 0.1 to 2){pct}"
        )


def check_amplitude(amp_g: float, name: str = "amp_max_g") -> None:
    """A largest amplitude of a search or pulse study [g]: finite, > 0 and at most :data:`AMP_MAX_G`.

    Raises
    ------
    ParameterError
        Outside (one line naming ``name``).
    """
    check_finite({name: amp_g})
    if not 0 < amp_g <= AMP_MAX_G:
        raise ParameterError(
            f"{name} {amp_g:g} is outside (0, {AMP_MAX_G:g}] g: recorded PGAs stay below about 4 g, and a "
            f"block still standing at {AMP_MAX_G:g} g is counted as not overturning"
        )


def check_block_size(
    lam: float | None = None, R_m: float | None = None, *, names: Mapping[str, str] | None = None
) -> None:
    """A block of a grid by its slenderness ``lam`` [-] (> 0; the model refuses those that bounce at
    impact) and half-diagonal ``R_m`` [m] (> 0, at most :data:`R_MAX_M`).

    Raises
    ------
    ParameterError
        Outside (one line naming the key).
    """
    check_finite({"lambda": lam, "R_m": R_m}, names=names)
    if lam is not None and not lam > 0:
        raise ParameterError(f"{_name(names, 'lambda')} {lam:g} must be > 0")
    if R_m is not None and not 0 < R_m <= R_MAX_M:
        raise ParameterError(
            f"{_name(names, 'R_m')} {R_m:g} is outside (0, {R_MAX_M:g}] m: the paper's maps go to 15 m, "
            f"and {R_MAX_M:g} m is a tower"
            # the other reading only where it is a block this check accepts
            + (f"; if it is in cm, {R_m:g} cm would be {R_m / 100:g} m" if 0 < R_m / 100 <= R_MAX_M else "")
        )
