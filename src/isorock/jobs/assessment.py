"""The assessment part of the workflow: one job per object, isolation case and block of records (the
stripes), one per object and block of records for the isolation design search, and the tables of
``/assessment`` that the merge derives from them (:func:`assessment_tables`).

A job file holds one table per record of its block (``/assess_jobs/<object>/<case>/<record>``,
``/design_jobs/<object>/<record>``, attribute ``position``: the record's place in the block), so that
the merge reads the same tables, in the same order, whatever the size of the blocks
(``resources.records_per_job``: :func:`isorock.control.plan.record_blocks`). The fits of the merge
(:mod:`isorock.assessment.case`, :mod:`~isorock.assessment.design`: scipy.stats) are imported when it
needs them, not by the jobs, whose Python start-up is part of their time."""

from __future__ import annotations

import itertools
import json
import math
import os
import time
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from isorock.assessment.design import candidate_params
from isorock.assessment.scaling import Scaling, record_basis
from isorock.assessment.stripes import AssessedObject
from isorock.control.config import case_from, grid_values, isolation_cases
from isorock.control.joblog import say
from isorock.jobs.jobfiles import ASSESS_KEY, DESIGN_KEY, _add_measures, _job_tables, _period
from isorock.jobs.record import read_job_record, search_row
from isorock.parallel import fork_map
from isorock.physics.model import LinearIsolation, NoIsolation, make_isolation
from isorock.store import atomic_path, config_hash, write_tables
from isorock.version import __version__

if TYPE_CHECKING:
    from isorock.assessment.case import Settings

__all__ = [
    "assess_records",
    "design_records",
    "assessment_tables",
    "design_isolations",
    "ASSESS_KEY",
    "DESIGN_KEY",
]


def _levels(stripes: Sequence[float], design: Sequence[float], mce: Sequence[float] = ()) -> list[float]:
    return sorted({float(x) for x in (*stripes, *design, *mce)})


def _scaling(scaling: Mapping | None) -> Scaling:
    """The rule's ``scaling`` parameter (None: PGA of the analysed component)."""
    if not scaling:
        return Scaling()
    return Scaling(str(scaling["imt"]), str(scaling["component"]), str(scaling.get("basis", "")))


def design_isolations(grid: Mapping, rho: float) -> list:
    """The isolators of a design grid (``{kind: linear, Tb_s, xi_b}`` or ``{kind: fp, mu_b, R_b_m}``)."""
    if grid["kind"] == "linear":
        return [
            LinearIsolation(Tb, xi, rho)
            for Tb, xi in itertools.product(grid_values(grid["Tb_s"]), grid_values(grid["xi_b"]))
        ]
    return [
        make_isolation("fp", mu_b=mu, R_b_m=Rb, rho=rho)
        for mu, Rb in itertools.product(grid_values(grid["mu_b"]), grid_values(grid["R_b_m"]))
    ]


# ------------------------------------------------------------------ the jobs
def _records(record_h5: str | os.PathLike | Sequence[str | os.PathLike]) -> list[str | os.PathLike]:
    """One path, or a block of them, as a list."""
    return [record_h5] if isinstance(record_h5, str | os.PathLike) else list(record_h5)


_FIRST_KEYS = (
    "min_overturn_g",
    "uplift_g",
    "resolution",
    "min_overturn_as_recorded_g",
    "min_overturn_reversed_g",
)
"""The first-overturning search's values kept per record (the last two for an asymmetric body only)."""


