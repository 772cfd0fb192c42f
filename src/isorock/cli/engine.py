"""``isorock simulate``, ``isorock min-overturn`` and ``isorock demo``: one analysis, the minimum
overturning amplitude, and a demonstration over the paper's pulses."""

from __future__ import annotations

import argparse
import math
import sys
import time

from isorock.cli.options import (
    add_block_options,
    add_excitation_options,
    add_isolation_options,
    add_json_option,
    add_pga_max_option,
    add_pga_option,
    all_or_errors,
    block_from_args,
    block_text,
    excitation_from_args,
    isolation_from_args,
    processing_text,
)
from isorock.cli.output import print_json
from isorock.cli.vertical import add_vertical_option, attach_vertical
from isorock.errors import IsorockError
from isorock.plausibility import check_amplitude, check_object

__all__ = ["register"]


def _record_text(source) -> str:
    return (
        f"record: {source.file} [{source.component or '-'}], {source.format}, units {source.units} "
        f"({'from the file' if source.units_source == 'header' else 'as given'}), {processing_text(source)}"
    )


def _input_text(exc, scale: float, pga_g: float) -> list[str]:
    """The excitation and the PGA actually applied, for the text output of ``simulate``: a record's own
    PGA (processed) and the factor applied to it are labelled apart from the applied PGA."""
    from isorock.physics.excitation import GroundMotion

    if not isinstance(exc, GroundMotion):  # a pulse: its amplitude is the PGA applied
        return [f"input: {exc.describe()}", f"PGA applied: {pga_g:.4g} g"]
    return [
        f"input: record {exc.name or '(unnamed)'}: {exc.npts} samples, dt={exc.dt:g} s",
        f"PGA applied: {pga_g:.4g} g (record's own PGA {exc.pga_g:.4g} g x scale factor {scale:.4g})",
    ]


def _angle_text(system) -> str:
    """The slenderness angle, or a rigid body's two (docs/model.md §18)."""
    from isorock.physics.body import RigidBody

    if isinstance(system.block, RigidBody):
        lt, rt = system.block.left.alpha, system.block.right.alpha
        return f"alpha {lt:.4f} rad (left edge), {rt:.4f} rad (right edge)"
    return f"alpha={system.alpha:.4f} rad"


def _stall_warning(stalls: int) -> None:
    if stalls:
        print(
            f"isorock: warning: the engine's zero-progress guard skipped {stalls} uplift test(s): "
            "an uplift may have been missed (the block chatters at the uplift threshold)",
            file=sys.stderr,
        )


def _pulse_ok(a: argparse.Namespace) -> None:
    """A pulse's own options, checked before anything is read (the rest of the input is read after)."""
    if getattr(a, "pulse", None) and getattr(a, "td", None) is None:
        raise IsorockError("--pulse needs --td (half-cycle duration, s)")


