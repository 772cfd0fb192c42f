"""The worked examples at real sites, end to end: ``config/site-openquake.yaml`` (an OpenQuake mean
curve in SA(0.15)) and ``config/site-usgs.yaml`` (the USGS hazard service's curve in SA(1.0)), the
Table 1 records scaled on the RotD50 of their two horizontals; and a record with one horizontal,
refused for a RotD hazard in one line unless ``assessment.component: analysed``."""

from __future__ import annotations

import json
import subprocess
import sys

import h5py
import pandas as pd
import pytest
import yaml

from support.records import ROOT, need_records

EXAMPLES = {
    "openquake": ("config/site-openquake.yaml", "SA(0.15)", "OpenQuake's mean curve at site 0"),
    "usgs": ("config/site-usgs.yaml", "SA(1.0)", "the USGS hazard service's Total curve"),
}


def _isorock(*args, cwd, timeout=900):
    return subprocess.run(
        [sys.executable, "-m", "isorock.cli", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _example(name: str, wd) -> dict:
    cfg = yaml.safe_load((ROOT / EXAMPLES[name][0]).read_text())
    hz = cfg["assessment"]["hazard"]
    for k in ("openquake", "usgs"):
        if k in hz:
            hz[k] = str(ROOT / hz[k])  # the example reads it from the repository's root
    return cfg


@pytest.fixture(scope="module", params=sorted(EXAMPLES))
def site(request, tmp_path_factory):
    pytest.importorskip("snakemake")
    recs = need_records()
    name = request.param
    wd = tmp_path_factory.mktemp(name)
    (wd / "site.yaml").write_text(yaml.safe_dump(_example(name, wd)))
    res = _isorock("assess", "site.yaml", "--cores", "2", "--records", recs, "--json", cwd=wd)
    assert res.returncode == 0, res.stderr[-4000:]
    return name, wd, json.loads(res.stdout)


@pytest.mark.e2e
def test_the_verdict_names_the_measure_the_component_and_the_source(site):
    name, _, s = site
    _, imt, source = EXAMPLES[name]
    assert (s["imt"], s["component"]) == (imt, "RotD50")
    assert s["hazard"]["imt"] == imt and s["hazard"]["component_definition"] == "RotD50"
    assert source in s["hazard"]["source"]
    head = s["conclusions"][0]["headline"]
    assert f"g {imt} RotD50, the 2475-year level of {source}" in head, head
    if name == "usgs":
        assert s["hazard"]["vs30_m_s"] == 537.0
    for d in s["design"]:
        assert d["measure"] == f"{imt} RotD50" and d["unit"] == "g"


@pytest.mark.e2e
def test_every_record_is_scaled_on_the_rotd50_of_its_pair(site):
    name, wd, _ = site
    imt = EXAMPLES[name][1]
    h5 = wd / "results" / "isorock.h5"
    recs = pd.read_hdf(h5, "summary/records").set_index("record")
    runs = pd.read_hdf(h5, "assessment/runs")
    with h5py.File(h5, "r") as f:
        assert f["assessment"].attrs["imt"] == imt and f["assessment"].attrs["component"] == "RotD50"
    for rid, r in recs.iterrows():
        rot50, rot100 = json.loads(r["rotd50"]), json.loads(r["rotd100"])
        assert r["rotd_pair"], rid
        assert 0 < rot50[imt] <= rot100[imt] and 0 < rot50["PGA"] <= rot100["PGA"]
        mine = runs[runs["record"] == rid]
        assert len(mine)
        # the level is the record's RotD50 times the scale; the analysed component gets the same factor
        assert (mine["scale"] * rot50[imt]).to_numpy() == pytest.approx(mine["level"].to_numpy(), rel=1e-9)
        assert (mine["scale"] * r["pga_g"]).to_numpy() == pytest.approx(mine["pga_g"].to_numpy(), rel=1e-9)


@pytest.mark.e2e
def test_the_report_names_the_measure(site):
    name, wd, s = site
    html = next(wd.glob("report-*.html")).read_text(encoding="utf-8")
    assert f"{EXAMPLES[name][1]} RotD50" in html


@pytest.mark.e2e
def test_a_record_with_one_horizontal_is_refused_for_a_rotd_hazard_unless_analysed(tmp_path):
    pytest.importorskip("snakemake")
    recs = need_records()
    cfg = {
        "records": {"dir": str(recs), "select": ["IMV79-E05", "IMV79-E06"]},  # E05: one SN file only
        "isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"}]},
        "assessment": {
            "objects": [{"name": "statue", "height_m": 1.8, "width_m": 0.6, "friction": 0.5}],
            "cases": ["none"],
            "stripes_g": [0.1, 0.2, 0.4],
            "design_g": [0.2],
            "mce_g": [0.4],
            "bootstrap": 100,
            "hazard": {
                "points": [[0.05, 2.0e-2], [0.1, 7.0e-3], [0.2, 2.1e-3], [0.4, 4.0e-4], [1.0, 2.0e-5]]
            },
        },
    }
    (tmp_path / "c.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "c.yaml", "--cores", "2", "--json", cwd=tmp_path)
    assert res.returncode == 2, res.stderr[-3000:]
    err = json.loads(res.stdout)["error"]  # --json: the error as JSON on stdout, one line
    assert err.startswith("record IMV79-E05: one horizontal only") and "\n" not in err, err
    assert "assessment.component: analysed" in err and "Traceback" not in res.stderr
    res = _isorock("assess", "c.yaml", "--cores", "2", cwd=tmp_path)  # the same without --json
    last = res.stderr.strip().splitlines()[-1]
    assert res.returncode == 2 and last.startswith("isorock: error: record IMV79-E05: one horizontal"), last
    cfg["assessment"]["component"] = "analysed"
    (tmp_path / "c.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "c.yaml", "--cores", "2", "--json", cwd=tmp_path)
    assert res.returncode == 0, res.stderr[-3000:]
    s = json.loads(res.stdout)
    assert s["component"] == "analysed" and "assumption" in s["measure"]["basis"]
    assert any("assumption" in d for c in s["conclusions"] for d in c["details"])
