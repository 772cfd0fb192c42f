"""``isorock records``: the record files: a directory's status, one file's check, adding records.

::

    isorock records status [DIR] [--manifest CSV] [--catalog PATH] [--json]
    isorock records check FILE [--format F] [--dt S] [--units U] [--component C] [--json]
    isorock records add FILE... [--records DIR] [--id ID ...] [--table1-id ID]
                        [--format F --dt S --units U --component C] [--event E --station S --note N]
                        [--replace] [--json]
    isorock records add --peer-search DIR [--records RECDIR] [--replace] [--json]

``add --peer-search`` exits 1 when a row of the search's ``_SearchResults.csv`` was skipped (a file
not in DIR; the other rows are added), 0 when every row was added. ``status`` exits 0 when every
listed file passes its checks and 1 when some fail (the report says
which); user errors (a missing directory, a malformed manifest, an unreadable record for ``check``
and ``add``) exit 2 with one line on stderr. ``import`` is the former name of ``status``.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import asdict
from pathlib import Path

from isorock.cli.options import add_json_option, add_length_options, add_record_options
from isorock.cli.output import print_json
from isorock.constants import ENV_RECORDS, G
from isorock.errors import IsorockError, RecordError

__all__ = ["register"]

DEFAULT_RECORDS = "records"  # = isorock.records.directory.DEFAULT_RECORDS_DIR (not imported: ObsPy)
"""Records directory ``records add`` uses when neither --records nor $ISOROCK_RECORDS names one (a
run finds it there too: :func:`isorock.records.lookup.find_records`)."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``records`` command group to the ``isorock`` parser."""
    p = subparsers.add_parser(
        "records",
        help="record files: a directory's status, check one file, add your own records",
        description="Record files, records directories and the record catalog.",
    )
    sub = p.add_subparsers(
        dest="records_command", metavar="ACTION", help="'isorock records ACTION --help' shows its options"
    )
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])

    status_text = (
        "Check each file a directory's manifest lists (readable, units plausible, dt sane) and report "
        "which catalog rows are present, substituted or missing, and the records added with 'records add'. "
        f"Without DIR: ${ENV_RECORDS}, else the built-in pyslammer sample set."
    )
    for name in ("status", "import"):
        if name == "status":
            st = sub.add_parser(
                name,
                help="check the record files of a directory against the catalog",
                description=status_text,
            )
        else:  # the former name of "status", hidden: added without help=, argparse leaves it out of the
            # list of actions (help=argparse.SUPPRESS would list it as "==SUPPRESS==")
            st = sub.add_parser(
                name,
                description="Deprecated (removed in 0.3.0): the former name of 'isorock records status'. "
                + status_text,
            )
        st.add_argument(
            "dir",
            nargs="?",
            metavar="DIR",
            help=f"records directory (default: ${ENV_RECORDS}, else the pyslammer sample set)",
        )
        st.add_argument("--manifest", metavar="CSV", help="manifest (default DIR/manifest.csv)")
        st.add_argument("--catalog", metavar="PATH", help="catalog CSV (default: the paper's Table 1)")
        add_json_option(st)
        st.set_defaults(func=_cmd_status, deprecated_name=name if name == "import" else None)

    chk = sub.add_parser(
        "check",
        help="read one record file and print its summary",
        description="Read one record file with the checks isorock applies to every record.",
    )
    add_record_options(chk, positional=True, processing=False)
    add_length_options(chk)
    add_json_option(chk)
    chk.set_defaults(func=_cmd_check)

    add = sub.add_parser(
        "add",
        help="add your own records to a records directory",
        description="Read and check each FILE, copy it into the records directory (the content of a "
        "symbolic link, never the link) and register it in the directory's manifest.csv by its name "
        "there (format, units, time step, component, sha256), so that "
        "'isorock report --records DIR' runs it with the records already there (the directory's "
        "Table 1 files, else the pyslammer samples; see records.include). The directory is "
        f"--records DIR, else ${ENV_RECORDS}, else ./{DEFAULT_RECORDS} (created when absent; "
        "'isorock report' finds it there). A component that the file does not name is taken from "
        "the file name (-E, _fn, 090, hor1 ...). A file already registered (same sha256) is not "
        "added again; another file under a registered id is refused. --peer-search DIR adds a PEER "
        "NGA-West2 search folder instead: every row of DIR/_SearchResults.csv becomes the record "
        "RSN<n> (e.g. RSN1063) with its two horizontals and its vertical and the row's metadata "
        "(rsn, mw, mechanism, rjb_km, rrup_km, vs30_m_s, luf_hz, earthquake, year, station) in the "
        "manifest; a row whose file is not in DIR is skipped with one line (exit 1).",
    )
    add_record_options(add, positional=False, processing=False)
    add_length_options(add)
    add.add_argument("files", nargs="*", metavar="FILE", help="record files")
    add.add_argument(
        "--peer-search",
        metavar="DIR",
        help="a PEER NGA-West2 search folder (its .AT2 files and _SearchResults.csv): every row becomes "
        "the record RSN<n> (e.g. RSN1063) with its two horizontals, its vertical and its metadata; "
        "no FILE then",
    )
    add.add_argument(
        "--records",
        metavar="DIR",
        help=f"records directory (default: ${ENV_RECORDS}, else ./{DEFAULT_RECORDS}, created when absent)",
    )
    add.add_argument(
        "--id",
        dest="ids",
        action="append",
        metavar="ID",
        help="record id, once per FILE (default: file name)",
    )
    add.add_argument("--table1-id", default="", metavar="ID", help="the Table 1 row these files record")
    add.add_argument(
        "--azimuth",
        dest="azimuths",
        type=float,
        action="append",
        metavar="DEG",
        help="azimuth of the file's component [deg clockwise from north], once per FILE, when its "
        "name does not state it (default: from the name, e.g. 228 or N-S)",
    )
    add.add_argument("--event", default="", help="earthquake (default: from the file header)")
    add.add_argument("--station", default="", help="station (default: from the file)")
    add.add_argument(
        "--note",
        default="",
        help="free text for the note column of the manifest (default: none); a note starting with "
        "'substitute' marks a file that stands in for its Table 1 row (another station)",
    )
    add.add_argument(
        "--replace", action="store_true", help="replace a registered file or id of the same name"
    )
    add_json_option(add)
    add.set_defaults(func=_cmd_add)


