"""The tables of an assessment: the short table that follows each verdict (the same cells in
``isorock assess`` and in the report, at most :data:`~isorock.assessment.formats.TABLE_WIDTH`
columns as text), its legend, and the report's summary and candidates tables."""

from __future__ import annotations

import math
import textwrap
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

from isorock.assessment.formats import (
    _by_rate,
    _g2,
    _interval,
    _p,
    _pb,
    _pct0,
    _short,
    describe,
    finite,
    pct,
    sci,
)
from isorock.assessment.fragility import clopper_pearson

__all__ = ["short_table", "text_table", "LEGEND", "summary_table", "candidates_table"]


def _table_rows(design: Mapping[str, Any], n_grid: int = 3) -> list[Mapping[str, Any]]:
    cands = design["candidates"]
    keep = [c for c in cands if c["source"] == "floor"] + [c for c in cands if c["source"] == "case"]
    grid = [c for c in cands if c["source"] == "grid" and c["rank"]][:n_grid]
    for c in (design.get("recommended"), design.get("best")):
        if c is not None and c["source"] == "grid" and all(c["name"] != g["name"] for g in grid):
            grid.append(next(x for x in cands if x["name"] == c["name"]))
    return keep + sorted(grid, key=lambda c: c["rank"])


def _scale(design: Mapping[str, Any], rows: Sequence[Mapping[str, Any]]) -> float:
    """The power of ten the annual frequencies of a table are printed in: the fixed base's estimate's
    (the reference every row is compared with), else the smallest positive estimate's."""
    floor = design.get("floor") or {}
    ref = finite(floor.get("estimate"))
    if not ref:
        ref = min((v for r in rows if (v := finite(r.get("estimate"))) is not None and v > 0), default=0.0)
    return 10.0 ** math.floor(math.log10(ref)) if ref and ref > 0 else 1.0


def _ci_cell(lo: str, hi: str) -> str:
    """An interval in a table cell: "(0.1-3.1)", or "(71, >99.9)" where an end carries a sign (never
    "71->99.9", which reads as an arrow)."""
    return f"({lo}, {hi})" if (hi[:1] in "<>" or lo[:1] in "<>-" and lo != "-") else f"({lo}-{hi})"


def _observed_cell(z: Any, n: Any, ci: Sequence[float] | None, upper: Any) -> str:
    """A count with its exact interval: "3/18 (3.6-41)", "0/17 (<=16)" (the one-sided bound the text
    gives for a count of zero)."""
    if not n:
        return "-"
    if not z:
        u = finite(upper)
        return f"0/{n}" + (f" (<={_p(u)})" if u is not None else "")
    return f"{z}/{n}" + (" " + _ci_cell("0" if ci[0] == 0 else _p(ci[0]), _p(ci[1])) if ci else "")


