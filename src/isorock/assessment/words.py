"""What an assessment says in words: the verdict first, then a short table, then the details.

The same sentences and the same table are printed by ``isorock assess`` and open the report's
Assessment page (the text and the HTML say the same). Per object and design level:

1. the **verdict** (:func:`verdict_sentence`): ``isolate`` ("Isolate statue: a linear isolator Tb 1.5 s,
   xi 0.5 gives failure at 0.3 g 1.5 % (0.032 % to 3.7 %) against 4.6 % (0.57 % to 9.8 %) on the fixed
   base, lower in 98 % of 1000 resamples of 18 records.", and the lowest estimate beside it when the
   simpler isolator is recommended), ``fixed_base`` ("Keep statue on a fixed base: ...") or
   ``inconclusive`` ("No decision for statue at 0.3 g: ...", and what would decide it), with the
   numbers that carry it;
2. where the design search stopped (:func:`grid_sentence`): extended, or at a bound of the search;
3. the short table (:func:`short_table`, :func:`text_table`: at most 100 columns): the fixed base,
   the configured cases and the best isolators of the grid, each with its estimate and interval, its
   paired difference from the fixed base, the share of resamples in which it is better, the
   displacement at the MCE with its interval, and the records beyond the capacity there.

Then the details (the report and the JSON): the probabilities of every case with what was observed,
the fragilities, the site's hazard with both tails of the risk integral, the intensity measures with
intervals, the displacement check and its rule, the runs outside the model.

The numbers are printed by :mod:`~isorock.assessment.formats`, the tables built by
:mod:`~isorock.assessment.tables`.
"""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Mapping, Sequence
from typing import Any

from isorock.assessment.case import MIN_RECORDS
from isorock.assessment.formats import (
    TABLE_WIDTH,
    _by_rate,
    _interval,
    _pct0,
    _short,
    bound,
    describe,
    finite,
    pct,
    sci,
    share,
)
from isorock.assessment.tables import LEGEND, text_table

__all__ = ["verdict_sentence", "mce_sentence", "grid_sentence", "conclusions", "text_summary"]


def _metric(
    r: Mapping[str, Any], design: Mapping[str, Any], basis: str | None = None, lead: bool = True
) -> str:
    """A candidate's metric with its interval, in words, on ``basis`` (``fitted``, ``observed``; default
    its own: fitted where its failure fragility is estimable); ``lead``: with the words that say what it
    is ("a probability of failure at 0.3 g (PGA) of ..."), else the number alone ("4.6 % (...)")."""
    fitted = bool(r.get("fitted")) if basis is None else (basis == "fitted" and bool(r.get("fitted")))
    if _by_rate(design):
        if fitted or not r.get("fitted"):
            ci = r.get("estimate_ci95")
            how = "" if fitted else " from its stripe fractions"
            return (
                f"{sci(r['estimate'])} failures per year{how}"
                + (f" ({_interval(ci, sci)})" if ci else "")
                + _in_50_years(r["estimate"])
            )
        est = r.get("estimate_observed")
        return f"{sci(est)} failures per year from its stripe fractions" + _in_50_years(est)
    x = design["design_g"]
    if fitted:
        ci = r.get("estimate_ci95")
        head = f"a probability of failure at {_lv(x, design)} of " if lead else ""
        what = "95 % interval " if lead else ""
        z, n = r.get("n_failure_observed"), r.get("n_failure_counted")
        seen = f"; {z} of {n} records observed" if n else ""
        tail = " (both a fitted tail: no failure observed there)" if n and not z and lead else ""
        return (
            head
            + ("fitted " if not lead and n and not z else "")
            + pct(r["estimate"])
            + (f" ({what}{_interval(ci, bound)}{seen})" if ci else (f" ({seen[2:]})" if seen else ""))
            + tail
        )
    z, n = r.get("n_failure_observed"), r.get("n_failure_counted")
    head = f"failure at {_lv(x, design)} in " if lead else ""
    if not n:
        return f"failure at {_lv(x, design)}: not estimable (no run counted)"
    if z == 0:
        return head + f"0 of {n} records (at most {pct(r.get('p_failure_upper95'))}, one-sided 95 %)"
    ci = r.get("p_failure_observed_ci95")
    return head + f"{z} of {n} records ({pct(z / n)}; exact 95 % interval {_interval(ci, _pct0)})"


def _lv(x: float, design: Mapping[str, Any]) -> str:
    """A level with its unit and measure: "0.3 g PGA" (of the analysed component), "0.21 g SA(1.0) RotD50"."""
    return f"{x:g} {design.get('unit', 'g')} {design.get('measure', 'PGA')}"


def _in_50_years(rate: Any) -> str:
    """The 50-year probability beside an annual frequency: ", 0.35 % in 50 years"."""
    v = finite(rate)
    return "" if v is None else f", {pct(-math.expm1(-50.0 * v))} in 50 years"


def _records(design: Mapping[str, Any], vs: Mapping[str, Any] | None = None) -> str:
    n = (vs or {}).get("n") or design["n_boot"]
    return f"{n} resamples of {design['n_records']} records"


def _basis_note(a: Mapping[str, Any], b: Mapping[str, Any], vs: Mapping[str, Any] | None) -> str:
    """Said when two bases are compared on their observed fractions because one has no fitted fragility."""
    if (vs or {}).get("basis") == "observed" and (a.get("fitted") or b.get("fitted")):
        return " (compared on the records observed, as one of the two has no fitted fragility)"
    return ""


def _target(design: Mapping[str, Any]) -> Mapping[str, Any]:
    return design.get("target") or {
        "kind": "p_mce",
        "value": 0.1,
        "words": "P(failure) at the MCE at most 10 %",
    }


def _measure(design: Mapping[str, Any]) -> str:
    """What the target measures: "P(failure) at the MCE (0.45 g)", "the annual frequency of failure"."""
    kind = _target(design)["kind"]
    if kind == "rate_per_yr":
        return "the annual frequency of failure"
    if kind == "p_50yr":
        return "P(failure) in 50 years"
    b = str(design.get("mce_basis") or "")
    at = f", {b.removesuffix(' (the default MCE)')}" if "-year" in b else ""
    return f"P(failure) at the MCE ({_lv(finite(design.get('mce_g')) or 0, design)}{at})"


