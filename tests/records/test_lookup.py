"""The record lookup (issue 17): the user's added records run with the records already there
(``records.include``), a record added twice is one record, a different file under a registered id is
refused, and an added record is found by its id like a catalog row.

Every record here is synthetic; ``$ISOROCK_RECORDS`` is unset so that no shared directory joins in.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from isorock.errors import ConfigError, IsorockError
from isorock.pipeline import load_config
from isorock.records.adding import NAMED_COMPONENT_NOTE, add_records
from isorock.records.directory import DEFAULT_RECORDS_DIR, default_records_dir
from isorock.records.lookup import INCLUDE, catalog_record, find_records
from isorock.records.manifest import read_manifest
from isorock.records.naming import component_from_name

N_SAMPLES = 18  # pyslammer's sample ground motions


@pytest.fixture(autouse=True)
def _no_env_records(monkeypatch):
    monkeypatch.delenv("ISOROCK_RECORDS", raising=False)


def _quake(path: Path, amp: float = 0.3, n: int = 800, dt: float = 0.01) -> Path:
    t = np.arange(n) * dt
    np.savetxt(path, amp * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.4 * t) * np.minimum(t, 1.0))
    return path


def _rc(**records) -> dict:
    return load_config({"records": records})["records"]


def _samples() -> int:
    pytest.importorskip("pyslammer", reason="the sample record set needs pyslammer (isorock[samples])")
    return N_SAMPLES


@pytest.fixture
def mine(tmp_path) -> Path:
    """A records directory holding two records of the user's own."""
    d = tmp_path / "mine"
    add_records([_quake(tmp_path / "q1.txt")], d, ids=["Q1"], dt=0.01, units="g")
    add_records([_quake(tmp_path / "q2.txt", amp=0.2)], d, ids=["Q2"], dt=0.01, units="g")
    return d


@pytest.fixture
def with_row(tmp_path, mine) -> Path:
    """``mine`` with a file registered as the Table 1 row TAB78-TAB."""
    add_records([_quake(tmp_path / "tab.txt", amp=0.5)], mine, table1_id="TAB78-TAB",
                format="one-column", dt=0.01, units="g")  # fmt: skip
    return mine


# --------------------------------------------------------------------------------------- include
def test_added_records_run_with_the_samples_by_default(mine):
    n = _samples()
    rs = find_records(_rc(dir=str(mine)))
    ids = [r.id for r in rs.records]
    assert len(ids) == n + 2 and ids[-2:] == ["Q1", "Q2"]
    assert rs.source == f"pyslammer samples + records directory {mine.resolve()}"
    assert any("its added records run with the pyslammer samples" in w for w in rs.warnings)


def test_added_records_run_with_the_table1_rows_and_not_the_samples(with_row):
    rs = find_records(_rc(dir=str(with_row)))
    assert [r.id for r in rs.records] == ["TAB78-TAB", "Q1", "Q2"]
    assert "pyslammer" not in rs.source


@pytest.mark.parametrize(
    "include, expect",
    [
        (["added"], ["Q1", "Q2"]),
        (["table1"], ["TAB78-TAB"]),
        (["table1", "added"], ["TAB78-TAB", "Q1", "Q2"]),
        (["samples"], "samples"),
        (["samples", "added"], "samples+Q"),
        (["samples", "table1", "added"], "samples+TAB+Q"),
    ],
)
def test_include_takes_the_record_sets_it_names(with_row, include, expect):
    if "samples" in include:
        n = _samples()
    rs = find_records(_rc(dir=str(with_row), include=include))
    ids = [r.id for r in rs.records]
    if expect == "samples":
        assert len(ids) == n and all(r.source == "pyslammer samples" for r in rs.records)
    elif expect == "samples+Q":
        assert len(ids) == n + 2 and ids[-2:] == ["Q1", "Q2"]
    elif expect == "samples+TAB+Q":
        assert len(ids) == n + 3 and ids[-3:] == ["TAB78-TAB", "Q1", "Q2"]
    else:
        assert ids == expect


def test_include_values_and_errors(mine):
    assert INCLUDE == ("samples", "table1", "added")
    assert load_config({})["records"]["include"] is None  # default: what is there
    with pytest.raises(ConfigError, match="records.include"):
        load_config({"records": {"include": ["tabel1"]}})
    with pytest.raises(ConfigError, match=r"records.include \(table1\) takes none of the records"):
        find_records(_rc(dir=str(mine), include=["table1"]))


def test_an_empty_directory_still_stops_the_run(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ConfigError, match="no records to run"):
        find_records(_rc(dir=str(empty)))


def test_no_directory_gives_the_samples():
    n = _samples()
    rs = find_records(_rc())
    assert len(rs.records) == n and rs.source == "pyslammer samples"


