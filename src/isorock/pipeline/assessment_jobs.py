"""The assessment part of the workflow: one job per object, isolation case and record (the stripes),
one per object and record for the isolation design search, and the tables of ``/assessment`` that
the merge derives from them (:func:`assessment_tables`)."""

from __future__ import annotations

import itertools
import json
import math
import os
import time
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import h5py
import numpy as np
import pandas as pd

from .. import __version__
from ..assessment.design import design_table, recommend
from ..assessment.stripes import (
    AssessedObject,
    design_level_rows,
    fragility_rows,
    run_levels,
    stripe_table,
)
from ..model import LinearIsolation, System, make_isolation
from ..store import atomic_path, config_hash, write_tables
from ..store.hdf import read_table
from .config import case_from, grid_values, isolation_cases
from .jobs import read_job_record, say, search_row

__all__ = [
    "assess_record",
    "design_record",
    "assessment_tables",
    "design_isolations",
    "ASSESS_KEY",
    "DESIGN_KEY",
]

#: top-level groups of the job files (not copied into the store: the merge derives /assessment; the
#: merge skips these names)
ASSESS_KEY = "assess_jobs"
DESIGN_KEY = "design_jobs"


def _levels(stripes: Sequence[float], design: Sequence[float]) -> list[float]:
    return sorted({float(x) for x in (*stripes, *design)})


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
def assess_record(
    record_h5: str | os.PathLike,
    out: str | os.PathLike,
    *,
    obj: Mapping,
    case: Mapping,
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    search: Mapping,
    threads: int | None = None,
) -> pd.DataFrame:
    """Rule ``assess_stripes``: one object on one isolation under one record scaled to every stripe.

    Every run is a full run (peaks, displacement and contact reactions over the whole motion). The
    first overturning PGA of the record (:func:`isorock.overturning.min_overturn_amplitude`) is kept
    beside the stripes, as the table's attributes.

    Parameters
    ----------
    record_h5 : path-like
        Output of ``process_record``.
    out : path-like
        HDF5 file written with the table ``/assess_jobs/<object>/<case>/<record>``: one row per level
        (``pga_g`` [g], ``stripe``, ``design``, :data:`isorock.assessment.stripes.RUN_COLUMNS`).
    obj : mapping
        The object as configured (``name``, ``height_m``/``width_m`` or ``lambda``/``R_m``, ``friction``).
    case : mapping
        The isolation case (:class:`~isorock.pipeline.config.IsolationCase` fields).
    stripes_g, design_g : sequence of float
        Stripe PGAs and design levels [g].
    search : mapping
        ``amp_max_g``, ``growth``, ``rtol`` of the first-overturning search.
    threads : int, optional
        Threads of the parallel runs.
    """
    rid, gm, rattrs = read_job_record(record_h5)
    o = AssessedObject.from_config(obj)
    c = case_from(case)
    system = System(o.block(), c.isolation())
    levels = _levels(stripes_g, design_g)
    t0 = time.perf_counter()
    runs = run_levels([system], gm, levels, o.friction, threads=threads)
    stripes = {float(x) for x in stripes_g}
    design = {float(x) for x in design_g}
    runs.insert(0, "object", o.name)
    runs.insert(1, "case", c.name)
    runs.insert(2, "record", rid)
    runs["stripe"] = runs["pga_g"].isin(stripes)
    runs["design"] = runs["pga_g"].isin(design)
    runs = runs.drop(columns=["system"])
    for _, r in runs.iterrows():
        say(
            f"{o.name} / {c.name} / {rid}: {r['pga_g']:g} g -> {r['outcome']} "
            f"(max theta/alpha {r['max_theta_over_alpha']:.3g}, base {r['max_base_disp_m']:.3g} m, "
            f"mu_required {r['mu_required']:.3g})"
        )
    first = search_row(system, gm, search)
    secs = time.perf_counter() - t0
    say(f"{o.name} / {c.name} / {rid}: {len(runs)} runs and the first-overturning search in {secs:.1f} s")
    attrs = {
        "object": o.name,
        "case": c.name,
        "record": rid,
        "record_sha256": rattrs.get("record_sha256", ""),
        "record_pga_g": gm.pga_g,
        "first_overturn": json.dumps({k: first[k] for k in ("min_overturn_g", "uplift_g", "resolution")}),
        "config_hash": config_hash(
            {"obj": dict(obj), "case": dict(case), "levels": levels, "search": dict(search)}
        ),
        "seconds": secs,
        "isorock_version": __version__,
    }
    key = f"{ASSESS_KEY}/{o.name}/{c.name}/{rid}"
    with atomic_path(out) as tmp:
        write_tables(tmp, {key: runs}, {key: attrs})
    return runs


