"""HDF5 attributes (written and read back), pandas tables with their units, and merging job files."""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pandas as pd
import tables as tb

from .layout import COLUMN_UNITS

__all__ = ["set_attrs", "attr", "attrs_dict", "write_tables", "read_table", "merge_h5"]


def _attr_value(v: Any) -> Any:
    """A value h5py can store as an attribute: None -> NaN, bool -> int8 0/1, dict/list of non-numbers
    -> JSON."""
    if v is None:
        return np.nan
    if isinstance(v, (bool, np.bool_)):
        return np.int8(v)  # an HDF5 boolean attribute makes PyTables (pandas) warn: stored as 0 / 1
    if isinstance(v, (int, float, str, np.integer, np.floating)):
        return v
    if isinstance(v, Path):
        return str(v)
    if isinstance(v, (list, tuple)) and v and all(isinstance(x, (int, float)) for x in v):
        return np.asarray(v, dtype=float)
    return json.dumps(v, default=str)


def set_attrs(obj: h5py.HLObject, attrs: Mapping[str, Any]) -> None:
    """Set attributes, turning None into NaN and mappings or mixed lists into JSON text."""
    for k, v in attrs.items():
        obj.attrs[k] = _attr_value(v)


def _decode(v: Any) -> Any:
    """An attribute as read by h5py -> a plain Python value (bytes -> str, 1-element arrays and
    numpy scalars -> Python scalars)."""
    if isinstance(v, bytes):
        v = v.decode()
    if isinstance(v, np.ndarray) and v.size == 1:
        v = v.item()
    if isinstance(v, np.generic):
        v = v.item()
    return v


def attr(obj: h5py.HLObject, key: str, default: Any = math.nan) -> Any:
    """One attribute of an HDF5 object as a plain Python value (``default`` when absent).

    This is the one place where attributes are decoded: strings come back as ``str``, numbers as
    ``int``/``float``/``bool``, numeric arrays stay arrays.
    """
    return _decode(obj.attrs[key]) if key in obj.attrs else default


def attrs_dict(obj: h5py.HLObject) -> dict[str, Any]:
    """All attributes of an HDF5 object as plain Python values (see :func:`attr`)."""
    return {k: _decode(v) for k, v in obj.attrs.items()}


def write_tables(
    path: str | os.PathLike, tables: Mapping[str, Any], attrs: Mapping[str, Mapping] | None = None
):
    """Write pandas tables (PyTables ``format="table"``) into an HDF5 file, then their attributes.

    Parameters
    ----------
    path : path-like
        An HDF5 file that no h5py handle holds open (created if absent, else added to): normally
        the temporary path of :func:`atomic_path`.
    tables : mapping of str to pandas.DataFrame
        Key (``"overturn/IMV79-EMO"``) to table; the index is not kept.
    attrs : mapping of str to mapping, optional
        Extra attributes of each table's group (key as in ``tables``). Every table group also gets
        ``units`` (JSON: column -> unit, for the columns with a unit) and ``columns`` (JSON list).
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tb.NaturalNameWarning)
        with pd.HDFStore(path, mode="a") as store:
            for key, df in tables.items():
                df = df.reset_index(drop=True)
                try:  # pandas >= 3: deterministic files
                    store.put(key, df, format="table", data_columns=True, index=False, track_times=False)
                except TypeError:  # older pandas: no track_times
                    store.put(key, df, format="table", data_columns=True, index=False)
    with h5py.File(path, "a") as f:
        for key, df in tables.items():
            g = f[key]
            units = {c: COLUMN_UNITS[c] for c in df.columns if c in COLUMN_UNITS}
            g.attrs["units"] = json.dumps(units)
            g.attrs["columns"] = json.dumps([str(c) for c in df.columns])
            if attrs and key in attrs:
                set_attrs(g, attrs[key])


def read_table(path: str | os.PathLike, key: str):
    """Read a table written by :func:`write_tables` (``pandas.read_hdf`` without the warning)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tb.NaturalNameWarning)
        return pd.read_hdf(path, key)


def _merge_group(src: h5py.Group, dst: h5py.Group, where: str) -> None:
    for k, v in src.attrs.items():
        dst.attrs[k] = v
    for name, obj in src.items():
        if isinstance(obj, h5py.Group) and name in dst and isinstance(dst[name], h5py.Group):
            if obj.attrs.get("pandas_type") is not None:
                raise ValueError(f"{where}: table {obj.name} is written by two jobs")
            _merge_group(obj, dst[name], where)
        elif name in dst:
            raise ValueError(f"{where}: {obj.name} is written by two jobs")
        else:
            src.copy(obj, dst, name=name)


def merge_h5(sources: Iterable[str | os.PathLike], dst: h5py.Group, *, skip: Iterable[str] = ()) -> None:
    """Merge the trees of several HDF5 files into ``dst`` (their union).

    Groups present in several files are merged (attributes updated, members added); a dataset
    or a pandas table present in two files is an error. The root attributes of the sources are
    not copied.

    Parameters
    ----------
    sources : iterable of path-like
        HDF5 files.
    dst : h5py.Group
        Destination (normally the root of an open file).
    skip : iterable of str
        Top-level names of the sources not copied.

    Raises
    ------
    ValueError
        Two sources write the same dataset or table.
    """
    skip = set(skip)
    for s in sources:
        with h5py.File(s, "r") as src:
            for name, obj in src.items():
                if name in skip:
                    continue
                if name in dst and isinstance(obj, h5py.Group) and isinstance(dst[name], h5py.Group):
                    _merge_group(obj, dst[name], str(s))
                elif name in dst:
                    raise ValueError(f"{s}: /{name} is written by two jobs")
                else:
                    src.copy(obj, dst, name=name)
