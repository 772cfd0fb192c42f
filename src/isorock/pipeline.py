"""The science of the Snakemake workflow: one function per rule, taking configuration dicts and paths.

The workflow (``Snakefile``, ``workflow/rules/*.smk``) only wires these functions together; its
scripts (``workflow/scripts/*.py``) are a few lines that call them. The DAG::

    process_record (1 per record) -> extract_pulse (1 per record) -> min_overturn (1 per record)
                                                                  -> regime_maps (1 per record)
    pulse_overturn (1 per pulse shape), pulse_maps (1 per pulse of Fig 6)
    all of the above -> merge (results/isorock.h5) -> figures (results/figures/*.png)
                                                   -> report_tables (results/report/*.html)
    snakemake --report report.html  (captions in workflow/report/*.rst)

Records come from :func:`plan`: the rows of the record catalog (Table 1 by default) that have a file in
the records directory (``records.dir`` of the configuration, else ``$ISOROCK_RECORDS``), described by
the directory's ``manifest.csv``; rows without a file are skipped with one warning line each. With no
records directory at all the built-in pyslammer sample set (:func:`isorock.catalog.sample_records`)
is used. Every job writes one HDF5 file atomically (:mod:`isorock.store`); :func:`merge` builds
``results/isorock.h5`` (layout in :mod:`isorock.store`).

Configuration: ``config/config.yaml`` (validated against ``workflow/schemas/config.schema.yaml``,
which also gives the defaults; :func:`load_config` does the same outside Snakemake). Lengths in m,
times in s, accelerations in g.
"""

from __future__ import annotations

import contextlib
import copy
import json
import math
import os
import sys
import time
import traceback
import warnings
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import IsorockError

__all__ = [
    "REPO",
    "SCHEMA_PATH",
    "PULSE_SHAPES",
    "RecordFile",
    "RecordSpec",
    "IsolationCase",
    "Plan",
    "load_config",
    "validate_config",
    "grid_values",
    "isolation_cases",
    "plan",
    "params_process",
    "params_pulse",
    "params_overturn",
    "params_maps",
    "params_pulse_overturn",
    "params_pulse_maps",
    "process_record",
    "extract_pulse",
    "min_overturn",
    "regime_maps",
    "pulse_overturn",
    "pulse_maps",
    "merge",
    "report_tables",
    "figures",
    "figures_available",
    "script_logging",
    "pulse_source",
]

#: the repository (source tree) holding the Snakefile, config/ and workflow/
REPO = Path(__file__).resolve().parents[2]
#: JSON Schema (YAML) of the workflow configuration
SCHEMA_PATH = REPO / "workflow" / "schemas" / "config.schema.yaml"
PULSE_SHAPES = ("rect", "halfsine", "fullsine")
_G_TOL = 1e-12


# ============================================================================================ configuration
def _defaulting_validator(schema: dict):
    """A jsonschema validator that fills in ``default`` values (as ``snakemake.utils.validate`` does)."""
    import jsonschema

    base = jsonschema.validators.validator_for(schema)

    def set_defaults(validator, properties, instance, schema):
        if isinstance(instance, dict):
            for prop, sub in properties.items():
                if "default" in sub:
                    instance.setdefault(prop, copy.deepcopy(sub["default"]))
        yield from base.VALIDATORS["properties"](validator, properties, instance, schema)

    return jsonschema.validators.extend(base, {"properties": set_defaults})(schema)


