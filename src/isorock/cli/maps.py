"""``isorock map lambda-R`` and ``isorock map Tb-xi``: response-regime maps."""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np

from isorock.cli.options import (
    DeprecatedAlias,
    add_block_options,
    add_excitation_options,
    add_isolation_options,
    add_json_option,
    add_pga_option,
    block_from_args,
    block_text,
    excitation_from_args,
    isolation_from_args,
)
from isorock.cli.output import print_json
from isorock.errors import IsorockError
from isorock.plausibility import (
    PERIOD_MAX_S,
    PERIOD_MIN_S,
    R_MAX_M,
    RHO_MAX,
    XI_MAX,
    check_block_size,
    check_finite,
    check_isolator,
)

__all__ = ["register"]


def _range(vals: list[float], n: int, name: str) -> np.ndarray:
    lo, hi = vals
    for v in vals:
        check_finite({f"--{name}-range": v})
    if not (hi >= lo) or n < 1:
        raise IsorockError(f"--{name}-range {lo} {hi} with --n-{name} {n}: need low <= high and n >= 1")
    if name in ("lambda", "R") and not lo > 0:
        raise IsorockError(f"--{name}-range {lo} {hi}: a block's {name} must be > 0")
    if name == "R":  # the grids' block bound of the configuration (at most 100 m)
        check_block_size(R_m=hi, names={"R_m": "--R-range"})
    return np.linspace(lo, hi, n)


def _check_size(a: argparse.Namespace) -> str:
    """Refuse a map of more points than :data:`isorock.control.cost.MAX_ANALYSES` unless ``--force``:
    the points and the expected time at the engine's measured speed, in one line; returns that line
    (what ``--dry-run`` prints)."""
    from isorock.control.cost import MAP_MS, PULSE_MAP_MS, check_limit, format_duration

    nx, ny = (a.n_lambda, a.n_R) if a.grid == "lambda-R" else (a.n_Tb, a.n_xi)
    if nx < 1 or ny < 1:
        return ""  # _range says so
    n = nx * ny
    threads = a.threads or os.cpu_count() or 1
    kind = getattr(a, "isolation", "linear")
    ms = (PULSE_MAP_MS if a.pulse else MAP_MS).get(kind, max(MAP_MS.values()))
    what = f"map {a.grid} {nx} x {ny}: {n:,} analyses on {threads} thread(s)"
    check_limit(n, n * ms / 1000.0 / threads, what, force=a.force)
    return f"cost estimate: {what}, about {format_duration(n * ms / 1000.0 / threads)}"


def cmd_map(a: argparse.Namespace) -> int:
    """``isorock map``: a lambda-R or Tb-xi regime map, optionally written to HDF5 with its inputs."""
    from isorock.physics.model import isolation_params
    from isorock.physics.regime_maps import regime_map_lambda_R, regime_map_Tb_xi

    out_path = Path(a.out) if a.out else None
    if out_path is not None and out_path.exists() and not a.force:
        raise IsorockError(f"{out_path}: exists; give another --out, or --force to replace it")
    if not (a.pga > 0 and math.isfinite(a.pga)):
        raise IsorockError(f"--pga {a.pga} must be a number > 0 g")
    cost = _check_size(a)  # before a record is read or a grid made
    if a.dry_run:
        print(cost or "cost estimate: an empty grid")
        return 0
    # the block, the axes and the isolation before a record is read
    block, dims = block_from_args(a) if a.grid == "Tb-xi" else (None, {})
    if a.grid == "lambda-R":
        lams = _range(a.lambda_range, a.n_lambda, "lambda")
        Rs = _range(a.R_range, a.n_R, "R")
        iso = isolation_from_args(a)
    else:
        Tbs = _range(a.Tb_range, a.n_Tb, "Tb")
        xis = _range(a.xi_range, a.n_xi, "xi")
        for lo_hi, key, flag in ((a.Tb_range, "Tb_s", "--Tb-range"), (a.xi_range, "xi_b", "--xi-range")):
            for v in lo_hi:
                check_isolator("linear", **{key: v}, names={key: flag})
        check_isolator("linear", rho=a.rho, names={"rho": "--rho"})
    loaded = excitation_from_args(a, amplitude=False)
    exc, source = loaded.excitation, loaded.source
    progress = not a.json
    t0 = time.perf_counter()
    if a.grid == "lambda-R":
        m = regime_map_lambda_R(exc, iso, lams, Rs, a.pga, threads=a.threads, progress=progress)
        fixed = {"isolation": iso.kind, **isolation_params(iso)}
    else:
        m = regime_map_Tb_xi(exc, block, Tbs, xis, a.rho, a.pga, threads=a.threads, progress=progress)
        fixed = {"isolation": "linear", "lambda": dims["lambda"], "R_m": dims["R_m"], "rho": a.rho}
    secs = time.perf_counter() - t0
    inputs = _inputs(a, source, fixed)
    if out_path is not None:
        from isorock.store import atomic_h5, write_map  # h5py and pandas only for a map written to a file

        with atomic_h5(out_path) as f:
            write_map(f.create_group(f"maps/{a.grid}"), m, inputs)
    counts = m.counts()
    out = {
        "grid": a.grid,
        "shape": list(m.codes.shape),
        "axes": {m.x_name: [float(m.x[0]), float(m.x[-1])], m.y_name: [float(m.y[0]), float(m.y[-1])]},
        "counts": counts,
        **counts,
        "n_analyses": m.n_analyses,
        "seconds": secs,
        "pga_g": a.pga,
        "amp_g": a.pga,
        "out": a.out,
        **dims,
    }
    if source is not None:
        out["record_pga_g"] = exc.pga_g
        out["record"] = source.to_dict()
    if a.json:
        print_json(out)
        return 0
    nx, ny = m.codes.shape
    if dims:
        print(block_text(dims))
    if source is not None:
        own = exc.pga_g
        print(f"PGA applied: {a.pga:g} g (record's own PGA {own:.4g} g x scale factor {a.pga / own:.4g})")
    print(
        f"{a.grid} map {nx} x {ny} at PGA {a.pga:g} g: no uplift {counts['no_uplift']}, "
        f"rocking {counts['rocking']}, overturn {counts['overturn']}; {m.n_analyses} analyses in {secs:.2f} s"
        + (f"; written to {a.out}" if a.out else "")
    )
    return 0


