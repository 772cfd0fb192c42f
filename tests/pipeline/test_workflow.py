"""The Snakemake workflow (Snakefile, workflow/, config/) and its package side (isorock.pipeline).

The end-to-end tests copy the workflow into ``tmp_path`` and run it there on two real records of the
shared records directory (``$ISOROCK_RECORDS``, else ``../shared/records``) with tiny grids: the run
is interrupted once and restarted (finished jobs must not run again), then it must have nothing left
to do, a deleted output must rerun only its job and what depends on it, and the report must build.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import yaml

from isorock import pipeline
from isorock.errors import IsorockError
from isorock.store import file_sha256
from support.records import ROOT, records_dir

E2E_RECORDS = ["TAB78-TAB", "NOR94-RRS"]  # short records; NOR94-RRS has two files to choose from
RUN_TIMEOUT = 900


def _snakemake_available() -> bool:
    import importlib.util

    return importlib.util.find_spec("snakemake") is not None


needs_snakemake = pytest.mark.skipif(not _snakemake_available(), reason="snakemake is not installed")


def need_records() -> Path:
    d = records_dir()
    if d is None:
        pytest.skip("shared records not found: set ISOROCK_RECORDS (default ../shared/records)")
    return d


def snakemake(args: list[str], cwd: Path, timeout: float = RUN_TIMEOUT) -> subprocess.CompletedProcess:
    """Run snakemake in ``cwd``; stdout and stderr together in ``.stdout``."""
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=timeout,
    )


def job_stats(text: str) -> dict[str, int]:
    """The first 'Job stats' table of a snakemake output: rule -> count."""
    out: dict[str, int] = {}
    m = re.search(r"Job stats:\njob\s+count\n[- ]+\n((?:\S+\s+\d+\n)+)", text)
    if not m:
        return out
    for line in m.group(1).splitlines():
        name, n = line.split()
        if name != "total":
            out[name] = int(n)
    return out


def copy_workflow(dst: Path) -> Path:
    """Copy the Snakefile, workflow/ and config/ into ``dst``."""
    dst.mkdir(parents=True, exist_ok=True)
    shutil.copy2(ROOT / "Snakefile", dst / "Snakefile")
    shutil.copytree(ROOT / "workflow", dst / "workflow", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "config", dst / "config")
    return dst


def tiny_config(records: Path, select: list[str]) -> dict:
    """A complete configuration with tiny grids (tens of seconds)."""
    return {
        "records": {"dir": str(records), "select": select, "choose": "table1_pgv"},
        "processing": None,
        "isolation": {
            "rho": 0.5,
            "cases": [
                {"name": "none", "kind": "none"},
                {"name": "linear", "kind": "linear", "Tb_s": 3.0, "xi_b": 0.35},
                {"name": "fp", "kind": "fp", "mu_b": 0.11, "R_b_m": 2.24},
            ],
        },
        "search": {"amp_max_g": 3.0, "growth": 1.1, "rtol": 1e-2},
        "overturn": {"lambda": [4.0], "R_m": [1.0, 5.0], "cases": ["none", "linear", "fp"]},
        "maps": {
            "amplitude": "table1",
            "lambda_R": {"lambda": [2.0, 4.0, 6.0], "R_m": [1.0, 3.0, 9.0], "cases": ["none", "linear"]},
            "Tb_xi": {
                "Tb_s": [1.0, 2.0, 3.0],
                "xi_b": [0.1, 0.3],
                "rho": None,
                "blocks": [{"lambda": 4.0, "R_m": 6.0}],
            },
        },  # fmt: skip
        "pulses": {
            "enabled": True,
            "lambda": 4.0,
            "amp_max_g": 5.0,
            "shapes": {
                "rect": ["none"],
                "halfsine": ["none", "linear"],
                "fullsine": ["none", "linear", "fp"],
            },
            "vs_R": {"td_s": [0.5], "R_m": [1.0, 5.0]},
            "vs_omega": {"R_m": [3.0], "omega_p_rad_s": [2.0, 10.0]},
            "vs_isolation": {
                "shapes": ["fullsine"],
                "base_case": "linear",
                "R_m": [3.0],
                "td_fixed_s": 0.5,
                "td_s": [0.5],
                "R_fixed_m": 3.0,
                "Tb_s": [2.0, 3.0],
                "xi_b": [0.1, 0.35],
                "rho": [0.5],
            },
            "maps": {
                "amp_g": 0.5,
                "cases": ["none", "linear"],
                "excitations": [{"shape": "fullsine", "td_s": 0.5}],
            },
        },  # fmt: skip
        "resources": {"map_threads": 2},
    }


# ============================================================================================ configuration
@pytest.mark.parametrize("name", ["config.yaml", "ci.yaml", "paper.yaml"])
def test_shipped_configs_validate(name):
    cfg = pipeline.load_config(ROOT / "config" / name)
    assert {c["name"] for c in cfg["isolation"]["cases"]} >= {"none", "linear", "fp"}


def test_paper_config_has_the_paper_grids():
    cfg = pipeline.load_config(ROOT / "config" / "paper.yaml")
    lr = cfg["maps"]["lambda_R"]
    lam, R = pipeline.grid_values(lr["lambda"]), pipeline.grid_values(lr["R_m"])
    assert (len(lam), len(R)) == (100, 60)
    assert (lam[0], lam[-1], R[0], R[-1]) == (1.5, 8.0, 0.5, 15.0)
    cases = pipeline.isolation_cases(cfg)
    assert (cases["linear"].Tb_s, cases["linear"].xi_b, cases["linear"].rho) == (3.0, 0.35, 0.5)
    assert (cases["fp"].mu_b, cases["fp"].R_b_m) == (0.11, 2.24)
    assert cfg["pulses"]["maps"]["amp_g"] == 0.5
    assert (cfg["search"]["growth"], cfg["search"]["rtol"]) == (1.005, 1e-6)


@pytest.mark.parametrize("name", ["config.yaml", "ci.yaml", "paper.yaml"])
def test_shipped_configs_scan_no_coarser_than_the_paper(name):
    """The scan step is the uncertainty of every minimum overturning PGA: at most the paper's 0.5 %."""
    cfg = pipeline.load_config(ROOT / "config" / name)
    assert cfg["search"]["growth"] <= 1.005
    assert cfg["search"]["rtol"] <= 1e-4


