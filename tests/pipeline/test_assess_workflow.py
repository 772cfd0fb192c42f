"""``isorock assess CONFIG``: the assessment workflow end to end, its JSON contract, the agreement of a
stripe's overturning count with ``isorock simulate`` of each record, the store and the report.

With the shared records the records are two Table 1 rows (and ``simulate --id`` checks the counts);
without them, two of pyslammer's sample records (``simulate --record FILE``)."""

from __future__ import annotations

import json
import re
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
            "mce_g": [0.6],
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


@pytest.mark.e2e
def test_json_contract(assessed):
    _, out, _ = assessed
    assert {"records", "cases", "design", "warnings", "assumptions", "conclusions"} <= set(out)
    assert len(out["records"]) == 2 and all({"id", "file"} <= set(r) for r in out["records"])
    assert [(c["object"], c["isolation"]) for c in out["cases"]] == [("statue", "none"), ("statue", "lin3")]
    frag_keys = {"median_g", "beta", "median_ci95_g", "beta_ci95", "estimable"}
    for c in out["cases"]:
        assert frag_keys <= set(c["fragility"]) and frag_keys <= set(c["fragility_failure"])
        for f in (c["fragility"], c["fragility_failure"]):
            if f["estimable"]:
                assert f["median_ci95_g"][0] <= f["median_g"] <= f["median_ci95_g"][1]
            else:  # never a number from a clamped fit
                assert f["median_g"] is None and f["beta"] is None and f["note"].startswith("not estimable")
        assert [s["level"] for s in c["stripes"]] == STRIPES
        for s in c["stripes"]:
            keys = {"level", "n_records", "n_overturn", "n_uplift", "disp_median_m", "disp_p84_m"}
            assert keys | {"n_exceed_capacity", "n_outside_model", "n_failure"} <= set(s)
            assert s["n_records"] == 2 and 0 <= s["n_overturn"] <= s["n_uplift"] <= 2
            assert s["n_overturn"] <= s["n_failure"] <= 2
        (d,) = c["design_levels"]
        assert d["level"] == 0.4
        keys = {"p_overturn", "p_overturn_ci95", "p_failure", "p_failure_ci95", "p_overturn_observed"}
        assert keys | {"estimable", "p_uplift", "disp_p84_m", "mce_g", "disp_mce_m"} <= set(d)
        assert d["mce_g"] == pytest.approx(0.6)  # given
        # the collapse check: P(failure) at the MCE, never below P(overturn) at any level
        assert {
            "p_failure_mce",
            "p_failure_mce_ci95",
            "n_failure_mce_observed",
            "p_failure_mce_basis",
        } <= set(d)
        assert d["p_failure_mce_basis"].startswith("observed")  # 2 records: the exact count decides
        if d["p_failure"] is not None and d["p_overturn"] is not None:
            assert d["p_failure"] >= d["p_overturn"]
        assert d["p_overturn_observed"] is not None  # the design level was run
        for p in ("p_overturn", "p_failure"):
            if d[p] is None:  # not estimable: the observed count and its exact bound instead
                assert d[f"{p}_upper95"] is not None and 0 < d[f"{p}_upper95"] <= 1
            else:
                assert 0.0 < d[p] < 1.0 and d[f"{p}_ci95"][0] <= d[p] <= d[f"{p}_ci95"][1]
        # the displacement at the MCE with its interval, and the records beyond the capacity there
        assert {"disp_mce_ci95_m", "p_mce_exceed_capacity", "p_mce_exceed_capacity_ci95"} <= set(d)
        if c["kind"] != "none":
            lo, hi = d["disp_mce_ci95_m"]
            assert lo <= d["disp_mce_m"] <= hi
            plo, phi = d["p_mce_exceed_capacity_ci95"]
            assert plo <= d["p_mce_exceed_capacity"] <= phi
        for b in c["beta_by_measure"]:
            assert b["beta_ci95"] is None or b["beta_ci95"][0] <= b["beta"] <= b["beta_ci95"][1]
    assert out["conclusions"] and "statue" in out["conclusions"][0]["text"]
    head = out["conclusions"][0]["headline"]
    assert head.startswith(("statue is safe on", "statue is not safe on any base", "Whether statue is safe"))
    assert any("at least 7 ground motions" in w for w in out["warnings"])  # 2 records only
    (v,) = out["conclusions"][0]["verdicts"]
    assert v["mce"].startswith("At the MCE level, 0.6 g PGA, ")
    (design,) = out["design"]
    assert (
        design["verdict"] in ("isolate", "fixed_base", "restrain", "inconclusive")
        and design["n_records"] == 2
    )
    assert design["target"]["kind"] == "p_mce" and design["target"]["value"] == 0.1
    assert design["decided_by"] == "exact bounds"  # 2 records
    assert set(design["grid"]) >= {"extended", "bounds_reached"}
    assert design["n_isolators"] == 4 + (design["grid"]["added"] if design["grid"]["extended"] else 0)
    names = [c["name"] for c in design["candidates"]]
    assert "none" in names and "lin3" in names and len(names) == 2 + design["n_isolators"]
    floor = next(c for c in design["candidates"] if c["name"] == "none")
    assert floor["isolation"] == "none" and floor["source"] == "floor"
    for c in design["candidates"]:
        assert {"isolation", "p_failure", "p_failure_ci95", "disp_mce_m", "within_capacity"} <= set(c)
        assert {"adequate", "p_failure_mce", "p_failure_mce_ci95"} <= set(c) and c["adequate"] in (
            True,
            False,
            None,
        )
        for k in ("vs_floor", "vs_best") if design["best"] is not None else ("vs_floor",):
            assert set(c[k]) >= {"difference", "difference_ci95", "p_better"}, (k, c[k])
        if c["source"] != "floor":
            assert "p_adjusted" in c["vs_floor"] and c["vs_floor"]["decided_by"] == "exact bounds"
    if design["verdict"] in ("inconclusive", "restrain"):
        assert design["recommended"] is None
    else:
        assert design["recommended"] is not None and design["recommended"]["adequate"] is True
        assert design["recommended"]["estimate"] <= floor["estimate"]  # never worse than doing nothing
    assert isinstance(design["edge_of_grid"], bool)


