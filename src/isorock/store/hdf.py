"""HDF5 attributes (written and read back), pandas tables with their units, the dimension scales that name
the axes of the arrays (netCDF-4 style: xarray reads them as named dimensions and coordinates), and
merging job files."""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pandas as pd
import tables as tb

from isorock.store.layout import COLUMN_UNITS

__all__ = [
    "set_attrs",
    "attr",
    "attrs_dict",
    "write_tables",
    "read_table",
    "read_tables",
    "NOT_A_VARIABLE",
    "coordinate",
    "dimension",
    "time_coordinate",
    "attach_dims",
    "merge_h5",
]


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


#: the ``NAME`` of a dimension scale that is a dimension without values (netCDF-4's convention, followed by
#: netCDF-C and h5netcdf: such a dataset is a dimension, not a variable)
NOT_A_VARIABLE = "This is a netCDF dimension but not a netCDF variable."


def coordinate(
    group: h5py.Group, name: str, values: Any, *, units: str, long_name: str = "", **kwargs: Any
) -> h5py.Dataset:
    """A 1-D dataset that is an HDF5 dimension scale named ``name``: the coordinate of the axes it is
    attached to (:func:`attach_dims`; xarray reads it as the coordinate and dimension ``name``).

    Parameters
    ----------
    group : h5py.Group
        Where it is written.
    name : str
        Dataset, scale and dimension name.
    values : array-like
        The coordinate values (float).
    units : str
        Attribute ``units`` (``-``: dimensionless).
    long_name : str, optional
        Attribute ``long_name`` (xarray labels plots with it).
    **kwargs
        Passed to :meth:`h5py.Group.create_dataset` (compression).
    """
    ds = group.create_dataset(name, data=np.asarray(values, dtype=float), **kwargs)
    ds.make_scale(name)
    ds.attrs["units"] = units
    if long_name:
        ds.attrs["long_name"] = long_name
    return ds


def dimension(group: h5py.Group, name: str, size: int) -> h5py.Dataset:
    """A dimension without values (a count: lines, steps), as netCDF-4 writes one: a dimension scale whose
    ``NAME`` is :data:`NOT_A_VARIABLE` and the size, never written (it takes no space in the file; h5py
    reads it as zeros). xarray lists it under "Dimensions without coordinates"."""
    ds = group.create_dataset(name, shape=(int(size),), dtype="f4")
    ds.make_scale(f"{NOT_A_VARIABLE}{int(size):10d}")
    return ds


def time_coordinate(group: h5py.Group, n: int, dt: float) -> h5py.Dataset:
    """The coordinate ``time_s`` [s] of a sampled history: ``k dt`` for ``k = 0 .. n-1``."""
    ds = coordinate(
        group, "time_s", np.arange(int(n)) * float(dt), units="s", long_name="time",
        compression="gzip", shuffle=True,
    )  # fmt: skip
    ds.attrs["dt_s"] = float(dt)
    return ds


def attach_dims(ds: h5py.Dataset, *scales: h5py.Dataset) -> None:
    """Attach one dimension scale to each axis of ``ds``, in order (a scale named ``time_s`` makes the
    axis the dimension ``time_s`` for netCDF-4 readers such as xarray with h5netcdf).

    Raises
    ------
    ValueError
        Not one scale per axis, or a scale's length differs from its axis.
    """
    if len(scales) != ds.ndim:
        raise ValueError(f"{ds.name}: {ds.ndim} axes, {len(scales)} dimension scales")
    for i, s in enumerate(scales):
        if s.shape != (ds.shape[i],):
            raise ValueError(f"{ds.name}: axis {i} has {ds.shape[i]} values, its scale {s.name} {s.shape}")
        ds.dims[i].attach_scale(s)


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

    Notes
    -----
    Every table group also gets the dataset ``row`` (layout 5): a dimension without values
    (:func:`dimension`) as long as the table. HDF5 attaches no dimension scale to a PyTables table
    (``H5DSattach_scale`` refuses a dataset of class ``TABLE``, and PyTables, hence pandas, could not
    read a table that carried one); netCDF-4 readers give an axis that has no scale the dimension of
    its group that has its length, so that xarray (h5netcdf) reads the table as the variable ``table``
    (a record per row) of dimension ``row``, with no invented ``phony_dim``.
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
            if "row" in g:  # a table written again (an older length)
                del g["row"]
            dimension(g, "row", g["table"].shape[0])
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


def read_tables(path: str | os.PathLike, keys: Sequence[str]) -> list:
    """The tables ``keys`` of one file written by :func:`write_tables`, read through one open file (the
    same tables as :func:`read_table` of each: opening the file is most of the time of a small one)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tb.NaturalNameWarning)
        with pd.HDFStore(path, mode="r") as store:
            return [store.select(k) for k in keys]


def _scale_links(src: h5py.File, skip: set[str]) -> list[tuple[str, list[list[str]]]]:
    """The datasets of ``src`` with dimension scales: (path, the paths of each axis' scales), relative to
    the root."""
    out: list[tuple[str, list[list[str]]]] = []

    def visit(name: str, obj: Any) -> None:
        if name.split("/")[0] in skip or not isinstance(obj, h5py.Dataset):
            return
        if "DIMENSION_LIST" in obj.attrs:
            out.append((name, [[s.name.lstrip("/") for s in obj.dims[i].values()] for i in range(obj.ndim)]))

    src.visititems(visit)
    return out


def _reattach(dst: h5py.Group, links: list[tuple[str, list[list[str]]]]) -> None:
    """Attach again, in ``dst``, the dimension scales of datasets copied from another file.

    An HDF5 copy between files keeps the attributes ``DIMENSION_LIST`` (on a dataset) and
    ``REFERENCE_LIST`` (on a scale) as they were, references into the other file that point nowhere in
    this one: they are removed and written again by attaching the same scales by path.
    """
    scales = {p for _, axes in links for ax in axes for p in ax if p in dst}
    for p in sorted(scales):
        if "REFERENCE_LIST" in dst[p].attrs:
            del dst[p].attrs["REFERENCE_LIST"]
    for path, axes in links:
        if path not in dst:
            continue
        ds = dst[path]
        if "DIMENSION_LIST" in ds.attrs:
            del ds.attrs["DIMENSION_LIST"]
        if all(p in scales for ax in axes for p in ax):  # else (a scale not copied) none: no phony link
            for i, ax in enumerate(axes):
                for p in ax:
                    ds.dims[i].attach_scale(dst[p])


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
    not copied. Dimension scales (:func:`attach_dims`) are attached again in ``dst`` to the same
    scales, by path: the copy of a file's tree keeps references into the file it came from.

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
            links = _scale_links(src, skip)
            for name, obj in src.items():
                if name in skip:
                    continue
                if name in dst and isinstance(obj, h5py.Group) and isinstance(dst[name], h5py.Group):
                    _merge_group(obj, dst[name], str(s))
                elif name in dst:
                    raise ValueError(f"{s}: /{name} is written by two jobs")
                else:
                    src.copy(obj, dst, name=name)
            _reattach(dst, links)
