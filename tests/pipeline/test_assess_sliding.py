"""``isorock assess`` with an object that slides (issue 24, second stage: ``pytest -m e2e``): the worked
example's showcase (1.2 m x 0.5 m, friction 0.35 below tan(alpha) 0.417) gets sliding analyses, a
failure fragility, a verdict and its words, the store's sliding columns, the sliding figure and the
report's paragraph; on two records (the shared Table 1 records, else pyslammer's samples)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pandas as pd
import pytest
import yaml

from support.records import records_dir

pytestmark = pytest.mark.e2e

SHOWCASE = {"name": "showcase", "height_m": 1.2, "width_m": 0.5, "friction": 0.35, "slide_allow_m": 0.05}
STRIPES = [0.2, 0.4, 0.6, 0.8, 1.0]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    pytest.importorskip("snakemake")
    recs = records_dir()
    if recs is None:
        pytest.importorskip("pyslammer")
    records = (
        {"dir": str(recs), "select": ["IMV79-EMO", "NOR94-RRS"]} if recs else {"dir": None, "max_records": 2}
    )
    cfg = {
        "records": records,
        "isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"},
                                            {"name": "lin3", "kind": "linear", "Tb_s": 3.0, "xi_b": 0.2}]},
        "assessment": {"objects": [SHOWCASE], "cases": ["none", "lin3"], "capacity_m": 0.3,
                       "stripes_g": STRIPES, "design_g": [0.4], "mce_g": [0.6],
                       "design_grid": {"kind": "linear", "Tb_s": [2.0, 3.5], "xi_b": [0.1, 0.3]}},
    }  # fmt: skip
    wd = tmp_path_factory.mktemp("slide")
    (wd / "cabinet.yaml").write_text(yaml.safe_dump(cfg))
    res = subprocess.run([sys.executable, "-m", "isorock.cli", "assess", "cabinet.yaml", "--cores", "2",
                          "--json"], cwd=wd, capture_output=True, text=True, timeout=900)  # fmt: skip
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-4000:]
    return wd, json.loads(res.stdout)


def test_the_sliding_object_gets_a_verdict_and_says_it_slides(run):
    _, out = run
    (o,) = out["objects"]
    assert o["slides"] and o["slide_allow_m"] == 0.05
    assert {c["mode"] for c in out["cases"]} == {"sliding"}
    (c,) = out["conclusions"]
    assert c["headline"].startswith("showcase slides and never rocks (friction 0.35 below tan alpha 0.417)")
    assert "farther than its allowance of 0.05 m" in c["headline"]
    assert c["verdicts"] and c["verdicts"][0]["verdict"] in (
        "isolate",
        "fixed_base",
        "restrain",
        "inconclusive",
    )
    assert any(p.startswith("showcase: ") and "Sliding: " in p for p in c["details"])
    for case in out["cases"]:
        assert case["fragility"]["estimable"] is False  # it never rocks, so never overturns
        assert all(s["n_overturn"] == 0 for s in case["stripes"])
        # failure counts the slides beyond the allowance (and, on the isolator, the capacity)
        for s in case["stripes"]:
            assert s["n_slides_beyond"] <= s["n_failure"] <= s["n_records"]
    none = next(x for x in out["cases"] if x["isolation"] == "none")
    assert none["stripes"][-1]["n_slid"] == 2 and none["stripes"][-1]["slide_max_m"] > 0.0


def test_the_store_the_figure_and_the_report(run):
    wd, _ = run
    store = wd / "results" / "isorock.h5"
    runs = pd.read_hdf(store, "assessment/runs")
    assert set(runs["mode"]) == {"sliding"} and (runs["outcome"] == "no_uplift").all()
    slid = runs[runs["n_slips"] > 0]
    assert len(slid) and (slid["sliding_peak_m"] > 0).all()
    assert (runs["slides_beyond"] == (runs["sliding_peak_m"] > 0.05)).all()
    objs = pd.read_hdf(store, "assessment/objects")
    assert objs["mode"].tolist() == ["sliding"] and math.isclose(objs["slide_allow_m"].iloc[0], 0.05)
    assert (wd / "results" / "figures" / "assessment_sliding_showcase.png").stat().st_size > 10_000
    html = (wd / "results" / "report" / "assessment.html").read_text()
    assert "slides and never rocks" in html and "never: it slides" in html
