"""``isorock records add --peer-search DIR``: a PEER NGA-West2 search folder added as records RSN<n>.

The table is a real ``_SearchResults.csv`` (tests/data/peer_search/SOURCES.md); its AT2 files are not
available, so the tests write small PEER AT2 files under the names the table gives.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from isorock import cli
from isorock.jobs import record as jobs
from isorock.processing import applied_steps, default_config, process, with_lowest_usable_frequency
from isorock.records.lookup import catalog_record
from isorock.records.manifest import PAIRED_NOTE, read_manifest
from isorock.records.metadata import RecordMetadata
from isorock.records.peer_search import SEARCH_RESULTS, read_search_results
from isorock.records.spec import RecordSpec
from isorock.store import attrs_dict

REAL = Path(__file__).resolve().parents[1] / "data" / "peer_search" / SEARCH_RESULTS
#: the RSNs of the real table, in its order
RSNS = [6, 14, 15, 20, 26, 30, 31, 33, 36, 57, 68, 70, 78, 79, 88, 93, 95, 96, 122, 125, 126, 130, 132,
        136, 138, 139, 140, 147, 148, 149]  # fmt: skip


def _component(name: str, k: int) -> str:
    """The component an AT2 header would state for the k-th file (0, 1: horizontals; 2: vertical)."""
    if k == 2:
        return "UP"
    digits = "".join(c for c in name.split(".AT2")[0][-3:] if c.isdigit())
    return digits if len(digits) == 3 else ("L" if k == 0 else "T")


def write_at2(path: Path, rsn: int, k: int, npts: int = 2000, dt: float = 0.01) -> None:
    """A small valid PEER AT2 file (units g); its content differs by record and component."""
    t = np.arange(npts) * dt
    amp = 0.05 + 0.001 * rsn + 0.02 * k
    acc = amp * np.sin(2 * np.pi * (1.0 + 0.1 * k) * t) * np.exp(-0.2 * t) * np.minimum(t, 1.0)
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        f"Test quake {rsn}, 1/1/2000, Test station {rsn}, {_component(path.name, k)}",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {npts:6d}, DT= {dt:7.4f} SEC,",
    ]
    for i in range(0, npts, 5):
        lines.append("".join(f"{v:15.7E}" for v in acc[i : i + 5]))
    path.write_text("\n".join(lines) + "\n")


def search_folder(tmp_path: Path, rows: int | None = None, missing: int | None = None) -> Path:
    """A search folder: the real table and an AT2 file per file name of its first ``rows`` rows,
    except the second horizontal of row ``missing``."""
    d = tmp_path / "search"
    d.mkdir()
    shutil.copy(REAL, d / SEARCH_RESULTS)
    for r in read_search_results(REAL)[:rows]:
        for k, name in enumerate((r.h1, r.h2, r.vertical)):
            if name and not (r.row == missing and k == 1):
                write_at2(d / name, r.rsn, k)
    return d


# ------------------------------------------------------------------------------------------- the table
def test_the_real_table_is_read():
    rows = read_search_results(REAL)
    assert len(rows) == 30 and [r.rsn for r in rows] == RSNS
    assert [r.row for r in rows] == list(range(1, 31))
    r = rows[0]  # 1, SRSS, 6, ..., "Imperial Valley-02", 1940, "El Centro Array #9", 6.95, strike slip, ...
    m = r.metadata
    assert (r.id, r.earthquake, m.year, r.station, m.mw, m.mechanism) == (
        "RSN6", "Imperial Valley-02", 1940, "El Centro Array #9", 6.95, "strike slip"
    )  # fmt: skip
    assert (m.rjb_km, m.rrup_km, m.vs30_m_s, m.luf_hz, r.scale_factor) == (6.09, 6.09, 213.44, 0.25, 1.0)
    assert (r.h1, r.h2, r.vertical) == (
        "RSN6_IMPVALL.I_I-ELC180.AT2", "RSN6_IMPVALL.I_I-ELC270.AT2", "RSN6_IMPVALL.I_I-ELC-UP.AT2"
    )  # fmt: skip
    r78 = rows[12]  # its vertical is "-----": none
    assert (r78.rsn, r78.vertical, r78.files) == (
        78,
        None,
        ("RSN78_SFERN_PDL120.AT2", "RSN78_SFERN_PDL210.AT2"),
    )
    assert rows[27].metadata.mechanism == "strike slip" and rows[23].metadata.mechanism == "Reverse Oblique"


# --------------------------------------------------------------------------------------- the addition
def test_a_search_folder_is_added_with_its_metadata(tmp_path, capsys):
    d = search_folder(tmp_path, rows=4)
    recs = tmp_path / "recs"
    # rows 5 to 30 have no file in the folder: skipped, one line each; rows 1 to 4 added
    assert cli.main(["records", "add", "--peer-search", str(d), "--records", str(recs), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert [x["id"] for x in out["records"]] == ["RSN6", "RSN14", "RSN15", "RSN20"]
    assert len(out["skipped"]) == 26 and len(out["added"]) == 12
    assert out["records"][0]["metadata"] == {
        "rsn": 6, "mw": 6.95, "mechanism": "strike slip", "rjb_km": 6.09, "rrup_km": 6.09,
        "vs30_m_s": 213.44, "luf_hz": 0.25, "earthquake": "Imperial Valley-02", "year": 1940,
        "station": "El Centro Array #9",
    }  # fmt: skip
    man = read_manifest(recs / "manifest.csv")
    assert len(man) == 12
    h1, h2, v = man[:3]
    assert (h1.id, h1.file) == ("RSN6", "RSN6_IMPVALL.I_I-ELC180.AT2")
    assert h1.metadata == RecordMetadata(
        rsn=6, mw=6.95, mechanism="strike slip", rjb_km=6.09, rrup_km=6.09, vs30_m_s=213.44, luf_hz=0.25,
        year=1940,
    )  # fmt: skip
    assert (h1.event, h1.station) == ("Imperial Valley-02", "El Centro Array #9")
    # the two horizontals of one recording: one record, the same station and format, azimuths stated
    assert (h2.id, h2.metadata, h2.station, h2.format, h2.component) == (
        "", h1.metadata, h1.station, h1.format, "270"
    )  # fmt: skip
    assert h1.component == "180" and PAIRED_NOTE in h2.note
    assert (v.id, v.metadata.rsn, v.component) == ("", 6, "UP")
    # the record runs with its second horizontal (a partner file) and its vertical
    spec = catalog_record("RSN6", recs)
    assert [Path(f.path).name for f in spec.files] == [h1.file, v.file, h2.file]
    assert [f.partner for f in spec.files] == [False, False, True]
    assert spec.metadata == h1.metadata and spec.year == 1940
    # records status --json: the metadata of each added record
    assert cli.main(["records", "status", str(recs), "--json"]) == 0
    st = json.loads(capsys.readouterr().out)
    assert st["added"] == ["RSN6", "RSN14", "RSN15", "RSN20"]
    assert st["metadata"]["RSN14"] == {
        "rsn": 14, "mw": 7.36, "mechanism": "Reverse", "rjb_km": 81.3, "rrup_km": 82.19,
        "vs30_m_s": 514.99, "luf_hz": 0.375, "earthquake": "Kern County", "year": 1952,
        "station": "Santa Barbara Courthouse",
    }  # fmt: skip
    # run again (as after a stop): the files are recognised, nothing is added twice
    assert cli.main(["records", "add", "--peer-search", str(d), "--records", str(recs)]) == 1
    captured = capsys.readouterr()
    assert "already there RSN6" in captured.out and "same sha256: not added again" in captured.out
    assert len(read_manifest(recs / "manifest.csv")) == 12


def test_a_missing_file_is_reported_by_row_and_the_others_added(tmp_path, capsys):
    d = search_folder(tmp_path, missing=13)  # row 13: RSN 78, which has no vertical ("-----")
    (d / "RSN79_SFERN_PAS090.AT2").unlink()  # row 14: its second horizontal
    recs = tmp_path / "recs"
    assert cli.main(["records", "add", "--peer-search", str(d), "--records", str(recs)]) == 1
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [
        f"isorock: _SearchResults.csv row 13 (RSN 78): file RSN78_SFERN_PDL210.AT2 is not in {d}",
        f"isorock: _SearchResults.csv row 14 (RSN 79): file RSN79_SFERN_PAS090.AT2 is not in {d}",
    ]
    ids = [e.id for e in read_manifest(recs / "manifest.csv") if e.id]
    assert ids == [f"RSN{n}" for n in RSNS if n not in (78, 79)]
    assert "28 of 30 rows" in captured.out
    # with the files there, the same command finishes the job: exit 0
    write_at2(d / "RSN78_SFERN_PDL210.AT2", 78, 1)
    write_at2(d / "RSN79_SFERN_PAS090.AT2", 79, 1)
    assert cli.main(["records", "add", "--peer-search", str(d), "--records", str(recs)]) == 0
    assert capsys.readouterr().err == ""
    man = read_manifest(recs / "manifest.csv")
    assert [e.id for e in man if e.id] == [f"RSN{n}" for n in RSNS if n not in (78, 79)] + ["RSN78", "RSN79"]
    assert len(man) == 30 * 3 - 1  # RSN 78 has no vertical


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("Magnitude Min:, 0.0\nnothing else\n", "no table of records"),
        (
            "Result ID, Record Sequence Number, Horizontal-1 Acc. Filename\n1, 6, a.AT2\n",
            "no column 'horizontal-2 acc. filename'",
        ),
        (
            "Record Sequence Number, Magnitude, Horizontal-1 Acc. Filename, Horizontal-2 Acc. Filename\n"
            "six, 6.9, a.AT2, b.AT2\n",
            "Record Sequence Number 'six' is not a number",
        ),
        (
            "Record Sequence Number, Magnitude, Horizontal-1 Acc. Filename, Horizontal-2 Acc. Filename\n"
            "6, big, a.AT2, b.AT2\n",
            "Magnitude 'big' is not a number",
        ),
        (
            "Record Sequence Number, Horizontal-1 Acc. Filename, Horizontal-2 Acc. Filename\n"
            "6, ../../etc/passwd, b.AT2\n",
            "is not the name of a file in the folder",
        ),
        ("Record Sequence Number, Horizontal-1 Acc. Filename, Horizontal-2 Acc. Filename\n\n", "has no row"),
    ],
)
def test_a_malformed_table_exits_2_in_one_line(tmp_path, capsys, text, says):
    d = tmp_path / "search"
    d.mkdir()
    (d / SEARCH_RESULTS).write_text(text)
    recs = tmp_path / "recs"
    assert cli.main(["records", "add", "--peer-search", str(d), "--records", str(recs)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err and "Traceback" not in err
    assert not (recs / "manifest.csv").exists()


def test_peer_search_refuses_files_and_file_options(tmp_path, capsys):
    d = search_folder(tmp_path, rows=1)
    argv = ["records", "add", "--peer-search", str(d), "--records", str(tmp_path / "r")]
    assert cli.main([*argv, str(d / "RSN6_IMPVALL.I_I-ELC180.AT2"), "--event", "X"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not with FILE, --event" in err
    assert cli.main(["records", "add", "--peer-search", str(tmp_path / "nope")]) == 2
    assert "not a folder" in capsys.readouterr().err


def test_an_old_manifest_still_reads(tmp_path):
    (tmp_path / "manifest.csv").write_text(
        "file,table1_id,id,format,units,dt_s,column\nx.AT2,,X,peer-at2,,,\n"
    )
    (e,) = read_manifest(tmp_path / "manifest.csv")
    assert (e.id, e.metadata) == ("X", RecordMetadata())
    (tmp_path / "manifest.csv").write_text(
        "file,table1_id,id,format,units,dt_s,column,luf_hz\nx.AT2,,X,peer-at2,,,,-1\n"
    )
    with pytest.raises(Exception, match="luf_hz='-1' is not a frequency > 0 Hz"):
        read_manifest(tmp_path / "manifest.csv")


# ---------------------------------------------------------------------- the lowest usable frequency
def _bandpass(steps):
    (bp,) = [s for s in steps if s.step == "bandpass_filter"]
    return bp


def test_the_lowest_usable_frequency_raises_the_high_pass_corner(tmp_path):
    from isorock.io import read_trace

    f = tmp_path / "RSN1_X_ABC090.AT2"
    write_at2(f, 1, 0)
    tr = read_trace(f)
    default = _bandpass(applied_steps(process(tr)))
    assert default.parameters["freqmin"] == 0.05 and "luf_hz" not in default.parameters
    raised = process(tr, with_lowest_usable_frequency(None, 0.25))
    bp = _bandpass(applied_steps(raised))
    assert bp.parameters["freqmin"] == 0.25 and bp.parameters["luf_hz"] == 0.25
    assert "raised from 0.05 Hz to the record's lowest usable frequency 0.25 Hz" in bp.note
    assert any("lowest usable frequency 0.25 Hz" in line for line in raised.stats.processing)
    # a lowest usable frequency below the corner keeps it
    kept = _bandpass(applied_steps(process(tr, with_lowest_usable_frequency(None, 0.02))))
    assert kept.parameters["freqmin"] == 0.05 and "not above freqmin: kept" in kept.note
    # without one, the processing is the configuration's own
    assert with_lowest_usable_frequency(default_config(), None) == default_config()
    assert not np.allclose(raised.data, process(tr).data)


def test_the_metadata_and_the_corner_reach_the_store(tmp_path, capsys):
    d = search_folder(tmp_path, rows=1)
    recs = tmp_path / "recs"
    assert cli.main(["records", "add", "--peer-search", str(d), "--records", str(recs)]) == 1  # 29 skipped
    capsys.readouterr()
    spec = catalog_record("RSN6", recs)
    out = tmp_path / "rec.h5"
    attrs = jobs.process_record(spec, out)
    assert (attrs["rsn"], attrs["mw"], attrs["mechanism"]) == (6, 6.95, "strike slip")
    assert (attrs["rjb_km"], attrs["rrup_km"], attrs["vs30_m_s"], attrs["luf_hz"]) == (
        6.09,
        6.09,
        213.44,
        0.25,
    )
    with h5py.File(out, "r") as h:
        stored = attrs_dict(h["records/RSN6"])
        lines = [x.decode() if isinstance(x, bytes) else x for x in h["records/RSN6/processing"][()]]
    assert stored["luf_hz"] == 0.25 and stored["mw"] == 6.95 and stored["rsn"] == 6
    steps = json.loads(stored["processing_json"])
    (bp,) = [s for s in steps if s["step"] == "bandpass_filter"]
    assert bp["parameters"]["freqmin"] == 0.25
    assert any("raised from 0.05 Hz" in line for line in lines)
    # its two horizontals (the second a partner file, no record of its own) give its RotD values
    h1, h2 = read_search_results(REAL)[0].h1, read_search_results(REAL)[0].h2
    assert h1 in attrs["rotd_pair"] and h2 in attrs["rotd_pair"]
    rot50, rot100 = json.loads(attrs["rotd50"]), json.loads(attrs["rotd100"])
    assert 0 < rot50["PGA"] <= rot100["PGA"] and 0 < rot50["PGV"] <= rot100["PGV"]
    # isorock info --id reads it as the workflow does: the same corner, the same RotD values
    capsys.readouterr()
    assert cli.main(["info", "--id", "RSN6", "--records", str(recs), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["rotd50"]["PGV"] == pytest.approx(rot50["PGV"], rel=1e-12)
    assert shown["pgv_m_s"] == pytest.approx(attrs["pgv_m_s"], rel=1e-12)
    # a record without metadata: NaN, -1, ""
    plain = jobs.process_record(RecordSpec(id="X", label="x", files=spec.files[:1]), tmp_path / "x.h5")
    assert plain["rsn"] == -1 and math.isnan(plain["luf_hz"]) and plain["mechanism"] == ""
    assert plain["rotd_pair"] == "" and json.loads(plain["rotd50"]) == {}  # one horizontal
    assert _bandpass_freqmin(plain) == 0.05


def _bandpass_freqmin(attrs) -> float:
    (bp,) = [s for s in json.loads(attrs["processing_json"]) if s["step"] == "bandpass_filter"]
    return bp["parameters"]["freqmin"]