def test_empty_config_gets_the_schema_defaults():
    cfg = pipeline.load_config({})
    assert cfg["isolation"]["rho"] == 0.5
    assert cfg["maps"]["lambda_R"]["lambda"] == {"start": 1.5, "stop": 8.0, "num": 100, "spacing": "linear"}
    assert cfg["records"]["dir"] is None


@pytest.mark.parametrize(
    "bad, match",
    [
        ({"search": {"growth": 0.9}}, "search.growth"),
        ({"records": {"colour": 1}}, "colour"),
        ({"overturn": {"cases": ["none", "nope"]}}, "unknown isolation case 'nope'"),
        ({"isolation": {"cases": [{"name": "a", "kind": "linear", "Tb_s": 2.0}]}}, "xi_b"),
    ],
)
def test_bad_config_is_one_line(bad, match):
    with pytest.raises(IsorockError, match=match) as e:
        pipeline.load_config(bad)
    assert "\n" not in str(e.value)


def test_isorock_report_bad_config_exits_2(tmp_path, capsys):
    from isorock.cli import main

    bad = tmp_path / "bad.yaml"
    bad.write_text("search: {growth: 0.5}\n")
    assert main(["report", "--configfile", str(bad), "--snakefile", str(ROOT / "Snakefile")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("isorock: error: configuration: search.growth")


@needs_snakemake
def test_isorock_report_commands():
    from isorock.cli import build_parser
    from isorock.cli import report as cli_report

    # the default configuration: the records of $ISOROCK_RECORDS, else the pyslammer samples (no ../shared)
    a = build_parser().parse_args(["report", "--cores", "3"])
    rc = cli_report.build(a)
    run, rep = rc.run_cmd(), rc.report_cmd()
    assert run[1:3] == ["-m", "snakemake"] and run[run.index("--cores") + 1] == "3"
    assert rep[-2:] == ["--report", str(Path("report.html").resolve())]
    # the run writes its report itself once its jobs are done: one Snakemake, one parse of the Snakefile
    both = rc.run_cmd(report=True)
    at = both.index("--report")
    assert both[at : at + 3] == ["--report", str(Path("report.html").resolve()), "--report-after-run"]
    assert "--report" not in rc.run_cmd() and "--report" not in rc.run_cmd(dry_run=True, report=True)
    assert str(rc.profile).endswith("workflow/profiles/default")


@needs_snakemake
def test_plain_snakemake_stops_on_a_mistyped_case_before_any_job(tmp_path):
    """The README's plain ``snakemake --configfile`` route uses the same validator as isorock report."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("overturn:\n  cases: [none, linaer]\n")
    res = snakemake(["-s", str(ROOT / "Snakefile"), "--cores", "1", "--configfile", str(bad)], cwd=tmp_path)
    assert res.returncode != 0
    errors = [ln for ln in res.stdout.splitlines() if "error" in ln.lower()]
    assert errors == [
        "isorock: error: configuration: overturn.cases: unknown isolation case 'linaer': valid none, linear, "
        "fp, linear_Tb2_xi0.2, linear_Tb3_xi0.2"
    ], res.stdout
    assert "Traceback" not in res.stdout and not (tmp_path / "results").exists()


# ============================================================================================ plan
def test_plan_finds_present_rows_and_warns_once_per_missing_row():
    d = need_records()
    cfg = pipeline.load_config({"records": {"dir": str(d)}})
    p = pipeline.plan(cfg)
    assert "IMV79-EMO" in p.ids and "NOR94-PKC" in p.ids
    assert "AIG95-AEGL" not in p.ids and "NOR94-SCG" not in p.ids  # absent; only a substitute
    for rid in ("AIG95-AEGL", "AIG95-AEGT", "BUC77-BRI", "PKF04-CH3W", "NOR94-SCG"):
        lines = [w for w in p.warnings if f"record {rid} " in w]
        assert len(lines) == 1 and "skipped" in lines[0], (rid, p.warnings)
    emo = p.spec("IMV79-EMO")
    assert emo.table1_pga_g == 0.38 and len(emo.files) == 2
    subs = pipeline.plan(pipeline.load_config({"records": {"dir": str(d), "use_substitutes": True}}))
    assert subs.spec("NOR94-SCG").files[0].substitute


def test_plan_without_records_directory_uses_the_samples(monkeypatch):
    pytest.importorskip("pyslammer")
    monkeypatch.delenv("ISOROCK_RECORDS", raising=False)
    p = pipeline.plan(pipeline.load_config({"records": {"dir": None, "max_records": 3}}))
    assert p.source == "pyslammer samples" and len(p.records) == 3
    assert all(r.files[0].format == "pyslammer-csv" for r in p.records)


def test_plan_missing_directory_is_an_error(tmp_path):
    with pytest.raises(IsorockError, match="does not exist"):
        pipeline.plan(pipeline.load_config({"records": {"dir": str(tmp_path / "nope")}}))


@pytest.mark.parametrize(
    ("n", "per_job", "sizes"),
    [(5, 2, [2, 2, 1]), (5, 4, [3, 2]), (17, 20, [17]), (17, 16, [9, 8]), (3, 1, [1, 1, 1]), (0, 4, [])],
)
def test_record_blocks_are_few_and_even(n, per_job, sizes):
    ids = [f"r{k}" for k in range(n)]
    blocks = pipeline.record_blocks(ids, per_job)
    assert [len(b) for b in blocks.values()] == sizes
    assert list(blocks) == [f"b{k}" for k in range(len(sizes))]
    assert [r for b in blocks.values() for r in b] == ids  # every record once, in its order


def test_records_per_job_is_validated():
    assert pipeline.load_config({})["resources"]["records_per_job"] == 20
    with pytest.raises(IsorockError, match="records_per_job"):
        pipeline.load_config({"resources": {"records_per_job": 0}})


# ============================================================================================ dry runs
@needs_snakemake
def test_dry_run_ci_lists_the_expected_jobs(tmp_path):
    d = need_records()
    # config/ci.yaml names ../shared/records relative to the working directory, here tmp_path: a second
    # configuration file merged over it names the records directory itself
    where = tmp_path / "records.yaml"
    where.write_text(yaml.safe_dump({"records": {"dir": str(d)}}))
    res = snakemake(
        [
            "-s",
            str(ROOT / "Snakefile"),
            "-d",
            str(tmp_path),
            "-n",
            "--configfile",
            str(ROOT / "config/ci.yaml"),
            str(where),
        ],
        cwd=ROOT,
        timeout=300,
    )
    assert res.returncode == 0, res.stdout[-3000:]
    cfg = pipeline.load_config(ROOT / "config" / "ci.yaml", where)
    ids = pipeline.plan(cfg).ids
    n = len(ids)
    assert n >= 4  # the Table 1 records of the shared directory
    r = cfg["resources"]
    batches = pipeline.process_batches(ids, r["records_per_job"], r["map_threads"])
    assert 1 < len(batches) < n  # records processed in batches, on every core
    expected = {
        # one process_record job per batch of records (each record's pulse too)
        **{f"process_record_{b}": 1 for b in batches}, "min_overturn": n, "regime_maps": n,
        "pulse_overturn": 3, "pulse_maps": len(cfg["pulses"]["maps"]["excitations"]),
        "merge": 1, "report_tables": 1, "figures": 1, "all": 1,
    }  # fmt: skip
    assert job_stats(res.stdout) == expected
    for rid in ("AIG95-AEGL", "BUC77-BRI", "NOR94-SCG"):  # absent rows: one warning line each
        assert len(re.findall(rf"isorock: warning: record {rid} .*skipped", res.stdout)) == 1
    assert not list(tmp_path.glob("results"))


# ============================================================================================ end to end
def _job_files(d: Path) -> dict[str, float]:
    jobs = d / "results" / "jobs"
    return {str(p.relative_to(d)): p.stat().st_mtime_ns for p in sorted(jobs.rglob("*.h5"))}


def _finished_outputs(log: str) -> set[str]:
    """Outputs of the jobs a snakemake log reports as finished."""
    outputs: dict[str, list[str]] = {}
    for block in re.split(r"\n(?=\[)", log):
        m_out = re.search(r"^\s+output: (.+)$", block, re.M)
        m_id = re.search(r"^\s+jobid: (\d+)$", block, re.M)
        if m_out and m_id:
            outputs[m_id.group(1)] = [o.strip() for o in m_out.group(1).split(",")]
    done = re.findall(r"Finished jobid: (\d+)", log)
    return {o for j in done for o in outputs.get(j, [])}


def _planned_outputs(log: str) -> set[str]:
    """Every output of the jobs listed in a snakemake log."""
    return {o.strip() for m in re.findall(r"^\s+output: (.+)$", log, re.M) for o in m.split(",")}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The workflow run once on two records, interrupted (Ctrl-C) after its first finished job, restarted."""
    if not _snakemake_available():
        pytest.skip("snakemake is not installed")
    d = need_records()
    wd = copy_workflow(tmp_path_factory.mktemp("wf"))
    (wd / "config" / "tiny.yaml").write_text(yaml.safe_dump(tiny_config(d, E2E_RECORDS)))
    args = ["--cores", "2", "--configfile", "config/tiny.yaml"]
    t0 = time.perf_counter()
    first = wd / "first.log"
    with open(first, "w") as log:
        proc = subprocess.Popen(
            [sys.executable, "-m", "snakemake", *args], cwd=wd, stdout=log, stderr=subprocess.STDOUT,
            start_new_session=True,
            # a shell's background job (`pytest &`) ignores SIGINT, and so would snakemake: undo that
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )  # fmt: skip
        try:
            while proc.poll() is None and time.perf_counter() - t0 < RUN_TIMEOUT:
                if "Finished jobid" in first.read_text():
                    break
                time.sleep(0.1)
            interrupted = proc.poll() is None
            if interrupted:
                os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: snakemake stops its jobs and unlocks
            proc.wait(timeout=120)
        finally:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
    finished = {f for f in _finished_outputs(first.read_text()) if f.startswith("results/jobs/")}
    before = {f: m for f, m in _job_files(wd).items() if f in finished}
    res = snakemake([*args, "--rerun-incomplete"], cwd=wd)
    (wd / "second.log").write_text(res.stdout)
    assert res.returncode == 0, res.stdout[-4000:]
    return {"dir": wd, "args": args, "before": before, "interrupted": interrupted, "second": res.stdout,
            "seconds": time.perf_counter() - t0}  # fmt: skip


@pytest.mark.e2e
def test_restart_does_not_redo_finished_jobs(run):
    wd = run["dir"]
    after = _job_files(wd)
    assert run["before"], "no job finished before the interruption"
    for f, mtime in run["before"].items():
        assert after[f] == mtime, f"{f} was recomputed after the restart"
        assert f not in _planned_outputs(run["second"]), f"{f} is an output of a job of the restart"
    if run["interrupted"]:
        assert sum(job_stats(run["second"]).values()) > 0
    # a killed job never leaves a file under a final name; temporary files are hidden dot-files
    assert all(p.name.startswith(".") for p in (wd / "results").rglob("*.tmp"))


@pytest.mark.filterwarnings("ignore::tables.NaturalNameWarning")  # reading /overturn/<record id> by key
@pytest.mark.e2e
def test_store_layout(run):
    wd = run["dir"]
    h5 = wd / "results" / "isorock.h5"
    assert h5.is_file()
    with h5py.File(h5, "r") as f:
        assert f.attrs["isorock_version"] and len(f.attrs["config_hash"]) == 64
        assert json.loads(f.attrs["config_json"])["search"]["growth"] == 1.1
        for key in ("pulses/overturn_R", "summary/overturn", "overturn/TAB78-TAB"):
            assert f[key].attrs["isorock_version"] and json.loads(f[key].attrs["units"])["R_m"] == "m"
        assert f["pulses/overturn_R"].attrs["config_hash"] == f.attrs["config_hash"]
        assert json.loads(f["overturn/TAB78-TAB"].attrs["search"])["growth"] == 1.1
        assert sorted(f["records"]) == sorted(E2E_RECORDS)
        for rid in E2E_RECORDS:
            g = f["records"][rid]
            assert g["acc"].attrs["units"] == "m/s^2" and g["acc"].attrs["dt_s"] > 0
            assert g["acc"].shape == (int(g.attrs["npts"]),)
            assert len(g["processing"]) >= 5
            for k in ("pga_g", "pgv_m_s", "Tp_s", "dt_s", "record_sha256", "config_hash", "isorock_version"):
                assert k in g.attrs, k
            assert 0.1 < g.attrs["Tp_s"] < 15
            assert g.attrs["record_sha256"] == file_sha256(g.attrs["source_file"])
            assert g["pulse/velocity"].attrs["units"] == "m/s"
        cands = json.loads(f["records/NOR94-RRS"].attrs["candidates"])
        assert len(cands) == 2 and sum(c["chosen"] for c in cands) == 1
        # maps: axes, codes 0/1/2, fixed parameters
        for rid in E2E_RECORDS:
            for name in ("lambda_R-none", "lambda_R-linear", "Tb_xi-lam4-R6"):
                m = f[f"maps/{rid}/{name}"]
                assert set(np.unique(m["codes"][()])) <= {0, 1, 2}
                assert m.attrs["source"] == rid and m.attrs["amp_source"] == "table1"
            assert f[f"maps/{rid}/lambda_R-none"]["codes"].shape == (3, 3)
            assert f[f"maps/{rid}/Tb_xi-lam4-R6"]["codes"].shape == (3, 2)
        assert f["maps/TAB78-TAB/lambda_R-none"].attrs["amp_g"] == pytest.approx(0.85)
        assert f["maps/pulse-fullsine-td0.5/lambda_R-linear"].attrs["fixed_Tb_s"] == 3.0
    # tables: plain pandas
    ov = pd.read_hdf(h5, "overturn/TAB78-TAB")
    assert len(ov) == 2 * 3 and set(ov["case"]) == {"none", "linear", "fp"}
    none = ov[ov["case"] == "none"]
    assert np.allclose(none["uplift_g"], 0.25)  # tan(alpha) of lambda = 4
    assert (ov["min_overturn_g"].dropna() > ov["uplift_g"][ov["min_overturn_g"].notna()]).all()
    summ = pd.read_hdf(h5, "summary/overturn")
    assert sorted(summ["record"].unique()) == sorted(E2E_RECORDS)
    recs = pd.read_hdf(h5, "summary/records")
    assert set(recs["record"]) == set(E2E_RECORDS) and recs["Tp_s"].notna().all()
    maps = pd.read_hdf(h5, "summary/maps")
    assert len(maps) == 2 * 3 + 2
    assert (maps["no_uplift"] + maps["rocking"] + maps["overturn"] == maps["nx"] * maps["ny"]).all()
    for key, n in (("pulses/overturn_R", 1 + 2 + 3), ("pulses/overturn_omega", 1 + 2 + 3)):
        assert len(pd.read_hdf(h5, key)) == 2 * n  # (cases of the three shapes) x 2 abscissae
    iso = pd.read_hdf(h5, "pulses/overturn_isolation")
    assert set(iso["param"]) == {"none", "Tb_s", "xi_b", "rho"}


@pytest.mark.e2e
def test_store_reads_without_warnings(run):
    """What was seen: NaturalNameWarning for the column lambda on every read of /summary/*, and
    DataTypeWarning for boolean attributes (qa_passed) with pd.HDFStore."""
    import warnings

    h5 = run["dir"] / "results" / "isorock.h5"
    keys = ("summary/records", "summary/overturn", "summary/maps", "pulses/overturn_R", "pulses/restitution")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for key in keys:
            assert len(pd.read_hdf(h5, key))
        with pd.HDFStore(h5, mode="r") as store:
            for key in keys:
                assert "lambda" not in store[key].columns
            assert "lambda_" in store["summary/overturn"].columns
    with h5py.File(h5, "r") as f:
        assert f["records/TAB78-TAB"].attrs["qa_passed"] in (0, 1)  # an integer, not an HDF5 boolean
        assert f.attrs["config_name"] == "tiny"
    assert len(pd.read_hdf(h5, "pulses/restitution")) > 10


@pytest.mark.e2e
def test_figures_and_report_tables(run):
    wd = run["dir"]
    pages = wd / "results" / "report"
    for name in ("records.html", "overturn.html", "maps.html", "records/TAB78-TAB.html"):
        assert (pages / name).stat().st_size > 500
    assert "Minimum overturning PGA" in (pages / "overturn.html").read_text()
    assert list((wd / "results" / "figures").glob("*.png"))
    # a record's page shows its figures from results/figures (issue 35, item 1)
    rec_page = pages / "records" / "TAB78-TAB.html"
    srcs = re.findall(r'<img src="([^"]+)"', rec_page.read_text())
    assert srcs and all((rec_page.parent / s).resolve().is_file() for s in srcs)
    # where the physics departs from the paper's conclusions, with the cases and this run's evidence
    paper = (pages / "paper.html").read_text()
    assert "regardless of block size and excitation period" in paper and "0.636 g tan(alpha)" in paper
    assert "0.243 g" in paper and "record-block pairs overturn at a lower PGA" in paper


@pytest.mark.e2e
def test_second_run_has_nothing_to_do(run):
    res = snakemake(run["args"], cwd=run["dir"], timeout=300)
    assert res.returncode == 0
    assert "Nothing to be done" in res.stdout


@pytest.mark.e2e
def test_report(run):
    wd = run["dir"]
    res = snakemake(["--configfile", "config/tiny.yaml", "--report", "report.html"], cwd=wd, timeout=300)
    assert res.returncode == 0, res.stdout[-3000:]
    html = (wd / "report.html").read_text()
    assert len(html) > 100_000 and "Minimum overturning PGA" in html and "TAB78-TAB" in html


@pytest.mark.e2e
def test_isorock_report_no_run(run, capsys):
    from isorock.cli import main

    wd = run["dir"]
    out = wd / "r2.html"
    rc = main(["report", "--no-run", "--snakefile", str(wd / "Snakefile"), "--directory", str(wd),
               "--configfile", str(wd / "config/tiny.yaml"), "--report", str(out)])  # fmt: skip
    assert rc == 0 and out.stat().st_size > 100_000
    assert "report written to" in capsys.readouterr().out


@pytest.mark.e2e
def test_deleted_final_output_reruns_only_the_jobs_after_it(run):
    wd = run["dir"]
    target = wd / "results" / "isorock.h5"
    target.unlink()
    before = _job_files(wd)
    res = snakemake(run["args"], cwd=wd)
    assert res.returncode == 0, res.stdout[-3000:]
    expected = {"merge": 1, "report_tables": 1, "figures": 1, "all": 1}
    assert job_stats(res.stdout) == expected
    assert target.is_file()
    assert _job_files(wd) == before  # no record or pulse job ran again
