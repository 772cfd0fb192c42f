"""What a workflow run computes: the records present, the pulse jobs, and the parameters of each rule.

:func:`plan` finds the records: the rows of the record catalog (Table 1 by default) that have a file in
the records directory (``records.dir`` of the configuration, else ``$ISOROCK_RECORDS``), described by
the directory's ``manifest.csv``; rows without a file are skipped with one warning line each. With no
records directory at all the built-in pyslammer sample set (:func:`isorock.records.sample_records`)
is used. Relative paths of the configuration are relative to the working directory (Snakemake's
convention). The ``params_*`` functions give each rule its parameters (JSON-ready dicts).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from .. import catalog as cat
from .. import records as recs
from ..components import RecordFile, Target
from ..constants import PULSE_SHAPES
from ..errors import ConfigError, IsorockError
from ..manifest import ManifestEntry, catalog_status, read_manifest
from .config import case_dict, grid_values, isolation_cases, ref_applies, ref_name

__all__ = [
    "RecordFile",
    "RecordSpec",
    "Plan",
    "catalog_record",
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
    "design_runs",
]


@dataclass(frozen=True)
class RecordSpec:
    """A record the workflow runs: identity, catalog values and the files that may provide it.

    Parameters
    ----------
    id : str
        Record id (catalog id or sample name): the wildcard, the HDF5 group name.
    label : str
        Human-readable name.
    event, station : str
        Descriptions.
    component : str
        The catalog row's component (``SN``, ``SP``, ``090`` ...), or the file's for a record
        without a row.
    strike_deg : float or None
        Fault strike [deg] defining the row's SN/SP direction.
    strike_source : str
        Its citation.
    tp_source : str
        Source of the catalog's Tp (its definition: Mavroeidis & Papageorgiou fit or Bray &
        Rodriguez-Marek).
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
    strike_deg: float | None = None
    strike_source: str = ""
    tp_source: str = ""
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

    @property
    def target(self) -> Target:
        """The direction the catalog row asks for (none for a record without a row)."""
        if not self.catalog_id:
            return Target()
        return Target.of(self.component, self.strike_deg, self.strike_source)


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


def _text(v: Any) -> str:
    """A text cell of the catalog ("" for a missing one, which pandas gives as NaN)."""
    return v if isinstance(v, str) else ""


def _resolve(p: str | None, basedir: Path) -> Path | None:
    """A path of the configuration: absolute, or relative to ``basedir``."""
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
        A records directory is named but does not exist; the catalog or manifest is malformed.
    """
    base = Path(basedir) if basedir is not None else Path.cwd()
    rc = config["records"]
    warn: list[str] = []
    named = _resolve(rc.get("dir"), base)
    directory = recs.records_dir(named)
    if directory is not None:
        directory = directory.resolve()
    records: list[RecordSpec] = []
    if directory is not None:
        source = f"records directory {directory}"
        manifest_path = directory / "manifest.csv"
        manifest = read_manifest(manifest_path) if manifest_path.is_file() else []
        if not manifest_path.is_file():
            warn.append(f"{directory}: no manifest.csv: only catalog rows with their own file can be found")
        row_warnings: list[str] = []
        records = _catalog_records(rc, directory, manifest, base, row_warnings)
        if records or any(e.table1_id for e in manifest):
            warn += row_warnings  # a directory of catalog records: one line per row it lacks
        elif row_warnings:  # the user's own records only: one line for all the rows
            warn.append(
                f"{directory} holds no file of the {len(row_warnings)} catalog rows: its added records run"
            )
        records += _added_records(directory, manifest, {r.id for r in records}, warn)
    else:
        try:
            samples = recs.sample_records()
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
    if not records:
        raise ConfigError(f"no records to run from {source}: {_why_none(rc, directory, select)}")
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
        raise ConfigError(f"processing: {proc}: no such processing configuration file")
    return Plan(records, source, warn, shapes, sources, str(proc) if proc else None)


def catalog_record(
    rid: str, directory: str | Path | None = None, *, catalog: str | Path | None = None
) -> RecordSpec:
    """One catalog row with its files in a records directory, as the workflow would run it.

    Parameters
    ----------
    rid : str
        Catalog id (``NOR94-RRS``).
    directory : path-like, optional
        Records directory; default ``$ISOROCK_RECORDS`` (:func:`isorock.records.records_dir`).
    catalog : path-like, optional
        Catalog CSV; default the Table 1 catalog.

    Raises
    ------
    IsorockError
        No records directory, an unknown id, or no file of the row in the directory (a substitute
        file is used, and said so, when it is the only one).
    """
    d = recs.records_dir(Path(directory) if directory is not None else None)
    if d is None:
        raise IsorockError(f"record {rid}: no records directory: give --records DIR or set $ISOROCK_RECORDS")
    d = d.resolve()
    mpath = d / "manifest.csv"
    manifest = read_manifest(mpath) if mpath.is_file() else []
    ids = list(cat.load_catalog(catalog)["id"])
    if rid not in ids:
        raise IsorockError(f"record {rid!r} is not a catalog row: valid {', '.join(ids)}")
    warn: list[str] = []
    rc = {"catalog": str(catalog) if catalog is not None else None, "use_substitutes": True}
    for spec in _catalog_records(rc, d, manifest, Path.cwd(), warn):
        if spec.id == rid:
            return spec
    why = next((w for w in warn if w.startswith(f"record {rid} ")), f"record {rid}: no file in {d}")
    raise IsorockError(why.replace(" skipped: ", ": ", 1))


def _why_none(rc: Mapping, directory: Path | None, select: list[str]) -> str:
    """Why a run has no record, in words, with what to do."""
    if select:
        return f"records.select ({', '.join(select)}) names none of the records present"
    if directory is None:
        return "no records directory, and the built-in samples need: pip install 'isorock[samples]'"
    return (
        "the directory holds no file of a catalog row and no record added with "
        f"'isorock records add FILE --records {directory}'"
    )


def _added_records(
    directory: Path, manifest: list[ManifestEntry], taken: set[str], warn: list[str]
) -> list[RecordSpec]:
    """The user's own records of a directory: manifest rows with an ``id`` and no catalog row."""
    out = []
    for e in manifest:
        if not e.id or e.table1_id:
            continue
        if e.id in taken:
            raise ConfigError(f"{directory / 'manifest.csv'}:{e.line}: id {e.id!r} is also a catalog row")
        if not (directory / e.file).is_file():
            warn.append(f"record {e.id} skipped: {e.file} is not in {directory}")
            continue
        label = ", ".join(x for x in (e.event, " / ".join(y for y in (e.station, e.component) if y)) if x)
        out.append(
            RecordSpec(
                id=e.id,
                label=label or e.file,
                event=e.event,
                station=e.station,
                component=e.component,
                files=(RecordFile.from_entry(directory, e),),
                source="records directory",
            )
        )
    return out


