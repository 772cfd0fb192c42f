"""The impact map never creates energy and conserves the horizontal momentum (docs/model.md §7, §14F)."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from isorock import Block, LinearIsolation, Pulse, System
from isorock.physics.engine import simulate
from isorock.physics.model import impact_coefficients


def kinetic(v, om, kappa, h, R):
    """Kinetic energy per unit total mass at theta = 0 (C = h there)."""
    return 0.5 * v * v + kappa * h * v * om + 0.5 * kappa * (4 / 3) * R * R * om * om


@settings(max_examples=300, deadline=None)
@given(
    lam=st.floats(1.2, 20.0),
    R=st.floats(0.1, 20.0),
    rho=st.floats(0.01, 5.0),
    om=st.floats(-5.0, 5.0),
    v=st.floats(-3.0, 3.0),
)
def test_impact_map_dissipates_and_conserves_momentum(lam, R, rho, om, v):
    blk = Block.from_lambda_R(lam, R)
    eps, beta1, beta2 = impact_coefficients(lam, blk.h, rho)
    kappa = rho / (1 + rho)
    t0 = kinetic(v, om, kappa, blk.h, R)
    # rocking continues
    om1, v1 = eps * om, v + beta1 * om
    t1 = kinetic(v1, om1, kappa, blk.h, R)
    assert t1 <= t0 + 1e-12 * (1 + t0)
    assert math.isclose(v1 + kappa * blk.h * om1, v + kappa * blk.h * om, rel_tol=1e-12, abs_tol=1e-12)
    # energy loss formula of docs/model.md §7 (per m_b, i.e. times (1 + rho) per unit total mass)
    lam2 = lam * lam
    dT = -2 * rho * blk.b**2 * om**2 * (lam2 * (rho + 4) + rho + 1) / (lam2 * (rho + 4) + 4 * (rho + 1))
    assert math.isclose((t1 - t0) * (1 + rho), dT, rel_tol=1e-9, abs_tol=1e-12)
    # rocking ceases
    v2 = v + beta2 * om
    assert 0.5 * v2 * v2 <= t0 + 1e-12 * (1 + t0)
    assert math.isclose(v2, v + kappa * blk.h * om, rel_tol=1e-12, abs_tol=1e-12)


def energy(res, sysm):
    """Energy per unit total mass of the linear-isolated block along the histories (docs/model.md §9)."""
    blk, iso = sysm.block, sysm.isolation
    kap = sysm.kappa
    s = np.sign(res.theta)
    C = blk.R * np.cos(blk.alpha - s * res.theta)
    e = (
        0.5 * res.u_dot**2
        + kap * C * res.u_dot * res.theta_dot
        + 0.5 * kap * (4 / 3) * blk.R**2 * res.theta_dot**2
        + kap * 9.81 * (C - blk.h)
        + 0.5 * iso.kb * res.u**2
    )
    return e


@settings(max_examples=25, deadline=None)
@given(
    lam=st.floats(2.0, 10.0),
    R=st.floats(0.3, 10.0),
    rho=st.floats(0.1, 3.0),
    theta0_frac=st.floats(0.05, 0.9),
)
def test_free_rocking_energy_never_increases(lam, R, rho, theta0_frac):
    """Undamped isolator, no input: e is constant between impacts and drops at each impact."""
    sysm = System(Block.from_lambda_R(lam, R), LinearIsolation(Tb=2.5, xi_b=0.0, rho=rho))
    theta0 = theta0_frac * sysm.alpha
    res = simulate(sysm, Pulse("rect", 0.1, 0.0), theta0=theta0, histories=True, rtol=1e-10, atol=1e-12)
    rock = res.regime == 1
    e = energy(res, sysm)[rock]
    th = res.theta[rock]
    e0 = e[0]
    de = np.diff(e)
    # never increases (to integration tolerance), and the impacts removed energy
    assert np.all(de <= 1e-7 * e0), de.max() / e0
    assert res.n_impacts > 0 and e[-1] < e0 * (1 - 1e-3)
    # constant between impacts: consecutive steps on the same side, away from theta = 0
    same_side = (th[1:] * th[:-1]) > 0
    assert np.all(np.abs(de[same_side]) <= 1e-7 * e0)
    assert np.any(de[~same_side] < -1e-6 * e0)