def _goal(design: Mapping[str, Any]) -> str:
    """The target in a few words: "the target of at most 10 %"."""
    t = _target(design)
    if t["kind"] == "rate_per_yr":
        return f"the target of at most {sci(t['value'])} per year"
    return f"the target of at most {100 * t['value']:.3g} %"


def _safety(r: Mapping[str, Any], design: Mapping[str, Any]) -> str:
    """A base's value in the target's measure with its interval and what was observed: "33 % (95 %
    interval 18 % to 52 %; 12 of 17 records fail there)"."""
    t = _target(design)
    est, ci = r.get("target_estimate"), r.get("target_estimate_ci95")
    if t["kind"] == "rate_per_yr":
        return f"{sci(est)} per year" + (f" (95 % interval {_interval(ci, sci)})" if ci else "")
    if t["kind"] == "p_50yr":
        return pct(est) + (f" (95 % interval {_interval(ci, _pct0)})" if ci else "")
    z, n = r.get("n_failure_mce_observed"), r.get("n_failure_mce_counted")
    seen = f"{z} of {n} records fail there" if n else "no run counted there"
    total = design.get("n_records")
    if total and (n or 0) < total:
        seen += (
            f"; {total - (n or 0)} of {total} records left out there: outside the model (the object would "
            "slide or jump)"
        )
    if est is None:
        return f"not estimable ({seen})"
    if str(r.get("target_basis", "")).startswith("observed"):
        return f"{_pct0(est)} ({seen}; exact 95 % interval {_interval(ci, _pct0)})"
    return f"{pct(est)} (95 % interval {_interval(ci, bound)}; {seen})"


def _adequacy_words(r: Mapping[str, Any]) -> str:
    a = r.get("adequate")
    if a is True:
        return "meets the target"
    if a is False:
        return "clearly misses the target" if not r.get("adequacy_note") else f"is {r['adequacy_note']}"
    return "is not shown to meet the target"


def _adequacy_with(r: Mapping[str, Any], design: Mapping[str, Any]) -> str:
    """ "meets the target with 7 % (...)", "is beyond the displacement capacity at the MCE (16 % ...)"."""
    a, s = r.get("adequate"), _safety(r, design)
    if a is False and r.get("adequacy_note"):
        return f"is {r['adequacy_note']} (it has {s})"
    if a is True:
        return f"meets the target with {s}"
    return f"has {s}, " + ("clearly above the target" if a is False else "not shown to meet the target")


def _lowest(design: Mapping[str, Any]) -> str:
    """The isolator shown beside the fixed base: "the one of lowest estimate" among several, "the only
    isolator assessed" when there is one (issue 35, item 8)."""
    n = sum(1 for c in design.get("candidates") or [] if c.get("isolation") != "none")
    return "the only isolator assessed" if n == 1 else "the isolator of lowest estimate"


def _test_words(r: Mapping[str, Any], design: Mapping[str, Any]) -> str:
    """How "fails less than the fixed base" was shown: the familywise p-value, or exact bounds."""
    vs = r.get("vs_floor") or {}
    if vs.get("decided_by") == "exact bounds":
        shown = "and they separate" if r.get("beats_floor") else "and they overlap"
        if design["n_records"] < MIN_RECORDS:
            return (
                f"with fewer than {MIN_RECORDS} records only exact 95 % bounds can show a difference, {shown}"
            )
        if vs.get("p_single") is None and vs.get("n"):
            return f"every resample gives the same difference, so exact 95 % bounds decide, {shown}"
        where = "at any stripe" if _by_rate(design) else f"at {_lv(design['design_g'], design)}"
        return (
            f"no failure is observed {where} on either base, so only exact 95 % bounds can show a "
            f"difference, {shown}"
        )
    pa, m = finite(vs.get("p_adjusted")), vs.get("n_family") or design.get("n_family") or 0
    if pa is None:
        return "no test possible (no spread over the resamples)"
    least = ", the least its resamples can show" if pa <= 1.5 / ((vs.get("n") or 1) + 1) else ""
    return f"familywise p = {pa:.2g}{least}, over the {m} eligible isolator{'s' if m != 1 else ''} searched"


def _lower_in(vs: Mapping[str, Any]) -> str:
    nb, n = vs.get("n_better"), vs.get("n")
    if nb is None or not n:
        return f"lower in {share(vs.get('p_better'))} of the resamples"
    return f"lower in {nb} of {n} resamples"


def _at(design: Mapping[str, Any]) -> str:
    """Where the metric looks: "at 0.3 g" (a design level), or over the hazard curve."""
    if _by_rate(design):
        return " over the whole hazard curve"
    return f" at {_lv(design['design_g'], design)}"


def _vs(r: Mapping[str, Any], floor: Mapping[str, Any], design: Mapping[str, Any]) -> str:
    """An isolator against the fixed base, on the same footing: "1.4 % (...) against 4.6 % (...) on
    the fixed base at 0.3 g, lower in 976 of 1000 resamples of 18 records (familywise p = ...)"."""
    vs = r.get("vs_floor") or {}
    basis = vs.get("basis")
    return (
        f"{_metric(r, design, basis, lead=False)} against {_metric(floor, design, basis, lead=False)} on the "
        f"fixed base{_at(design)}{_basis_note(r, floor, vs)}, {_lower_in(vs)} of {design['n_records']} "
        f"records ({_test_words(r, design)})"
    )


