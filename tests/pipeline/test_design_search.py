"""The design search settles itself (isorock.jobs.design): where the best isolator of the
grid lies on an edge, the grid is extended in that direction, one step of its own spacing at a time,
until the best is inside or a bound is reached, and the merge ranks the extended grid. Real engine
runs on synthetic records (long-period pulses, which a short isolation period amplifies)."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pandas as pd
import pytest

from isorock import G
from isorock.assessment.case import Settings
from isorock.assessment.design import Candidate, candidate_params, evaluate_candidates, rank
from isorock.assessment.stripes import AssessedObject
from isorock.jobs.assessment import design_records
from isorock.jobs.design import (
    GridSpec,
    design_extend,
    design_tables,
    grid_candidates,
    read_extension,
    split_design_runs,
)
from isorock.jobs.jobfiles import DESIGN_KEY, _job_tables
from isorock.jobs.record import read_job_record
from isorock.physics.engine import simulate
from isorock.physics.model import LinearIsolation, NoIsolation, System

OBJ = {"name": "statue", "height_m": 1.8, "width_m": 0.5, "friction": 0.8}


def _records(tmp_path, n: int = 10) -> list:
    """``process_record``-like files: short-period shaking (1.5 to 3.5 Hz), which an isolator filters:
    its displacement approaches the ground's, and less of it the longer its period and the more its
    damping."""
    rng = np.random.default_rng(3)
    t = np.arange(0.0, 14.0, 0.01)
    paths = []
    for k in range(n):
        a = np.zeros(t.size)
        for _ in range(6):
            a += np.sin(2 * np.pi * (1.5 + 2.0 * rng.random()) * t + 2 * np.pi * rng.random())
        a *= np.exp(-(((t - 5.0) / 2.5) ** 2))
        a = a / np.abs(a).max() * 0.4 * G
        p = tmp_path / f"r{k}.h5"
        with h5py.File(p, "w") as h:
            g = h.create_group(f"records/r{k}")
            d = g.create_dataset("acc", data=a)
            d.attrs["dt_s"] = 0.01
            g.attrs["record_sha256"] = f"{k}"
        paths.append(p)
    return paths


def _assessment(grid: dict) -> dict:
    """Failure is the isolator's displacement beyond 6 cm (the statue does not overturn on these
    isolators; gamma_x 1: the displacement as analysed): the longer the period and the more the
    damping, the better."""
    return {
        "objects": [OBJ], "cases": ["none"], "capacity_m": 0.06, "stripes_g": [0.3, 0.6, 1.0, 1.5, 2.0],
        "design_g": [1.0], "mce_g": [1.0], "gamma_x": 1.0, "outside_model": "exclude", "bootstrap": 300,
        "seed": 0,
        "design_grid": grid,
    }  # fmt: skip


def _design_runs(design_file, spec):
    d = pd.concat([df for df, _ in _job_tables([design_file], DESIGN_KEY)], ignore_index=True)
    return split_design_runs(d, spec)


def _merged(design_file, ext_file, a) -> tuple[pd.DataFrame, dict]:
    """What the merge makes of the job files (isorock.jobs.design.design_tables): the
    candidates' table and the verdict row."""
    from isorock.control.config import isolation_cases, workflow_config

    cfg = workflow_config(
        {"isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"}]}, "assessment": a}
    )
    tables = design_tables(
        [design_file, ext_file], cfg, [AssessedObject.from_config(OBJ)], isolation_cases(cfg), {},
        Settings.from_config(cfg["assessment"]),
    )  # fmt: skip
    (verdict,) = tables["verdicts"].to_dict("records")
    return tables["design"], verdict