@pytest.mark.e2e
def test_the_verdict_is_recomputed_from_the_store_alone(assessed, tmp_path):
    """Every candidate's runs (the design search's grid included) are in /assessment/runs: the store
    alone, copied away from its job files, gives the same verdicts, recommendation and ranking."""
    import shutil

    from isorock.jobs.design import verdicts_from_store
    from isorock.store import Store

    wd, out, _ = assessed
    lone = tmp_path / "isorock.h5"
    shutil.copy(wd / "results" / "isorock.h5", lone)
    again = verdicts_from_store(lone)
    stored = Store(lone).table("assessment/verdicts").to_dict("records")
    assert len(again) == len(stored) == len(out["design"]) > 0
    for a, s, d in zip(again, stored, out["design"], strict=True):
        assert (a["object"], a["design_g"], a["verdict"]) == (s["object"], s["design_g"], s["verdict"])
        assert (a["recommended"], a["best"], a["closest"]) == (s["recommended"], s["best"], s["closest"])
        ranked = [(r["name"], r["rank"], r["adequate"]) for r in a["level"]["candidates"]]
        assert ranked == [(r["name"], r["rank"], r["adequate"]) for r in d["candidates"]]
    runs = Store(lone).table("assessment/runs")
    assert runs["case"].str.startswith("design/grid-").any() and (runs["case"] == "design/none").any()


