"""The user's own records in the workflow: added records run beside the others, a run with no record
stops at once, ``isorock report --records`` wins over the configuration, and reports are named after
their configuration."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from isorock.cli import build_parser, main
from isorock.control import run as runner
from isorock.errors import ConfigError, IsorockError
from isorock.pipeline import load_config, plan
from isorock.records.adding import add_records
from support.records import ROOT, need_records


def _record(path, amp=0.3, n=800, dt=0.01):
    t = np.arange(n) * dt
    np.savetxt(path, amp * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.4 * t) * np.minimum(t, 1.0))
    return path


def test_added_records_run_with_the_catalog_rows(tmp_path):
    d = need_records()
    mine = tmp_path / "mine"
    # a Table 1 file of the shared directory registered as its row, and one record of the user's own
    add_records([d / "SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt"], mine, table1_id="TAB78-TAB",
                format="one-column", dt=0.02, units="g")  # fmt: skip
    add_records(
        [_record(tmp_path / "quake.txt")], mine, ids=["MY-QUAKE"], dt=0.01, units="g", event="My quake"
    )
    p = plan(load_config({"records": {"dir": str(mine)}}))
    assert p.ids == ["TAB78-TAB", "MY-QUAKE"]
    tab, own = p.spec("TAB78-TAB"), p.spec("MY-QUAKE")
    assert tab.table1_pga_g == 0.85 and tab.catalog_id == "TAB78-TAB"
    # a record that is not a Table 1 row carries no Table 1 fields, and its label no doubled date
    assert own.catalog_id == "" and own.table1_pga_g is None and own.table1_tp_s is None
    assert own.label == "My quake, quake" and own.files[0].units == "g" and own.files[0].dt_s == 0.01


def test_a_run_without_records_stops_with_one_line(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ConfigError, match="no records to run") as info:
        plan(load_config({"records": {"dir": str(empty)}}))
    assert "isorock records add" in str(info.value) and "\n" not in str(info.value)
    mine = tmp_path / "mine"
    add_records([_record(tmp_path / "q.txt")], mine, dt=0.01, units="g")
    with pytest.raises(ConfigError, match="records.select"):
        plan(load_config({"records": {"dir": str(mine), "select": ["NOPE"]}}))


def test_report_records_option_wins_over_the_configuration(tmp_path, capsys):
    """What was seen: --records DIR with config/ci.yaml silently used ../shared/records."""
    pytest.importorskip("snakemake")
    mine = tmp_path / "mine"
    add_records([_record(tmp_path / "q.txt")], mine, ids=["Q1"], dt=0.01, units="g")
    argv = ["report", "--configfile", str(ROOT / "config" / "ci.yaml"), "--records", str(mine),
            "--directory", str(tmp_path), "--print-commands"]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f'records={{"dir": "{mine.resolve()}"}}' in out
    a = build_parser().parse_args(argv)
    from isorock.cli import report as cli_report

    rc = cli_report.build(a)
    assert rc.config["records"]["dir"] == str(mine.resolve())
    ids = plan(rc.config, basedir=tmp_path).ids
    assert ids[-1] == "Q1"  # the user's record, with the records already there (the samples, if any)
    assert rc.report == (tmp_path / "report-ci.html").resolve()  # named after its configuration


def test_report_names_and_the_note_on_replaced_results(tmp_path):
    assert runner.default_report_name(None) == "report.html"
    assert runner.default_report_name("config/config.yaml") == "report.html"
    assert runner.default_report_name("studies/museum.yaml") == "report-museum.html"
    store = tmp_path / "results" / "isorock.h5"
    store.parent.mkdir()
    with h5py.File(store, "w") as f:
        f.attrs["config_hash"] = "0" * 64
        f.attrs["config_name"] = "ci"
    rc = runner.RunSettings(
        snakefile=ROOT / "Snakefile", directory=tmp_path, configfile=tmp_path / "museum.yaml",
        report=tmp_path / "report-museum.html", config=load_config({}),
    )  # fmt: skip
    note = runner.previous_results(rc)
    assert note.endswith("holds the results of configuration 'ci', not of this one")
    said: list[str] = []
    assert runner.stale_store(rc, said.append) and not store.exists()  # never trusted: removed
    assert len(said) == 1 and "museum.yaml" in said[0] and "merges it again" in said[0]
    assert not runner.stale_store(rc, said.append)  # nothing left to remove


def _settings(tmp_path, name):
    return runner.RunSettings(
        snakefile=ROOT / "Snakefile", directory=tmp_path, configfile=tmp_path / f"{name}.yaml",
        report=tmp_path / runner.default_report_name(f"{name}.yaml"), config=load_config({}),
    )  # fmt: skip


def test_another_configuration_keeps_the_results_of_the_first_apart(tmp_path):
    """A run of cabinet.yaml where results/ holds statue.yaml's moves them, pages and all, to
    results-statue/ (saying so in one line); the next run of statue.yaml brings them back."""
    results = tmp_path / "results"
    (results / "report").mkdir(parents=True)
    (results / "report" / "records.html").write_text("statue's page")
    with h5py.File(results / "isorock.h5", "w") as f:  # an isorock that wrote no configuration.txt
        f.attrs["config_name"] = "statue"
    meta = tmp_path / ".snakemake" / "metadata"  # Snakemake's records of those outputs go with them
    meta.mkdir(parents=True)
    (meta / "cmVzdWx0cy9pc29yb2NrLmg1").write_text("statue's")
    said: list[str] = []
    runner.keep_apart(_settings(tmp_path, "cabinet"), said.append)
    kept = tmp_path / "results-statue"
    assert (kept / ".snakemake" / "metadata" / "cmVzdWx0cy9pc29yb2NrLmg1").read_text() == "statue's"
    assert not meta.exists()
    assert (kept / "report" / "records.html").read_text() == "statue's page"
    assert (kept / "isorock.h5").is_file() and not (results / "isorock.h5").exists()
    assert (results / runner.OWNER_FILE).read_text().strip() == "cabinet"
    assert len(said) == 1 and "'statue' (report-statue.html): kept in" in said[0], said
    (results / "isorock.h5").write_text("cabinet's store")
    meta.mkdir()
    (meta / "cmVzdWx0cy9pc29yb2NrLmg1").write_text("cabinet's")
    said.clear()
    runner.keep_apart(_settings(tmp_path, "statue"), said.append)  # back: its finished jobs are kept
    assert (meta / "cmVzdWx0cy9pc29yb2NrLmg1").read_text() == "statue's"
    assert not (results / ".snakemake").exists()
    assert (tmp_path / "results-cabinet" / ".snakemake" / "metadata" / "cmVzdWx0cy9pc29yb2NrLmg1").is_file()
    assert (results / "report" / "records.html").read_text() == "statue's page"
    assert (tmp_path / "results-cabinet" / "isorock.h5").read_text() == "cabinet's store"
    assert not kept.exists() and runner.results_owner(tmp_path) == "statue"
    assert len(said) == 2 and "is back in" in said[1], said
    said.clear()
    runner.keep_apart(_settings(tmp_path, "statue"), said.append)  # the same one again: nothing moves
    assert said == [] and (tmp_path / "results-cabinet").is_dir()
    # the default configuration's results are kept as results-config/ (its report: report.html)
    runner.keep_apart(_settings(tmp_path, "config"), said.append)
    assert "'statue' (report-statue.html)" in said[0] and runner.results_owner(tmp_path) == "config"
    runner.keep_apart(_settings(tmp_path, "cabinet"), said.append)
    assert "'config' (report.html): kept in" in said[1] and (tmp_path / "results-config").is_dir()


def test_a_report_without_a_run_of_a_configuration_with_no_results_is_refused(tmp_path):
    """``isorock report --no-run`` of a configuration that never ran where results/ holds another's:
    one line, no report of the other one's numbers under this one's name."""
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / runner.OWNER_FILE).write_text("statue\n")
    (tmp_path / "results" / "isorock.h5").write_text("statue's store")
    s = _settings(tmp_path, "cabinet")
    with pytest.raises(IsorockError, match="no results of 'cabinet' here: run the workflow first"):
        s.execute(run_jobs=False, notify=lambda line: None)
    assert not s.report.exists() and (tmp_path / "results-statue" / "isorock.h5").is_file()


def test_records_dir_of_the_report_must_exist(tmp_path, capsys):
    assert main(["report", "--records", str(tmp_path / "none"), "--print-commands"]) == 2
    assert "no such directory" in capsys.readouterr().err