def validate_config(config: dict, schema_path: str | Path = SCHEMA_PATH) -> dict:
    """Validate a workflow configuration in place, filling in the defaults of the schema.

    Parameters
    ----------
    config : dict
        Parsed YAML (changed in place).
    schema_path : path-like
        The schema (default ``workflow/schemas/config.schema.yaml``).

    Returns
    -------
    dict
        ``config``.

    Raises
    ------
    IsorockError
        The first violation, in one line naming the key.
    """
    import yaml

    try:
        schema = yaml.safe_load(Path(schema_path).read_text())
    except OSError as exc:
        raise IsorockError(f"{schema_path}: cannot read the configuration schema: {exc.strerror}") from None
    validator = _defaulting_validator(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        where = ".".join(str(p) for p in e.absolute_path) or "(top level)"
        raise IsorockError(f"configuration: {where}: {e.message}")
    # a second pass validates the defaults filled in by the first
    errors = list(validator.iter_errors(config))
    if errors:
        e = errors[0]
        where = ".".join(str(p) for p in e.absolute_path) or "(top level)"
        raise IsorockError(f"configuration: {where}: {e.message}")
    _check_names(config)
    return config


def load_config(source: str | Path | Mapping | None = None) -> dict:
    """Read and validate a workflow configuration (defaults filled in).

    Parameters
    ----------
    source : path-like, mapping or None
        A YAML file, a parsed configuration, or None for ``config/config.yaml``.

    Raises
    ------
    IsorockError
        Unreadable file, bad YAML or a schema violation (one line).
    """
    import yaml

    if source is None:
        source = REPO / "config" / "config.yaml"
    if isinstance(source, Mapping):
        cfg = copy.deepcopy(dict(source))
    else:
        p = Path(source)
        try:
            cfg = yaml.safe_load(p.read_text()) or {}
        except OSError as exc:
            raise IsorockError(f"{p}: cannot read configuration: {exc.strerror or exc}") from None
        except yaml.YAMLError as exc:
            raise IsorockError(f"{p}: not valid YAML: {str(exc).splitlines()[0]}") from None
        if not isinstance(cfg, dict):
            raise IsorockError(f"{p}: a configuration is a mapping of keys, got {type(cfg).__name__}")
    return validate_config(cfg)


def _check_names(cfg: Mapping) -> None:
    """Cross-checks the schema cannot express: case names exist and are unique."""
    names = [c["name"] for c in cfg["isolation"]["cases"]]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise IsorockError(f"configuration: isolation.cases: name {dup[0]!r} is used twice")
    known = set(names)

    def need(name: str, where: str) -> None:
        if name not in known:
            raise IsorockError(
                f"configuration: {where}: unknown isolation case {name!r}: valid {', '.join(names)}"
            )

    for ref in cfg["overturn"]["cases"]:
        need(_ref_name(ref), "overturn.cases")
    for ref in cfg["maps"]["lambda_R"]["cases"]:
        need(_ref_name(ref), "maps.lambda_R.cases")
    p = cfg["pulses"]
    for shape, cases in p["shapes"].items():
        for c in cases:
            need(c, f"pulses.shapes.{shape}")
    for c in p["maps"]["cases"]:
        need(c, "pulses.maps.cases")
    base = p["vs_isolation"]["base_case"]
    need(base, "pulses.vs_isolation.base_case")
    kind = {c["name"]: c["kind"] for c in cfg["isolation"]["cases"]}[base]
    if kind != "linear" and p["vs_isolation"]["shapes"]:
        raise IsorockError(
            f"configuration: pulses.vs_isolation.base_case: {base!r} is a {kind!r} case; it must be linear"
        )


def _ref_name(ref: str | Mapping) -> str:
    return ref if isinstance(ref, str) else ref["case"]


def _ref_applies(ref: str | Mapping, record_id: str) -> bool:
    if isinstance(ref, str):
        return True
    recs = ref.get("records") or []
    return not recs or record_id in recs


def grid_values(spec: Sequence[float] | Mapping) -> list[float]:
    """The values of a grid entry of the configuration.

    Parameters
    ----------
    spec : list of float or mapping
        A list, or ``{start, stop, num[, spacing]}`` (``spacing`` ``linear`` (default) or ``log``).

    Returns
    -------
    list of float
    """
    if isinstance(spec, Mapping):
        start, stop, num = float(spec["start"]), float(spec["stop"]), int(spec["num"])
        if spec.get("spacing", "linear") == "log":
            if not (start > 0 and stop > 0):
                raise IsorockError(f"log grid {dict(spec)} needs start and stop > 0")
            vals = np.geomspace(start, stop, num)
        else:
            vals = np.linspace(start, stop, num)
        return [float(v) for v in vals]
    return [float(v) for v in spec]


# ============================================================================================ isolation
@dataclass(frozen=True)
class IsolationCase:
    """A named isolation case of the configuration.

    Parameters
    ----------
    name : str
        Name used in the configuration, the tables and the map names.
    kind : {"none", "linear", "fp"}
        Isolation model.
    rho : float
        Block-to-base mass ratio [-] (ignored for ``none``).
    Tb_s : float or None
        Linear isolator period [s].
    xi_b : float or None
        Linear isolator damping ratio [-].
    mu_b : float or None
        FP friction coefficient [-].
    R_b_m : float or None
        FP radius of curvature [m].
    Y_m, bw_beta, bw_gamma : float or None
        Bouc-Wen parameters of the FP isolator ([m], [-], [-]); None: the model's defaults.
    """

    name: str
    kind: str
    rho: float = 0.5
    Tb_s: float | None = None
    xi_b: float | None = None
    mu_b: float | None = None
    R_b_m: float | None = None
    Y_m: float | None = None
    bw_beta: float | None = None
    bw_gamma: float | None = None

    def isolation(self):
        """The :mod:`isorock.model` isolation object."""
        from .model import FPIsolation, LinearIsolation, NoIsolation

        if self.kind == "none":
            return NoIsolation()
        if self.kind == "linear":
            return LinearIsolation(Tb=self.Tb_s, xi_b=self.xi_b, rho=self.rho)
        kw = {
            k: v
            for k, v in (("Y", self.Y_m), ("beta", self.bw_beta), ("gamma", self.bw_gamma))
            if v is not None
        }
        return FPIsolation(mu_b=self.mu_b, R_b=self.R_b_m, rho=self.rho, **kw)

    def columns(self) -> dict[str, Any]:
        """The case columns of the tables: case, isolation, Tb_s, xi_b, rho, mu_b, R_b_m (NaN if n/a)."""
        nan = math.nan
        iso = self.isolation()
        return {
            "case": self.name,
            "isolation": self.kind,
            "Tb_s": float(iso.Tb) if self.kind != "none" else nan,
            "xi_b": float(self.xi_b) if self.kind == "linear" else nan,
            "rho": float(self.rho) if self.kind != "none" else nan,
            "mu_b": float(self.mu_b) if self.kind == "fp" else nan,
            "R_b_m": float(self.R_b_m) if self.kind == "fp" else nan,
        }


def isolation_cases(config: Mapping) -> dict[str, IsolationCase]:
    """The isolation cases of a validated configuration, by name."""
    rho = float(config["isolation"]["rho"])
    out = {}
    for c in config["isolation"]["cases"]:
        kw = {k: c[k] for k in ("Tb_s", "xi_b", "mu_b", "R_b_m", "Y_m", "bw_beta", "bw_gamma") if k in c}
        out[c["name"]] = IsolationCase(name=c["name"], kind=c["kind"], rho=float(c.get("rho", rho)), **kw)
    return out


def _case_dict(case: IsolationCase) -> dict:
    return {k: v for k, v in asdict(case).items() if v is not None}


def _case_from(d: Mapping) -> IsolationCase:
    return IsolationCase(**d)


# ============================================================================================ records
@dataclass(frozen=True)
class RecordFile:
    """One file that may provide a record.

    Parameters
    ----------
    path : str
        Absolute path of the file.
    format : str or None
        Manifest format name (None: detect).
    dt_s : float or None
        Time step [s] for files that do not state it.
    units : str or None
        Units of the values in the file.
    component : str or None
        Component of a multi-component file.
    substitute : bool
        The file stands in for the catalog row (another station).
    note : str
        Manifest note.
    """

    path: str
    format: str | None = None
    dt_s: float | None = None
    units: str | None = None
    component: str | None = None
    substitute: bool = False
    note: str = ""


@dataclass(frozen=True)
class RecordSpec:
    """A record the workflow runs: identity, catalog values and the files that may provide it.

    Parameters
    ----------
    id : str
        Record id (catalog id or sample name): the wildcard, the HDF5 group name.
    label : str
        Human-readable name.
    event, station, component : str
        Descriptions.
    year : int or None
        Year of the earthquake.
    catalog_id : str
        Catalog row ("" for a sample record).
    table1_pga_g, table1_pgv_m_s, table1_tp_s : float or None
        Catalog values [g, m/s, s].
    files : tuple of RecordFile
        Candidate files, in manifest order.
    source : str
        "records directory" or "pyslammer samples".
    """

    id: str
    label: str
    event: str = ""
    station: str = ""
    component: str = ""
    year: int | None = None
    catalog_id: str = ""
    table1_pga_g: float | None = None
    table1_pgv_m_s: float | None = None
    table1_tp_s: float | None = None
    files: tuple[RecordFile, ...] = ()
    source: str = "records directory"

    def to_dict(self) -> dict:
        """JSON-ready form (Snakemake params)."""
        d = asdict(self)
        d["files"] = [asdict(f) for f in self.files]
        return d

    @classmethod
    def from_dict(cls, d: Mapping) -> RecordSpec:
        d = dict(d)
        d["files"] = tuple(RecordFile(**f) for f in d.get("files", ()))
        return cls(**d)


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


def _num(v: Any) -> float | None:
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def _resolve(p: str | None, basedir: Path) -> Path | None:
    if p is None or str(p).strip() == "":
        return None
    q = Path(str(p)).expanduser()
    return q if q.is_absolute() else (basedir / q)


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
        Directory against which relative paths of the configuration are resolved (the
        Snakefile's directory; default the repository).

    Returns
    -------
    Plan
        Records present (catalog rows with a file, or the sample set) and one warning line per
        catalog row skipped.

    Raises
    ------
    IsorockError
        A records directory is named but does not exist; the catalog or manifest is malformed.
    """
    from . import catalog as cat

    base = Path(basedir) if basedir is not None else REPO
    rc = config["records"]
    warn: list[str] = []
    named = _resolve(rc.get("dir"), base)
    directory = cat.records_dir(named)
    if directory is not None:
        directory = directory.resolve()
    records: list[RecordSpec] = []
    if directory is not None:
        source = f"records directory {directory}"
        records = _catalog_records(rc, directory, base, warn)
    else:
        try:
            samples = cat.sample_records()
        except IsorockError as exc:
            warn.append(f"no records run: {exc}")
            samples = []
        source = "pyslammer samples" if samples else "none"
        records = [
            RecordSpec(
                id=s.name,
                label=f"{s.event} {s.year or ''}, {s.station} / {s.component}".replace("  ", " "),
                event=s.event,
                station=s.station,
                component=s.component,
                year=s.year,
                files=(RecordFile(path=str(s.path), format=s.format),),
                source="pyslammer samples",
            )
            for s in samples
        ]
    select = list(rc.get("select") or [])
    if select:
        have = {r.id for r in records}
        for rid in select:
            if rid not in have:
                warn.append(f"records.select: {rid!r} is not among the records present; skipped")
        records = [r for r in records if r.id in select]
    if rc.get("max_records"):
        records = records[: int(rc["max_records"])]
    for r in records:
        if r.id.startswith("pulse-"):
            raise IsorockError(f"record id {r.id!r}: ids starting with 'pulse-' are reserved for pulses")
    p = config["pulses"]
    shapes = [s for s in PULSE_SHAPES if p["enabled"] and p["shapes"].get(s)]
    sources: list[str] = []
    if p["enabled"]:
        for e in p["maps"]["excitations"]:
            s = pulse_source(e["shape"], e["td_s"])
            if s not in sources and p["maps"]["cases"]:
                sources.append(s)
    proc = _resolve(config.get("processing"), base)
    if proc is not None and not proc.is_file():
        raise IsorockError(f"processing: {proc}: no such processing configuration file")
    return Plan(records, source, warn, shapes, sources, str(proc) if proc else None)


def _catalog_records(rc: Mapping, directory: Path, base: Path, warn: list[str]) -> list[RecordSpec]:
    from . import catalog as cat

    catalog_path = _resolve(rc.get("catalog"), base)
    catalog = cat.load_catalog(catalog_path)
    manifest_path = directory / "manifest.csv"
    manifest = cat.read_manifest(manifest_path) if manifest_path.is_file() else []
    if not manifest_path.is_file():
        warn.append(f"{directory}: no manifest.csv: only catalog rows with their own file can be found")
    status = {s.id: s for s in cat.catalog_status(directory, manifest, catalog)}
    cat_dir = Path(catalog.attrs.get("path", cat.CATALOG_PATH)).parent
    out = []
    for row in catalog.to_dict("records"):
        rid = row["id"]
        st = status[rid]
        desc = f"{row['event']} {row.get('year') or ''}, {row['station']} / {row['component']}"
        desc = " ".join(desc.split())
        files: list[RecordFile] = []
        for e in manifest:
            if e.table1_id != rid or not (directory / e.file).is_file():
                continue
            kw = e.read_kwargs()
            files.append(
                RecordFile(
                    path=str((directory / e.file).resolve()),
                    format=kw["format"],
                    dt_s=kw["dt"],
                    units=kw["units"],
                    component=kw["component"],
                    substitute=e.is_substitute,
                    note=e.note,
                )
            )
        own = row.get("file")
        if isinstance(own, str) and own:
            p = Path(own) if Path(own).is_absolute() else cat_dir / own
            if p.is_file():
                files.append(
                    RecordFile(
                        path=str(p.resolve()),
                        format=row.get("format") or None,
                        dt_s=_num(row.get("dt_s")),
                        units=row.get("units") or None,
                        component=row.get("column") or None,
                    )
                )
        good = [f for f in files if not f.substitute]
        subs = [f for f in files if f.substitute]
        if not good and subs and not rc.get("use_substitutes"):
            names = ", ".join(Path(f.path).name for f in subs)
            warn.append(
                f"record {rid} ({desc}) skipped: only a substitute file ({names}); "
                "set records.use_substitutes: true to run it"
            )
            continue
        if not good and not subs:
            missing = f" (listed but absent: {', '.join(st.failed)})" if st.failed else ""
            warn.append(f"record {rid} ({desc}) skipped: no file in {directory}{missing}")
            continue
        out.append(
            RecordSpec(
                id=rid,
                label=desc,
                event=str(row["event"]),
                station=str(row["station"]),
                component=str(row["component"]),
                year=None if row.get("year") is None or _num(row.get("year")) is None else int(row["year"]),
                catalog_id=rid,
                table1_pga_g=_num(row.get("pga_g")),
                table1_pgv_m_s=_num(row.get("pgv_m_s")),
                table1_tp_s=_num(row.get("tp_s")),
                files=tuple(good or subs),
                source="records directory",
            )
        )
    return out


# ============================================================================================ rule parameters
def params_process(config: Mapping, spec: RecordSpec, processing: str | None) -> dict:
    """Parameters of rule ``process_record`` for one record."""
    return {
        "spec": spec.to_dict(),
        "processing": processing,
        "choose": config["records"]["choose"],
    }


def params_pulse(config: Mapping) -> dict:
    """Parameters of rule ``extract_pulse``."""
    return {"pulse": dict(config["pulse"])}


def params_overturn(config: Mapping, record_id: str) -> dict:
    """Parameters of rule ``min_overturn`` for one record."""
    cases = isolation_cases(config)
    o = config["overturn"]
    use = [_case_dict(cases[_ref_name(r)]) for r in o["cases"] if _ref_applies(r, record_id)]
    return {
        "lambdas": grid_values(o["lambda"]),
        "Rs": grid_values(o["R_m"]),
        "cases": use,
        "search": dict(config["search"]),
    }


def params_maps(config: Mapping, spec: RecordSpec) -> dict:
    """Parameters of rule ``regime_maps`` for one record."""
    cases = isolation_cases(config)
    m = config["maps"]
    lr = m["lambda_R"]
    tx = m["Tb_xi"]
    return {
        "amplitude": m["amplitude"],
        "table1_pga_g": spec.table1_pga_g,
        "lambda_R": {
            "lambdas": grid_values(lr["lambda"]),
            "Rs": grid_values(lr["R_m"]),
            "cases": [_case_dict(cases[_ref_name(r)]) for r in lr["cases"] if _ref_applies(r, spec.id)],
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
        "cases": [_case_dict(cases[c]) for c in p["shapes"].get(shape, [])],
        "search": {**config["search"], "amp_max_g": float(p["amp_max_g"])},
        "vs_R": {"td_s": grid_values(p["vs_R"]["td_s"]), "R_m": grid_values(p["vs_R"]["R_m"])},
        "vs_omega": {
            "R_m": grid_values(p["vs_omega"]["R_m"]),
            "omega_p_rad_s": grid_values(p["vs_omega"]["omega_p_rad_s"]),
        },
        "vs_isolation": None
        if shape not in vi["shapes"]
        else {
            "base": _case_dict(cases[vi["base_case"]]),
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
        raise IsorockError(f"{source}: not a pulse excitation of pulses.maps.excitations")
    return {
        "source": source,
        "shape": e["shape"],
        "td_s": float(e["td_s"]),
        "amp_g": float(p["amp_g"]),
        "lambdas": grid_values(lr["lambda"]),
        "Rs": grid_values(lr["R_m"]),
        "cases": [_case_dict(cases[c]) for c in p["cases"]],
    }


# ============================================================================================ logging
@contextlib.contextmanager
def script_logging(log: str | os.PathLike | None, what: str = "") -> Iterator[None]:
    """Send the output of a workflow script to its log file; record the traceback of a failure there.

    Parameters
    ----------
    log : path-like or None
        Log file (appended to); None: leave stdout and stderr alone.
    what : str
        Name of the job, for the first and last lines.
    """
    if log is None:
        yield
        return
    Path(log).parent.mkdir(parents=True, exist_ok=True)
    with open(log, "a", encoding="utf-8") as fh:
        old_out, old_err = sys.stdout, sys.stderr
        sys.stdout = sys.stderr = fh
        t0 = time.perf_counter()
        from . import __version__

        print(f"isorock {__version__}: {what} started", flush=True)
        try:
            yield
        except BaseException:
            traceback.print_exc(file=fh)
            fh.flush()
            raise
        else:
            print(f"{what} done in {time.perf_counter() - t0:.2f} s", flush=True)
        finally:
            sys.stdout, sys.stderr = old_out, old_err


def _version() -> str:
    from . import __version__

    return __version__


def _say(msg: str) -> None:
    print(msg, flush=True)


# ============================================================================================ records jobs
def _read_candidate(f: RecordFile, processing: str | None) -> tuple[Any, dict]:
    from .io import read_record
    from .processing import metrics, process, qa_passed, qa_reasons

    st = read_record(f.path, f.format, dt=f.dt_s, units=f.units, component=f.component)
    if len(st) != 1:
        comps = ", ".join(tr.stats.channel or "(unnamed)" for tr in st)
        raise IsorockError(f"{f.path}: {len(st)} components ({comps}); the manifest must name one")
    raw = st[0]
    tr = process(raw, processing)
    m = metrics(tr)
    info = {
        "file": Path(f.path).name,
        "ok": True,
        "problem": "",
        "qa_passed": qa_passed(tr),
        "qa_reasons": qa_reasons(tr),
        "pga_g": m["pga_g"],
        "pgv_m_s": m["pgv_m_s"],
        "component": str(raw.stats.channel),
        "substitute": f.substitute,
    }
    return (raw, tr, m), info


def process_record(
    spec: Mapping | RecordSpec,
    out: str | os.PathLike,
    *,
    processing: str | None = None,
    choose: str = "table1_pgv",
) -> dict:
    """Rule ``process_record``: read the record's file(s), process, choose one, write ``/records/<id>``.

    Every candidate file of the record is read (:func:`isorock.io.read_record`) and processed
    (:func:`isorock.processing.process`); files that fail to read are noted and skipped. Among the
    files that read, those passing the QA checks are preferred; ``choose="table1_pgv"`` then picks
    the one whose PGV is closest (in ratio) to the Table 1 PGV, ``"first"`` the first in manifest order.

    Parameters
    ----------
    spec : RecordSpec or dict
        The record (as given by :func:`plan`).
    out : path-like
        HDF5 file written (atomically) with the group ``/records/<id>`` (layout in :mod:`isorock.store`).
    processing : str, optional
        Processing YAML (None: the packaged steps).
    choose : {"table1_pgv", "first"}
        Rule choosing among several files.

    Returns
    -------
    dict
        The attributes written.

    Raises
    ------
    IsorockError
        No candidate file could be read (the message lists why).
    """
    import h5py

    from . import __version__
    from .store import atomic_path, config_hash, file_sha256, set_attrs, stamp

    spec = spec if isinstance(spec, RecordSpec) else RecordSpec.from_dict(spec)
    results = []
    infos = []
    for f in spec.files:
        try:
            res, info = _read_candidate(f, processing)
        except IsorockError as exc:
            info = {"file": Path(f.path).name, "ok": False, "problem": str(exc).splitlines()[0]}
            res = None
            _say(f"{spec.id}: {info['file']} cannot be used: {info['problem']}")
        results.append(res)
        infos.append(info)
    ok = [i for i, r in enumerate(results) if r is not None]
    if not ok:
        why = "; ".join(f"{i['file']}: {i['problem']}" for i in infos)
        raise IsorockError(f"record {spec.id}: no file could be read ({why})")
    passed = [i for i in ok if infos[i]["qa_passed"]] or ok
    pick = passed[0]
    if choose == "table1_pgv" and spec.table1_pgv_m_s and len(passed) > 1:
        target = float(spec.table1_pgv_m_s)
        pick = min(passed, key=lambda i: abs(math.log(max(infos[i]["pgv_m_s"], 1e-12) / target)))
    for i, info in enumerate(infos):
        info["chosen"] = i == pick
    raw, tr, m = results[pick]
    f = spec.files[pick]
    _say(f"{spec.id}: using {Path(f.path).name} (PGA {m['pga_g']:.3f} g, PGV {m['pgv_m_s']:.3f} m/s)")
    meta = dict(raw.stats.get("isorock", {}))
    from .processing import qa_passed, qa_reasons

    attrs = {
        "id": spec.id,
        "label": spec.label,
        "event": spec.event,
        "year": spec.year if spec.year is not None else -1,
        "station": spec.station,
        "component": spec.component or str(raw.stats.channel),
        "catalog_id": spec.catalog_id,
        "record_source": spec.source,
        "source_file": f.path,
        "source_format": str(meta.get("format", f.format or "")),
        "file_units": str(meta.get("units", f.units or "")),
        "file_component": str(raw.stats.channel),
        "record_sha256": file_sha256(f.path),
        "candidates": infos,
        "substitute": bool(f.substitute),
        "npts": int(m["npts"]),
        "dt_s": float(m["dt_s"]),
        "duration_s": float(m["duration_s"]),
        "pga_g": float(m["pga_g"]),
        "pga_m_s2": float(m["pga_m_s2"]),
        "pgv_m_s": float(m["pgv_m_s"]),
        "pgd_m": float(m["pgd_m"]),
        "arias_m_s": float(m["arias_m_s"]),
        "d5_95_s": float(m["d5_95_s"]),
        "final_disp_m": float(m["final_disp_m"]),
        "qa_passed": bool(qa_passed(tr)),
        "qa_reasons": qa_reasons(tr),
        "table1_pga_g": spec.table1_pga_g,
        "table1_pgv_m_s": spec.table1_pgv_m_s,
        "table1_tp_s": spec.table1_tp_s,
        "config_hash": config_hash({"spec": spec.to_dict(), "processing": processing, "choose": choose}),
        "isorock_version": __version__,
        "units": json.dumps({"acc": "m/s^2", "dt_s": "s", "pga_g": "g", "pgv_m_s": "m/s", "pgd_m": "m"}),
    }
    if not attrs["qa_passed"]:
        _say(f"{spec.id}: QA warning: {'; '.join(attrs['qa_reasons'])}")
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        g = h.create_group(f"records/{spec.id}")
        set_attrs(g, attrs)
        d = g.create_dataset("acc", data=np.asarray(tr.data, dtype=float), compression="gzip")
        d.attrs["units"] = "m/s^2"
        d.attrs["dt_s"] = float(tr.stats.delta)
        d.attrs["description"] = "processed ground acceleration, sample k at t = k dt"
        hist = [str(s) for s in tr.stats.get("processing", [])]
        g.create_dataset("processing", data=np.array(hist, dtype=h5py.string_dtype()))
    return attrs


def _load_record(path: str | os.PathLike) -> tuple[str, Any, dict]:
    """(id, GroundMotion, attrs) of the one record of a ``process_record`` output."""
    import h5py

    from .excitation import GroundMotion

    with h5py.File(path, "r") as h:
        (rid,) = list(h["records"].keys())
        g = h["records"][rid]
        acc = g["acc"][()]
        dt = float(g["acc"].attrs["dt_s"])
        attrs = {k: (v.item() if hasattr(v, "item") else v) for k, v in g.attrs.items()}
    return rid, GroundMotion(dt=dt, acc=acc, name=rid), attrs


def extract_pulse(
    record_h5: str | os.PathLike, out: str | os.PathLike, *, pulse: Mapping | None = None
) -> dict:
    """Rule ``extract_pulse``: velocity pulse and Tp of a processed record -> ``/records/<id>/pulse``.

    Parameters
    ----------
    record_h5 : path-like
        Output of :func:`process_record`.
    out : path-like
        HDF5 file written with ``/records/<id>`` (attributes Tp_s, Tp_mp_s, pulse_like,
        pulse_indicator) and ``/records/<id>/pulse`` (summary attributes, velocity histories [m/s]).
    pulse : mapping, optional
        ``tp_min_s``, ``tp_max_s`` [s], ``fit_mp``.

    Returns
    -------
    dict
        :meth:`isorock.pulse.PulseResult.summary`.
    """
    import h5py

    from .pulse import PulseConfig
    from .pulse import extract_pulse as _extract
    from .store import atomic_path, config_hash, set_attrs, stamp

    pulse = dict(pulse or {})
    cfg = PulseConfig(
        tp_min=float(pulse.get("tp_min_s", 0.25)),
        tp_max=float(pulse.get("tp_max_s", 15.0)),
        fit_mp=bool(pulse.get("fit_mp", True)),
    )
    rid, gm, rattrs = _load_record(record_h5)
    res = _extract((gm.dt, gm.acc), cfg)
    summ = res.summary()
    _say(
        f"{rid}: Tp = {res.Tp_s:.3f} s (wavelet), {summ['Tp_mp_s'] or math.nan:.3f} s (MP), "
        f"pulse-like {res.pulse_like} (PI {res.pulse_indicator:.2f})"
    )
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        g = h.create_group(f"records/{rid}")
        set_attrs(
            g,
            {
                "Tp_s": summ["Tp_s"],
                "Tp_mp_s": summ["Tp_mp_s"],
                "pulse_like": summ["pulse_like"],
                "pulse_indicator": summ["pulse_indicator"],
            },
        )
        p = g.create_group("pulse")
        set_attrs(p, summ)
        set_attrs(
            p,
            {
                "config_hash": config_hash(pulse),
                "record_sha256": rattrs.get("record_sha256", ""),
                "method": "db4 wavelet (Baker 2007) and Mavroeidis-Papageorgiou (2003) fit; isorock.pulse",
                "units": json.dumps(
                    {
                        "Tp_s": "s",
                        "Tp_mp_s": "s",
                        "pgv_m_s": "m/s",
                        "mp_A_m_s": "m/s",
                        "mp_fp_hz": "Hz",
                        "mp_nu_rad": "rad",
                        "mp_t0_s": "s",
                        "t_pulse_s": "s",
                    }
                ),
            },
        )
        for name, arr in (
            ("velocity", res.velocity),
            ("pulse_velocity", res.pulse_velocity),
            ("mp_velocity", res.mp_velocity),
        ):
            d = p.create_dataset(name, data=np.asarray(arr, dtype=float), compression="gzip")
            d.attrs["units"] = "m/s"
            d.attrs["dt_s"] = gm.dt
    return summ


def _search_row(system, excitation, search: Mapping) -> dict:
    from .assess import min_overturn_amplitude

    m = min_overturn_amplitude(
        system,
        excitation,
        amp_max=float(search["amp_max_g"]),
        growth=float(search["growth"]),
        rtol=float(search["rtol"]),
    )
    tan_a = system.block.tan_alpha
    mo = math.nan if m.min_overturn_g is None else float(m.min_overturn_g)
    return {
        "min_overturn_g": mo,
        "overturns": m.min_overturn_g is not None,
        "min_overturn_over_tan_alpha": mo / tan_a,
        "uplift_g": float(m.uplift_g),
        "uplift_over_tan_alpha": float(m.uplift_g) / tan_a,
        "n_analyses": int(m.n_analyses),
        "amp_max_g": float(m.amp_max_g),
    }


def _block_cols(block) -> dict:
    return {
        "lambda": float(block.lam),
        "R_m": float(block.R),
        "b_m": float(block.b),
        "h_m": float(block.h),
        "tan_alpha": float(block.tan_alpha),
    }


def min_overturn(
    record_h5: str | os.PathLike,
    out: str | os.PathLike,
    *,
    lambdas: Sequence[float],
    Rs: Sequence[float],
    cases: Sequence[Mapping],
    search: Mapping,
    pulse_h5: str | os.PathLike | None = None,
) -> Any:
    """Rule ``min_overturn``: minimum overturning PGA of a record per block and isolation case.

    For every slenderness ``lambda`` [-], size ``R`` [m] and isolation case, the record is scaled by
    the engine's search (:func:`isorock.assess.min_overturn_amplitude`: upward scan from the uplift
    PGA, then bisection) to the smallest PGA that overturns the block.

    Parameters
    ----------
    record_h5 : path-like
        Output of :func:`process_record`.
    out : path-like
        HDF5 file written with the pandas table ``/overturn/<id>`` (columns
        :data:`isorock.store.OVERTURN_COLUMNS`).
    lambdas, Rs : sequence of float
        Block slenderness values [-] and sizes (half-diagonal) [m].
    cases : sequence of mapping
        Isolation cases (:class:`IsolationCase` fields).
    search : mapping
        ``amp_max_g`` [g], ``growth`` [-], ``rtol`` [-].
    pulse_h5 : path-like, optional
        Output of :func:`extract_pulse`; its Tp is copied into the table's attributes.

    Returns
    -------
    pandas.DataFrame
        The table.
    """
    import h5py
    import pandas as pd

    from .model import Block, System
    from .store import OVERTURN_COLUMNS, atomic_path, config_hash, write_tables

    rid, gm, rattrs = _load_record(record_h5)
    tp = math.nan
    if pulse_h5 is not None:
        with h5py.File(pulse_h5, "r") as h:
            tp = float(h[f"records/{rid}"].attrs.get("Tp_s", math.nan))
    pga = gm.pga_g
    rows = []
    t0 = time.perf_counter()
    objs = [_case_from(c) for c in cases]
    for lam in lambdas:
        for R in Rs:
            block = Block.from_lambda_R(lam, R)
            for case in objs:
                try:
                    system = System(block, case.isolation())
                except ValueError as exc:
                    _say(f"{rid}: lambda={lam:g} R={R:g} {case.name}: skipped: {exc}")
                    continue
                row = {
                    "record": rid,
                    **_block_cols(block),
                    **case.columns(),
                    **_search_row(system, gm, search),
                }
                row["record_pga_g"] = pga
                row["scale_min"] = row["min_overturn_g"] / pga
                rows.append(row)
    df = pd.DataFrame(rows, columns=list(OVERTURN_COLUMNS))
    secs = time.perf_counter() - t0
    _say(
        f"{rid}: {len(rows)} minimum-overturning searches, {int(df['n_analyses'].sum())} analyses "
        f"in {secs:.1f} s"
    )
    attrs = {
        "record": rid,
        "record_sha256": rattrs.get("record_sha256", ""),
        "record_pga_g": pga,
        "Tp_s": tp,
        "config_hash": config_hash(
            {"lambdas": list(lambdas), "Rs": list(Rs), "cases": list(cases), "search": dict(search)}
        ),
        "search": dict(search),
        "seconds": secs,
        "isorock_version": _version(),
        "description": "minimum overturning PGA of the record scaled by the search of "
        "isorock.assess.min_overturn_amplitude; NaN: no overturn up to amp_max_g",
    }
    with atomic_path(out) as tmp:
        write_tables(tmp, {f"overturn/{rid}": df}, {f"overturn/{rid}": attrs})
    return df


def _map_amplitude(amplitude: str | float, table1_pga_g: float | None, pga_g: float) -> tuple[float, str]:
    if isinstance(amplitude, (int, float)) and not isinstance(amplitude, bool):
        return float(amplitude), "config"
    if amplitude == "table1" and table1_pga_g:
        return float(table1_pga_g), "table1"
    return float(pga_g), "record"


def _map_name_lr(case: str) -> str:
    return f"lambda_R-{case}"


def _map_name_tx(lam: float, R: float) -> str:
    return f"Tb_xi-lam{lam:g}-R{R:g}"


def regime_maps(
    record_h5: str | os.PathLike,
    out: str | os.PathLike,
    *,
    amplitude: str | float,
    table1_pga_g: float | None,
    lambda_R: Mapping,
    Tb_xi: Mapping,
    threads: int = 1,
    pulse_h5: str | os.PathLike | None = None,
) -> list[str]:
    """Rule ``regime_maps``: response-regime maps of a record (lambda-R per case, Tb-xi per block).

    Parameters
    ----------
    record_h5 : path-like
        Output of :func:`process_record`.
    out : path-like
        HDF5 file written with ``/maps/<id>/lambda_R-<case>`` and ``/maps/<id>/Tb_xi-lam<l>-R<R>``.
    amplitude : {"table1", "record"} or float
        PGA of the record in the maps: its Table 1 PGA (else its own), its own, or this value [g].
    table1_pga_g : float or None
        Table 1 PGA of the record [g].
    lambda_R : mapping
        ``lambdas`` [-], ``Rs`` [m], ``cases`` (isolation cases).
    Tb_xi : mapping
        ``Tbs`` [s], ``xis`` [-], ``rho`` [-], ``blocks`` (``lambda``, ``R_m``).
    threads : int
        Threads of the compiled engine.
    pulse_h5 : path-like, optional
        Output of :func:`extract_pulse` (Tp copied into the attributes).

    Returns
    -------
    list of str
        The map paths written.
    """
    import h5py

    from .assess import regime_map_lambda_R, regime_map_Tb_xi
    from .model import Block
    from .store import atomic_path, config_hash, stamp, write_map

    rid, gm, rattrs = _load_record(record_h5)
    amp, amp_source = _map_amplitude(amplitude, table1_pga_g, gm.pga_g)
    tp = math.nan
    if pulse_h5 is not None:
        with h5py.File(pulse_h5, "r") as h:
            tp = float(h[f"records/{rid}"].attrs.get("Tp_s", math.nan))
    chash = config_hash(
        {
            "amplitude": amplitude,
            "table1_pga_g": table1_pga_g,
            "lambda_R": dict(lambda_R),
            "Tb_xi": dict(Tb_xi),
        }
    )
    common = {
        "source": rid,
        "source_kind": "record",
        "amp_source": amp_source,
        "record_pga_g": gm.pga_g,
        "record_sha256": rattrs.get("record_sha256", ""),
        "Tp_s": tp,
        "config_hash": chash,
    }
    written = []
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        root = h.create_group(f"maps/{rid}")
        for c in lambda_R["cases"]:
            case = _case_from(c)
            m = regime_map_lambda_R(
                gm, case.isolation(), lambda_R["lambdas"], lambda_R["Rs"], amp, jobs=threads
            )
            name = _map_name_lr(case.name)
            write_map(root.create_group(name), m, {**common, "map": name, **case.columns()})
            written.append(f"/maps/{rid}/{name}")
            _say(f"{rid}: {name} at {amp:.3g} g ({amp_source}): {m.counts()} in {m.seconds:.1f} s")
        for b in Tb_xi["blocks"]:
            block = Block.from_lambda_R(b["lambda"], b["R_m"])
            m = regime_map_Tb_xi(gm, block, Tb_xi["Tbs"], Tb_xi["xis"], Tb_xi["rho"], amp, jobs=threads)
            name = _map_name_tx(b["lambda"], b["R_m"])
            extra = {
                "map": name,
                "case": "",
                "isolation": "linear",
                "rho": Tb_xi["rho"],
                "lambda": b["lambda"],
                "R_m": b["R_m"],
            }
            write_map(root.create_group(name), m, {**common, **extra})
            written.append(f"/maps/{rid}/{name}")
            _say(f"{rid}: {name} at {amp:.3g} g ({amp_source}): {m.counts()} in {m.seconds:.1f} s")
    return written


# ============================================================================================ pulse jobs
def pulse_overturn(
    out: str | os.PathLike,
    *,
    shape: str,
    cases: Sequence[Mapping],
    search: Mapping,
    vs_R: Mapping,
    vs_omega: Mapping,
    vs_isolation: Mapping | None,
    **kw: Any,
) -> dict:
    """Rule ``pulse_overturn``: minimum overturning amplitude under one pulse shape (Figs 4, 5, 7).

    Parameters
    ----------
    out : path-like
        HDF5 file with the pandas tables ``/pulses/<shape>/overturn_R``, ``.../overturn_omega`` and
        (when ``vs_isolation`` is given) ``.../overturn_isolation`` (columns
        :data:`isorock.store.PULSE_COLUMNS`); :func:`merge` stacks them into ``/pulses/overturn_*``.
    shape : {"rect", "halfsine", "fullsine"}
        Pulse shape.
    cases : sequence of mapping
        Isolation cases of the curves vs R and vs omega_p.
    search : mapping
        ``amp_max_g`` [g], ``growth`` [-], ``rtol`` [-].
    vs_R : mapping
        ``td_s`` (one curve each) [s] and ``R_m`` (the abscissae) [m].
    vs_omega : mapping
        ``R_m`` (one curve each) [m] and ``omega_p_rad_s`` (the abscissae, ``td = pi / omega_p``).
    vs_isolation : mapping or None
        Fig 5: ``base`` (a linear case), ``R_m`` (curves at ``td_fixed_s``), ``td_s`` (curves at
        ``R_fixed_m``), and the values of ``Tb_s``, ``xi_b`` and ``rho`` varied one at a time.
    **kw
        ``lambda`` [-] (default 4).

    Returns
    -------
    dict of pandas.DataFrame
        The tables by key.
    """
    import pandas as pd

    from .excitation import Pulse
    from .model import Block, System
    from .store import PULSE_COLUMNS, atomic_path, config_hash, write_tables

    lam = float(kw.get("lambda", 4.0))
    objs = [_case_from(c) for c in cases]
    t0 = time.perf_counter()

    def row(td: float, R: float, case: IsolationCase, series: str, param: str = "", value: float = math.nan):
        block = Block.from_lambda_R(lam, R)
        system = System(block, case.isolation())
        r = {
            "pulse": shape,
            "td_s": float(td),
            "omega_p_rad_s": math.pi / td,
            "series": series,
            "param": param,
            "value": float(value),
            **_block_cols(block),
            **case.columns(),
        }
        r.update(_search_row(system, Pulse(shape, td, 1.0), search))
        return r

    rows_R = [row(td, R, c, "td") for c in objs for td in vs_R["td_s"] for R in vs_R["R_m"]]
    rows_w = [
        row(math.pi / w, R, c, "R") for c in objs for R in vs_omega["R_m"] for w in vs_omega["omega_p_rad_s"]
    ]
    tables = {
        f"pulses/{shape}/overturn_R": pd.DataFrame(rows_R, columns=list(PULSE_COLUMNS)),
        f"pulses/{shape}/overturn_omega": pd.DataFrame(rows_w, columns=list(PULSE_COLUMNS)),
    }
    if vs_isolation:
        base = _case_from(vs_isolation["base"])
        none = IsolationCase(name="none", kind="none")
        combos = [("R", R, vs_isolation["td_fixed_s"]) for R in vs_isolation["R_m"]]
        combos += [("td", vs_isolation["R_fixed_m"], td) for td in vs_isolation["td_s"]]
        rows_i = []
        for series, R, td in combos:
            rows_i.append(row(td, R, none, series, "none"))
            for param, key in (("Tb_s", "Tb_s"), ("xi_b", "xi_b"), ("rho", "rho")):
                for v in vs_isolation[key]:
                    c = IsolationCase(**{**asdict(base), key: float(v), "name": f"{base.name}:{param}={v:g}"})
                    rows_i.append(row(td, R, c, series, param, v))
        tables[f"pulses/{shape}/overturn_isolation"] = pd.DataFrame(rows_i, columns=list(PULSE_COLUMNS))
    secs = time.perf_counter() - t0
    n = sum(len(t) for t in tables.values())
    _say(f"{shape}: {n} minimum-overturning searches in {secs:.1f} s")
    chash = config_hash(
        {
            "shape": shape,
            "cases": list(cases),
            "search": dict(search),
            "vs_R": dict(vs_R),
            "vs_omega": dict(vs_omega),
            "vs_isolation": vs_isolation,
            "lambda": lam,
        }
    )
    attrs = {
        k: {
            "pulse": shape,
            "config_hash": chash,
            "search": dict(search),
            "lambda": lam,
            "amplitude": "pulse amplitude A_g0 [g]",
            "isorock_version": _version(),
        }
        for k in tables
    }
    with atomic_path(out) as tmp:
        write_tables(tmp, {k: v for k, v in tables.items() if len(v)}, attrs)
    return tables


def pulse_maps(
    out: str | os.PathLike,
    *,
    source: str,
    shape: str,
    td_s: float,
    amp_g: float,
    lambdas: Sequence[float],
    Rs: Sequence[float],
    cases: Sequence[Mapping],
    threads: int = 1,
) -> list[str]:
    """Rule ``pulse_maps``: lambda-R regime maps under one pulse (Fig 6), one per isolation case.

    Parameters
    ----------
    out : path-like
        HDF5 file with ``/maps/<source>/lambda_R-<case>``.
    source : str
        ``pulse-<shape>-td<td_s>``.
    shape : str
        Pulse shape.
    td_s : float
        Pulse half-cycle duration [s].
    amp_g : float
        Pulse amplitude [g].
    lambdas, Rs : sequence of float
        Axes: slenderness [-] and size [m].
    cases : sequence of mapping
        Isolation cases.
    threads : int
        Threads of the compiled engine.
    """
    import h5py

    from .assess import regime_map_lambda_R
    from .excitation import Pulse
    from .store import atomic_path, config_hash, stamp, write_map

    pulse = Pulse(shape, td_s, 1.0)
    chash = config_hash(
        {"source": source, "amp_g": amp_g, "lambdas": list(lambdas), "Rs": list(Rs), "cases": list(cases)}
    )
    written = []
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        root = h.create_group(f"maps/{source}")
        for c in cases:
            case = _case_from(c)
            m = regime_map_lambda_R(pulse, case.isolation(), lambdas, Rs, amp_g, jobs=threads)
            name = _map_name_lr(case.name)
            attrs = {
                "source": source,
                "source_kind": "pulse",
                "map": name,
                "amp_source": "pulse",
                "pulse_shape": shape,
                "td_s": td_s,
                "omega_p_rad_s": math.pi / td_s,
                "config_hash": chash,
                **case.columns(),
            }
            write_map(root.create_group(name), m, attrs)
            written.append(f"/maps/{source}/{name}")
            _say(f"{source}: {name} at {amp_g:g} g: {m.counts()} in {m.seconds:.1f} s")
    return written


# ============================================================================================ merge
_RECORD_SUMMARY = (
    "record", "label", "event", "year", "station", "component", "catalog_id", "source_file",
    "source_format", "substitute", "npts", "dt_s", "duration_s", "pga_g", "pgv_m_s", "pgd_m", "arias_m_s",
    "d5_95_s", "Tp_s", "Tp_mp_s", "pulse_like", "pulse_indicator", "table1_pga_g", "table1_pgv_m_s",
    "table1_tp_s", "qa_passed", "record_sha256",
)  # fmt: skip


def _attr(g, k, default=math.nan):
    v = g.attrs.get(k, default)
    if isinstance(v, bytes):
        v = v.decode()
    if hasattr(v, "item") and getattr(v, "size", 1) == 1:
        v = v.item()
    return v


def _restitution_table():
    import pandas as pd

    from .model import housner_restitution, impact_coefficients

    rows = []
    for rho in (0.1, 0.25, 0.5, 1.0, 2.0):
        for lam in np.linspace(1.0, 10.0, 91):
            h = 1.0
            eps, beta1, _ = impact_coefficients(float(lam), h, rho)
            rows.append(
                {
                    "lambda": float(lam),
                    "rho": rho,
                    "eps": eps,
                    "beta1_over_h": beta1 / h,
                    "eps_housner": housner_restitution(math.atan(1.0 / lam)),
                }
            )
    return pd.DataFrame(rows)


def merge(
    inputs: Iterable[str | os.PathLike], out: str | os.PathLike, *, config: Mapping, source: str = ""
) -> dict:
    """Rule ``merge``: the job files -> ``results/isorock.h5`` (layout in :mod:`isorock.store`).

    Groups are merged as they are (records, overturn tables, maps); the per-shape pulse tables are
    stacked into ``/pulses/overturn_R``, ``/pulses/overturn_omega`` and ``/pulses/overturn_isolation``;
    the Tp of every record is copied onto ``/records/<id>``; the summary tables
    (``/summary/records``, ``/summary/overturn``, ``/summary/maps``) and ``/pulses/restitution`` are
    added; the root gets the configuration and its hash.

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

    Returns
    -------
    dict
        Counts: records, overturn rows, maps.
    """
    import h5py
    import pandas as pd

    from .store import (
        MAP_INDEX_COLUMNS,
        OUTCOME_LEGEND,
        atomic_path,
        config_hash,
        map_paths,
        merge_h5,
        read_table,
        stamp,
        write_tables,
    )

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
    common = {"config_hash": config_hash(cfg), "isorock_version": _version()}
    table_attrs: dict[str, dict] = {}
    for name, parts in pulse_tables.items():
        if parts:
            key = f"pulses/{name}"
            tables[key] = pd.concat([read_table(p, k) for p, k in parts], ignore_index=True)
            with h5py.File(parts[0][0], "r") as h:
                first = h[parts[0][1]].attrs
                extra = {k: _attr(h[parts[0][1]], k) for k in ("search", "lambda", "amplitude") if k in first}
            table_attrs[key] = {**extra, **common, "shapes": sorted(set(tables[key]["pulse"]))}
    tables["pulses/restitution"] = _restitution_table()
    table_attrs["pulses/restitution"] = {
        **common,
        "description": "impact coefficients of physics.md section 7 (Fig 3): eps and beta1/h vs lambda",
    }
    if overturn:
        tables["summary/overturn"] = pd.concat([read_table(p, k) for p, k in overturn], ignore_index=True)
        table_attrs["summary/overturn"] = {**common, "description": "all /overturn/<id> tables stacked"}

    with atomic_path(out) as tmp:
        with h5py.File(tmp, "w") as f:
            stamp(f)
            merge_h5(plain, f, skip=("pulses",))
            rec_rows = []
            for rid, g in f["records"].items() if "records" in f else []:
                if "pulse" in g:
                    for k in ("Tp_s", "Tp_mp_s", "pulse_like", "pulse_indicator"):
                        if k in g["pulse"].attrs:
                            v = g["pulse"].attrs[k]
                            g.attrs[k] = np.nan if isinstance(v, str) else v
                row = {k: _attr(g, k) for k in _RECORD_SUMMARY if k != "record"}
                row["record"] = rid
                rec_rows.append(row)
            map_rows = []
            for path in map_paths(f):
                g = f[path]
                codes = g["codes"][()]
                fixed = json.loads(_attr(g, "fixed", "{}"))
                r = {
                    "path": path,
                    "source": _attr(g, "source", path.split("/")[2]),
                    "source_kind": _attr(g, "source_kind", ""),
                    "map": _attr(g, "map", path.split("/")[-1]),
                    "kind": _attr(g, "kind", ""),
                    "case": _attr(g, "case", ""),
                    "isolation": _attr(g, "isolation", fixed.get("isolation", "")),
                    "pulse": _attr(g, "pulse_shape", ""),
                    "amp_source": _attr(g, "amp_source", ""),
                    "nx": int(codes.shape[0]),
                    "ny": int(codes.shape[1]),
                    "no_uplift": int(np.sum(codes == 0)),
                    "rocking": int(np.sum(codes == 1)),
                    "overturn": int(np.sum(codes == 2)),
                }
                for k in (
                    "Tb_s",
                    "xi_b",
                    "rho",
                    "mu_b",
                    "R_b_m",
                    "lambda",
                    "R_m",
                    "td_s",
                    "amp_g",
                    "n_analyses",
                    "seconds",
                ):
                    v = _attr(g, k, fixed.get(k, math.nan))
                    r[k] = float(v) if not isinstance(v, str) else math.nan
                map_rows.append(r)
            f.attrs["config_hash"] = common["config_hash"]
            f.attrs["config_json"] = json.dumps(cfg, sort_keys=True)
            f.attrs["created_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
            f.attrs["outcome_legend"] = OUTCOME_LEGEND
            f.attrs["record_source"] = source
            f.attrs["description"] = (
                "isorock results: rocking of rigid blocks on isolated bases; layout in the docstring of "
                "isorock.store"
            )
        if rec_rows:
            df = pd.DataFrame(rec_rows, columns=list(_RECORD_SUMMARY))
            for c in (
                "label",
                "event",
                "station",
                "component",
                "catalog_id",
                "source_file",
                "source_format",
                "record_sha256",
            ):
                df[c] = df[c].astype(str)
            for c in ("substitute", "pulse_like", "qa_passed"):
                df[c] = df[c].map(
                    lambda v: bool(v) if not (isinstance(v, float) and math.isnan(v)) else False
                )
            tables["summary/records"] = df
        if map_rows:
            tables["summary/maps"] = pd.DataFrame(map_rows, columns=list(MAP_INDEX_COLUMNS))
        for key in ("summary/records", "summary/maps"):
            table_attrs[key] = common
        write_tables(tmp, tables, table_attrs)
    n = {
        "records": len(rec_rows),
        "overturn_rows": int(len(tables.get("summary/overturn", []))),
        "maps": len(map_rows),
        "pulse_rows": int(sum(len(tables[k]) for k in tables if k.startswith("pulses/overturn"))),
    }
    _say(f"merged {len(inputs)} job files into {out}: {n}")
    return n


# ============================================================================================ report, figures
_CSS = """
body { font-family: sans-serif; font-size: 13px; margin: 1em; }
table { border-collapse: collapse; margin-bottom: 1em; }
th, td { border: 1px solid #bbb; padding: 2px 6px; text-align: right; }
th { background: #eee; }
td:first-child, th:first-child { text-align: left; }
"""


def _html(path: Path, title: str, parts: Sequence[tuple[str, Any]]) -> None:
    """Write an HTML page of (paragraph or heading text, DataFrame or None) parts, atomically."""
    import html

    from .store import atomic_path

    body = [f"<h3>{html.escape(title)}</h3>"]
    for text, df in parts:
        if text:
            body.append(f"<p>{html.escape(text)}</p>")
        if df is not None:
            body.append(df.to_html(index=False, na_rep="-", float_format=lambda x: f"{x:.4g}", border=0))
    page = (
        f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{html.escape(title)}</title>'
        f"<style>{_CSS}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n"
    )
    with atomic_path(path) as tmp:
        tmp.write_text(page, encoding="utf-8")


_REC_COLS = {
    "record": "record", "label": "label", "pga_g": "PGA [g]", "pgv_m_s": "PGV [m/s]",
    "Tp_s": "Tp wavelet [s]", "Tp_mp_s": "Tp MP [s]", "pulse_like": "pulse-like",
    "table1_pga_g": "Table 1 PGA [g]", "table1_pgv_m_s": "Table 1 PGV [m/s]", "table1_tp_s": "Table 1 Tp [s]",
    "qa_passed": "QA passed", "source_file": "file",
}  # fmt: skip
_MAP_COLS = ["map", "kind", "case", "amp_g", "amp_source", "nx", "ny", "no_uplift", "rocking", "overturn"]


def _overturn_pivot(df):
    piv = df.pivot_table(
        index=["record", "lambda", "R_m"],
        columns="case",
        values="min_overturn_g",
        aggfunc="first",
        dropna=False,
    ).reset_index()
    piv.columns.name = None
    return piv.rename(columns={"lambda": "lambda [-]", "R_m": "R [m]"})


def report_tables(h5: str | os.PathLike, outdir: str | os.PathLike) -> list[Path]:
    """Rule ``report_tables``: HTML tables of the results for the Snakemake report.

    Writes into ``outdir``: ``records.html`` (record, PGA, PGV, Tp), ``overturn.html`` (minimum
    overturning PGA [g] per record, block and isolation case), ``maps.html`` (regime counts of every
    map) and ``records/<id>.html`` (one page per record: its values, Tp, its minimum overturning
    PGA per block and its maps).
    """
    import h5py
    import pandas as pd

    from .store import read_table

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with h5py.File(h5, "r") as f:
        keys: set[str] = set()
        f.visit(keys.add)
        src = str(f.attrs.get("record_source", ""))
    rec = read_table(h5, "summary/records") if "summary/records" in keys else None
    ovt = read_table(h5, "summary/overturn") if "summary/overturn" in keys else None
    mps = read_table(h5, "summary/maps") if "summary/maps" in keys else None
    if rec is not None:
        rec = rec[list(_REC_COLS)].copy()
        rec["source_file"] = rec["source_file"].map(lambda s: Path(s).name)
    out = []
    note_tp = "Tp: velocity-pulse period (db4 wavelet, Baker 2007; Mavroeidis-Papageorgiou 2003 fit)."
    p = outdir / "records.html"
    _html(
        p,
        "Records",
        [
            (f"Processed records ({src or 'none'}). {note_tp}", None),
            ("", rec.rename(columns=_REC_COLS) if rec is not None else pd.DataFrame({"record": []})),
        ],
    )
    out.append(p)
    note_ov = (
        "Smallest PGA [g] of the scaled record that overturns the block, per block (lambda = h/b, "
        "R = half-diagonal) and isolation case; '-' = no overturn up to the largest PGA searched."
    )
    p = outdir / "overturn.html"
    _html(
        p,
        "Minimum overturning PGA [g]",
        [(note_ov, _overturn_pivot(ovt) if ovt is not None else pd.DataFrame({"record": []}))],
    )
    out.append(p)
    p = outdir / "maps.html"
    note_maps = "Number of grid points in each regime (no uplift, rocking, overturn) of every map."
    cols = ["source"] + _MAP_COLS + ["seconds"]
    _html(
        p, "Response-regime maps", [(note_maps, mps[cols] if mps is not None else pd.DataFrame({"map": []}))]
    )
    out.append(p)
    pages = outdir / "records"
    pages.mkdir(exist_ok=True)
    for r in [] if rec is None else rec.to_dict("records"):
        rid = r["record"]
        one = pd.DataFrame([r]).rename(columns=_REC_COLS)
        parts = [(note_tp, one)]
        if ovt is not None and (ovt["record"] == rid).any():
            parts.append((note_ov, _overturn_pivot(ovt[ovt["record"] == rid]).drop(columns="record")))
        if mps is not None and (mps["source"] == rid).any():
            parts.append((note_maps, mps[mps["source"] == rid][_MAP_COLS]))
        q = pages / f"{rid}.html"
        _html(q, f"{rid}: {r['label']}", parts)
        out.append(q)
    return out


def figures_available() -> bool:
    """Whether :mod:`isorock.figures` (the paper figures) is installed."""
    import importlib.util

    return importlib.util.find_spec("isorock.figures") is not None


def figures(h5: str | os.PathLike, outdir: str | os.PathLike) -> list[Path]:
    """Rule ``figures``: the paper's figures from the store (:func:`isorock.figures.make_all`)."""
    from . import figures as fig  # noqa: PLC0415 - optional module, written separately

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        paths = fig.make_all(h5, outdir)
    _say(f"{len(paths)} figures in {outdir}")
    return [Path(p) for p in paths]
