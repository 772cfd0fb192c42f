"""``isorock assess CONFIG``: the assessment workflow end to end, its JSON contract, the agreement of a
stripe's overturning count with ``isorock simulate`` of each record, the store and the report.

With the shared records the records are two Table 1 rows (and ``simulate --id`` checks the counts);
without them, two of pyslammer's sample records (``simulate --record FILE``)."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings

import pandas as pd
import pytest
import yaml

from isorock import pipeline
from support.records import ROOT, records_dir

STRIPES = [0.15, 0.4, 0.8]
CASES = {
    "none": {"name": "none", "kind": "none"},
    "lin3": {"name": "lin3", "kind": "linear", "Tb_s": 3.0, "xi_b": 0.2},
}
FLAGS = {"none": [], "lin3": ["--isolation", "linear", "--Tb", "3", "--xi", "0.2", "--rho", "0.5"]}


def _config(recs) -> dict:
    records = (
        {"dir": str(recs), "select": ["IMV79-EMO", "NOR94-RRS"]} if recs else {"dir": None, "max_records": 2}
    )
    return {
        "records": records,
        "isolation": {"rho": 0.5, "cases": list(CASES.values())},
        "assessment": {
            "objects": [{"name": "statue", "height_m": 1.8, "width_m": 0.6, "friction": 0.5}],
            "cases": ["none", "lin3"],
            "capacity_m": 0.3,
            "stripes_g": STRIPES,
            "design_g": [0.4],
            "design_grid": {"kind": "linear", "Tb_s": [2.0, 3.5], "xi_b": [0.1, 0.3]},
        },
    }


def _isorock(*args, cwd, env=None, timeout=900):
    return subprocess.run(
        [sys.executable, "-m", "isorock.cli", *map(str, args)], cwd=cwd, capture_output=True, text=True,
        timeout=timeout, env=env,
    )  # fmt: skip


@pytest.fixture(scope="module")
def assessed(tmp_path_factory):
    pytest.importorskip("snakemake")
    recs = records_dir()
    if recs is None:
        pytest.importorskip("pyslammer")
    wd = tmp_path_factory.mktemp("assess")
    (wd / "museum.yaml").write_text(yaml.safe_dump(_config(recs)))
    res = _isorock("assess", "museum.yaml", "--cores", "2", "--json", cwd=wd)
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-4000:]
    return wd, json.loads(res.stdout), recs


def test_json_contract(assessed):
    _, out, _ = assessed
    assert {"records", "cases"} <= set(out)
    assert len(out["records"]) == 2 and all({"id", "file"} <= set(r) for r in out["records"])
    assert [(c["object"], c["isolation"]) for c in out["cases"]] == [("statue", "none"), ("statue", "lin3")]
    for c in out["cases"]:
        assert {"median_g", "beta"} <= set(c["fragility"])
        assert [s["pga_g"] for s in c["stripes"]] == STRIPES
        for s in c["stripes"]:
            assert {"pga_g", "n_records", "n_overturn", "n_uplift", "disp_median_m", "disp_p84_m"} <= set(s)
            assert s["n_records"] == 2 and 0 <= s["n_overturn"] <= s["n_uplift"] <= 2
        (d,) = c["design_levels"]
        assert d["pga_g"] == 0.4 and {"p_overturn", "p_uplift", "disp_p84_m"} <= set(d)
        assert 0.0 <= d["p_overturn"] <= 1.0
    assert out["conclusions"] and "statue" in out["conclusions"][0]["text"]
    assert out["conclusions"][0]["headline"].startswith("statue: probability of overturning at 0.4 g: ")
    (design,) = out["design"]
    assert design["n_isolators"] == 4


def test_stripe_counts_agree_with_simulate(assessed):
    """A stripe's n_overturn is the number of its records that ``isorock simulate`` overturns."""
    wd, out, recs = assessed
    o = out["objects"][0]
    for c in out["cases"]:
        for s in c["stripes"]:
            n = 0
            for r in out["records"]:
                src = ["--id", r["id"], "--records", recs] if recs else ["--record", r["file"]]
                res = _isorock(
                    "simulate", "--lambda", repr(o["lambda"]), "--R", repr(o["R_m"]), *FLAGS[c["isolation"]],
                    *src, "--pga", repr(s["pga_g"]), "--json", cwd=wd,
                )  # fmt: skip
                assert res.returncode == 0, res.stderr
                sim = json.loads(res.stdout)
                n += sim["outcome"] == "overturn"
                assert {"mu_required", "min_normal_over_weight"} <= set(sim)
            assert s["n_overturn"] == n, (c["isolation"], s["pga_g"])