@pytest.mark.e2e
def test_stripe_counts_agree_with_simulate(assessed):
    """A stripe's n_overturn is the number of its records that ``isorock simulate`` overturns; its
    n_failure those that overturn or move the isolator beyond the capacity (0.3 m)."""
    wd, out, recs = assessed
    o = out["objects"][0]
    for c in out["cases"]:
        for s in c["stripes"]:
            n_ov = n_fail = 0
            for r in out["records"]:
                src = ["--id", r["id"], "--records", recs] if recs else ["--record", r["file"]]
                res = _isorock(
                    "simulate", "--lambda", repr(o["lambda"]), "--R", repr(o["R_m"]), *FLAGS[c["isolation"]],
                    *src, "--pga", repr(s["level"]), "--json", cwd=wd,
                )  # fmt: skip
                assert res.returncode == 0, res.stderr
                sim = json.loads(res.stdout)
                over = sim["outcome"] == "overturn"
                n_ov += over
                n_fail += over or sim["max_base_disp_m"] > 0.3
                assert {"mu_required", "min_normal_over_weight"} <= set(sim)
            assert s["n_overturn"] == n_ov, (c["isolation"], s["level"])
            assert s["n_failure"] == n_fail, (c["isolation"], s["level"])


@pytest.mark.e2e
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
            "verdicts",
        ):
            df = pd.read_hdf(store, f"assessment/{key}")
            assert len(df), key
    runs = pd.read_hdf(store, "assessment/runs")
    assert {"mu_required", "min_normal_over_weight", "outside_model", "max_base_disp_m"} <= set(runs.columns)
    # 2 cases x 2 records x (stripes, the design level and its MCE level); and the design search's
    # fixed base and grid (case design/<candidate>), as many runs per candidate
    cases = runs[~runs["case"].str.startswith("design/")]
    assert len(cases) == 2 * 2 * len(set(STRIPES) | {0.4, 0.6})
    assert len(runs) % len(cases[cases["case"] == "none"]) == 0 and (runs["case"] == "design/none").any()
    assert {"failure", "exceeds_capacity", "overturn"} <= set(runs.columns)
    # no paper study ran: a file with only records, isolation and assessment
    assert (
        not (wd / "results" / "jobs" / "overturn").exists()
        and not (wd / "results" / "jobs" / "maps").exists()
    )
    landing = (wd / "results" / "report" / "landing.rst").read_text()
    answer = ("statue is safe on", "statue is not safe on any base", "Whether statue is safe")
    assert landing.index("Assessment") < landing.index("Method") and any(a in landing for a in answer)
    # the page stays short, on one screen; its one directive, at the end, is the style that puts it at the
    # top of the report's window (Snakemake centres it vertically)
    text, _, style = landing.partition(".. raw:: html")
    assert sum(1 for ln in text.splitlines() if ln.strip()) <= 20 and ".. " not in text
    assert "<style" in style and ".. " not in style
    html = (wd / "report-museum.html").read_text()
    assert any(a in html for a in answer)  # the landing page of the report opens with the answer
    for kind in ("fragility", "displacement", "design"):
        assert (wd / "results" / "figures" / f"assessment_{kind}_statue.png").stat().st_size > 10_000


@pytest.mark.e2e
def test_job_files_hold_one_table_per_record_of_their_block(assessed, tmp_path):
    """A block's job file gives the merge the same tables as one job file per record."""
    from isorock.jobs.jobfiles import ASSESS_KEY, _job_tables

    wd, _, _ = assessed
    cfg = pipeline.workflow_config(wd / "museum.yaml")
    ids = pipeline.plan(cfg, basedir=wd).ids
    assert list(pipeline.record_blocks(ids, cfg["resources"]["records_per_job"])) == ["b0"]
    block = wd / "results" / "jobs" / "assess" / "statue" / "lin3" / "b0.h5"
    singles = []
    for rid in reversed(ids):  # records written out of order: the merge reads them in the inputs' order
        singles.append(tmp_path / f"{rid}.h5")
        pipeline.assess_records(wd / "results" / "jobs" / "records" / f"{rid}.h5", singles[-1],
                               **pipeline.params_assess(cfg, "statue", "lin3"))  # fmt: skip
    from_block = _job_tables([block], ASSESS_KEY)
    from_singles = _job_tables(singles[::-1], ASSESS_KEY)
    assert [at["record"] for _, at in from_block] == ids == [at["record"] for _, at in from_singles]
    for (a, _), (b, _) in zip(from_block, from_singles, strict=True):
        pd.testing.assert_frame_equal(a, b)