def verdict_sentence(name: str, design: Mapping[str, Any], capacity_m: float | None = None) -> str:
    """The answer for one object and design level: first whether the object is safe, and what to do;
    then the numbers that carry it (see the module docstring)."""
    v = design["verdict"]
    floor, best, rec = design.get("floor"), design.get("best"), design.get("recommended")
    if floor is None:
        return (
            f"No decision for {name}{_at(design)}: no fixed-base case was assessed, so no advice can be "
            "compared with doing nothing; add the case {name: none, kind: none}."
        )
    m, goal = _measure(design), _goal(design)
    if v == "isolate" and rec is not None:
        on_floor = {
            True: f"on the fixed base it is safe too ({_safety(floor, design)}) but fails more",
            False: f"on the fixed base it is not safe ({_safety(floor, design)})",
            None: f"on the fixed base that is not shown ({_safety(floor, design)})",
        }[floor.get("adequate")]
        txt = (
            f"{name} is safe on {describe(rec)}: its {m} is {_safety(rec, design)}, within {goal}; "
            f"{on_floor}. Isolate it: on the isolator it has {_vs(rec, floor, design)}."
        )
        if best is not None and best["name"] != rec["name"]:
            txt += f" The lowest estimate, {_metric(best, design, lead=False)} with {describe(best)}, is " + (
                f"shown equivalent within {_margin(design)} (two one-sided tests), and the recommended "
                f"isolator has the shorter period ({rec['period_s']:.3g} s against {best['period_s']:.3g} s)."
                if best["name"] in design.get("equivalent", [])
                else "not recommended: " + _why_not(best, design)
            )
        return txt
    if v == "fixed_base":
        txt = f"{name} is safe on a fixed base: its {m} is {_safety(floor, design)}, within {goal}."
        txt += " Keep it there:"
        if best is None:
            cap = f" of {capacity_m:g} m" if capacity_m else ""
            return txt + (
                f" no isolator assessed is within the displacement capacity{cap} at the MCE"
                + (f" ({_lv(design['mce_g'], design)})" if design.get("mce_g") else "")
                + "."
            )
        return txt + (
            f" no isolator that meets the target is shown to fail less; {_lowest(design)}, "
            f"{describe(best)}, has {_vs(best, floor, design)}."
        )
    if v == "restrain":
        c = design.get("closest")
        txt = (
            f"{name} is not safe on any base assessed: on each, even the lower end of the 95 % interval of "
            f"its {m} is above {goal}, or the isolator is beyond its capacity. Restrain it, relocate it or "
            "redesign its mounting."
        )
        if c is not None:
            est, ci = finite(c.get("target_estimate")), c.get("target_estimate_ci95")
            gap = "" if est is None else f", {_gap(est, _target(design))} above the target"
            lo = (
                f"; the lower end of its interval is {_pct0(ci[0])}"
                if ci and _target(design)["kind"] != "rate_per_yr"
                else ""
            )
            txt += (
                f" The closest is {'the fixed base' if c['isolation'] == 'none' else describe(c)}: "
                f"{_safety(c, design)}{gap}{lo}"
                + (f" (and it is {c['adequacy_note']})" if c.get("adequacy_note") else "")
                + "."
            )
        return txt
    # inconclusive
    vs = (best or {}).get("vs_floor") or {}
    fl = {
        True: f"within {goal}",
        False: f"clearly above {goal}",
        None: _few_records(floor, design)
        or (
            "so whether it meets the target cannot be said"
            if finite(floor.get("target_estimate")) is None
            else f"above {goal}, though its interval reaches below it"
        ),
    }[floor.get("adequate")]
    head = (
        f"Whether {name} is safe is not shown, so do not treat it as safe yet: on the fixed base its {m} is "
        f"{_safety(floor, design)}, {fl}"
    )
    if best is None or not vs.get("n"):
        return f"{head}; {design.get('reason', '')}. {_to_decide(design)}"
    worse = (finite(vs.get("difference")) or 0.0) > 0
    txt = (
        f"{head}. {_lowest(design).capitalize()}, {describe(best)}, {_adequacy_with(best, design)}, "
        + ("but is" if best.get("adequate") is True else "and is")
        + " not shown to fail less than the fixed base: it has "
        f"{_vs(best, floor, design)}" + (", more than the fixed base" if worse else "") + "."
    )
    c = design.get("closest")
    if c is not None and c["isolation"] != "none" and c["name"] != best["name"]:
        txt += f" The isolator closest to the target, {describe(c)}, {_adequacy_with(c, design)}."
    return txt + " " + _to_decide(design)


def _margin(design: Mapping[str, Any]) -> str:
    m = finite(design.get("equivalence_margin"))
    frac = finite(design.get("equivalence_margin_fraction"))
    if m is None:
        return "the equivalence margin"
    shown = sci(m) + " per year" if _by_rate(design) else f"{100 * m:.2g} percentage points"
    return shown + (f" ({frac:g} of the fixed base's estimate)" if frac else "")


def _gap(est: float, t: Mapping[str, Any]) -> str:
    if t["kind"] == "rate_per_yr":
        return f"{sci(est - t['value'])} per year"
    return f"{100 * (est - t['value']):.2g} percentage points"


def _why_not(r: Mapping[str, Any], design: Mapping[str, Any]) -> str:
    """Why a base of lower estimate is not the recommendation."""
    if r.get("adequate") is not True:
        return f"it {_adequacy_words(r)} ({_safety(r, design)})."
    if not r.get("beats_floor"):
        return f"it is not shown to fail less than the fixed base ({_test_words(r, design)})."
    return "a simpler isolator is shown equivalent."


def _mce_short(design: Mapping[str, Any]) -> str:
    b = str(design.get("mce_basis") or "")
    if "-year" in b:
        return f" ({b.split(' of ')[0].removeprefix('the ')})"
    return ""


