"""Two configurations run one after the other in one folder (issue 35, items 5 and 7).

An engineer comparing two objects runs ``isorock report --configfile statue.yaml``, then
``--configfile cabinet.yaml``, in one folder: the second keeps the first one's results apart
(``results-statue/``, with the pages ``report-statue.html`` was made from), and a run of the first
again brings them back without running a job. Each run says the records check's warning and its status
line once (they were said by isorock report, by the run's Snakefile and again by the report's).

The records are one of the user's own, added with ``records add`` (so the records check warns that the
directory holds no Table 1 file), and one pyslammer sample; the configurations assess one object on
the fixed base at two stripes (tens of seconds a run on 2 cores).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import pytest
import yaml

from support.records import own_records

pytestmark = pytest.mark.e2e

SAMPLE = "Northridge_1994_PAC-175"


def _config(mine: Path, height_m: float) -> dict:
    return {
        "records": {"dir": str(mine), "select": ["Q1", SAMPLE]},
        "isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"}]},
        "assessment": {
            "objects": [{"name": "block", "height_m": height_m, "width_m": 0.5, "friction": 0.6}],
            "cases": ["none"],
            "stripes_g": [0.2, 0.5],
            "design_g": [0.5],
            "mce_g": [0.8],
        },
    }


def _report(wd: Path, name: str) -> subprocess.CompletedProcess:
    res = subprocess.run(
        [sys.executable, "-m", "isorock.cli", "report", "--configfile", f"{name}.yaml", "--cores", "2"],
        cwd=wd, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-5000:]
    return res


def _said_once(stderr: str) -> None:
    lines = stderr.splitlines()
    warn = [ln for ln in lines if "holds no file of the 22 catalog rows" in ln]
    status = [ln for ln in lines if ln.startswith("isorock: 2 record(s) from ")]
    assert len(warn) == 1 and len(status) == 1, (warn, status)


def _config_name(store: Path) -> str:
    with h5py.File(store, "r") as f:
        return str(f.attrs["config_name"])


def test_a_second_configuration_keeps_the_first_ones_results(tmp_path):
    pytest.importorskip("snakemake")
    pytest.importorskip("pyslammer")
    mine = own_records(tmp_path)
    wd = tmp_path / "study"
    wd.mkdir()
    for name, height in (("statue", 1.8), ("cabinet", 1.2)):
        (wd / f"{name}.yaml").write_text(yaml.safe_dump(_config(mine, height)))

    first = _report(wd, "statue")
    _said_once(first.stderr)
    pages = {p.relative_to(wd / "results"): p.read_bytes() for p in (wd / "results" / "report").rglob("*")
             if p.is_file()}  # fmt: skip
    report = (wd / "report-statue.html").read_bytes()

    second = _report(wd, "cabinet")
    _said_once(second.stderr)
    kept = wd / "results-statue"
    assert f"kept in {kept}" in second.stderr, second.stderr[-3000:]
    assert "merges it again" not in second.stderr  # nothing of the first run is removed
    # the first configuration's store and pages are where its report says, as its report shows them
    assert _config_name(kept / "isorock.h5") == "statue"
    assert {p: (kept / p).read_bytes() for p in pages} == pages
    assert (wd / "report-statue.html").read_bytes() == report
    assert _config_name(wd / "results" / "isorock.h5") == "cabinet"
    landing = "results/report/landing.rst"
    assert (wd / landing).read_bytes() != pages[Path(landing).relative_to("results")]

    third = _report(wd, "statue")  # back: its finished jobs are kept, none runs again
    _said_once(third.stderr)
    assert "is back in" in third.stderr and (wd / "results-cabinet" / "isorock.h5").is_file()
    assert _config_name(wd / "results" / "isorock.h5") == "statue" and not kept.exists()
    assert "Nothing to be done" in third.stdout + third.stderr, (third.stdout + third.stderr)[-3000:]
