"""What a workflow run computes: the records present, the pulse jobs, and the parameters of each rule.

:func:`plan` takes the records from the record lookup (:func:`isorock.records.lookup.find_records`:
the Table 1 rows with a file in the records directory, the records added to it, or the pyslammer
samples) and the pulse jobs from the configuration. Relative paths of the configuration are relative
to the working directory (Snakemake's convention). The ``params_*`` functions give each rule its
parameters (JSON-ready dicts).
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from isorock.assessment.levels import resolve_levels
from isorock.constants import PULSE_SHAPES
from isorock.control.config import case_dict, grid_values, isolation_cases, ref_applies, ref_name
from isorock.errors import ConfigError, IsorockError
from isorock.records.lookup import find_records, resolve_path
from isorock.records.spec import RecordFile, RecordSpec

__all__ = [
    "RecordFile",
    "RecordSpec",
    "Plan",
    "plan",
    "pulse_source",
    "params_process",
    "params_pulse",
    "params_overturn",
    "params_maps",
    "params_pulse_overturn",
    "params_pulse_maps",
    "params_assess",
    "params_design",
    "params_extend",
    "design_runs",
    "record_blocks",
]


@dataclass
class Plan:
    """What a workflow run computes.

    Attributes
    ----------
    records : list of RecordSpec
        The records, in catalog order.
    source : str
        Where they come from ("records directory DIR", "pyslammer samples", "none").
    warnings : list of str
        One line per skipped catalog row or other problem.
    pulse_shapes : list of str
        Pulse shapes with minimum-overturning studies (one job each).
    pulse_sources : list of str
        Pulse excitations with regime maps (one job each), as ``pulse-<shape>-td<td>``.
    processing : str or None
        Absolute path of the processing YAML (None: the packaged one).
    """

    records: list[RecordSpec]
    source: str
    warnings: list[str] = field(default_factory=list)
    pulse_shapes: list[str] = field(default_factory=list)
    pulse_sources: list[str] = field(default_factory=list)
    processing: str | None = None

    @property
    def ids(self) -> list[str]:
        return [r.id for r in self.records]

    def spec(self, rid: str) -> RecordSpec:
        for r in self.records:
            if r.id == rid:
                return r
        raise KeyError(rid)


def pulse_source(shape: str, td_s: float) -> str:
    """Map source name of a pulse excitation: ``pulse-<shape>-td<td_s>`` (``%g``)."""
    return f"pulse-{shape}-td{td_s:g}"


def plan(config: Mapping, basedir: str | Path | None = None) -> Plan:
    """Find the records and the pulse jobs of a workflow run.

    Parameters
    ----------
    config : mapping
        Validated configuration.
    basedir : path-like, optional
        Directory against which relative paths of the configuration are resolved: the working
        directory of the run (default: the current directory).

    Returns
    -------
    Plan
        Records present (catalog rows with a file, or the sample set) and one warning line per
        catalog row skipped.

    Raises
    ------
    IsorockError
        A records directory is named but does not exist; the catalog or manifest is malformed; the
        ``processing`` file is missing or is no processing file (:func:`isorock.processing.load_config`).
    """
    base = Path(basedir) if basedir is not None else Path.cwd()
    found = find_records(config["records"], base)
    p = config["pulses"]
    shapes = [s for s in PULSE_SHAPES if p["enabled"] and p["shapes"].get(s)]
    sources: list[str] = []
    if p["enabled"]:
        for e in p["maps"]["excitations"]:
            s = pulse_source(e["shape"], e["td_s"])
            if s not in sources and p["maps"]["cases"]:
                sources.append(s)
    proc = resolve_path(config.get("processing"), base)
    if proc is not None and not proc.is_file():
        raise ConfigError(f"processing: {proc}: no such processing configuration file")
    if proc is not None:  # read now, so that a file that is no processing file stops the run before any job
        from isorock.processing.config import load_config as load_processing

        try:
            load_processing(proc)
        except IsorockError as exc:
            raise ConfigError(f"configuration: processing: {exc}") from None
    return Plan(found.records, found.source, found.warnings, shapes, sources, str(proc) if proc else None)


def params_process(config: Mapping, spec: RecordSpec, processing: str | None) -> dict:
    """Parameters of rule ``process_record`` for one record."""
    return {
        "spec": spec.to_dict(),
        "processing": processing,
        "choose": config["records"]["choose"],
        "max_samples": int(config["records"]["max_samples"]),
        "max_duration_s": float(config["records"]["max_duration_s"]),
        "rotd_imts": rotd_measures(config),
    }


def params_pulse(config: Mapping) -> dict:
    """Parameters of the pulse extraction (rule ``process_record``,
    :func:`~isorock.jobs.record.extract_pulse`)."""
    return {"pulse": dict(config["pulse"])}


def params_overturn(config: Mapping, record_id: str) -> dict:
    """Parameters of rule ``min_overturn`` for one record."""
    cases = isolation_cases(config)
    o = config["overturn"]
    use = [case_dict(cases[ref_name(r)]) for r in o["cases"] if ref_applies(r, record_id)]
    return {
        "lambdas": grid_values(o["lambda"]),
        "Rs": grid_values(o["R_m"]),
        "cases": use,
        "search": dict(config["search"]),
        "vertical": uses_vertical(config),
    }


def uses_vertical(config: Mapping) -> bool:
    """``records.vertical``: the analyses include each record's vertical where it has one."""
    return bool((config.get("records") or {}).get("vertical", False))


