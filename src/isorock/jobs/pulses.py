"""The rule bodies of the paper's pulse studies (Figs 4-7): minimum overturning amplitude under one
pulse shape, and lambda-R regime maps under one pulse. No record files are needed."""

from __future__ import annotations

import math
import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict
from typing import Any

import h5py
import pandas as pd

from isorock.control.config import IsolationCase, case_from
from isorock.control.joblog import say
from isorock.jobs.record import block_columns, map_name_lr, search_row
from isorock.physics.excitation import Pulse
from isorock.physics.model import Block, System
from isorock.physics.regime_maps import regime_map_lambda_R
from isorock.store import PULSE_COLUMNS, atomic_path, config_hash, stamp, write_map, write_tables
from isorock.version import __version__

__all__ = ["pulse_overturn", "pulse_maps"]


def pulse_overturn(
    out: str | os.PathLike,
    *,
    shape: str,
    cases: Sequence[Mapping],
    search: Mapping,
    vs_R: Mapping,
    vs_omega: Mapping,
    vs_isolation: Mapping | None,
    **kw: Any,
) -> dict:
    """Rule ``pulse_overturn``: minimum overturning amplitude under one pulse shape (Figs 4, 5, 7).

    Parameters
    ----------
    out : path-like
        HDF5 file with the pandas tables ``/pulses/<shape>/overturn_R``, ``.../overturn_omega`` and
        (when ``vs_isolation`` is given) ``.../overturn_isolation`` (columns
        :data:`isorock.store.PULSE_COLUMNS`); :func:`merge` stacks them into ``/pulses/overturn_*``.
    shape : {"rect", "halfsine", "fullsine"}
        Pulse shape.
    cases : sequence of mapping
        Isolation cases of the curves vs R and vs omega_p.
    search : mapping
        ``amp_max_g`` [g], ``growth`` [-], ``rtol`` [-].
    vs_R : mapping
        ``td_s`` (one curve each) [s] and ``R_m`` (the abscissae) [m].
    vs_omega : mapping
        ``R_m`` (one curve each) [m] and ``omega_p_rad_s`` (the abscissae, ``td = pi / omega_p``).
    vs_isolation : mapping or None
        Fig 5: ``base`` (a linear case), ``R_m`` (curves at ``td_fixed_s``), ``td_s`` (curves at
        ``R_fixed_m``), and the values of ``Tb_s``, ``xi_b`` and ``rho`` varied one at a time.
    **kw
        ``lambda`` [-] (default 4).

    Returns
    -------
    dict of pandas.DataFrame
        The tables by key.
    """
    lam = float(kw.get("lambda", 4.0))
    objs = [case_from(c) for c in cases]
    t0 = time.perf_counter()

    def row(td: float, R: float, case: IsolationCase, series: str, param: str = "", value: float = math.nan):
        block = Block.from_lambda_R(lam, R)
        system = System(block, case.isolation())
        r = {
            "pulse": shape,
            "td_s": float(td),
            "omega_p_rad_s": math.pi / td,
            "series": series,
            "param": param,
            "value": float(value),
            **block_columns(block),
            **case.columns(),
        }
        r.update(search_row(system, Pulse(shape, td, 1.0), search))
        return r

    rows_R = [row(td, R, c, "td") for c in objs for td in vs_R["td_s"] for R in vs_R["R_m"]]
    rows_w = [
        row(math.pi / w, R, c, "R") for c in objs for R in vs_omega["R_m"] for w in vs_omega["omega_p_rad_s"]
    ]
    tables = {
        f"pulses/{shape}/overturn_R": pd.DataFrame(rows_R, columns=list(PULSE_COLUMNS)),
        f"pulses/{shape}/overturn_omega": pd.DataFrame(rows_w, columns=list(PULSE_COLUMNS)),
    }
    if vs_isolation:
        base = case_from(vs_isolation["base"])
        none = IsolationCase(name="none", kind="none")
        combos = [("R", R, vs_isolation["td_fixed_s"]) for R in vs_isolation["R_m"]]
        combos += [("td", vs_isolation["R_fixed_m"], td) for td in vs_isolation["td_s"]]
        rows_i = []
        for series, R, td in combos:
            rows_i.append(row(td, R, none, series, "none"))
            for param, key in (("Tb_s", "Tb_s"), ("xi_b", "xi_b"), ("rho", "rho")):
                for v in vs_isolation[key]:
                    c = IsolationCase(**{**asdict(base), key: float(v), "name": f"{base.name}:{param}={v:g}"})
                    rows_i.append(row(td, R, c, series, param, v))
        tables[f"pulses/{shape}/overturn_isolation"] = pd.DataFrame(rows_i, columns=list(PULSE_COLUMNS))
    secs = time.perf_counter() - t0
    n = sum(len(t) for t in tables.values())
    say(f"{shape}: {n} minimum-overturning searches in {secs:.1f} s")
    chash = config_hash(
        {
            "shape": shape,
            "cases": list(cases),
            "search": dict(search),
            "vs_R": dict(vs_R),
            "vs_omega": dict(vs_omega),
            "vs_isolation": vs_isolation,
            "lambda": lam,
        }
    )
    attrs = {
        k: {
            "pulse": shape,
            "config_hash": chash,
            "search": dict(search),
            "lambda": lam,
            "amplitude": "pulse amplitude A_g0 [g]",
            "isorock_version": __version__,
        }
        for k in tables
    }
    with atomic_path(out) as tmp:
        write_tables(tmp, {k: v for k, v in tables.items() if len(v)}, attrs)
    return tables


def pulse_maps(
    out: str | os.PathLike,
    *,
    source: str,
    shape: str,
    td_s: float,
    amp_g: float,
    lambdas: Sequence[float],
    Rs: Sequence[float],
    cases: Sequence[Mapping],
    threads: int = 1,
) -> list[str]:
    """Rule ``pulse_maps``: lambda-R regime maps under one pulse (Fig 6), one per isolation case.

    Parameters
    ----------
    out : path-like
        HDF5 file with ``/maps/<source>/lambda_R-<case>``.
    source : str
        ``pulse-<shape>-td<td_s>``.
    shape : str
        Pulse shape.
    td_s : float
        Pulse half-cycle duration [s].
    amp_g : float
        Pulse amplitude [g].
    lambdas, Rs : sequence of float
        Axes: slenderness [-] and size [m].
    cases : sequence of mapping
        Isolation cases.
    threads : int
        Threads of the compiled engine.
    """
    pulse = Pulse(shape, td_s, 1.0)
    chash = config_hash(
        {"source": source, "amp_g": amp_g, "lambdas": list(lambdas), "Rs": list(Rs), "cases": list(cases)}
    )
    written = []
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        root = h.create_group(f"maps/{source}")
        for c in cases:
            case = case_from(c)
            m = regime_map_lambda_R(pulse, case.isolation(), lambdas, Rs, amp_g, threads=threads)
            name = map_name_lr(case.name)
            attrs = {
                "source": source,
                "source_kind": "pulse",
                "map": name,
                "amp_source": "pulse",
                "pulse_shape": shape,
                "td_s": td_s,
                "omega_p_rad_s": math.pi / td_s,
                "config_hash": chash,
                **case.columns(),
            }
            write_map(root.create_group(name), m, attrs)
            written.append(f"/maps/{source}/{name}")
            say(f"{source}: {name} at {amp_g:g} g: {m.counts()} in {m.seconds:.1f} s")
    return written