def _catalog_records(
    rc: Mapping, directory: Path, manifest: list[ManifestEntry], base: Path, warn: list[str]
) -> list[RecordSpec]:
    catalog_path = _resolve(rc.get("catalog"), base)
    catalog = cat.load_catalog(catalog_path)
    status = {s.id: s for s in catalog_status(directory, manifest, catalog)}
    cat_dir = Path(catalog.attrs["path"]).parent
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
            files.append(RecordFile.from_entry(directory, e))
        own = row.get("file")
        if isinstance(own, str) and own:
            p = Path(own) if Path(own).is_absolute() else cat_dir / own
            if p.is_file():
                files.append(
                    RecordFile(
                        path=str(p.resolve()),
                        format=_text(row.get("format")) or None,
                        dt_s=_num(row.get("dt_s")),
                        units=_text(row.get("units")) or None,
                        component=_text(row.get("column")) or None,
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
                strike_deg=_num(row.get("strike_deg")),
                strike_source=_text(row.get("strike_source")),
                tp_source=_text(row.get("tp_source")),
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
    use = [case_dict(cases[ref_name(r)]) for r in o["cases"] if ref_applies(r, record_id)]
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


def params_assess(config: Mapping, obj: str, case: str) -> dict:
    """Parameters of rule ``assess_stripes`` for one object and isolation case."""
    a = config["assessment"]
    o = next(d for d in a["objects"] if d["name"] == obj)
    return {
        "obj": dict(o),
        "case": case_dict(isolation_cases(config)[case]),
        "stripes_g": list(a["stripes_g"]),
        "design_g": list(a["design_g"]),
        "search": dict(config["search"]),
    }


def params_design(config: Mapping, obj: str) -> dict:
    """Parameters of rule ``assess_design`` for one object."""
    a = config["assessment"]
    o = next(d for d in a["objects"] if d["name"] == obj)
    return {
        "obj": dict(o),
        "grid": dict(a["design_grid"]),
        "rho": float(config["isolation"]["rho"]),
        "stripes_g": list(a["stripes_g"]),
        "design_g": list(a["design_g"]),
    }


def design_runs(config: Mapping, obj: str) -> int:
    """Runs of one ``assess_design`` job (isolators of the grid x stripes and design levels): what sizes
    its run time on a cluster (``workflow/rules/common.smk``)."""
    p = params_design(config, obj)
    g = p["grid"]
    axes = ("Tb_s", "xi_b") if g["kind"] == "linear" else ("mu_b", "R_b_m")
    return math.prod(len(grid_values(g[a])) for a in axes) * len(
        {float(x) for x in (*p["stripes_g"], *p["design_g"])}
    )
