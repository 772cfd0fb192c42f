"""A rigid body of measured geometry on the command line (issue 34): ``--b-left --b-right --h-cg
--r-gyration [--restitution]`` on ``simulate`` and ``min-overturn``, the keys of its JSON, a minimum
overturning amplitude per direction, and the errors (one line, exit 2)."""

from __future__ import annotations

import pytest

from isorock import Block, NoIsolation, Pulse, System
from isorock.physics.body import RigidBody
from isorock.physics.engine import simulate
from isorock.physics.overturning import min_overturn_amplitude
from support.cli import run_cli, run_json

BODY = ["--b-left", "0.16", "--b-right", "0.28", "--h-cg", "0.72", "--r-gyration", "0.42"]
STATUE = RigidBody(0.16, 0.28, 0.72, 0.42)


def test_simulate_a_body(capsys):
    argv = ["simulate", *BODY, "--pulse", "fullsine", "--td", "0.6", "--pga", "0.3", "--json"]
    out = run_json(capsys, argv)
    ref = simulate(System(STATUE), Pulse("fullsine", td=0.6, amp=0.3))
    assert out["outcome"] == ref.outcome and out["n_impacts"] == ref.n_impacts
    assert out["max_theta_over_alpha"] == ref.max_theta_over_alpha
    assert out["b_left_m"] == 0.16 and out["b_right_m"] == 0.28
    assert out["h_cg_m"] == 0.72 and out["r_gyration_m"] == 0.42
    assert out["tan_alpha_left"] == pytest.approx(0.16 / 0.72)
    assert out["tan_alpha_right"] == pytest.approx(0.28 / 0.72)


def test_given_restitution_is_used(capsys):
    base = ["simulate", *BODY, "--pulse", "halfsine", "--td", "0.5", "--pga", "0.3", "--json"]
    a = run_json(capsys, base)
    b = run_json(capsys, [*base, "--restitution", "0.95"])
    ref = simulate(System(RigidBody(0.16, 0.28, 0.72, 0.42, restitution=0.95)), Pulse("halfsine", 0.5, 0.3))
    assert b["restitution"] == 0.95 and b["n_impacts"] == ref.n_impacts
    assert (a["n_impacts"], a["max_theta_over_alpha"]) != (b["n_impacts"], b["max_theta_over_alpha"])


def test_min_overturn_per_direction(capsys):
    argv = ["min-overturn", *BODY, "--pulse", "halfsine", "--td", "0.6", "--json"]
    out = run_json(capsys, argv)
    both = {d["polarity"]: d for d in out["by_direction"]}
    assert set(both) == {1.0, -1.0}
    assert both[1.0]["tips_first_onto"] == "left" and both[-1.0]["tips_first_onto"] == "right"
    for pol in (1.0, -1.0):
        ref = min_overturn_amplitude(System(STATUE), Pulse("halfsine", 0.6, 1.0), polarity=pol)
        assert both[pol]["min_overturn_g"] == ref.min_overturn_g
        assert both[pol]["uplift_g"] == pytest.approx(ref.uplift_g)
    # the body lifts off onto its weaker (left) edge first: the smaller answer governs
    assert both[1.0]["min_overturn_g"] < both[-1.0]["min_overturn_g"]
    assert out["min_overturn_g"] == both[1.0]["min_overturn_g"]
    # the uplift of a half-sine pushing toward each edge is that edge's tan(alpha)
    assert both[1.0]["uplift_g"] == pytest.approx(0.16 / 0.72, rel=1e-6)
    assert both[-1.0]["uplift_g"] == pytest.approx(0.28 / 0.72, rel=1e-6)


def test_symmetric_body_searched_once(capsys):
    blk = Block(0.2, 0.7)
    body = ["--b-left", "0.2", "--b-right", "0.2", "--h-cg", "0.7", "--r-gyration", str(blk.R / 3**0.5)]
    out = run_json(capsys, ["min-overturn", *body, "--pulse", "halfsine", "--td", "0.6", "--json"])
    assert "by_direction" not in out
    ref = min_overturn_amplitude(System(blk, NoIsolation()), Pulse("halfsine", 0.6, 1.0))
    assert out["min_overturn_g"] == pytest.approx(ref.min_overturn_g, rel=2e-6)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--b-left", "0.2", "--h-cg", "0.7", "--r-gyration", "0.3"], "give --b-right"),
        ([*BODY, "--height", "1.4", "--width", "0.4"], "not both"),
        ([*BODY[:-1], "-0.3"], "--r-gyration -0.3 must be > 0"),
        (["--height", "1.4", "--width", "0.4", "--restitution", "0.9"], "--restitution is for a rigid body"),
        ([*BODY, "--restitution", "1.5"], "--restitution 1.5 is out of range"),
        (["--b-left", "0.5", "--b-right", "0.9", "--h-cg", "0.4", "--r-gyration", "0.3"], "bounce"),
    ],
)
def test_errors(extra, message):
    p = run_cli(["simulate", *extra, "--pulse", "rect", "--td", "0.2", "--pga", "0.3"])
    assert p.returncode == 2, p.stderr
    assert message in p.stderr and "Traceback" not in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1
