"""``isorock simulate`` and ``isorock min-overturn``: one analysis, or the minimum overturning amplitude."""

from __future__ import annotations

import argparse
import time

from .errors import IsorockError
from .excitation import PULSE_SHAPES, Excitation, GroundMotion, Pulse, load_plain_record
from .model import Block, FPIsolation, LinearIsolation, NoIsolation, System

UNITS = ("g", "m/s2", "cm/s2")


def add_system_options(p: argparse.ArgumentParser) -> None:
    """Block and isolation options shared by the analysis commands."""
    g = p.add_argument_group("block and isolation")
    g.add_argument("--lambda", dest="lam", type=float, required=True, help="slenderness h/b [-]")
    g.add_argument("--R", dest="R", type=float, required=True, help="half-diagonal of the block [m]")
    g.add_argument("--isolation", choices=("none", "linear", "fp"), default="none", help="isolation model")
    g.add_argument("--Tb", type=float, default=None, help="isolation period [s] (linear; fp if --Rb absent)")
    g.add_argument("--xi", type=float, default=None, help="isolation damping ratio [-] (linear)")
    g.add_argument("--rho", type=float, default=None, help="block-to-base mass ratio m/m_b [-]")
    g.add_argument("--mu", type=float, default=None, help="FP friction coefficient [-]")
    g.add_argument("--Rb", type=float, default=None, help="FP radius of curvature [m]")


def add_excitation_options(p: argparse.ArgumentParser, *, with_amplitude: bool) -> None:
    """Pulse or record options shared by the analysis commands."""
    g = p.add_argument_group("excitation (a pulse or a record)")
    src = g.add_mutually_exclusive_group(required=True)
    src.add_argument("--pulse", choices=PULSE_SHAPES, help="pulse shape (paper Eqs. 36-38)")
    src.add_argument("--record", metavar="FILE", help="accelerogram file")
    g.add_argument("--td", type=float, default=None, help="pulse half-cycle duration [s]")
    if with_amplitude:
        g.add_argument("--amp", type=float, default=None, help="pulse amplitude [g]")
        g.add_argument("--scale", type=float, default=1.0, help="factor on the record [-] (default 1)")
    g.add_argument("--dt", type=float, default=None, help="record time step [s] (one-column files)")
    g.add_argument("--units", choices=UNITS, default=None, help="record units (default g)")
    g.add_argument("--format", dest="fmt", default=None, help="record format (see 'isorock records')")
    g.add_argument("--component", default=None, help="component of a multi-component file (e.g. N-S)")


def system_from_args(a: argparse.Namespace) -> System:
    """Build the :class:`System` named by the command-line options."""
    block = Block.from_lambda_R(a.lam, a.R)

    def need(name: str, value: float | None, flag: str) -> float:
        if value is None:
            raise IsorockError(f"--isolation {a.isolation} needs {flag} ({name})")
        return value

    if a.isolation == "none":
        iso = NoIsolation()
    elif a.isolation == "linear":
        iso = LinearIsolation(
            Tb=need("isolation period, s", a.Tb, "--Tb"),
            xi_b=need("damping ratio", a.xi, "--xi"),
            rho=need("mass ratio", a.rho, "--rho"),
        )
    else:
        mu = need("friction coefficient", a.mu, "--mu")
        rho = need("mass ratio", a.rho, "--rho")
        if a.Rb is not None:
            iso = FPIsolation(mu_b=mu, R_b=a.Rb, rho=rho)
        elif a.Tb is not None:
            iso = FPIsolation.from_period(mu_b=mu, Tb=a.Tb, rho=rho)
        else:
            raise IsorockError("--isolation fp needs --Rb (radius, m) or --Tb (period, s)")
    return System(block, iso)


def load_record(
    path: str, *, fmt: str | None, dt: float | None, units: str | None, component: str | None
) -> GroundMotion:
    """Read a record through the ObsPy readers when available, else as a plain numeric file."""
    try:
        from .io import read_record, to_ground_motion  # records front end
    except ImportError:  # pragma: no cover - front end not installed
        read_record = None
    if read_record is not None:
        plain = fmt in (None, "one-column", "two-column")
        try:
            st = read_record(path, fmt, dt=dt, units=units, component=component)
        except IsorockError:
            if not plain or fmt is not None:
                raise
            # autodetection failed: a plain numeric file with the user's dt/units
            return load_plain_record(path, dt=dt, units=units or "g")
        if len(st) != 1:
            comps = ", ".join(tr.stats.channel for tr in st)
            raise IsorockError(f"{path}: {len(st)} components ({comps}): choose one with --component")
        return to_ground_motion(st[0])
    return load_plain_record(path, dt=dt, units=units or "g")


