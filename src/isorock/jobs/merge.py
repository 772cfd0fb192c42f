"""Rule ``merge``: the job files of a run -> ``results/isorock.h5`` (layout in :mod:`isorock.store`)."""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from isorock.constants import OUTCOME_LEGEND
from isorock.environment import store_attrs
from isorock.version import __version__

# h5py, pandas and the store's table modules are imported by merge() itself: isorock.pipeline imports
# this module, and the commands that read only the cost model (isorock map, min-overturn) need none

#: what each /assessment table holds
ASSESSMENT_TABLES = {
    "objects": "the objects assessed: dimensions [m], lambda, R [m], friction, tan(alpha)",
    "measure": "the stripes' intensity measure (imt, unit), its component definition (RotD50, RotD100 or "
    "analysed) and why, the hazard curve's measure, definition, kind, site, Vs30 [m/s] and source",
    "runs": "every full run of every candidate base (the design search's grid included, case "
    "design/<candidate>): object, case, record, level (in the measure of /assessment/measure), the "
    "analysed component's PGA [g], outcome, peaks, contact forces, failure modes, "
    "the base's parameters",
    "first_overturn": "first overturning PGA [g] of every record (the minimum-overturning search)",
    "stripes": "per stripe: records, counts of overturn, uplift, beyond the capacity, failure, outside the "
    "model; isolator displacement [m]",
    "fragility": "lognormal fragility (maximum likelihood, Baker 2015) per damage state (overturn, failure, "
    "uplift): median (in the stripes' measure), beta, 95 % bootstrap intervals (_lo, _hi), or why not "
    "estimable",
    "fragility_band": "fitted P(damage | level) and its 95 % bootstrap band on a grid of levels of the "
    "stripes' measure",
    "design_levels": "at each design level: P(overturn), P(failure), P(uplift) with 95 % intervals, the "
    "fractions observed with their exact binomial bounds, displacement [m], the check at the MCE level",
    "validity": "runs outside the model: sliding (mu_required > friction) or jumping; how they count",
    "hazard": "with a hazard curve: mean annual frequency [1/yr] and 50-year probability of overturning and "
    "of failure, with 95 % intervals",
    "design": "the candidates (fixed base, isolated cases, design grid) per design level: P(failure) or "
    "annual frequency with 95 % intervals, adequacy against the target (target_estimate, adequate), "
    "P(failure) at the MCE (p_failure_mce), the paired differences from the fixed base and from the best "
    "(vs_floor_*, vs_best_*, with vs_floor_p_adjusted the familywise p-value), MCE displacement [m] times "
    "gamma_x vs capacity, rank, recommended, equivalent",
    "verdicts": "per object and design level: the verdict (isolate, fixed_base, restrain, inconclusive), "
    "why, the target (JSON), the recommended, best and closest candidates, the levels and their bases, "
    "what the grid's search did (JSON)",
}


__all__ = ["merge"]