def mce_sentence(
    name: str, design: Mapping[str, Any], capacity_m: float | None = None, sliding: bool = False
) -> str:
    """What the answer's base (the recommended isolator; with no decision, the isolator of lowest
    estimate) and the fixed base do at the MCE level: the isolator's displacement, times gamma_x, by the
    codes' statistic and by the stated fractile against the capacity, and the records that overturn the
    object there (on each; for a ``sliding`` object, that slide it beyond its allowance)."""
    key, verb = (
        ("n_mce_slides_beyond", "slides beyond its allowance") if sliding else ("n_mce_overturn", "overturns")
    )
    floor = design.get("floor")
    rec = design.get("recommended")
    base = rec if rec is not None else (design.get("closest") or design.get("best"))
    if floor is None or not design.get("mce_g"):
        return ""
    parts = []
    if base is not None and base["isolation"] != "none" and finite(base.get("disp_mce_m")) is not None:
        who = "the recommended isolator" if base is rec else f"the isolator {_short(base)}"
        ci = base.get("disp_mce_ci95_m")
        n = base.get("n_mce_records")
        stat = "mean" if "mean" in str(base.get("disp_mce_statistic")) else "maximum"
        gx = finite(base.get("gamma_x")) or 1.0
        q = finite(base.get("disp_fractile"))
        fr = finite(base.get("disp_mce_fractile_m"))
        txt = (
            f"{who} moves {base['disp_mce_m']:.2f} m ("
            + (f"{ci[0]:.2f} to {ci[1]:.2f} m; " if ci else "")
            + f"the {stat} of {n} records)"
        )
        if capacity_m:
            txt += (
                f", {gx:g} x {base['disp_mce_m']:.2f} = {gx * base['disp_mce_m']:.2f} m against the capacity "
                f"{capacity_m:g} m"
            )
            if q is not None and fr is not None:
                txt += f" ({100 * q:.0f}th percentile of the records x {gx:g}: {gx * fr:.2f} m)"
            if base.get("p_mce_exceed_capacity") is not None:
                txt += f", {base.get('n_mce_exceed_capacity')} of {n} records beyond it"
        parts.append(txt + f", and {name} {verb} on it in {base.get(key) or 0} of {n} records")
    if floor.get("n_mce_records"):
        out = floor.get("n_mce_outside_model")
        among = f" ({out} of them outside the model: it would slide or jump)" if out else ""
        parts.append(
            f"{name} {verb} on the fixed base in {floor.get(key) or 0} of {floor['n_mce_records']}{among}"
        )
    if not parts:
        return ""
    return f"At the MCE level, {_lv(design['mce_g'], design)}{_mce_short(design)}, " + "; ".join(parts) + "."


def _records_for_target(r: Mapping[str, Any], design: Mapping[str, Any]) -> int | None:
    """About how many records would show a base clearly above the target (the lower end of its
    interval above it), were its estimate what it is now: its interval narrows as one over the square
    root of the number of records. None where its adequacy is shown already, or it meets the target."""
    est, ci = finite(r.get("target_estimate")), r.get("target_estimate_ci95")
    t = _target(design)["value"]
    n = design["n_records"]
    if r.get("adequate") is not None or est is None or not ci or est <= t or ci[0] >= est:
        return None
    lo_half = est - ci[0]  # the lower half-width of the 95 % interval, 1.96 standard deviations
    return max(n + 1, math.ceil(n * (lo_half / (est - t)) ** 2 - 1e-9))


def _mce_direction(summary: Mapping[str, Any]) -> str:
    """With RotD50 levels and the default target: that the MCE is the curve's RotD50 level, not the
    maximum-direction MCE_R the target's source refers to, and by how much the two differ for these
    records (" " + a sentence, or "")."""
    m = summary.get("measure") or {}
    r = m.get("rotd100_over_rotd50")
    designs = summary.get("design") or []
    kinds = {str((d.get("target") or {}).get("kind", "p_mce")) for d in designs}
    if m.get("component") != "RotD50" or "p_mce" not in kinds:
        return ""
    ratio = f": {r[0]:.2f} to {r[2]:.2f} times RotD50 for these records (median {r[1]:.2f})" if r else ""
    return (
        " The MCE here is that RotD50 level; ASCE/SEI 7-16's MCE_R, to which the default target of P(failure)"
        f" at the MCE refers, is in the direction of maximum response (RotD100){ratio}"
    ) + "."


def _few_records(r: Mapping[str, Any], design: Mapping[str, Any]) -> str:
    """Why an estimate that meets the target does not show safety with fewer than MIN_RECORDS records
    ("" when that is not the case)."""
    est, ci, n = finite(r.get("target_estimate")), r.get("target_estimate_ci95"), design["n_records"]
    t = _target(design)
    if est is None or not ci or n >= MIN_RECORDS or est > t["value"]:
        return ""
    upper = sci(ci[1]) + " per year" if t["kind"] == "rate_per_yr" else _pct0(ci[1])
    return (
        f"within {_goal(design)} as an estimate, but from {n} record{'s' if n != 1 else ''} its exact "
        f"interval reaches {upper}: with fewer than {MIN_RECORDS} records safety is shown only by the "
        "upper end of that interval"
    )


def _records_without_failure(target: float) -> int | None:
    """The fewest records with no failure whose exact 95 % upper bound meets a probability ``target``
    (Clopper-Pearson: ``1 - 0.025^(1/n) <= target``)."""
    if not 0.0 < target < 1.0:
        return None
    return max(MIN_RECORDS, math.ceil(math.log(0.025) / math.log(1.0 - target) - 1e-12))


def _to_decide(design: Mapping[str, Any]) -> str:
    """What would decide an inconclusive answer: whether the fixed base meets the target, then the
    comparison (by the resamples, or by exact bounds where those decide)."""
    parts = []
    floor = design.get("floor") or {}
    best = design.get("best") or {}
    n, need = design["n_records"], design.get("records_to_decide")
    need_floor = _records_for_target(floor, design)
    if _few_records(floor, design):
        t = _target(design)
        m = _records_without_failure(t["value"]) if t["kind"] == "p_mce" else None
        parts.append(
            f"at least {m} records of this kind without a failure at the MCE to show the fixed base safe "
            "(the upper end of the exact 95 % interval of 0 of n within the target)"
            if m
            else f"at least {MIN_RECORDS} records of this kind"
        )
    if need_floor:
        parts.append(
            f"about {need_floor} records of this kind instead of {n} to show that the fixed base misses the "
            "target, were its estimate what it is now"
        )
    exact = (best.get("vs_floor") or {}).get("decided_by") == "exact bounds"
    if exact and n < MIN_RECORDS:
        parts.append(f"at least {MIN_RECORDS} records (with fewer, only exact bounds can decide)")
    elif exact:
        parts.append(
            "failures observed where the two are compared: "
            + (
                "the site's hazard curve, whose ranking weighs the stripes where failures are observed"
                if not _by_rate(design)
                else "stripes at higher levels"
            )
        )
    elif need:
        diff = finite((best.get("vs_floor") or {}).get("difference"))
        which = "the isolator" if (diff or 0.0) < 0 else "the fixed base"
        parts.append(
            f"about {need} records of this kind instead of {n} to show {which} better, were the difference "
            "what it is now (before the correction for the search)"
            if need <= 10 * n
            else f"more than {10 * n} records of this kind: the difference is small against its spread"
        )
    elif design.get("best") is not None:
        parts.append("more records of this kind would hardly separate them (their estimates are equal)")
    if not _by_rate(design) and not exact:
        parts.append(
            "the site's hazard curve (the ranking would then weigh every level, not only "
            f"{_lv(design['design_g'], design)})"
        )
    hit = design.get("grid", {}).get("bounds_reached") or []
    if hit:
        parts.append("isolators beyond the search's bounds (" + ", ".join(_bound(h) for h in hit) + ")")
    if not parts:
        parts.append(f"more records of this kind (at least {MIN_RECORDS}), analysed within the model")
    return "What would decide it: " + "; or ".join(parts) + "."


