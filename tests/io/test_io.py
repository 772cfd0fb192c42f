"""Reading the real strong-motion records of the shared records directory through ObsPy.

Reference values: ``SOURCES.md`` of the records directory ("computed peak" and "values parsed";
PGA in g with g = 9.81 m/s^2). Tolerance: 1 % on PGA (SOURCES.md rounds to 3 or 5 digits).
Independently of the readers, every file is also parsed with plain numpy (``numpy.loadtxt`` or a
token split) and the whole time series is compared sample by sample.

The records directory is ``$ISOROCK_RECORDS``, else ``../shared/records`` beside the repository;
the tests that need it skip when it does not exist.
"""

from __future__ import annotations

import csv
import io
import keyword
import os
import re
from pathlib import Path

import numpy as np
import obspy
import pytest

from isorock.constants import G
from isorock.io import (
    AUTODETECTED,
    FORMATS,
    OBSPY_FORMATS,
    RecordError,
    obspy_format,
    read_record,
    to_ground_motion,
)
from isorock.io import plain as plain_mod
from isorock.physics.excitation import GroundMotion
from support.records import DATA, ROOT

REPO = ROOT
GOOD = DATA / "good"


def records_dir() -> Path:
    env = os.environ.get("ISOROCK_RECORDS")
    return Path(env) if env else REPO.parent / "shared" / "records"


RECORDS = records_dir()
needs_records = pytest.mark.skipif(
    not RECORDS.is_dir(), reason=f"records directory {RECORDS} not found: set ISOROCK_RECORDS"
)

PGA_RTOL = 0.01  # SOURCES.md gives PGA to 3 significant digits for most files

# file -> (PGA g from SOURCES.md "computed peak", samples ("values parsed"), dt s); bbp: the manifest column
EXPECTED = {
    "IMPVALL_E04-140_PulseClassification_example1.AT2": (0.484, 7818, 0.005),
    "IMPVALL_E04-230_PulseClassification_example2.AT2": (0.370, 7818, 0.005),
    "SLAMMER_ImperialValley1979_E06-230_g.txt": (0.43899, 7556, 0.005),
    "SLAMMER_ImperialValley1979_E06-140_g.txt": (0.41048, 7547, 0.005),
    "elcen05_230fn.dat": (0.381, 7864, 0.005),
    "elcen07_230fn.dat": (0.459, 1845, 0.02),
    "SLAMMER_ImperialValley1979_EMO-270_g.txt": (0.29612, 7720, 0.005),
    "SLAMMER_ImperialValley1979_EMO-000_g.txt": (0.31367, 7731, 0.005),
    "SLAMMER_Parkfield1966_C02-065_g.txt": (0.47585, 4166, 0.01),
    "RSN77_SFERN_PUL164-hor1.AT2": (1.219, 4172, 0.01),
    "RSN77_SFERN_PUL254-hor2.AT2": (1.238, 4172, 0.01),
    "pacoima_164.dat": (1.170, 1024, 0.02),
    "SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt": (0.85176, 1642, 0.02),
    "RSN982_NORTHR_JEN022.AT2.g3": (0.411, 5721, 0.005),
    "bbp_NR_obs.s11_JensenFilterPlant.fas.acc.bbp": (0.427, 5720, 0.005),
    "bbp_NR_2004-JGB.bbp": (0.435, 5723, 0.005),
    "NGA_no_1063_RRS228.AT2": (0.825, 1991, 0.01),
    "rinaldi_fn.dat": (0.890, 2990, 0.005),
    "bbp_NR_2001-SCE.bbp": (0.834, 8000, 0.005),
    "sylmar_fn.dat": (0.732, 3000, 0.02),
    "Northridge_Sylmar_County.dat": (0.843, 3000, 0.02),
    "bbp_NR_2002-SYL.bbp": (0.604, 2000, 0.02),  # manifest column E-W
    "SLAMMER_Northridge1994_WPI-046_g.txt": (0.45493, 2493, 0.01),
    "SLAMMER_Northridge1994_WPI-316_g.txt": (0.32543, 2492, 0.01),
    "RSN1052_NORTHR_PKC090.AT2.g3": (0.301, 2000, 0.02),
    "FEMAP695_120821_Kocaeli_Arcelik_ARC000.txt": (0.219, 6001, 0.005),
    "FEMAP695_120822_Kocaeli_Arcelik_ARC090.txt": (0.150, 6001, 0.005),
    "SLAMMER_Kocaeli1999_SKR-090_g.txt": (0.37643, 2962, 0.01),
    "SLAMMER_Kocaeli1999_GBZ-000_g.txt": (0.24408, 5517, 0.005),
    "SLAMMER_Kocaeli1999_IZT-090_g.txt": (0.21954, 5862, 0.005),
    "FEMAP695_120811_Kocaeli_Duzce_DZC180.txt": (0.312, 5438, 0.005),
    "FEMAP695_120812_Kocaeli_Duzce_DZC270.txt": (0.358, 5438, 0.005),
    "bbp_NR_2006-PAC.bbp": (0.401, 1000, 0.02),
    "newhall_360.dat": (0.589, 3000, 0.02),
}
# the other BBP columns (SOURCES.md rows "#EW" and the N-S of 2002-SYL)
EXPECTED_BBP_OTHER = {
    ("bbp_NR_2002-SYL.bbp", "N-S"): 0.843,
    ("bbp_NR_2001-SCE.bbp", "E-W"): 0.502,
    ("bbp_NR_obs.s11_JensenFilterPlant.fas.acc.bbp", "E-W"): 0.583,
    ("bbp_NR_2004-JGB.bbp", "E-W"): 1.077,
    ("bbp_NR_2006-PAC.bbp", "E-W"): 0.447,
}
UNIT_TO_M_S2 = {"g": G, "m/s2": 1.0, "cm/s2": 0.01}


