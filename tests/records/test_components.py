"""The component of a record: azimuths from names, rotation (against ObsPy), and the choice of the
direction the catalog row asks for, on synthetic files whose true direction is known."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from obspy import Trace, UTCDateTime
from obspy.signal.rotate import rotate_ne_rt

from isorock import G  # the g of the readers' unit conversion
from isorock.errors import IsorockError
from isorock.processing.orientation import rotate_horizontal
from isorock.records.components import choose_component
from isorock.records.files import check_alignment
from isorock.records.naming import is_vertical, line_angle, parse_azimuth, provided_orientation
from isorock.records.spec import RecordFile, Target
from isorock.records.table1 import load_table1
from support.records import RECORDS_SKIP, need_records, read_row, row_of
from support.records import manifest as records_manifest

DT = 0.01
GBZ000, GBZ270 = "SLAMMER_Kocaeli1999_GBZ-000_g.txt", "SLAMMER_Kocaeli1999_GBZ-270_g.txt"
TAB_TR, TAB_LN = "SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt", "SLAMMER_Tabas1978_TAB-LN_g_dt0.02.txt"


@pytest.mark.parametrize(
    "name, az",
    [("230", 230.0), ("090", 90.0), ("360", 0.0), ("000", 0.0), ("N-S", 0.0), ("E-W", 90.0),
     ("S16E", 164.0), ("N44W", 316.0), ("S50W", 230.0), ("N10E", 10.0), ("HNE", 90.0), ("HNN", 0.0),
     ("TR", None), ("FN", None), ("Long", None), ("", None), ("N95E", None)],
)  # fmt: skip
def test_parse_azimuth(name, az):
    assert parse_azimuth(name) == az


def test_provided_orientation_and_line_angle():
    assert provided_orientation("FN") == "SN" and provided_orientation("fault-parallel") == "SP"
    assert provided_orientation("230") is None
    assert (
        line_angle(233.0, 53.0) == 0.0 and line_angle(65.0, 50.0) == 15.0 and line_angle(350.0, 80.0) == 90.0
    )


def test_target_of_a_catalog_row():
    t = Target.of("SN", 323.0, "NGA-West2")
    assert (t.label, t.azimuth_deg) == ("SN", 53.0)
    assert Target.of("SP", 271.0, "x").azimuth_deg == 271.0
    assert Target.of("090").azimuth_deg == 90.0
    assert Target.of("Long").azimuth_deg is None
    assert Target.of("SN").azimuth_deg is None  # no strike: the direction is not known


@pytest.mark.parametrize("az", [0.0, 53.0, 212.0, 301.5])
def test_rotation_of_north_east_matches_obspy(az):
    """The component along ``az`` is minus ObsPy's radial component for back-azimuth ``az``."""
    rng = np.random.default_rng(3)
    n, e = rng.standard_normal(200), rng.standard_normal(200)
    r, _ = rotate_ne_rt(n, e, az)
    np.testing.assert_allclose(rotate_horizontal(n, 0.0, e, 90.0, az), -r, atol=1e-12)


def test_rotation_of_non_orthogonal_components_recovers_the_motion():
    rng = np.random.default_rng(4)
    n, e = rng.standard_normal(100), rng.standard_normal(100)

    def along(a):
        return n * math.cos(math.radians(a)) + e * math.sin(math.radians(a))

    got = rotate_horizontal(along(20.0), 20.0, along(95.0), 95.0, 233.0)
    np.testing.assert_allclose(got, along(233.0), atol=1e-12)
    with pytest.raises(IsorockError, match="parallel"):
        rotate_horizontal(n, 10.0, e, 15.0, 0.0)


