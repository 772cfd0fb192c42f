"""Fuzzing the record readers with damaged files (hypothesis).

Real record files (the test files, and the shared records when present) are damaged the ways files
get damaged: truncated, garbage bytes inserted, a column dropped on some lines, numbers replaced by
text. Every reader must then either read a valid trace (finite samples, a positive time step) or
raise :class:`isorock.errors.RecordError` naming the file (and the line where the problem sits on
one): never another exception, never a hang (each example has a deadline).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from isorock.errors import RecordError
from isorock.io import read_record
from support.records import DATA, manifest, records_dir


def _seeds() -> list[tuple[bytes, str, dict]]:
    """(file content, file name, reading options) of undamaged files of every format."""
    t = np.arange(300) * 0.01
    acc = 0.2 * np.sin(2 * np.pi * t) * np.exp(-0.5 * t)
    one = "\n".join(f"{a:.6e}" for a in acc) + "\n"
    two = "\n".join(f"{x:.3f}, {a:.6e}" for x, a in zip(t, acc, strict=True)) + "\n"
    pct = "% synthetic record\n% 300 POINTS OF ACCEL DATA EQUALLY SPACED AT 0.010 SEC (UNITS: CM/SEC/SEC)\n"
    pct += "\n".join(" ".join(f"{100 * a:.4e}" for a in acc[i : i + 6]) for i in range(0, 300, 6)) + "\n"
    pysl = "# Time Series: Synthetic - TST-090\n# Time (s),Acceleration (g's)\n" + two
    seeds = [
        ((DATA / "good" / "tiny.AT2").read_bytes(), "tiny.AT2", {}),
        ((DATA / "good" / "columns_described.bbp").read_bytes(), "c.bbp", {}),
        (one.encode(), "one.txt", {"format": "one-column", "dt": 0.01, "units": "g"}),
        (two.encode(), "two.txt", {"format": "two-column", "units": "g"}),
        (pct.encode(), "pct.dat", {"format": "percent-header"}),
        (pysl.encode(), "Synthetic_2000_TST-090.csv", {}),
    ]
    d = records_dir()
    if d is not None:
        for row in manifest()[::4]:  # a few real files of every kind
            kw = {"format": row["format"], "units": row["units"] or None}
            if row["dt_s"]:
                kw["dt"] = float(row["dt_s"])
            seeds.append(((d / row["file"]).read_bytes(), row["file"], kw))
    return seeds


SEEDS = _seeds()


def _damage(data: bytes, how: str, at: float, junk: bytes, word: str) -> bytes:
    k = int(at * len(data))
    if how == "truncate":
        return data[:k]
    if how == "garbage":
        return data[:k] + junk + data[k:]
    lines = data.decode("latin-1").splitlines(keepends=True)
    if not lines:
        return data
    i = min(int(at * len(lines)), len(lines) - 1)
    toks = lines[i].split()
    if how == "drop_column" and len(toks) > 1:
        lines[i] = " ".join(toks[:-1]) + "\n"
    elif how == "text" and toks:
        toks[len(toks) // 2] = word
        lines[i] = " ".join(toks) + "\n"
    return "".join(lines).encode("latin-1")


@settings(
    max_examples=200,
    deadline=5000,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(
    seed=st.integers(min_value=0, max_value=len(SEEDS) - 1),
    how=st.sampled_from(["truncate", "garbage", "drop_column", "text"]),
    at=st.floats(min_value=0.0, max_value=1.0),
    junk=st.binary(min_size=1, max_size=40),
    word=st.sampled_from(["abc", "nan", "1e999", "--", "1.2.3", "0x1F", "", "inf", "NPTS=", "%"]),
)
def test_damaged_files_read_or_fail_clearly(tmp_path, seed, how, at, junk, word):
    data, name, kw = SEEDS[seed]
    path = tmp_path / name
    path.write_bytes(_damage(data, how, at, junk, word))
    try:
        stream = read_record(path, **kw)
    except RecordError as exc:
        assert str(exc).startswith(str(path)), str(exc)
        assert exc.line is None or exc.line >= 1
        assert "\n" not in str(exc)
        return
    assert len(stream) >= 1
    for tr in stream:
        assert tr.stats.npts >= 2 and tr.stats.delta > 0 and math.isfinite(tr.stats.delta)
        assert np.all(np.isfinite(tr.data))


@pytest.mark.parametrize("seed", range(len(SEEDS)), ids=[s[1] for s in SEEDS])
def test_undamaged_seeds_read(seed, tmp_path):
    """The fuzzing starts from files that read (else it would only test errors)."""
    data, name, kw = SEEDS[seed]
    path = tmp_path / name
    path.write_bytes(data)
    assert len(read_record(path, **kw)) >= 1
