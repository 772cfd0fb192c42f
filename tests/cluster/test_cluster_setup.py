"""What the SLURM run rests on, checked without a cluster: the store comparison of
tests/cluster/run_slurm.sh, the --profile option, and the resources and groups of every job.

The cluster itself (slurmctld, slurmd, sbatch through the Snakemake plugin) is exercised by
``bash tests/cluster/run_slurm.sh``, which ``.ci/run`` runs.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from isorock.errors import IsorockError
from support.records import ROOT

sys.path.insert(0, str(Path(__file__).parent))
from compare_stores import compare  # noqa: E402

needs_snakemake = pytest.mark.skipif(
    importlib.util.find_spec("snakemake") is None, reason="snakemake is not installed"
)


def _store(path: Path, value: float = 1.5, created: str = "2026-01-01", extra: bool = False) -> Path:
    with h5py.File(path, "w") as f:
        f.attrs["created_utc"] = created
        f.attrs["config_hash"] = "abc"
        g = f.create_group("overturn/REC")
        g.create_dataset("pga_g", data=np.array([0.1, np.nan, value]))
        g.create_dataset("seconds", data=np.array([float(len(created))]))
        g.attrs["resolution"] = 0.005
        if extra:
            f.create_dataset("maps/extra", data=np.zeros(2))
    return path


def test_compare_stores_same_numbers(tmp_path):
    a = _store(tmp_path / "a.h5")
    b = _store(tmp_path / "b.h5", created="2026-11-23T10:00:00Z")  # another time, another job duration
    count, diffs = compare(str(a), str(b))
    assert count >= 3 and diffs == []


def test_compare_stores_finds_a_changed_number_and_a_missing_dataset(tmp_path):
    a = _store(tmp_path / "a.h5")
    b = _store(tmp_path / "b.h5", value=1.5 + 1e-15)
    c = _store(tmp_path / "c.h5", extra=True)
    assert compare(str(a), str(b))[1] == ["overturn/REC/pga_g: values differ"]
    assert compare(str(a), str(c))[1] == ["maps: only in B", "maps/extra: only in B"]
    with h5py.File(b, "a") as f:
        f["overturn/REC"].attrs["resolution"] = 0.01
    assert "overturn/REC@resolution" in " ".join(compare(str(a), str(b))[1])


def _scaled(path, axis_name: str):
    """A store with a map whose axis is a dimension scale (layout 5), as the workflow writes it."""
    with h5py.File(path, "w") as f:
        g = f.create_group("maps/REC/m")
        x = g.create_dataset("lambda_", data=np.array([2.0, 4.0]))
        y = g.create_dataset("R_m", data=np.array([1.0, 3.0]))
        x.make_scale("lambda_")
        y.make_scale("R_m")
        codes = g.create_dataset("codes", data=np.zeros((2, 2), dtype="i1"))
        codes.dims[0].attach_scale(g[axis_name])
        codes.dims[1].attach_scale(y)
    return path


def test_compare_stores_compares_dimension_scales_by_name(tmp_path):
    """The scales' HDF5 object references differ between two files with the same numbers: they are
    compared by the scales they name, and a scale attached to another axis is a difference."""
    a, b = _scaled(tmp_path / "a.h5", "lambda_"), _scaled(tmp_path / "b.h5", "lambda_")
    assert compare(str(a), str(b))[1] == []
    c = _scaled(tmp_path / "c.h5", "R_m")
    assert any("codes@DIMENSION_LIST" in d for d in compare(str(a), str(c))[1])


def test_find_profile(tmp_path, monkeypatch):
    from isorock.control import run as runner  # the workflow runner (isorock report)

    assert runner.find_profile("default", ROOT) == (ROOT / "workflow/profiles/default").resolve()
    with pytest.raises(IsorockError, match="--profile nope: no such profile; valid: default, slurm"):
        runner.find_profile("nope", ROOT)
    own = tmp_path / "site"
    own.mkdir()
    (own / "config.yaml").write_text("executor: local\ncores: 4\n")
    assert runner.find_profile(str(own), ROOT) == own.resolve()
    (own / "config.yaml").write_text("executor: [\n")
    with pytest.raises(IsorockError, match="not valid YAML"):
        runner.find_profile(str(own), ROOT)
    # the slurm profile without its plugin, or away from a cluster: one line that says what to do
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "snakemake_executor_plugin_slurm" else real(name, *a),
    )
    with pytest.raises(IsorockError, match=re.escape("pip install 'isorock[cluster]'")):
        runner.find_profile("slurm", ROOT)
    monkeypatch.setattr(importlib.util, "find_spec", real)
    monkeypatch.setattr(runner.shutil, "which", lambda cmd: None)
    if real("snakemake_executor_plugin_slurm") is not None:
        with pytest.raises(IsorockError, match="no sbatch here: run it on a login node"):
            runner.find_profile("slurm", ROOT)


def test_slurm_profile_settings():
    import yaml

    prof = yaml.safe_load((ROOT / "workflow/profiles/slurm/config.yaml").read_text())
    assert prof["executor"] == "slurm" and prof["jobs"] >= 1 and prof["latency-wait"] >= 30
    assert prof["restart-times"] >= 1 and {"mem_mb", "runtime"} <= set(prof["default-resources"])
    assert "NUMBA_CACHE_DIR=" in prof["precommand"]
    # the plugin refuses --export in slurm_extra (and then waits forever): never put it there
    assert "--export" not in str(prof["default-resources"].get("slurm_extra", ""))
    groups = dict(g.split("=") for g in prof["group-components"])
    assert set(groups) == {"record", "assess", "pulses", "final"} and all(
        int(n) >= 1 for n in groups.values()
    )


@needs_snakemake
def test_every_job_has_cluster_resources_and_a_group(tmp_path):
    """A dry run of the default workflow (the pyslammer samples): every job but the target asks for
    memory and run time and belongs to a group that the slurm profile batches."""
    res = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-n", "--cores", "2"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
        env={k: v for k, v in os.environ.items() if k != "ISOROCK_RECORDS"},
    )
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    out = res.stdout
    jobs: list[tuple[str, dict]] = []  # (rule, resources) of every job listed
    rule = None
    for line in out.splitlines():
        m = re.match(r"\s*(local)?rule (\w+):", line)
        if m:
            rule = None if m.group(1) or m.group(2) == "all" else m.group(2)  # all: the target, no job
        elif rule and line.strip().startswith("resources:"):
            jobs.append((rule, dict(kv.split("=", 1) for kv in line.split(":", 1)[1].strip().split(", "))))
            rule = None
    # process_record in batches (process_record_p0, _p1 ...: control.plan.process_batches), the rest per
    # record, block or study: 18 records give some 50 jobs
    rules = {r.split("_p")[0] if r.startswith("process_record_p") else r for r, _ in jobs}
    assert len(jobs) > 40 and rules >= {"process_record", "min_overturn", "regime_maps", "merge", "figures"}
    for rule, r in jobs:
        assert int(r["mem_mb"]) >= 500 and int(r["runtime"]) >= 5, (rule, r)
    groups = set(re.findall(r"Group job (\w+)", out))
    # the default configuration includes the example assessment: its jobs are the "assess" group
    assert groups == {"record", "pulses", "assess", "final"}
