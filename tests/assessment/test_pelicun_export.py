"""``isorock assess --export-fragility``: the fitted fragilities as a pelicun damage model
(:mod:`isorock.assessment.pelicun_export`).

The fragility table is built by the package's own code path (:func:`bootstrap_fragility` on synthetic
outcomes, :meth:`CaseEvaluation.fragility_rows`, the flags as :func:`assessment_tables` stores them),
not by a workflow run. The CSV is checked against what pelicun's loader relies on (:func:`_check_schema`,
written from pelicun's source, lines of commit 435f40b of NHERI-SimCenter/pelicun) and, where pelicun
imports (here, or in the Python that ``ISOROCK_PELICUN_PYTHON`` names), by pelicun itself: its loader,
and a damage calculation whose fraction in DS1 is the fitted curve at the demand.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import h5py
import numpy as np
import pandas as pd
import pytest
from scipy.stats import norm

from isorock import __version__
from isorock.assessment.case import CaseEvaluation
from isorock.assessment.fragility import bootstrap_fragility, resample_weights
from isorock.assessment.pelicun_export import (
    PELICUN_COLUMNS,
    component_id,
    demand_type,
    fragility_rows,
    pelicun_unit,
    read_measure,
    write_pelicun_csv,
)
from isorock.errors import IsorockError
from isorock.processing.imt import parse_imt
from isorock.store import atomic_path, write_tables

LEVELS = [0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 1.3]
N_RECORDS = 24


def _evaluation(capacity_median: float | None, seed: int = 1) -> CaseEvaluation:
    """A case's fits of synthetic outcomes: each record's capacity lognormal (median
    ``capacity_median`` g, beta 0.4), damaged at every level at or above it; failure at 0.8 of the
    capacity, uplift at 0.3 of it; ``None``: nothing ever damaged (the fits not estimable)."""
    rng = np.random.default_rng(seed)
    x = np.asarray(LEVELS)
    W = resample_weights(N_RECORDS, 50, 0)
    if capacity_median is None:
        cap = np.full(N_RECORDS, np.inf)
    else:
        cap = capacity_median * np.exp(0.4 * rng.standard_normal(N_RECORDS))
    est = {
        d: bootstrap_fragility(LEVELS, x[None, :] >= f * cap[:, None], weights=W)
        for d, f in (("overturn", 1.0), ("failure", 0.8), ("uplift", 0.3))
    }
    if capacity_median is None:  # uplift still estimable where nothing overturns
        est["uplift"] = bootstrap_fragility(LEVELS, x[None, :] >= 0.3 * 0.5 * np.exp(
            0.4 * rng.standard_normal(N_RECORDS))[:, None], weights=W)  # fmt: skip
    return CaseEvaluation(pd.DataFrame(), est, [], None, N_RECORDS, 0)


def _table(cases: dict[tuple[str, str, str], CaseEvaluation]) -> pd.DataFrame:
    """The ``/assessment/fragility`` table as :func:`assessment_tables` builds and stores it."""
    rows = []
    for (obj, case, kind), ev in cases.items():
        rows += [{"object": obj, "case": case, "isolation": kind, **r} for r in ev.fragility_rows()]
    df = pd.DataFrame(rows)
    df["estimable"] = df["estimable"].astype(np.int8)  # as assessment_tables stores a flag
    return df


@pytest.fixture(scope="module")
def fits():
    return {
        ("statue", "lin3", "linear"): _evaluation(0.5),
        ("statue", "none", "none"): _evaluation(None),
        ("vase-2", "fp1", "fp"): _evaluation(0.9, seed=2),
    }


@pytest.fixture(scope="module")
def table(fits):
    return _table(fits)


def _store(path: Path, table: pd.DataFrame, measure: dict | None = None) -> Path:
    """A store with the fragility table and, given, its /assessment/measure row (as the merge writes
    it; without: a store of layout 6 or older)."""
    tables = {"assessment/fragility": table}
    if measure:
        imt = measure["imt"]
        tables["assessment/measure"] = pd.DataFrame([{"unit": "cm/s" if imt == "PGV" else "g", **measure}])
    with atomic_path(path) as tmp:
        write_tables(tmp, tables)
    return path


# ------------------------------------------------------------------ pelicun's schema
#: the demand types pelicun knows (pelicun/base.py:1310 EDP_to_demand_type, the ground-motion ones)
_PELICUN_TYPES = {"Peak Ground Acceleration", "Peak Ground Velocity", "Spectral Acceleration",
                  "Peak Spectral Acceleration"}  # fmt: skip
#: acceleration and velocity units of pelicun/settings/default_units.json (g: line 45, cmps: 33)
_PELICUN_UNITS = {"g", "mps2", "inps2", "inchps2", "ftps2", "cmps", "mps", "mph", "inps", "inchps", "ftps"}


def _check_schema(path: Path) -> pd.DataFrame:
    """What pelicun's loader relies on, from its source (NHERI-SimCenter/pelicun at 435f40b):

    - file_io.py:599 ``load_from_file``: ``pd.read_csv(path, header=0, index_col=0)``: the first column
      is the component ID;
    - base.py:838 ``convert_to_MultiIndex``: the IDs (``load_data(..., reindex=False)``) and the columns
      are split at ``-`` into index levels: no ``-`` in an ID, at most two levels in a column name;
    - model/damage_model.py:2042 ``_is_for_ds_model``: a ``LS1`` column, else "Invalid damage model
      parameters";
    - model/demand_model.py:1314-1316 ``_get_required_demand_type``: ``Demand-Type``,
      ``Demand-Offset``, ``Demand-Directional`` of every component; 1332-1346: the type a key of
      ``EDP_to_demand_type`` (base.py:1310), with one optional ``|subtype``; 1360: the offset an
      integer; 1363: directional read as a truth value (0 or 1);
    - model/damage_model.py:527 ``convert_damage_parameter_units``: ``Demand-Unit``, a unit of
      settings/default_units.json;
    - model/damage_model.py:557 ``remove_incomplete_components``: ``Incomplete`` 1 drops a row;
    - model/damage_model.py:1454-1462 ``_create_dmg_RVs``: each limit state's ``Theta_0``,
      ``Family``, ``Theta_1`` and ``DamageStateWeights``; 1983 ``complete_ds_cols``: the column
      ``LS<i>-DamageStateWeights`` read by name (a KeyError without it).
    """
    df = pd.read_csv(path, header=0, index_col=0)
    assert df.index.name == "ID"
    assert not [i for i in df.index if "-" in str(i) or not str(i)], list(df.index)
    assert not df.index.duplicated().any()
    levels = [c.split("-") for c in df.columns]
    assert all(len(lv) <= 2 for lv in levels), list(df.columns)
    ls = sorted({lv[0] for lv in levels if re.fullmatch(r"LS\d+", lv[0])})
    assert "LS1" in ls
    need = {"Incomplete", "Demand-Type", "Demand-Unit", "Demand-Offset", "Demand-Directional"}
    need |= {f"{s}-{k}" for s in ls for k in ("Family", "Theta_0", "Theta_1", "DamageStateWeights")}
    assert need <= set(df.columns), sorted(need - set(df.columns))
    for cid, r in df.iterrows():
        t = str(r["Demand-Type"])
        assert t.split("|")[0] in _PELICUN_TYPES and t.count("|") <= 1, (cid, t)
        if "|" in t:
            assert float(t.split("|")[1]) > 0
        assert r["Demand-Unit"] in _PELICUN_UNITS, (cid, r["Demand-Unit"])
        assert r["Incomplete"] in (0, 1) and r["Demand-Directional"] in (0, 1)
        assert float(r["Demand-Offset"]) == int(r["Demand-Offset"])
        for s in ls:
            if not pd.isna(r[f"{s}-Theta_0"]):
                assert r[f"{s}-Family"] == "lognormal"
                assert r[f"{s}-Theta_0"] > 0 and r[f"{s}-Theta_1"] > 0
    return df


# ------------------------------------------------------------------ the rows
def test_columns_ids_and_the_fitted_parameters(fits, table):
    rows, left = fragility_rows(table)
    assert list(rows.columns) == list(PELICUN_COLUMNS)
    assert list(rows["ID"]) == [
        "statue.lin3.overturn", "statue.lin3.failure", "vase_2.fp1.overturn", "vase_2.fp1.failure",
    ]  # fmt: skip
    assert (rows["Incomplete"] == 0).all() and (rows["Demand-Offset"] == 0).all()
    assert (rows["Demand-Directional"] == 1).all() and (rows["LS1-Family"] == "lognormal").all()
    for cid, (key, damage) in {
        "statue.lin3.overturn": (("statue", "lin3", "linear"), "overturn"),
        "statue.lin3.failure": (("statue", "lin3", "linear"), "failure"),
        "vase_2.fp1.failure": (("vase-2", "fp1", "fp"), "failure"),
    }.items():
        fit = fits[key].estimates[damage].fit
        assert fit.estimable
        r = rows.set_index("ID").loc[cid]
        assert r["LS1-Theta_0"] == fit.median and r["LS1-Theta_1"] == fit.beta
    # uplift is fitted, but is no failure: not exported unless asked for
    assert not rows["ID"].str.endswith("uplift").any()
    up, _ = fragility_rows(table, damages=["uplift"])
    assert len(up) == 3 and up["ID"].str.endswith(".uplift").all()
    assert not any(x.damage == "uplift" for x in left)


def test_a_fit_not_estimable_is_left_out_with_its_reason(fits, table):
    rows, left = fragility_rows(table)
    assert {x.id for x in left} == {"statue.none.overturn", "statue.none.failure"}
    assert not rows["ID"].str.startswith("statue.none.").any()
    for x in left:
        fit = fits[("statue", "none", "none")].estimates[x.damage].fit
        assert not fit.estimable and x.reason == fit.note and x.reason.startswith("not estimable: no damage")
        assert x.line() == f"left out {x.id}: {fit.note}" and "\n" not in x.line()
        assert x.to_dict() == {"id": x.id, "object": "statue", "case": "none", "damage": x.damage,
                               "reason": fit.note}  # fmt: skip


def test_a_flag_that_says_estimable_with_no_median_is_still_left_out(table):
    t = table.copy()
    t.loc[(t["case"] == "lin3") & (t["damage"] == "failure"), "median_g"] = math.nan
    rows, left = fragility_rows(t)
    assert "statue.lin3.failure" not in set(rows["ID"])
    assert "statue.lin3.failure" in {x.id for x in left}


@pytest.mark.parametrize(
    ("imt", "dtype", "unit"),
    [
        ("PGA", "Peak Ground Acceleration", "g"),
        ("SA(1.0)", "Peak Spectral Acceleration|1.0", "g"),
        ("SA0P3", "Peak Spectral Acceleration|0.3", "g"),
        ("PGV", "Peak Ground Velocity", "cmps"),
    ],
)
def test_demand_type_and_unit_of_each_measure(table, imt, dtype, unit):
    m = parse_imt(imt)
    assert demand_type(m) == dtype and pelicun_unit(m) == unit
    rows, _ = fragility_rows(table, imt=imt, component="RotD50")
    assert set(rows["Demand-Type"]) == {dtype} and set(rows["Demand-Unit"]) == {unit}
    assert (
        rows["Comment"]
        .str.contains(f"measure {m.describe()} [{m.unit}], component definition RotD50", regex=False)
        .all()
    )


def test_ids_keep_only_what_pelicun_does_not_split():
    assert component_id("vase-2", "lin 3", "failure") == "vase_2.lin_3.failure"
    assert component_id("statue", "lin3", "overturn") == "statue.lin3.overturn"


def test_two_names_that_clean_to_one_id_are_refused(table):
    t = table.copy()
    t2 = t[t["object"] == "vase-2"].assign(object="vase_2")
    with pytest.raises(IsorockError, match="both become the ID vase_2.fp1"):
        fragility_rows(pd.concat([t, t2], ignore_index=True))


# ------------------------------------------------------------------ the store and the file
def test_from_a_store_its_measure_component_and_source(tmp_path, table):
    old = _store(tmp_path / "old.h5", table)
    assert read_measure(old) == (parse_imt("PGA"), "analysed")
    rows, _ = fragility_rows(old)
    assert set(rows["Demand-Type"]) == {"Peak Ground Acceleration"}
    new = _store(tmp_path / "new.h5", table, {"imt": "SA(1.0)", "component": "RotD100"})
    rows, left = fragility_rows(new)
    assert set(rows["Demand-Type"]) == {"Peak Spectral Acceleration|1.0"}
    c = rows.set_index("ID").loc["statue.lin3.failure", "Comment"]
    assert c.startswith(f"isorock {__version__}: failure (overturn")
    assert "object 'statue' on base 'lin3' (linear)" in c and "component definition RotD100" in c
    assert f"source {new}" in c and f"{N_RECORDS * len(LEVELS)} runs at {len(LEVELS)} stripes" in c
    assert "95 % bootstrap interval of the median" in c and len(left) == 2
    rows_t, _ = fragility_rows({"fragility": table}, imt="SA(1.0)", component="RotD100")
    assert rows_t.drop(columns="Comment").equals(rows.drop(columns="Comment"))
    measure = pd.DataFrame([{"imt": "SA(1.0)", "unit": "g", "component": "RotD100"}])
    rows_m, _ = fragility_rows({"fragility": table, "measure": measure})  # as assessment_tables gives them
    assert rows_m.equals(rows_t)


def test_write_is_atomic_and_readable_as_pelicun_reads_it(tmp_path, table):
    store = _store(tmp_path / "s.h5", table, {"imt": "SA(1.0)", "component": "RotD50"})
    out = tmp_path / "frag.csv"
    out.write_text("old\n")
    rows, left = write_pelicun_csv(out, store)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frag.csv", "s.h5"]  # no temporary left
    df = _check_schema(out)
    assert list(df.index) == list(rows["ID"]) and len(left) == 2
    assert np.array_equal(df["LS1-Theta_0"].to_numpy(), rows["LS1-Theta_0"].to_numpy())  # every digit
    assert np.array_equal(df["LS1-Theta_1"].to_numpy(), rows["LS1-Theta_1"].to_numpy())
    assert df["LS1-DamageStateWeights"].isna().all()


def test_a_missing_directory_is_one_error_and_nothing_written(tmp_path, table):
    with pytest.raises(IsorockError, match="the directory .*nowhere does not exist"):
        write_pelicun_csv(tmp_path / "nowhere" / "f.csv", table)
    with pytest.raises(IsorockError, match="is a directory"):
        write_pelicun_csv(tmp_path, table)
    assert not (tmp_path / "nowhere").exists()


# ------------------------------------------------------------------ pelicun itself
_PELICUN_SCRIPT = r"""
import json, sys
import numpy as np, pandas as pd
from pelicun.assessment import Assessment
paths, n = sys.argv[1:], 4000
ids = [i for p in paths for i in pd.read_csv(p, index_col=0).index]
a = Assessment({"PrintLog": False, "Seed": 1})
a.damage.load_model_parameters(paths, set(ids), warn_missing=True)
params = a.damage.ds_model.damage_params
x = {"PGA": 0.45, "SA_1.0": 0.8}
demand = pd.DataFrame({(k, "0", "1"): np.full(n, v) for k, v in x.items()})
demand.loc["Units"] = ["g"] * len(x)
a.demand.load_sample(pd.concat([demand.loc[["Units"]], demand.drop("Units")]))
a.asset.load_cmp_model({"marginals": pd.DataFrame(
    {"Units": "ea", "Location": "0", "Direction": "1", "Theta_0": 1.0}, index=ids)})
