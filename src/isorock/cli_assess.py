"""``isorock map lambda-R`` and ``isorock map Tb-xi``: response-regime maps."""

from __future__ import annotations

import argparse
import time

import numpy as np

from .cli_engine import add_system_options, excitation_from_args, system_from_args
from .errors import IsorockError
from .excitation import PULSE_SHAPES
from .model import Block

UNITS = ("g", "m/s2", "cm/s2")


def _excitation_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("excitation (a pulse or a record)")
    src = g.add_mutually_exclusive_group(required=True)
    src.add_argument("--pulse", choices=PULSE_SHAPES, help="pulse shape (paper Eqs. 36-38)")
    src.add_argument("--record", metavar="FILE", help="accelerogram file")
    g.add_argument("--td", type=float, default=None, help="pulse half-cycle duration [s]")
    g.add_argument("--amp", type=float, default=None, help="pulse amplitude [g]")
    g.add_argument("--pga", type=float, default=None, help="record scaled to this PGA [g]")
    g.add_argument("--dt", type=float, default=None, help="record time step [s] (one-column files)")
    g.add_argument("--units", choices=UNITS, default=None, help="record units (default g)")
    g.add_argument("--format", dest="fmt", default=None, help="record format")
    g.add_argument("--component", default=None, help="component of a multi-component file (e.g. N-S)")


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--jobs", type=int, default=None, help="parallel threads (default: all cores)")
    p.add_argument("--out", default=None, help="write the map to this HDF5 file")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _range(vals: list[float], n: int, name: str) -> np.ndarray:
    lo, hi = vals
    if not (hi >= lo) or n < 1:
        raise IsorockError(f"--{name}-range {lo} {hi} with --n-{name} {n}: need low <= high and n >= 1")
    return np.linspace(lo, hi, n)


def _amp(a: argparse.Namespace) -> float:
    amp = a.amp if a.pulse else a.pga
    if amp is None:
        raise IsorockError("--pulse needs --amp (g)" if a.pulse else "--record needs --pga (g)")
    if not amp > 0:
        raise IsorockError(f"amplitude {amp} g must be > 0")
    return amp


def cmd_map(a: argparse.Namespace) -> int:
    from .assess import regime_map_lambda_R, regime_map_Tb_xi
    from .cli import print_json

    a.amp_for_pulse = a.amp
    amp = _amp(a)
    a.amp = 1.0
    exc, _ = excitation_from_args(a, with_amplitude=False)
    progress = not a.json
    t0 = time.perf_counter()
    if a.grid == "lambda-R":
        lams = _range(a.lambda_range, a.n_lambda, "lambda")
        Rs = _range(a.R_range, a.n_R, "R")
        a.lam, a.R = float(lams[-1]), float(Rs[0])
        iso = system_from_args(a).isolation
        m = regime_map_lambda_R(exc, iso, lams, Rs, amp, jobs=a.jobs, progress=progress)
    else:
        Tbs = _range(a.Tb_range, a.n_Tb, "Tb")
        xis = _range(a.xi_range, a.n_xi, "xi")
        if a.rho is None:
            raise IsorockError("map Tb-xi needs --rho (mass ratio)")
        m = regime_map_Tb_xi(exc, Block.from_lambda_R(a.lam, a.R), Tbs, xis, a.rho, amp, jobs=a.jobs,
                             progress=progress)
    secs = time.perf_counter() - t0
    if a.out:
        from .store import atomic_h5, write_map

        with atomic_h5(a.out) as f:
            write_map(f.create_group(f"maps/{a.grid}"), m)
    out = {
        "grid": a.grid,
        "shape": list(m.codes.shape),
        "axes": {m.x_name: [float(m.x[0]), float(m.x[-1])], m.y_name: [float(m.y[0]), float(m.y[-1])]},
        "counts": m.counts(),
        **m.counts(),
        "n_analyses": m.n_analyses,
        "seconds": secs,
        "amp_g": amp,
        "out": a.out,
    }
    if a.json:
        print_json(out)
        return 0
    c = m.counts()
    print(f"{a.grid} map {m.codes.shape[0]} x {m.codes.shape[1]} at {amp:g} g: no uplift {c['no_uplift']}, "
          f"rocking {c['rocking']}, overturn {c['overturn']}; {m.n_analyses} analyses in {secs:.2f} s"
          + (f"; written to {a.out}" if a.out else ""))
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("map", help="response-regime maps (no uplift / rocking / overturn)")
    grids = p.add_subparsers(dest="grid", metavar="GRID", required=True)

    q = grids.add_parser("lambda-R", help="map over slenderness and block size")
    _excitation_options(q)
    add_system_options(q)
    for act in q._actions:  # lambda and R are the axes here
        if act.dest in ("lam", "R"):
            act.required = False
    q.add_argument("--lambda-range", nargs=2, type=float, default=[1.5, 8.0], metavar=("LO", "HI"))
    q.add_argument("--R-range", nargs=2, type=float, default=[0.5, 15.0], metavar=("LO", "HI"), help="[m]")
    q.add_argument("--n-lambda", type=int, default=100)
    q.add_argument("--n-R", type=int, default=60)
    _common(q)
    q.set_defaults(func=cmd_map)

    q = grids.add_parser("Tb-xi", help="map over isolation period and damping (linear isolator)")
    _excitation_options(q)
    q.add_argument("--lambda", dest="lam", type=float, required=True, help="slenderness h/b [-]")
    q.add_argument("--R", dest="R", type=float, required=True, help="half-diagonal of the block [m]")
    q.add_argument("--rho", type=float, default=None, help="block-to-base mass ratio [-]")
    q.add_argument("--isolation", choices=("linear",), default="linear", help="isolation model (linear)")
    q.add_argument("--Tb-range", nargs=2, type=float, default=[0.5, 5.0], metavar=("LO", "HI"), help="[s]")
    q.add_argument("--xi-range", nargs=2, type=float, default=[0.0, 0.5], metavar=("LO", "HI"))
    q.add_argument("--n-Tb", type=int, default=60)
    q.add_argument("--n-xi", type=int, default=40)
    _common(q)
    q.set_defaults(func=cmd_map)
