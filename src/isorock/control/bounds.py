"""The bounds of every value of a workflow configuration: finite numbers, and each grid and value of
the studies within the bounds of :mod:`isorock.plausibility`, the ones the command line applies.

:func:`check_finite_tree` refuses YAML ``.nan`` and ``.inf`` anywhere (the schema's bounds let NaN
through: every comparison with it is false); :func:`check_values` checks the grids and single values of
the studies by what they are (a slenderness, a block size, an isolator period, a pulse duration, a
largest amplitude ...). :func:`isorock.control.config.validate_config` calls both; each error is a
:class:`~isorock.errors.ConfigError`, one line naming the key.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from isorock.errors import ConfigError, ParameterError
from isorock.plausibility import (
    PERIOD_MAX_S,
    PERIOD_MIN_S,
    check_amplitude,
    check_block_size,
    check_duration,
    check_isolator,
)

__all__ = ["check_finite_tree", "check_values", "check_grid_values", "refuse", "DESIGN_AXES"]


#: the longest string a configuration holds (a path: PATH_MAX of Linux) [characters]; names are at
#: most 64 (the schema's maxLength)
MAX_STRING = 4096


def check_string_lengths(node: Any, path: str = "") -> None:
    """Refuse a string longer than :data:`MAX_STRING` anywhere in a configuration (a key or a value),
    naming its key and its length, before the schema's patterns are matched against it (a 10 MB name
    once hung the workflow's DAG)."""
    if isinstance(node, Mapping):
        for k, v in node.items():
            where = f"{path}.{k}" if path else str(k)
            if isinstance(k, str) and len(k) > MAX_STRING:
                raise ConfigError(
                    f"configuration: {path or '(top level)'}: a key of {len(k):,} characters (at most "
                    f"{MAX_STRING:,})"
                )
            check_string_lengths(v, where)
    elif isinstance(node, list | tuple):
        for k, v in enumerate(node):
            check_string_lengths(v, f"{path}.{k}" if path else str(k))
    elif isinstance(node, str) and len(node) > MAX_STRING:
        raise ConfigError(
            f"configuration: {path or '(top level)'}: a string of {len(node):,} characters (at most "
            f"{MAX_STRING:,})"
        )


def check_finite_tree(node: Any, path: str = "") -> None:
    """Refuse a number that is not finite anywhere in a configuration (YAML ``.nan``, ``.inf``,
    ``-.inf``), naming its key: the schema's bounds let NaN through (every comparison with it is
    false), and no key takes an infinity."""
    if isinstance(node, Mapping):
        for k, v in node.items():
            check_finite_tree(v, f"{path}.{k}" if path else str(k))
    elif isinstance(node, list | tuple):
        for k, v in enumerate(node):
            check_finite_tree(v, f"{path}.{k}" if path else str(k))
    elif isinstance(node, float) and not math.isfinite(node):
        shown = ".nan" if math.isnan(node) else (".inf" if node > 0 else "-.inf")
        raise ConfigError(
            f"configuration: {path or '(top level)'}: {shown} is not a finite number: must be a finite "
            "number (NaN and infinity are not values)"
        )


#: what the values of each grid of the studies are (:func:`_check_value`)
_GRIDS = (
    (("overturn", "lambda"), "lambda"),
    (("overturn", "R_m"), "R"),
    (("maps", "lambda_R", "lambda"), "lambda"),
    (("maps", "lambda_R", "R_m"), "R"),
    (("maps", "Tb_xi", "Tb_s"), "period"),
    (("maps", "Tb_xi", "xi_b"), "damping"),
    (("pulses", "vs_R", "td_s"), "duration"),
    (("pulses", "vs_R", "R_m"), "R"),
    (("pulses", "vs_omega", "R_m"), "R"),
    (("pulses", "vs_omega", "omega_p_rad_s"), "omega"),
    (("pulses", "vs_isolation", "R_m"), "R"),
    (("pulses", "vs_isolation", "td_s"), "duration"),
    (("pulses", "vs_isolation", "Tb_s"), "period"),
    (("pulses", "vs_isolation", "xi_b"), "damping"),
    (("pulses", "vs_isolation", "rho"), "rho"),
)
#: what the single values are
_SCALARS = (
    (("isolation", "rho"), "rho"),
    (("maps", "Tb_xi", "rho"), "rho"),
    (("pulse", "tp_min_s"), "duration"),
    (("pulse", "tp_max_s"), "duration"),
    (("pulses", "vs_isolation", "td_fixed_s"), "duration"),
    (("pulses", "vs_isolation", "R_fixed_m"), "R"),
    (("pulses", "lambda"), "lambda"),
    (("search", "amp_max_g"), "amp"),
    (("pulses", "amp_max_g"), "amp"),
)
#: what the axes of a design grid are
DESIGN_AXES = {"Tb_s": "period", "xi_b": "damping", "mu_b": "mu_b", "R_b_m": "R_b_m"}


