"""The workflow runner as a Python API (:mod:`isorock.control.run`), without the command line."""

from __future__ import annotations

from pathlib import Path

import pytest

from isorock.errors import ConfigError, IsorockError
from isorock.pipeline import RunResult, RunSettings, prepare_run, run_workflow
from support.records import ROOT, own_records

pytest.importorskip("snakemake")


def _records(tmp_path: Path) -> Path:
    return own_records(tmp_path, 800)


def test_prepare_run_checks_and_builds_the_commands(tmp_path):
    mine = _records(tmp_path)
    s = prepare_run(ROOT / "config" / "ci.yaml", records=mine, cores=3, directory=tmp_path, notify=print)
    assert isinstance(s, RunSettings)
    assert s.config["records"]["dir"] == str(mine.resolve())
    assert s.report == (tmp_path / "report-ci.html").resolve()
    assert s.store == tmp_path.resolve() / "results" / "isorock.h5"
    run, rep = s.run_cmd(), s.report_cmd()
    assert run[1:3] == ["-m", "snakemake"] and run[run.index("--cores") + 1] == "3"
    assert rep[-2:] == ["--report", str(s.report)] and "--workflow-profile" not in rep
    assert s.run_cmd(dry_run=True)[-1] == "-n"


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"cores": 0}, IsorockError, "--cores 0"),
        ({"profile": "nope"}, IsorockError, "no such profile"),
        ({"records": "/nonexistent/records"}, IsorockError, "no such directory"),
        ({"configfile": "/nonexistent/config.yaml"}, IsorockError, "no such configuration file"),
    ],
)
def test_bad_settings_raise_before_any_job(tmp_path, kwargs, error, words):
    kwargs = {"records": _records(tmp_path), **kwargs}
    with pytest.raises(error, match=words):
        run_workflow(directory=tmp_path, **kwargs)
    assert not (tmp_path / "results").exists() and not (tmp_path / ".snakemake").exists()


def test_bad_configuration_raises_config_error(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("search: {growth: 0.5}\n")
    with pytest.raises(ConfigError, match="search.growth"):
        run_workflow(bad, records=_records(tmp_path), directory=tmp_path)


def test_run_workflow_dry_run(tmp_path, capfd):
    """``run_workflow(dry_run=True)``: snakemake -n lists the jobs of the run, writes no result."""
    mine = _records(tmp_path)
    lines: list[str] = []
    res = run_workflow(
        ROOT / "config" / "ci.yaml",
        records=mine,
        cores=1,
        directory=tmp_path,
        dry_run=True,
        notify=lines.append,
    )
    assert isinstance(res, RunResult) and res.dry_run and res.report is None
    assert res.store == tmp_path.resolve() / "results" / "isorock.h5" and not res.store.exists()
    assert res.settings.config["records"]["dir"] == str(mine.resolve())
    out = capfd.readouterr().out
    assert "merge" in out and "Q1" in out  # the jobs, with the record's own
    assert not (tmp_path / "report-ci.html").exists()


def test_engine_is_compiled_before_local_jobs_only(tmp_path) -> None:
    """isorock report compiles the engine once, itself, when the jobs run on this machine; a cluster
    profile leaves it to the jobs (their nodes may differ from the login node)."""
    from isorock.control.run import runs_here

    root = Path(__file__).resolve().parents[2]
    assert runs_here(root / "workflow/profiles/default")
    assert not runs_here(root / "workflow/profiles/slurm")
    assert runs_here(None)
    own = tmp_path / "mine"
    own.mkdir()
    (own / "config.yaml").write_text("executor: cluster-generic\ncores: 4\n")
    assert not runs_here(own)
    (own / "config.yaml").write_text("cores: 4\n")
    assert runs_here(own)
