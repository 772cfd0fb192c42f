"""The component of a record: azimuths from names, rotation (against ObsPy), and the choice of the
direction the catalog row asks for, on synthetic files whose true direction is known."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from obspy.signal.rotate import rotate_ne_rt

from isorock import G  # the g of the readers' unit conversion
from isorock.errors import IsorockError
from isorock.pulse import rotate_horizontal
from isorock.records.components import (
    RecordFile,
    Target,
    choose_component,
    line_angle,
    parse_azimuth,
    provided_orientation,
)

DT = 0.01


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