def manifest() -> list[dict[str, str]]:
    if not (RECORDS / "manifest.csv").is_file():
        return []
    with open(RECORDS / "manifest.csv", newline="") as fh:
        return list(csv.DictReader(fh))


ROWS = manifest()
NO_RECORDS = f"records directory {RECORDS} (with manifest.csv) not found: set ISOROCK_RECORDS"
# one parameter per manifest row; a single skipped one, with the reason, when the records are absent
ROW_PARAMS = [pytest.param(r, id=r["file"]) for r in ROWS] or [
    pytest.param(None, id="no-records", marks=pytest.mark.skip(reason=NO_RECORDS))
]


def obspy_kwargs(row: dict[str, str]) -> dict:
    """What obspy.read needs for a manifest row: the format where it is not detected, dt, units."""
    kw: dict = {}
    if row["format"] not in AUTODETECTED:
        kw["format"] = obspy_format(row["format"])
        kw["units"] = row["units"]
    if row["dt_s"]:
        kw["dt"] = float(row["dt_s"])
    return kw


def pick(st: obspy.Stream, row: dict[str, str]) -> obspy.Trace:
    if row["column"]:
        hits = [tr for tr in st if tr.stats.channel == row["column"]]
        assert len(hits) == 1, [tr.stats.channel for tr in st]
        return hits[0]
    assert len(st) == 1
    return st[0]


# --------------------------------------------------------------------------- registration
def test_entry_points_registered():
    from obspy.core.util.base import ENTRY_POINTS

    names = set(OBSPY_FORMATS.values())
    assert names <= set(ENTRY_POINTS["waveform"]), "run `pip install -e .` to register the ObsPy plugins"
    for name in names:
        assert name.isidentifier() and not keyword.iskeyword(name) and name == name.upper()
    assert FORMATS == (
        "peer-at2",
        "peer-at2-body",
        "one-column",
        "two-column",
        "bbp",
        "percent-header",
        "pyslammer-csv",
    )
    assert {obspy_format(f) for f in FORMATS} == names
    assert obspy_format("PeerAt2") == "PEERAT2"


def test_manifest_formats_all_known():
    if not ROWS:
        pytest.skip(NO_RECORDS)
    assert {r["format"] for r in ROWS} <= set(FORMATS)
    sources = RECORDS / "SOURCES.md"
    if sources.is_file():  # the shared set: every file of the manifest is documented in SOURCES.md, and
        # the files whose values this test holds are still there (the folder may grow: not ==)
        text = sources.read_text()
        files = {r["file"] for r in ROWS}
        assert [f for f in sorted(files) if f"`{f}`" not in text] == []
        assert set(EXPECTED) <= files


