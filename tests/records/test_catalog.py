"""The Table 1 catalog, its schema, manifests, the records directory, the default record set, and the
``isorock records`` command."""

from __future__ import annotations

import csv
import hashlib
import importlib.util
import json
import os
import re
from pathlib import Path

import pytest

import isorock.records.catalog as cat
import isorock.records.directory as recs
import isorock.records.manifest as man
from isorock import cli, resources
from isorock.errors import IsorockError
from support.records import DATA, ROOT

REPO = ROOT
GOOD = DATA / "good"


def records_dir() -> Path:
    env = os.environ.get("ISOROCK_RECORDS")
    return Path(env) if env else REPO.parent / "shared" / "records"


RECORDS = records_dir()
needs_records = pytest.mark.skipif(
    not (RECORDS / "manifest.csv").is_file(),
    reason=f"records directory {RECORDS} (with manifest.csv) not found: set ISOROCK_RECORDS",
)
HAS_PYSLAMMER = importlib.util.find_spec("pyslammer") is not None

# the paper's Table 1 (ids as in the records README): id -> (mw, dist_km, pga_g, pgv_m_s, tp_s, component)
TABLE1 = {
    "PKF66-C02": (6.20, 0.1, 0.48, 0.75, 2.00, "SN"),
    "SFE71-PCD": (6.55, 3.0, 1.29, 1.20, 1.47, "SN"),
    "TAB78-TAB": (7.11, 1.2, 0.85, 1.22, 5.26, "SP"),
    "IMV79-E04": (6.50, 6.0, 0.36, 0.78, 4.44, "SN"),
    "IMV79-E05": (6.50, 2.7, 0.38, 0.92, 3.92, "SN"),
    "IMV79-E06": (6.50, 0.3, 0.44, 1.12, 3.85, "SN"),
    "IMV79-E07": (6.50, 1.8, 0.46, 1.09, 3.64, "SN"),
    "IMV79-EMO": (6.50, 1.2, 0.38, 1.15, 2.94, "SN"),
    "NOR94-JFA": (6.70, 5.2, 0.39, 1.05, 3.03, "SN"),
    "NOR94-RRS": (6.70, 6.0, 0.89, 1.73, 1.25, "SN"),
    "NOR94-SCG": (6.70, 5.1, 0.59, 1.34, 2.94, "SN"),
    "NOR94-SCH": (6.70, 5.0, 0.89, 1.22, 3.03, "SN"),
    "NOR94-NWS": (6.70, 5.3, 0.41, 1.17, 2.70, "SN"),
    "AIG95-AEGL": (6.33, 6.0, 0.50, 0.41, 0.71, "Long"),
    "AIG95-AEGT": (6.33, 6.0, 0.55, 0.52, 0.68, "Tran"),
    "KOC99-ARC": (7.40, 14.0, 0.13, 0.44, 7.14, "SN"),
    "KOC99-SKR": (7.40, 3.1, 0.41, 0.80, 9.52, "SP"),
    "KOC99-GBZN": (7.40, 11.0, 0.26, 0.41, 4.76, "SN"),
    "KOC99-GBZP": (7.40, 11.0, 0.03, 0.29, 6.06, "SP"),
    "BUC77-BRI": (7.3, 190.0, 0.21, 0.75, 2.13, "SN"),
    "NOR94-PKC": (6.7, 8.2, 0.30, 0.31, 0.61, "090"),
    "PKF04-CH3W": (6.0, 8.0, 0.57, 0.38, 0.52, "360"),
}


def readme_rows() -> dict[str, dict]:
    """The Table 1 table of the records README (an independent source): id -> its values and the status
    its "files here" column states (yes -> present, substitute -> substituted, no -> missing)."""
    text = (RECORDS / "README.md").read_text()
    rows = re.findall(
        r"^\| ([A-Z]{3}\d{2}-[A-Z0-9]+) \| (.*?) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| "
        r"([\d.]+) \| (.*?) \|$",
        text,
        re.M,
    )
    out = {}
    for rid, label, mw, dist, pga, pgv, tp, here in rows:
        status = (
            "substituted"
            if here.startswith("substitute")
            else "present"
            if here.startswith("yes")
            else "missing"
            if here.startswith("no")
            else f"unreadable 'files here' cell {here!r}"
        )
        out[rid] = {"label": label, "values": tuple(map(float, (mw, dist, pga, pgv, tp))), "status": status}
    return out


