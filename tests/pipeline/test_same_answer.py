"""One record, one block: the same minimum overturning PGA from every entry point.

``isorock min-overturn`` (command line), the Python API (:func:`isorock.load_motion` then
:func:`isorock.physics.overturning.min_overturn_amplitude`) and the workflow with ``config/ci.yaml`` all
read the file
through :func:`isorock.records.motion.load_record` and process it with the same steps, so they must agree to
round-off (1e-9 relative): what a user gets does not depend on where they ask.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from isorock import Block, System, load_motion
from isorock.physics.overturning import min_overturn_amplitude
from isorock.pipeline import load_config
from isorock.store import read_table
from support.records import ROOT, need_records

RECORD, FILE = "TAB78-TAB", "SLAMMER_Tabas1978_TAB-TR_g_dt0.02.txt"  # one-column, g, dt 0.02 s
READ = {"format": "one-column", "dt": 0.02, "units": "g"}
LAM, R = 4.0, 0.5  # a block of the ci configuration's grid (lambda 4, R from 0.5 m)


@pytest.fixture(scope="module")
def workflow_value(tmp_path_factory) -> tuple[float, dict]:
    """The workflow's answer (ci configuration, this record only, the overturn job and its inputs)."""
    pytest.importorskip("snakemake")
    d = need_records()
    wd = tmp_path_factory.mktemp("same")
    (wd / "only.yaml").write_text(yaml.safe_dump({"records": {"dir": str(d), "select": [RECORD]}}))
    target = f"results/jobs/overturn/{RECORD}.h5"
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--cores", "2", "--configfile",
           str(ROOT / "config" / "ci.yaml"), "only.yaml", "--", target]  # fmt: skip
    res = subprocess.run(cmd, cwd=wd, capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    df = read_table(wd / target, f"overturn/{RECORD}")
    row = df[(df["lambda_"] == LAM) & (df["R_m"] == R) & (df["case"] == "none")].iloc[0]
    search = load_config(ROOT / "config" / "ci.yaml")["search"]
    return float(row["min_overturn_g"]), search


def test_cli_api_and_workflow_agree(workflow_value):
    wf, search = workflow_value
    path = need_records() / FILE
    cli = subprocess.run(
        [sys.executable, "-m", "isorock.cli", "min-overturn", "--lambda", f"{LAM:g}", "--R", f"{R:g}",
         "--record", str(path), "--format", READ["format"], "--dt", str(READ["dt"]), "--units", READ["units"],
         "--pga-max", str(search["amp_max_g"]), "--growth", str(search["growth"]),
         "--rtol", str(search["rtol"]), "--json"],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert cli.returncode == 0, cli.stderr
    out = json.loads(cli.stdout)
    gm = load_motion(path, **READ)
    api = min_overturn_amplitude(
        System(Block.from_lambda_R(LAM, R)), gm,
        amp_max=search["amp_max_g"], growth=search["growth"], rtol=search["rtol"],
    ).min_overturn_g  # fmt: skip
    assert out["min_overturn_g"] == pytest.approx(wf, rel=1e-9)
    assert api == pytest.approx(wf, rel=1e-9)
    assert out["resolution"] == pytest.approx(search["growth"] - 1)
    assert out["record"]["sha256"] == gm.meta["record"]["sha256"] and Path(out["record"]["file"]).name == FILE