def cmd_simulate(a: argparse.Namespace) -> int:
    """``isorock simulate``: one analysis."""
    from isorock.physics.engine import simulate
    from isorock.physics.model import System

    # what is missing or wrong in the object, the isolation and the input is said at once
    (block, dims), iso = all_or_errors(
        lambda: block_from_args(a), lambda: isolation_from_args(a), lambda: _pulse_ok(a)
    )[:2]
    if a.friction is not None:
        check_object(friction=a.friction, names={"friction": "--friction"})
    # an object that slides never rocks: a squat one on an isolator is accepted (no impact, no bounce)
    sliding = a.friction is not None and a.friction < block.tan_alpha
    system = System(block, iso, sliding_only=sliding)
    loaded = excitation_from_args(a, amplitude=True)
    exc, scale, source, choice = loaded.excitation, loaded.scale, loaded.source, loaded.choice
    exc, vinfo = attach_vertical(a, loaded)
    t0 = time.perf_counter()
    res = simulate(system, exc, scale=scale, friction=a.friction)
    secs = time.perf_counter() - t0
    out = res.to_dict()
    if a.friction is not None:
        out["friction"] = a.friction
        out["tan_alpha"] = system.block.tan_alpha
    if vinfo is not None:
        out["vertical_pga_g"] = exc.vertical_pga_g * scale
        out["vertical"] = vinfo
    out["pga_g"] = a.pga if a.pga is not None else exc.pga_g * scale
    out["alpha_rad"] = system.alpha
    out.update(dims)
    out["seconds"] = secs
    if source is not None:
        out["scale"] = scale
        out["record_pga_g"] = exc.pga_g
        out["record"] = source.to_dict()
    if choice is not None:
        out = {"id": a.table1_id, **out, **choice.to_dict()}
    _stall_warning(res.stalls)
    if a.json:
        print_json(out)
        return 0
    print(f"{block_text(dims)}, {_angle_text(system)}; isolation: {a.isolation}")
    if source is not None:
        print(_record_text(source))
    if choice is not None:
        print(f"component: {choice.component} ({choice.method}): {choice.description}")
        if choice.qa_mark:
            print(f"QA mark: {choice.qa_mark}")
    print("\n".join(_input_text(exc, scale, out["pga_g"])))
    if vinfo is not None:
        print(
            f"vertical: {vinfo['component']} of {vinfo['file']}, peak applied {out['vertical_pga_g']:.3g} g "
            f"({vinfo['alignment']}; {vinfo['cut']} samples cut, {vinfo['padded']} padded)"
        )
        print(f"vertical polarity: {vinfo['polarity']}")
    if res.mode == "sliding":
        _print_sliding(res, a.friction, system.block.tan_alpha)
        return 0
    print(f"outcome: {res.outcome}")
    print(f"max |theta|/alpha: {res.max_theta_over_alpha:.4f}   impacts: {res.n_impacts}")
    print(f"max base displacement: {res.max_base_disp_m:.4f} m")
    if res.t_uplift_s is not None:
        print(f"uplift at t = {res.t_uplift_s:.4f} s")
    if res.t_overturn_s is not None:
        print(f"overturn at t = {res.t_overturn_s:.4f} s")
    mu = "not defined: the block would jump (N <= 0)" if res.jumps else f"{res.mu_required:.3f}"
    print(
        f"friction needed against sliding (mu_required): {mu}; least normal force / weight: "
        f"{res.min_normal_over_weight:.3f}"
    )
    if a.friction is not None and res.outside_model(a.friction):
        print(
            f"outside the model: the object's friction {a.friction:g} is at or above tan(alpha) but below "
            "what the rocking needs (or the block jumps): it would slide while it rocks (slide-rock, "
            "not modelled)"
        )
    return 0


def _print_sliding(res, friction: float, tan_alpha: float) -> None:
    """The text output of a sliding analysis."""
    print(
        f"mode: sliding (friction {friction:g} < tan(alpha) {tan_alpha:.4g}: the object slides and never "
        "rocks; Coulomb friction, rigid object, docs/model.md §16)"
    )
    print(
        f"peak slip: {res.sliding_peak_m:.4g} m   residual slip: {res.sliding_residual_m:.4g} m   "
        f"slips: {res.n_slips}"
    )
    if res.t_first_slip_s is not None:
        print(f"first slip at t = {res.t_first_slip_s:.4f} s")
    print(f"max base displacement: {res.max_base_disp_m:.4f} m")
    if res.jumps:
        print(
            "the vertical lifts the object off its base (g + a_v < 0): the sliding result is not valid "
            "from there on"
        )


def _digits(rel: float) -> int:
    """Significant digits a value of relative uncertainty ``rel`` has."""
    return int(min(8, max(2, math.ceil(-math.log10(rel))))) if rel > 0 else 8


def _first_edge(exc, polarity: float) -> str:
    """The edge that the input's largest ground acceleration tips the body onto (a positive one tips
    it onto its left edge)."""
    import numpy as np

    from isorock.physics.excitation import GroundMotion

    if isinstance(exc, GroundMotion):
        peak = float(exc.acc[int(np.argmax(np.abs(exc.acc)))])
    else:
        peak = 1.0  # a pulse starts positive
    return "left" if peak * polarity > 0 else "right"