def manifest_rows() -> list[dict[str, str]]:
    """The rows of the records directory's manifest.csv, read with the csv module."""
    with (RECORDS / "manifest.csv").open(newline="") as fh:
        return list(csv.DictReader(fh))


def manifest_status() -> dict[str, tuple[str, list[str]]]:
    """Catalog id -> (status, files) as the manifest states them: present with a file of the station,
    substituted with only files whose note says "substitute", else missing."""
    out = {}
    for rid in TABLE1:
        mine = [r for r in manifest_rows() if r["table1_id"] == rid and (RECORDS / r["file"]).is_file()]
        good = [r["file"] for r in mine if not r["note"].lower().startswith("substitute")]
        subs = [r["file"] for r in mine if r["note"].lower().startswith("substitute")]
        out[rid] = ("present", good + subs) if good else ("substituted", subs) if subs else ("missing", [])
    return out


# --------------------------------------------------------------------------- catalog
def test_catalog_rows_match_table1():
    df = cat.load_catalog()
    assert list(df["id"]) == list(TABLE1)
    for row in df.to_dict("records"):
        mw, dist, pga, pgv, tp, comp = TABLE1[row["id"]]
        assert (row["mw"], row["dist_km"], row["pga_g"], row["pgv_m_s"], row["tp_s"]) == (
            mw,
            dist,
            pga,
            pgv,
            tp,
        )
        assert row["component"] == comp
        assert row["event"] and row["station"] and 1960 <= row["year"] <= 2004
        assert row["file"] is None  # Table 1 rows name no file: files come from the records directory
    assert set(df.columns) >= {
        "id",
        "event",
        "year",
        "station",
        "component",
        "mw",
        "dist_km",
        "pga_g",
        "pgv_m_s",
        "tp_s",
        "tp_source",
    }


def test_tp_sources():
    df = cat.load_catalog().set_index("id")
    brm = {i for i in df.index if df.loc[i, "tp_source"] == "Bray & Rodriguez-Marek (2004)"}
    mp = {i for i in df.index if df.loc[i, "tp_source"] == "Mavroeidis & Papageorgiou (2003)"}
    assert brm == {"NOR94-PKC", "PKF04-CH3W"}
    assert mp == set(df.index) - brm


@needs_records
def test_catalog_agrees_with_records_readme():
    """Independent sources: the Table 1 rows of the records README, and its "files here" column
    against the status isorock computes from the directory."""
    readme = readme_rows()
    df = cat.load_catalog().set_index("id")
    assert sorted(readme) == sorted(df.index)
    status = {r.id: r.status for r in man.catalog_status(RECORDS)}
    for rid, row in readme.items():
        r = df.loc[rid]
        assert (r.mw, r.dist_km, r.pga_g, r.pgv_m_s, r.tp_s) == row["values"], rid
        assert status[rid] == row["status"], rid


def _write(path: Path, rows: list[dict], columns=cat.CATALOG_COLUMNS) -> Path:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(columns))
        w.writeheader()
        for r in rows:
            w.writerow(r)
    return path


def _row(**kw) -> dict:
    base = {"id": "MY00-ABC", "event": "Test", "station": "ABC", "component": "090"}
    base.update(kw)
    return base


@pytest.mark.parametrize(
    ("rows", "line", "words"),
    [
        ([_row(pga_g="-0.3")], 2, "pga_g"),
        ([_row(mw="big")], 2, "mw"),
        ([_row(), _row()], 3, "duplicate id"),
        ([_row(id="bad id!")], 2, "id"),
        ([_row(), _row(id="MY00-DEF", station="")], 3, "station"),
        ([_row(format="wav")], 2, "format"),
        ([_row(file="x.txt")], 2, "format"),  # a file needs its format
        ([_row(units="furlongs")], 2, "units"),
        ([_row(dt_s="0")], 2, "dt_s"),
        ([_row(tp_s="50")], 2, "tp_s"),
        ([_row(component="SN", strike_deg="323")], 2, "strike_source"),  # a strike needs its source
        ([_row(component="SN", strike_deg="400", strike_source="x")], 2, "strike_deg"),
    ],
)
def test_schema_violations(tmp_path, rows, line, words):
    path = _write(tmp_path / "c.csv", rows)
    with pytest.raises(cat.CatalogError) as info:
        cat.load_catalog(path)
    assert info.value.line == line
    assert str(info.value).startswith(f"{path}:{line}: ")
    assert words in str(info.value)


