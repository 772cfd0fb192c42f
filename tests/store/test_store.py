"""The HDF5 store: atomic writes, h5py and pandas readability, merging (isorock.store)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest

from isorock.store import (
    OVERTURN_COLUMNS,
    atomic_h5,
    atomic_path,
    config_hash,
    file_sha256,
    map_paths,
    merge_h5,
    read_map,
    read_table,
    write_map,
    write_tables,
)


def _listing(d: Path) -> list[str]:
    return sorted(p.name for p in d.iterdir())


# ------------------------------------------------------------------------------------------ atomic writes
def test_atomic_h5_raised_write_leaves_nothing(tmp_path):
    out = tmp_path / "job.h5"
    with pytest.raises(RuntimeError, match="boom"), atomic_h5(out) as f:
        f["x"] = np.arange(10)
        raise RuntimeError("boom")
    assert _listing(tmp_path) == []  # no final file, no temporary file


def test_atomic_h5_failure_keeps_the_old_file(tmp_path):
    out = tmp_path / "job.h5"
    with atomic_h5(out) as f:
        f["x"] = np.arange(3)
    with pytest.raises(KeyboardInterrupt), atomic_h5(out, "a") as f:
        f["y"] = 1.0
        raise KeyboardInterrupt
    with h5py.File(out, "r") as f:
        assert list(f) == ["x"]
        assert f.attrs["isorock_version"]
    assert _listing(tmp_path) == ["job.h5"]


def test_atomic_h5_append_mode_adds_to_a_copy(tmp_path):
    out = tmp_path / "job.h5"
    with atomic_h5(out) as f:
        f["x"] = 1
    with atomic_h5(out, "a") as f:
        f["y"] = 2
    with h5py.File(out, "r") as f:
        assert sorted(f) == ["x", "y"]


def test_atomic_path_needs_a_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="nothing was written"), atomic_path(tmp_path / "a.h5"):
        pass
    assert _listing(tmp_path) == []


_KILLED_WRITER = """
import os, signal, sys, time
import numpy as np
from isorock.store import atomic_h5
with atomic_h5(sys.argv[1]) as f:
    f.create_dataset("big", data=np.zeros(200_000))
    f.flush()
    print("writing", flush=True)
    time.sleep(60)