def merge(
    inputs: Iterable[str | os.PathLike],
    out: str | os.PathLike,
    *,
    config: Mapping,
    source: str = "",
    config_name: str = "",
    threads: int = 1,
) -> dict:
    """Rule ``merge``: the job files -> ``results/isorock.h5`` (layout in :mod:`isorock.store`).

    Groups are merged as they are (records, overturn tables, maps); the per-shape pulse tables are
    stacked into ``/pulses/overturn_R``, ``/pulses/overturn_omega`` and ``/pulses/overturn_isolation``;
    the ``extract_pulse`` attributes of :data:`isorock.store.RECORD_ATTRS` (Tp, pulse indicator) are
    copied from ``/records/<id>/pulse`` onto ``/records/<id>``; the summary tables
    (``/summary/records``: columns :data:`isorock.store.RECORD_SUMMARY_COLUMNS`; ``/summary/overturn``,
    ``/summary/maps``) and ``/pulses/restitution`` (:func:`isorock.store.restitution_table`) are added;
    the root gets the configuration and its hash, and the versions of Python and of the numerical
    packages and the platform of the merge (:func:`isorock.environment.store_attrs`).

    Parameters
    ----------
    inputs : iterable of path-like
        Outputs of the job rules.
    out : path-like
        The merged file (written atomically).
    config : mapping
        The validated configuration (stored as JSON; its hash is ``config_hash``).
    source : str
        Where the records came from.
    config_name : str
        Name of the configuration (its file name without extension), written as ``config_name``.
    threads : int
        Processes that fit the assessment's bases at once (the same numbers as one).

    Returns
    -------
    dict
        Counts: records, overturn rows, maps.
    """
    import h5py
    import pandas as pd

    from isorock.store import (
        RECORD_ATTRS,
        RECORD_SUMMARY_COLUMNS,
        atomic_path,
        attr,
        config_hash,
        map_index,
        merge_h5,
        read_table,
        restitution_table,
        stamp,
        write_tables,
    )

    # the record attributes of ``extract_pulse``, copied from ``/records/<id>/pulse`` onto ``/records/<id>``
    pulse_attrs = tuple(a for a in RECORD_ATTRS if a.job == "extract_pulse")
    # columns of ``/summary/records`` stored as str, and as bool
    summary_text = tuple(a.name for a in RECORD_ATTRS if a.summary and a.kind in ("text", "json"))
    summary_flags = tuple(a.name for a in RECORD_ATTRS if a.summary and a.kind == "flag")
    inputs = [Path(p) for p in inputs]
    pulse_tables: dict[str, list] = {"overturn_R": [], "overturn_omega": [], "overturn_isolation": []}
    overturn: list = []
    plain = []
    for p in inputs:
        with h5py.File(p, "r") as h:
            keys = list(h.keys())
            if "pulses" in keys:
                for shape in h["pulses"]:
                    for t in h["pulses"][shape]:
                        pulse_tables.setdefault(t, []).append((p, f"pulses/{shape}/{t}"))
            if "overturn" in keys:
                overturn += [(p, f"overturn/{rid}") for rid in h["overturn"]]
            if any(k != "pulses" for k in keys):
                plain.append(p)
    tables: dict[str, Any] = {}
    cfg = json.loads(json.dumps(config, default=str))
    common = {"config_hash": config_hash(cfg), "isorock_version": __version__}
    table_attrs: dict[str, dict] = {}
    for name, parts in pulse_tables.items():
        if parts:
            key = f"pulses/{name}"
            tables[key] = pd.concat([read_table(p, k) for p, k in parts], ignore_index=True)
            with h5py.File(parts[0][0], "r") as h:
                first = h[parts[0][1]].attrs
                extra = {k: attr(h[parts[0][1]], k) for k in ("search", "lambda", "amplitude") if k in first}
            table_attrs[key] = {**extra, **common, "shapes": sorted(set(tables[key]["pulse"]))}
    tables["pulses/restitution"] = restitution_table()
    table_attrs["pulses/restitution"] = {
        **common,
        "description": "impact coefficients of docs/model.md section 7 (Fig 3): eps and beta1/h vs lambda",
    }
    if overturn:
        tables["summary/overturn"] = pd.concat([read_table(p, k) for p, k in overturn], ignore_index=True)
        table_attrs["summary/overturn"] = {**common, "description": "all /overturn/<id> tables stacked"}

    with atomic_path(out) as tmp:
        with h5py.File(tmp, "w") as f:
            stamp(f)
            merge_h5(plain, f, skip=("pulses", "assess_jobs", "design_jobs", "design_extend"))
            rec_rows = []
            for rid, g in f["records"].items() if "records" in f else []:
                if "pulse" in g:
                    for a in pulse_attrs:
                        if a.name in g["pulse"].attrs:
                            v = g["pulse"].attrs[a.name]
                            g.attrs[a.name] = np.nan if a.kind != "text" and isinstance(v, str) else v
                row = {k: attr(g, k) for k in RECORD_SUMMARY_COLUMNS if k != "record"}
                row["record"] = rid
                rec_rows.append(row)
            maps = map_index(f)
            f.attrs["config_hash"] = common["config_hash"]
            f.attrs["config_name"] = config_name
            f.attrs["config_json"] = json.dumps(cfg, sort_keys=True)
            f.attrs["created_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
            f.attrs["outcome_legend"] = OUTCOME_LEGEND
            f.attrs["record_source"] = source
            # what the store was made of: a run finds one of them deleted (pipeline.run.previous_results)
            f.attrs["job_files_json"] = json.dumps(sorted(str(p) for p in inputs))
            for k, v in store_attrs().items():  # version_python, version_numpy, ..., platform
                f.attrs[k] = v
            f.attrs["description"] = (
                "isorock results: rocking of rigid blocks on isolated bases; layout in the docstring of "
                "isorock.store"
            )
        if rec_rows:
            df = pd.DataFrame(rec_rows, columns=list(RECORD_SUMMARY_COLUMNS))
            for c in summary_text:
                df[c] = df[c].astype(str)
            for c in summary_flags:
                df[c] = df[c].map(
                    lambda v: bool(v) if not (isinstance(v, float) and math.isnan(v)) else False
                )
            tables["summary/records"] = df
        if len(maps):
            tables["summary/maps"] = maps
        for key in ("summary/records", "summary/maps"):
            table_attrs[key] = common
        from isorock.jobs.assessment import (
            assessment_tables,  # scipy.optimize, scipy.stats: only when merging
        )

        for name, df in assessment_tables(inputs, cfg, workers=threads).items():
            tables[f"assessment/{name}"] = df
            table_attrs[f"assessment/{name}"] = {**common, "description": ASSESSMENT_TABLES.get(name, "")}
        write_tables(tmp, tables, table_attrs)
        if "assessment/measure" in tables:  # the stripes' measure on the group, for readers of the HDF5
            m = tables["assessment/measure"].iloc[0]
            with h5py.File(tmp, "a") as f:
                f["assessment"].attrs["imt"] = str(m["imt"])
                f["assessment"].attrs["component"] = str(m["component"])
                f["assessment"].attrs["unit"] = str(m["unit"])
    n = {
        "records": len(rec_rows),
        "overturn_rows": int(len(tables.get("summary/overturn", []))),
        "maps": len(maps),
        "pulse_rows": int(sum(len(tables[k]) for k in tables if k.startswith("pulses/overturn"))),
        "assessment_runs": int(len(tables.get("assessment/runs", []))),
    }
    print(f"merged {len(inputs)} job files into {out}: {n}", flush=True)
    return n