# ------------------------------------------------------------------ synthetic recordings
def _pulse(n: int = 3000) -> np.ndarray:
    """A two-sided acceleration pulse [m/s^2] with a little noise, zero at both ends."""
    t = np.arange(n) * DT
    a = 3.0 * np.sin(2 * np.pi * t / 2.0) * np.exp(-(((t - 10.0) / 2.5) ** 2))
    return a + 0.05 * np.random.default_rng(5).standard_normal(n) * np.sin(np.pi * t / t[-1]) ** 2


def _write(path: Path, acc: np.ndarray) -> Path:
    np.savetxt(path, acc / G, fmt="%.8e")  # one column, g
    return path


def _file(path: Path, component: str, station: str = "STA", **kw) -> RecordFile:
    return RecordFile(
        path=str(path), format="one-column", dt_s=DT, units="g", component=component, station=station,
        component_name=component, **kw,
    )  # fmt: skip


@pytest.fixture()
def pair(tmp_path):
    """Two recorded components (azimuths 140 and 230) of a motion polarised along azimuth 53 deg."""
    p = _pulse()
    files = []
    for az in (140.0, 230.0):
        f = _write(tmp_path / f"STA-{az:03.0f}.txt", p * math.cos(math.radians(az - 53.0)))
        files.append(_file(f, f"{az:03.0f}"))
    return p, files


def test_two_components_are_rotated_to_the_strike_normal(pair):
    p, files = pair
    ch = choose_component(files, Target.of("SN", 323.0, "test strike"), raw=True)
    assert ch.method == "rotated" and ch.component == "SN" and ch.azimuth_deg == 53.0
    assert ch.qa_mark == ""
    np.testing.assert_allclose(ch.record.trace.data, p, atol=2e-8 * np.abs(p).max())
    rot = ch.record.source.rotated_from
    assert [r["component"] for r in rot] == ["140", "230"] and all(len(r["sha256"]) == 64 for r in rot)
    assert "140" in ch.description and "230" in ch.description and "053.0" in ch.description


def test_one_component_is_used_as_recorded_with_a_qa_mark(pair):
    _, files = pair
    ch = choose_component(files[:1], Target.of("SN", 323.0, "test strike"), raw=True)
    assert (ch.method, ch.component, ch.azimuth_deg) == ("as recorded", "140", 140.0)
    assert ch.qa_mark == "as recorded, azimuth 140 instead of SN (87 deg off)"


def test_a_component_within_5_degrees_is_the_direction_without_a_mark(pair):
    _, files = pair
    ch = choose_component(files[1:], Target.of("SN", 323.0, "test strike"), raw=True)
    assert (ch.method, ch.component, ch.qa_mark) == ("aligned", "SN", "")


def test_components_of_different_stations_are_not_rotated_together(pair):
    _, (f1, f2) = pair
    other = RecordFile(**{**f2.__dict__, "station": "OTHER"})
    ch = choose_component([f1, other], Target.of("SN", 323.0, "s"), raw=True)
    assert ch.method == "aligned"  # 230 is 3 deg from 233: no pair was formed


def test_a_provided_fault_normal_file_comes_first(pair, tmp_path):
    p, files = pair
    fn = _file(_write(tmp_path / "STA-FN.txt", 0.9 * p), "FN")
    ch = choose_component([*files, fn], Target.of("SN", 323.0, "s"), raw=True)
    assert (ch.method, ch.component, ch.azimuth_deg) == ("provided", "SN", 53.0)


def test_a_direction_that_disagrees_with_the_catalog_is_not_chosen(pair):
    """The paper's own PGA and PGV identify its component: the SN rotation (PGV about 0.4 x) loses
    to a recorded component that matches them, and the choice says so."""
    p, files = pair
    rotated = choose_component(files, Target.of("SN", 323.0, "s"), raw=True)
    pga = float(np.abs(rotated.record.trace.data).max()) / G
    # a catalog whose PGA is that of the 140 component (cos 87 deg of the pulse): the rotation is 19 x off
    ch = choose_component(files, Target.of("SN", 323.0, "s"), raw=True, table1_pga_g=pga * 0.0523)
    assert ch.method == "as recorded" and ch.component == "140"
    assert "the rotated SN is not used: its PGA is" in ch.qa_mark


