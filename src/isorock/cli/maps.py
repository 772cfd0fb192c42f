"""``isorock map lambda-R`` and ``isorock map Tb-xi``: response-regime maps."""

from __future__ import annotations

import argparse
import time

import numpy as np

from ..errors import IsorockError
from .options import (
    add_block_options,
    add_excitation_options,
    add_isolation_options,
    add_json_option,
    add_pulse_options,
    excitation_from_args,
    isolation_from_args,
)
from .output import print_json

__all__ = ["register"]


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
    """``isorock map``: a lambda-R or Tb-xi regime map, optionally written to HDF5."""
    from ..assess import regime_map_lambda_R, regime_map_Tb_xi
    from ..model import Block
    from ..store import atomic_h5, write_map

    amp = _amp(a)
    exc, _ = excitation_from_args(a, amplitude=False)
    progress = not a.json
    t0 = time.perf_counter()
    if a.grid == "lambda-R":
        lams = _range(a.lambda_range, a.n_lambda, "lambda")
        Rs = _range(a.R_range, a.n_R, "R")
        m = regime_map_lambda_R(exc, isolation_from_args(a), lams, Rs, amp, jobs=a.jobs, progress=progress)
    else:
        Tbs = _range(a.Tb_range, a.n_Tb, "Tb")
        xis = _range(a.xi_range, a.n_xi, "xi")
        if a.rho is None:
            raise IsorockError("map Tb-xi needs --rho (mass ratio)")
        block = Block.from_lambda_R(a.lam, a.R)
        m = regime_map_Tb_xi(exc, block, Tbs, xis, a.rho, amp, jobs=a.jobs, progress=progress)
    secs = time.perf_counter() - t0
    if a.out:
        with atomic_h5(a.out) as f:
            write_map(f.create_group(f"maps/{a.grid}"), m)
    counts = m.counts()
    out = {
        "grid": a.grid,
        "shape": list(m.codes.shape),
        "axes": {m.x_name: [float(m.x[0]), float(m.x[-1])], m.y_name: [float(m.y[0]), float(m.y[-1])]},
        "counts": counts,
        **counts,
        "n_analyses": m.n_analyses,
        "seconds": secs,
        "amp_g": amp,
        "out": a.out,
    }
    if a.json:
        print_json(out)
        return 0
    nx, ny = m.codes.shape
    print(
        f"{a.grid} map {nx} x {ny} at {amp:g} g: no uplift {counts['no_uplift']}, "
        f"rocking {counts['rocking']}, overturn {counts['overturn']}; {m.n_analyses} analyses in {secs:.2f} s"
        + (f"; written to {a.out}" if a.out else "")
    )
    return 0


def _map_parser(grids: argparse._SubParsersAction, name: str, help_: str) -> argparse.ArgumentParser:
    q = grids.add_parser(name, help=help_)
    g = add_excitation_options(q)
    add_pulse_options(g, amplitude=True)
    g.add_argument("--pga", type=float, default=None, help="record scaled to this PGA [g]")
    return q


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--jobs", type=int, default=None, help="parallel threads (default: all cores)")
    p.add_argument("--out", default=None, help="write the map to this HDF5 file")
    add_json_option(p)
    p.set_defaults(func=cmd_map)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``map lambda-R`` and ``map Tb-xi``."""
    p = sub.add_parser("map", help="response-regime maps (no uplift / rocking / overturn)")
    grids = p.add_subparsers(dest="grid", metavar="GRID", required=True)

    q = _map_parser(grids, "lambda-R", "map over slenderness and block size")
    add_block_options(q, required=False)  # the axes of this map
    add_isolation_options(q)
    q.add_argument("--lambda-range", nargs=2, type=float, default=[1.5, 8.0], metavar=("LO", "HI"))
    q.add_argument("--R-range", nargs=2, type=float, default=[0.5, 15.0], metavar=("LO", "HI"), help="[m]")
    q.add_argument("--n-lambda", type=int, default=100)
    q.add_argument("--n-R", type=int, default=60)
    _common(q)

    q = _map_parser(grids, "Tb-xi", "map over isolation period and damping (linear isolator)")
    add_block_options(q)
    q.add_argument("--rho", type=float, default=None, help="block-to-base mass ratio [-]")
    q.add_argument("--isolation", choices=("linear",), default="linear", help="isolation model (linear)")
    q.add_argument("--Tb-range", nargs=2, type=float, default=[0.5, 5.0], metavar=("LO", "HI"), help="[s]")
    q.add_argument("--xi-range", nargs=2, type=float, default=[0.0, 0.5], metavar=("LO", "HI"))
    q.add_argument("--n-Tb", type=int, default=60)
    q.add_argument("--n-xi", type=int, default=40)
    _common(q)
