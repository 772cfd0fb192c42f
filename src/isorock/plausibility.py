"""Plausibility of what a user types: values that the model accepts but that are almost surely a slip.

The model takes any positive size and friction (:mod:`isorock.model`): the paper's regime maps go up to
R = 15 m. But an *object* described by its height and width is a statue, a cabinet, a piece of
equipment: a height of 180 m is a height of 180 cm typed in the wrong unit, and an assessment of it
would be silently wrong. These checks refuse such values with both readings of them and what to write
instead; the command line (``--height``, ``--width``, ``--mu``) and the configuration (objects,
isolation cases, the design grid) apply the same ones (:func:`check_object`, :func:`check_isolator`).
An object that really is that large is given by its slenderness and size (``lambda`` and ``R_m``,
``--lambda`` and ``--R``), which are not checked here.
"""

from __future__ import annotations

from collections.abc import Mapping

from .errors import ParameterError

__all__ = ["HEIGHT_MAX_M", "WIDTH_MAX_M", "FRICTION_MAX", "MU_B_MAX", "check_object", "check_isolator"]

#: an object's full height above this reads like centimetres [m]
HEIGHT_MAX_M = 10.0
#: an object's full width above this reads like centimetres [m]
WIDTH_MAX_M = 5.0
#: an object's friction coefficient above this is no real interface (rubber on concrete reaches about 1)
FRICTION_MAX = 1.0
#: a friction-pendulum isolator's friction coefficient above this is no isolator (products: 0.02 to 0.2)
MU_B_MAX = 0.3


def _name(names: Mapping[str, str] | None, key: str) -> str:
    return (names or {}).get(key, key)


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
        Friction coefficient against its floor [-].
    names : mapping, optional
        How the caller spells the keys (``{"height_m": "--height"}``), for the messages.

    Raises
    ------
    ParameterError
        One line naming every such value, both readings of it and what to write instead.
    """
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
    if problems:
        raise ParameterError("; ".join(problems))


def check_isolator(kind: str, mu_b: float | None = None, *, names: Mapping[str, str] | None = None) -> None:
    """Refuse a friction-pendulum isolator whose friction coefficient is above :data:`MU_B_MAX`.

    Raises
    ------
    ParameterError
        One line naming the value and the range of real isolators.
    """
    if kind == "fp" and mu_b is not None and mu_b > MU_B_MAX:
        n = _name(names, "mu_b")
        raise ParameterError(
            f"{n} {mu_b:g} is above {MU_B_MAX:g}: friction pendulum isolators have 0.02 to 0.2 (above "
            f"{MU_B_MAX:g} the slider hardly moves: no isolation); if it is a percentage, {mu_b:g} % "
            f"would be {mu_b / 100:g}"
        )