def _stripes_one(
    record_h5: str | os.PathLike,
    *,
    obj: Mapping,
    case: Mapping,
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    search: Mapping,
    mce_g: Sequence[float],
    threads: int | None,
    vertical: bool,
    scaling: Mapping | None,
) -> tuple[str, pd.DataFrame, dict]:
    """The table of one record of :func:`assess_records`: (key, runs, attributes)."""
    rid, gm, rattrs = read_job_record(record_h5, vertical=vertical)
    sc = _scaling(scaling)
    basis = record_basis(rid, gm, rattrs, sc)
    o = AssessedObject.from_config(obj)
    c = case_from(case)
    system = o.system(c.isolation())
    levels = _levels(stripes_g, design_g, mce_g)
    t0 = time.perf_counter()
    runs = o.runs([system], gm, levels, basis=basis, threads=threads)
    runs = _add_measures(runs, gm, [_period(system.isolation)])
    stripes = {float(x) for x in stripes_g}
    design = {float(x) for x in design_g}
    runs.insert(0, "object", o.name)
    runs.insert(1, "case", c.name)
    runs.insert(2, "record", rid)
    runs["stripe"] = runs["level"].isin(stripes)
    runs["design"] = runs["level"].isin(design)
    runs["mce"] = runs["level"].isin({float(x) for x in mce_g})
    runs = runs.drop(columns=["system"])
    for _, r in runs.iterrows():
        if o.slides:
            say(
                f"{o.name} / {c.name} / {rid}: {r['level']:g} {sc.unit} -> slides "
                f"{r['sliding_peak_m']:.3g} m "
                f"({r['n_slips']} slips, base {r['max_base_disp_m']:.3g} m)"
            )
            continue
        say(
            f"{o.name} / {c.name} / {rid}: {r['level']:g} {sc.unit} -> {r['outcome']} "
            f"(max theta/alpha {r['max_theta_over_alpha']:.3g}, base {r['max_base_disp_m']:.3g} m, "
            f"mu_required {r['mu_required']:.3g})"
        )
    # an object that slides never rocks: it has no overturning PGA to search for
    first = (
        {"min_overturn_g": None, "uplift_g": None, "resolution": None}
        if o.slides
        else search_row(system, gm, search, polarities=o.polarities)
    )
    secs = time.perf_counter() - t0
    say(f"{o.name} / {c.name} / {rid}: {len(runs)} runs and the first-overturning search in {secs:.1f} s")
    attrs = {
        "object": o.name,
        "case": c.name,
        "record": rid,
        "record_sha256": rattrs.get("record_sha256", ""),
        "record_pga_g": gm.pga_g,
        "imt": sc.imt,
        "component": sc.component,
        "record_basis": basis,
        "first_overturn": json.dumps({k: first[k] for k in _FIRST_KEYS if k in first}),
        "config_hash": config_hash(
            {"obj": dict(obj), "case": dict(case), "levels": levels, "search": dict(search)}
            | ({"vertical": True} if vertical else {})
            | ({"scaling": [sc.imt, sc.component]} if scaling else {})
        ),
        "seconds": secs,
        "isorock_version": __version__,
    }
    return f"{ASSESS_KEY}/{o.name}/{c.name}/{rid}", runs, attrs


def _write_block(out: str | os.PathLike, parts: Sequence[tuple[str, pd.DataFrame, dict]]) -> pd.DataFrame:
    """The tables of a block into one job file (atomically), each with its ``position`` in the block;
    returns them stacked."""
    tables = {key: df for key, df, _ in parts}
    attrs = {key: {**at, "position": k} for k, (key, _, at) in enumerate(parts)}
    with atomic_path(out) as tmp:
        write_tables(tmp, tables, attrs)
    return pd.concat([df for _, df, _ in parts], ignore_index=True)