_AXIS_WORDS = {
    ("Tb_s", "high"): "longer periods", ("Tb_s", "low"): "shorter periods",
    ("xi_b", "high"): "more damping", ("xi_b", "low"): "less damping",
    ("mu_b", "high"): "more friction", ("mu_b", "low"): "less friction",
    ("R_b_m", "high"): "larger radii", ("R_b_m", "low"): "smaller radii",
}  # fmt: skip


_UNITS = {"Tb_s": " s", "R_b_m": " m", "xi_b": "", "mu_b": ""}


def _bound(h: Mapping[str, Any]) -> str:
    p = h["parameter"]
    return f"{p.split('_')[0]} {'<' if h['side'] == 'low' else '>'} {h['bound']:g}{_UNITS.get(p, '')}"


def grid_sentence(design: Mapping[str, Any]) -> str:
    """Where the design search stopped, in one sentence ("" when the grid settled as configured)."""
    g = design.get("grid") or {}
    if not design.get("has_grid", False) or not g:
        return ""
    edges = [tuple(e) for e in design.get("edges") or []]
    hit = g.get("bounds_reached") or []
    axes = g.get("axes") or {}
    span = ", ".join(
        f"{p.split('_')[0]} {min(v):g}-{max(v):g}{_UNITS.get(p, '')}" for p, v in axes.items() if v
    )
    out = []
    n = g.get("rounds", 0)
    if g.get("extended"):
        out.append(
            f"The best isolator lay on the design grid's edge, so the search extended the grid to {span} "
            f"({g.get('added', 0)} isolators in {n} round{'s' if n != 1 else ''})."
        )
    at_bound = [h for h in hit if (h["parameter"], h["side"]) in edges]
    if at_bound:
        what = " or ".join(f"{_AXIS_WORDS[(h['parameter'], h['side'])]} ({_bound(h)})" for h in at_bound)
        out.append(
            f"The best isolator lies at the search's bound: isolators with {what} were not searched "
            "(design_grid.bounds)."
        )
    elif edges and not g.get("extend", True):
        out.append(
            f"The best isolator lies on the grid's edge ({', '.join(f'{p} {s}' for p, s in edges)}); "
            "the grid "
            "was not extended (design_grid.extend: false)."
        )
    elif edges:
        out.append("The best isolator is still on the grid's edge after the most rounds the search makes.")
    elif g.get("extended"):
        out.append("It now lies inside the grid.")
    return " ".join(out)


def _p_words(d: Mapping[str, Any], damage: str) -> str:
    """P(damage) at a design level, with its interval and what was observed there."""
    z, n = d.get(f"n_{damage}_observed"), d.get(f"n_{damage}_counted")
    seen = f"observed {z} of {n}" if n else "not run at this level"
    if d.get(f"p_{damage}") is not None:
        return f"{pct(d[f'p_{damage}'])} ({_interval(d.get(f'p_{damage}_ci95'))}; {seen})"
    ub = d.get(f"p_{damage}_upper95")
    bound = f", at most {pct(ub)} at 95 % confidence" if ub is not None else ""
    return f"not estimable ({seen}{bound})"


def _frag_words(f: Mapping[str, Any], what: str, c: Mapping[str, Any] | None = None) -> str:
    if f.get("estimable"):
        ci, bci = f.get("median_ci95_g"), f.get("beta_ci95")
        u, ms = (c or {}).get("unit", "g"), (c or {}).get("measure", "PGA")
        m = f"median {what} {ms} {f['median_g']:.2g} {u}"
        m += f" (95 % interval {ci[0]:.2g} to {ci[1]:.2g} {u})" if ci else ""
        m += f", beta {f['beta']:.2f}" + (f" ({bci[0]:.2f} to {bci[1]:.2f})" if bci else "")
        return m
    return f"{what} fragility not estimable ({str(f.get('note', '')).removeprefix('not estimable: ')})"


_MEASURE_NAMES = {"pga": "PGA", "pgv": "PGV", "sa": "SA"}  # the names of a store of layout 6 or older


def _measure_label(b: Mapping[str, Any]) -> str:
    """'SA(3.0) of the analysed component' (a store of layout 6 or older: 'sa' with its period)."""
    name = str(b["measure"])
    if name == "sa" and b.get("period_s"):
        name = f"SA({float(b['period_s'])!r})"
    return f"{_MEASURE_NAMES.get(name, name)} of the analysed component"


def _measure_words(cs: Sequence[Mapping[str, Any]]) -> list[str]:
    """Which intensity measure predicts failure best, per case: beta of the failure fragility under each,
    with its interval."""
    out = []
    for c in cs:
        bm = [b for b in c.get("beta_by_measure", []) if b["damage"] == "failure" and b["estimable"]]
        if len(bm) < 2:
            continue
        best = min(bm, key=lambda b: b["beta"])

        def one(b: Mapping[str, Any]) -> str:
            ci = b.get("beta_ci95")
            return (
                f"{b['beta']:.2f}"
                + (f" ({ci[0]:.2f} to {ci[1]:.2f})" if ci else "")
                + f" under {_measure_label(b)}"
            )

        out.append(
            f"{c['isolation']}: beta of failure {', '.join(one(b) for b in bm)}; {_measure_label(best)} has "
            "the "
            "smallest dispersion (compare the intervals before choosing a measure)."
        )
    return out


