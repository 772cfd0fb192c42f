"""The job files of an assessment: their top-level groups, the tables they hold (read in the order of
their records) and the intensity measures added to every run; read by the stripes' and the design
search's jobs (:mod:`~.assessment`, :mod:`~.design`) and the merge."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from typing import Any

import h5py
import numpy as np
import pandas as pd

from isorock.parallel import fork_map
from isorock.store.hdf import read_tables

__all__ = ["ASSESS_KEY", "DESIGN_KEY"]

#: top-level groups of the job files (not copied into the store: the merge derives /assessment; the
#: merge skips these names)
ASSESS_KEY = "assess_jobs"
DESIGN_KEY = "design_jobs"


def _period(iso: Any) -> float | None:
    """The isolation period of a base [s] (None for the fixed base): Tb, or 2 pi sqrt(R_b / g) of an FP."""
    return None if iso.kind == "none" else float(iso.Tb)


def _add_measures(runs: pd.DataFrame, gm: Any, periods: Sequence[float | None]) -> pd.DataFrame:
    """The other intensity measures of every run, beside its PGA: ``pgv_m_s`` [m/s] and ``sa_g`` [g], the
    5 %-damped Sa at the base's isolation period ``sa_period_s`` [s] (NaN on a fixed base), each the
    record's value times the run's scale (every measure is linear in the scale:
    :mod:`isorock.processing.intensity`). ``periods`` holds the period of each system (column ``system``)."""
    from isorock.errors import ParameterError
    from isorock.processing.intensity import intensity

    pgv = intensity(gm, "pgv")
    sa = {}
    for T in {t for t in periods if t is not None}:
        try:
            sa[T] = intensity(gm, "sa", period_s=T)
        except ParameterError:  # a period beyond the record's duration: no Sa for it
            sa[T] = math.nan
    T_of = np.array([math.nan if t is None else t for t in periods])[runs["system"].to_numpy()]
    sa_of = np.array([math.nan if t is None else sa[t] for t in periods])[runs["system"].to_numpy()]
    out = runs.copy()
    out["pgv_m_s"] = out["scale"].to_numpy() * pgv
    out["sa_g"] = out["scale"].to_numpy() * sa_of
    out["sa_period_s"] = T_of
    return out


def _table_keys(group: h5py.Group) -> list[str]:
    """Paths (relative to ``group``) of the pandas tables under it."""
    keys: list[str] = []

    def visit(name: str, obj: Any) -> None:
        if obj.attrs.get("pandas_type") is not None:
            keys.append(name)

    group.visititems(visit)
    return keys


def _job_tables(
    paths: Iterable[str | os.PathLike], top: str, workers: int = 1
) -> list[tuple[pd.DataFrame, dict]]:
    """The tables under ``top`` of the job files ``paths`` with their attributes, file after file and,
    in a file, in the order of its records; the files read by ``workers`` processes."""
    with_top = []
    for p in paths:
        with h5py.File(p, "r") as h:
            if top in h:
                with_top.append(p)
    return [t for tables in fork_map(lambda p: _file_tables(p, top), with_top, workers) for t in tables]


def _file_tables(p: str | os.PathLike, top: str) -> list[tuple[pd.DataFrame, dict]]:
    with h5py.File(p, "r") as h:
        keys = _table_keys(h[top])
        attrs = {k: {a: h[f"{top}/{k}"].attrs[a] for a in h[f"{top}/{k}"].attrs} for k in keys}
    # a block's tables in the order of its records (the order of the job's inputs)
    keys.sort(key=lambda k: int(attrs[k].get("position", 0)))
    return [
        (df, {a: (v.decode() if isinstance(v, bytes) else v) for a, v in attrs[k].items()})
        for k, df in zip(keys, read_tables(p, [f"{top}/{k}" for k in keys]), strict=True)
    ]