"""


def test_killed_write_leaves_no_complete_looking_file(tmp_path):
    out = tmp_path / "job.h5"
    proc = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(_KILLED_WRITER), str(out)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout.readline().strip() == "writing"
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert not out.exists()
    left = _listing(tmp_path)
    # only the hidden temporary file of the killed writer may remain, never the final name
    assert all(n.startswith(".job.h5.") and n.endswith(".tmp") for n in left), left


# ------------------------------------------------------------------------------------------ tables
def _overturn_df(rid: str = "IMV79-EMO") -> pd.DataFrame:
    rows = []
    for R in (1.0, 3.0):
        for case, iso in (("none", "none"), ("linear", "linear")):
            rows.append(
                {
                    "record": rid, "lambda_": 4.0, "R_m": R, "b_m": R / 17**0.5, "h_m": 4 * R / 17**0.5,
                    "tan_alpha": 0.25, "case": case, "isolation": iso,
                    "Tb_s": np.nan if iso == "none" else 3.0, "xi_b": np.nan if iso == "none" else 0.35,
                    "rho": np.nan if iso == "none" else 0.5, "mu_b": np.nan, "R_b_m": np.nan,
                    "min_overturn_g": 0.3 * R if case == "none" else np.nan, "overturns": case == "none",
                    "min_overturn_over_tan_alpha": 1.2 * R if case == "none" else np.nan,
                    "uplift_g": 0.25, "uplift_over_tan_alpha": 1.0, "n_analyses": 10, "amp_max_g": 5.0,
                    "record_pga_g": 0.38, "scale_min": 0.3 * R / 0.38 if case == "none" else np.nan,
                }
            )  # fmt: skip
    return pd.DataFrame(rows, columns=list(OVERTURN_COLUMNS))


def test_tables_readable_with_pandas_and_h5py(tmp_path):
    out = tmp_path / "t.h5"
    df = _overturn_df()
    with atomic_path(out) as tmp:
        write_tables(tmp, {"overturn/IMV79-EMO": df}, {"overturn/IMV79-EMO": {"record_sha256": "ab12"}})
    back = read_table(out, "overturn/IMV79-EMO")
    pd.testing.assert_frame_equal(back, df, check_dtype=False)
    plain = pd.read_hdf(out, "overturn/IMV79-EMO")  # plain pandas, as a user would read it
    assert list(plain.columns) == list(OVERTURN_COLUMNS)
    with h5py.File(out, "r") as f:
        g = f["overturn/IMV79-EMO"]
        assert g.attrs["record_sha256"] == "ab12"
        units = json.loads(g.attrs["units"])
        assert units["min_overturn_g"] == "g" and units["R_m"] == "m"
        tab = g["table"][()]  # a compound dataset, one field per column
        assert np.allclose(tab["R_m"], df["R_m"])
        assert np.isnan(tab["min_overturn_g"][1])


def test_merge_unites_groups_and_keeps_tables_readable(tmp_path):
    a, b, m = tmp_path / "a.h5", tmp_path / "b.h5", tmp_path / "m.h5"
    with atomic_path(a) as tmp:
        write_tables(tmp, {"overturn/R1": _overturn_df("R1")})
        with h5py.File(tmp, "a") as f:
            g = f.create_group("records/R1")
            g.attrs["pga_g"] = 0.4
            g["acc"] = np.ones(5)
    with atomic_h5(b) as f:
        f.create_group("records/R1/pulse").attrs["Tp_s"] = 2.5
        f.create_group("pulses/x").attrs["skipped"] = 1
    with atomic_h5(m) as f:
        merge_h5([a, b], f, skip=("pulses",))
    with h5py.File(m, "r") as f:
        assert sorted(f) == ["overturn", "records"]
        assert f["records/R1"].attrs["pga_g"] == 0.4
        assert f["records/R1/pulse"].attrs["Tp_s"] == 2.5
        assert f["records/R1/acc"].shape == (5,)
    assert len(read_table(m, "overturn/R1")) == 4
    with atomic_h5(tmp_path / "bad.h5") as f, pytest.raises(ValueError, match="written by two jobs"):
        merge_h5([a, a], f)


def test_map_round_trip_and_index(tmp_path):
    from isorock.physics.regime_maps import RegimeMap

    codes = np.array([[0, 1, 2], [1, 1, 2]], dtype=np.int8)
    m = RegimeMap("lambda-R", "lambda", "R_m", np.array([2.0, 4.0]), np.array([1.0, 2.0, 3.0]), codes,
                  np.zeros((2, 3)), 0.5, {"isolation": "none"}, 6, 0.1)  # fmt: skip
    out = tmp_path / "m.h5"
    with atomic_h5(out) as f:
        write_map(f.create_group("maps/REC/lambda_R-none"), m, {"source": "REC", "case": "none"})
    with h5py.File(out, "r") as f:
        assert map_paths(f) == ["/maps/REC/lambda_R-none"]
        g = f["maps/REC/lambda_R-none"]
        assert g.attrs["source"] == "REC" and g["R_m"].attrs["units"] == "m"
        assert "overturn" in g["codes"].attrs["legend"]
        back = read_map(g)
    assert np.array_equal(back.codes, codes) and back.amp_g == 0.5 and back.fixed == {"isolation": "none"}


def test_hashes(tmp_path):
    assert config_hash({"a": 1, "b": [1, 2]}) == config_hash({"b": [1, 2], "a": 1})
    assert config_hash({"a": 1}) != config_hash({"a": 2})
    p = tmp_path / "f.txt"
    p.write_bytes(b"abc")
    assert file_sha256(p) == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"


def test_stale_temporary_file_is_not_a_result(tmp_path):
    """A temporary name from a killed writer never shadows the final file name."""
    (tmp_path / ".job.h5.abc.tmp").write_bytes(b"partial")
    with atomic_h5(tmp_path / "job.h5") as f:
        f["x"] = 1
    assert (tmp_path / "job.h5").exists()
    assert os.path.getsize(tmp_path / ".job.h5.abc.tmp") == 7