def cmd_min_overturn(a: argparse.Namespace) -> int:
    """``isorock min-overturn``: minimum overturning amplitude and uplift amplitude."""
    from isorock.physics.model import System
    from isorock.physics.overturning import check_search, min_overturn_amplitude

    check_amplitude(a.pga_max, "--pga-max")  # names the option; before a record is read
    check_search(a.pga_max, a.growth, a.rtol)
    block, dims = block_from_args(a)
    system = System(block, isolation_from_args(a))
    from isorock.control.cost import SEARCH_MS, check_limit, search_analyses

    kind = system.isolation.kind
    # a body whose sides differ has a minimum overturning amplitude per direction: both are searched
    polarities = (1.0,) if getattr(block, "symmetric", True) else (1.0, -1.0)
    n = len(polarities) * search_analyses(
        block.lam, {"amp_max_g": a.pga_max, "growth": a.growth, "rtol": a.rtol}, kind
    )
    check_limit(
        n,
        n * SEARCH_MS[kind] / 1e3,
        f"cost estimate: {n:,} analyses for this search on 1 core",
        force=a.force,
        advice="raise --growth or --rtol",
    )
    loaded = excitation_from_args(a, amplitude=False)
    exc, source = loaded.excitation, loaded.source
    t0 = time.perf_counter()
    found = [
        min_overturn_amplitude(system, exc, amp_max=a.pga_max, growth=a.growth, rtol=a.rtol, polarity=p)
        for p in polarities
    ]
    secs = time.perf_counter() - t0
    # the answer is the smaller of the directions (nothing overturning counts as beyond --pga-max)
    m = min(found, key=lambda r: math.inf if r.min_overturn_g is None else r.min_overturn_g)
    out = m.to_dict()
    if len(found) > 1:
        out["by_direction"] = [
            {"tips_first_onto": _first_edge(exc, r.polarity), **r.to_dict()} for r in found
        ]
        out["n_analyses"] = sum(r.n_analyses for r in found)
    out["tan_alpha"] = system.block.tan_alpha
    out.update(dims)
    out["seconds"] = secs
    if source is not None:
        out["record"] = source.to_dict()
    _stall_warning(m.stalls)
    if a.json:
        print_json(out)
        return 0
    weaker = " (the weaker side's)" if "h_cg_m" in dims else ""
    print(f"{block_text(dims)}, tan(alpha){weaker}={system.block.tan_alpha:.4f}; isolation: {a.isolation}")
    if source is not None:
        print(_record_text(source))
    if len(found) > 1:
        for r in found:
            mo = (
                "none" if r.min_overturn_g is None else f"{r.min_overturn_g:.{_digits(r.resolution or 0)}g} g"
            )
            print(
                f"input {'as given' if r.polarity > 0 else 'reversed'} (its first strong pulse tips the body "
                f"onto its {_first_edge(exc, r.polarity)} edge): uplift {r.uplift_g:.4g} g, minimum "
                f"overturning {mo}"
            )
        print("the smaller governs (a record may arrive with either polarity):")
    print(f"uplift amplitude: {m.uplift_g:.4g} g")
    if m.min_overturn_g is None:
        print(f"no overturning up to {a.pga_max:g} g")
    else:
        d = _digits(m.resolution)
        print(
            f"minimum overturning amplitude: {m.min_overturn_g:.{d}g} g "
            f"({m.min_overturn_over_tan_alpha:.{d}g} x tan(alpha)); resolution {100 * m.resolution:.2g} % "
            f"(the scan step, --growth {a.growth:g})"
        )
    if m.full_runs_only:
        print("note: early-stopped and full runs disagreed at the bracket: the search used full runs only")
    print(f"{out['n_analyses']} analyses in {secs:.2f} s")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``simulate``, ``min-overturn`` and ``demo``."""
    p = sub.add_parser("simulate", help="one analysis of a block under a pulse or a record")
    add_block_options(p)
    add_isolation_options(p)
    g = add_excitation_options(p)
    add_pga_option(
        g,
        required=False,
        what="PGA [g]: the pulse amplitude (required with --pulse), or the PGA "
        "the processed record is scaled to",
    )
    g.add_argument(
        "--scale",
        type=float,
        default=None,
        metavar="F",
        help="factor on the processed record [-] (instead of --pga)",
    )
    m = p.add_argument_group("sliding and vertical input")
    m.add_argument(
        "--friction",
        type=float,
        default=None,
        metavar="MU",
        help="the object's friction coefficient on its base [-], 0 < MU <= 1: below tan(alpha) the object "
        "slides and never rocks, and the sliding is analysed (peak and residual slip, slips); at or above "
        "it, rocking as without it, flagged where the rocking needs more friction (slide-rock, not "
        "modelled). Default: no sliding check",
    )
    add_vertical_option(m)
    add_json_option(p)
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("min-overturn", help="minimum overturning amplitude (PGA) and uplift amplitude")
    add_block_options(p)
    add_isolation_options(p)
    add_excitation_options(p)
    s = p.add_argument_group("search")
    add_pga_max_option(s, default=5.0, what="largest PGA scanned")
    s.add_argument(
        "--growth",
        type=float,
        default=1.005,
        help="ratio of the scan grid [-], > 1 (default 1.005, the paper's); growth - 1 is the resolution",
    )
    s.add_argument(
        "--rtol",
        type=float,
        default=1e-6,
        help="relative width of the final bisection [-], 0 < rtol < 1 (default 1e-6)",
    )
    s.add_argument(
        "--force",
        action="store_true",
        help="run a search whose cost estimate is above the limit of 50 million analyses",
    )
    add_json_option(p)
    p.set_defaults(func=cmd_min_overturn)

    p = sub.add_parser("demo", help="demonstration: minimum overturning amplitudes under the paper's pulses")
    add_pga_max_option(p, default=3.0, what="largest PGA (pulse amplitude) scanned")
    add_json_option(p)
    p.set_defaults(func=cmd_demo)


def cmd_demo(a: argparse.Namespace) -> int:
    """Minimum overturning amplitude of a few blocks under the paper's pulses, three isolation cases."""
    from tqdm import tqdm

    from isorock.physics.excitation import Pulse
    from isorock.physics.model import Block, FPIsolation, LinearIsolation, NoIsolation, System
    from isorock.physics.overturning import check_search, min_overturn_amplitude

    isolations = {
        "none": NoIsolation(),
        "linear": LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5),
        "fp": FPIsolation(mu_b=0.11, R_b=2.24, rho=0.5),
    }
    blocks = [(4.0, 1.0), (4.0, 3.0), (6.0, 6.0)]
    pulses = [Pulse("halfsine", 0.5), Pulse("fullsine", 0.5), Pulse("fullsine", 1.5)]
    jobs = [(lam, R, pulse, name) for lam, R in blocks for pulse in pulses for name in isolations]
    check_amplitude(a.pga_max, "--pga-max")  # before the progress bar
    check_search(amp_max=a.pga_max)
    rows = []
    t0 = time.perf_counter()
    for lam, R, pulse, name in tqdm(jobs, desc="min-overturn searches", disable=a.json, unit="search"):
        system = System(Block.from_lambda_R(lam, R), isolations[name])
        m = min_overturn_amplitude(system, pulse, amp_max=a.pga_max)
        rows.append(
            {
                "lambda": lam,
                "R_m": R,
                "pulse": pulse.shape,
                "td_s": pulse.td,
                "isolation": name,
                **m.to_dict(),
            }
        )
    secs = time.perf_counter() - t0
    if a.json:
        print_json({"rows": rows, "seconds": secs})
        return 0
    print(
        f"\nMinimum overturning amplitude [g] (uplift amplitude in brackets); rho=0.5, linear Tb=3 s "
        f"xi=0.35, FP mu=0.11 Rb=2.24 m; '-' = no overturn up to {a.pga_max:g} g"
    )
    print(f"{'lambda':>6s} {'R m':>5s} {'pulse':>13s} " + " ".join(f"{n:>20s}" for n in isolations))
    for i in range(0, len(rows), len(isolations)):
        grp = rows[i : i + len(isolations)]
        r0 = grp[0]
        cells = []
        for r in grp:
            mo = "-" if r["min_overturn_g"] is None else f"{r['min_overturn_g']:.3f}"
            cells.append(f"{mo:>11s} ({r['uplift_g']:.3f})")
        print(
            f"{r0['lambda']:6.1f} {r0['R_m']:5.1f} {r0['pulse'] + ' ' + format(r0['td_s'], 'g') + 's':>13s} "
            + " ".join(f"{c:>20s}" for c in cells)
        )
    print(f"\n{sum(r['n_analyses'] for r in rows)} analyses in {secs:.1f} s")
    return 0
