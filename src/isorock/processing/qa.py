"""QA marks of a processed record (the gmprocess pattern): checks mark a trace failed with a reason,
they never raise; :func:`qa_passed` and :func:`qa_reasons` read the marks in ``trace.stats.qa``."""

from __future__ import annotations

from collections.abc import Mapping

from obspy import Trace
from obspy.core.util import AttribDict

__all__ = ["fail", "qa_passed", "qa_reasons", "ensure_qa"]


def ensure_qa(tr: Trace) -> AttribDict:
    """The QA marks of ``tr``, created (passed, no reasons) when absent."""
    if "qa" not in tr.stats or not isinstance(tr.stats.qa, Mapping):
        tr.stats.qa = AttribDict({"passed": True, "reasons": []})
    return tr.stats.qa


def fail(tr: Trace, step: str, reason: str) -> None:
    """Mark a trace as failed by a QA check (it is not removed, nothing is raised).

    Parameters
    ----------
    tr : obspy.Trace
        The record.
    step : str
        Name of the check that failed.
    reason : str
        Why, in words with numbers.
    """
    qa = ensure_qa(tr)
    qa.passed = False
    qa.reasons = [*qa.reasons, f"{step}: {reason}"]


def qa_passed(tr: Trace) -> bool:
    """Whether no QA check has marked ``tr`` failed."""
    qa = tr.stats.get("qa")
    return True if qa is None else bool(qa.get("passed", True))


def qa_reasons(tr: Trace) -> list[str]:
    """Reasons given by the QA checks that failed ``tr`` (empty when it passed)."""
    qa = tr.stats.get("qa")
    return [] if qa is None else list(qa.get("reasons", []))