# --------------------------------------------------------------------------- status
def _cmd_status(args: argparse.Namespace) -> int:
    import isorock.records.catalog as cat
    import isorock.records.directory as recs
    import isorock.records.manifest as man

    if args.deprecated_name:
        print("isorock: warning: 'records import' is now 'records status' (it checks, it copies nothing); "
              "'records import' will be removed in 0.3.0", file=sys.stderr)  # fmt: skip
    catalog = cat.load_catalog(args.catalog)
    directory = recs.records_dir(args.dir) or recs.default_records_dir()
    if directory is None:
        if args.manifest:
            raise IsorockError("--manifest needs a records directory (DIR or $" + ENV_RECORDS + ")")
        return _status_samples(args, catalog)
    if args.manifest:
        mpath = Path(args.manifest)
    elif (directory / "manifest.csv").is_file():
        mpath = directory / "manifest.csv"
    else:
        raise IsorockError(
            f"{directory}: no manifest.csv; add records with 'isorock records add FILE --records "
            f"{directory}', or name a manifest with --manifest CSV "
            f"(columns {', '.join(man.MANIFEST_COLUMNS)})"
        )
    manifest = man.read_manifest(mpath, directory)  # its paths are relative to DIR and stay inside it
    checks = man.check_manifest_files(directory, manifest)
    rows = man.catalog_status(directory, manifest, catalog, checks)
    added = [c for c in checks if c.id and not c.table1_id]
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
                "added": [c.id for c in added],
                # the recording's metadata of each added record (records add --peer-search), by id
                "metadata": {
                    e.id: e.metadata.with_names(e.event, e.station)
                    for e in manifest
                    if e.id and not e.table1_id
                },
                "summary": {"files": len(checks), "files_failed": nbad, "added": len(added), **counts},
            }
        )
        return 1 if nbad else 0
    print(f"records: {directory}  (manifest {mpath.name}, {len(checks)} files)")
    for c in checks:
        print("  " + _file_line(c))
    print(f"files: {len(checks) - nbad} ok, {nbad} failed")
    if rows and not any(c.table1_id for c in checks):
        # a directory of the user's own records: the paper's catalog is optional, not missing
        print(
            f"catalog rows: none of the paper's {len(rows)} Table 1 records is here, which is fine: they are "
            f"optional; records added with 'records add': {len(added)} (--json lists the catalog's rows)"
        )
        rows = []
    else:
        print(
            f"catalog rows: {counts['present']} present, {counts['substituted']} substituted, "
            f"{counts['missing']} missing; records added with 'records add': {len(added)}"
        )
    for r in rows:
        extra = f"  (failed: {', '.join(r.failed)})" if r.failed else ""
        print(f"  {r.status:<11s} {r.id:<11s} {', '.join(r.files)}{extra}")
    meta = {e.id: e.metadata.with_names(e.event, e.station) for e in manifest if e.id and not e.table1_id}
    for c in added:
        m = meta.get(c.id, {})
        known = ", ".join(f"{k} {v}" for k, v in m.items() if v not in (None, "") and k != "station")
        print(f"  {'added':<11s} {c.id:<11s} {c.file}" + (f"  ({known})" if m.get("rsn") is not None else ""))
    return 1 if nbad else 0


