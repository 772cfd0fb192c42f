"""How every record is scaled to a stripe: the intensity measure and its component definition.

The assessment's intensity measure ``assessment.imt`` is one of OpenQuake's strings (``PGA``,
``PGV``, ``SA(T)``: :mod:`isorock.processing.imt`); the stripes, the design and the MCE levels are in
it (g, or cm/s for PGV). The level of a stripe is a value of that measure **of a component
definition**:

* with a hazard curve, the curve's (``RotD50`` unless the file or the key says otherwise): each record
  is scaled so that the RotD50 (or RotD100) of its two processed horizontals equals the level, and
  the component the engine analyses (strike-normal, a pair's rotation, a single file) and the
  vertical are multiplied by that same factor. The two RotD values of every record are computed once,
  when the record is processed, and stored (``/records`` columns ``rotd50`` and ``rotd100``);
* ``analysed``: the measure of the analysed component itself equals the level (the default without a
  hazard curve, as before; with a hazard curve only when ``assessment.component: analysed`` says so,
  which the output then states as an assumption: a pulse-like strike-normal component is stronger
  than the RotD50 of its pair, so the object sees less than the hazard's level at a given stripe).

A record with one horizontal only has no RotD: it is refused for a RotD scaling with one line naming
it and the ways out. A spectral measure at a period longer than the record can support (its
duration, or ``1 / luf_hz``, the lowest usable frequency PEER states for it) is refused for that
record the same way.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from isorock.errors import ConfigError, IsorockError, ParameterError
from isorock.physics.excitation import GroundMotion
from isorock.processing.imt import IMT, component_definition, imt_value, parse_imt

__all__ = ["Scaling", "scaling_from_config", "record_basis", "record_rotd"]

#: each component definition in words, for the output
_DEFINED = {
    "RotD50": "RotD50 (the median over all horizontal orientations of the peak of the two components)",
    "RotD100": "RotD100 (the largest over all horizontal orientations of the peak of the two components)",
    "analysed": "the component analysed",
}


@dataclass(frozen=True)
class Scaling:
    """The stripes' measure and the component definition the records are scaled on.

    Parameters
    ----------
    imt : str
        Canonical intensity measure type (``PGA``, ``PGV``, ``SA(1.0)``).
    component : {"RotD50", "RotD100", "analysed"}
        Component definition of the levels.
    basis : str
        Why this component, in words (the hazard curve's definition, the key, the default).
    """

    imt: str = "PGA"
    component: str = "analysed"
    basis: str = "without a hazard curve, the analysed component (assessment.component not given)"

    @property
    def measure(self) -> IMT:
        return parse_imt(self.imt)

    @property
    def unit(self) -> str:
        """``g`` or ``cm/s``."""
        return self.measure.unit

    @property
    def label(self) -> str:
        """'SA(1.0) RotD50', 'PGA of the analysed component'."""
        if self.component == "analysed":
            return f"{self.imt} of the analysed component"
        return f"{self.imt} {self.component}"

    @property
    def axis(self) -> str:
        """An axis label: 'SA(1.0) RotD50 [g]'."""
        short = f"{self.imt} (analysed component)" if self.component == "analysed" else self.label
        return f"{short} [{self.unit}]"

    def to_dict(self) -> dict[str, str]:
        return {"imt": self.imt, "component": self.component, "basis": self.basis, "unit": self.unit}


def scaling_from_config(a: Mapping[str, Any], hazard: Any = None) -> Scaling:
    """The scaling of a validated ``assessment`` section and its hazard curve (None: no curve).

    ``assessment.imt`` (default ``PGA``; the former ``measure: pga`` reads as ``PGA``) must be the
    curve's measure; ``assessment.component`` (default: the curve's component definition, else
    ``analysed``) may only be the curve's definition or ``analysed``.

    Raises
    ------
    ConfigError
        A measure or component not recognised, or not the hazard curve's (one line naming both).
    """
    try:
        raw = a.get("imt")
        if raw is None:
            raw = str(a.get("measure") or "PGA")
        imt = str(parse_imt(raw, "assessment.imt"))
        comp = a.get("component")
        comp = None if comp is None else component_definition(comp, "assessment.component")
    except ParameterError as exc:
        raise ConfigError(f"configuration: {exc}") from None
    if hazard is None:
        if comp is None:
            return Scaling(imt, "analysed")
        return Scaling(imt, comp, "assessment.component")
    h_imt = str(getattr(hazard, "imt", "PGA"))
    h_comp = str(getattr(hazard, "component_definition", "RotD50"))
    where = hazard.describe() if hasattr(hazard, "describe") else str(getattr(hazard, "source", ""))
    how = (
        "as assessment.hazard.component_definition states"
        if getattr(hazard, "component_stated", False)
        else "assumed: the file does not state it; assessment.hazard.component_definition sets it"
    )
    if h_imt != imt:
        raise ConfigError(
            f"configuration: assessment.imt is {imt} but the hazard curve ({where}) is in {h_imt}: "
            "the stripes and the curve must be in one measure"
        )
    if comp is None:
        return Scaling(
            imt, h_comp, f"the component definition of the hazard curve, {_DEFINED[h_comp]}, {how} ({where})"
        )
    if comp == "analysed":
        return Scaling(
            imt,
            "analysed",
            f"assessment.component: analysed (an assumption: the hazard curve is {h_comp}, {how}; the "
            "records are scaled on the component analysed)",
        )
    if comp != h_comp:
        raise ConfigError(
            f"configuration: assessment.component is {comp} but the hazard curve ({where}) is {h_comp} "
            f"({how}): give {h_comp} or analysed, or state the curve's definition in "
            "assessment.hazard.component_definition"
        )
    return Scaling(imt, comp, f"assessment.component, the hazard curve's, {_DEFINED[comp]} ({where})")


def record_rotd(attrs: Mapping[str, Any]) -> dict[str, dict[str, float]]:
    """``{"rotd50": {imt: value}, "rotd100": {...}}`` of a record's stored attributes (empty mappings
    for a record with one horizontal)."""
    out: dict[str, dict[str, float]] = {}
    for key in ("rotd50", "rotd100"):
        try:
            out[key] = {str(k): float(v) for k, v in json.loads(str(attrs.get(key) or "{}")).items()}
        except (ValueError, AttributeError):
            out[key] = {}
    return out


def _check_period(rid: str, imt: IMT, gm: GroundMotion, attrs: Mapping[str, Any]) -> None:
    if imt.period_s is None:
        return
    T = float(imt.period_s)
    luf = attrs.get("luf_hz")
    try:
        luf = float(luf) if luf is not None else math.nan
    except (TypeError, ValueError):
        luf = math.nan
    if math.isfinite(luf) and luf > 0 and T > 1.0 / luf * (1.0 + 1e-9):
        raise IsorockError(
            f"record {rid}: {imt} is beyond its usable band (lowest usable frequency {luf:g} Hz, periods up "
            f"to {1.0 / luf:.3g} s): leave the record out (records.select) or choose a shorter period"
        )
    if T > gm.duration or T < 2.0 * gm.dt:
        raise IsorockError(
            f"record {rid}: {imt} is outside the periods it supports ({2.0 * gm.dt:g} s to its duration "
            f"{gm.duration:g} s): leave the record out (records.select) or choose another period"
        )


def record_basis(rid: str, gm: GroundMotion, attrs: Mapping[str, Any], scaling: Scaling) -> float:
    """The record's value of the stripes' measure, as it is, on the scaling's component definition.

    Parameters
    ----------
    rid : str
        The record's id (for messages).
    gm : GroundMotion
        Its analysed component, processed [m/s^2].
    attrs : mapping
        Its stored attributes (``rotd50``, ``rotd100``, ``luf_hz``).
    scaling : Scaling

    Returns
    -------
    float
        In :attr:`Scaling.unit`; the scale of a level ``x`` is ``x / basis``.

    Raises
    ------
    IsorockError
        One horizontal only for a RotD scaling, a period the record does not support, a zero measure.
    """
    imt = scaling.measure
    _check_period(rid, imt, gm, attrs)
    if scaling.component == "analysed":
        value = imt_value(gm, imt)
    else:
        rot = record_rotd(attrs)[scaling.component.lower()]
        if not rot:
            raise IsorockError(
                f"record {rid}: one horizontal only, so no {scaling.component}: add its second horizontal "
                "(records add --id), leave it out (records.select), or set assessment.component: analysed "
                "(stated as an assumption)"
            )
        if scaling.imt not in rot:
            raise IsorockError(
                f"record {rid}: its {scaling.component} of {scaling.imt} was not computed (stored: "
                f"{', '.join(rot)}); run again so that the record is processed for this measure"
            )
        value = rot[scaling.imt]
    if not (math.isfinite(value) and value > 0.0):
        raise IsorockError(f"record {rid}: its {scaling.label} is {value!r}: it cannot be scaled")
    return float(value)