@pytest.fixture(scope="module")
def searched(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("design")
    recs = _records(tmp)
    grid = {"kind": "linear", "Tb_s": [1.0, 1.25], "xi_b": [0.05, 0.1, 0.15],
            "bounds": {"Tb_s": [1.0, 2.0], "xi_b": [0.05, 0.3]}}  # fmt: skip
    a = _assessment(grid)
    levels = a["stripes_g"]
    dfile = tmp / "design.h5"
    design_records(recs, dfile, obj=OBJ, grid=grid, rho=0.5, stripes_g=levels, design_g=[1.0], mce_g=[1.0])
    efile = tmp / "extend.h5"
    attrs = design_extend([dfile], recs, efile, obj=OBJ, assessment=a, rho=0.5, levels_g=levels)
    return dfile, efile, a, attrs, recs, tmp


def test_the_configured_grid_has_its_best_on_an_edge(searched):
    """The premise: on the configured 2 x 3 grid (Tb 1-1.25 s) the best isolator is at an end."""
    dfile, _, a, _, _, _ = searched
    spec = GridSpec.from_config(a["design_grid"])
    floor, runs = _design_runs(dfile, spec)
    cands = [Candidate("none", "floor", candidate_params(NoIsolation()), floor)]
    cands += grid_candidates(spec.values, runs, spec, 0.5)
    s = Settings.from_config(a)
    evaluate_candidates(cands, s)
    (lvl,) = rank(cands, s)
    assert lvl["edges"], "the configured grid's best is inside: the test's premise does not hold"


def test_the_search_extends_the_grid_until_the_best_is_inside_or_at_a_bound(searched):
    """The best lies towards long periods and high damping: the search steps Tb by 0.25 s and xi by
    0.05 (the grid's own steps), within the bounds, until the best is inside the grid or at a bound it
    says it reached; the added isolators' runs are the engine's single analyses."""
    dfile, efile, a, attrs, recs, _ = searched
    assert attrs["extended"] and attrs["rounds"] >= 1
    design, verdict = _merged(dfile, efile, a)
    grid = json.loads(verdict["grid"])
    tb, xi = grid["axes"]["Tb_s"], grid["axes"]["xi_b"]
    assert grid["extended"] and grid["configured"] == {"Tb_s": [1.0, 1.25], "xi_b": [0.05, 0.1, 0.15]}
    assert max(tb) > 1.25 and max(xi) > 0.15  # grown towards both
    assert np.allclose(np.diff(tb), 0.25) and np.allclose(np.diff(xi), 0.05)
    assert max(tb) <= 2.0 and max(xi) <= 0.3 and min(tb) == 1.0 and min(xi) == 0.05
    # the merge ranks the whole extended grid and the fixed base
    assert attrs["added"] == len(tb) * len(xi) - 6 and len(design) == 1 + len(tb) * len(xi)
    assert set(zip(design["Tb_s"].dropna(), design["xi_b"].dropna(), strict=True)) == {
        (t, x) for t in tb for x in xi
    }
    reached = {(h["parameter"], h["side"]) for h in grid["bounds_reached"]}
    assert all(tuple(e) in reached for e in json.loads(verdict["edges"]))  # settled
    # an added isolator's run is simulate() of the record scaled to the level
    ext, _ = read_extension(efile, "statue")
    row = ext[(ext["p0"] == max(tb)) & (ext["p1"] == max(xi)) & (ext["level"] == 1.0)].iloc[0]
    _, gm, _ = read_job_record(next(p for p in recs if p.stem == row["record"]))
    system = System(AssessedObject.from_config(OBJ).block(), LinearIsolation(max(tb), max(xi), 0.5))
    one = simulate(system, gm,
                   scale=1.0 / gm.pga_g)  # fmt: skip
    assert row["max_base_disp_m"] == one.max_base_disp_m and row["outcome"] == one.outcome


def test_an_extension_is_reproducible_and_records_its_rounds(searched, tmp_path):
    dfile, efile, a, attrs, recs, _ = searched
    again = tmp_path / "again.h5"
    levels = a["stripes_g"]
    b = design_extend([dfile], recs, again, obj=OBJ, assessment=a, rho=0.5, levels_g=levels)
    assert {k: b[k] for k in ("axes", "bounds_reached", "rounds", "added")} == {
        k: attrs[k] for k in ("axes", "bounds_reached", "rounds", "added")
    }
    with h5py.File(efile) as h:
        g = h["design_extend/statue"]
        assert json.loads(g.attrs["axes"]) == json.loads(attrs["axes"]) and "runs" in g


def test_no_extension_when_switched_off(searched, tmp_path):
    dfile, _, a, _, recs, _ = searched
    off = _assessment({**a["design_grid"], "extend": False})
    out = tmp_path / "off.h5"
    attrs = design_extend([dfile], recs, out, obj=OBJ, assessment=off, rho=0.5, levels_g=off["stripes_g"])
    assert not attrs["extended"] and attrs["added"] == 0
    runs, info = read_extension(out, "statue")
    assert runs.empty and info["axes"] == [[1.0, 1.25], [0.05, 0.1, 0.15]]


def test_an_unsorted_grid_keeps_each_isolator_with_its_runs():
    """A grid given out of order ({Tb_s: [3, 2]}): the runs of assess_design's k-th isolator belong to
    the k-th point of the grid as configured, whatever the order the candidates are drawn in."""
    from isorock.jobs.assessment import design_isolations

    grid = {"kind": "linear", "Tb_s": [3.0, 2.0], "xi_b": [0.2, 0.1]}
    spec = GridSpec.from_config(grid)
    isos = design_isolations(grid, 0.5)
    assert spec.configured() == [(iso.Tb, iso.xi_b) for iso in isos]
    assert spec.values == ([2.0, 3.0], [0.1, 0.2])


def test_a_grid_value_given_twice_is_refused(tmp_path, monkeypatch):
    from isorock.control.config import workflow_config
    from isorock.errors import ConfigError

    monkeypatch.chdir(tmp_path)
    a = {**_assessment({"kind": "linear", "Tb_s": [2.0, 2.0, 3.0], "xi_b": [0.1]}), "cases": ["none"]}
    cfg = {"isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"}]}, "assessment": a}
    with pytest.raises(ConfigError, match=r"design_grid.Tb_s: \[2.0, 2.0, 3.0\]: a value is given twice"):
        workflow_config(cfg)


def test_the_configured_cases_alone_are_ranked_without_a_grid(searched):
    """No design grid: the merge ranks the configured cases (it once failed with "No objects to
    concatenate", having no design search's runs to add to /assessment/runs)."""
    from isorock.control.config import isolation_cases, workflow_config

    dfile, _, a, _, _, _ = searched
    spec = GridSpec.from_config(a["design_grid"])
    floor, runs = _design_runs(dfile, spec)
    lin = runs[(1.25, 0.15)].drop(columns=["isolator"])
    cases = [{"name": "none", "kind": "none"}, {"name": "lin", "kind": "linear", "Tb_s": 1.25, "xi_b": 0.15}]
    plain = {k: v for k, v in a.items() if k != "design_grid"} | {"cases": ["none", "lin"]}
    cfg = workflow_config({"isolation": {"rho": 0.5, "cases": cases}, "assessment": plain})
    obj = AssessedObject.from_config(OBJ)
    case_runs = {("statue", "none"): floor.drop(columns=["isolator"]), ("statue", "lin"): lin}
    tables = design_tables([dfile], cfg, [obj], isolation_cases(cfg), case_runs,
                           Settings.from_config(cfg["assessment"]))  # fmt: skip
    assert "candidate_runs" not in tables and set(tables["design"]["name"]) == {"none", "lin"}
    (v,) = tables["verdicts"].to_dict("records")
    assert v["verdict"] in ("isolate", "fixed_base", "restrain", "inconclusive") and not v["has_grid"]