def _displacement_words(d: Mapping[str, Any], cap: float | None, rho: Any) -> str:
    """The MCE displacement of a candidate row: the codes' statistic with its interval, the probability
    of exceeding the capacity, the eligibility rule and how overturned runs enter."""
    ci = d.get("disp_mce_ci95_m")
    txt = (
        f"isolator displacement at the MCE ({_lv(d['mce_g'], d)}): {d['disp_mce_m']:.3g} m"
        + (f" (95 % interval {ci[0]:.3g} to {ci[1]:.3g} m)" if ci else "")
        + f", the {d['disp_mce_statistic']}"
    )
    gx = finite(d.get("gamma_x")) or 1.0
    q, fr = finite(d.get("disp_fractile")), finite(d.get("disp_mce_fractile_m"))
    if cap and d.get("p_mce_exceed_capacity") is not None:
        ci = d.get("p_mce_exceed_capacity_ci95")
        stat = "mean" if "mean" in str(d["disp_mce_statistic"]) else "maximum"
        txt += (
            f"; times gamma_x = {gx:g} (EN 1998-1 §10.3(2)), {gx * d['disp_mce_m']:.3g} m"
            + (
                f", and its {100 * q:.0f}th percentile of the records {gx * fr:.3g} m"
                if q and fr is not None
                else ""
            )
            + f", against the capacity {cap:g} m; {d.get('n_mce_exceed_capacity')} of "
            f"{d.get('n_mce_records')} records beyond it (gamma_x times their peak"
            + (f"; exact 95 % interval {_interval(ci, _pct0)})" if ci else ")")
            + f". Eligible when gamma_x times the {stat} (EN 1998-1 §4.3.3.4.3(3): the mean of at least "
            f"{MIN_RECORDS} time-history analyses, else the most unfavourable) and times the "
            f"{100 * (q or 0.9):.0f}th percentile are within the capacity"
        )
    if d.get("n_mce_overturn"):
        txt += (
            f"; {d['n_mce_overturn']} of its MCE runs overturn the object and count the peak reached before "
            "the "
            "overturn (a lower bound)"
        )
    return txt + f"; one horizontal component, not the vector of two; mass ratio rho = {rho}."


def _sliding_words(cs: Sequence[Mapping[str, Any]], allow: float | None) -> str:
    """How far a sliding object slid, per case at the highest stripe with a slip: the median and the
    largest peak slip over the records, and how many went beyond the allowance."""
    parts = []
    for c in cs:
        rows = [r for r in c.get("stripes", []) if r.get("n_slid")]
        if not rows:
            parts.append(f"{c['isolation']}: no slip at any stripe")
            continue
        r = rows[-1]
        parts.append(
            f"{c['isolation']}: at {_lv(r['level'], c)} {r['n_slid']} of {r['n_records']} records slide, "
            f"peak slip median {r['slide_median_m']:.2g} m, largest {r['slide_max_m']:.2g} m"
            + (f", {r['n_slides_beyond']} beyond {allow:g} m" if allow else "")
        )
    return "Sliding: " + "; ".join(parts) + "."


def _case_lines(cs: Sequence[Mapping[str, Any]], cap: float | None) -> list[str]:
    parts = []
    levels = sorted({d["level"] for c in cs for d in c["design_levels"]})
    for x in levels:
        rows = []
        for c in cs:
            d = next((d for d in c["design_levels"] if d["level"] == x), None)
            if d is None:
                continue
            txt = f"{c['isolation']}: {_p_words(d, 'failure')}"
            if c["kind"] != "none" and cap and d.get("p_exceed_capacity") is not None:
                ci = d.get("p_exceed_capacity_ci95")
                txt += f", beyond {cap:g} m in {d.get('n_exceed_capacity')} of {d['n_records']} records" + (
                    f" ({_interval(ci, _pct0)})" if ci else ""
                )
            rows.append(txt)
        what = "a slide beyond the allowance" if any(c.get("mode") == "sliding" for c in cs) else "overturn"
        at = _lv(x, cs[0])
        parts.append(f"P(failure: {what} or beyond the capacity) at {at}: " + "; ".join(rows) + ".")
    for c in cs:
        if c.get("mode") == "sliding":
            parts.append(
                f"{c['isolation']}, failure by a slide beyond the allowance or the isolator beyond the "
                f"capacity: {_frag_words(c['fragility_failure'], 'failure', c)}."
            )
            continue
        parts.append(f"{c['isolation']}: {_frag_words(c['fragility'], 'overturning', c)}.")
        h = c.get("hazard")
        if h:
            ci, b = h.get("annual_rate_failure_ci95"), h.get("annual_rate_failure_bounds")
            txt = (
                f"{c['isolation']} at the site: failure {h['annual_rate_failure']:.2g} per year"
                + (f" ({ci[0]:.2g} to {ci[1]:.2g})" if ci else "")
                + f", {pct(h['p50_failure'])} in 50 years ({h['method_failure']})"
            )
            if b:
                txt += (
                    f"; with every exceedance of the hazard curve's last level counted as a failure "
                    f"{b[1]:.2g} per year"
                    + (" (the tail matters: extend the curve)" if h.get("tails_differ_failure") else "")
                )
            deagg = _deaggregation_words(h.get("deaggregation_failure") or [])
            parts.append(txt + (f"; {deagg}" if deagg else "") + ".")
    return parts


def _deaggregation_words(parts: Sequence[Mapping[str, Any]]) -> str:
    """Which shaking contributes the annual frequency of failure: "from shaking of return period 475 to
    2475 years 61 %, 2475 to 10000 years 30 %, ..." (largest first)."""
    if not parts:
        return ""

    def band(p: Mapping[str, Any]) -> str:
        lo, hi = p["from_yr"], p.get("to_yr")
        if not lo:
            return f"below {hi:g} years"
        return f"{lo:g} to {hi:g} years" if hi else f"beyond {lo:g} years"

    ranked = sorted(parts, key=lambda p: -p["share"])
    return "from shaking of return period " + ", ".join(f"{band(p)} {pct(p['share'])}" for p in ranked)


