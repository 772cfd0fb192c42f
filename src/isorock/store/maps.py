"""Regime maps in the store: one group per map (:func:`write_map`, :func:`read_map`) and the map index
(:func:`map_index_row`), computed once from the group attributes for ``/summary/maps`` and the reader."""

from __future__ import annotations

import json
import keyword
import math
import re
from collections.abc import Mapping
from typing import Any

import h5py
import numpy as np
import pandas as pd

from isorock.physics.result import RegimeMap
from isorock.store.hdf import attach_dims, attr, coordinate, set_attrs
from isorock.store.layout import MAP_AXIS_LONG_NAMES, MAP_AXIS_UNITS, MAP_INDEX_COLUMNS, OUTCOME_LEGEND

__all__ = ["write_map", "read_map", "node_name", "map_paths", "map_index_row", "map_index"]


def write_map(group: h5py.Group, m: RegimeMap, attrs: Mapping[str, Any] | None = None) -> None:
    """Write a :class:`isorock.physics.result.RegimeMap` into ``group`` (created by the caller).

    Parameters
    ----------
    group : h5py.Group
        Empty group.
    m : RegimeMap
        The map.
    attrs : mapping, optional
        Extra attributes (source, case, ...).
    """
    units = MAP_AXIS_UNITS
    group.attrs["kind"] = m.kind
    group.attrs["x_name"] = m.x_name
    group.attrs["y_name"] = m.y_name
    group.attrs["amp_g"] = m.amp_g
    group.attrs["amp_units"] = "g"
    group.attrs["n_analyses"] = m.n_analyses
    group.attrs["seconds"] = m.seconds
    group.attrs["fixed"] = json.dumps(m.fixed)
    group.attrs["outcome_legend"] = OUTCOME_LEGEND
    for k, v in m.fixed.items():
        if isinstance(v, (int, float, str)):
            group.attrs[f"fixed_{k}"] = v
    if attrs:
        attrs = {node_name(k): v for k, v in attrs.items()}
    # the axes are dimension scales (layout 5): xarray reads codes and max_theta_over_alpha with the
    # dimensions and coordinates lambda_ and R_m, or Tb_s and xi_b
    dx, dy = (
        coordinate(group, node_name(n), v, units=units.get(n, ""), long_name=MAP_AXIS_LONG_NAMES.get(n, ""))
        for n, v in ((m.x_name, m.x), (m.y_name, m.y))
    )
    dc = group.create_dataset("codes", data=np.asarray(m.codes, dtype=np.int8), compression="gzip")
    dc.attrs["legend"] = OUTCOME_LEGEND
    dc.attrs["dims"] = f"{m.x_name}, {m.y_name}"
    dc.attrs["long_name"] = "response regime"
    attach_dims(dc, dx, dy)
    dm = group.create_dataset(
        "max_theta_over_alpha", data=np.asarray(m.max_theta_over_alpha), compression="gzip"
    )
    dm.attrs["units"] = "-"
    dm.attrs["long_name"] = "peak rotation over alpha"
    dm.attrs["note"] = "partial where the outcome was decided early"
    attach_dims(dm, dx, dy)
    if attrs:
        set_attrs(group, attrs)


def node_name(name: str) -> str:
    """The HDF5 name of a column, dataset or attribute: a Python keyword (``lambda``) gets a trailing
    underscore, so that PyTables (pandas) reads the file without a NaturalNameWarning."""
    return name + "_" if keyword.iskeyword(name) else name


def read_map(group: h5py.Group) -> RegimeMap:
    """Read back a map written by :func:`write_map` as a :class:`isorock.physics.result.RegimeMap`."""
    xn, yn = group.attrs["x_name"], group.attrs["y_name"]
    return RegimeMap(
        kind=str(group.attrs["kind"]),
        x_name=str(xn),
        y_name=str(yn),
        x=group[node_name(str(xn))][()],
        y=group[node_name(str(yn))][()],
        codes=group["codes"][()],
        max_theta_over_alpha=group["max_theta_over_alpha"][()],
        amp_g=float(group.attrs["amp_g"]),
        fixed=json.loads(group.attrs["fixed"]),
        n_analyses=int(group.attrs["n_analyses"]),
        seconds=float(group.attrs["seconds"]),
    )


def map_paths(f: h5py.Group) -> list[str]:
    """HDF5 paths of all map groups under ``/maps`` (groups holding a ``codes`` dataset), sorted."""
    out: list[str] = []
    if "maps" not in f:
        return out

    def visit(name: str, obj) -> None:
        if isinstance(obj, h5py.Group) and "codes" in obj:
            out.append(obj.name)

    f["maps"].visititems(visit)
    return sorted(out)


_PULSE_SOURCE = re.compile(r"pulse-(rect|halfsine|fullsine)-td([0-9.eE+-]+)")
_INDEX_NUMBERS = (
    "Tb_s", "xi_b", "rho", "mu_b", "R_b_m", "lambda", "R_m", "td_s", "amp_g", "n_analyses", "seconds",
)  # fmt: skip


def _float(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def map_index_row(group: h5py.Group) -> dict[str, Any]:
    """The row of ``/summary/maps`` (:data:`~isorock.store.layout.MAP_INDEX_COLUMNS`) of one map group.

    Values come from the group's attributes, then from its ``fixed`` JSON, then from its path
    (``/maps/<source>/<map>``; a source ``pulse-<shape>-td<td>`` names a pulse); the regime counts
    from its ``codes``.
    """
    fixed = json.loads(attr(group, "fixed", "{}") or "{}")

    def get(key: str, *alt: str, default: Any = None) -> Any:
        for k in (key, *alt):
            if k in group.attrs:
                return attr(group, k)
            if k in fixed:
                return fixed[k]
        return default

    parts = group.name.strip("/").split("/")
    source = str(get("source", default=parts[1] if len(parts) > 2 else ""))
    shape = str(get("pulse_shape", default="") or "")
    td = _float(get("td_s"))
    m = _PULSE_SOURCE.fullmatch(source)
    if m:
        shape = shape or m.group(1)
        td = td if math.isfinite(td) else _float(m.group(2))
    codes = group["codes"][()]
    row: dict[str, Any] = {
        "path": group.name,
        "source": source,
        "source_kind": str(get("source_kind", default="pulse" if shape else "record")),
        "map": str(get("map", default=parts[-1])),
        "kind": str(get("kind", default="")),
        "case": str(get("case", default="")),
        "isolation": str(get("isolation", default="")),
        "pulse": shape,
        "amp_source": str(get("amp_source", default="")),
        "nx": int(codes.shape[0]),
        "ny": int(codes.shape[1]),
        "no_uplift": int(np.sum(codes == 0)),
        "rocking": int(np.sum(codes == 1)),
        "overturn": int(np.sum(codes == 2)),
    }
    for k in _INDEX_NUMBERS:
        row[node_name(k)] = _float(get(node_name(k), k))
    row["td_s"] = td
    return row


def map_index(f: h5py.Group) -> pd.DataFrame:
    """The index of every map under ``/maps`` of an open file: one :func:`map_index_row` per map."""
    rows = [map_index_row(f[p]) for p in map_paths(f)]
    return pd.DataFrame(rows, columns=list(MAP_INDEX_COLUMNS))
