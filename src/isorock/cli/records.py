"""``isorock records``: check a records directory, read one record, add a record to a catalog.

::

    isorock records import [DIR] [--manifest CSV] [--catalog PATH] [--json]
    isorock records check FILE [--format F] [--dt S] [--units U] [--component C] [--json]
    isorock records add FILE --id ID [--format F --dt S --units U --component C]
                        [--event E --station S --year Y --mw M --dist-km D --pga G --pgv V --tp T --note N]
                        [--catalog PATH] [--replace] [--json]

``import`` exits 0 when every listed file passes its checks and 1 when some fail (the report says
which); user errors (a missing directory, a malformed manifest, an unreadable record for ``check``
and ``add``) exit 2 with one line on stderr.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import asdict
from pathlib import Path

from ..constants import ENV_RECORDS, USER_CATALOG_NAME, G
from ..errors import IsorockError, RecordError
from .options import add_json_option, add_record_options, read_record_trace
from .output import print_json

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``records`` command group to the ``isorock`` parser."""
    p = subparsers.add_parser(
        "records",
        help="record files: check a directory, read one, add to a catalog",
        description="Record files and the record catalog.",
    )
    sub = p.add_subparsers(dest="records_command", metavar="ACTION")
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])

    imp = sub.add_parser(
        "import",
        help="check the record files of a directory against the catalog",
        description="Check each file a manifest lists (readable, units plausible, dt sane) and "
        "report which catalog rows are present, substituted or missing. Without DIR: "
        f"${ENV_RECORDS}, else the built-in pyslammer sample set.",
    )
    imp.add_argument("dir", nargs="?", metavar="DIR", help="records directory")
    imp.add_argument("--manifest", metavar="CSV", help="manifest (default DIR/manifest.csv)")
    imp.add_argument("--catalog", metavar="PATH", help="catalog CSV (default: the paper's Table 1)")
    imp.add_argument("--json", action="store_true", help="print one JSON object")
    imp.set_defaults(func=_cmd_import)

    def read_opts(sp: argparse.ArgumentParser) -> None:
        add_record_options(sp, positional=True)
        add_json_option(sp)

    chk = sub.add_parser(
        "check",
        help="read one record file and print its summary",
        description="Read one record file with the checks isorock applies to every record.",
    )
    read_opts(chk)
    chk.set_defaults(func=_cmd_check)

    add = sub.add_parser(
        "add",
        help="add your own record to a catalog",
        description="Read and check FILE, then add it as a row of a user catalog (default "
        f"./{USER_CATALOG_NAME}, created as a copy of the Table 1 catalog).",
    )
    read_opts(add)
    add.add_argument("--id", required=True, help="record id (unique in the catalog)")
    add.add_argument("--event", help="earthquake name (default: from the file header)")
    add.add_argument("--station", help="station (default: from the file)")
    add.add_argument("--year", type=int)
    add.add_argument("--mw", type=float, help="moment magnitude")
    add.add_argument("--dist-km", type=float, help="distance [km]")
    add.add_argument("--pgv", type=float, metavar="M_S", help="PGV [m/s]")
    add.add_argument("--tp", type=float, metavar="S", help="pulse period Tp [s]")
    add.add_argument("--tp-source", help="where Tp comes from")
    add.add_argument("--note")
    add.add_argument("--catalog", metavar="PATH", help=f"user catalog (default ./{USER_CATALOG_NAME})")
    add.add_argument("--replace", action="store_true", help="replace a row with the same id")
    add.set_defaults(func=_cmd_add)


# --------------------------------------------------------------------------- import
def _cmd_import(args: argparse.Namespace) -> int:
    from .. import catalog as cat
    from .. import records as recs

    catalog = cat.load_catalog(args.catalog)
    directory = recs.records_dir(args.dir)
    if directory is None:
        if args.manifest:
            raise IsorockError("--manifest needs a records directory (DIR or $" + ENV_RECORDS + ")")
        return _import_samples(args, catalog)
    if args.manifest:
        mpath = Path(args.manifest)
    elif (directory / "manifest.csv").is_file():
        mpath = directory / "manifest.csv"
    else:
        raise IsorockError(
            f"{directory}: no manifest.csv; name one with --manifest CSV "
            f"(columns {', '.join(recs.MANIFEST_COLUMNS)})"
        )
    manifest = recs.read_manifest(mpath)
    checks = recs.check_manifest_files(directory, manifest)
    rows = recs.catalog_status(directory, manifest, catalog, checks)
    nbad = sum(not c.ok for c in checks)
    counts = {s: sum(r.status == s for r in rows) for s in ("present", "substituted", "missing")}
    if args.json:
        print_json(
            {
                "directory": str(directory),
                "manifest": str(mpath),
                "catalog": catalog.attrs.get("path"),
                "files": [asdict(c) for c in checks],
                "rows": [r.to_dict() for r in rows],
                "summary": {"files": len(checks), "files_failed": nbad, **counts},
            }
        )
        return 1 if nbad else 0
    print(f"records: {directory}  (manifest {mpath.name}, {len(checks)} files)")
    for c in checks:
        print("  " + _file_line(c))
    print(f"files: {len(checks) - nbad} ok, {nbad} failed")
    print(
        f"catalog rows: {counts['present']} present, {counts['substituted']} substituted, "
        f"{counts['missing']} missing"
    )
    for r in rows:
        extra = f"  (failed: {', '.join(r.failed)})" if r.failed else ""
        print(f"  {r.status:<11s} {r.id:<11s} {', '.join(r.files)}{extra}")
    return 1 if nbad else 0