def test_store_and_report(assessed):
    wd, _, _ = assessed
    store = wd / "results" / "isorock.h5"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for key in (
            "objects",
            "runs",
            "stripes",
            "fragility",
            "design_levels",
            "validity",
            "first_overturn",
            "design",
        ):
            df = pd.read_hdf(store, f"assessment/{key}")
            assert len(df), key
    runs = pd.read_hdf(store, "assessment/runs")
    assert {"mu_required", "min_normal_over_weight", "outside_model", "max_base_disp_m"} <= set(runs.columns)
    assert len(runs) == 2 * 2 * len(set(STRIPES) | {0.4})  # 2 cases x 2 records x (stripes and design level)
    # no paper study ran: a file with only records, isolation and assessment
    assert (
        not (wd / "results" / "jobs" / "overturn").exists()
        and not (wd / "results" / "jobs" / "maps").exists()
    )
    landing = (wd / "results" / "report" / "landing.rst").read_text()
    assert landing.index("Assessment") < landing.index("Method") and "probability of overturning" in landing
    # Snakemake centres the landing page vertically: a taller page loses its top, so it stays short
    assert sum(1 for ln in landing.splitlines() if ln.strip()) <= 20 and ".. " not in landing
    html = (wd / "report-museum.html").read_text()
    assert "probability of overturning" in html  # the landing page of the report opens with the results
    for kind in ("fragility", "displacement", "design"):
        assert (wd / "results" / "figures" / f"assessment_{kind}_statue.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    "change, words",
    [
        ({"objects": [{"name": "s", "height_m": -1.8, "width_m": 0.6, "friction": 0.5}]},
         "height_m: -1.8 is out of range: must be > 0"),
        ({"objects": [{"name": "s", "height_m": 1.8, "width_m": 0.6, "friction": 0.5, "mass": 3}]},
         "unknown key 'mass': valid"),
        ({"capacity": 0.3}, "unknown key 'capacity': valid objects, cases, capacity_m"),
        ({"cases": ["none", "lin9"]}, "unknown isolation case 'lin9'"),
        ({"stripes_g": [0.4, 0.2]}, "must increase"),
    ],
)  # fmt: skip
def test_bad_configurations_stop_before_any_job(tmp_path, change, words):
    cfg = _config(None)
    cfg["assessment"].update(change)
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "bad.yaml", cwd=tmp_path, timeout=120)
    assert res.returncode == 2 and words in res.stderr, res.stderr
    assert len(res.stderr.strip().splitlines()) == 1 and not (tmp_path / "results").exists()


def test_an_isolation_model_missing_a_parameter_names_it_and_its_range(tmp_path):
    cfg = _config(None)
    cfg["isolation"]["cases"][1] = {"name": "lin3", "kind": "linear", "Tb_s": 3.0}
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "bad.yaml", cwd=tmp_path, timeout=120)
    assert res.returncode == 2
    assert (
        "isolation.cases.1: 'xi_b' is missing (linear isolator damping [-]; valid >= 0 and < 1)" in res.stderr
    )


def test_studies_default_off_for_an_assessment_file_on():
    assert pipeline.workflow_config(ROOT / "config" / "assessment.yaml")["studies"] == []
    assert pipeline.workflow_config(ROOT / "config" / "ci.yaml")["studies"] == ["overturn", "maps", "pulses"]
    both = {
        **_config(None),
        "studies": ["overturn"],
        "overturn": {"lambda": [4.0], "R_m": [1.0], "cases": ["none"]},
    }
    assert pipeline.workflow_config(both)["studies"] == ["overturn"]