def params_maps(config: Mapping, spec: RecordSpec) -> dict:
    """Parameters of rule ``regime_maps`` for one record."""
    cases = isolation_cases(config)
    m = config["maps"]
    lr = m["lambda_R"]
    tx = m["Tb_xi"]
    return {
        "amplitude": m["amplitude"],
        "table1_pga_g": spec.table1_pga_g,
        "vertical": uses_vertical(config),
        "lambda_R": {
            "lambdas": grid_values(lr["lambda"]),
            "Rs": grid_values(lr["R_m"]),
            "cases": [case_dict(cases[ref_name(r)]) for r in lr["cases"] if ref_applies(r, spec.id)],
        },
        "Tb_xi": {
            "Tbs": grid_values(tx["Tb_s"]),
            "xis": grid_values(tx["xi_b"]),
            "rho": float(tx["rho"] if tx.get("rho") is not None else config["isolation"]["rho"]),
            "blocks": [
                {"lambda": float(b["lambda"]), "R_m": float(b["R_m"])}
                for b in tx["blocks"]
                if not b.get("records") or spec.id in b["records"]
            ],
        },
    }


def params_pulse_overturn(config: Mapping, shape: str) -> dict:
    """Parameters of rule ``pulse_overturn`` for one pulse shape."""
    cases = isolation_cases(config)
    p = config["pulses"]
    vi = p["vs_isolation"]
    return {
        "shape": shape,
        "lambda": float(p["lambda"]),
        "cases": [case_dict(cases[c]) for c in p["shapes"].get(shape, [])],
        "search": {**config["search"], "amp_max_g": float(p["amp_max_g"])},
        "vs_R": {"td_s": grid_values(p["vs_R"]["td_s"]), "R_m": grid_values(p["vs_R"]["R_m"])},
        "vs_omega": {
            "R_m": grid_values(p["vs_omega"]["R_m"]),
            "omega_p_rad_s": grid_values(p["vs_omega"]["omega_p_rad_s"]),
        },
        "vs_isolation": None
        if shape not in vi["shapes"]
        else {
            "base": case_dict(cases[vi["base_case"]]),
            "R_m": grid_values(vi["R_m"]),
            "td_fixed_s": float(vi["td_fixed_s"]),
            "td_s": grid_values(vi["td_s"]),
            "R_fixed_m": float(vi["R_fixed_m"]),
            "Tb_s": grid_values(vi["Tb_s"]),
            "xi_b": grid_values(vi["xi_b"]),
            "rho": grid_values(vi["rho"]),
        },
    }