def _file_line(c) -> str:
    if not c.ok:
        return f"FAIL  {c.file}: {c.problem}"
    from isorock.records.naming import is_vertical

    comp = f" [{c.component}]" if c.component else ""
    who = c.table1_id or c.id or ("vertical of its event and station" if is_vertical(c.component) else "")
    return (
        f"ok    {c.file}{comp}  {c.format}  {c.npts} x {c.dt_s:g} s = {c.duration_s:.2f} s  "
        f"PGA {c.pga_g:.3f} g  {who}"
    )


def _status_samples(args: argparse.Namespace, catalog) -> int:
    import isorock.records.directory as recs
    import isorock.records.manifest as man

    samples = recs.sample_records()  # raises with install advice when pyslammer is absent
    checks = [recs.check_file(s.path, s.format, label=s.name) for s in samples]
    nbad = sum(not c.ok for c in checks)
    rows = man.catalog_status(None, [], catalog, checks)
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


# --------------------------------------------------------------------------- check
def _cmd_check(args: argparse.Namespace) -> int:
    from isorock.cli.stdin import STDIN_NAME, check_stdin_format, is_stdin, stdin_record

    if args.table1_id:
        raise IsorockError("records check reads a FILE, not --id (see 'isorock info --id ID')")
    if not args.file:
        raise IsorockError("give the record FILE to check (- reads it from standard input, with --format)")
    if not is_stdin(args.file):
        return _check_file(args, Path(args.file), args.file)
    check_stdin_format(args.file, args.fmt)
    with stdin_record() as tmp:
        return _check_file(args, tmp, STDIN_NAME)


def _check_file(args: argparse.Namespace, path: Path, name: str) -> int:
    """``records check`` of the record file ``path``, named ``name`` in the output."""
    from isorock.io import read_trace, trace_component, trace_station
    from isorock.records.directory import check_size, check_trace
    from isorock.store import file_sha256

    big = check_size(path, args.max_samples)
    if big:
        raise RecordError(name, big.split(": ", 1)[-1])
    tr = read_trace(path, args.fmt, dt=args.dt, units=args.units, component=args.component)
    fc = check_trace(tr, name, max_samples=args.max_samples, max_duration_s=args.max_duration)
    if not fc.ok:
        raise RecordError(name, fc.problem.split(": ", 1)[-1])
    info = tr.stats.isorock
    s = {
        "file": name if name != args.file else str(info.get("source", "")),
        "format": info.get("format"),
        "units": info.get("units"),
        "units_source": info.get("units_source"),
        "station": trace_station(tr),
        "component": trace_component(tr),
        "event": info.get("event", ""),
        "npts": fc.npts,
        "dt_s": fc.dt_s,
        "duration_s": fc.duration_s,
        "pga_g": fc.pga_g,
        "pga_m_s2": fc.pga_g * G,
        "sha256": file_sha256(path),
    }
    if args.json:
        print_json(s)
        return 0
    units_from = "stated in the file" if s["units_source"] == "header" else "as given"
    print(
        f"{s['file']}: {s['format']}, units {s['units']} ({units_from}), station {s['station'] or '-'}, "
        f"component {s['component'] or '-'}"
    )
    if s["event"]:
        print(f"  event: {s['event']}")
    print(
        f"  {s['npts']} samples x {s['dt_s']:g} s = {s['duration_s']:.2f} s, PGA {s['pga_g']:.4f} g "
        f"({s['pga_m_s2']:.3f} m/s^2) as read, before processing"
    )
    return 0