# --------------------------------------------------------------------------- every manifest file
@needs_records
@pytest.mark.parametrize("row", ROW_PARAMS)
def test_obspy_read_every_manifest_file(row):
    path = RECORDS / row["file"]
    st = obspy.read(str(path), **obspy_kwargs(row))
    tr = pick(st, row)
    pga = float(np.max(np.abs(tr.data))) / G
    if row["file"] in EXPECTED:
        pga_exp, npts_exp, dt_exp = EXPECTED[row["file"]]
        assert tr.stats.npts == npts_exp
        assert tr.stats.delta == pytest.approx(dt_exp, rel=1e-9)
    else:  # a file SOURCES.md does not list: expectation from an independent parse
        pga_exp = float(np.max(np.abs(independent_values(path, row)))) * UNIT_TO_M_S2[row["units"]] / G
    assert pga == pytest.approx(pga_exp, rel=PGA_RTOL)
    info = tr.stats.isorock
    assert info.format == row["format"]
    assert info.units == {"g": "g", "cm/s2": "cm/s2", "m/s2": "m/s2"}[row["units"]]
    assert Path(info.source).name == row["file"]
    assert tr.stats.station
    assert tr.data.dtype == np.float64


def independent_values(path: Path, row: dict[str, str]) -> np.ndarray:
    """The file's acceleration values in its own units, parsed without isorock."""
    fmt = row["format"]
    if fmt == "one-column":
        return np.loadtxt(path)
    if fmt == "two-column":
        return np.loadtxt(path)[:, 1]
    if fmt == "bbp":
        col = {"N-S": 1, "E-W": 2, "U-D": 3}[row["column"]]
        return np.loadtxt(path, comments="#")[:, col]
    lines = path.read_text(encoding="latin-1").splitlines()
    if fmt == "peer-at2":
        return np.array(" ".join(lines[4:]).split(), dtype=float)
    if fmt == "peer-at2-body":
        return np.array(" ".join(lines).split(), dtype=float)
    if fmt == "percent-header":
        vals = np.array(" ".join(ln for ln in lines if not ln.lstrip().startswith("%")).split(), dtype=float)
        if row["file"] in EXPECTED:
            return vals[: EXPECTED[row["file"]][1]]  # drop the zero padding (counts from SOURCES.md)
        return np.trim_zeros(vals, "b")
    raise AssertionError(fmt)


@needs_records
@pytest.mark.parametrize("row", ROW_PARAMS)
def test_every_sample_matches_an_independent_parse(row):
    path = RECORDS / row["file"]
    ref = independent_values(path, row) * UNIT_TO_M_S2[row["units"]]
    tr = pick(obspy.read(str(path), **obspy_kwargs(row)), row)
    assert tr.data.shape == ref.shape
    np.testing.assert_allclose(tr.data, ref, rtol=1e-12, atol=0)
    if row["format"] == "percent-header":  # what was stripped really was zero padding
        lines = path.read_text(encoding="latin-1").splitlines()
        allv = np.array(" ".join(ln for ln in lines if not ln.lstrip().startswith("%")).split(), dtype=float)
        assert allv.size == tr.stats.npts + tr.stats.isorock.padding
        assert not np.any(allv[tr.stats.npts :])


@needs_records
@pytest.mark.parametrize("row", ROW_PARAMS)
def test_read_record_with_manifest_values(row):
    st = read_record(
        RECORDS / row["file"],
        row["format"],
        dt=float(row["dt_s"]) if row["dt_s"] else None,
        units=row["units"],
        component=row["column"] or row["component"],
    )
    assert len(st) == 1
    tr = st[0]
    assert tr.stats.isorock.component == (row["column"] or row["component"])
    assert len(tr.stats.channel) <= 3 and len(tr.stats.station) <= 5  # MiniSEED codes
    gm = to_ground_motion(tr)
    assert isinstance(gm, GroundMotion)
    assert gm.dt == tr.stats.delta
    assert gm.pga_g == pytest.approx(np.max(np.abs(tr.data)) / G, rel=1e-12)
    if row["file"] in EXPECTED:
        assert gm.pga_g == pytest.approx(EXPECTED[row["file"]][0], rel=PGA_RTOL)
    assert gm.meta["units"] == tr.stats.isorock.units
    assert gm.name.startswith(row["file"])


