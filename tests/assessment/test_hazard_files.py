"""The site's hazard curve read from real files of the field (isorock.assessment.hazard_files):
OpenQuake's hazard-curve CSVs and a USGS hazard service JSON (tests/data/hazard/SOURCES.md)."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from isorock.assessment.hazard import HazardCurve
from isorock.assessment.hazard_files import (
    curve_from_config,
    great_circle_km,
    openquake_metadata,
    read_openquake,
    read_usgs,
)
from isorock.errors import ConfigError

DATA = Path(__file__).resolve().parents[1] / "data" / "hazard"
CASE_13 = DATA / "hazard_curve-mean_SA(0.2).csv"  # 21 sites, investigation_time 50 yr, new style
CASE_11 = DATA / "hazard_curve-mean-SA(1.0).csv"  # trailing zeros, investigation_time 1 yr
CASE_1 = DATA / "hazard_curve-PGA.csv"  # old style metadata line
CASE_08 = DATA / "hcurves.csv"  # custom_site_id, two site classes at one location
USGS = DATA / "dwight_7th.json"


def _one_line(exc: pytest.ExceptionInfo) -> str:
    msg = str(exc.value)
    assert "\n" not in msg and msg.strip() == msg and msg
    return msg


def test_poe_to_rate_against_a_hand_computation():
    # case_13, site 3: -121.38,36.90,0.00000,8.974078E-01,... over investigation_time=50.0
    c = read_openquake(CASE_13, site=3)
    assert c.levels[0] == 0.005 and c.levels[-1] == 0.284 and c.levels.size == 13
    assert c.annual_rate[0] == pytest.approx(-math.log(1 - 0.8974078) / 50.0, rel=1e-12)  # 0.04554 /yr
    assert c.annual_rate[0] == pytest.approx(0.045539868, rel=1e-7)
    assert c.annual_rate[-1] == pytest.approx(-math.log(1 - 0.4202279) / 50.0, rel=1e-12)
    assert (c.imt, c.kind, c.component_definition, c.notes) == ("SA(0.2)", "mean", "RotD50", ())
    assert c.site == "site 3 (lon -121.38, lat 36.9)"
    assert c.describe() == (
        "OpenQuake's mean curve at site 3 (lon -121.38, lat 36.9), file hazard_curve-mean_SA(0.2).csv"
    )
    d = c.to_dict()
    assert d["imt"] == "SA(0.2)" and d["kind"] == "mean" and d["origin"] == "openquake"
    assert d["vs30_m_s"] is None and d["notes"] == [] and len(d["annual_rate"]) == 13


def test_the_old_metadata_style_and_a_kind_left_unsaid():
    c = read_openquake(CASE_1)  # one site: no site needed
    assert c.imt == "PGA" and c.kind == ""  # no kind in the line nor in the name
    np.testing.assert_allclose(c.levels, [0.1, 0.4, 0.6])
    np.testing.assert_allclose(
        c.annual_rate, -np.log1p(-np.array([4.528811e-01, 5.589804e-02, 5.585141e-03]))
    )
    assert c.describe().startswith("OpenQuake's curve at site 0 (lon 0, lat 0)")
    meta = openquake_metadata(CASE_1.read_text().splitlines()[0])
    assert meta["investigation_time"] == "1.0" and meta["imt"] == "PGA"


def test_trailing_zeros_are_trimmed_with_a_note():
    c = read_openquake(CASE_11, site=1)
    # poe-0.0464159 is the last nonzero (3.000660E-04); the 4 levels above it are 0
    assert c.levels[-1] == pytest.approx(0.0464159) and c.levels.size == 6
    assert c.notes == ("4 trailing levels of poe 0 dropped (above 0.04642 g)",)
    c0 = read_openquake(CASE_11, site=0)  # 2 zeros at the top, two equal poes at the bottom
    assert c0.levels[0] == pytest.approx(0.0021544) and c0.levels[-1] == pytest.approx(0.2154435)
    assert c0.notes[0] == "2 trailing levels of poe 0 dropped (above 0.2154 g)"
    assert "1 leading level" in c0.notes[1] and np.all(np.diff(c0.annual_rate) < 0)
    assert c0.annual_rate[0] == pytest.approx(-math.log(1 - 1.591452e-02))  # investigation_time 1 yr


def test_a_site_with_no_hazard_is_refused_naming_the_file_and_the_site():
    with pytest.raises(ConfigError) as exc:
        read_openquake(CASE_11, site=2)
    msg = _one_line(exc)
    assert "hazard_curve-mean-SA(1.0).csv" in msg and "site 2 (lon -63, lat 2)" in msg and "3" in msg


def test_nearest_site_by_lon_lat_and_the_refusal_beyond_the_distance():
    # site 0 of case_13 is at (-122.34, 37.72); (-122.30, 37.70) is ~4.2 km away
    d = great_circle_km(-122.30, 37.70, -122.34, 37.72)
    assert 4.0 < d < 4.4
    c = read_openquake(CASE_13, site=[-122.30, 37.70])
    assert c.site.startswith("site 0 (lon -122.34, lat 37.72), 4.16 km from [-122.3, 37.7]")
    assert c.annual_rate[0] == pytest.approx(-math.log(1 - 0.8661497) / 50.0)
    with pytest.raises(ConfigError) as exc:
        read_openquake(CASE_13, site=[-122.30, 37.70], max_distance_km=4.0)
    msg = _one_line(exc)
    assert "4.16 km away, beyond max_distance_km 4 km" in msg and "site 0" in msg
    with pytest.raises(ConfigError) as exc:  # 43.6 km from the nearest, site 2; the default 5 km
        curve_from_config({"openquake": CASE_13.name, "site": [-122.0, 37.0]}, DATA)
    assert "beyond max_distance_km 5 km" in _one_line(exc)
    assert "assessment.hazard.site" in str(exc.value)


def test_two_site_classes_at_one_location_are_not_chosen_between():
    with pytest.raises(ConfigError) as exc:
        read_openquake(CASE_08, site=[15.2, 37.5])
    msg = _one_line(exc)
    assert "'0:CD'" in msg and "'0:BC'" in msg and "give site: N" in msg
    c = read_openquake(CASE_08, site=1)
    assert c.site == "site 1 '0:BC' (lon 15.2, lat 37.5)" and c.imt == "PGA"
    assert c.annual_rate[0] == pytest.approx(-math.log(1 - 8.933418e-01) / 100.0)
    # 0:BC: the poe of 0.0360962 g (5.823374E-05) is its last nonzero; the 11 levels above are 0
    assert c.notes == ("11 trailing levels of poe 0 dropped (above 0.0361 g)",) and c.levels.size == 9


def test_site_index_out_of_range_and_missing():
    with pytest.raises(ConfigError) as exc:
        read_openquake(CASE_13, site=21)
    assert "assessment.hazard.site: 21:" in _one_line(exc) and "21 sites (0 to 20)" in str(exc.value)
    with pytest.raises(ConfigError) as exc:
        read_openquake(CASE_13)
    assert "holds 21 sites: give site: N" in _one_line(exc)


def test_imt_mismatch_is_refused_naming_both():
    with pytest.raises(ConfigError) as exc:
        curve_from_config({"openquake": CASE_13.name, "site": 0, "imt": "PGA"}, DATA)
    msg = _one_line(exc)
    assert "assessment.hazard.imt" in msg and "PGA" in msg and "SA(0.2)" in msg
    # the same measure in the USGS spelling is the file's
    c = curve_from_config({"openquake": CASE_13.name, "site": 0, "imt": "SA0P2"}, DATA)
    assert c.imt == "SA(0.2)"


def test_usgs_total_curve_is_picked_with_vs30_and_location():
    c = curve_from_config({"usgs": USGS.name, "imt": "SA1P0"}, DATA)
    doc = json.loads(USGS.read_text())
    sa1 = next(r for r in doc["response"] if r["metadata"]["imt"]["value"] == "SA1P0")
    total = next(d for d in sa1["data"] if d["component"] == "Total")
    np.testing.assert_array_equal(c.levels, sa1["metadata"]["xvalues"])
    np.testing.assert_array_equal(c.annual_rate, total["yvalues"])  # already annual rates
    assert c.annual_rate[0] != next(d for d in sa1["data"] if d["component"] == "System")["yvalues"][0]
    assert (c.imt, c.kind, c.vs30_m_s, c.site) == ("SA(1.0)", "Total", 537.0, "lon -122.294, lat 37.86")
    assert c.describe() == (
        "the USGS hazard service's Total curve at lon -122.294, lat 37.86, Vs30 537 m/s, file dwight_7th.json"
    )
    assert c.to_dict()["vs30_m_s"] == 537.0 and c.component_definition == "RotD50"
    assert read_usgs(USGS, "SA(1.0)").annual_rate[0] == c.annual_rate[0]  # either spelling
    sa3 = read_usgs(USGS, "SA3P0")  # its Total ends with 3 zeros
    assert sa3.levels[-1] == 2.19 and sa3.notes == (
        "3 trailing levels of annual rate 0 dropped (above 2.19 g)",
    )


def test_usgs_imt_missing_or_absent_is_refused_listing_the_imts():
    with pytest.raises(ConfigError) as exc:
        curve_from_config({"usgs": USGS.name}, DATA)
    msg = _one_line(exc)
    assert "11 measures" in msg and "PGA, SA(0.1), SA(0.2)" in msg and "SA(5.0)" in msg
    with pytest.raises(ConfigError) as exc:
        read_usgs(USGS, "SA(0.15)")
    assert "holds no curve of it" in _one_line(exc) and "SA(0.75)" in str(exc.value)
    with pytest.raises(ConfigError) as exc:
        read_usgs(USGS, "PGA", site=[-122.0, 37.86])  # ~26 km east
    assert "beyond max_distance_km 5 km" in _one_line(exc)


def test_file_and_points_name_their_measure(tmp_path):
    f = tmp_path / "my-site.csv"
    f.write_text("level,annual_rate\n0.1,1e-2\n0.2,1e-3\n0.4,1e-4\n")
    c = curve_from_config(
        {"file": "my-site.csv", "imt": "SA(1.0)", "component_definition": "rotd100"}, tmp_path
    )
    assert (c.imt, c.component_definition, c.describe()) == ("SA(1.0)", "RotD100", "file my-site.csv")
    p = curve_from_config({"points": [[0.1, 1e-2], [0.2, 1e-3], [0.4, 1e-4]]})
    assert (p.imt, p.component_definition, p.describe()) == ("PGA", "RotD50", "the curve given inline")
    assert HazardCurve(np.array([0.1, 0.2, 0.4]), np.array([1e-2, 1e-3, 1e-4])).describe() == (
        "the curve given inline"
    )


@pytest.mark.parametrize(
    "cfg, needle",
    [
        ({}, "give exactly one of openquake, usgs, file, points"),
        ({"file": "a.csv", "points": [[1, 1]]}, "(given: file, points)"),
        ({"points": [[0.1, 1e-2], [0.2, 1e-3], [0.4, 1e-4]], "site": 0}, "assessment.hazard.site: only with"),
        ({"points": [[0.1, 1e-2], [0.2, 1e-3], [0.4, 1e-4]], "imt": "SA(-1)"}, "assessment.hazard.imt"),
        ({"points": [[0.1, 1e-2], [0.2, 1e-3], [0.4, 1e-4]], "component_definition": "GM"}, "component_def"),
        ({"openquake": CASE_13.name, "site": "three"}, "assessment.hazard.site"),
        ({"openquake": CASE_13.name, "site": 0, "max_distance_km": -1}, "max_distance_km"),
        ({"openquake": CASE_13.name, "sites": 0}, "unknown key 'sites'"),
    ],
)
def test_config_errors_are_one_line(cfg, needle):
    with pytest.raises(ConfigError) as exc:
        curve_from_config(cfg, DATA)
    assert needle in _one_line(exc)


def _oq_file(tmp_path: Path, first: str, rest: str | None = None) -> Path:
    lines = CASE_13.read_text().splitlines(keepends=True)
    f = tmp_path / "hazard_curve-mean-PGA.csv"
    f.write_text(first + (rest if rest is not None else "".join(lines[1:])))
    return f


@pytest.mark.parametrize(
    "first, rest, needle",
    [
        ("lon,lat,depth\n", None, ":1: expected OpenQuake's metadata line starting with '#'"),
        ("#\n", None, ":1: the metadata line holds no key=value pair"),
        (
            "#,,\"generated_by='OpenQuake engine 3.7', kind='mean', imt='PGA'\"\n",
            None,
            "no investigation_time",
        ),
        ("# investigation_time=0, imt='PGA'\n", None, "investigation_time='0': not a positive number"),
        ("# investigation_time=50.0, imt='SA(x)'\n", None, ":1: imt: 'SA(x)' is not an intensity measure"),
        ("# investigation_time=50.0\n", None, "names no imt"),
        (
            "# investigation_time=1, imt='PGA'\n",
            "lon,lat,poe-0.1,poe-0.2,poe-0.3\n0,0,0.5,1.0,0.1\n",
            "poe 1 at 0.2 g",
        ),
        (
            "# investigation_time=1, imt='PGA'\n",
            "lon,lat,poe-0.1,poe-0.2,poe-0.3\n0,0,0.5,0.2\n",
            ":3: 4 fields",
        ),
        ("# investigation_time=1, imt='PGA'\n", "lon,lat,poe-0.1,poe-x\n", ":2: 'poe-x'"),
        ("# investigation_time=1, imt='PGA'\n", "site,poe-0.1\n", ":2: the header must name lon, lat"),
        (
            "# investigation_time=1, imt='PGA'\n",
            "lon,lat,poe-0.1,poe-0.2,poe-0.3\n0,0,0.5,0.6,0.1\n",
            "does not decrease",
        ),
        (
            "# investigation_time=1, imt='PGA'\n",
            "lon,lat,poe-0.1,poe-0.2,poe-0.3\n0,0,0.5,abc,0.1\n",
            ":3: 'abc'",
        ),
    ],
)
def test_malformed_openquake_files_give_one_line(tmp_path, first, rest, needle):
    f = _oq_file(tmp_path, first, rest)
    with pytest.raises(ConfigError) as exc:
        read_openquake(f, site=0)
    msg = _one_line(exc)
    assert needle in msg and "hazard_curve-mean-PGA.csv" in msg


def test_the_kind_falls_back_to_the_file_name(tmp_path):
    for name, kind in (
        ("quantile_curve-0.84-PGA_17.csv", "quantile-0.84"),
        ("hazard_curve-mean-PGA_3.csv", "mean"),
    ):
        f = tmp_path / name
        f.write_text(CASE_1.read_text())
        assert read_openquake(f).kind == kind


@pytest.mark.parametrize(
    "doc, needle",
    [
        ("{not json", ":1: not JSON"),
        ('{"status": "error", "message": "bad vs30"}', "status 'error': bad vs30"),
        (
            '{"response": {"hazardCurves": []}}',
            "current nshmp-haz layout (response.hazardCurves) is not read",
        ),
        ('{"response": []}', "no 'response' list"),
        ('{"response": [{"metadata": {}}]}', "response[0].metadata.imt.value: missing"),
    ],
)
def test_malformed_usgs_files_give_one_line(tmp_path, doc, needle):
    f = tmp_path / "site.json"
    f.write_text(doc)
    with pytest.raises(ConfigError) as exc:
        read_usgs(f, "PGA")
    msg = _one_line(exc)
    assert needle in msg and "site.json" in msg


def test_usgs_without_a_total_component(tmp_path):
    doc = json.loads(USGS.read_text())
    for r in doc["response"]:
        r["data"] = [d for d in r["data"] if d["component"] != "Total"]
    f = tmp_path / "no_total.json"
    f.write_text(json.dumps(doc))
    with pytest.raises(ConfigError) as exc:
        read_usgs(f, "PGA")
    assert "no 'Total' component (it has System, Grid, Slab, Interface, Fault)" in _one_line(exc)


def test_relative_paths_are_relative_to_basedir(tmp_path):
    shutil.copy(CASE_1, tmp_path / CASE_1.name)
    c = curve_from_config({"openquake": CASE_1.name}, tmp_path)
    assert Path(c.source).parent == tmp_path