# --------------------------------------------------------------------------- add
def _cmd_add(args: argparse.Namespace) -> int:
    from isorock.records.adding import NAMED_COMPONENT_NOTE, add_records

    if args.records:
        directory, why = Path(args.records), "--records"
    elif os.environ.get(ENV_RECORDS, "").strip():
        directory, why = Path(os.environ[ENV_RECORDS].strip()), f"${ENV_RECORDS}"
    else:
        directory, why = Path(DEFAULT_RECORDS), "the default"
    if args.peer_search is not None:
        return _cmd_add_peer_search(args, directory, why)
    if not args.files:
        raise IsorockError("give the record FILE(s) to add, or --peer-search DIR (a PEER search folder)")
    if "-" in args.files:
        raise IsorockError(
            "records add copies FILEs into the records directory under their names: standard input "
            "('-') has none; save the record to a file and add that"
        )
    if args.ids is not None and len(args.ids) != len(args.files):
        raise IsorockError(f"{len(args.files)} file(s) but {len(args.ids)} --id: give one --id per FILE")
    if args.azimuths is not None and len(args.azimuths) != len(args.files):
        raise IsorockError(
            f"{len(args.files)} file(s) but {len(args.azimuths)} --azimuth: give one --azimuth per FILE"
        )
    notes: list[str] = []
    rows = add_records(
        args.files,
        directory,
        ids=args.ids,
        table1_id=args.table1_id,
        format=args.fmt,
        dt=args.dt,
        units=args.units,
        component=args.component,
        event=args.event,
        station=args.station,
        note=args.note,
        azimuths=args.azimuths,
        replace=args.replace,
        notes=notes,
        max_samples=args.max_samples,
        max_duration_s=args.max_duration,
        waiting=lambda: print(
            f"isorock: another 'records add' is writing {directory / 'manifest.csv'}: waiting for it",
            file=sys.stderr,
            flush=True,
        ),
    )
    next_cmd = f"isorock report --records {directory} --cores 2"
    if args.json:
        added = [{k: v for k, v in r.to_dict().items() if k != "line"} for r in rows]
        print_json({"directory": str(directory), "added": added, "not_added": notes, "next": next_cmd})
        return 0
    print(f"records directory: {directory} ({why}); manifest {directory / 'manifest.csv'}")
    for r in rows:
        dt = f", dt {r.dt_s:g} s" if r.dt_s else ""
        name = r.table1_id + " (Table 1 row)" if r.table1_id else r.id
        if not name:
            name = "a vertical (no record of its own; it goes with the records beside it)"
        named = " (from the file name)" if NAMED_COMPONENT_NOTE in r.note else ""
        comp = f"component {r.component or '-'}{named}"
        print(f"  added {name}: {r.file} ({r.format}, units {r.units}{dt}, {comp})")
    for line in notes:
        print(f"  {line}")
    print(f"next: {next_cmd}   (runs these records with the others of {directory})")
    return 0


def _cmd_add_peer_search(args: argparse.Namespace, directory: Path, why: str) -> int:
    """``records add --peer-search DIR``: every row of DIR/_SearchResults.csv, as the record ``RSN<n>``."""
    from isorock.records.peer_search import add_peer_search

    given = [
        flag
        for flag, value in (
            ("FILE", args.files),
            ("--id", args.ids),
            ("--azimuth", args.azimuths),
            ("--table1-id", args.table1_id),
            ("--event", args.event),
            ("--station", args.station),
            ("--note", args.note),
            ("--format", args.fmt),
            ("--dt", args.dt),
            ("--units", args.units),
            ("--component", args.component),
        )
        if value
    ]
    if given:
        raise IsorockError(
            f"--peer-search takes the files, ids and metadata from DIR/_SearchResults.csv: not with "
            f"{', '.join(given)}"
        )
    res = add_peer_search(
        args.peer_search,
        directory,
        replace=args.replace,
        waiting=lambda: print(
            f"isorock: another 'records add' is writing {directory / 'manifest.csv'}: waiting for it",
            file=sys.stderr,
            flush=True,
        ),
        max_samples=args.max_samples,
        max_duration_s=args.max_duration,
    )
    rc = 1 if res.skipped else 0
    next_cmd = f"isorock report --records {directory} --cores 2"
    by_id = {r.id: r for r in res.rows}
    if args.json:
        print_json(
            {
                "directory": str(directory),
                "search": str(args.peer_search),
                "rows": len(res.rows),
                "records": [
                    {
                        "id": rid,
                        "metadata": by_id[rid].metadata.with_names(by_id[rid].earthquake, by_id[rid].station),
                    }
                    for rid in res.records
                ],
                "added": [{k: v for k, v in r.to_dict().items() if k != "line"} for r in res.added],
                "skipped": res.skipped,
                "not_added": res.notes,
                "next": next_cmd,
            }
        )
        return rc
    for line in res.skipped:
        print(f"isorock: {line}", file=sys.stderr)
    print(f"records directory: {directory} ({why}); manifest {directory / 'manifest.csv'}")
    added = {r.file for r in res.added}
    for rid in res.records:
        r = by_id[rid]
        m = r.metadata
        meta = ", ".join(
            x
            for x in (
                r.earthquake + (f" {m.year}" if m.year else ""),
                r.station,
                f"Mw {m.mw:g}" if m.mw is not None else "",
                f"Rjb {m.rjb_km:g} km" if m.rjb_km is not None else "",
                f"Vs30 {m.vs30_m_s:g} m/s" if m.vs30_m_s is not None else "",
                f"lowest usable frequency {m.luf_hz:g} Hz" if m.luf_hz is not None else "",
            )
            if x
        )
        state = "added" if any(f in added for f in r.files) else "already there"
        print(f"  {state} {rid}: {', '.join(r.files)} ({meta})")
    for line in res.notes:
        print(f"  {line}")
    print(
        f"{len(res.records)} of {len(res.rows)} rows of {args.peer_search}/_SearchResults.csv in "
        f"{directory}" + (f"; {len(res.skipped)} skipped (said above)" if res.skipped else "")
    )
    print(f"next: {next_cmd}   (runs these records with the others of {directory})")
    return rc