def test_without_a_catalog_direction_the_record_is_as_recorded(pair):
    _, files = pair
    ch = choose_component(files, None, raw=True)
    assert ch.method == "as recorded" and ch.qa_mark == "" and ch.target.label == ""


def test_unreadable_files_are_reported_not_fatal(pair, tmp_path):
    _, files = pair
    bad = tmp_path / "bad.txt"
    bad.write_text("1.0\nnot a number\n")
    ch = choose_component([_file(bad, "000"), *files], Target.of("SN", 323.0, "s"), raw=True)
    assert ch.method == "rotated"
    assert ch.candidates[0]["ok"] is False and "bad.txt" in ch.candidates[0]["file"]
    with pytest.raises(IsorockError, match="no file could be read"):
        choose_component([_file(bad, "000")], Target.of("SN", 323.0, "s"))


def test_bbp_file_gives_both_horizontals(tmp_path):
    """A BBP file holds N-S and E-W: they are rotated together, whichever column its row names."""
    p = _pulse(2000)
    az = 212.0
    n, e = p * math.cos(math.radians(az)), p * math.sin(math.radians(az))
    t = np.arange(p.size) * DT
    path = tmp_path / "sta.bbp"
    with path.open("w") as fh:
        fh.write("# station STA\n# time(sec) N-S(cm/s/s) E-W(cm/s/s) U-D(cm/s/s)\n")
        for row in zip(t, 100 * n, 100 * e, 100 * n, strict=True):
            fh.write(" ".join(f"{x:.8e}" for x in row) + "\n")
    f = RecordFile(path=str(path), format="bbp", component="N-S", station="STA", component_name="N-S")
    ch = choose_component([f], Target.of("SN", 122.0, "s"), raw=True)
    assert ch.method == "rotated" and ch.azimuth_deg == 212.0
    np.testing.assert_allclose(ch.record.trace.data, p, atol=1e-6 * np.abs(p).max())


# ------------------------------------------------------------------ time alignment of a pair
def _shifted(a: np.ndarray, seconds: float, dt: float = DT) -> np.ndarray:
    """``a`` delayed by ``seconds`` (zeros in front), cut to its length."""
    k = int(round(seconds / dt))
    return np.concatenate([np.zeros(k), a[: a.size - k]])


def _trace(a: np.ndarray, dt: float = DT) -> Trace:
    return Trace(np.asarray(a, dtype=float), header={"delta": dt})


def test_check_alignment_of_two_components_of_one_motion(pair):
    p, _ = pair
    al = check_alignment(_trace(p * 0.3), _trace(-p))
    assert al.ok and al.problem == "" and abs(al.lag_s) <= DT and al.envelope_corr == pytest.approx(1.0)
    assert "time-aligned" in al.describe()


@pytest.mark.parametrize("shift", [2.0, -3.0, 8.0])
def test_check_alignment_finds_a_shift(pair, shift):
    """A shift of either component by 2 s or more is refused, with its size and sign."""
    p, _ = pair
    first, second = (p, _shifted(p, shift)) if shift > 0 else (_shifted(p, -shift), p)
    al = check_alignment(_trace(first), _trace(second))
    assert not al.ok and al.lag_s == pytest.approx(shift, abs=2 * DT)
    when = "after" if shift > 0 else "before"
    assert f"the energy of the second arrives {abs(al.lag_s):.2f} s {when} that of the first" in al.problem