a.asset.generate_cmp_sample(n)
a.damage.calculate()
ds = a.damage.ds_model.sample
out = {"loaded": sorted(params.index), "columns": [list(c) for c in params.columns],
       "theta0_si": {i: float(params.loc[i, ("LS1", "Theta_0")]) for i in ids},
       "p_ds1": {i: float(ds[(i, "0", "1", "0", "1")].mean()) for i in ids}}
print(json.dumps(out))
"""


def _pelicun_python() -> str | None:
    if importlib.util.find_spec("pelicun") is not None:
        return sys.executable
    return os.environ.get("ISOROCK_PELICUN_PYTHON") or None


def test_pelicun_loads_it_and_computes_the_fitted_curve(tmp_path, table):
    py = _pelicun_python()
    if py is None:
        pytest.skip(
            "pelicun does not import here: pip install pelicun, or set ISOROCK_PELICUN_PYTHON to a Python "
            "that has it; the schema test above checks what its loader relies on"
        )
    # the files the command writes: the statue's fits against PGA, the vase's against SA(1.0)
    pga_csv, sa_csv = tmp_path / "pga.csv", tmp_path / "sa.csv"
    pga, _ = write_pelicun_csv(pga_csv, table[table["object"] == "statue"], imt="PGA", component="RotD50")
    sa, _ = write_pelicun_csv(sa_csv, table[table["object"] == "vase-2"], imt="SA(1.0)", component="RotD50")
    res = subprocess.run(
        [py, "-c", _PELICUN_SCRIPT, str(pga_csv), str(sa_csv)], capture_output=True, text=True, timeout=120
    )
    assert res.returncode == 0, res.stderr[-3000:]
    out = json.loads(res.stdout.strip().splitlines()[-1])
    assert out["loaded"] == sorted(pga["ID"].tolist() + sa["ID"].tolist())
    assert ["Comment", ""] in out["columns"]  # kept, and harmless
    x = {"statue": 0.45, "vase_2": 0.8}
    for r in pd.concat([pga, sa]).to_dict("records"):
        assert out["theta0_si"][r["ID"]] == pytest.approx(r["LS1-Theta_0"] * 9.80665)  # g -> m/s2
        p = norm.cdf(math.log(x[r["ID"].split(".")[0]] / r["LS1-Theta_0"]) / r["LS1-Theta_1"])
        assert out["p_ds1"][r["ID"]] == pytest.approx(p, abs=0.03)


# ------------------------------------------------------------------ the command
def _fake_run(monkeypatch, store: Path) -> list:
    """``isorock assess`` without the workflow: ``build`` returns settings whose run "wrote" ``store``."""
    import isorock.cli.assessment as cli

    calls: list = []

    def build(a):
        calls.append(a)
        return SimpleNamespace(
            config={"assessment": {"objects": []}},
            configfile=Path(a.config),
            execute=lambda **kw: SimpleNamespace(
                store=store, report=store.parent / "report.html", dry_run=False
            ),
        )

    monkeypatch.setattr(cli, "build", build)
    return calls


def test_the_command_writes_the_file_and_says_what_it_left_out(tmp_path, table, monkeypatch, capsys):
    from isorock.cli import main

    store = _store(tmp_path / "isorock.h5", table, {"imt": "PGA", "component": "RotD50"})
    _fake_run(monkeypatch, store)
    out = tmp_path / "frag.csv"
    assert main(["assess", "museum.yaml", "--export-fragility", str(out), "--json"]) == 0
    cap = capsys.readouterr()
    j = json.loads(cap.out)["exported_fragility"]
    assert j["path"] == str(out.absolute()) and j["n_rows"] == 4
    assert [x["id"] for x in j["left_out"]] == ["statue.none.overturn", "statue.none.failure"]
    err = cap.err.strip().splitlines()
    assert [ln for ln in err if ln.startswith("isorock assess: --export-fragility:")] == [
        f"isorock assess: --export-fragility: left out {x['id']}: {x['reason']}" for x in j["left_out"]
    ]
    assert err[-1] == f"fragility for pelicun: {out.absolute()} (4 row(s), 2 left out)"
    assert len(_check_schema(out)) == 4


def test_the_command_refuses_a_missing_directory_before_the_run(tmp_path, table, monkeypatch, capsys):
    from isorock.cli import main

    calls = _fake_run(monkeypatch, _store(tmp_path / "isorock.h5", table))
    bad = tmp_path / "no" / "frag.csv"
    assert main(["assess", "museum.yaml", "--export-fragility", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"isorock: error: --export-fragility {bad}: the directory {bad.parent} does not exist"]
    assert calls == []  # nothing was run


def test_the_comment_says_the_base_the_capacity_and_a_median_beyond_the_stripes(tmp_path, table):
    """A loss analyst reads what a row is without the store: the base's parameters, the capacity and
    gamma_x behind "failure", and a median read off the fitted form beyond the highest stripe."""
    store = _store(tmp_path / "s.h5", table, {"imt": "PGA", "component": "analysed"})
    cases = [{"name": c, "kind": "linear", "Tb_s": 3.0, "xi_b": 0.2} for c in sorted(set(table["case"]))]
    cfg = {"isolation": {"cases": cases}, "assessment": {"capacity_m": 0.3, "gamma_x": 1.2,
                                                         "stripes_g": [0.05, 0.1]}}  # fmt: skip
    with h5py.File(store, "a") as f:
        f.attrs["config_json"] = json.dumps(cfg)
    rows, _ = fragility_rows(store)
    for _, r in rows.iterrows():
        assert "linear isolator Tb 3.0 s, xi 0.2" in r["Comment"]
        assert (
            "failure counts 1.2 x the isolator's displacement beyond its capacity 0.3 m" in r["Comment"]
        ) == (r["ID"].endswith(".failure"))
        beyond = "the median lies beyond the highest stripe (0.1 g)" in r["Comment"]
        assert beyond == (r["LS1-Theta_0"] > 0.1)
    assert any(rows["LS1-Theta_0"] > 0.1)