def short_table(design: Mapping[str, Any]) -> pd.DataFrame:
    """The short table of one object and design level (the same cells in the text and the report): the
    fixed base, the configured cases and the best isolators of the grid (:func:`_table_rows`): the
    metric with its interval and what was observed, the paired difference from the fixed base and its
    familywise p-value, P(failure) at the MCE against the target, and the MCE displacement times
    gamma_x."""
    rate = _by_rate(design)
    x = design["design_g"]
    cands = _table_rows(design)
    k = _scale(design, cands) if rate else 100.0  # rates in units of 10^n per year; probabilities in %

    def num(v: Any, sign: bool = False) -> str:
        y = finite(v)
        if y is None:
            return "-"
        if not rate:
            if sign:
                z = k * y
                return f"{z:+.0f}" if abs(z) >= 10 else f"{z:+.2g}"
            return _p(y)
        v = y / k  # in units of the fixed base's power of ten: beyond 0.01 to 100 of it, coarser
        text = "0" if v == 0 else ("<0.01" if abs(v) < 0.01 else (f"{v:.0f}" if abs(v) >= 100 else _g2(v)))
        if abs(v) < 0.01 and v != 0 and sign:
            text = ("-" if v < 0 else "+") + text
        return ("+" if sign and v > 0 and abs(v) >= 0.01 else "") + text

    rows = []
    for c in cands:
        ci = c.get("estimate_ci95")
        if rate:
            est = num(c["estimate"]) + (" " + _ci_cell(num(ci[0]), num(ci[1])) if ci else "")
        elif c.get("fitted"):
            est = num(c["estimate"]) + (" " + _ci_cell(_pb(ci[0]), _pb(ci[1])) if ci else "")
        else:  # observed: the count and its exact interval
            est = _observed_cell(c.get("n_failure_observed"), c.get("n_failure_counted"), ci,
                                 c.get("p_failure_upper95"))  # fmt: skip
        seen = (
            f"{c.get('n_failure_observed')}/{c.get('n_failure_counted')}"
            if c.get("n_failure_counted")
            else "-"
        )
        vs = c.get("vs_floor") or {}
        if c["source"] == "floor" or finite(vs.get("difference")) is None:
            diff, test = "-", "-"
        else:
            diff = num(vs["difference"], True)
            pa = finite(vs.get("p_adjusted"))
            test = "exact" if vs.get("decided_by") == "exact bounds" else ("-" if pa is None else f"{pa:.2g}")
        tm = c.get("target_estimate")
        tci = c.get("target_estimate_ci95")
        rate_t = (design.get("target") or {}).get("kind") == "rate_per_yr"
        mce = "-" if finite(tm) is None else (sci(tm) if rate_t else _p(tm))
        if tci and finite(tm) is not None and not rate_t:
            lo, hi = ("0" if tci[0] == 0 else _pb(tci[0])), _pb(tci[1])
            mce += "" if lo == hi == mce else " " + _ci_cell(lo, hi)
        ok = {True: "yes", False: "no", None: "not shown"}[c.get("adequate")]
        if c.get("adequate") is False and c.get("adequacy_note"):
            ok = "no: capacity"
        if c["isolation"] == "none":
            disp = "-"
        else:
            f2 = lambda v: "-" if finite(v) is None else f"{v:.2f}"  # noqa: E731 (cm: what the spread allows)
            # what eligibility is judged on: the larger of the codes' statistic and the fractile
            both = (finite(c.get("disp_mce_factored_m")), finite(c.get("disp_mce_fractile_factored_m")))
            vals = [v for v in both if v is not None]
            disp = f2(max(vals)) if vals else "-"
        mark = "* " if c.get("recommended") else ("x " if not c.get("within_capacity", True) else "  ")
        unit = "%" if not rate else f"1e{round(math.log10(k))}/yr"
        t = design.get("target") or {}
        lvl = f"{x:g} {design.get('unit', 'g')} {design.get('measure', 'PGA')}"
        tword = {"p_mce": "P(failure) at MCE [%]", "p_50yr": "P(failure) in 50 yr [%]"}.get(
            t.get("kind", "p_mce"), "failures per year"
        )
        rows.append(
            {
                "base": mark + _short(c),
                # a probability at a level has the count observed there beside it; a frequency
                # integrates every stripe (the report's Assessment page has their counts)
                (f"P(failure) at {lvl} [%], seen" if not rate else f"failures per year [{unit}]"): (
                    est if rate or not c.get("fitted") else f"{est} {seen}"
                ),
                "minus fixed base": diff,  # in the unit of the column before it
                "adj. p": test,
                tword: mce,
                "meets target": ok,
                "gamma_x MCE displ. [m]": disp,
            }
        )
    return pd.DataFrame(rows)


def _count(c: Mapping[str, Any]) -> str:
    """Records beyond the capacity at the MCE: "3/18 (3.6-41)", the count with its exact 95 % interval in
    %, "0/18 (<=15)" for none (the one-sided bound); "-" where it does not apply (a fixed base, no
    capacity)."""
    n_k, n = c.get("n_mce_exceed_capacity"), c.get("n_mce_records")
    ci = c.get("p_mce_exceed_capacity_ci95")
    if c.get("p_mce_exceed_capacity") is None or n_k is None or not n:
        return "-"
    upper = clopper_pearson(0, int(n), side="upper")[1] if not n_k else None
    return _observed_cell(n_k, n, ci, upper)


def _disp_pair(c: Mapping[str, Any]) -> str:
    """The isolator's MCE displacement times gamma_x, the codes' statistic and the fractile: "0.2 / 0.51"."""
    a, b = finite(c.get("disp_mce_factored_m")), finite(c.get("disp_mce_fractile_factored_m"))
    if c["isolation"] == "none" or a is None:
        return "-"
    return f"{a:.3g} / {b:.3g}" if b is not None else f"{a:.3g}"


