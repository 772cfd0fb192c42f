"""A rigid body of general geometry (docs/model.md §18): closed forms, symmetry, the uniform case.

Each test can fail: the restitution against a hand derivation, each side's uplift threshold, free
rocking's energy per impact, the mirror image of a body under the mirrored input, a uniform body given
as a RigidBody against the Block.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock import Block, FPIsolation, LinearIsolation, NoIsolation, Pulse, System
from isorock.constants import G
from isorock.errors import ParameterError
from isorock.physics.body import Part, RigidBody, restitution
from isorock.physics.engine import simulate
from isorock.physics.model import housner_restitution, impact_coefficients

ISOLATIONS = {
    "none": NoIsolation(),
    "linear": LinearIsolation(Tb=2.5, xi_b=0.15, rho=0.7),
    "fp": FPIsolation.from_period(mu_b=0.07, Tb=3.0, rho=0.7),
}
STATUE = RigidBody(b_left=0.16, b_right=0.28, h_cg=0.72, r_gyration=0.42)


def test_restitution_hand_derivation():
    # fixed base, landing from the right edge (b_old = 0.28) onto the left (b_new = 0.16): angular
    # momentum about the new edge, I_c w + m (h^2 - b_old b_new) w = (I_c + m (h^2 + b_new^2)) w+
    r2, h = 0.42**2, 0.72
    by_hand = (0.1764 + 0.5184 - 0.28 * 0.16) / (0.1764 + 0.5184 + 0.16**2)
    assert math.isclose(restitution(r2, h, 0.28, 0.16), by_hand, rel_tol=1e-14)
    assert STATUE.impact(1.0)[0] == restitution(r2, h, 0.28, 0.16)
    assert STATUE.impact(-1.0)[0] == restitution(r2, h, 0.16, 0.28)
    assert STATUE.impact(1.0)[0] != STATUE.impact(-1.0)[0]


@pytest.mark.parametrize("lam", [1.5, 3.0, 8.0])
@pytest.mark.parametrize("rho", [0.0, 0.3, 2.0])
def test_restitution_reduces_to_the_uniform_block(lam, rho):
    blk = Block.from_lambda_R(lam, 1.3)
    body = RigidBody.uniform(2 * blk.b, 2 * blk.h)
    kappa = rho / (1 + rho)
    eps, beta1 = body.impact(1.0, kappa)
    if rho == 0.0:
        assert math.isclose(eps, housner_restitution(blk.alpha), rel_tol=1e-12)
        assert beta1 == 0.0
    else:
        e_ref, b1_ref, b2_ref = impact_coefficients(lam, blk.h, rho)
        assert math.isclose(eps, e_ref, rel_tol=1e-12)
        assert math.isclose(beta1, b1_ref, rel_tol=1e-12)
        assert math.isclose(System(body, LinearIsolation(2.0, 0.1, rho)).beta2, b2_ref, rel_tol=1e-12)


def test_given_restitution_replaces_both_sides():
    body = RigidBody(0.16, 0.28, 0.72, 0.42, restitution=0.8)
    assert body.impact(1.0) == (0.8, 0.0)
    assert body.impact(-1.0, 0.5)[0] == 0.8
    assert math.isclose(body.impact(-1.0, 0.5)[1], 0.5 * 0.72 * 0.2)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_uplift_threshold_of_each_side(sign):
    # fixed base: a rectangular pulse lifts the body exactly above g b_s / h of the edge it tips onto
    thr = STATUE.left.tan_alpha if sign > 0 else STATUE.right.tan_alpha
    sysm = System(STATUE, NoIsolation())
    below = simulate(sysm, Pulse("rect", td=0.3, amp=thr * (1 - 1e-9)), scale=sign)
    above = simulate(sysm, Pulse("rect", td=0.3, amp=thr * (1 + 1e-9)), scale=sign, histories=True)
    assert below.outcome == "no_uplift"
    assert above.outcome != "no_uplift"
    # a positive input tips it onto its left edge: theta < 0
    assert np.sign(above.theta[np.nonzero(above.theta)[0][0]]) == -sign


def test_uplift_threshold_on_linear_isolator_per_side():
    # the isolated body in contact lifts off where A = -f_b first passes g tan(alpha_left) upward or
    # -g tan(alpha_right) downward; the contact motion does not depend on the body, so A(t) is read
    # from a run that never lifts off (histories at the exact contact steps of 0.025 s)
    iso = ISOLATIONS["linear"]
    pulse = Pulse("halfsine", td=0.8, amp=0.1)
    ref = simulate(System(Block.from_lambda_R(1.5, 1.0), iso), pulse, histories=True)
    assert ref.outcome == "no_uplift"
    A = -(iso.kb * ref.u + iso.cb * ref.u_dot)
    thr_l, thr_r = G * STATUE.left.tan_alpha, G * STATUE.right.tan_alpha
    k_none = 0.98 * min(thr_l / A.max(), thr_r / -A.min())
    sysm = System(STATUE, iso)
    assert simulate(sysm, pulse, scale=k_none).outcome == "no_uplift"
    for k in (1.03 * thr_l / A.max(), 1.03 * thr_r / -A.min()):
        over = (k * A > thr_l) | (k * A < -thr_r)
        i = int(np.argmax(over))
        res = simulate(sysm, pulse, scale=k, histories=True)
        assert res.t_uplift_s is not None and ref.t[i - 1] <= res.t_uplift_s <= ref.t[i]
        first = res.theta[np.nonzero(res.theta)[0][0]]
        # a positive A tips the body onto its left edge (theta < 0)
        assert np.sign(first) == (-1.0 if A[i] > 0 else 1.0)


def test_free_rocking_energy_ratio_per_impact():
    # fixed base, no input: released at theta0 on the right edge; the first impact lands on the left
    # edge with kinetic energy I_left (eps w)^2 / 2 out of I_right w^2 / 2
    body = STATUE
    right, left = body.right, body.left
    th0 = 0.6 * right.alpha
    res = simulate(System(body, NoIsolation()), Pulse("rect", td=1e-3, amp=0.0), theta0=th0, histories=True)
    e0 = G * (right.R * math.cos(right.alpha - th0) - right.h)
    i = next(j for j in range(1, res.t.size) if res.theta[j] == 0.0)
    e_after = 0.5 * left.inertia * res.theta_dot[i] ** 2
    eps = body.impact(1.0)[0]
    assert math.isclose(e_after / e0, left.inertia * eps**2 / right.inertia, rel_tol=1e-7)
    # and the body then rocks on its left edge (theta < 0)
    assert res.theta_dot[i] < 0


@pytest.mark.parametrize("kind", list(ISOLATIONS))
@pytest.mark.parametrize("amp", [0.2, 0.35, 0.6])
def test_mirror_image(kind, amp):
    # the body mirrored left to right under the input reversed moves as the mirror image
    mirror = RigidBody(STATUE.b_right, STATUE.b_left, STATUE.h_cg, STATUE.r_gyration)
    a = simulate(System(STATUE, ISOLATIONS[kind]), Pulse("fullsine", td=0.6, amp=amp), histories=True)
    b = simulate(
        System(mirror, ISOLATIONS[kind]), Pulse("fullsine", td=0.6, amp=amp), scale=-1.0, histories=True
    )
    assert a.outcome == b.outcome and a.n_impacts == b.n_impacts
    assert math.isclose(a.max_theta_over_alpha, b.max_theta_over_alpha, rel_tol=1e-12)
    assert math.isclose(a.max_base_disp_m, b.max_base_disp_m, rel_tol=1e-12, abs_tol=1e-15)
    np.testing.assert_allclose(a.theta, -b.theta, rtol=1e-12, atol=1e-15)


def test_asymmetry_matters():
    # the same outline with its centre of mass off the middle: a pulse toward the weak side lifts it,
    # the same pulse the other way does not
    sysm = System(STATUE, NoIsolation())
    amp = 0.5 * (STATUE.left.tan_alpha + STATUE.right.tan_alpha)
    assert simulate(sysm, Pulse("rect", td=0.2, amp=amp), scale=1.0).outcome != "no_uplift"
    assert simulate(sysm, Pulse("rect", td=0.2, amp=amp), scale=-1.0).outcome == "no_uplift"


@pytest.mark.parametrize("kind", list(ISOLATIONS))
@pytest.mark.parametrize("amp", [0.3, 0.45, 0.7])
def test_uniform_body_equals_block(kind, amp):
    # the same block given as a RigidBody: the same answer to rounding (the inertia r^2 + R^2 and the
    # restitution are computed by other formulas, equal to a few ulps)
    blk = Block.from_lambda_R(4.0, 1.0)
    body = RigidBody.uniform(2 * blk.b, 2 * blk.h)
    pulse = Pulse("fullsine", td=0.7, amp=amp)
    a = simulate(System(blk, ISOLATIONS[kind]), pulse)
    b = simulate(System(body, ISOLATIONS[kind]), pulse)
    assert (a.outcome, a.n_impacts) == (b.outcome, b.n_impacts)
    assert math.isclose(a.max_theta_over_alpha, b.max_theta_over_alpha, rel_tol=1e-8)
    assert math.isclose(a.max_base_disp_m, b.max_base_disp_m, rel_tol=1e-8, abs_tol=1e-12)


def test_parts():
    # a plinth 0.6 x 0.3 m (120 kg) under a figure 0.3 x 1.2 m (80 kg) set 0.05 m right of its middle
    body = RigidBody.from_parts([Part(0.6, 0.3, 0.0, 0.0, 120.0), Part(0.3, 1.2, 0.05, 0.3, 80.0)])
    xc = (80 * 0.05) / 200
    yc = (120 * 0.15 + 80 * 0.9) / 200
    ic = 120 * ((0.36 + 0.09) / 12 + xc**2 + (0.15 - yc) ** 2) + 80 * (
        (0.09 + 1.44) / 12 + (0.05 - xc) ** 2 + (0.9 - yc) ** 2
    )
    assert math.isclose(body.b_left, 0.3 + xc) and math.isclose(body.b_right, 0.3 - xc)
    assert math.isclose(body.h_cg, yc)
    assert math.isclose(body.r_gyration, math.sqrt(ic / 200))
    # one uniform part is the uniform block
    one = RigidBody.from_parts([Part(0.5, 2.0, 1.0, 0.0, 10.0)])
    ref = RigidBody.uniform(0.5, 2.0)
    for k in ("b_left", "b_right", "h_cg", "r_gyration"):
        assert math.isclose(getattr(one, k), getattr(ref, k), rel_tol=1e-14)


def test_parts_refused():
    with pytest.raises(ParameterError, match="outside the footprint"):
        RigidBody.from_parts([Part(0.2, 0.2, 0.0, 0.0, 1.0), Part(0.2, 1.0, 0.5, 0.2, 50.0)])
    with pytest.raises(ParameterError, match="no part stands on the base"):
        RigidBody.from_parts([Part(0.2, 0.2, 0.0, 0.1, 1.0)])
    with pytest.raises(ParameterError, match="b_left"):
        RigidBody(0.0, 0.2, 1.0, 0.3)


def test_bouncing_body_refused():
    # a squat body whose restitution is negative on one side is outside the model
    with pytest.raises(ParameterError, match="bounce landing on its"):
        System(RigidBody(0.5, 0.9, 0.4, 0.3))
    System(RigidBody(0.5, 0.9, 0.4, 0.3), sliding_only=True)
