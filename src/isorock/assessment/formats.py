"""How an assessment prints its numbers and names its bases: probabilities with the precision they have
(2 significant digits; the ends of an interval with 1 below 1 %; "< 0.01 %", never "0 %" for an
estimate), shares of resamples, annual frequencies ("7.2e-5"), and a base in words. Never ``NaN``: a
value that does not apply is "-". Used by :mod:`~isorock.assessment.words` (the sentences) and
:mod:`~isorock.assessment.tables` (the tables)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["TABLE_WIDTH", "finite", "pct", "bound", "share", "sci", "describe"]

#: the short table's width at most [characters]
TABLE_WIDTH = 100


def finite(x: Any) -> float | None:
    """``x`` as a finite float, or None (None, NaN, infinite, not a number)."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def pct(p: float | None) -> str:
    """A probability in words with the precision it has: "0.52 %", "12 %", "< 0.01 %", "> 99.9 %"; "-"
    where there is none."""
    v = finite(p)
    if v is None:
        return "-"
    if v < 1e-4:
        return "< 0.01 %"
    if v > 0.999:
        return "> 99.9 %"
    if v > 0.99:
        return f"{100 * v:.1f} %"
    return f"{100 * v:.2g} %" if v < 0.1 else f"{100 * v:.0f} %"


def _pb(v: float | None) -> str:
    """:func:`bound` without the unit and its spaces, for the short table."""
    return bound(v).removesuffix(" %").replace("< ", "<").replace("> ", ">")


def _p(v: float | None) -> str:
    """:func:`pct` without the unit and its spaces, for the short table ("0.93", "<0.01")."""
    return pct(v).removesuffix(" %").replace("< ", "<").replace("> ", ">")


def _g2(v: float | None) -> str:
    """2 significant digits, trailing zeros kept ("1.0", "0.40", "15")."""
    x = finite(v)
    if x is None:
        return "-"
    return f"{x:#.2g}".rstrip(".") if abs(x) < 1e4 and (x == 0 or abs(x) >= 1e-3) else f"{x:.1e}"


def bound(p: float | None) -> str:
    """The end of a 95 % interval of a probability: its precision is lower than the estimate's, so 1
    significant digit below 1 % ("0.03 %", "0.6 %"), 2 below 10 % ("9.8 %"), whole percents above."""
    v = finite(p)
    if v is None or not 1e-4 <= v <= 0.01:
        return pct(p)
    return f"{100 * v:.1g} %"


def _pct0(p: float | None) -> str:
    """:func:`pct`, but an exact zero (the lower bound of 0 of n) as "0 %"."""
    return "0 %" if finite(p) == 0.0 else pct(p)


def share(p: float | None) -> str:
    """A share of the bootstrap resamples, never rounded up across a threshold: "98 %", "94.9 %" (not
    "95 %" for 0.9499), "99.9 %" (not "100 %" for 0.9993), "100 %" and "0 %" only for all and none of
    them, "< 0.1 %" for a few."""
    v = finite(p)
    if v is None:
        return "-"
    if v in (0.0, 1.0):
        return f"{100 * v:.0f} %"
    if v < 0.001:
        return "< 0.1 %"
    tenths = math.floor(1000 * v + 1e-9)
    return f"{tenths // 10} %" if tenths % 10 == 0 else f"{tenths / 10:.1f} %"


def sci(v: float | None) -> str:
    """An annual frequency: "7.2e-5", 2 significant digits; "0"."""
    x = finite(v)
    if x is None:
        return "-"
    if x == 0:
        return "0"
    m, e = f"{x:.1e}".split("e")
    return f"{m}e{int(e)}"


def _interval(ci: Sequence[float] | None, fmt=pct) -> str:
    return "" if not ci else f"{fmt(ci[0])} to {fmt(ci[1])}"


def describe(r: Mapping[str, Any]) -> str:
    """A base in words: "no isolation", "a linear isolator Tb 2 s, xi 0.4", "a friction pendulum
    mu_b 0.06, R_b 2.24 m (Tb 3 s)"; a configured case adds its name."""
    if r["isolation"] == "none":
        return "no isolation"
    if r["isolation"] == "linear":
        txt = f"a linear isolator Tb {r['Tb_s']:.3g} s, xi {r['xi_b']:.2g}"
    else:
        txt = f"a friction pendulum mu_b {r['mu_b']:.3g}, R_b {r['R_b_m']:.3g} m (Tb {r['period_s']:.3g} s)"
    return txt + (f" (case {r['name']})" if r.get("source") == "case" else "")


def _short(r: Mapping[str, Any]) -> str:
    """A base in a few characters: "fixed base", "lin3: Tb 3 xi 0.2" (a configured case), "Tb 2 xi 0.4"
    (an isolator of the grid), "fp: mu 0.06 R 2.2"."""
    if r["isolation"] == "none":
        return "fixed base"
    name = "" if r["source"] == "grid" else f"{r['name'][:6]}: "
    if r["isolation"] == "linear":
        return f"{name}Tb {r['Tb_s']:.3g} xi {r['xi_b']:.2g}"
    return f"{name}mu {r['mu_b']:.2g} R {r['R_b_m']:.2g}"


def _by_rate(design: Mapping[str, Any]) -> bool:
    return "annual" in str(design.get("ranked_by", ""))
