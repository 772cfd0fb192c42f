"""Checks without holes (issue 23, item 4): one validator for the configuration, with the bounds of the
command line (:mod:`isorock.plausibility`), messages naming the key and what it must be, a processing
file checked as a processing file, and the cost of a run estimated and limited before any job.

Each case goes through :func:`isorock.pipeline.load_config` (the validator), and the review's cases
also through ``isorock report --dry-run`` on a small configuration file (exit 2, one line, no job).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from isorock.cli import main
from isorock.errors import ConfigError, IsorockError
from isorock.pipeline import load_config, prepare_run
from isorock.processing.config import load_config as load_processing
from support.records import ROOT, own_records

HUGE = {"start": 1.5, "stop": 8.0, "num": 100000}
OBJECT = {"name": "s", "height_m": 1.8, "width_m": 0.6, "friction": 0.5}


def _assessment(**obj) -> dict:
    return {"studies": [], "assessment": {"objects": [{**OBJECT, **obj}], "cases": ["none"],
                                          "stripes_g": [0.1, 0.2]}}  # fmt: skip


# ------------------------------------------------------------------ the validator, one line each
@pytest.mark.parametrize(
    "bad, words",
    [
        # numbers that are not finite: jsonschema's bounds let NaN through; the key is named
        ({"isolation": {"rho": float("nan")}}, "configuration: isolation.rho: .nan is not a finite number"),
        ({"search": {"amp_max_g": float("inf")}}, "search.amp_max_g: .inf is not a finite number"),
        ({"isolation": {"cases": [{"name": "l", "kind": "linear", "Tb_s": 3.0, "xi_b": 0.2,
                                   "rho": float("nan")}]}},
         "configuration: isolation.cases.0.rho: .nan is not a finite number"),
        ({"maps": {"lambda_R": {"R_m": [1.0, float("-inf")]}}}, "maps.lambda_R.R_m.1: -.inf is not a finite"),
        # a oneOf (grid, amplitude, case reference): the key inside and what it must be
        ({"maps": {"lambda_R": {"lambda": {"start": 1, "stop": 2, "num": 0}}}},
         "configuration: maps.lambda_R.lambda.num: 0 is out of range: must be >= 1"),
        ({"maps": {"lambda_R": {"lambda": []}}},
         "maps.lambda_R.lambda: [] has 0 item(s): must have at least 1; or a mapping with start, stop, num"),
        ({"maps": {"lambda_R": {"lambda": "abc"}}},
         "maps.lambda_R.lambda: 'abc' is not valid: must be a list of numbers, or {start, stop, num}"),
        ({"maps": {"amplitude": "x"}}, "maps.amplitude: 'x' is not one of table1, record; or a number > 0"),
        ({"overturn": {"cases": [{"case": "none", "recs": []}]}},
         "overturn.cases.0: unknown key 'recs': valid case, records; or a string"),
        # the bounds of the command line
        ({"isolation": {"rho": 50}}, "isolation.rho: rho 50 is out of range: the block-to-base mass ratio"),
        ({"isolation": {"cases": [{"name": "f", "kind": "fp", "mu_b": 1.5, "R_b_m": 2.0}]}, "studies": []},
         "isolation.cases.0 (f): mu_b 1.5 is above 0.3"),
        ({"isolation": {"cases": [{"name": "f", "kind": "fp", "mu_b": 0, "R_b_m": 2.0}]}, "studies": []},
         "isolation.cases.0 (f): mu_b 0 must be > 0 and <= 0.3"),
        ({"isolation": {"cases": [{"name": "f", "kind": "fp", "mu_b": 0.1, "R_b_m": 224}]}, "studies": []},
         "R_b_m 224 gives a pendulum period 2 pi sqrt(R_b/g) of 30 s, outside 0.05 to 20 s"),
        ({"isolation": {"cases": [{"name": "l", "kind": "linear", "Tb_s": 30, "xi_b": 0.2}]}, "studies": []},
         "isolation.cases.0 (l): Tb_s 30 is outside 0.05 to 20 s"),
        ({"maps": {"Tb_xi": {"Tb_s": {"start": 0.01, "stop": 5.0, "num": 10}}}},
         "maps.Tb_xi.Tb_s: Tb_s 0.01 is outside 0.05 to 20 s"),
        ({"maps": {"Tb_xi": {"xi_b": [0.1, 35]}}}, "maps.Tb_xi.xi_b: xi_b 35 is out of range: a damping"),
        ({"pulses": {"vs_R": {"td_s": [0.5, 1e9]}}}, "pulses.vs_R.td_s: td_s 1e+09 is outside 0.05 to 20 s"),
        ({"pulses": {"vs_isolation": {"td_fixed_s": 500}}},
         "td_fixed_s 500 is outside 0.05 to 20 s: a pulse's duration or period must be within them"),
        ({"pulses": {"maps": {"excitations": [{"shape": "rect", "td_s": 0.001}]}}},
         "pulses.maps.excitations.0: td_s 0.001 is outside 0.05 to 20 s"),
        ({"pulses": {"vs_omega": {"omega_p_rad_s": [2.0, 100.0]}}},
         "pulses.vs_omega.omega_p_rad_s: omega_p_rad_s 100 is outside 0.157 to 62.8 rad/s"),
        ({"pulse": {"tp_max_s": 60}}, "pulse.tp_max_s: tp_max_s 60 is outside 0.05 to 20 s"),
        ({"pulse": {"tp_min_s": 5, "tp_max_s": 2}}, "pulse: tp_min_s 5 must be below tp_max_s 2"),
        ({"overturn": {"R_m": [-1.0, 2.0]}}, "overturn.R_m: R_m -1 is outside (0, 100] m"),
        ({"overturn": {"R_m": [1.0, 1e12]}}, "overturn.R_m: R_m 1e+12 is outside (0, 100] m"),
        ({"overturn": {"lambda": [0.0, 4.0]}}, "overturn.lambda: lambda 0 must be > 0"),
        ({"search": {"amp_max_g": 1e9}}, "search.amp_max_g: amp_max_g 1e+09 is outside (0, 50] g"),
        ({"pulses": {"amp_max_g": 60.0}}, "pulses.amp_max_g: amp_max_g 60 is outside (0, 50] g"),
        ({"overturn": {"R_m": {"start": 0, "stop": 5, "num": 3, "spacing": "log"}}},
         "overturn.R_m: a log grid needs start and stop > 0"),
        (_assessment(friction=1.5), "assessment.objects.0 (s): friction 1.5 is above 1"),
        ({**_assessment(), "assessment": {**_assessment()["assessment"], "design_g": [0.15],
                                          "mce_g": [0.2],
                                          "design_grid": {"kind": "linear", "Tb_s": [2.0, 40.0],
                                                          "xi_b": [0.1]}}},
         "assessment.design_grid.Tb_s: Tb_s 40 is outside 0.05 to 20 s"),
    ],
)  # fmt: skip
def test_a_hole_is_closed_with_one_line_naming_the_key(bad, words):
    with pytest.raises(ConfigError) as e:
        load_config(bad)
    msg = str(e.value)
    assert words in msg, msg
    assert "\n" not in msg and "is not valid under any of the given schemas" not in msg


@pytest.mark.parametrize(
    "good",
    [
        {"pulses": {"vs_R": {"td_s": [0.05, 20.0]}}},  # the bounds themselves
        {"isolation": {"rho": 10.0}},
        {"isolation": {"cases": [{"name": "f", "kind": "fp", "mu_b": 0.3, "R_b_m": 2.0}]}, "studies": []},
        {"maps": {"lambda_R": {"lambda": HUGE, "R_m": HUGE}}},  # a huge grid is the cost check's, not made
    ],
)
def test_values_within_the_bounds_pass(good):
    load_config(good)


def test_the_command_line_and_the_configuration_say_the_same(capsys):
    """One set of bounds: ``--Tb 30`` and ``Tb_s: 30`` are refused with the same words."""
    argv = ["simulate", "--lambda", "4", "--R", "1", "--isolation", "linear", "--Tb", "30", "--xi", "0.2",
            "--rho", "0.5", "--pulse", "rect", "--td", "1", "--pga", "1"]  # fmt: skip
    assert main(argv) == 2
    cli = capsys.readouterr().err
    with pytest.raises(ConfigError) as e:
        load_config({"isolation": {"cases": [{"name": "l", "kind": "linear", "Tb_s": 30, "xi_b": 0.2}]}})
    tail = "30 is outside 0.05 to 20 s: an isolator's period must be within them (isolators: 1.5 to 6 s)"
    assert f"--Tb {tail}" in cli and f"Tb_s {tail}" in str(e.value)


# ------------------------------------------------------------------ a processing file
@pytest.fixture
def not_processing(tmp_path) -> dict[str, Path]:
    files = {
        "binary": tmp_path / "bin.dat",
        "empty": tmp_path / "empty.yaml",
        "no 'processing' list": tmp_path / "workflow.yaml",
        "not valid YAML": tmp_path / "notes.md",
        "'processing' is not a list of steps": tmp_path / "nulls.yaml",
    }
    files["binary"].write_bytes(bytes(range(256)) * 4)
    files["empty"].write_text("")
    files["no 'processing' list"].write_text("isolation:\n  rho: 0.5\n")
    files["not valid YAML"].write_text("key: value: other\n")
    files["'processing' is not a list of steps"].write_text("processing: null\n")
    if Path("/etc/passwd").is_file():
        files["no 'processing' list "] = Path("/etc/passwd")  # text of 'name:x:0:0:...' lines
    return files


def test_a_file_that_is_no_processing_file_is_refused_naming_it(not_processing):
    for why, f in not_processing.items():
        with pytest.raises(IsorockError) as e:
            load_processing(f)
        msg = str(e.value)
        assert msg.startswith(f"{f}: not a processing file ({why.strip()}"), msg
        assert "a processing file is YAML text with a 'processing' list of steps" in msg and "\n" not in msg
    assert len(load_processing(ROOT / "src" / "isorock" / "processing" / "processing.yaml").steps) > 3


# ------------------------------------------------------------------ isorock report --dry-run
def _records(tmp_path: Path) -> Path:
    return own_records(tmp_path, 600)


def _report(tmp_path: Path, cfg: dict | str, capsys, *extra: str) -> tuple[int, list[str]]:
    """``isorock report --configfile F --records R --directory tmp --dry-run``: exit code, stderr lines."""
    f = tmp_path / "mine.yaml"
    text = cfg if isinstance(cfg, str) else yaml.safe_dump(cfg)
    f.write_text(text + ("" if "records:" in text else "records: {include: [added]}\n"))  # the one record
    argv = ["report", "--configfile", str(f), "--records", str(_records(tmp_path)), "--directory",
            str(tmp_path), "--dry-run", *extra]  # fmt: skip
    rc = main(argv)
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    return rc, err


@pytest.mark.parametrize(
    "text, words",
    [
        ("isolation:\n  rho: .nan\n", "configuration: isolation.rho: .nan is not a finite number"),
        ("search:\n  amp_max_g: .inf\n", "configuration: search.amp_max_g: .inf is not a finite number"),
        ("maps:\n  lambda_R:\n    lambda: {start: 1, stop: 8, num: 0}\n",
         "configuration: maps.lambda_R.lambda.num: 0 is out of range: must be >= 1"),
        ("isolation:\n  cases:\n    - {name: f, kind: fp, mu_b: 1.5, R_b_m: 2.0}\nstudies: []\n",
         "mu_b 1.5 is above 0.3"),
        (yaml.safe_dump(_assessment(friction=1.5)), "friction 1.5 is above 1: no floor grips an object"),
    ],
)  # fmt: skip
def test_report_dry_run_refuses_a_bad_configuration(tmp_path, capsys, text, words):
    rc, err = _report(tmp_path, text, capsys)
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith("isorock: error: ") and words in err[0], err
    assert not (tmp_path / ".snakemake").exists() and not (tmp_path / "results").exists()


def test_report_dry_run_refuses_a_system_file_as_processing_file(tmp_path, capsys):
    pytest.importorskip("snakemake")
    binary = tmp_path / "steps.bin"
    binary.write_bytes(b"\x7fELF\x00\x01" * 100)
    for path, why in ((Path("/etc/passwd"), "no 'processing' list"), (binary, "binary")):
        if not path.is_file():
            continue
        rc, err = _report(tmp_path, f"processing: {path}\n", capsys)
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(
            f"isorock: error: configuration: processing: {path}: not a processing file ({why})"
        )
        assert "a processing file is YAML text with a 'processing' list of steps" in err[0]
        assert not (tmp_path / ".snakemake").exists()


def test_report_dry_run_refuses_a_huge_grid_unless_forced(tmp_path, capsys):
    pytest.importorskip("snakemake")
    cfg = {"studies": ["maps"], "maps": {"lambda_R": {"lambda": HUGE, "R_m": HUGE}}}
    rc, err = _report(tmp_path, cfg, capsys)
    assert rc == 2 and len(err) == 1, err
    assert re.match(r"isorock: error: cost estimate: [\d,]{14,} analyses \(maps [\d,]{14,}\)", err[0]), err
    assert "on 1 record(s)" in err[0] and "rerun with --force to run it anyway" in err[0]
    assert not (tmp_path / ".snakemake").exists()
    # with --force it goes on (here to the commands, which run nothing), the estimate said on stderr
    rc, err = _report(tmp_path, cfg, capsys, "--force", "--print-commands")
    assert rc == 0 and any(ln.startswith("isorock: cost estimate: ") for ln in err), err


def test_assess_takes_force_too(tmp_path, capsys):
    pytest.importorskip("snakemake")
    a = _assessment()["assessment"]
    grid = {"kind": "linear", "Tb_s": {"start": 1.0, "stop": 5.0, "num": 100000},
            "xi_b": {"start": 0.05, "stop": 0.5, "num": 1000}}  # fmt: skip
    a.update(design_g=[0.15], mce_g=[0.225], design_grid=grid)
    f = tmp_path / "big.yaml"
    f.write_text(yaml.safe_dump({"records": {"include": ["added"]}, "studies": [], "assessment": a}))
    mine = _records(tmp_path)
    argv = ["assess", str(f), "--records", str(mine), "--directory", str(tmp_path), "--print-commands"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    # 1 object x 1 record x 4 levels (0.1, 0.15, 0.2 and the MCE 0.225 g) x 100000 x 1000 isolators
    assert len(err) == 1 and "cost estimate: 400,000," in err[0] and "(assessment 400,000," in err[0], err
    assert "rerun with --force to run it anyway" in err[0]
    assert main([*argv, "--force"]) == 0


def test_prepare_run_notifies_the_estimate_and_takes_force(tmp_path):
    pytest.importorskip("snakemake")
    mine = _records(tmp_path)
    lines: list[str] = []
    s = prepare_run(
        ROOT / "config" / "ci.yaml", records=mine, cores=3, directory=tmp_path, notify=lines.append
    )
    est = [ln for ln in lines if "cost estimate" in ln]
    assert len(est) == 1 and est[0].startswith("isorock: cost estimate: ") and "(overturn " in est[0]
    from isorock.control.plan import plan

    assert f"on {len(plan(s.config, basedir=tmp_path).records)} record(s)" in est[0]
    assert "on 3 core(s)" in est[0] and s.cores == 3
    big = tmp_path / "big.yaml"
    big.write_text(yaml.safe_dump({"search": {"growth": 1.0000001, "rtol": 1e-9}}))
    with pytest.raises(IsorockError, match="rerun with --force to run it anyway"):
        prepare_run(big, records=mine, directory=tmp_path, notify=lines.append)
    assert prepare_run(big, records=mine, directory=tmp_path, notify=lines.append, force=True).config