def assess_records(
    record_h5: str | os.PathLike | Sequence[str | os.PathLike],
    out: str | os.PathLike,
    *,
    obj: Mapping,
    case: Mapping,
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    search: Mapping,
    mce_g: Sequence[float] = (),
    threads: int | None = None,
    vertical: bool = False,
    scaling: Mapping | None = None,
) -> pd.DataFrame:
    """Rule ``assess_stripes``: one object on one isolation under each record of a block, scaled to
    every stripe.

    Every run is a full run (peaks, displacement and contact reactions over the whole motion). The
    first overturning PGA of each record (:func:`isorock.physics.overturning.min_overturn_amplitude`) is kept
    beside the stripes, as its table's attributes.

    Parameters
    ----------
    record_h5 : path-like or sequence of path-like
        Outputs of ``process_record``: one record, or the block of records of the job.
    out : path-like
        HDF5 file written with one table ``/assess_jobs/<object>/<case>/<record>`` per record: one row
        per level (``level`` [g], ``stripe``, ``design``, :data:`isorock.assessment.stripes.RUN_COLUMNS`);
        its attribute ``position`` is the record's place in ``record_h5``.
    obj : mapping
        The object as configured (``name``, ``height_m``/``width_m`` or ``lambda``/``R_m``, ``friction``).
    case : mapping
        The isolation case (:class:`~isorock.control.config.IsolationCase` fields).
    stripes_g, design_g : sequence of float
        Stripe PGAs and design levels [g].
    search : mapping
        ``amp_max_g``, ``growth``, ``rtol`` of the first-overturning search.
    mce_g : sequence of float
        The maximum considered earthquake levels [g] (the displacement check).
    threads : int, optional
        Threads of the parallel runs.
    vertical : bool
        Include each record's vertical where it has one (``records.vertical``).
    scaling : mapping, optional
        ``{imt, component}`` of the stripes (:class:`isorock.assessment.scaling.Scaling`; None: PGA of
        the analysed component).

    Returns
    -------
    pandas.DataFrame
        The runs of every record, stacked in the order of ``record_h5``.
    """
    kw = {"obj": obj, "case": case, "stripes_g": stripes_g, "design_g": design_g, "search": search}
    parts = [
        _stripes_one(p, **kw, mce_g=mce_g, threads=threads, vertical=vertical, scaling=scaling)
        for p in _records(record_h5)
    ]
    return _write_block(out, parts)


def _design_one(
    record_h5: str | os.PathLike,
    *,
    obj: Mapping,
    grid: Mapping,
    rho: float,
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    mce_g: Sequence[float],
    threads: int | None,
    vertical: bool,
    scaling: Mapping | None,
) -> tuple[str, pd.DataFrame, dict]:
    """The table of one record of :func:`design_records`: (key, runs, attributes)."""
    rid, gm, rattrs = read_job_record(record_h5, vertical=vertical)
    basis = record_basis(rid, gm, rattrs, _scaling(scaling))
    o = AssessedObject.from_config(obj)
    isos = [NoIsolation(), *design_isolations(grid, rho)]
    systems = [o.system(iso) for iso in isos]
    levels = _levels(stripes_g, design_g, mce_g)
    t0 = time.perf_counter()
    runs = o.runs(systems, gm, levels, basis=basis, threads=threads)
    runs = _add_measures(runs, gm, [_period(iso) for iso in isos])
    secs = time.perf_counter() - t0
    runs = runs.rename(columns={"system": "isolator"})
    runs.insert(0, "object", o.name)
    runs.insert(1, "record", rid)
    say(
        f"{o.name} / {rid}: the fixed base and {len(isos) - 1} isolators x {len(levels)} levels = "
        f"{len(runs)} runs in {secs:.1f} s"
    )
    attrs = {"object": o.name, "record": rid, "grid": json.dumps(dict(grid)), "rho": rho, "seconds": secs}
    return f"{DESIGN_KEY}/{o.name}/{rid}", runs, attrs


def design_records(
    record_h5: str | os.PathLike | Sequence[str | os.PathLike],
    out: str | os.PathLike,
    *,
    obj: Mapping,
    grid: Mapping,
    rho: float,
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    mce_g: Sequence[float] = (),
    threads: int | None = None,
    vertical: bool = False,
    scaling: Mapping | None = None,
) -> pd.DataFrame:
    """Rule ``assess_design``: one object on the fixed base and on every isolator of the design grid
    under each record of a block, at every stripe, design and MCE level (one table
    ``/design_jobs/<object>/<record>`` per record, attribute ``position`` its place in ``record_h5``;
    column ``isolator``: 0 the fixed base, ``k`` >= 1 the isolator ``k - 1`` of
    :func:`design_isolations`). ``record_h5``: one output of ``process_record``, or the job's block of
    them; ``vertical``: include each record's vertical where it has one. Returns the runs of every
    record, stacked in the order of ``record_h5``."""
    kw = {"obj": obj, "grid": grid, "rho": rho, "stripes_g": stripes_g, "design_g": design_g}
    parts = [
        _design_one(p, **kw, mce_g=mce_g, threads=threads, vertical=vertical, scaling=scaling)
        for p in _records(record_h5)
    ]
    return _write_block(out, parts)