def text_table(design: Mapping[str, Any]) -> list[str]:
    """:func:`short_table` as text lines (each header over at most two lines; the cells are short
    enough that a line stays within :data:`TABLE_WIDTH` characters for the bases the search names)."""
    df = short_table(design)
    specs = []
    for c in df.columns:
        w = max([len(str(v)) for v in df[c]] + [len(x) for x in c.split()] + [0])
        lines = textwrap.wrap(c, w) or [""]
        while len(lines) > 2:
            w += 1
            lines = textwrap.wrap(c, w)
        specs.append((c, w, (lines + ["", ""])[:2]))
    out = ["  ".join(h[i].ljust(w) for _, w, h in specs).rstrip() for i in range(2)]
    for _, r in df.iterrows():
        out.append("  ".join(str(r[c]).ljust(w) for c, w, _ in specs).rstrip())
    return out


LEGEND = (
    "Failure: the object overturns, or slides beyond its allowance (an object whose friction is below "
    "tan alpha), or the isolator moves, times gamma_x, beyond its capacity. * recommended; x not "
    "eligible: gamma_x times the mean of the records' peak displacements at the MCE (their maximum with "
    "fewer than 7 records), or times the stated fractile of them, exceeds the capacity. A base without "
    "a name: an isolator of the design grid (Tb [s], xi; or mu, R [m]); shown: the fixed base, the "
    "configured cases, the three isolators of lowest estimate and the recommended one. Intervals 95 %: "
    "bootstrap over the records (every base on the same resamples) for fitted probabilities, exact "
    "binomial for counts (k/n: k of n records; <= the one-sided bound of 0 of n); seen: failures "
    "observed at the design level; minus fixed base: the paired difference, in the unit of the column "
    "before it; adj. p: the familywise p-value of the test that the base fails less than the fixed "
    "base, corrected for every isolator searched (exact: judged by exact bounds); meets target: yes "
    "(its estimate meets it), no (even the lower end of its interval misses it), no: capacity (beyond "
    "the displacement capacity at the MCE), not shown; gamma_x MCE displ.: the larger of the codes' "
    "statistic and the stated fractile of the records' peak displacements at the MCE, times gamma_x: "
    "what eligibility is judged on."
)


def summary_table(summary: Mapping[str, Any]) -> pd.DataFrame:
    """The summary of the report: one row per object and isolation case, each estimate beside its
    interval and what was observed ("-" where a value does not apply)."""
    cap = summary.get("capacity_m")
    rows = []
    for c in summary["cases"]:
        sliding = c.get("mode") == "sliding"
        never = "never: it slides"  # an object below tan(alpha) does not rock (docs/model.md §16)
        im, u = c.get("measure", "PGA"), c.get("unit", "g")
        row = {
            "object": c["object"],
            "isolation": c["isolation"],
            f"median overturning {im} [{u}]": never if sliding else _median_text(c["fragility"]),
            f"median failure {im} [{u}]": _median_text(c["fragility_failure"]),
        }
        for d in c["design_levels"]:
            x = d["level"]
            for damage in ("failure", "overturn"):
                if damage == "overturn" and sliding:
                    row[f"P({damage}) at {x:g} {u} {im}"] = never
                    row[f"95 % interval ({damage})"] = "-"
                    row[f"observed ({damage})"] = "-"
                    continue
                p, ci = d.get(f"p_{damage}"), d.get(f"p_{damage}_ci95")
                row[f"P({damage}) at {x:g} {u} {im}"] = pct(p) if p is not None else "not estimable"
                row[f"95 % interval ({damage})"] = (
                    _interval(ci) if ci else f"at most {pct(d.get(f'p_{damage}_upper95'))}"
                )
                row[f"observed ({damage})"] = (
                    f"{d.get(f'n_{damage}_observed')} of {d.get(f'n_{damage}_counted')}"
                )
            if c["kind"] != "none":
                dci = d.get("disp_mce_ci95_m")
                row[f"MCE displacement [m] ({d.get('mce_g') or 0:g} {u} {im})"] = (
                    "-" if finite(d.get("disp_mce_m")) is None else f"{d['disp_mce_m']:.3g}"
                ) + (f" ({dci[0]:.3g} to {dci[1]:.3g})" if dci else "")
                if cap:
                    for key, where in (("", f"{x:g} {u} {im}"), ("mce_", "the MCE")):
                        k, ci = d.get(f"p_{key}exceed_capacity"), d.get(f"p_{key}exceed_capacity_ci95")
                        gx = summary.get("gamma_x") or 1.0
                        row[f"records beyond {cap:g} m (x {gx:g}) at {where}"] = (
                            "-" if k is None else f"{pct(k)}" + (f" ({_interval(ci, _pct0)})" if ci else "")
                        )
        h = c.get("hazard")
        if h:
            b = h.get("annual_rate_failure_bounds")
            row["failures per year"] = f"{h['annual_rate_failure']:.2g}" + (
                f" (up to {b[1]:.2g})" if b else ""
            )
            row["P(failure) in 50 years"] = pct(h["p50_failure"])
        v = c["validity"]
        row["outside the model"] = f"{v['n_outside_model']} of {v['n_runs']}"
        rows.append(row)
    return pd.DataFrame(rows).fillna("-")


