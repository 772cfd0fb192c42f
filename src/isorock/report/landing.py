"""The landing page of the report (``results/report/landing.rst``, the Snakefile's ``report:``): the
results first, in plain language, then the method, on one screen.

With an assessment: the plain-language conclusion of the first objects and where the rest is (the
'Assessment' category: summary table, fragility, displacement and design charts). With the
minimum-overturning study, per block: the records that overturn it at or below their own PGA on the
ground, and per isolation case how many do and by how much isolation raises or lowers the overturning
PGA (the median over the records), then which case helps most. Then what was computed and where the
numbers are (``results/isorock.h5``). The tables and figures are the categories' pages, not this one.

The page is laid out by the template ``templates/landing.rst.j2`` (:mod:`isorock.report.html`: every
value made plain RST text); it ends with the style that puts it at the top of the report's window
(Snakemake centres its landing page vertically: at 1400 x 3000 the answer sat below 1000 px of blank),
sets the title of the browser's tab (:func:`report_title`, not "Snakemake Report"), and puts the
workflow's graph, which Snakemake draws beside the text, under it.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from isorock.assessment.summary import assessment_summary
from isorock.report.html import render_rst
from isorock.store import Store, atomic_path

__all__ = ["write_landing", "landing_text", "report_title"]

_METHOD = (
    "Records processed (band-pass, baseline, QA) in the component the paper used; Tp by the wavelet "
    "method; every analysis integrates the model's exact equations (rocking, impacts with base-block "
    "interaction; sliding for an object whose friction is below tan alpha) in an engine validated "
    "against closed forms and independent integrators."
)

#: the page stays short, on one screen (the gist for the first objects, then pointers to the categories)
_MAX_OBJECTS = 4
#: non-empty lines of the page at most (a block per line in the minimum-overturning section, fewer
#: blocks shown when there are more)
MAX_LINES = 20
#: record names listed in a sentence at most
_MAX_NAMES = 2


@dataclass
class _Section:
    """A paragraph that starts with its title in bold (a heading would take three lines of the page),
    its bullets and the paragraphs after them: plain text, made RST by the template."""

    title: str
    text: str
    bullets: list[str] = field(default_factory=list)
    after: list[str] = field(default_factory=list)

    @property
    def lines(self) -> int:
        """Its lines on the page (non-empty lines of the RST)."""
        return 1 + len(self.bullets) + len(self.after)


#: the lines of the page's title ('isorock results' and its underline)
_TITLE_LINES = 2


def landing_text(store: Store, figdir: Path | None, overturn: pd.DataFrame | None) -> str:
    """The landing RST of a store (see the module docstring)."""
    sections = []
    s = assessment_summary(store)
    if s["cases"]:
        more = len(s["conclusions"]) - _MAX_OBJECTS
        text = (
            (f"{len(s['conclusions'])} objects; the first {_MAX_OBJECTS}. " if more > 0 else "")
            + "Per object and design level the verdict, below; its table, the details, the fragility, "
            "displacement and design charts under 'Assessment'; where the model departs from the paper "
            "under 'The paper'."
        )
        sections.append(
            _Section("Assessment", text, [c["headline"] for c in s["conclusions"][:_MAX_OBJECTS]])
        )
    cfg = store.root_attrs.get("config_name", "")
    src = store.root_attrs.get("record_source", "")
    method = _Section(
        "Method", f"{_METHOD} Configuration {cfg}; records: {src}; every number in results/isorock.h5."
    )
    ovt = store.table("summary/overturn") if overturn is not None and not overturn.empty else None
    if ovt is not None and not ovt.empty:
        used = _TITLE_LINES + sum(x.lines for x in sections) + method.lines
        sections.append(_overturn_section(ovt, max(1, MAX_LINES - used - 2)))
    return render_rst("landing.rst.j2", sections=[*sections, method], title=report_title(store, overturn))


def report_title(store: Store, overturn: pd.DataFrame | None = None) -> str:
    """The title of the report's browser tab: what the answer is about (the objects assessed, else the
    studies and how many records), then 'isorock report'. Letters, digits and plain punctuation only:
    it goes into an HTML attribute of the landing page's raw HTML."""
    s = assessment_summary(store)
    if s["cases"]:
        names = [c["object"] for c in s["conclusions"]] or [o["name"] for o in s["objects"]]
        more = len(names) - _MAX_NAMES
        subject = "assessment of " + ", ".join(names[:_MAX_NAMES]) + (f" +{more}" if more > 0 else "")
    else:
        rec = store.table("summary/records")
        n = 0 if rec is None else len(rec)
        subject = (
            "minimum overturning PGA" if overturn is not None and not overturn.empty else "results"
        ) + (f" of {n} record{'s' if n != 1 else ''}")
    return re.sub(r" +", " ", re.sub(r"[^0-9A-Za-z .,+()-]", " ", f"{subject} - isorock report")).strip()