@pytest.mark.e2e
def test_dry_run_one_job_per_object_case_and_block(assessed, tmp_path):
    wd, _, _ = assessed
    cfg = yaml.safe_load((wd / "museum.yaml").read_text())
    cfg["resources"] = {"records_per_job": 1}  # the two records in two blocks
    (tmp_path / "blocks.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "blocks.yaml", "--dry-run", cwd=tmp_path, timeout=300)
    assert res.returncode == 0, res.stderr[-3000:]
    out = res.stdout + res.stderr
    stats = dict(re.findall(r"^(\w+)\s+(\d+)$", out, re.M))
    assert (stats["assess_stripes"], stats["assess_design"]) == ("4", "2")
    # at most records_per_job records per process_record job: one job, and one rule, per record here
    assert (stats["process_record_p0"], stats["process_record_p1"]) == ("1", "1")
    assert "results/jobs/assess/statue/lin3/b1.h5" in out


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
        ({"design_g": [0.9]}, "design_g: 0.9 g is outside the stripes (0.15 to 0.8 g)"),
        ({"outside_model": "ignore"}, "outside_model"),
        ({"hazard": {"points": [[0.1, 1e-2], [0.2, 1e-3]]}}, "hazard"),
        ({"hazard": {"points": [[0.1, 1e-2], [0.2, 1e-3], [0.4, 2e-3]]}}, "must be positive and decrease"),
        # the same plausibility checks as the command line's
        ({"objects": [{"name": "s", "height_m": 180, "width_m": 60, "friction": 0.5}]},
         "assessment.objects.0 (s): height_m 180 reads like centimetres: 180 m is above 10 m"),
        ({"objects": [{"name": "s", "height_m": 1.8, "width_m": 0.6, "friction": 1.5}]},
         "friction 1.5 is above 1: no floor grips an object that hard"),
        # an object that slides must say how far it may (issue 24)
        ({"objects": [{"name": "s", "height_m": 1.2, "width_m": 0.5, "friction": 0.35}]},
         "friction 0.35 is below tan(alpha) 0.417: the object slides and never rocks; give slide_allow_m"),
        ({"objects": [{"name": "s", "height_m": 1.2, "width_m": 0.5, "friction": 0.35, "slide_allow_m": 0}]},
         "slide_allow_m: 0 is out of range"),
        ({"design_grid": {"kind": "fp", "mu_b": [0.05, 0.5], "R_b_m": [2.0]}},
         "design_grid.mu_b: mu_b 0.5 is above 0.3"),
        ({"design_grid": {"kind": "linear", "Tb_s": [2.0, 3.5], "xi_b": [0.1, 0.3],
                          "bounds": {"Tb_s": [6, 2]}}},
         "design_grid.bounds.Tb_s: [6, 2]: give [low, high], low < high"),
    ],
)  # fmt: skip
def test_bad_configurations_stop_before_any_job(tmp_path, change, words):
    cfg = _config(None)
    cfg["assessment"].update(change)
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "bad.yaml", cwd=tmp_path, timeout=120)
    assert res.returncode == 2 and words in res.stderr, res.stderr
    assert len(res.stderr.strip().splitlines()) == 1 and not (tmp_path / "results").exists()