@needs_records
@pytest.mark.parametrize(
    ("key", "pga"), EXPECTED_BBP_OTHER.items(), ids=[f"{k[0]}#{k[1]}" for k in EXPECTED_BBP_OTHER]
)
def test_bbp_other_columns(key, pga):
    st = obspy.read(str(RECORDS / key[0]))
    assert [tr.stats.channel for tr in st] == ["N-S", "E-W", "U-D"]
    tr = st.select(channel=key[1])[0]
    assert np.max(np.abs(tr.data)) / G == pytest.approx(pga, rel=PGA_RTOL)


@needs_records
def test_bbp_duplicate_vertical_is_flagged():
    dup = obspy.read(str(RECORDS / "bbp_NR_2001-SCE.bbp"))
    assert dup.select(channel="U-D")[0].stats.isorock.duplicate_of == "N-S"
    own = obspy.read(str(RECORDS / "bbp_NR_obs.s11_JensenFilterPlant.fas.acc.bbp"))
    assert "duplicate_of" not in own.select(channel="U-D")[0].stats.isorock


# --------------------------------------------------------------------------- detection and headers
@needs_records
@pytest.mark.parametrize("row", ROW_PARAMS)
def test_autodetection_claims_only_headed_formats(row):
    path = str(RECORDS / row["file"])
    if row["format"] in AUTODETECTED:
        st = obspy.read(path)
        assert st[0].stats._format == OBSPY_FORMATS[row["format"]]
    elif row["format"] == "percent-header" and plain_mod._is_percent_header(path):
        # a %-header that states the time step is detected (issue 17)
        assert obspy.read(path, units=row["units"])[0].stats._format == "PERCENTHEADER"
    else:
        with pytest.raises(TypeError, match="Unknown format"):
            obspy.read(path)


@needs_records
@pytest.mark.parametrize(
    ("name", "station", "channel", "event", "variant"),
    [
        (
            "RSN77_SFERN_PUL164-hor1.AT2",
            "Pacoima Dam (upper left abut)",
            "164",
            "San Fernando, 2/9/1971",
            "NGA-West2",
        ),
        (
            "IMPVALL_E04-140_PulseClassification_example1.AT2",
            "El Centro Array #4",
            "140",
            "IMPERIAL VALLEY 10/15/79 2316",
            "PE&A",
        ),
        ("NGA_no_1063_RRS228.AT2", "RINALDI RECEIVING STA", "228", "NORTHRIDGE, 1/17/94 12:31", "NGA 2005"),
    ],
)
def test_at2_header_variants(name, station, channel, event, variant):
    tr = obspy.read(str(RECORDS / name))[0]
    info = tr.stats.isorock
    assert (info.station_name, info.component, info.event) == (station, channel, event)
    assert (tr.stats.station, tr.stats.channel) == (re.sub("[^0-9A-Za-z]", "", station).upper()[:5], channel)
    assert tr.stats.isorock.units_source == "header"
    assert tr.stats.isorock.npts_declared == tr.stats.npts
    assert tr.stats.isorock.dt_source == "header"
    assert len(tr.stats.isorock.header) == 4
    if variant == "PE&A":
        assert tr.stats.isorock.header_pga_g == pytest.approx(0.48431)
        assert np.max(np.abs(tr.data)) / G == pytest.approx(0.48431, rel=1e-4)


@needs_records
def test_percent_header_units_and_dt_from_header():
    tr = obspy.read(str(RECORDS / "elcen07_230fn.dat"), format="PERCENTHEADER", units="cm/s2")[0]
    assert tr.stats.delta == 0.02 and tr.stats.isorock.dt_source == "header"
    assert tr.stats.isorock.padding == 3
    # header: PEAK ACCELERATION = -450.32200 CMS/SEC/SEC AT 4.980 SEC (the data carry the opposite sign)
    k = int(np.argmax(np.abs(tr.data)))
    assert abs(tr.data[k]) == pytest.approx(4.5032200, rel=1e-6)
    assert k * tr.stats.delta == pytest.approx(4.98)
    tr = obspy.read(str(RECORDS / "newhall_360.dat"), format="PERCENTHEADER")[0]  # (UNITS: CM/SEC/SEC)
    assert tr.stats.isorock.units == "cm/s2" and tr.stats.delta == 0.02
    tr = obspy.read(str(RECORDS / "rinaldi_fn.dat"), format="PERCENTHEADER", units="cm/s2")[0]
    assert (tr.stats.npts, tr.stats.delta, tr.stats.isorock.padding) == (2990, 0.005, 4)
    tr = obspy.read(str(RECORDS / "elcen05_230fn.dat"), format="PERCENTHEADER", units="cm/s2", dt=0.005)[0]
    assert tr.stats.isorock.dt_source == "given" and tr.stats.npts == 7864  # commented-out samples skipped