def test_table1_components_carry_their_direction():
    """Every SN/SP row names the strike defining it, with the source, or says in its note why not;
    the direction of every row follows from it."""
    from isorock.records.spec import Target

    df = cat.load_catalog()
    for row in df.to_dict("records"):
        source = row["strike_source"] if isinstance(row["strike_source"], str) else ""
        t = Target.of(row["component"], row["strike_deg"], source)
        if row["component"] in ("SN", "SP"):
            if source:
                assert 0 <= row["strike_deg"] < 360 and "EQID" in row["strike_source"], row["id"]
                assert t.azimuth_deg is not None
            else:
                assert "strike" in row["note"], row["id"]
        elif t.azimuth_deg is None:
            assert "azimuth" in row["note"], row["id"]  # Long / Tran: said why
    by_event = df.groupby("event")["strike_deg"].nunique()
    assert (by_event <= 1).all()  # one strike per earthquake
    sn = df.set_index("id")
    assert Target.of("SN", sn.loc["IMV79-E04", "strike_deg"]).azimuth_deg == 53.0
    assert Target.of("SN", sn.loc["NOR94-RRS", "strike_deg"]).azimuth_deg == 212.0


def test_unknown_and_missing_columns(tmp_path):
    with pytest.raises(cat.CatalogError, match="unknown columns"):
        cat.load_catalog(_write(tmp_path / "a.csv", [_row(colour="red")], [*cat.CATALOG_COLUMNS, "colour"]))
    with pytest.raises(cat.CatalogError, match="missing column 'component'"):
        cat.load_catalog(
            _write(
                tmp_path / "b.csv", [{"id": "X", "event": "E", "station": "S"}], ["id", "event", "station"]
            )
        )
    with pytest.raises(cat.CatalogError, match="no such catalog"):
        cat.load_catalog(tmp_path / "none.csv")