def params_pulse_maps(config: Mapping, source: str) -> dict:
    """Parameters of rule ``pulse_maps`` for one pulse excitation (``pulse-<shape>-td<td>``)."""
    cases = isolation_cases(config)
    p = config["pulses"]["maps"]
    lr = config["maps"]["lambda_R"]
    for e in p["excitations"]:
        if pulse_source(e["shape"], e["td_s"]) == source:
            break
    else:
        raise ConfigError(f"{source}: not a pulse excitation of pulses.maps.excitations")
    return {
        "source": source,
        "shape": e["shape"],
        "td_s": float(e["td_s"]),
        "amp_g": float(p["amp_g"]),
        "lambdas": grid_values(lr["lambda"]),
        "Rs": grid_values(lr["R_m"]),
        "cases": [case_dict(cases[c]) for c in p["cases"]],
    }


@functools.lru_cache(maxsize=8)
def _scaling_of(assessment_json: str) -> dict:
    from isorock.assessment.hazard_files import curve_from_config
    from isorock.assessment.scaling import scaling_from_config

    a = json.loads(assessment_json)
    hz = a.get("hazard")
    s = scaling_from_config(a, curve_from_config(hz, Path.cwd()) if hz else None)
    return {"imt": s.imt, "component": s.component, "basis": s.basis}


def scaling_params(config: Mapping) -> dict:
    """The stripes' measure and component definition of the configuration's assessment
    (:class:`isorock.assessment.scaling.Scaling` fields; PGA of the analysed component without one)."""
    a = config.get("assessment") or {}
    return dict(_scaling_of(json.dumps(a, sort_keys=True, default=str)))


def rotd_measures(config: Mapping) -> list[str]:
    """The measures whose RotD50 and RotD100 ``process_record`` computes: PGA, PGV and the assessment's
    measure."""
    out = ["PGA", "PGV"]
    if config.get("assessment"):
        imt = scaling_params(config)["imt"]
        if imt not in out:
            out.append(imt)
    return out


def params_assess(config: Mapping, obj: str, case: str) -> dict:
    """Parameters of rule ``assess_stripes`` for one object and isolation case."""
    a = config["assessment"]
    o = next(d for d in a["objects"] if d["name"] == obj)
    lv = resolve_levels(a)
    return {
        "obj": dict(o),
        "case": case_dict(isolation_cases(config)[case]),
        "stripes_g": list(a["stripes_g"]),
        "design_g": list(lv.design),
        "mce_g": list(lv.mce),
        "search": dict(config["search"]),
        "vertical": uses_vertical(config),
        "scaling": scaling_params(config),
    }


def params_design(config: Mapping, obj: str) -> dict:
    """Parameters of rule ``assess_design`` for one object."""
    a = config["assessment"]
    o = next(d for d in a["objects"] if d["name"] == obj)
    lv = resolve_levels(a)
    return {
        "obj": dict(o),
        "grid": dict(a["design_grid"]),
        "rho": float(config["isolation"]["rho"]),
        "stripes_g": list(a["stripes_g"]),
        "design_g": list(lv.design),
        "mce_g": list(lv.mce),
        "vertical": uses_vertical(config),
        "scaling": scaling_params(config),
    }


def params_extend(config: Mapping, obj: str) -> dict:
    """Parameters of rule ``assess_design_extend`` for one object: the object, the whole ``assessment``
    section (the merge's ranking), the grid's mass ratio and every level the records are run at."""
    p = params_design(config, obj)
    levels = sorted({float(x) for x in (*p["stripes_g"], *p["design_g"], *p["mce_g"])})
    return {
        "obj": p["obj"],
        "assessment": dict(config["assessment"]),
        "rho": p["rho"],
        "levels_g": levels,
        "vertical": p["vertical"],
    }


