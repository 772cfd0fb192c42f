"""The isolation design search of the workflow: the grid as candidates, a grid that settles itself, and
the merge's tables of the decision (``/assessment/design``, ``/assessment/verdicts``).

Rule ``assess_design`` (:func:`isorock.jobs.assessment.design_records`) runs the fixed base
and every isolator of the configured grid, per block of records. Rule ``assess_design_extend``
(:func:`design_extend`, one job per object, after every block of it) ranks them as the merge does
(:func:`isorock.assessment.design.rank`) and, when the best isolator lies on an end of the grid
(:func:`~isorock.assessment.design.grid_edges`), adds the next value of that axis, one step of the
grid's own spacing and never beyond the axis' bound (``design_grid.bounds``, default
:data:`~isorock.assessment.design.GRID_BOUNDS`), runs the new isolators on every record, and ranks
again: until the best is inside the grid or a bound is reached, which the job records
(``bounds_reached``). The merge ranks the final grid (:func:`grid_candidates`) with the configured
cases. The answer never asks the user to extend the grid: it says where the search stopped and why.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import h5py
import numpy as np
import pandas as pd

from isorock.assessment.design import GRID_BOUNDS, Candidate, candidate_params, extend_axis, grid_axes
from isorock.assessment.scaling import record_basis
from isorock.assessment.stripes import AssessedObject
from isorock.control.config import grid_values
from isorock.control.joblog import say
from isorock.jobs.record import read_job_record
from isorock.physics.model import NoIsolation, make_isolation
from isorock.store import atomic_path, write_tables
from isorock.store.hdf import read_table

__all__ = [
    "EXTEND_KEY",
    "MAX_ROUNDS",
    "GridSpec",
    "grid_candidates",
    "design_extend",
    "read_extension",
    "design_tables",
]

#: top-level group of the extension's job files (not copied into the store)
EXTEND_KEY = "design_extend"
#: rounds of extension at most (each adds one step at every end where the best lies)
MAX_ROUNDS = 20


@dataclass(frozen=True)
class GridSpec:
    """A design grid of the configuration.

    Attributes
    ----------
    kind : {"linear", "fp"}
    names : (str, str)
        Its two parameters (:func:`~isorock.assessment.design.grid_axes`).
    values : (list of float, list of float)
        The configured values of each, increasing.
    configured_values : (list of float, list of float)
        The same, in the order the configuration gives them (that of ``assess_design``'s isolators).
    spacing : (str, str)
        ``linear`` or ``log`` (how an axis is extended: its own step).
    bounds : ((float, float), (float, float))
        How far each axis may be extended (low, high), in its unit.
    extend : bool
        Whether the workflow extends the grid (``design_grid.extend``).
    """

    kind: str
    names: tuple[str, str]
    values: tuple[list[float], list[float]]
    spacing: tuple[str, str]
    bounds: tuple[tuple[float, float], tuple[float, float]]
    extend: bool = True

    @classmethod
    def from_config(cls, grid: Mapping[str, Any]) -> GridSpec:
        names = grid_axes(grid)
        b = grid.get("bounds") or {}
        given = tuple(grid_values(grid[n]) for n in names)
        values = tuple(sorted(v) for v in given)
        spacing = tuple(
            str(grid[n].get("spacing", "linear")) if isinstance(grid[n], Mapping) else "linear" for n in names
        )
        bounds = tuple(
            (
                min(float((b.get(n) or GRID_BOUNDS[n])[0]), v[0]),
                max(float((b.get(n) or GRID_BOUNDS[n])[1]), v[-1]),
            )
            for n, v in zip(names, values, strict=True)
        )
        return cls(
            str(grid["kind"]),
            names,  # type: ignore[arg-type]
            values,  # type: ignore[arg-type]
            spacing,  # type: ignore[arg-type]
            bounds,  # type: ignore[arg-type]
            bool(grid.get("extend", True)),
            given,  # type: ignore[arg-type]
        )

    def isolation(self, v0: float, v1: float, rho: float):
        """The isolator of the grid point ``(v0, v1)``."""
        return make_isolation(self.kind, **{self.names[0]: v0, self.names[1]: v1}, rho=rho)

    configured_values: tuple[list[float], list[float]] = ([], [])

    def configured(self) -> list[tuple[float, float]]:
        """The configured grid points, in the order of ``assess_design``'s isolators
        (:func:`~isorock.jobs.assessment.design_isolations`: the axes as configured, row-major)."""
        return [(float(a), float(b)) for a, b in itertools.product(*self.configured_values)]


def grid_candidates(
    axes: tuple[Sequence[float], Sequence[float]],
    runs: Mapping[tuple[float, float], pd.DataFrame],
    spec: GridSpec,
    rho: float,
) -> list[Candidate]:
    """The grid isolators of ``axes`` (their runs from ``runs``, keyed by grid point) as candidates,
    named ``grid-<k>`` in row-major order of the increasing axes, with their place on the grid."""
    a0, a1 = sorted(axes[0]), sorted(axes[1])
    shape = (len(a0), len(a1))
    out = []
    for i0, v0 in enumerate(a0):
        for i1, v1 in enumerate(a1):
            key = (float(v0), float(v1))
            if key not in runs:
                continue
            iso = spec.isolation(v0, v1, rho)
            k = i0 * shape[1] + i1
            out.append(Candidate(f"grid-{k}", "grid", candidate_params(iso), runs[key], (i0, i1), shape))
    return out


def split_design_runs(
    d: pd.DataFrame, spec: GridSpec
) -> tuple[pd.DataFrame, dict[tuple[float, float], pd.DataFrame]]:
    """The fixed base's runs and each configured grid point's, from the stacked ``assess_design``
    tables (column ``isolator``: 0 the fixed base, ``k`` >= 1 the configured point ``k - 1``)."""
    points = spec.configured()
    by_point = {p: d[d["isolator"] == k + 1] for k, p in enumerate(points)}
    return d[d["isolator"] == 0], by_point


def _run_points(
    points: Sequence[tuple[float, float]],
    gms: Sequence[tuple[str, Any, float]],
    obj: AssessedObject,
    spec: GridSpec,
    rho: float,
    levels: Sequence[float],
    threads: int | None,
) -> pd.DataFrame:
    """Full runs of the object on the isolators of ``points`` under every record (id, ground motion,
    its value of the stripes' measure: :func:`isorock.assessment.scaling.record_basis`), at every level."""
    from isorock.jobs.jobfiles import _add_measures, _period

    isos = [spec.isolation(v0, v1, rho) for v0, v1 in points]
    systems = [obj.system(iso) for iso in isos]
    parts = []
    for rid, gm, basis in gms:
        r = obj.runs(systems, gm, levels, basis=basis, threads=threads)
        r = _add_measures(r, gm, [_period(iso) for iso in isos])
        r.insert(0, "object", obj.name)
        r.insert(1, "record", rid)
        r["p0"] = [points[i][0] for i in r["system"]]
        r["p1"] = [points[i][1] for i in r["system"]]
        parts.append(r.drop(columns=["system"]))
    return pd.concat(parts, ignore_index=True)


def design_extend(
    design_h5: Sequence[str | os.PathLike],
    record_h5: Sequence[str | os.PathLike],
    out: str | os.PathLike,
    *,
    obj: Mapping,
    assessment: Mapping,
    rho: float,
    levels_g: Sequence[float],
    threads: int | None = None,
    vertical: bool = False,
) -> dict[str, Any]:
    """Rule ``assess_design_extend``: extend one object's design grid until its best isolator is inside
    it or a bound is reached (see the module docstring).

    Parameters
    ----------
    design_h5 : sequence of path-like
        The object's ``assess_design`` job files (every block).
    record_h5 : sequence of path-like
        The processed records (``process_record`` outputs), every record of the run.
    out : path-like
        HDF5 file written with ``/design_extend/<object>/runs`` (the runs of the added isolators, if
        any: ``p0``, ``p1`` their two grid parameters, and the columns of ``assess_design``) and the
        attributes of the group ``/design_extend/<object>``: ``axes`` (JSON: the final values of the
        two axes), ``names``, ``bounds_reached``
        (JSON list of ``{parameter, side, bound}``), ``rounds``, ``added``, ``extended``, ``seconds``.
    obj : mapping
        The object as configured.
    assessment : mapping
        The validated ``assessment`` section (the same ranking as the merge's).
    rho : float
        Mass ratio of the grid's isolators [-].
    levels_g : sequence of float
        Every level the records are run at [g] (stripes, design, MCE).
    threads : int, optional
        Threads of the runs.

    Returns
    -------
    dict
        The attributes written.
    """
    from isorock.assessment.case import Settings
    from isorock.assessment.design import evaluate_candidates, rank
    from isorock.jobs.jobfiles import DESIGN_KEY, _job_tables

    t0 = time.perf_counter()
    o = AssessedObject.from_config(obj)
    spec = GridSpec.from_config(assessment["design_grid"])
    settings = Settings.from_config(assessment)
    parts = [df for df, at in _job_tables(design_h5, DESIGN_KEY, threads or 1) if at["object"] == o.name]
    d = pd.concat(parts, ignore_index=True)
    floor_runs, runs = split_design_runs(d, spec)
    axes = (list(spec.values[0]), list(spec.values[1]))
    added: list[pd.DataFrame] = []
    reached: list[dict[str, Any]] = []
    gms: list[tuple[str, Any, float]] | None = None
    rounds = 0
    # each round evaluates only the isolators it added: the others' runs and records are the same
    evaluated: dict[tuple, Any] = {}
    while spec.extend and rounds < MAX_ROUNDS:
        cands = [Candidate("none", "floor", candidate_params(NoIsolation()), floor_runs)]
        cands += grid_candidates(axes, runs, spec, rho)
        evaluate_candidates(cands, settings, evaluated, workers=threads or 1)
        edges = sorted({e for lvl in rank(cands, settings) for e in lvl["edges"]})
        new = (list(axes[0]), list(axes[1]))
        for ax, side in edges:
            lo, hi = spec.bounds[ax]
            v = extend_axis(axes[ax], side, lo if side == "low" else hi, spec.spacing[ax])
            if v is None:
                hit = {"parameter": spec.names[ax], "side": side, "bound": lo if side == "low" else hi}
                if hit not in reached:
                    reached.append(hit)
                continue
            new[ax].append(v)
        if len(new[0]) == len(axes[0]) and len(new[1]) == len(axes[1]):
            break
        axes = (sorted(new[0]), sorted(new[1]))
        points = [p for p in itertools.product(*axes) if (float(p[0]), float(p[1])) not in runs]
        if gms is None:
            gms = []
            for p in record_h5:
                rid, gm, rattrs = read_job_record(p, vertical=vertical)
                gms.append((rid, gm, record_basis(rid, gm, rattrs, settings.scaling)))
        rounds += 1
        where = ", ".join(f"{spec.names[a]} {side}" for a, side in edges)
        say(
            f"{o.name}: the best isolator is on the grid's edge ({where}): round {rounds} adds "
            f"{len(points)} isolators ({spec.names[0]} {axes[0][0]:g}-{axes[0][-1]:g}, "
            f"{spec.names[1]} {axes[1][0]:g}-{axes[1][-1]:g})"
        )
        r = _run_points(points, gms, o, spec, rho, levels_g, threads)
        added.append(r)
        for p in points:
            key = (float(p[0]), float(p[1]))
            runs[key] = r[(r["p0"] == key[0]) & (r["p1"] == key[1])]
    attrs = {
        "object": o.name,
        "names": json.dumps(list(spec.names)),
        "axes": json.dumps([list(map(float, axes[0])), list(map(float, axes[1]))]),
        "bounds_reached": json.dumps(reached),
        "rounds": rounds,
        "added": int(sum(len(r.groupby(["p0", "p1"])) for r in added)),
        "extended": bool(rounds > 0),
        "seconds": time.perf_counter() - t0,
    }
    with atomic_path(out) as tmp:
        if added:
            write_tables(tmp, {f"{EXTEND_KEY}/{o.name}/runs": pd.concat(added, ignore_index=True)})
        with h5py.File(tmp, "a") as h:
            g = h.require_group(f"{EXTEND_KEY}/{o.name}")
            for k, v in attrs.items():
                g.attrs[k] = v
    hits = ", ".join(f"{h['parameter']} {h['side']} {h['bound']:g}" for h in reached)
    say(
        f"{o.name}: design grid {'extended' if rounds else 'not extended'} in {rounds} round(s), "
        f"{attrs['added']} isolators added" + (f"; bounds reached: {hits}" if reached else "")
    )
    return attrs


def read_extension(path: str | os.PathLike, obj: str) -> tuple[pd.DataFrame, dict[str, Any]]:
    """The runs of the isolators added to ``obj``'s grid and the extension's attributes (``axes`` and
    ``bounds_reached`` decoded)."""
    key = f"{EXTEND_KEY}/{obj}"
    with h5py.File(path, "r") as h:
        at = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in h[key].attrs.items()}
        have = "runs" in h[key]
    runs = read_table(path, f"{key}/runs") if have else pd.DataFrame({"p0": [], "p1": []})
    info = {
        "axes": json.loads(at["axes"]),
        "names": json.loads(at["names"]),
        "bounds_reached": json.loads(at["bounds_reached"]),
        "rounds": int(at["rounds"]),
        "added": int(at["added"]),
        "extended": bool(at["extended"]),
    }
    return runs, info


# ------------------------------------------------------------------ the merge's tables
def _extensions(paths: Sequence[str | os.PathLike]) -> dict[str, str | os.PathLike]:
    """The extension job file of each object among ``paths``."""
    out: dict[str, str | os.PathLike] = {}
    for p in paths:
        with h5py.File(p, "r") as h:
            if EXTEND_KEY in h:
                for name in h[EXTEND_KEY]:
                    out[name] = p
    return out


def _object_candidates(
    o: AssessedObject,
    config: Mapping,
    design_runs: pd.DataFrame | None,
    spec: GridSpec | None,
    cases: Mapping[str, Any],
    case_runs: Mapping[tuple[str, str], pd.DataFrame],
    extension: str | os.PathLike | None,
) -> tuple[list[Candidate], dict[str, Any]]:
    """The candidates of one object (the fixed base, the isolated cases, the final grid) and what the
    grid's search did (``extended``, ``bounds_reached``, ``rounds``, ``added``, ``axes``, ``extend``)."""
    a = config["assessment"]
    cands = []
    info: dict[str, Any] = {"extended": False, "bounds_reached": [], "rounds": 0, "added": 0}
    have_grid = design_runs is not None and spec is not None
    if have_grid:
        floor_runs, by_point = split_design_runs(design_runs, spec)
        cands.append(Candidate("none", "floor", candidate_params(NoIsolation()), floor_runs))
    for cname in a["cases"]:
        if (o.name, cname) not in case_runs:
            continue
        fixed = cases[cname].kind == "none"
        if fixed and cands:
            continue  # the design job's fixed base is the floor
        iso = candidate_params(cases[cname].isolation())
        cands.append(Candidate(cname, "floor" if fixed else "case", iso, case_runs[(o.name, cname)]))
    if not have_grid:
        return cands, {}
    assert spec is not None
    axes = (list(spec.values[0]), list(spec.values[1]))
    if extension is not None:
        ext, found = read_extension(extension, o.name)
        axes = (found["axes"][0], found["axes"][1])
        info = {k: found[k] for k in ("extended", "bounds_reached", "rounds", "added")}
        for (v0, v1), g in ext.groupby(["p0", "p1"]):
            by_point[(float(v0), float(v1))] = g.drop(columns=["p0", "p1"])
    info["axes"] = {spec.names[i]: [float(v) for v in axes[i]] for i in (0, 1)}
    info["configured"] = {spec.names[i]: [float(v) for v in spec.values[i]] for i in (0, 1)}
    info["extend"] = spec.extend
    cands += grid_candidates(axes, by_point, spec, float(config["isolation"]["rho"]))
    return cands, info


def _verdict_row(
    o: str, k: int, lvl: Mapping[str, Any], settings: Any, spec: GridSpec | None, info: dict
) -> dict:
    """One row of ``/assessment/verdicts``: the verdict of one object and design level."""
    rec, best = lvl["recommended"], lvl["best"]

    def nth(seq: Sequence[Any], default: Any) -> Any:
        return seq[k] if k < len(seq) else default

    closest = lvl.get("closest")
    return {
        "object": o,
        "design_g": lvl["design_g"],
        "design_basis": nth(settings.design_basis, ""),
        "mce_g": nth(settings.mce, math.nan),
        "mce_basis": nth(settings.mce_basis, ""),
        "verdict": lvl["verdict"],
        "reason": lvl["reason"],
        "recommended": "" if rec is None else rec["name"],
        "best": "" if best is None else best["name"],
        "closest": "" if closest is None else closest["name"],
        "target": json.dumps(lvl["target"]),
        "decided_by": lvl["decided_by"],
        "n_family": lvl["n_family"],
        "equivalence_margin": math.nan if lvl["equivalence_margin"] is None else lvl["equivalence_margin"],
        "equivalence_margin_fraction": settings.equivalence_margin,
        "gamma_x": settings.gamma_x,
        "disp_fractile": settings.disp_fractile,
        "n_records": lvl["n_records"],
        "n_boot": settings.n_boot,
        "records_to_decide": math.nan if lvl["records_to_decide"] is None else lvl["records_to_decide"],
        "ranked_by": lvl["ranked_by"],
        "has_floor": lvl["floor"] is not None,
        "edge_of_grid": lvl["edge_of_grid"],
        "edges": json.dumps([[spec.names[ax], side] for ax, side in lvl["edges"]] if spec else []),
        "has_grid": spec is not None,
        "grid": json.dumps(info if spec is not None else {}),
    }


def _paired_columns(name: str, p: Mapping[str, Any] | None) -> dict[str, Any]:
    """A paired comparison (:func:`isorock.assessment.design.paired`) as the columns ``<name>_difference``,
    ``<name>_difference_ci95_lo``/``_hi``, ``<name>_p_better``, ``<name>_p_worse`` (NaN where none),
    ``<name>_n`` (resamples compared) and ``<name>_basis`` (fitted or observed)."""
    from isorock.assessment.case import interval_columns

    p = p or {}

    def f(v: Any) -> float:
        return math.nan if v is None else float(v)

    return {
        f"{name}_difference": f(p.get("difference")),
        **interval_columns(f"{name}_difference_ci95", p.get("difference_ci95")),
        f"{name}_p_better": f(p.get("p_better")),
        f"{name}_p_worse": f(p.get("p_worse")),
        f"{name}_n": int(p.get("n") or 0),
        f"{name}_n_better": int(p.get("n_better") or 0),
        f"{name}_n_worse": int(p.get("n_worse") or 0),
        f"{name}_basis": str(p.get("basis") or ""),
        f"{name}_p_single": f(p.get("p_single")),
        f"{name}_p_adjusted": f(p.get("p_adjusted")),
        f"{name}_n_family": int(p.get("n_family") or 0),
        f"{name}_decided_by": str(p.get("decided_by") or ""),
    }


def design_tables(
    paths: Sequence[str | os.PathLike],
    config: Mapping,
    objects: Sequence[AssessedObject],
    cases: Mapping[str, Any],
    case_runs: Mapping[tuple[str, str], pd.DataFrame],
    settings: Any,
    workers: int = 1,
) -> dict[str, pd.DataFrame]:
    """``design`` (every candidate per object and design level, with its paired comparisons) and
    ``verdicts`` (the verdict of each object and design level, and what the grid's search did); empty
    without design levels. The candidates: the fixed base (the design job's, else a configured case
    without isolation), the isolated cases, and the grid of the design search when there is one,
    extended by ``assess_design_extend`` where its best isolator lay on an edge."""
    from isorock.assessment.case import table_row
    from isorock.assessment.design import evaluate_candidates, rank
    from isorock.jobs.jobfiles import DESIGN_KEY, _job_tables

    grid = config["assessment"].get("design_grid")
    if not settings.design:
        return {}
    design_jobs = _job_tables(paths, DESIGN_KEY, workers) if grid else []
    spec = GridSpec.from_config(grid) if grid else None
    extensions = _extensions(paths)
    dres, vres, runs = [], [], []
    for o in objects:
        parts = [df for df, at in design_jobs if at["object"] == o.name]
        d = pd.concat(parts, ignore_index=True) if parts else None
        cands, info = _object_candidates(o, config, d, spec, cases, case_runs, extensions.get(o.name))
        if not cands:
            continue
        evaluate_candidates(cands, settings, workers=workers)
        # the design job's fixed base and the grid (the configured cases have their rows already)
        runs += [candidate_runs(o.name, c, settings) for c in cands if d is not None and c.source != "case"]
        for k, lvl in enumerate(rank(cands, settings)):
            rec = lvl["recommended"]
            for row in lvl["candidates"]:
                flat = {key: v for key, v in row.items() if key not in ("vs_floor", "vs_best")}
                dres.append(
                    {
                        "object": o.name,
                        "design_g": lvl["design_g"],
                        **table_row(flat),
                        **_paired_columns("vs_floor", row["vs_floor"]),
                        **_paired_columns("vs_best", row["vs_best"]),
                        "recommended": bool(rec is not None and row["name"] == rec["name"]),
                        "edge_of_grid": lvl["edge_of_grid"],
                        "ranked_by": lvl["ranked_by"],
                        "has_floor": lvl["floor"] is not None,
                    }
                )
            vres.append(_verdict_row(o.name, k, lvl, settings, spec, info))
    if not dres:
        return {}
    out = {"design": pd.DataFrame(dres), "verdicts": pd.DataFrame(vres)}
    if runs:
        out["candidate_runs"] = pd.concat(runs, ignore_index=True)
    return out


#: the columns of a candidate's base in ``/assessment/runs`` (its rows of the design search)
CANDIDATE_COLUMNS = ("candidate", "source", "isolation", "Tb_s", "xi_b", "mu_b", "R_b_m", "rho")


def candidate_runs(obj: str, c: Candidate, settings: Any) -> pd.DataFrame:
    """The runs of one candidate of the design job (its fixed base, the grid's isolators) as rows of
    ``/assessment/runs``: ``case`` ``design/<name>``, :data:`CANDIDATE_COLUMNS`, the flags ``stripe``,
    ``design``, ``mce`` and the failure modes (the configured cases have their rows already)."""
    from isorock.assessment.stripes import classify_runs

    r = c.runs.drop(columns=[k for k in ("isolator", "p0", "p1") if k in c.runs]).copy()
    r["case"] = f"design/{c.name}"
    r["object"] = obj
    lv = r["level"].to_numpy(dtype=float)
    for flag, levels in (("stripe", settings.stripes), ("design", settings.design), ("mce", settings.mce)):
        r[flag] = np.isclose(lv[:, None], np.asarray(levels, dtype=float)[None, :], rtol=1e-12).any(axis=1)
    r["candidate"] = c.name
    r["source"] = c.source
    for key in CANDIDATE_COLUMNS[2:]:
        v = c.params.get(key)
        r[key] = math.nan if v is None else v
    r["isolation"] = c.params["isolation"]
    return classify_runs(r, settings.capacity_factored_m)


def verdicts_from_store(
    path: str | os.PathLike, basedir: str | os.PathLike | None = None
) -> list[dict[str, Any]]:
    """Every verdict recomputed from the store alone: its configuration (root attribute
    ``config_json``) and ``/assessment/runs`` (every candidate's runs, the design search's included),
    ranked as the merge ranks them (:func:`isorock.assessment.design.rank`). ``basedir``: where a
    hazard curve given as a relative file is (default: the run folder, two levels above
    ``results/isorock.h5``); an inline curve needs nothing else.

    Returns
    -------
    list of dict
        Per object and design level: ``object``, ``design_g``, ``verdict``, ``recommended``, ``best``,
        ``closest`` (candidate names, "" where none), and ``level`` (the whole ranking).
    """
    from isorock.assessment.case import Settings
    from isorock.assessment.design import evaluate_candidates, rank
    from isorock.store import Store

    store = Store(path)
    cfg = json.loads(str(store.root_attrs.get("config_json", "{}")) or "{}")
    a = cfg.get("assessment") or {}
    runs = store.table("assessment/runs")
    if not a or runs is None or "candidate" not in runs:
        return []
    from pathlib import Path

    settings = Settings.from_config(a, basedir if basedir is not None else Path(path).resolve().parent.parent)
    out = []
    for obj in [o["name"] for o in a["objects"]]:
        r = runs[runs["object"] == obj]
        cands = []
        for _case, g in r.groupby("case", sort=False):
            first = g.iloc[0]
            params = {
                k: (None if k != "isolation" and pd.isna(first[k]) else first[k])
                for k in CANDIDATE_COLUMNS[2:]
            }
            src = str(first["source"])
            cands.append(Candidate(str(first["candidate"]), src, params, g.reset_index(drop=True)))
        floors = [c for c in cands if c.source == "floor"]
        floor = next(
            (c for c in floors if c.name == "none" and c.runs["case"].iloc[0] == "design/none"), None
        )
        floor = floor or (floors[0] if floors else None)
        cases = [c for c in cands if c.source == "case"]
        grid = sorted((c for c in cands if c.source == "grid"), key=lambda c: int(c.name.split("-")[1]))
        chosen = ([floor] if floor is not None else []) + cases + grid
        if not chosen:
            continue
        evaluate_candidates(chosen, settings)
        for lvl in rank(chosen, settings):

            def name(row: Mapping[str, Any] | None) -> str:
                return "" if row is None else str(row["name"])

            out.append(
                {"object": obj, "design_g": lvl["design_g"], "verdict": lvl["verdict"],
                 "recommended": name(lvl["recommended"]), "best": name(lvl["best"]),
                 "closest": name(lvl["closest"]), "level": lvl}
            )  # fmt: skip
    return out