def test_an_isolator_friction_out_of_catalogues_is_refused_in_the_cases_too(tmp_path):
    cfg = _config(None)
    cfg["isolation"]["cases"].append({"name": "fp", "kind": "fp", "mu_b": 0.45, "R_b_m": 2.0})
    (tmp_path / "bad.yaml").write_text(yaml.safe_dump(cfg))
    res = _isorock("assess", "bad.yaml", cwd=tmp_path, timeout=120)
    assert res.returncode == 2 and "isolation.cases.2 (fp): mu_b 0.45 is above 0.3" in res.stderr, res.stderr


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


def test_the_example_assessment_is_the_default_runs_only(tmp_path):
    """config/config.yaml's example assessment is not merged into another configuration."""
    assert pipeline.workflow_config()["assessment"]["objects"]
    assert pipeline.workflow_config(ROOT / "config" / "ci.yaml")["assessment"] is None
    own = pipeline.workflow_config(ROOT / "config" / "assessment.yaml")["assessment"]
    names = [
        o["name"]
        for o in yaml.safe_load((ROOT / "config" / "assessment.yaml").read_text())["assessment"]["objects"]
    ]
    assert [o["name"] for o in own["objects"]] == names and own["hazard"]
    assert names != [o["name"] for o in pipeline.workflow_config()["assessment"]["objects"]]
    (tmp_path / "x.yaml").write_text("records: {dir: null}\n")
    res = _isorock("assess", "x.yaml", "--print-commands", cwd=tmp_path, timeout=120)
    assert res.returncode == 2 and "no 'assessment' section" in res.stderr


@pytest.mark.e2e
def test_the_worked_example_verdicts_are_recomputed_from_its_store(tmp_path):
    """config/assessment.yaml as a user runs it (the Table 1 records of $ISOROCK_RECORDS, else the
    pyslammer samples): every object's verdict says whether it is safe against the stated target, and
    the store alone, away from the job files, gives the same verdicts."""
    import shutil

    from isorock.jobs.design import verdicts_from_store
    from isorock.store import Store

    pytest.importorskip("snakemake")
    if records_dir() is None:
        pytest.importorskip("pyslammer")
    shutil.copy(ROOT / "config" / "assessment.yaml", tmp_path / "assessment.yaml")
    res = _isorock("assess", "assessment.yaml", "--cores", "2", "--json", cwd=tmp_path, timeout=1500)
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-4000:]
    out = json.loads(res.stdout)
    cfg = yaml.safe_load((ROOT / "config" / "assessment.yaml").read_text())["assessment"]
    assert {d["object"] for d in out["design"]} == {o["name"] for o in cfg["objects"]}
    # the statue of measured geometry beside the uniform block of its outline (issue 34): the report
    # says what it is and how and why the two answers differ
    measured = next(c for c in out["conclusions"] if c["object"] == "statue-measured")
    text = " ".join(measured["details"])
    assert "is a rigid body of measured geometry" in text and "as recorded and reversed" in text
    assert "Beside statue, the uniform block of the same 1.8 m x 0.6 m outline" in text
    assert "Runs that overturned over the stripes, per base" in text
    for d, c in zip(out["design"], out["conclusions"], strict=True):
        assert d["target"]["kind"] == "p_mce" and d["target"]["value"] == 0.1
        assert d["verdict"] in ("isolate", "fixed_base", "restrain", "inconclusive")
        assert "2475-year" in d["mce_basis"]
        head = c["headline"]
        assert " is safe on " in head or " is not safe on any base" in head or "is safe is not shown" in head
    lone = tmp_path / "lone.h5"
    shutil.copy(tmp_path / "results" / "isorock.h5", lone)
    shutil.rmtree(tmp_path / "results")
    again = verdicts_from_store(lone)
    stored = Store(lone).table("assessment/verdicts").to_dict("records")
    assert [(a["object"], a["verdict"], a["recommended"], a["best"], a["closest"]) for a in again] == [
        (s["object"], s["verdict"], s["recommended"], s["best"], s["closest"]) for s in stored
    ]