def design_record(
    record_h5: str | os.PathLike,
    out: str | os.PathLike,
    *,
    obj: Mapping,
    grid: Mapping,
    rho: float,
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    threads: int | None = None,
) -> pd.DataFrame:
    """Rule ``assess_design``: one object on every isolator of the design grid under one record, at
    every stripe and design level (table ``/design_jobs/<object>/<record>``, column ``isolator`` the
    index in :func:`design_isolations`)."""
    rid, gm, _ = read_job_record(record_h5)
    o = AssessedObject.from_config(obj)
    isos = design_isolations(grid, rho)
    systems = [System(o.block(), iso) for iso in isos]
    levels = _levels(stripes_g, design_g)
    t0 = time.perf_counter()
    runs = run_levels(systems, gm, levels, o.friction, threads=threads)
    secs = time.perf_counter() - t0
    runs = runs.rename(columns={"system": "isolator"})
    runs.insert(0, "object", o.name)
    runs.insert(1, "record", rid)
    say(f"{o.name} / {rid}: {len(isos)} isolators x {len(levels)} levels = {len(runs)} runs in {secs:.1f} s")
    attrs = {"object": o.name, "record": rid, "grid": json.dumps(dict(grid)), "rho": rho, "seconds": secs}
    key = f"{DESIGN_KEY}/{o.name}/{rid}"
    with atomic_path(out) as tmp:
        write_tables(tmp, {key: runs}, {key: attrs})
    return runs


# ------------------------------------------------------------------ the /assessment tables
def _table_keys(group: h5py.Group) -> list[str]:
    """Paths (relative to ``group``) of the pandas tables under it."""
    keys: list[str] = []

    def visit(name: str, obj: Any) -> None:
        if obj.attrs.get("pandas_type") is not None:
            keys.append(name)

    group.visititems(visit)
    return keys


def _job_tables(paths: Iterable[str | os.PathLike], top: str) -> list[tuple[pd.DataFrame, dict]]:
    out = []
    for p in paths:
        with h5py.File(p, "r") as h:
            if top not in h:
                continue
            keys = _table_keys(h[top])
            attrs = {k: {a: h[f"{top}/{k}"].attrs[a] for a in h[f"{top}/{k}"].attrs} for k in keys}
        for k in keys:
            df = read_table(p, f"{top}/{k}")
            out.append((df, {a: (v.decode() if isinstance(v, bytes) else v) for a, v in attrs[k].items()}))
    return out


def assessment_tables(paths: Iterable[str | os.PathLike], config: Mapping) -> dict[str, pd.DataFrame]:
    """The ``/assessment`` tables from the job files (empty when the configuration has no assessment).

    ``objects`` (one row per object: dimensions, lambda, R, friction), ``runs`` (every stripe and
    design run), ``first_overturn`` (per object, case and record), ``stripes`` (counts and displacement
    per level), ``fragility`` (median [g] and beta per object, case and damage state),
    ``design_levels`` (probabilities and displacement demand at each design level), ``validity``
    (runs outside the model), and with a design grid ``design`` (every isolator and design level,
    ``rank`` 1 = recommended).
    """
    a = config.get("assessment")
    if not a:
        return {}
    paths = list(paths)
    capacity = a.get("capacity_m")
    jobs = _job_tables(paths, ASSESS_KEY)
    objects = [AssessedObject.from_config(o) for o in a["objects"]]
    tables: dict[str, pd.DataFrame] = {"objects": pd.DataFrame([o.columns() for o in objects])}
    if not jobs:
        return tables
    runs = pd.concat([df for df, _ in jobs], ignore_index=True)
    tables["runs"] = runs
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
    st_rows, fr_rows, dl_rows, va_rows = [], [], [], []
    for o in objects:
        for cname in a["cases"]:
            r = runs[(runs["object"] == o.name) & (runs["case"] == cname)]
            if r.empty:
                continue
            cc = {"object": o.name, "case": cname, "isolation": cases[cname].kind}
            st = stripe_table(r[r["stripe"]], capacity)
            st_rows += [{**cc, **row} for row in st.to_dict("records")]
            fr = fragility_rows(st)
            fits = {row["damage"]: row.pop("_fit") for row in fr}
            fr_rows += [{**cc, **row} for row in fr]
            dl = design_level_rows(st, r[r["design"]], fits, a["design_g"], capacity)
            dl_rows += [{**cc, **row} for row in dl]
            va_rows.append(
                {**cc, "friction": o.friction, "n_runs": len(r), "n_slides": int(r["slides"].sum()),
                 "n_jumps": int(r["jumps"].sum()), "n_outside_model": int(r["outside_model"].sum()),
                 "mu_required_max": float(r["mu_required"].max())}
            )  # fmt: skip
    tables["stripes"] = pd.DataFrame(st_rows)
    tables["fragility"] = pd.DataFrame(fr_rows)
    tables["design_levels"] = pd.DataFrame(dl_rows)
    tables["validity"] = pd.DataFrame(va_rows)
    design_jobs = _job_tables(paths, DESIGN_KEY)
    if design_jobs and a.get("design_grid"):
        isos = design_isolations(a["design_grid"], float(config["isolation"]["rho"]))
        dres = []
        for o in objects:
            parts = [df for df, at in design_jobs if at["object"] == o.name]
            if not parts:
                continue
            d = pd.concat(parts, ignore_index=True).rename(columns={"isolator": "system"})
            tab = recommend(design_table(d, isos, a["stripes_g"], a["design_g"], capacity))
            tab.insert(0, "object", o.name)
            dres.append(tab)
        if dres:
            tables["design"] = pd.concat(dres, ignore_index=True)
    for name, df in tables.items():
        for col in df.columns:
            if df[col].dtype == bool:
                df[col] = df[col].astype(np.int8)
        tables[name] = df
    return tables