def test_the_default_place_of_records_add_is_found(tmp_path):
    n = _samples()
    assert default_records_dir(tmp_path) is None
    d = tmp_path / DEFAULT_RECORDS_DIR
    add_records([_quake(tmp_path / "q.txt")], d, ids=["MINE"], dt=0.01, units="g")
    assert default_records_dir(tmp_path) == d
    rs = find_records(_rc(), tmp_path)
    assert len(rs.records) == n + 1 and rs.records[-1].id == "MINE"
    assert "the default place of 'isorock records add'" in rs.source


# --------------------------------------------------------------------------------------- one record
def test_a_record_added_twice_is_one_record(tmp_path, mine):
    notes: list[str] = []
    again = add_records([tmp_path / "q1.txt"], mine, ids=["Q1"], dt=0.01, units="g", notes=notes)
    assert again == [] and len(notes) == 1 and "same sha256" in notes[0] and "record Q1" in notes[0]
    # the same content under another id and name is the same record too
    shutil.copy(tmp_path / "q1.txt", tmp_path / "copy.txt")
    notes.clear()
    assert add_records([tmp_path / "copy.txt"], mine, ids=["Q9"], dt=0.01, units="g", notes=notes) == []
    assert "record Q1" in notes[0]
    assert [e.id for e in read_manifest(mine / "manifest.csv")] == ["Q1", "Q2"]


def test_another_file_under_a_registered_id_is_refused_in_one_line(tmp_path, mine):
    other = _quake(tmp_path / "other.txt", amp=0.4)
    with pytest.raises(IsorockError, match="id 'Q1' is already registered") as info:
        add_records([other], mine, ids=["Q1"], dt=0.01, units="g")
    msg = str(info.value)
    assert "different sha256" in msg and "--replace" in msg and "\n" not in msg
    assert not (mine / "other.txt").exists()


def test_an_added_sample_file_runs_once(tmp_path):
    _samples()
    from isorock.records.directory import sample_records

    s = sample_records()[0]
    d = tmp_path / "mine"
    add_records([s.path], d, ids=["MY-COPY"])
    rs = find_records(_rc(dir=str(d)))
    assert len(rs.records) == N_SAMPLES and "MY-COPY" not in [r.id for r in rs.records]
    assert any("is the pyslammer sample" in w and "same sha256" in w for w in rs.warnings)


def test_an_added_id_that_is_a_sample_name_is_refused(tmp_path):
    _samples()
    from isorock.records.directory import sample_records

    name = sample_records()[0].name
    d = tmp_path / "mine"
    add_records([_quake(tmp_path / "q.txt")], d, ids=[name], dt=0.01, units="g")
    with pytest.raises(ConfigError, match="also the name of a pyslammer sample"):
        find_records(_rc(dir=str(d)))
    assert [r.id for r in find_records(_rc(dir=str(d), include=["added"])).records] == [name]


def test_an_added_record_is_found_by_its_id(mine):
    spec = catalog_record("Q2", mine)
    assert spec.id == "Q2" and spec.catalog_id == "" and spec.target.azimuth_deg is None
    f = spec.files[0]
    assert (f.format, f.units, f.dt_s) == ("one-column", "g", 0.01) and Path(f.path).name == "q2.txt"
    with pytest.raises(IsorockError, match="not a catalog row nor a record added to") as info:
        catalog_record("NOPE", mine)
    assert "added: Q1, Q2" in str(info.value)


def test_a_sample_is_found_by_its_name():
    _samples()
    from isorock.records.directory import sample_records

    s = sample_records()[0]
    assert catalog_record(s.name).files[0].format == "pyslammer-csv"


# --------------------------------------------------------------------------------------- components
@pytest.mark.parametrize(
    "name, comp",
    [
        ("rinaldi_fn.dat", "FN"),
        ("elcen05_230fn.dat", "FN"),
        ("site_fp.txt", "FP"),
        ("quake-E.AT2", "E"),
        ("sta-N.dat", "N"),
        ("IV_ns.txt", "NS"),
        ("x_ud.txt", "U-D"),
        ("pacoima_164.dat", "164"),
        ("RSN1052_NORTHR_PKC090.AT2.g3", "090"),
        ("RSN77_SFERN_PUL164-hor1.AT2", "164"),
        ("abc-hor2.AT2", "HOR2"),
        ("my_S16E.txt", "S16E"),
        ("A.AT2.g3", None),
        ("B.dat", None),
        ("E.txt", None),  # the first part is the event or station, never a component
        ("Northridge_Sylmar_County.dat", None),
        ("SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt", None),
    ],
)
def test_component_from_name(name, comp):
    assert component_from_name(name) == comp


def test_records_add_takes_the_component_from_the_name_and_says_so(tmp_path):
    d = tmp_path / "mine"
    (e,) = add_records([_quake(tmp_path / "quake-E.txt")], d, dt=0.01, units="g")
    assert e.component == "E" and NAMED_COMPONENT_NOTE in e.note
    spec = catalog_record("quake-E", d)
    assert spec.files[0].component == "E"
    (e,) = add_records([_quake(tmp_path / "other-E.txt", amp=0.2)], d, dt=0.01, units="g", component="N")
    assert e.component == "N" and e.note == ""  # given: not inferred