def _names(ids: list[str]) -> str:
    more = len(ids) - _MAX_NAMES
    return ", ".join(ids[:_MAX_NAMES]) + (f" +{more}" if more > 0 else "")


def _pct(x: float) -> str:
    return f"{100 * x + 0.0:+.0f} %".replace("-0 %", "+0 %")


def _of_block(ratio: pd.Series, lam: float, R: float) -> pd.Series:
    """A block's ratios over its records; empty when the block never overturned (pivot_table leaves
    out a block whose every value is NaN: it had raised KeyError for a block larger than the grid)."""
    try:
        return ratio.xs((lam, R), level=["lambda_", "R_m"]).dropna()
    except KeyError:
        return pd.Series(dtype=float)


def _overturn_section(ovt: pd.DataFrame, n_blocks: int) -> _Section:
    """The minimum-overturning paragraph, one line per block (at most ``n_blocks``, spread over the
    sizes) and the conclusion (see the module docstring)."""
    ovt = ovt.copy()
    ovt["below"] = ovt["min_overturn_g"] <= ovt["record_pga_g"]  # NaN (no overturn): False
    kinds = dict(zip(ovt["case"], ovt["isolation"], strict=False))
    cases = list(dict.fromkeys(ovt["case"]))
    ground = next((c for c in cases if kinds[c] == "none"), None)
    isolated = [c for c in cases if kinds[c] != "none"]
    blocks = list(dict.fromkeys(zip(ovt["lambda_"], ovt["R_m"], strict=True)))
    one_lambda = len({lam for lam, _ in blocks}) == 1
    n_rec = ovt["record"].nunique()
    # per record, block and case: the minimum overturning PGA over the ground's (finite both)
    wide = ovt.pivot_table(index=["lambda_", "R_m", "record"], columns="case", values="min_overturn_g")
    ratio = {c: wide[c] / wide[ground] - 1.0 for c in isolated if ground is not None and c in wide}
    shown = blocks
    if len(blocks) > n_blocks:
        step = (len(blocks) - 1) / max(n_blocks - 1, 1)
        shown = [blocks[round(i * step)] for i in range(n_blocks)]
    lam_txt = f" (lambda {blocks[0][0]:g})" if one_lambda else ""
    intro = (
        f"Of {n_rec} records, those that overturn each block{lam_txt} at or below their own PGA, on the "
        "ground and on each isolator (in brackets: the median change of the block's overturning PGA)"
        + (f"; {len(shown)} of {len(blocks)} blocks" if len(shown) < len(blocks) else "")
        + ". All of it under 'Minimum overturning PGA'."
    )
    section = _Section("Minimum overturning PGA", intro)
    for lam, R in shown:
        g = ovt[(ovt["lambda_"] == lam) & (ovt["R_m"] == R)]
        head = (
            f"R {R:.3g} m" if one_lambda else f"lambda {lam:g}, R {R:.3g} m"
        ) + f", h {g.iloc[0]['h_m']:.2g} m"
        parts = []
        if ground is not None:
            ids = list(g[(g["case"] == ground) & g["below"]]["record"])
            parts.append(f"ground {len(ids)}" + (f" ({_names(ids)})" if ids else ""))
        for c in isolated:
            n = int(g[(g["case"] == c) & g["below"]]["below"].sum())
            r = _of_block(ratio[c], lam, R) if c in ratio else pd.Series(dtype=float)
            parts.append(f"{c} {n}" + (f" ({_pct(r.median())})" if len(r) else ""))
        section.bullets.append(f"{head}: " + "; ".join(parts) + ".")
    if ratio:
        med = {c: r.median() for c, r in ratio.items() if r.notna().any()}
        if med:
            best = max(med, key=lambda c: med[c])
            lower = {c: int((r < 0).sum()) for c, r in ratio.items()}
            n_pairs = {c: int(r.notna().sum()) for c, r in ratio.items()}
            worst = max(lower, key=lambda c: lower[c] / max(n_pairs[c], 1))
            text = f"{best} raises the overturning PGA most (median {_pct(med[best])})" + (
                f"; {worst} lowers it for {lower[worst]} of {n_pairs[worst]} record-block pairs."
                if lower[worst]
                else "; no isolator lowers it."
            )
            section.after.append(text)
    return section


def write_landing(
    store: Store, path: str | os.PathLike, figdir: Path | None, overturn: pd.DataFrame | None
) -> Path:
    """Write :func:`landing_text` atomically; returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(landing_text(store, figdir, overturn), encoding="utf-8")
    return path