def test_check_alignment_refuses_what_the_files_state():
    p = _pulse()
    assert "time steps differ" in check_alignment(_trace(p), _trace(p, 0.02)).problem
    assert (
        "lengths differ by 100 samples" in check_alignment(_trace(p), _trace(np.r_[p, np.zeros(100)])).problem
    )
    # within 0.5 %: a longer trailer is allowed
    assert check_alignment(_trace(p), _trace(np.r_[p, np.zeros(10)])).ok
    early, late = _trace(p), _trace(p)  # formats stating an absolute start
    early.stats.starttime = UTCDateTime(1999, 8, 17, 0, 1, 40)
    late.stats.starttime = early.stats.starttime + 2.0
    assert "starts +2.000 s apart" in check_alignment(early, late).problem
    assert check_alignment(late, _trace(p)).ok  # one states none: nothing to compare
    noise = np.random.default_rng(9).standard_normal(p.size)  # stationary: an envelope without a burst
    assert "do not correlate" in check_alignment(_trace(p), _trace(noise)).problem
    # one file with one time column (BBP): aligned by construction, whatever the envelopes
    assert check_alignment(_trace(p), _trace(_shifted(p, 3.0)), one_file=True).ok


def test_a_pair_shifted_in_time_is_not_rotated(pair, tmp_path):
    """The 140 component delayed by 3 s: no rotation, the 230 one (3 deg from SN) is analysed and the
    QA mark says why the pair was refused."""
    p, (f140, f230) = pair
    late = _write(tmp_path / "STA-140-late.txt", _shifted(p * math.cos(math.radians(140.0 - 53.0)), 3.0))
    f_late = RecordFile(**{**f140.__dict__, "path": str(late)})
    ch = choose_component([f_late, f230], Target.of("SN", 323.0, "s"), raw=True)
    assert ch.method == "aligned" and ch.component == "SN"
    (why,) = ch.pairs_refused
    assert why.startswith("140 (STA-140-late.txt) and 230 (STA-230.txt) not rotated to SN: not time-aligned")
    assert "the energy of the second arrives 2.99 s before that of the first" in why and ch.qa_mark == why
    # the same files in time are rotated, and the description says they were checked
    ok = choose_component([f140, f230], Target.of("SN", 323.0, "s"), raw=True)
    assert ok.method == "rotated" and ok.pairs_refused == [] and "time-aligned" in ok.description


def test_a_pair_whose_files_state_different_starts_is_not_rotated(pair, tmp_path):
    p, _ = pair
    files = []
    for az, t0 in ((140.0, 0.0), (230.0, 1.5)):
        path = tmp_path / f"TC-{az:03.0f}.txt"
        t = t0 + np.arange(p.size) * DT
        np.savetxt(path, np.c_[t, p * math.cos(math.radians(az - 53.0)) / G], fmt="%.8e")
        files.append(RecordFile(path=str(path), format="two-column", units="g", station="STA",
                                component_name=f"{az:03.0f}"))  # fmt: skip
    ch = choose_component(files, Target.of("SN", 323.0, "s"), raw=True)
    assert ch.method == "aligned" and "their files state starts +1.500 s apart" in ch.qa_mark


def test_a_component_of_unknown_azimuth_is_not_rotated_and_the_mark_says_so(pair, tmp_path):
    p, (f140, _) = pair
    tr = RecordFile(**{**f140.__dict__, "component": "TR", "component_name": "TR"})
    ln_path = _write(tmp_path / "STA-LN.txt", 0.5 * p)
    ln = _file(ln_path, "LN")
    ch = choose_component([tr, ln], Target.of("SP", 330.0, "s"), raw=True)
    assert ch.method == "as recorded" and ch.azimuth_deg is None
    assert ch.qa_mark.startswith("as recorded (") and "instead of SP" in ch.qa_mark
    assert "not rotated to SP: their azimuths are not known" in ch.qa_mark
    assert "the two are time-aligned" in ch.qa_mark