@needs_records
def test_units_conversion_consistent_across_files():
    """The same Sylmar record in m/s^2 (two-column) and cm/s^2 (BBP N-S) gives the same PGA."""
    a = obspy.read(str(RECORDS / "Northridge_Sylmar_County.dat"), format="TWOCOLUMN", units="m/s2")[0]
    b = obspy.read(str(RECORDS / "bbp_NR_2002-SYL.bbp")).select(channel="N-S")[0]
    assert np.max(np.abs(a.data)) == pytest.approx(np.max(np.abs(b.data)), rel=2e-3)


# --------------------------------------------------------------------------- pyslammer sample motions
def _pyslammer_files() -> list[Path]:
    import importlib.util

    spec = importlib.util.find_spec("pyslammer")
    if spec is None:
        return []
    return sorted((Path(spec.submodule_search_locations[0]) / "sample_ground_motions").glob("*.csv"))


@pytest.mark.skipif(not _pyslammer_files(), reason="pyslammer (optional extra 'samples') not installed")
def test_pyslammer_samples_autodetected():
    files = _pyslammer_files()
    assert len(files) == 18
    for f in files:
        tr = obspy.read(str(f))[0]
        assert tr.stats._format == "PYSLAMMERCSV"
        ref = np.loadtxt(f, delimiter=",", comments="#", encoding="utf-8-sig")
        np.testing.assert_allclose(tr.data, ref[:, 1] * G, rtol=1e-12)
        assert tr.stats.delta == pytest.approx(ref[1, 0] - ref[0, 0], rel=1e-6)
        assert tr.stats.station and tr.stats.channel and tr.stats.isorock.event
    tr = obspy.read(str(files[0].parent / "Imperial_Valley_1979_BCR-230.csv"))[0]
    assert (tr.stats.station, tr.stats.channel, tr.stats.isorock.event) == (
        "BCR",
        "230",
        "Imperial Valley 1979",
    )


# --------------------------------------------------------------------------- small committed files
def test_tiny_at2_without_records_dir():
    st = read_record(GOOD / "tiny.AT2")
    tr = st[0]
    assert tr.stats.npts == 12 and tr.stats.delta == 0.01
    assert tr.data[4] == pytest.approx(0.5 * G)
    assert tr.stats.isorock.pga_g == pytest.approx(0.5)
    assert tr.stats.isorock.obspy_format == "PEERAT2"
    gm = to_ground_motion(tr)
    assert gm.name == "tiny.AT2:090" and gm.pga_g == pytest.approx(0.5)


def test_file_like_objects():
    raw = (GOOD / "tiny.AT2").read_bytes()
    st = obspy.read(io.BytesIO(raw))
    assert st[0].stats.npts == 12 and st[0].stats._format == "PEERAT2"


def test_one_column_and_units(tmp_path):
    p = tmp_path / "acc.txt"
    p.write_text("# comment\n1.0\n-2.0\n\n3.0\n")
    for units, factor in (("g", G), ("cm/s2", 0.01), ("gal", 0.01), ("m/s^2", 1.0), ("CM/SEC/SEC", 0.01)):
        tr = read_record(p, "one-column", dt=0.01, units=units)[0]
        np.testing.assert_allclose(tr.data, np.array([1.0, -2.0, 3.0]) * factor)
    tr = read_record(p, "one-column", dt=0.01, units="cm/s2", component="FN")[0]
    assert tr.stats.channel == "FN" and tr.stats.isorock.units == "cm/s2"


