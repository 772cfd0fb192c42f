"""Parameter validation and derived quantities (docs/model.md §1, §7)."""

import math

import pytest

from isorock import Block, FPIsolation, LinearIsolation, NoIsolation, System
from isorock.constants import G
from isorock.physics.model import impact_coefficients


def test_block_geometry_from_lambda_R():
    blk = Block.from_lambda_R(4.0, 3.0)
    assert blk.lam == pytest.approx(4.0, rel=1e-14)
    assert blk.R == pytest.approx(3.0, rel=1e-14)
    assert blk.alpha == pytest.approx(math.atan(0.25), rel=1e-14)
    assert blk.p == pytest.approx(math.sqrt(3 * G / 12.0), rel=1e-14)
    assert blk.b == pytest.approx(3.0 * math.sin(blk.alpha), rel=1e-14)


@pytest.mark.parametrize(
    "make, name",
    [
        (lambda: Block(-1.0, 1.0), "b"),
        (lambda: Block(1.0, 0.0), "h"),
        (lambda: Block.from_lambda_R(4.0, -3.0), "R"),
        (lambda: LinearIsolation(Tb=3.0, xi_b=-0.1, rho=0.5), "xi_b"),
        (lambda: LinearIsolation(Tb=3.0, xi_b=0.2, rho=0.0), "rho"),
        (lambda: LinearIsolation(Tb=-3.0, xi_b=0.2, rho=0.5), "Tb"),
        (lambda: FPIsolation(mu_b=0.1, R_b=2.0, rho=-1.0), "rho"),
        (lambda: FPIsolation(mu_b=-0.1, R_b=2.0, rho=0.5), "mu_b"),
        (lambda: FPIsolation(mu_b=0.1, R_b=2.0, rho=0.5, beta=0.95, gamma=0.5), "beta"),
        (lambda: System(Block.from_lambda_R(0.7, 1.0), LinearIsolation(3.0, 0.1, 1.0)), "lambda"),
        (lambda: System(Block.from_lambda_R(0.7, 1.0)), "lambda"),
        (lambda: LinearIsolation(Tb=float("nan"), xi_b=0.1, rho=0.5), "Tb"),
    ],
)
def test_bad_parameters_name_the_parameter_and_range(make, name):
    with pytest.raises(ValueError) as exc:
        make()
    msg = str(exc.value)
    assert msg.startswith(f"{name}=")
    assert "valid" in msg


def test_no_bounce_limit_matches_eps_sign():
    for rho in (0.1, 0.5, 2.0):
        lim = math.sqrt(2 * (rho + 1) / (rho + 4))
        eps_below, _, _ = impact_coefficients(lim * 0.999, 1.0, rho)
        eps_above, _, _ = impact_coefficients(lim * 1.001, 1.0, rho)
        assert eps_below < 0 < eps_above
        System(Block.from_lambda_R(lim * 1.001, 1.0), LinearIsolation(3.0, 0.1, rho))


def test_impact_coefficient_limits():
    blk = Block.from_lambda_R(4.0, 2.0)
    # rho -> 0: Housner, beta1 -> 0
    eps, b1, b2 = impact_coefficients(blk.lam, blk.h, 1e-12)
    assert eps == pytest.approx(1 - 1.5 * math.sin(blk.alpha) ** 2, abs=1e-11)
    assert abs(b1) < 1e-10 and abs(b2) < 1e-10
    # lambda -> infinity: eps -> 1
    eps, b1, _ = impact_coefficients(1e6, 1.0, 0.5)
    assert eps == pytest.approx(1.0, abs=1e-11)
    sysm = System(blk, LinearIsolation(3.0, 0.35, 0.5))
    assert sysm.beta2 == pytest.approx(0.5 * blk.h / 1.5)
    assert sysm.kappa == pytest.approx(1 / 3)


def test_isolator_derived_quantities():
    iso = LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5)
    w = 2 * math.pi / 3.0
    assert iso.kb == pytest.approx(w * w)
    assert iso.cb == pytest.approx(2 * 0.35 * w)
    fp = FPIsolation.from_period(mu_b=0.11, Tb=3.0, rho=0.5)
    assert fp.R_b == pytest.approx(2.236, abs=1e-3)  # docs/model.md §1
    assert fp.Tb == pytest.approx(3.0)
    assert NoIsolation().kind == "none"