def test_a_partner_file_is_only_the_second_component_of_a_rotation(pair):
    """The file of another catalog row of the same recording (GBZ/SN and GBZ/SP) helps rotate, but is
    never analysed alone for this row."""
    p, (f140, f230) = pair
    partner = RecordFile(**{**f230.__dict__, "partner": True})
    ch = choose_component([f140, partner], Target.of("SN", 323.0, "s"), raw=True)
    assert ch.method == "rotated" and Path(ch.file.path).name == "STA-140.txt"
    assert [c["component"] for c in ch.candidates] == ["140", "SN"]  # no 230 alone
    refused = choose_component([f140, partner], Target.of("SN", 323.0, "s"), raw=True, table1_pgv_m_s=1e-3)
    assert refused.method == "rotated"  # inconsistent with the catalog, but the 230 alone is no candidate
    with pytest.raises(IsorockError, match="no file could be read"):
        choose_component(
            [RecordFile(**{**f140.__dict__, "path": "/none"}), partner], Target.of("SN", 323.0, "s")
        )


# ------------------------------------------------------------------ the shared records
def _manifest_pairs() -> list:
    """``pytest.param`` per two horizontal files of one station and format of the records manifest
    (a vertical, ``UP`` or ``DWN``, is never rotated with a horizontal)."""
    rows = [r for r in records_manifest() if r["format"] != "bbp" and not is_vertical(r["component"])]
    out = [
        pytest.param(a, b, id=f"{a['file']}+{b['file']}")
        for i, a in enumerate(rows)
        for b in rows[i + 1 :]
        if a["station"] == b["station"] and a["format"] == b["format"] and a["dt_s"] == b["dt_s"]
    ]
    return out or [pytest.param(None, None, marks=pytest.mark.skip(reason=RECORDS_SKIP), id="no-records")]


@pytest.mark.parametrize(("a", "b"), _manifest_pairs())
def test_every_pair_of_the_shared_records_is_time_aligned(a, b):
    """No false refusal: the two horizontal files of every station of the shared records pass the
    check, and delaying one of them by 3 s is refused. Real sets: their energy envelopes peak within
    0.65 s of each other and correlate at 0.75 (El Centro 1940, 180 and 270, files 26 samples apart)
    to 0.97; the check's own floor for one recording is 0.5."""
    t1, t2 = read_row(a), read_row(b)
    al = check_alignment(t1, t2)
    assert al.ok, al.problem
    assert abs(al.lag_s) < 1.0 and al.envelope_corr > 0.7
    late = _trace(_shifted(t2.data, 3.0, t2.stats.delta), t2.stats.delta)
    bad = check_alignment(t1, late)
    assert not bad.ok and bad.lag_s == pytest.approx(al.lag_s + 3.0, abs=0.3)


def test_gebze_is_rotated_to_its_strike_normal_and_strike_parallel():
    """GBZ-000 (row KOC99-GBZN) and GBZ-270 (row KOC99-GBZP): one recording, a file per row,
    time-aligned: both rows are rotated from the two; the SP row keeps its PGA check (Table 1's 0.03 g
    fits no direction of the recording)."""
    d = need_records()
    if not all((d / f).is_file() for f in (GBZ000, GBZ270)):
        pytest.skip("the Gebze files are not in the records directory")
    sn, sp = load_table1("KOC99-GBZN", d), load_table1("KOC99-GBZP", d)
    assert (sn.method, sn.component, sn.azimuth_deg) == ("rotated", "SN", 1.0)
    assert (sp.method, sp.component, sp.azimuth_deg) == ("rotated", "SP", 271.0)
    assert sn.qa_mark == sp.qa_mark == "" and sn.pairs_refused == sp.pairs_refused == []
    assert [r["component"] for r in sn.record.source.rotated_from] == ["000", "270"]
    assert [r["component"] for r in sp.record.source.rotated_from] == ["270", "000"]
    assert "time-aligned" in sn.description
    assert sn.table1_check == "" and 0.9 < sn.pga_over_table1 < 1.0 and 1.2 < sn.pgv_over_table1 < 1.3
    # SP: the PGV is Table 1's, the PGA 4.5 x: flagged, and no candidate is chosen over it for that
    assert 0.95 < sp.pgv_over_table1 < 1.05 and 4.4 < sp.pga_over_table1 < 4.6
    assert sp.table1_check.startswith("PGA 0.135 g = 4.49 x")
    assert [c["component"] for c in sp.candidates] == ["270", "SP"]
    assert all(c["pga_g"] > 4 * 0.03 for c in sp.candidates)


