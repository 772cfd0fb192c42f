"""Access to the real records (not part of the repository) and to the small test files, for the tests.

The directory is ``$ISOROCK_RECORDS``, else ``../shared/records`` next to the repository;
tests that need it are skipped, with the reason, when it is absent.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
"""The repository."""
DATA = ROOT / "tests" / "data"
"""Small record files of the tests (good and bad inputs)."""


RECORDS_SKIP = (
    "shared records not found: set ISOROCK_RECORDS to the directory holding manifest.csv "
    "(default ../shared/records)"
)
"""The reason of the tests skipped when the real records are absent."""


def records_dir() -> Path | None:
    """The records directory, or None when it (or its manifest) is absent."""
    env = os.environ.get("ISOROCK_RECORDS", "").strip()
    d = Path(env) if env else (ROOT / ".." / "shared" / "records").resolve()
    return d if (d / "manifest.csv").is_file() else None


def manifest() -> list[dict[str, str]]:
    """Rows of the records manifest (empty when the records are absent)."""
    d = records_dir()
    if d is None:
        return []
    with (d / "manifest.csv").open(newline="") as fh:
        return list(csv.DictReader(fh))


def need_records() -> Path:
    """The records directory, or skip the calling test."""
    d = records_dir()
    if d is None:
        pytest.skip(RECORDS_SKIP)
    return d


def manifest_params(only_table1: bool = False) -> list:
    """``pytest.param`` per manifest row (id = file name); one skipped param when the records are absent."""
    rows = [r for r in manifest() if r["table1_id"] or not only_table1]
    if not rows:
        return [
            pytest.param(
                None,
                marks=pytest.mark.skip(reason="shared records not found: set ISOROCK_RECORDS"),
                id="no-records",
            )
        ]
    return [pytest.param(r, id=r["file"]) for r in rows]


def read_row(row: dict[str, str]):
    """The trace of one manifest row, read with :func:`isorock.io.read_record` (acceleration, m/s^2)."""
    from isorock.io import read_record

    d = need_records()
    st = read_record(
        d / row["file"],
        row["format"],
        dt=float(row["dt_s"]) if row["dt_s"] else None,
        units=row["units"] or None,
        component=row["column"] or None,
    )
    assert len(st) == 1
    return st[0]


def row_of(file: str) -> dict[str, str]:
    """The manifest row of a file, or skip when the records are absent."""
    need_records()
    for r in manifest():
        if r["file"] == file:
            return r
    pytest.skip(f"{file} is not in the records manifest")
    raise AssertionError  # unreachable


def own_records(tmp_path: Path, n: int = 800) -> Path:
    """A records directory (``tmp_path/mine``) holding one small record of the user's own, ``Q1``: a
    decaying 1.5 Hz sine of 0.3 g, ``n`` samples at 0.01 s, added with ``records add``'s function."""
    import numpy as np

    from isorock.records.adding import add_records

    t = np.arange(n) * 0.01
    f = tmp_path / "q.txt"
    np.savetxt(f, 0.3 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.4 * t) * np.minimum(t, 1.0))
    mine = tmp_path / "mine"
    add_records([f], mine, ids=["Q1"], dt=0.01, units="g")
    return mine


def synthetic_record(seed: int, pga_g: float):
    """A 12 s synthetic ground motion at 0.01 s, peak ``pga_g`` [g]: a 0.6-1.0 Hz wave packet around
    4 s plus tapered noise, the same for the same ``seed``."""
    import numpy as np

    from isorock import G, GroundMotion

    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 12.0, 0.01)
    a = np.sin(2 * np.pi * (0.6 + 0.4 * rng.random()) * t) * np.exp(-(((t - 4.0) / 1.5) ** 2))
    a += 0.3 * rng.standard_normal(t.size) * np.sin(np.pi * t / t[-1]) ** 2
    return GroundMotion(0.01, a / np.abs(a).max() * pga_g * G, f"synthetic-{seed}")