def _median_text(f: Mapping[str, Any]) -> str:
    if not f.get("estimable"):
        return "not estimable"
    ci = f.get("median_ci95_g")
    return f"{f['median_g']:.2g}" + (f" ({ci[0]:.2g} to {ci[1]:.2g})" if ci else "")


def candidates_table(design: Mapping[str, Any], n_grid: int | None = None) -> pd.DataFrame:
    """Every candidate of one design level for the report: the fixed base, the cases and the isolators
    of the grid (every one, or the best ``n_grid``), with their estimates, intervals, adequacy and
    paired comparisons."""
    rows = []
    cands = design["candidates"]
    keep = [c for c in cands if c["source"] != "grid"]
    keep += [c for c in cands if c["source"] == "grid"][:n_grid]
    rate = _by_rate(design)
    fmt = sci if rate else pct
    for c in keep:
        ci = c.get("estimate_ci95")
        vf = c.get("vs_floor") or {}
        dfmt = sci if rate else (lambda v: "-" if finite(v) is None else f"{100 * v:+.2g} points")
        if c["fitted"] or rate:
            est, interval = fmt(c["estimate"]), (_interval(ci, fmt) if ci else "-")
        else:  # what was observed, with its exact interval
            est = f"{c.get('n_failure_observed')} of {c.get('n_failure_counted')}"
            interval = _interval(ci, _pct0) if ci else "-"
        rows.append(
            {
                "candidate": c["name"],
                "base": describe(c),
                ("failures per year" if rate else "P(failure)"): est,
                "95 % interval": interval,
                "fitted": "yes" if c["fitted"] else "observed fraction",
                "minus fixed base": "-" if c["source"] == "floor" else dfmt(vf.get("difference")),
                "its 95 % interval": "-"
                if c["source"] == "floor" or not vf.get("difference_ci95")
                else _interval(vf["difference_ci95"], dfmt),
                "lower than fixed base in": "-"
                if c["source"] == "floor"
                else f"{vf.get('n_better', '-')} of {vf.get('n', '-')} resamples",
                "familywise p": "-"
                if c["source"] == "floor" or finite(vf.get("p_adjusted")) is None
                else f"{vf['p_adjusted']:.2g}",
                "P(failure) at the MCE": "-"
                if finite(c.get("p_failure_mce")) is None
                else pct(c["p_failure_mce"])
                + (
                    f" ({_interval(c.get('p_failure_mce_ci95'), _pct0)})"
                    if c.get("p_failure_mce_ci95")
                    else ""
                ),
                "meets the target": {True: "yes", False: "no", None: "not shown"}[c.get("adequate")]
                + (f" ({c['adequacy_note']})" if c.get("adequacy_note") else ""),
                "MCE displacement x gamma_x, mean / fractile [m]": _disp_pair(c),
                "beyond capacity at MCE": _count(c),
                "eligible": "yes" if c.get("eligible", c["within_capacity"]) else "no (beyond capacity)",
                "rank": c["rank"] or "-",
                "advice": "recommended"
                if c.get("recommended")
                else ("equivalent to the recommended" if c.get("equivalent") else ""),
            }
        )
    return pd.DataFrame(rows)