def excitation_from_args(a: argparse.Namespace, *, with_amplitude: bool) -> tuple[Excitation, float]:
    """The excitation and the scale factor to apply to it."""
    if a.pulse:
        if a.td is None:
            raise IsorockError("--pulse needs --td (half-cycle duration, s)")
        if with_amplitude:
            if a.amp is None:
                raise IsorockError("--pulse needs --amp (amplitude, g)")
            return Pulse(a.pulse, a.td, a.amp), 1.0
        return Pulse(a.pulse, a.td, 1.0), 1.0
    gm = load_record(a.record, fmt=a.fmt, dt=a.dt, units=a.units, component=a.component)
    scale = getattr(a, "scale", 1.0) if with_amplitude else 1.0
    if not scale > 0:
        raise IsorockError(f"--scale {scale} must be > 0")
    return gm, scale


def cmd_simulate(a: argparse.Namespace) -> int:
    from .cli import print_json
    from .engine import simulate

    system = system_from_args(a)
    exc, scale = excitation_from_args(a, with_amplitude=True)
    t0 = time.perf_counter()
    res = simulate(system, exc, scale=scale)
    secs = time.perf_counter() - t0
    out = res.to_dict()
    out["pga_g"] = exc.pga_g * scale
    out["alpha_rad"] = system.alpha
    out["seconds"] = secs
    if a.json:
        print_json(out)
        return 0
    print(f"block: lambda={a.lam:g}, R={a.R:g} m, alpha={system.alpha:.4f} rad; isolation: {a.isolation}")
    print(f"input: {exc.describe()}" + (f", scaled x{scale:g}" if scale != 1.0 else ""))
    print(f"outcome: {res.outcome}")
    print(f"max |theta|/alpha: {res.max_theta_over_alpha:.4f}   impacts: {res.n_impacts}")
    print(f"max base displacement: {res.max_base_disp_m:.4f} m")
    if res.t_uplift_s is not None:
        print(f"uplift at t = {res.t_uplift_s:.4f} s")
    if res.t_overturn_s is not None:
        print(f"overturn at t = {res.t_overturn_s:.4f} s")
    return 0


def cmd_min_overturn(a: argparse.Namespace) -> int:
    from .assess import min_overturn_amplitude
    from .cli import print_json

    system = system_from_args(a)
    exc, _ = excitation_from_args(a, with_amplitude=False)
    t0 = time.perf_counter()
    m = min_overturn_amplitude(system, exc, amp_max=a.amp_max, growth=a.growth)
    secs = time.perf_counter() - t0
    out = m.to_dict()
    out["tan_alpha"] = system.block.tan_alpha
    out["seconds"] = secs
    if a.json:
        print_json(out)
        return 0
    print(
        f"block: lambda={a.lam:g}, R={a.R:g} m, tan(alpha)={system.block.tan_alpha:.4f}; "
        f"isolation: {a.isolation}"
    )
    print(f"uplift amplitude: {m.uplift_g:.5g} g")
    if m.min_overturn_g is None:
        print(f"no overturning up to {a.amp_max:g} g")
    else:
        print(
            f"minimum overturning amplitude: {m.min_overturn_g:.6g} g "
            f"({m.min_overturn_over_tan_alpha:.5g} x tan(alpha)), resolution {m.resolution:.1e}"
        )
    print(f"{m.n_analyses} analyses in {secs:.2f} s")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help="one analysis of a block under a pulse or a record")
    add_system_options(p)
    add_excitation_options(p, with_amplitude=True)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("min-overturn", help="minimum overturning amplitude (PGA) and uplift amplitude")
    add_system_options(p)
    add_excitation_options(p, with_amplitude=False)
    p.add_argument("--amp-max", type=float, default=5.0, help="largest amplitude scanned [g] (default 5)")
    p.add_argument("--growth", type=float, default=1.005, help="ratio of the scan grid (default 1.005)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_min_overturn)

    register_demo(sub)


def cmd_demo(a: argparse.Namespace) -> int:
    """Minimum overturning amplitude of a few blocks under the paper's pulses, three isolation cases."""
    from tqdm import tqdm

    from .assess import min_overturn_amplitude
    from .cli import print_json

    isolations = {
        "none": NoIsolation(),
        "linear": LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5),
        "fp": FPIsolation(mu_b=0.11, R_b=2.24, rho=0.5),
    }
    blocks = [(4.0, 1.0), (4.0, 3.0), (6.0, 6.0)]
    pulses = [Pulse("halfsine", 0.5), Pulse("fullsine", 0.5), Pulse("fullsine", 1.5)]
    jobs = [(lam, R, pulse, name) for lam, R in blocks for pulse in pulses for name in isolations]
    rows = []
    t0 = time.perf_counter()
    for lam, R, pulse, name in tqdm(jobs, desc="min-overturn searches", disable=a.json, unit="search"):
        system = System(Block.from_lambda_R(lam, R), isolations[name])
        m = min_overturn_amplitude(system, pulse, amp_max=a.amp_max)
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
        f"xi=0.35, FP mu=0.11 Rb=2.24 m; '-' = no overturn up to {a.amp_max:g} g"
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


def register_demo(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("demo", help="demonstration: minimum overturning amplitudes under the paper's pulses")
    p.add_argument("--amp-max", type=float, default=3.0, help="largest amplitude scanned [g] (default 3)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_demo)
