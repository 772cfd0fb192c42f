"""Regime maps: the parallel grid runner agrees with single analyses; the `isorock map` interface."""

import json

import h5py
import numpy as np
import pytest

from isorock import Block, FPIsolation, LinearIsolation, NoIsolation, Pulse
from isorock.cli import main
from isorock.physics.engine import simulate
from isorock.physics.model import System
from isorock.physics.regime_maps import regime_map_lambda_R, regime_map_Tb_xi
from isorock.physics.result import OUTCOME_CODES


@pytest.mark.parametrize(
    "iso", [NoIsolation(), LinearIsolation(3.0, 0.35, 0.5), FPIsolation(0.11, 2.24, 0.5)]
)
def test_lambda_R_map_matches_single_runs(iso):
    pulse = Pulse("fullsine", 0.5)
    lams, Rs = np.linspace(1.5, 8.0, 6), np.linspace(0.5, 10.0, 5)
    m = regime_map_lambda_R(pulse, iso, lams, Rs, 0.5, threads=2)
    assert m.codes.shape == (6, 5) and m.n_analyses == 30
    for i, lam in enumerate(lams):
        for j, R in enumerate(Rs):
            r = simulate(System(Block.from_lambda_R(lam, R), iso), pulse.with_pga(0.5))
            assert m.codes[i, j] == OUTCOME_CODES[r.outcome], (lam, R)
    assert sum(m.counts().values()) == 30


def test_Tb_xi_uplift_boundary_is_independent_of_R():
    """Paper Fig. 12 / docs/model.md §13: in full contact the linear isolator does not see the block size."""
    pulse = Pulse("halfsine", 0.3)
    Tbs, xis = np.linspace(0.5, 4.0, 8), np.linspace(0.0, 0.5, 6)
    uplift = []
    for R in (1.0, 4.0, 12.0):
        m = regime_map_Tb_xi(pulse, Block.from_lambda_R(3.0, R), Tbs, xis, 0.5, 0.5)
        uplift.append(m.codes > 0)
    assert np.array_equal(uplift[0], uplift[1]) and np.array_equal(uplift[0], uplift[2])
    assert uplift[0].any() and not uplift[0].all()


def test_map_cli_json_and_store(tmp_path, capsys):
    out = tmp_path / "map.h5"
    argv = [
        "map",
        "lambda-R",
        "--pulse",
        "halfsine",
        "--td",
        "0.5",
        "--pga",
        "0.6",
        "--isolation",
        "linear",
        "--Tb",
        "3",
        "--xi",
        "0.35",
        "--rho",
        "0.5",
        "--lambda-range",
        "2",
        "6",
        "--R-range",
        "0.5",
        "8",
        "--n-lambda",
        "7",
        "--n-R",
        "4",
        "--jobs",
        "2",
        "--out",
        str(out),
        "--json",
    ]
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["shape"] == [7, 4] and d["n_analyses"] == 28 and d["seconds"] >= 0
    assert sum(d["counts"].values()) == 28
    with h5py.File(out) as f:
        g = f["maps/lambda-R"]
        assert g["codes"].shape == (7, 4)
        assert np.array_equal(
            np.bincount(g["codes"][()].ravel(), minlength=3),
            [d["counts"][k] for k in ("no_uplift", "rocking", "overturn")],
        )
        assert g["R_m"].attrs["units"] == "m" and g["lambda_"].shape == (7,)
        # the map carries its inputs
        a = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in g.attrs.items()}
        assert (a["source_kind"], a["pulse_shape"], a["td_s"], a["amp_g"]) == ("pulse", "halfsine", 0.5, 0.6)
        assert (a["isolation"], a["Tb_s"], a["xi_b"], a["rho"]) == ("linear", 3.0, 0.35, 0.5)
    # a second --out to the same file is refused, unless --force
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "exists" in err and "--force" in err
    assert main([*argv, "--force"]) == 0


def test_map_of_a_record_carries_its_provenance(tmp_path, capsys):
    t = np.arange(0, 8, 0.01)
    f = tmp_path / "rec.txt"
    np.savetxt(f, 0.3 * np.sin(2 * np.pi * t) * np.exp(-0.3 * t))
    out = tmp_path / "m.h5"
    argv = ["map", "Tb-xi", "--lambda", "4", "--R", "3", "--rho", "0.5", "--record", str(f), "--dt",
            "0.01", "--units", "g", "--pga", "0.4", "--n-Tb", "3", "--n-xi", "2", "--out", str(out),
            "--json"]  # fmt: skip
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["record"]["units"] == "g" and d["pga_g"] == 0.4
    with h5py.File(out) as h:
        a = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in h["maps/Tb-xi"].attrs.items()}
    assert a["source_kind"] == "record" and a["record_file"] == str(f.resolve())
    assert len(a["record_sha256"]) == 64 and a["record_units"] == "g" and "bandpass" in a["record_processing"]
    assert (a["lambda_"], a["R_m"], a["rho"], a["amp_g"]) == (4.0, 3.0, 0.5, 0.4)