def _slender(o: Mapping[str, Any]) -> str:
    """The object's slenderness and friction (a rigid body's slenderness is not height / width: its weaker
    side's tan alpha instead)."""
    if o.get("body"):
        return f"friction {o['friction']:g} (its weaker side's tan alpha {o['tan_alpha']:.3g})"
    return f"slenderness {o['lambda']:.3g}, friction {o['friction']:g} (tan alpha {o['tan_alpha']:.3g})"


def _object_text(o: Mapping[str, Any], cs: Sequence[Mapping[str, Any]], summary: Mapping[str, Any]) -> dict:
    name = o["name"]
    designs = [d for d in summary.get("design", []) if d["object"] == name]
    cap = summary.get("capacity_m")
    size = (
        f"{o['height_m']:g} m high and {o['width_m']:g} m wide"
        if o.get("height_m")
        else f"R = {o['R_m']:.3g} m"
    )
    verdicts = []
    mode = ""
    if o["slides"]:
        allow = o.get("slide_allow_m")
        mode = (
            f"{name} slides and never rocks (friction {o['friction']:g} below tan alpha "
            f"{o['tan_alpha']:.3g}): its analyses are of sliding (Coulomb friction, rigid object), and "
            "it fails when it slides "
            + (f"farther than its allowance of {allow:g} m" if allow else "beyond its allowance")
            + " or its isolator moves beyond the capacity."
        )
    if not designs:
        head = f"{name}: no design level was given, so no base is recommended."
    else:
        for d in designs:
            verdicts.append(
                {
                    "design_g": d["design_g"],
                    "verdict": d["verdict"],
                    "sentence": verdict_sentence(name, d, cap),
                    "mce": mce_sentence(name, d, cap, sliding=bool(o["slides"])),
                    "grid": grid_sentence(d),
                }
            )
        head = verdicts[0]["sentence"]
    if mode:
        head = f"{mode} {head}"
    # the details, a paragraph each: the object and its levels; the probabilities; fragilities and
    # hazard; intensity measures; what stays within the model
    about = [f"{name}: {size}, {_slender(o)}; {len(summary.get('records', []))} records."]
    if o.get("body"):
        about.append(body_words(o, summary))
    m = summary.get("measure")
    if m:
        about.append(f"The levels are {m['label']} [{m['unit']}]: {m['basis']}." + _mce_direction(summary))
    if o["slides"]:
        about.append(_sliding_words(cs, o.get("slide_allow_m")))
    for d in designs:
        if d.get("design_basis") and not str(d["design_basis"]).startswith("given"):
            about.append(f"Design level {_lv(d['design_g'], d)}: {d['design_basis']}.")
        if d.get("mce_basis"):
            about.append(f"MCE level {_lv(d['mce_g'], d)}: {d['mce_basis']}.")
        shown = d.get("recommended") or d.get("best")
        if shown is not None and shown["isolation"] != "none" and shown.get("disp_mce_m") is not None:
            about.append(f"{_short(shown)}: " + _displacement_words(shown, cap, summary.get("rho")))
        if shown is not None and shown["isolation"] == "fp" and shown.get("residual_max_m") is not None:
            about.append(
                f"Friction pendulum: residual displacement up to mu_b R_b = {shown['residual_max_m']:.3g} m; "
                "restoring-force check of ASCE/SEI 7-16 §17.2.4.4 "
                + ("met." if shown.get("recentring_ok") else "NOT met (D / (2 R_b) < 0.025).")
            )
    lines = _case_lines(cs, cap)
    n_p = sum(1 for ln in lines if ln.startswith("P(failure"))
    n_out = sum(c["validity"]["n_outside_model"] for c in cs)
    n_runs = sum(c["validity"]["n_runs"] for c in cs)
    if n_out:
        slides = sum(c["validity"]["n_slides"] for c in cs)
        jumps = sum(c["validity"]["n_jumps"] for c in cs)
        rule = cs[0]["validity"]["outside_model_rule"]
        how = "left out of the fits" if rule == "exclude" else "counted as failures"
        valid = [
            f"{n_out} of {n_runs} stripe runs are outside the model ({slides} would slide, {jumps} would "
            f"jump): {how}."
        ]
    elif o["slides"]:
        valid = [f"All {n_runs} stripe runs stay within the model: the sliding is the motion analysed."]
    else:
        valid = [f"All {n_runs} stripe runs stay within the model (no sliding, no jumping)."]
    mine = [
        w for w in summary.get("warnings", []) if " / " not in w.split(":")[0] or w.startswith(f"{name} /")
    ]
    valid += [w[0].upper() + w[1:] + "." for w in mine]
    details = [" ".join(p) for p in (about, lines[:n_p], lines[n_p:], _measure_words(cs), valid) if p]
    first = [head] + [v["sentence"] for v in verdicts[1:]]
    first += [v[k] for v in verdicts for k in ("mce", "grid") if v[k]]
    return {
        "object": name,
        "text": " ".join(first + details),
        "headline": head,
        "mode": mode,
        "verdicts": verdicts,
        "details": details,
    }


def _twin(o: Mapping[str, Any], summary: Mapping[str, Any]) -> Mapping[str, Any] | None:
    """The uniform block of the same outline among the objects assessed, if there is one."""
    if not (o.get("height_m") and o.get("width_m")):
        return None
    for x in summary.get("objects", []):
        if x.get("body") or not x.get("height_m") or not x.get("width_m"):
            continue
        if math.isclose(x["height_m"], o["height_m"], rel_tol=1e-9) and math.isclose(
            x["width_m"], o["width_m"], rel_tol=1e-9
        ):
            return x
    return None


def _overturns(summary: Mapping[str, Any], name: str) -> dict[str, tuple[int, int]]:
    """Per isolation case: (runs that overturned, runs) over the stripes of an object."""
    out = {}
    for c in summary.get("cases", []):
        if c["object"] == name:
            n = sum(int(r.get("n_records", 0)) for r in c["stripes"])
            k = sum(int(r.get("n_overturn", 0)) for r in c["stripes"])
            out[c["isolation"]] = (k, n)
    return out


