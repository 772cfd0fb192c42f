"""Structured provenance of record processing: one :class:`AppliedStep` per step applied.

Every processing step (:mod:`isorock.processing.steps`) calls :func:`record_step` once: it appends the
step, as an :class:`AppliedStep` (``step``, ``parameters``, ``note``), to ``trace.stats.processing_steps``
and its human-readable line (``isorock <version>: name(param=value, ...): note``) to ObsPy's history
``trace.stats.processing``. Readers take the structured steps (:func:`applied_steps`, the JSON of
:func:`steps_to_json`); the lines are for people. :func:`isorock.processing.legacy.parse_history` turns old
lines back
into steps, for results written before the steps were kept (store layout 2).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from obspy import Trace

from isorock.version import __version__

__all__ = [
    "AppliedStep",
    "record_step",
    "applied_steps",
    "steps_to_json",
    "steps_from_json",
]


def _plain(value: Any) -> Any:
    """A parameter value as a plain Python value (numpy scalars -> int, float, bool)."""
    return value.item() if isinstance(value, np.generic) else value


def _fmt(value: object) -> str:
    """A parameter value as written in a history line (floats to 6 significant digits)."""
    if isinstance(value, float):
        return f"{value:.6g}"
    return repr(value)


@dataclass(frozen=True)
class AppliedStep:
    """One processing step as applied to a record.

    Attributes
    ----------
    step : str
        Name of the step (a key of :data:`isorock.processing.STEPS`).
    parameters : dict
        Keyword parameters as applied, in the units of the step's documentation (s, Hz, g, ...);
        a value the step changed is the value used (``bandpass_filter``'s ``freqmax`` after the
        Nyquist cap [Hz]).
    note : str
        What the step did, in words with numbers ("" when nothing to add).
    """

    step: str
    parameters: dict[str, Any] = field(default_factory=dict)
    note: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "parameters", {str(k): _plain(v) for k, v in self.parameters.items()})

    def line(self, version: str = __version__) -> str:
        """The human-readable history line: ``isorock <version>: name(param=value, ...)[: note]``."""
        args = ", ".join(f"{k}={_fmt(v)}" for k, v in self.parameters.items())
        text = f"isorock {version}: {self.step}({args})"
        return f"{text}: {self.note}" if self.note else text

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form: ``{"step": ..., "parameters": {...}, "note": ...}``."""
        return {"step": self.step, "parameters": dict(self.parameters), "note": self.note}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> AppliedStep:
        """The step of :meth:`to_dict`."""
        return cls(str(d["step"]), dict(d.get("parameters") or {}), str(d.get("note") or ""))


def record_step(
    tr: Trace, step: str, parameters: Mapping[str, object], note: str = "", n_before: int | None = None
) -> AppliedStep:
    """Record a step applied to ``tr``: the structured step and its history line.

    Parameters
    ----------
    tr : obspy.Trace
        The record; ``stats.processing_steps`` (list of :class:`AppliedStep`) and ``stats.processing``
        (ObsPy's history, list of str) are extended.
    step : str
        Name of the step.
    parameters : mapping
        Parameters as applied (units of the step).
    note : str
        What the step did.
    n_before : int, optional
        Length of ``stats.processing`` before the step: the lines ObsPy added after it (its own history
        of the methods the step called) are replaced by the step's line.

    Returns
    -------
    AppliedStep
        The step recorded.
    """
    applied = AppliedStep(step, dict(parameters), note)
    hist = list(tr.stats.get("processing", []))
    if n_before is not None:
        hist = hist[:n_before]
    hist.append(applied.line())
    tr.stats.processing = hist
    tr.stats.processing_steps = [*applied_steps(tr), applied]
    return applied


def applied_steps(tr: Trace) -> list[AppliedStep]:
    """The processing steps applied to ``tr``, in order (empty for a raw record)."""
    return list(tr.stats.get("processing_steps", []))


def steps_to_json(steps: Iterable[AppliedStep]) -> str:
    """The JSON text of the steps: a list of ``{"step", "parameters", "note"}`` objects."""
    return json.dumps([s.to_dict() for s in steps])


def steps_from_json(text: str) -> list[AppliedStep]:
    """The steps of :func:`steps_to_json`."""
    return [AppliedStep.from_dict(d) for d in json.loads(text)]