def _file_line(c) -> str:
    if not c.ok:
        return f"FAIL  {c.file}: {c.problem}"
    comp = f" [{c.component}]" if c.component else ""
    return (
        f"ok    {c.file}{comp}  {c.format}  {c.npts} x {c.dt:g} s = {c.duration:.2f} s  "
        f"PGA {c.pga_g:.3f} g  {c.table1_id}"
    )


def _import_samples(args: argparse.Namespace, catalog) -> int:
    from .. import records as recs

    samples = recs.sample_records()  # raises with install advice when pyslammer is absent
    checks = [recs.check_file(s.path, s.format, label=s.name) for s in samples]
    nbad = sum(not c.ok for c in checks)
    rows = recs.catalog_status(None, [], catalog, checks)
    if args.json:
        print_json(
            {
                "directory": None,
                "default_set": "pyslammer samples",
                "samples_dir": str(recs.samples_dir()),
                "files": [asdict(c) for c in checks],
                "rows": [r.to_dict() for r in rows],
                "summary": {
                    "files": len(checks),
                    "files_failed": nbad,
                    **{s: sum(r.status == s for r in rows) for s in ("present", "substituted", "missing")},
                },
            }
        )
        return 1 if nbad else 0
    print(
        f"no records directory named (${ENV_RECORDS} unset): default record set = pyslammer's "
        f"{len(samples)} sample ground motions in {recs.samples_dir()}"
    )
    for c in checks:
        print("  " + _file_line(c))
    print(f"files: {len(checks) - nbad} ok, {nbad} failed")
    print(
        f"catalog rows: the sample set holds none of the {len(rows)} Table 1 records; "
        f"name a records directory to use them"
    )
    return 1 if nbad else 0


# --------------------------------------------------------------------------- check / add
def _read_one(args: argparse.Namespace):
    from ..records import check_trace

    tr = read_record_trace(args.file, args)
    fc = check_trace(tr, args.file)
    if not fc.ok:
        raise RecordError(args.file, fc.problem.split(": ", 1)[-1])
    return tr, fc


def _summary(tr, fc) -> dict:
    info = dict(tr.stats.isorock)
    return {
        "file": str(info.get("source", "")),
        "format": info.get("format"),
        "units": info.get("units"),
        "station": tr.stats.station,
        "component": tr.stats.channel,
        "event": info.get("event", ""),
        "npts": fc.npts,
        "dt": fc.dt,
        "duration": fc.duration,
        "pga_g": fc.pga_g,
        "pga_m_s2": fc.pga_g * G,
    }


def _cmd_check(args: argparse.Namespace) -> int:
    tr, fc = _read_one(args)
    s = _summary(tr, fc)
    if args.json:
        print_json(s)
        return 0
    print(
        f"{s['file']}: {s['format']} ({s['units']}), station {s['station'] or '-'}, "
        f"component {s['component'] or '-'}"
    )
    if s["event"]:
        print(f"  event: {s['event']}")
    print(
        f"  {s['npts']} samples x {s['dt']:g} s = {s['duration']:.2f} s, PGA {s['pga_g']:.4f} g "
        f"({s['pga_m_s2']:.3f} m/s^2)"
    )
    return 0


def _cmd_add(args: argparse.Namespace) -> int:
    from .. import catalog as cat

    tr, fc = _read_one(args)
    info = tr.stats.isorock
    target = Path(args.catalog) if args.catalog else cat.default_user_catalog()
    fpath = Path(args.file).resolve()
    try:
        stored = str(fpath.relative_to(target.resolve().parent))
    except ValueError:
        stored = str(fpath)
    multi = info.get("format") == "bbp"
    row = {
        "id": args.id,
        "event": args.event or info.get("event") or Path(args.file).stem,
        "year": args.year,
        "station": args.station or tr.stats.station or Path(args.file).stem,
        "component": tr.stats.channel or args.component or "?",
        "mw": args.mw,
        "dist_km": args.dist_km,
        "pga_g": round(fc.pga_g, 5),
        "pgv_m_s": args.pgv,
        "tp_s": args.tp,
        "tp_source": args.tp_source,
        "file": stored,
        "format": info.get("format"),
        "dt_s": args.dt if info.get("dt_source") == "given" else None,
        "units": info.get("units"),
        "column": tr.stats.channel if multi else None,
        "note": args.note,
    }
    row = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()}
    path = cat.add_record(row, target, replace=args.replace)
    if args.json:
        print_json({"catalog": str(path), "row": row})
    else:
        print(
            f"added {args.id} to {path}: {row['file']} ({row['format']}, {fc.npts} x {fc.dt:g} s, "
            f"PGA {fc.pga_g:.3f} g)"
        )
    return 0