def _inputs(a: argparse.Namespace, source, fixed: dict) -> dict:
    """The inputs of a map, as HDF5 attributes: the excitation (record provenance or pulse), the
    amplitude, the fixed parameters and the isolation."""
    d: dict = {"amp_source": "pga", "source_kind": "pulse" if a.pulse else "record", **fixed}
    if a.pulse:
        d.update({"source": f"pulse-{a.pulse}-td{a.td:g}", "pulse_shape": a.pulse, "td_s": a.td})
    else:
        from isorock.processing import steps_to_json

        r = source.to_dict()
        d.update(
            {
                "source": Path(source.file).name,
                "record_file": r["file"],
                "record_sha256": r["sha256"],
                "record_format": r["format"],
                "record_units": r["units"],
                "record_units_source": r["units_source"],
                "record_component": r["component"],
                "record_processing": r["processing"],
                "record_processing_json": steps_to_json(source.steps or []),
            }
        )
    return d


def _map_parser(grids: argparse._SubParsersAction, name: str, help_: str) -> argparse.ArgumentParser:
    q = grids.add_parser(name, help=help_)
    g = add_excitation_options(q)
    add_pga_option(
        g,
        required=True,
        what="PGA of the excitation [g]: the pulse amplitude, or the PGA the processed record is scaled to",
    )
    return q


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--threads",
        "--jobs",
        dest="threads",
        type=int,
        default=None,
        action=DeprecatedAlias,
        metavar="N",
        help="parallel threads (default: all cores); --jobs is its deprecated alias",
    )
    p.add_argument(
        "--out", default=None, metavar="FILE", help="write the map and its inputs to this HDF5 file"
    )
    p.add_argument(
        "--dry-run",
        "-n",
        action="store_true",
        help="print the map's cost estimate (analyses, expected time), compute nothing",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="replace an existing --out file; run a map of more than 50 million points",
    )
    add_json_option(p)
    p.set_defaults(func=cmd_map)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``map lambda-R`` and ``map Tb-xi``."""
    p = sub.add_parser("map", help="response-regime maps (no uplift / rocking / overturn)")
    grids = p.add_subparsers(
        dest="grid", metavar="GRID", required=True, help="'isorock map GRID --help' shows its options"
    )

    q = _map_parser(grids, "lambda-R", "map over slenderness and block size")
    add_isolation_options(q)  # lambda and R are the axes of this map: no --lambda/--R
    a = q.add_argument_group("grid (evenly spaced, both ends included)")
    a.add_argument(
        "--lambda-range",
        nargs=2,
        type=float,
        default=[1.5, 8.0],
        metavar=("LO", "HI"),
        help="range of the slenderness h/b (height over width) [-], LO > 0 (default 1.5 8)",
    )
    a.add_argument(
        "--R-range",
        nargs=2,
        type=float,
        default=[0.5, 15.0],
        metavar=("LO", "HI"),
        help=f"range of the block size R, the half-diagonal of the block [m], LO > 0, HI <= {R_MAX_M:g} "
        "(default 0.5 15)",
    )
    a.add_argument(
        "--n-lambda", type=int, default=100, metavar="N", help="number of lambda values [-] (default 100)"
    )
    a.add_argument("--n-R", type=int, default=60, metavar="N", help="number of R values [-] (default 60)")
    _common(q)

    q = _map_parser(grids, "Tb-xi", "map over isolation period and damping (linear isolator)")
    add_block_options(q)
    i = q.add_argument_group("isolation")
    i.add_argument(
        "--isolation", choices=("linear",), default="linear", help="isolation model (linear, the only one)"
    )
    i.add_argument(
        "--rho", type=float, required=True, help=f"block-to-base mass ratio m/m_b [-], 0 < rho <= {RHO_MAX:g}"
    )
    a = q.add_argument_group("grid (evenly spaced, both ends included)")
    a.add_argument(
        "--Tb-range",
        nargs=2,
        type=float,
        default=[0.5, 5.0],
        metavar=("LO", "HI"),
        help=f"range of the isolation period Tb [s], {PERIOD_MIN_S:g} to {PERIOD_MAX_S:g} (default 0.5 5)",
    )
    a.add_argument(
        "--xi-range",
        nargs=2,
        type=float,
        default=[0.0, 0.5],
        metavar=("LO", "HI"),
        help=f"range of the isolation damping ratio xi [-], 0 <= xi < {XI_MAX:g} (default 0 0.5)",
    )
    a.add_argument("--n-Tb", type=int, default=60, metavar="N", help="number of Tb values [-] (default 60)")
    a.add_argument("--n-xi", type=int, default=40, metavar="N", help="number of xi values [-] (default 40)")
    _common(q)
