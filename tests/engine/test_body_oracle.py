"""Self-tests of the general-body rocking oracle (``tests/engine/body_oracle.py``).

Each check compares the oracle with a second, independent route: the scipy oracle of the uniform block
(:mod:`isorock.physics.engine.oracle`), closed forms written out here (uplift thresholds, the impact map
solved
as a Newton-Euler impulse problem, the free-rocking energy and amplitudes), invariants (energy between
impacts, horizontal momentum at impacts), the mirror symmetry and the time scaling of a constant
vertical acceleration.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock import Block, FPIsolation, GroundMotion, LinearIsolation, NoIsolation, Pulse, System
from isorock.constants import G
from isorock.physics.engine.oracle import simulate
from support.modules import load_beside

bo = load_beside(__file__, "body_oracle")
simulate_body = bo.simulate_body

# an asymmetric body: CM nearer the left edge, a radius of gyration unlike a uniform block's
BL, BR, H, RG = 0.25, 0.40, 1.1, 0.55


def iso_tuple(iso) -> tuple:
    if iso.kind == "none":
        return ("none",)
    if iso.kind == "linear":
        return ("linear", iso.Tb, iso.xi_b, iso.rho)
    return ("fp", iso.mu_b, iso.R_b, iso.rho, iso.Y, iso.beta, iso.gamma)


def rel(a: float, b: float) -> float:
    return abs(a - b) / max(abs(a), abs(b), 1e-300)


def excursions(res: dict):
    """Index ranges of the rocking stretches between events: (side, indices) of consecutive points."""
    side = res["side"]
    t = res["t"]
    out = []
    start = 0
    for i in range(1, side.size + 1):
        if i == side.size or side[i] != side[start] or t[i] == t[i - 1]:
            if side[start] != 0 and i - start > 1:
                out.append((int(side[start]), np.arange(start, i)))
            start = i
    return out


# ------------------------------------------------------------------------------------------------
# 1. the uniform block against the scipy oracle of the uniform block
# ------------------------------------------------------------------------------------------------
UNIFORM_CASES = [
    # (lambda, R, isolation, shape, td, amplitude / tan(alpha))
    (6.0, 1.0, NoIsolation(), "halfsine", 0.5, 1.5),  # rocks, impacts, ceases
    (6.0, 1.0, NoIsolation(), "rect", 0.3, 1.2),
    (8.0, 1.5, NoIsolation(), "fullsine", 0.5, 1.6),  # overturns after an impact
    (5.0, 1.0, LinearIsolation(2.0, 0.05, 0.8), "halfsine", 0.4, 1.6),
    (5.0, 1.0, LinearIsolation(2.5, 0.1, 2.0), "rect", 0.3, 1.6),
    (5.0, 1.0, LinearIsolation(2.0, 0.05, 0.8), "halfsine", 0.4, 2.0),  # overturns after 3 impacts
    (4.0, 0.8, FPIsolation.from_period(0.08, 2.0, 0.7), "fullsine", 0.6, 1.0),
    (4.0, 0.8, FPIsolation.from_period(0.08, 2.0, 0.7), "fullsine", 0.6, 1.2),  # overturns
]


@pytest.mark.parametrize(("lam", "R", "iso", "shape", "td", "ratio"), UNIFORM_CASES)
def test_uniform_block_matches_scipy_oracle(lam, R, iso, shape, td, ratio):
    blk = Block.from_lambda_R(lam, R)
    amp = ratio * blk.tan_alpha
    ref = simulate(System(blk, iso), Pulse(shape, td, amp))
    # the reference stops at its overturn: go on a little so that pi/2 is reached here too
    t_end = ref.t_end_s + (0.5 if ref.outcome == "overturn" else 0.0)
    r = math.sqrt((blk.b**2 + blk.h**2) / 3.0)
    res = simulate_body(
        blk.b,
        blk.b,
        blk.h,
        r,
        isolation=iso_tuple(iso),
        excitation=bo.pulse_excitation(shape, td, amp),
        t_end=t_end,
    )
    assert res["outcome"] == ref.outcome
    assert ref.outcome != "no_uplift"
    assert res["n_impacts"] == ref.n_impacts
    assert rel(res["max_theta_over_alpha"], ref.max_theta_over_alpha) < 1e-6
    if iso.kind != "none":
        assert rel(res["max_base_disp"], ref.max_base_disp_m) < 1e-6
    assert abs(res["t_uplift"] - ref.t_uplift_s) < 1e-7
    if ref.outcome == "overturn":
        assert rel(res["t_overturn"], ref.t_overturn_s) < 1e-6


RECORD_CASES = [
    (NoIsolation(), 0.35),  # rocks, 12 impacts
    (LinearIsolation(2.0, 0.05, 0.8), 0.9),  # rocks, 70 impacts
    (FPIsolation.from_period(0.06, 1.5, 1.0), 0.8),  # overturns after an impact
]


@pytest.mark.parametrize(("iso", "scale"), RECORD_CASES)
def test_uniform_block_matches_scipy_oracle_on_a_record(iso, scale):
    """A sampled input (linear between samples, zero after the last one), restarted at every sample."""
    dt = 0.01
    t = np.arange(301) * dt
    acc = (np.sin(2 * np.pi * 1.3 * t) + 0.6 * np.sin(2 * np.pi * 3.1 * t + 0.4)) * np.exp(
        -(((t - 1.2) / 0.7) ** 2)
    )
    gm = GroundMotion(dt, acc * scale * G)
    blk = Block.from_lambda_R(5.0, 1.0)
    ref = simulate(System(blk, iso), gm)
    t_end = ref.t_end_s + (0.5 if ref.outcome == "overturn" else 0.0)
    r = math.sqrt((blk.b**2 + blk.h**2) / 3.0)
    res = simulate_body(
        blk.b, blk.b, blk.h, r, isolation=iso_tuple(iso), excitation=(dt, gm.acc), t_end=t_end
    )
    assert res["outcome"] == ref.outcome != "no_uplift"
    assert res["n_impacts"] == ref.n_impacts
    assert rel(res["max_theta_over_alpha"], ref.max_theta_over_alpha) < 1e-6
    if iso.kind != "none":
        assert rel(res["max_base_disp"], ref.max_base_disp_m) < 1e-6
    assert abs(res["t_uplift"] - ref.t_uplift_s) < 1e-7


def test_uniform_coefficients_reduce_to_housner_and_model_section_7():
    for lam in (2.0, 4.0, 9.0):
        b, h = 0.3, 0.3 * lam
        r = math.sqrt((b * b + h * h) / 3.0)
        alpha = math.atan(b / h)
        eps, beta1 = bo.restitution(b, b, h, r, 0.0)
        assert abs(eps - (1.0 - 1.5 * math.sin(alpha) ** 2)) < 1e-14
        assert beta1 == 0.0
        for rho in (0.3, 1.0, 4.0):
            den = lam * lam * (rho + 4.0) + 4.0 * (rho + 1.0)
            eps, beta1 = bo.restitution(b, b, h, r, rho / (1.0 + rho))
            assert abs(eps - (lam * lam * (rho + 4.0) - 2.0 * (rho + 1.0)) / den) < 1e-14
            assert abs(beta1 - 6.0 * rho * h / den) < 1e-14


# ------------------------------------------------------------------------------------------------
# 2. closed forms
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("sign", "b_edge", "side"), [(1.0, BL, -1), (-1.0, BR, 1)])
def test_uplift_threshold_per_side_fixed_base(sign, b_edge, side):
    """A rectangular pulse tips the body about the far edge: threshold ``g b_edge/h`` on that side."""
    thr = G * b_edge / H
    for factor, lifts in ((1.0 - 1e-9, False), (1.0 + 1e-9, True)):
        a0 = sign * thr * factor
        res = simulate_body(BL, BR, H, RG, excitation=(lambda t, a0=a0: a0, 0.3), t_end=1.0)
        assert (res["outcome"] != "no_uplift") == lifts
        if lifts:
            assert res["uplifts"][0] == (0.0, side)


def test_uplift_threshold_linear_isolator():
    """Undamped linear isolator, rectangular pulse: ``max|A| = 2 a0 sin(pi td/Tb)`` (td <= Tb/2).

    With ``b_left < b_right`` the smaller, left-side threshold ``g b_left/h`` decides.
    """
    Tb, td = 2.0, 0.3
    a_up = G * BL / H / (2.0 * math.sin(math.pi * td / Tb))
    for factor, lifts in ((1.0 - 1e-6, False), (1.0 + 1e-6, True)):
        a0 = a_up * factor
        res = simulate_body(
            BL,
            BR,
            H,
            RG,
            isolation=("linear", Tb, 0.0, 0.5),
            excitation=(lambda t, a0=a0: a0, td),
            t_end=td + Tb,
        )
        assert (res["outcome"] != "no_uplift") == lifts
        if lifts:
            assert res["uplifts"][0][1] == -1


def test_uplift_with_vertical_ramp():
    """Ramps ``x_g'' = r_h t``, ``a_v = r_v t``: uplift to the left at
    ``t = g tan(a_L)/(r_h - r_v tan(a_L))``."""
    dt, n = 0.01, 101
    t = np.arange(n) * dt
    r_h, r_v = 9.0, -4.0
    res = simulate_body(BL, BR, H, RG, excitation=(dt, r_h * t), vertical=r_v * t, t_end=1.0)
    tan_l = BL / H
    t_exact = G * tan_l / (r_h - r_v * tan_l)
    assert res["uplifts"][0][1] == -1
    assert abs(res["t_uplift"] - t_exact) < 1e-12


def impulse_map(b_old, b_new, h, r, rho, s, w_minus, v_minus):
    """The impact solved as a Newton-Euler impulse problem (unit body mass, base mass ``1/rho``).

    Unknowns: CM velocity ``(vx, vy)``, ``theta'`` (clockwise), absolute base velocity ``v``, impulse
    ``(Px, Py)`` on the body at the new edge ``(-s b_new, -h)`` from the CM. The body arrives turning
    about the old edge ``(s b_old, -h)`` and leaves stuck to the base at the new edge.
    """
    vx_m, vy_m = v_minus + h * w_minus, s * b_old * w_minus
    a = np.zeros((6, 6))
    rhs = np.zeros(6)
    # unknowns: vx, vy, w, v, Px, Py
    a[0, [0, 4]] = [1.0, -1.0]  # vx+ - vx- = Px
    rhs[0] = vx_m
    a[1, [1, 5]] = [1.0, -1.0]  # vy+ - vy- = Py
    rhs[1] = vy_m
    a[2, [2, 4, 5]] = [r * r, h, -s * b_new]  # r^2 (w+ - w-) = s b_new Py - h Px (clockwise moments)
    rhs[2] = r * r * w_minus
    if rho == 0.0:
        a[3, 3] = 1.0  # fixed base: v+ = v-
        rhs[3] = v_minus
    else:
        a[3, [3, 4]] = [1.0 / rho, 1.0]  # base: (v+ - v-)/rho = -Px
        rhs[3] = v_minus / rho
    a[4, [0, 2, 3]] = [1.0, -h, -1.0]  # the new edge moves with the base: vx - h w = v
    a[5, [1, 2]] = [1.0, s * b_new]  # ... and does not move vertically: vy + s b_new w = 0
    sol = np.linalg.solve(a, rhs)
    return sol[2], sol[3]


@pytest.mark.parametrize("rho", [0.0, 0.4, 2.5])
@pytest.mark.parametrize("s", [1, -1])
def test_restitution_against_impulse_problem_and_hand_formula(rho, s):
    kappa = rho / (1.0 + rho)
    b_old, b_new = (BR, BL) if s == 1 else (BL, BR)
    w_minus, v_minus = -s * 1.3, 0.27
    w_plus, v_plus = impulse_map(b_old, b_new, H, RG, rho, s, w_minus, v_minus)
    j = RG**2 + H**2 - b_old * b_new
    i_new = RG**2 + H**2 + b_new**2
    eps_hand = (j - kappa * H * H) / (i_new - kappa * H * H)
    assert abs(w_plus / w_minus - eps_hand) < 1e-12
    eps, beta1 = bo.restitution(b_old, b_new, H, RG, kappa)
    assert abs(eps - eps_hand) < 1e-14
    assert abs((v_plus - v_minus) - beta1 * w_minus) < 1e-12
    # the oracle's map in a run: free rocking on an undamped isolator (or the ground) from side s
    iso = ("none",) if rho == 0.0 else ("linear", 3.0, 0.0, rho)
    res = simulate_body(BL, BR, H, RG, isolation=iso, theta0=s * 0.05, t_end=1.5)
    imp = res["impacts"][0]
    assert imp["side"] == s and not imp["ceased"]
    assert abs(imp["w_plus"] / imp["w_minus"] - eps_hand) < 1e-12
    if rho:
        assert abs((imp["v_plus"] - imp["v_minus"]) - beta1 * imp["w_minus"]) < 1e-12
        # horizontal momentum of body + base at every impact, the final cease included
        for imp in res["impacts"]:
            before = imp["v_minus"] + kappa * H * imp["w_minus"]
            after = imp["v_plus"] + kappa * H * imp["w_plus"]
            assert abs(after - before) < 1e-14


def test_user_restitution_overrides_both_sides():
    kappa = 0.5 / 1.5
    res = simulate_body(BL, BR, H, RG, isolation=("linear", 3.0, 0.0, 0.5), theta0=0.05, eps=0.7, t_end=2.0)
    assert res["n_impacts"] >= 3
    for imp in res["impacts"]:
        if not imp["ceased"]:
            assert imp["w_plus"] == pytest.approx(0.7 * imp["w_minus"], rel=1e-15)
        jump = kappa * H * (imp["w_minus"] - imp["w_plus"])
        assert abs(imp["v_plus"] - imp["v_minus"] - jump) < 1e-14


def side_geometry(s: int):
    b = BR if s == 1 else BL
    R = math.hypot(b, H)
    return b, R, math.atan2(b, H), RG**2 + R * R


def test_free_rocking_energy_per_impact_and_amplitudes():
    """Fixed base, no input, released at ``theta0`` on the right edge.

    Energy per unit mass ``E = I_s theta'^2/2 + g (C - h)``. It is all kinetic at ``theta = 0``, so over
    the impact leaving side ``s`` onto the edge ``-s``: ``E+/E- = I_{-s} eps_s^2 / I_s``; between impacts it
    is conserved, so ``E-`` of impact ``n+1`` is ``E+`` of impact ``n``, and the peak of the excursion after
    it solves ``g (R cos(alpha - theta_max) - h) = E+``. With ``eps_s = J/I_{-s}`` the ratio is
    ``J^2/(I_{+1} I_{-1})`` in both directions (``J = r^2 + h^2 - b_left b_right`` is symmetric), although
    ``eps_{+1} != eps_{-1}``; over two impacts ``eps_{+1}^2 eps_{-1}^2``.
    """
    theta0 = 0.1
    res = simulate_body(BL, BR, H, RG, theta0=theta0, t_end=8.0)
    imps = res["impacts"]
    assert res["outcome"] == "rocking" and len(imps) > 10
    b, R, a, inertia = side_geometry(1)
    e0 = G * (R * math.cos(a - theta0) - H)
    assert rel(0.5 * inertia * imps[0]["w_minus"] ** 2, e0) < 1e-9
    eps = {}
    for s in (1, -1):
        b_old, b_new = side_geometry(s)[0], side_geometry(-s)[0]
        eps[s] = (RG**2 + H**2 - b_old * b_new) / (RG**2 + H**2 + b_new**2)
    e_minus = [0.5 * side_geometry(i["side"])[3] * i["w_minus"] ** 2 for i in imps]
    ratios = []
    for n in range(len(imps) - 1):
        s = imps[n]["side"]
        assert imps[n + 1]["side"] == -s and not imps[n]["ceased"]
        ratio = side_geometry(-s)[3] * eps[s] ** 2 / side_geometry(s)[3]
        assert rel(e_minus[n + 1] / e_minus[n], ratio) < 1e-8
        j = RG**2 + H**2 - BL * BR
        assert rel(ratio, j * j / (side_geometry(1)[3] * side_geometry(-1)[3])) < 1e-14
        ratios.append(e_minus[n + 1] / e_minus[n])
    assert rel(ratios[0] * ratios[1], (eps[1] * eps[-1]) ** 2) < 1e-8
    # the last impact ceases (eta = 1e-4 of p alpha of the side left), none before
    last = imps[-1]
    bs, Rs, als, Is = side_geometry(last["side"])
    assert last["ceased"] and abs(eps[last["side"]] * last["w_minus"]) < 1e-4 * math.sqrt(G * Rs / Is) * als
    # the peak of each excursion after an impact
    for s, idx in excursions(res)[1:6]:
        _, Rn, an, _ = side_geometry(s)
        th_max = np.max(np.abs(res["y"][idx, 2]))
        w_start = res["y"][idx[0], 3]
        e_plus = 0.5 * side_geometry(s)[3] * w_start**2
        assert rel(G * (Rn * math.cos(an - th_max) - H), e_plus) < 1e-8


# ------------------------------------------------------------------------------------------------
# 3. energy between impacts
# ------------------------------------------------------------------------------------------------
def test_energy_conserved_between_impacts_fixed_base():
    res = simulate_body(BL, BR, H, RG, theta0=-0.12, t_end=3.0)
    e_ref = None
    n = 0
    for s, idx in excursions(res):
        b, R, a, inertia = side_geometry(s)
        y = res["y"][idx]
        th, w = y[:, 2], y[:, 3]
        e = 0.5 * inertia * w * w + G * (H * np.cos(th) + s * b * np.sin(th) - H)
        e_ref = e_ref or e[0]
        assert np.max(np.abs(e - e[0])) < 1e-8 * e_ref
        n += 1
    assert n >= 5


def test_energy_conserved_between_impacts_linear_isolator():
    """Undamped isolator, no input: ``u'^2/2 + kappa C u' theta' + kappa I_s theta'^2/2 + kappa g (C-h)
    + omega_b^2 u^2/2`` per unit total mass is constant between impacts (the coupled equations)."""
    Tb, rho = 1.5, 1.2
    kappa, wb2 = rho / (1.0 + rho), (2.0 * math.pi / Tb) ** 2
    res = simulate_body(BL, BR, H, RG, isolation=("linear", Tb, 0.0, rho), theta0=0.1, omega0=0.3, t_end=2.0)
    n = 0
    for s, idx in excursions(res):
        b, R, a, inertia = side_geometry(s)
        u, v, th, w = res["y"][idx, :4].T
        c = H * np.cos(th) + s * b * np.sin(th)
        e = (
            0.5 * v * v
            + kappa * c * v * w
            + 0.5 * kappa * inertia * w * w
            + kappa * G * (c - H)
            + 0.5 * wb2 * u * u
        )
        assert np.max(np.abs(e - e[0])) < 1e-8 * abs(e[0])
        n += 1
    assert n >= 4
    assert res["max_base_disp"] > 1e-3  # the base does move


# ------------------------------------------------------------------------------------------------
# symmetry and vertical scaling
# ------------------------------------------------------------------------------------------------
def test_mirror_symmetry_linear_isolator():
    """Body (b_left, b_right) under ``x_g''`` = body (b_right, b_left) under ``-x_g''``, mirrored."""
    exc = bo.pulse_excitation("fullsine", 0.5, 0.35)
    neg = (lambda t: -exc[0](t), exc[1])
    iso = ("linear", 2.0, 0.05, 0.8)
    a = simulate_body(BL, BR, H, RG, isolation=iso, excitation=exc, t_end=4.0)
    b = simulate_body(BR, BL, H, RG, isolation=iso, excitation=neg, t_end=4.0)
    assert a["outcome"] == b["outcome"] == "rocking"
    assert a["n_impacts"] == b["n_impacts"] > 2
    assert rel(a["max_theta_over_alpha"], b["max_theta_over_alpha"]) < 1e-9
    assert rel(a["max_base_disp"], b["max_base_disp"]) < 1e-9
    assert [-s for _, s in a["uplifts"]] == [s for _, s in b["uplifts"]]
    assert [t for t, _ in a["uplifts"]] == pytest.approx([t for t, _ in b["uplifts"]], abs=1e-12)


@pytest.mark.parametrize("iso", [("none",), ("fp", 0.06, 1.5, 1.0)])
def test_constant_vertical_is_a_time_scaling(iso):
    """``a_v = c g`` constant and ``x_g''(t) = (1+c) f(sqrt(1+c) t)`` give
    ``theta(t) = theta_f(sqrt(1+c) t)``, where ``theta_f`` answers ``f`` without vertical (the friction
    pendulum scales with the load, Bouc-Wen is rate-independent)."""
    c = -0.3
    k = math.sqrt(1.0 + c)
    f, dur = bo.pulse_excitation("halfsine", 0.4, 0.45)
    t_end = 2.5

    def f_cut(t: float) -> float:
        return f(t) if t <= dur else 0.0

    # the vertical acts over the whole run: the input lasts to the end, with a break at the pulse's end
    base = simulate_body(BL, BR, H, RG, isolation=iso, excitation=(f_cut, t_end, [dur]), t_end=t_end)
    vert = simulate_body(
        BL,
        BR,
        H,
        RG,
        isolation=iso,
        excitation=(lambda t: (1.0 + c) * f_cut(k * t), t_end / k, [dur / k]),
        vertical=lambda t: c * G,
        t_end=t_end / k,
    )
    assert base["outcome"] == vert["outcome"] == "rocking"
    assert rel(base["max_theta_over_alpha"], vert["max_theta_over_alpha"]) < 1e-6
    assert abs(base["t_uplift"] - k * vert["t_uplift"]) < 1e-6
    for ia, ib in list(zip(base["impacts"], vert["impacts"], strict=False))[:5]:
        assert abs(ia["t"] - k * ib["t"]) < 1e-6
    if iso[0] == "fp":
        assert rel(base["max_base_disp"], vert["max_base_disp"]) < 1e-6


def test_piecewise_input_with_a_jump():
    """``[(t0, t1, fun), ...]``: each callable on its own piece. A single piece equals the callable form;
    a +a/-a rectangular cycle (a jump at 0.2 s) on a fixed base equals, after 0.2 s, a run restarted
    from the state at 0.2 s under -a."""
    a0 = 0.4 * G
    one = simulate_body(BL, BR, H, RG, excitation=[(0.0, 0.3, lambda t: a0)], t_end=2.0)
    ref = simulate_body(BL, BR, H, RG, excitation=(lambda t: a0, 0.3), t_end=2.0)
    assert one["n_impacts"] == ref["n_impacts"] and one["max_theta_over_alpha"] == ref["max_theta_over_alpha"]
    cyc = [(0.0, 0.2, lambda t: a0), (0.2, 0.4, lambda t: -a0)]
    res = simulate_body(BL, BR, H, RG, excitation=cyc, t_end=2.0)
    assert res["uplifts"][0] == (0.0, -1)
    k = int(np.searchsorted(res["t"], 0.2))
    assert res["t"][k] == 0.2
    th, w = res["y"][k, 2:4]
    assert th < 0.0
    rest = simulate_body(
        BL, BR, H, RG, excitation=[(0.0, 0.2, lambda t: -a0)], theta0=th, omega0=w, t_end=1.8
    )
    assert res["n_impacts"] == rest["n_impacts"] > 0
    assert [i["t"] for i in res["impacts"]] == pytest.approx(
        [0.2 + i["t"] for i in rest["impacts"]], abs=1e-9
    )
    later = res["t"] >= 0.2
    assert np.max(np.abs(res["y"][later, 2])) == pytest.approx(np.max(np.abs(rest["y"][:, 2])), rel=1e-9)