def test_fortran_fused_numbers(tmp_path):
    p = tmp_path / "fused.AT2"
    p.write_text(
        "TITLE\nEv, 1/1/2000, Sta, 000\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=   4, DT=   .0100 SEC,\n"
        "-.1000000E-01-.2000000E-01 .3000000E-01 .4000000D-01\n"
    )
    tr = read_record(p)[0]
    np.testing.assert_allclose(tr.data / G, [-0.01, -0.02, 0.03, 0.04])


def test_other_obspy_formats_are_refused(tmp_path):
    """A file ObsPy reads with one of its own plugins carries no acceleration units: refused clearly."""
    from isorock.io import UnknownFormatError

    st = obspy.Stream([obspy.Trace(np.arange(10.0), header={"delta": 0.01, "station": "ABC"})])
    path = tmp_path / "x.slist"
    st.write(str(path), format="SLIST")
    with pytest.raises(UnknownFormatError, match="ObsPy reads this file as SLIST"):
        read_record(path)


def test_headerless_numbers_are_read_by_their_column_count(tmp_path):
    """Without a format, a file of plain numbers is one-column or two-column by its values per line."""
    from isorock.io import TimeStepError, UnknownFormatError

    one = tmp_path / "one.txt"
    one.write_text("# acc [g]\n0.1\n-0.2\n0.05\n")
    tr = read_record(one, dt=0.01, units="g")[0]
    assert tr.stats.isorock.obspy_format == "ONECOLUMN" and tr.stats.npts == 3
    with pytest.raises(TimeStepError, match="time step not given"):
        read_record(one, units="g")
    two = tmp_path / "two.txt"
    two.write_text("0.00, 0.1\n0.01, -0.2\n0.02, 0.05\n")
    tr = read_record(two, units="g")[0]
    assert tr.stats.isorock.obspy_format == "TWOCOLUMN" and tr.stats.delta == pytest.approx(0.01)
    three = tmp_path / "three.txt"
    three.write_text("0.0 0.1 0.2\n0.01 0.1 0.2\n")
    with pytest.raises(UnknownFormatError, match="cannot tell the format"):
        read_record(three, dt=0.01, units="g")


@needs_records
@pytest.mark.parametrize("row", ROW_PARAMS)
def test_every_record_writes_to_miniseed(row, tmp_path):
    """Station and channel codes fit MiniSEED (the full names stay in stats.isorock)."""
    st = read_record(
        RECORDS / row["file"],
        row["format"],
        dt=float(row["dt_s"]) if row["dt_s"] else None,
        units=row["units"],
    )
    out = tmp_path / "x.mseed"
    st.write(str(out), format="MSEED")
    back = obspy.read(str(out))
    assert len(back) == len(st)
    for a, b in zip(st, back, strict=True):
        assert (b.stats.station, b.stats.channel) == (a.stats.station, a.stats.channel)
        np.testing.assert_allclose(b.data, a.data, rtol=1e-6)


def test_bbp_with_one_column_per_header_line():
    """The BBP validation data describe each column on its own line, units as (cm/s/s)."""
    path = GOOD / "columns_described.bbp"
    st = obspy.read(str(path))  # detected without a format
    assert [tr.stats.isorock.component for tr in st] == ["N-S", "E-W", "U-D"]
    tr = st[0]
    assert tr.stats.isorock.units == "cm/s2" and tr.stats.isorock.units_source == "header"
    assert tr.stats.delta == pytest.approx(0.005) and tr.stats.isorock.station_name == "tst"
    assert read_record(path, "bbp", component="EW")[0].stats.isorock.component == "E-W"


def test_every_missing_piece_is_named_at_once(tmp_path):
    """What was seen: format, then component, then units, one error at a time."""
    from isorock.io import read_trace

    f = tmp_path / "nounits.bbp"
    f.write_text((GOOD / "columns_described.bbp").read_text().replace(" (cm/s/s)", ""))
    with pytest.raises(RecordError) as info:
        read_trace(f)
    msg = str(info.value)
    assert "units not stated" in msg and "choose one with --component" in msg and "--units" in msg
    one = tmp_path / "one.txt"
    one.write_text("0.1\n0.2\n-0.1\n")
    with pytest.raises(RecordError) as info:
        read_trace(one)
    assert "units not given" in str(info.value) and "time step not given" in str(info.value)