def test_tabas_is_not_rotated_because_its_azimuths_are_not_known():
    """TAB-TR and TAB-LN: time-aligned, but the source states neither azimuth: no SP direction."""
    d = need_records()
    if not all((d / f).is_file() for f in (TAB_TR, TAB_LN)):
        pytest.skip("the Tabas files are not in the records directory")
    ch = load_table1("TAB78-TAB", d)
    assert (ch.method, ch.component, ch.azimuth_deg) == ("as recorded", "TR", None)
    (why,) = ch.pairs_refused
    assert why.startswith("TR (SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt) and LN (")
    assert "their azimuths are not known" in why and "the two are time-aligned" in why
    assert ch.qa_mark == f"as recorded (TR, azimuth not known) instead of SP; {why}"
    assert 0.95 < ch.pga_over_table1 < 1.05 and 0.95 < ch.pgv_over_table1 < 1.05
    al = check_alignment(read_row(row_of(TAB_TR)), read_row(row_of(TAB_LN)))
    assert al.ok and abs(al.lag_s) < 0.2 and al.npts == (1642, 1642)


@pytest.mark.parametrize("name", ["UP", "DWN", "U-D", "HNZ", "DOWN"])
def test_vertical_component_names(name):
    assert is_vertical(name)


def test_a_vertical_file_of_a_row_is_no_horizontal_candidate():
    """Every vertical file the shared manifest gives a Table 1 row (the Pacoima Dam DWN) is left out of
    the row's horizontal candidates and of its rotations."""
    d = need_records()
    rows = [r for r in records_manifest() if r["table1_id"] and is_vertical(r["component"])]
    if not rows:
        pytest.skip("no vertical file of a Table 1 row in the records directory")
    for r in rows:
        ch = load_table1(r["table1_id"], d)
        assert all(r["file"] not in c["file"] for c in ch.candidates), ch.candidates
        assert all(r["file"] not in why for why in ch.pairs_refused)


@pytest.mark.parametrize(
    "name, component",
    [("RSN6_IMPVALL.I_I-ELC-UP.AT2", "U-D"), ("RSN6_IMPVALL.I_I-ELC180.AT2", "180"),
     ("RSN6_IMPVALL.I_I-ELC270-hor2.AT2", "270"), ("RSN982_NORTHR_JEN022.AT2.g3", "022"),
     ("RSN30_PARKF_C05DWN.AT2", "DWN"), ("SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt", None)],
)  # fmt: skip
def test_a_dot_inside_a_peer_name_is_not_its_extension(name, component):
    """PEER names a record's files ``RSN6_IMPVALL.I_I-ELC180.AT2``: only the extensions are taken off."""
    from isorock.records.naming import component_from_name

    assert component_from_name(name) == component


def test_the_vertical_beside_a_peer_horizontal_is_found_by_its_name(tmp_path):
    from isorock.records.vertical import sibling_files

    for n in ("RSN6_IMPVALL.I_I-ELC180.AT2", "RSN6_IMPVALL.I_I-ELC270.AT2", "RSN6_IMPVALL.I_I-ELC-UP.AT2"):
        (tmp_path / n).write_text("x\n")
    found = sibling_files(tmp_path / "RSN6_IMPVALL.I_I-ELC180.AT2")
    assert [Path(f.path).name for f in found[1:]] == ["RSN6_IMPVALL.I_I-ELC-UP.AT2"]
    assert found[1].component_name == "U-D"