def refuse(where: str, kind: str, key: str, v: float) -> None:
    """:func:`_check_value`; its :class:`ParameterError` as a :class:`ConfigError` naming ``where``."""
    try:
        _check_value(kind, key, v)
    except ParameterError as exc:
        raise ConfigError(f"configuration: {where}: {exc}") from None


def _check_value(kind: str, key: str, v: float) -> None:
    """One value of the configuration within the bounds of :mod:`isorock.plausibility`, by what it is:
    ``lambda`` (a slenderness, > 0), ``R`` (a block's half-diagonal, m), ``amp`` (a largest
    amplitude, g), ``period`` (an isolator's, s), ``damping``, ``rho``, ``mu_b``, ``R_b_m``,
    ``duration`` (a pulse's td or Tp, s) or ``omega`` (a pulse's rad/s)."""
    if kind in ("R_b_m", "omega") and not v > 0:
        raise ParameterError(f"{key} {v:g} must be > 0")
    if kind == "lambda":
        check_block_size(lam=v, names={"lambda": key})
    elif kind == "R":
        check_block_size(R_m=v, names={"R_m": key})
    elif kind == "amp":
        check_amplitude(v, key)
    elif kind == "period":
        check_isolator("linear", Tb_s=v, names={"Tb_s": key})
    elif kind == "damping":
        check_isolator("linear", xi_b=v, names={"xi_b": key})
    elif kind == "rho":
        check_isolator("linear", rho=v, names={"rho": key})
    elif kind == "mu_b":
        check_isolator("fp", v, names={"mu_b": key})
    elif kind == "R_b_m":
        check_isolator("fp", R_b_m=v, names={"R_b_m": key})
    elif kind == "duration":
        check_duration(v, key)
    elif kind == "omega" and not PERIOD_MIN_S <= math.pi / v <= PERIOD_MAX_S:
        raise ParameterError(
            f"{key} {v:g} is outside {math.pi / PERIOD_MAX_S:.3g} to {math.pi / PERIOD_MIN_S:.3g} rad/s: a "
            f"pulse's td = pi/omega_p must be within {PERIOD_MIN_S:g} to {PERIOD_MAX_S:g} s (here "
            f"{math.pi / v:.3g} s)"
        )


def check_grid_values(where: str, spec: Sequence[float] | Mapping, kind: str) -> None:
    """A grid entry's log spacing and its values within their bounds (its ends: a ``{start, stop,
    num}`` grid is monotone between them)."""
    if isinstance(spec, Mapping) and spec.get("spacing") == "log":
        if not (float(spec["start"]) > 0 and float(spec["stop"]) > 0):
            raise ConfigError(
                f"configuration: {where}: a log grid needs start and stop > 0, got {spec['start']} to "
                f"{spec['stop']}"
            )
    key = where.rsplit(".", 1)[-1]
    from isorock.control.grids import grid_ends

    for v in grid_ends(spec):
        refuse(where, kind, key, v)


def _get(cfg: Mapping, path: Sequence[str]) -> Any:
    node: Any = cfg
    for k in path:
        if not isinstance(node, Mapping) or k not in node:
            return None
        node = node[k]
    return node


def check_values(cfg: Mapping) -> None:
    """Every grid and value of the studies within the bounds of :mod:`isorock.plausibility` (the
    command line's): block sizes > 0, isolator periods and pulse durations 0.05 to 20 s, damping,
    mass ratios; a pulse period range low < high."""
    for path, kind in _GRIDS:
        spec = _get(cfg, path)
        if spec is not None:
            check_grid_values(".".join(path), spec, kind)
    for path, kind in _SCALARS:
        v = _get(cfg, path)
        if v is not None:
            refuse(".".join(path), kind, path[-1], v)
    for k, e in enumerate(_get(cfg, ("pulses", "maps", "excitations")) or []):
        refuse(f"pulses.maps.excitations.{k}", "duration", "td_s", e["td_s"])
    p = cfg.get("pulse") or {}
    if not p.get("tp_min_s", 0) < p.get("tp_max_s", math.inf):
        raise ConfigError(
            f"configuration: pulse: tp_min_s {p['tp_min_s']:g} must be below tp_max_s {p['tp_max_s']:g}"
        )