# ------------------------------------------------------------------ the /assessment tables
def measure_row(settings: Settings) -> dict[str, Any]:
    """The one row of ``/assessment/measure``: the stripes' measure, its unit and component definition,
    why that one, and the hazard curve's measure, definition and source (empty without one)."""
    sc, h = settings.scaling, settings.hazard
    hz = {} if h is None else h.to_dict()
    return {
        "imt": sc.imt,
        "unit": sc.unit,
        "component": sc.component,
        "label": sc.label,
        "basis": sc.basis,
        "hazard_source": "" if h is None else (h.describe() if hasattr(h, "describe") else h.source),
        "hazard_file": "" if h is None else str(h.source),
        "hazard_imt": str(hz.get("imt", "")),
        "hazard_component_definition": str(hz.get("component_definition", "")),
        "hazard_kind": str(hz.get("kind", "")),
        "hazard_site": str(hz.get("site", "")),
        "hazard_vs30_m_s": math.nan if hz.get("vs30_m_s") is None else float(hz["vs30_m_s"]),
        "hazard_notes": json.dumps(list(hz.get("notes", []))),
    }


def assessment_tables(
    paths: Iterable[str | os.PathLike], config: Mapping, workers: int = 1
) -> dict[str, pd.DataFrame]:
    """The ``/assessment`` tables from the job files (empty when the configuration has no assessment).

    ``objects`` (one row per object: dimensions, lambda, R, friction), ``runs`` (every stripe, design and
    MCE run, with its failure modes), ``first_overturn`` (per object, case and record), ``stripes``
    (per level the counts of every failure mode and the displacement), ``fragility`` (per object, case
    and damage state, overturn, failure and uplift: median [g] and beta with their 95 % intervals, or
    why they are not estimable), ``design_levels`` (per design level the probabilities with their
    intervals and what was observed, the displacement, the MCE check), ``validity`` (runs outside the
    model), with a hazard curve ``hazard`` (annual frequencies and 50-year probabilities), and with a
    design grid ``design`` (every candidate, the fixed base and the cases included, at every design
    level, ``rank`` 1 the lowest estimate, ``recommended``, ``equivalent``).
    """
    a = config.get("assessment")
    if not a:
        return {}
    import scipy.stats  # noqa: F401  the fits' exact intervals: here, not in each forked worker

    from isorock.assessment.case import Settings  # scipy.stats: only when merging

    paths = list(paths)
    settings = Settings.from_config(a)
    jobs = _job_tables(paths, ASSESS_KEY, workers)
    objects = [AssessedObject.from_config(o) for o in a["objects"]]
    tables: dict[str, pd.DataFrame] = {
        "objects": pd.DataFrame([o.columns() for o in objects]),
        "measure": pd.DataFrame([measure_row(settings)]),
    }
    if not jobs:
        return tables
    runs = pd.concat([df for df, _ in jobs], ignore_index=True)
    if "mce" not in runs:
        runs["mce"] = False
    from isorock.assessment.stripes import classify_runs

    tables["runs"] = classify_runs(runs, settings.capacity_factored_m)
    first = []
    for _df, at in jobs:
        f = json.loads(at["first_overturn"])
        f = {k: (math.nan if v is None else v) for k, v in f.items()}
        first.append(
            {"object": at["object"], "case": at["case"], "record": at["record"],
             "record_pga_g": float(at["record_pga_g"]), **f}
        )  # fmt: skip
    tables["first_overturn"] = pd.DataFrame(first)
    cases = isolation_cases(config)
    case_runs = _case_tables(runs, objects, a["cases"], cases, settings, tables, workers)
    from isorock.jobs.design import design_tables

    tables.update(design_tables(paths, config, objects, cases, case_runs, settings, workers))
    extra = tables.pop("candidate_runs", None)
    r = tables["runs"]
    params = {n: candidate_params(cases[n].isolation()) for n in r["case"].unique()}
    r["candidate"] = r["case"]
    r["source"] = ["floor" if params[n]["isolation"] == "none" else "case" for n in r["case"]]
    for key in ("isolation", "Tb_s", "xi_b", "mu_b", "R_b_m", "rho"):
        r[key] = [math.nan if params[n][key] is None else params[n][key] for n in r["case"]]
    if extra is not None and len(extra):
        # every candidate's runs, the design search's included: the store alone reproduces a verdict
        tables["runs"] = pd.concat([tables["runs"], extra], ignore_index=True)
    for name, df in tables.items():
        for col in df.columns:
            if df[col].dtype == bool:
                df[col] = df[col].astype(np.int8)
            elif df[col].dtype == object:
                vals = df[col].dropna()
                if len(vals) and vals.map(lambda v: isinstance(v, bool | np.bool_)).all():
                    # flags with gaps (None where they do not apply): 1.0, 0.0, NaN
                    df[col] = df[col].map(lambda v: math.nan if v is None or v != v else float(bool(v)))
        tables[name] = df
    return tables


