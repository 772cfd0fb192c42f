"""A wheel installed anywhere works: built from the repository, installed (not editable) in a fresh
virtual environment, and run from an empty folder outside the repository.

The new environment sees the test environment's packages through a ``.pth`` file (so nothing is
downloaded), but not its editable isorock: ``import isorock`` there must load the wheel, and the
workflow, its configurations and the Table 1 catalog must come from inside the wheel.
"""

from __future__ import annotations

import json
import os
import site
import subprocess
import sys
from pathlib import Path

import h5py
import pytest
import yaml

from support.records import ROOT

TIMEOUT = 900


def _run(cmd: list[str], cwd: Path, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    res = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    assert res.returncode == 0, f"{cmd}\n{res.stdout[-3000:]}\n{res.stderr[-3000:]}"
    return res


def _write_at2(path: Path) -> None:
    """A small PEER NGA-West2 AT2 file: 20 s of a decaying 2 Hz sine, 0.01 s, in g."""
    import numpy as np

    t = np.arange(2001) * 0.01
    acc = 0.3 * np.sin(2 * np.pi * 2.0 * t) * np.exp(-0.2 * t) * np.minimum(t, 1.0)
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Synthetic, 1/1/2000, Test Station, 090",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {acc.size:6d}, DT= .0100 SEC,",
    ]
    lines += ["".join(f"{v:15.7E}" for v in acc[i : i + 5]) for i in range(0, acc.size, 5)]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> dict[str, Path]:
    """A wheel of the repository installed in a new virtual environment; returns its paths."""
    tmp = tmp_path_factory.mktemp("wheel")
    dist = tmp / "dist"
    _run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(dist), str(ROOT)], cwd=tmp)
    (wheel,) = dist.glob("isorock-*.whl")
    venv = tmp / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], cwd=tmp)
    py = venv / "bin" / "python"
    purelib = "import sysconfig; print(sysconfig.get_paths()['purelib'])"
    target = Path(_run([str(py), "-c", purelib], tmp).stdout.strip())
    # the test environment's packages (numpy, numba, obspy, snakemake, pyslammer ...), after the venv's own
    (target / "_isorock_test_deps.pth").write_text("\n".join(site.getsitepackages()) + "\n")
    _run([str(py), "-m", "pip", "install", "-q", "--no-deps", "--no-index", str(wheel)], cwd=tmp)
    work = tmp / "empty"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("ISOROCK_RECORDS", "PYTHONPATH")}
    return {"venv": venv, "py": py, "bin": venv / "bin", "purelib": target, "work": work, "env": env}


@pytest.mark.e2e
def test_the_wheel_is_what_runs(installed):
    out = _run(
        [str(installed["py"]), "-c", "import isorock, isorock.resources as r; print(isorock.__file__); "
         "print(r.workflow_root()); print(r.catalog_csv())"],
        installed["work"], installed["env"],
    ).stdout.split()  # fmt: skip
    purelib = str(installed["purelib"])
    assert all(p.startswith(purelib) for p in out), out
    assert out[1].endswith("isorock/_workflow")


@pytest.mark.e2e
def test_the_wheel_carries_the_licence_and_the_type_marker(installed):
    purelib = installed["purelib"]
    assert (purelib / "isorock" / "py.typed").is_file()  # PEP 561
    (dist_info,) = purelib.glob("isorock-*.dist-info")
    assert (dist_info / "licenses" / "LICENSE").read_text().startswith("MIT License")
    assert "License-Expression: MIT" in (dist_info / "METADATA").read_text().splitlines()


@pytest.mark.e2e
def test_records_check_and_info_on_a_peer_file(installed):
    work, env, isorock = installed["work"], installed["env"], str(installed["bin"] / "isorock")
    at2 = work / "synthetic.AT2"
    _write_at2(at2)
    chk = json.loads(_run([isorock, "records", "check", str(at2), "--json"], work, env).stdout)
    assert chk["format"] == "peer-at2" and chk["npts"] == 2001 and chk["units"] == "g"
    info = json.loads(_run([isorock, "info", str(at2), "--json"], work, env).stdout)
    assert info["dt_s"] == 0.01 and 0.2 < info["pga_g"] < 0.31


@pytest.mark.e2e
def test_simulate(installed):
    work, env, isorock = installed["work"], installed["env"], str(installed["bin"] / "isorock")
    res = _run(
        [isorock, "simulate", "--lambda", "4", "--R", "3", "--isolation", "linear", "--Tb", "3", "--xi",
         "0.35", "--rho", "0.5", "--pulse", "fullsine", "--td", "0.5", "--amp", "0.6", "--json"],
        work, env,
    )  # fmt: skip
    assert json.loads(res.stdout)["outcome"] in ("no_uplift", "rocking", "overturn")


@pytest.mark.e2e
def test_report_on_the_builtin_samples(installed):
    """``isorock report`` from an empty folder: the packaged workflow on pyslammer's sample records."""
    pytest.importorskip("pyslammer")
    work, env, isorock = installed["work"], installed["env"], str(installed["bin"] / "isorock")
    small = {
        "records": {"dir": None, "max_records": 2},
        "search": {"amp_max_g": 3.0, "growth": 1.2, "rtol": 1e-2},
        "overturn": {"R_m": [1.0, 5.0], "cases": ["none", "linear"]},
        "maps": {
            "lambda_R": {"lambda": [2.0, 5.0], "R_m": [1.0, 6.0], "cases": ["none"]},
            "Tb_xi": {"Tb_s": [2.0, 3.0], "xi_b": [0.1, 0.3]},
        },
        "pulses": {
            "shapes": {"rect": ["none"], "halfsine": [], "fullsine": []},
            "vs_R": {"td_s": [0.5], "R_m": [1.0]},
            "vs_omega": {"R_m": [1.0], "omega_p_rad_s": [5.0]},
            "vs_isolation": {"shapes": []},
            "maps": {"excitations": [{"shape": "halfsine", "td_s": 0.5}], "cases": ["none"]},
        },
    }
    (work / "small.yaml").write_text(yaml.safe_dump(small))
    env = {**env, "PATH": f"{installed['bin']}{os.pathsep}{env.get('PATH', '')}"}
    _run([isorock, "report", "--cores", "2", "--configfile", "small.yaml"], work, env)
    assert (work / "report-small.html").stat().st_size > 100_000
    with h5py.File(work / "results" / "isorock.h5", "r") as f:
        assert len(f["records"]) == 2 and "summary/overturn" in f
        assert f.attrs["record_source"] == "pyslammer samples"
    assert list((work / "results" / "figures").glob("*.png"))