def design_runs(config: Mapping, obj: str) -> int:
    """Runs of one ``assess_design`` job (isolators of the grid x stripes and design levels): what sizes
    its run time on a cluster (``workflow/rules/common.smk``)."""
    p = params_design(config, obj)
    g = p["grid"]
    axes = ("Tb_s", "xi_b") if g["kind"] == "linear" else ("mu_b", "R_b_m")
    return (1 + math.prod(len(grid_values(g[a])) for a in axes)) * len(
        {float(x) for x in (*p["stripes_g"], *p["design_g"], *p["mce_g"])}
    )


def record_blocks(ids: Sequence[str], per_job: int) -> dict[str, list[str]]:
    """The records of each assessment job: ``ids`` cut, in their order, into the fewest blocks of at
    most ``per_job`` records (``resources.records_per_job``), of sizes that differ by one at most.

    Parameters
    ----------
    ids : sequence of str
        Record ids, in the order of the run (:attr:`Plan.ids`).
    per_job : int
        The most records of one block (>= 1).

    Returns
    -------
    dict of str to list of str
        Block name (``b0``, ``b1``, ...: the ``{block}`` wildcard of rules ``assess_stripes`` and
        ``assess_design``) to its record ids; empty without records.

    Examples
    --------
    >>> record_blocks(["a", "b", "c", "d", "e"], 2)
    {'b0': ['a', 'b'], 'b1': ['c', 'd'], 'b2': ['e']}
    >>> record_blocks(["a", "b", "c", "d", "e"], 4)
    {'b0': ['a', 'b', 'c'], 'b1': ['d', 'e']}
    """
    if per_job < 1:
        raise ConfigError(f"resources.records_per_job: {per_job}: valid an integer >= 1")
    ids = list(ids)
    if not ids:
        return {}
    n = math.ceil(len(ids) / per_job)
    size, extra = divmod(len(ids), n)
    out: dict[str, list[str]] = {}
    start = 0
    for k in range(n):
        stop = start + size + (1 if k < extra else 0)
        out[f"b{k}"] = ids[start:stop]
        start = stop
    return out


def process_batches(ids: Sequence[str], per_job: int, spread: int) -> dict[str, list[str]]:
    """The records of each ``process_record`` job: ``ids`` cut, in their order, into blocks of at most
    ``per_job`` records (``resources.records_per_job``) and, where there are enough records, at least
    ``spread`` blocks (``resources.map_threads``: the first jobs of a run use every core), of sizes
    that differ by one at most. A job of several records starts Python and imports isorock once
    (about 1.5 s, longer than a record's processing and pulse).

    Parameters
    ----------
    ids : sequence of str
        Record ids, in the order of the run (:attr:`Plan.ids`).
    per_job : int
        The most records of one job (>= 1).
    spread : int
        The fewest jobs (>= 1), fewer only when there are fewer records.

    Returns
    -------
    dict of str to list of str
        Batch name (``p0``, ``p1``, ...: rules ``process_record_p0`` ...) to its record ids; every
        record in one batch; empty without records.

    Examples
    --------
    >>> process_batches(["a", "b", "c", "d", "e"], 20, 2)
    {'p0': ['a', 'b', 'c'], 'p1': ['d', 'e']}
    >>> process_batches(["a", "b", "c"], 1, 2)
    {'p0': ['a'], 'p1': ['b'], 'p2': ['c']}
    """
    if spread < 1:
        raise ConfigError(f"resources.map_threads: {spread}: valid an integer >= 1")
    ids = list(ids)
    if not ids:
        return {}
    if per_job < 1:
        raise ConfigError(f"resources.records_per_job: {per_job}: valid an integer >= 1")
    n = max(math.ceil(len(ids) / per_job), min(spread, len(ids)))
    size, extra = divmod(len(ids), n)
    out: dict[str, list[str]] = {}
    start = 0
    for k in range(n):
        stop = start + size + (1 if k < extra else 0)
        out[f"p{k}"] = ids[start:stop]
        start = stop
    return out