def test_schema_file_is_a_valid_json_schema():
    import jsonschema
    import yaml

    schema = yaml.safe_load(resources.catalog_schema().read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    assert set(schema["properties"]) == set(cat.CATALOG_COLUMNS)


# --------------------------------------------------------------------------- records directory
def test_records_dir_resolution(tmp_path, monkeypatch):
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    monkeypatch.delenv(recs.ENV_RECORDS, raising=False)
    assert recs.records_dir() is None
    assert recs.records_dir(a) == a
    monkeypatch.setenv(recs.ENV_RECORDS, str(b))
    assert recs.records_dir() == b
    assert recs.records_dir(a) == a  # the configuration value wins
    monkeypatch.setenv(recs.ENV_RECORDS, str(tmp_path / "none"))
    with pytest.raises(IsorockError, match="ISOROCK_RECORDS"):
        recs.records_dir()
    with pytest.raises(IsorockError, match="does not exist"):
        recs.records_dir(tmp_path / "none")


# --------------------------------------------------------------------------- manifests and status
@needs_records
def test_read_shared_manifest():
    """Every row of manifest.csv (read with the csv module) as isorock reads it."""
    rows = manifest_rows()
    m = man.read_manifest(RECORDS / "manifest.csv")
    assert rows and [e.file for e in m] == [r["file"] for r in rows]
    for e, r in zip(m, rows, strict=True):
        dt = float(r["dt_s"]) if r["dt_s"] else None
        assert e.dt_s == dt, r["file"]
        for col in ("table1_id", "format", "units", "column", "event", "station", "component", "note"):
            assert getattr(e, col) == r[col], (r["file"], col)
        assert e.is_substitute == r["note"].lower().startswith("substitute")
        assert e.line == rows.index(r) + 2
    assert {e.table1_id for e in m} - {""} <= set(TABLE1)  # files belong to Table 1 rows or to none


@pytest.mark.parametrize(
    ("change", "words", "line"),
    [
        ({"format": "wav"}, "unknown format", 2),
        ({"units": "furlongs"}, "unknown units", 2),
        ({"dt_s": "-1"}, "dt_s", 2),
        ({"file": ""}, "empty file name", 2),
    ],
)
def test_bad_manifest(tmp_path, change, words, line):
    row = {
        "file": "a.txt",
        "table1_id": "",
        "event": "",
        "station": "",
        "component": "",
        "format": "one-column",
        "units": "g",
        "dt_s": "0.01",
        "column": "",
        "note": "",
    }
    row.update(change)
    path = _write(tmp_path / "manifest.csv", [row], man.MANIFEST_COLUMNS)
    with pytest.raises(cat.CatalogError) as info:
        man.read_manifest(path)
    assert words in str(info.value) and info.value.line == line


def test_manifest_missing_columns(tmp_path):
    path = tmp_path / "manifest.csv"
    path.write_text("file,format\na.txt,one-column\n")
    with pytest.raises(cat.CatalogError, match="missing columns"):
        man.read_manifest(path)


@needs_records
def test_status_of_shared_directory():
    """The status isorock computes against the README's "files here" column and the manifest's rows."""
    m = man.read_manifest(RECORDS / "manifest.csv")
    checks = man.check_manifest_files(RECORDS, m)
    assert all(c.ok for c in checks), [c.problem for c in checks if not c.ok]
    rows = man.catalog_status(RECORDS, m, checks=checks)
    assert [r.id for r in rows] == list(TABLE1)
    assert {r.id: r.status for r in rows} == {rid: row["status"] for rid, row in readme_rows().items()}
    expected = manifest_status()
    for r in rows:
        assert (r.status, r.files, r.failed) == (*expected[r.id], []), r.id
    # without explicit arguments the directory's manifest.csv is used
    assert [r.status for r in man.catalog_status(RECORDS)] == [r.status for r in rows]


@needs_records
def test_status_with_missing_and_failing_files(tmp_path):
    """Copies of two shared files (a link out of the folder is refused: test_boundary.py): one row
    present, one file failing, one absent."""
    for name in ("RSN77_SFERN_PUL164-hor1.AT2", "elcen07_230fn.dat"):
        (tmp_path / name).write_bytes((RECORDS / name).read_bytes())
    rows = [
        r
        for r in csv.DictReader(open(RECORDS / "manifest.csv", newline=""))
        if r["file"] in ("RSN77_SFERN_PUL164-hor1.AT2", "elcen07_230fn.dat", "rinaldi_fn.dat")
    ]
    for r in rows:
        if r["file"] == "elcen07_230fn.dat":
            r["units"] = "g"  # wrong units: 450 cm/s2 read as 450 g
    _write(tmp_path / "manifest.csv", rows, man.MANIFEST_COLUMNS)
    m = man.read_manifest(tmp_path / "manifest.csv")
    checks = man.check_manifest_files(tmp_path, m)
    bad = {c.file: c.problem for c in checks if not c.ok}
    assert set(bad) == {"elcen07_230fn.dat", "rinaldi_fn.dat"}
    assert "implausible" in bad["elcen07_230fn.dat"] and "no such file" in bad["rinaldi_fn.dat"]
    st = {r.id: r for r in man.catalog_status(tmp_path, m, checks=checks)}
    assert st["SFE71-PCD"].status == "present"
    assert st["IMV79-E07"].status == "missing" and st["IMV79-E07"].failed == ["elcen07_230fn.dat"]
    assert st["NOR94-RRS"].status == "missing" and st["NOR94-RRS"].failed == ["rinaldi_fn.dat"]
    assert sum(r.status == "present" for r in st.values()) == 1


def test_check_file_flags_tiny_pga(tmp_path):
    p = tmp_path / "small.txt"
    p.write_text("\n".join(["0.00001", "-0.00002"] * 100))  # 2e-5 g: a file in g read as cm/s2?
    fc = recs.check_file(p, "one-column", dt=0.01, units="g")
    assert not fc.ok and "implausibly small" in fc.problem
    fc = recs.check_file(GOOD / "tiny.AT2")
    assert not fc.ok and "lasts only" in fc.problem  # 0.11 s
    p.write_text("\n".join(["0.1", "-0.2"] * 100))
    fc = recs.check_file(p, "one-column", dt=0.01, units="g")
    assert fc.ok and fc.npts == 200 and fc.pga_g == pytest.approx(0.2)


# --------------------------------------------------------------------------- default record set
@pytest.mark.skipif(not HAS_PYSLAMMER, reason="pyslammer (optional extra 'samples') not installed")
def test_sample_records():
    s = recs.sample_records()
    assert len(s) == 18
    bcr = next(r for r in s if r.name == "Imperial_Valley_1979_BCR-230")
    assert (bcr.event, bcr.year, bcr.station, bcr.component) == ("Imperial Valley", 1979, "BCR", "230")
    assert all(r.path.is_file() and r.format == "pyslammer-csv" for r in s)
    # read in place from the installed pyslammer package, never copied into the repository
    pkg = Path(importlib.util.find_spec("pyslammer").origin).resolve().parent
    assert all(pkg in r.path.resolve().parents for r in s)


def test_sample_records_without_pyslammer(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "pyslammer" else real(name, *a)
    )
    with pytest.raises(IsorockError, match=r"pip install 'isorock\[samples\]'"):
        recs.sample_records()


# --------------------------------------------------------------------------- command line
@needs_records
def test_cli_status_shared(capsys):
    """Counts and rows of ``records status`` against the manifest and the README."""
    nfiles = len(manifest_rows())
    readme = readme_rows()
    states = ("present", "substituted", "missing")
    counts = {s: sum(r["status"] == s for r in readme.values()) for s in states}
    assert cli.main(["records", "status", str(RECORDS)]) == 0
    out = capsys.readouterr().out
    assert f"files: {nfiles} ok, 0 failed" in out
    assert (
        f"catalog rows: {counts['present']} present, {counts['substituted']} substituted, "
        f"{counts['missing']} missing" in out
    )
    for rid, (status, files) in manifest_status().items():
        line = rf"^  {status}\s+{re.escape(rid)}\s+{re.escape(', '.join(files))}[ ]*$"
        assert re.search(line, out, re.M), (rid, status, files)
    assert cli.main(["records", "status", str(RECORDS), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["summary"] == {"files": nfiles, "files_failed": 0, "added": 0, **counts}
    assert {"dt_s", "duration_s"} <= set(data["files"][0])
    assert [f["file"] for f in data["files"]] == [r["file"] for r in manifest_rows()]
    assert {r["id"]: r["status"] for r in data["rows"]} == {rid: r["status"] for rid, r in readme.items()}


@needs_records
def test_cli_status_uses_env_and_import_is_its_old_name(monkeypatch, capsys):
    monkeypatch.setenv(recs.ENV_RECORDS, str(RECORDS))
    assert cli.main(["records", "status", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["directory"] == str(RECORDS)
    assert cli.main(["records", "import", "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["directory"] == str(RECORDS) and "now 'records status'" in cap.err


def test_cli_status_default_set(monkeypatch, capsys):
    monkeypatch.delenv(recs.ENV_RECORDS, raising=False)
    if not HAS_PYSLAMMER:
        assert cli.main(["records", "status"]) == 2
        assert "isorock[samples]" in capsys.readouterr().err
        return
    assert cli.main(["records", "status", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["default_set"] == "pyslammer samples" and data["summary"]["files"] == 18
    assert data["summary"]["missing"] == 22


def test_cli_status_errors(tmp_path, capsys):
    assert cli.main(["records", "status", str(tmp_path / "none")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "does not exist" in err
    assert cli.main(["records", "status", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no manifest.csv" in err and "isorock records add" in err
    (tmp_path / "manifest.csv").write_text("file,format\n")
    assert cli.main(["records", "status", str(tmp_path)]) == 2
    assert "missing columns" in capsys.readouterr().err


def test_cli_status_reports_failed_files(tmp_path, capsys):
    (tmp_path / "bad.txt").write_text("0.1\n0.2\nabc\n")
    _write(
        tmp_path / "manifest.csv",
        [
            {
                "file": "bad.txt",
                "table1_id": "TAB78-TAB",
                "format": "one-column",
                "units": "g",
                "dt_s": "0.01",
                "column": "",
                "note": "",
            }
        ],
        man.MANIFEST_COLUMNS,
    )
    assert cli.main(["records", "status", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert f"FAIL  bad.txt: {tmp_path / 'bad.txt'}:3: non-numeric value 'abc'" in out
    assert "files: 0 ok, 1 failed" in out and "0 present" in out


def _my_record(path: Path) -> Path:
    path.write_text("\n".join(f"{0.3 * (-1) ** k * (k % 7) / 7:.4f}" for k in range(500)))
    return path


def test_cli_add_registers_in_the_records_directory(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv(recs.ENV_RECORDS, raising=False)
    (tmp_path / "downloads").mkdir()
    src = _my_record(tmp_path / "downloads" / "my_record.txt")
    args = ["records", "add", str(src), "--id", "MY24-REC", "--format", "one-column", "--dt", "0.01",
            "--units", "g", "--component", "FN", "--event", "My quake"]  # fmt: skip
    assert cli.main(args) == 0
    out = capsys.readouterr().out
    assert "added MY24-REC" in out and "isorock report --records records" in out
    d = tmp_path / "records"  # the default directory
    assert (d / "my_record.txt").read_bytes() == src.read_bytes()  # copied
    (e,) = man.read_manifest(d / "manifest.csv")
    assert (e.id, e.table1_id, e.file, e.format, e.units, e.dt_s, e.component, e.event) == (
        "MY24-REC", "", "my_record.txt", "one-column", "g", 0.01, "FN", "My quake"
    )  # fmt: skip
    assert e.sha256 == hashlib.sha256(src.read_bytes()).hexdigest()
    # added again: one record (same sha256), said so, no error
    assert cli.main(args) == 0
    assert "same sha256: not added again" in capsys.readouterr().out
    assert len(man.read_manifest(d / "manifest.csv")) == 1
    # another content under the id taken: exit 2, one line, manifest unchanged; --replace replaces
    src.write_text(src.read_text() + "\n0.1")
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "already registered" in err and "different sha256" in err
    assert len(man.read_manifest(d / "manifest.csv")) == 1
    assert cli.main([*args, "--replace"]) == 0
    capsys.readouterr()
    # a second record joins the first; a Table 1 id cannot be taken by a user record
    other = _my_record(tmp_path / "downloads" / "second.txt")
    assert cli.main(["records", "add", str(other), "--dt", "0.02", "--units", "g", "--json"]) == 0
    added = json.loads(capsys.readouterr().out)["added"]
    assert [a["id"] for a in added] == ["second"]
    assert [x.id for x in man.read_manifest(d / "manifest.csv")] == ["MY24-REC", "second"]
    assert cli.main(["records", "add", str(other), "--id", "IMV79-EMO", "--dt", "0.02", "--units", "g"]) == 2
    assert "Table 1 id" in capsys.readouterr().err
    # status lists the added records
    assert cli.main(["records", "status", str(d), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["added"] == ["MY24-REC", "second"] and data["summary"]["present"] == 0
    # the azimuth of a component whose name does not state it; one per file
    third = _my_record(tmp_path / "downloads" / "third.txt")
    third.write_text(third.read_text() + "\n0.05")  # not the second's content (that would be one record)
    add3 = ["records", "add", str(third), "--dt", "0.02", "--units", "g", "--component", "TR"]
    assert cli.main([*add3, "--azimuth", "74", "--azimuth", "3"]) == 2
    assert "one --azimuth per FILE" in capsys.readouterr().err
    assert cli.main([*add3, "--azimuth", "74"]) == 0
    capsys.readouterr()
    assert man.read_manifest(d / "manifest.csv")[-1].azimuth_deg == 74.0


def test_cli_add_refuses_a_file_it_cannot_analyse(tmp_path, capsys):
    bad = tmp_path / "bad.txt"
    bad.write_text("0.1\n0.2\nabc\n")
    argv = [
        "records",
        "add",
        str(bad),
        "--records",
        str(tmp_path / "r"),
        "--dt",
        "0.01",
        "--format",
        "one-column",
    ]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "units not given" in err and "time step" not in err
    assert not (tmp_path / "r").exists()  # nothing copied


def test_cli_check(tmp_path, capsys):
    p = _my_record(tmp_path / "my_record.txt")
    assert cli.main(["records", "check", str(GOOD / "tiny.AT2"), "--json"]) == 2  # 0.11 s is too short
    assert "lasts only" in capsys.readouterr().err
    argv = ["records", "check", str(p), "--format", "one-column", "--dt", "0.01", "--units", "g", "--json"]
    assert cli.main(argv) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["npts"] == 500 and s["dt_s"] == 0.01 and s["duration_s"] == pytest.approx(4.99)
    assert s["format"] == "one-column" and s["units_source"] == "given" and len(s["sha256"]) == 64


@needs_records
def test_cli_add_multi_component_needs_choice(tmp_path, capsys):
    f = str(RECORDS / "bbp_NR_2002-SYL.bbp")
    d = str(tmp_path / "r")
    assert cli.main(["records", "add", f, "--id", "X", "--records", d]) == 2
    assert "choose one with --component" in capsys.readouterr().err
    assert cli.main(["records", "add", f, "--id", "X", "--records", d, "--component", "EW"]) == 0
    (e,) = man.read_manifest(Path(d) / "manifest.csv")
    assert (e.format, e.column, e.component, e.units, e.dt_s) == ("bbp", "E-W", "E-W", "cm/s2", None)