def body_words(o: Mapping[str, Any], summary: Mapping[str, Any]) -> str:
    """The paragraph on a rigid body of measured geometry (docs/model.md §18): its geometry, its two
    uplift thresholds, the polarities run and, beside a uniform block of the same outline, how and why
    their answers differ."""
    b = o["body"]
    name = o["name"]
    out = (
        f"{name} is a rigid body of measured geometry: its centre of mass is {b['h_cg_m']:.3g} m above its "
        f"base, {b['b_left_m']:.3g} m from the left edge and {b['b_right_m']:.3g} m from the right edge of "
        f"its footprint, radius of gyration {b['r_gyration_m']:.3g} m. On a fixed base it lifts off at "
        f"{b['tan_alpha_left']:.3g} g onto its left edge and {b['tan_alpha_right']:.3g} g onto its right "
        "edge (g tan alpha of each side, docs/model.md §18). "
    )
    if b.get("polarities", 1) > 1:
        out += (
            "Its sides differ, so every record was run as recorded and reversed, and each run counts as "
            "the worse of the two (a record may reach it with either polarity). "
        )
    twin = _twin(o, summary)
    if twin is None:
        return out.strip()
    h_uni = 0.5 * o["height_m"]
    lower = "lower" if b["h_cg_m"] < h_uni else "higher"
    weak = min(b["tan_alpha_left"], b["tan_alpha_right"])
    mine, theirs = _overturns(summary, name), _overturns(summary, twin["name"])
    runs = [
        f"{case} {mine[case][0]} of {mine[case][1]} against {theirs[case][0]} of {theirs[case][1]}"
        for case in mine
        if case in theirs
    ]
    out += (
        f"Beside {twin['name']}, the uniform block of the same {o['height_m']:g} m x {o['width_m']:g} m "
        f"outline: its centre of mass is {lower} ({b['h_cg_m']:.3g} m against {h_uni:.3g} m) and "
        f"{abs(b['b_left_m'] - b['b_right_m']) / 2:.3g} m off the middle, so it lifts off at "
        f"{weak:.3g} g on its weaker side against {twin['tan_alpha']:.3g} g, "
        f"{'later' if weak > twin['tan_alpha'] else 'earlier'}, and it needs "
        f"{'more' if weak > twin['tan_alpha'] else 'less'} rotation to pass over its edge; its inertia "
        f"about each edge (r^2 + R^2) and its restitution differ too. Runs that overturned over the "
        f"stripes, per base, {name} against {twin['name']}: " + "; ".join(runs) + "."
    )
    return out


def conclusions(summary: Mapping[str, Any]) -> list[dict[str, Any]]:
    """One paragraph per object that opens with the verdict (:func:`verdict_sentence`), then where the
    search stopped and the numbers with their intervals: ``{"object", "headline" (the first sentence),
    "verdicts" (per design level: ``design_g``, ``verdict``, ``sentence``, ``grid``), "details" (the
    paragraphs after them), "text" (all of it)}``."""
    out = []
    for o in summary.get("objects", []):
        cs = [c for c in summary["cases"] if c["object"] == o["name"]]
        if cs:
            out.append(_object_text(o, cs, summary))
    return out


def text_summary(summary: Mapping[str, Any], report: str = "") -> list[str]:
    """What ``isorock assess`` prints: per object the verdict, where the search stopped and the short
    table; then the assumptions in brief and where everything else is."""
    lines: list[str] = []

    def wrap(text: str) -> list[str]:
        """Lines of at most :data:`TABLE_WIDTH`, a number never cut from its unit ("95 %", "0.3 g")."""
        glued = re.sub(r"(\d) (%|g\b|s\b|m\b)", "\\1\x00\\2", text)
        return [ln.replace("\x00", " ") for ln in textwrap.wrap(glued, TABLE_WIDTH)] or [""]

    for c in summary.get("conclusions", []):
        o = next(x for x in summary["objects"] if x["name"] == c["object"])
        lines.append("")
        size = f"{o['height_m']:g} m x {o['width_m']:g} m" if o.get("height_m") else f"R {o['R_m']:.3g} m"
        if o.get("body"):
            # a body's slenderness is not height / width: its two thresholds follow
            outline = "outline " + size if o.get("height_m") else "rigid body"
            lines.append(f"{o['name']} ({outline}, friction {o['friction']:g})")
        else:
            lines.append(f"{o['name']} ({size}, lambda {o['lambda']:.3g}, friction {o['friction']:g})")
        b = o.get("body")
        if b:
            both = ", every record as recorded and reversed (the worse counts)" if b["polarities"] > 1 else ""
            lines += wrap(
                f"Measured geometry: centre of mass {b['h_cg_m']:.3g} m high, {b['b_left_m']:.3g} m from the "
                f"left edge and {b['b_right_m']:.3g} m from the right one, radius of gyration "
                f"{b['r_gyration_m']:.3g} m; lifts off at {b['tan_alpha_left']:.3g} g onto its left edge, "
                f"{b['tan_alpha_right']:.3g} g onto its right one{both}."
            )
        m = summary.get("measure")
        if m:
            lines += wrap(f"Levels in {m['label']} [{m['unit']}]: {m['basis']}." + _mce_direction(summary))
        if not c["verdicts"]:
            lines += wrap(c["headline"])
            continue
        if c.get("mode"):
            lines += wrap(c["mode"])
        for v in c["verdicts"]:
            d = next(
                x for x in summary["design"] if x["object"] == o["name"] and x["design_g"] == v["design_g"]
            )
            lines += wrap(v["sentence"])
            for k in ("mce", "grid"):
                if v[k]:
                    lines += wrap(v[k])
            lines.append("")
            lines += text_table(d)
    if any(c["verdicts"] for c in summary.get("conclusions", [])):
        lines.append("")
        lines += wrap(LEGEND)
    lines.append("")
    lines += wrap(
        "Assumes: a rigid object rocking without sliding or jumping (checked run by run), or, with its "
        "friction below tan alpha, sliding without rocking (Coulomb friction); one horizontal "
        "ground-motion component, the isolator displacement of that component, overturned runs counting "
        "their peak before the overturn."
    )
    for w in summary.get("warnings", []):
        lines += wrap("Warning: " + w + ".")
    where = f" {report}" if report else " the report"
    lines += wrap(
        f"Everything else (the probabilities of every case, fragilities, the site's hazard, intensity "
        f"measures, every candidate): the Assessment page of{where}, or --json."
    )
    return lines