def _case_tables(
    runs: pd.DataFrame,
    objects: Sequence[AssessedObject],
    case_names: Sequence[str],
    cases: Mapping[str, Any],
    settings: Settings,
    tables: dict[str, pd.DataFrame],
    workers: int = 1,
) -> dict[tuple[str, str], pd.DataFrame]:
    """The per-case tables (stripes, fragility, design_levels, validity, hazard) into ``tables``;
    returns the runs of each (object, case). The cases are evaluated on ``workers`` processes."""
    from isorock.assessment.case import evaluate, table_row
    from isorock.assessment.stripes import classify_runs

    st_rows, fr_rows, dl_rows, va_rows, hz_rows, band_rows, im_rows = [], [], [], [], [], [], []
    top = max(settings.levels) * 1.15
    x_band = np.linspace(top / 100, top, 60)
    case_runs: dict[tuple[str, str], pd.DataFrame] = {}
    records = sorted(runs["record"].unique())  # every base on the same resamples of the same records
    todo = []
    for o in objects:
        for cname in case_names:
            r = runs[(runs["object"] == o.name) & (runs["case"] == cname)]
            if not r.empty:
                case_runs[(o.name, cname)] = r
                todo.append((o, cname, r))

    def one(task: tuple[AssessedObject, str, pd.DataFrame]):
        _o, cname, r = task
        return evaluate(r, settings, candidate_params(cases[cname].isolation()), records=records)

    for (o, cname, r), ev in zip(todo, fork_map(one, todo, workers), strict=True):
        cc = {"object": o.name, "case": cname, "isolation": cases[cname].kind}
        st_rows += [{**cc, **row} for row in ev.stripes.to_dict("records")]
        fr_rows += [{**cc, **row} for row in ev.fragility_rows()]
        band_rows += [{**cc, **row} for row in ev.band_rows(x_band)]
        im_rows += [{**cc, **table_row(row)} for row in ev.by_measure]
        dl_rows += [{**cc, **table_row(row)} for row in ev.levels]
        if ev.hazard is not None:
            hz_rows += [{**cc, "damage": d, **table_row(h)} for d, h in ev.hazard.items()]
        st = r[r["stripe"]]
        va_rows.append(
            {
                **cc,
                "friction": o.friction,
                "tan_alpha": o.block().tan_alpha,
                "mode": "sliding" if o.slides else "rocking",
                "n_slid": int((st["n_slips"] > 0).sum()) if "n_slips" in st else 0,
                "n_slides_beyond": int(classify_runs(st, None)["slides_beyond"].sum()),
                "n_runs": len(st),
                "n_slides": int(st["slides"].sum()),
                "n_jumps": int(st["jumps"].sum()),
                "n_outside_model": int(st["outside_model"].sum()),
                "mu_required_max": float(st["mu_required"].max()),
                "outside_model_rule": settings.outside_model,
                "n_records": ev.n_records,
            }
        )
    tables["stripes"] = pd.DataFrame(st_rows)
    tables["fragility"] = pd.DataFrame(fr_rows)
    tables["fragility_band"] = pd.DataFrame(band_rows)
    if im_rows:
        tables["fragility_by_measure"] = pd.DataFrame(im_rows)
    tables["design_levels"] = pd.DataFrame(dl_rows)
    tables["validity"] = pd.DataFrame(va_rows)
    if hz_rows:
        tables["hazard"] = pd.DataFrame(hz_rows)
    return case_runs
