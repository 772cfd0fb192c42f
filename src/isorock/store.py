"""HDF5 store: self-describing results, written atomically.

The workflow (``Snakefile``, :mod:`isorock.pipeline`) writes one HDF5 file per job under ``results/``
and merges them into ``results/isorock.h5``. Every file is written under a temporary name in the
same directory and renamed when complete (:func:`atomic_path`, :func:`atomic_h5`), so a killed or
failed run never leaves a file under the final name that looks complete.

Reading
-------
Groups, arrays and attributes are plain HDF5 (``h5py``); every table is also a pandas table
(``pandas.read_hdf(path, key)``, PyTables ``format="table"``). Units are in the attribute ``units``
of a dataset, in the column names (``_g``, ``_m``, ``_s``, ``_m_s``, ``_rad_s``; ``lambda``, ``xi_b``
and ``rho`` are dimensionless) and, for tables, in the JSON attribute ``units`` of the table's
group. Missing numbers are NaN. Record ids such as ``IMV79-EMO`` are not Python identifiers, so
PyTables warns (``NaturalNameWarning``) when they are used as keys; the warning is harmless.

Layout of ``results/isorock.h5`` (``layout_version`` 1)
--------------------------------------------------------
::

    /                                   attrs: isorock_version, layout_version, config_hash (sha256 of
                                        the validated configuration, canonical JSON), config_json,
                                        created_utc, outcome_legend, record_source (where the records
                                        came from: "records directory DIR" | "pyslammer samples")
    /records/<id>                       one group per record (process_record, extract_pulse)
        attrs                           id, label, event, year (-1 if unknown), station, component,
                                        catalog_id ("" if none), record_source,
                                        source_file, source_format, file_units, record_sha256 (sha256
                                        of the file read), candidates (JSON: the files considered, the
                                        one chosen),
                                        substitute (bool), npts, dt_s, duration_s, pga_g, pga_m_s2, pgv_m_s,
                                        pgd_m, arias_m_s, d5_95_s, final_disp_m, qa_passed, qa_reasons (JSON),
                                        table1_pga_g, table1_pgv_m_s, table1_tp_s (NaN if not a catalog row),
                                        Tp_s (wavelet), Tp_mp_s (Mavroeidis-Papageorgiou), pulse_like,
                                        pulse_indicator, config_hash, isorock_version
        acc                 (npts,)     processed ground acceleration [m/s^2]; attrs units, dt_s
        processing          (n,)        processing history, one line per step (str)
        pulse/                          attrs: isorock.pulse.PulseResult.summary() (Tp_s, Tp_mp_s, mp_*, ...)
            velocity        (npts,)     ground velocity [m/s]
            pulse_velocity  (npts,)     extracted (db4 wavelet) velocity pulse [m/s]
            mp_velocity     (npts,)     fitted Mavroeidis-Papageorgiou pulse [m/s]
    /overturn/<id>                      pandas table, one row per (lambda, R, isolation case)
    /maps/<source>/<map>                a response-regime map (write_map layout below)
    /pulses/overturn_R                  pandas table: min. overturning amplitude vs R (Figs 4, 7 left)
    /pulses/overturn_omega              pandas table: the same vs omega_p (Figs 4, 7 right)
    /pulses/overturn_isolation          pandas table: vs Tb, xi_b, rho for the full-sine pulse (Fig 5)
    /pulses/restitution                 pandas table: eps and beta1/h vs lambda for several rho (Fig 3)
    /summary/records                    pandas table: one row per record (the /records attrs, no arrays)
    /summary/overturn                   pandas table: all /overturn/<id> tables stacked (column ``record``)
    /summary/maps                       pandas table: one row per map (MAP_INDEX_COLUMNS)

Map names. ``<source>`` is a record id or ``pulse-<shape>-td<td_s>`` (e.g. ``pulse-fullsine-td0.5``,
Fig 6). ``<map>`` is ``lambda_R-<case>`` (lambda-R plane, Figs 6, 9, 10, 13; ``<case>`` an isolation
case name of the configuration, e.g. ``none``, ``linear``, ``fp``) or ``Tb_xi-lam<lambda>-R<R_m>``
(Tb-xi plane for a linear isolator, Figs 11, 12), numbers formatted with ``%g``. Select maps by the
columns of ``/summary/maps`` (or the group attributes) rather than by name: the case names are the
user's.

A map group (:func:`write_map`) holds the datasets ``<x_name>`` and ``<y_name>`` (axes: ``lambda`` [-]
and ``R_m`` [m], or ``Tb_s`` [s] and ``xi_b`` [-]), ``codes`` (int8, shape (len(x), len(y)); 0 = no
uplift, 1 = rocking, 2 = overturn) and ``max_theta_over_alpha`` (partial where the outcome was
decided early), with attributes ``kind`` ("lambda-R" | "Tb-xi"), ``x_name``, ``y_name``, ``amp_g``
(excitation PGA [g]), ``fixed`` (JSON of the fixed parameters: isolation kind and its parameters,
or lambda, R_m, rho) plus ``fixed_<name>`` copies, ``n_analyses``, ``seconds``; maps written by the
workflow add ``source``, ``map``, ``source_kind`` ("record" | "pulse"), ``case``, ``amp_source``
("table1" | "record" | "config" | "pulse"), ``pulse_shape`` and ``td_s`` (pulses) or ``record_sha256``
(records), ``config_hash``.

Table columns
-------------
Every table group has the attributes ``units`` (JSON: column -> unit) and ``columns`` (JSON list);
``/overturn/<id>`` also ``record``, ``record_sha256``, ``record_pga_g``, ``Tp_s``, ``config_hash``,
``search`` (JSON: amp_max_g, growth, rtol), ``isorock_version``; the pulse tables ``config_hash``,
``search``, ``lambda`` and ``isorock_version``.

``/overturn/<id>`` and ``/summary/overturn`` (:data:`OVERTURN_COLUMNS`): ``record``, ``lambda``,
``R_m``, ``b_m``, ``h_m``, ``tan_alpha``, ``case``, ``isolation`` ("none" | "linear" | "fp"),
``Tb_s``, ``xi_b``, ``rho``, ``mu_b``, ``R_b_m`` (NaN where they do not apply; ``Tb_s`` of an FP
isolator is its pendulum period), ``min_overturn_g`` (smallest PGA that overturns the block [g],
NaN when nothing up to ``amp_max_g`` does), ``overturns`` (bool), ``min_overturn_over_tan_alpha``,
``uplift_g`` (PGA at which rocking starts [g]), ``uplift_over_tan_alpha``, ``n_analyses``,
``amp_max_g``, ``record_pga_g`` (PGA of the processed record [g]), ``scale_min`` (``min_overturn_g
/ record_pga_g``: the scale factor of the record that first overturns the block).

``/pulses/overturn_R``, ``/pulses/overturn_omega``, ``/pulses/overturn_isolation``
(:data:`PULSE_COLUMNS`): ``pulse`` ("rect" | "halfsine" | "fullsine"), ``td_s``, ``omega_p_rad_s``
(``pi / td``), ``series`` (which curve family the row belongs to: ``"td"`` (curves of fixed td),
``"R"`` (curves of fixed R)), ``param`` (``/pulses/overturn_isolation`` only: the varied
isolation parameter, "Tb_s" | "xi_b" | "rho", or "none" for the non-isolated reference rows;
"" elsewhere), ``value`` (its value, NaN elsewhere), then the block and isolation columns and the
results as in ``/overturn`` (without ``record``, ``record_pga_g``, ``scale_min``). The amplitudes
are pulse amplitudes ``A_g0`` [g].

``/pulses/restitution`` (Fig 3): ``lambda``, ``rho``, ``eps`` (angular restitution [-]),
``beta1_over_h`` (``beta1 / h`` [-]), ``eps_housner`` (rigid base, [-]).

``/summary/maps`` (:data:`MAP_INDEX_COLUMNS`): ``path`` (HDF5 path of the map group), ``source``,
``source_kind``, ``map``, ``kind``, ``case``, ``isolation``, ``Tb_s``, ``xi_b``, ``rho``, ``mu_b``,
``R_b_m``, ``lambda``, ``R_m`` (Tb-xi maps: the block), ``pulse``, ``td_s``, ``amp_g``,
``amp_source``, ``nx``, ``ny``, ``no_uplift``, ``rocking``, ``overturn`` (counts of grid points),
``n_analyses``, ``seconds``.

``/summary/records``: ``record``, ``label``, ``event``, ``year``, ``station``, ``component``,
``catalog_id``, ``source_file``, ``source_format``, ``substitute``, ``npts``, ``dt_s``, ``duration_s``,
``pga_g``, ``pgv_m_s``, ``pgd_m``, ``arias_m_s``, ``d5_95_s``, ``Tp_s``, ``Tp_mp_s``, ``pulse_like``,
``pulse_indicator``, ``table1_pga_g``, ``table1_pgv_m_s``, ``table1_tp_s``, ``qa_passed``,
``record_sha256``.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
import warnings
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import h5py
import numpy as np

__all__ = [
    "LAYOUT_VERSION",
    "OUTCOME_LEGEND",
    "OVERTURN_COLUMNS",
    "PULSE_COLUMNS",
    "MAP_INDEX_COLUMNS",
    "atomic_path",
    "atomic_h5",
    "write_map",
    "read_map",
    "write_tables",
    "read_table",
    "merge_h5",
    "map_paths",
    "config_hash",
    "file_sha256",
    "set_attrs",
]

# The column name "lambda" is a Python keyword: PyTables warns that it cannot be a natural-naming
# attribute, which is harmless (pandas reads the column by name).
warnings.filterwarnings("ignore", message="object name is a Python keyword: 'lambda'")

LAYOUT_VERSION = 1
OUTCOME_LEGEND = "0 = no uplift, 1 = rocking, 2 = overturn"

_CASE_COLUMNS = ("case", "isolation", "Tb_s", "xi_b", "rho", "mu_b", "R_b_m")
_BLOCK_COLUMNS = ("lambda", "R_m", "b_m", "h_m", "tan_alpha")
_RESULT_COLUMNS = (
    "min_overturn_g", "overturns", "min_overturn_over_tan_alpha", "uplift_g", "uplift_over_tan_alpha",
    "n_analyses", "amp_max_g",
)  # fmt: skip
#: columns of ``/overturn/<id>`` and ``/summary/overturn``
OVERTURN_COLUMNS: tuple[str, ...] = (
    ("record",) + _BLOCK_COLUMNS + _CASE_COLUMNS + _RESULT_COLUMNS + ("record_pga_g", "scale_min")
)
#: columns of the ``/pulses/overturn_*`` tables
PULSE_COLUMNS: tuple[str, ...] = (
    ("pulse", "td_s", "omega_p_rad_s", "series", "param", "value")
    + _BLOCK_COLUMNS
    + _CASE_COLUMNS
    + _RESULT_COLUMNS
)
#: columns of ``/summary/maps``
MAP_INDEX_COLUMNS: tuple[str, ...] = (
    "path", "source", "source_kind", "map", "kind", "case", "isolation", "Tb_s", "xi_b", "rho", "mu_b",
    "R_b_m", "lambda", "R_m", "pulse", "td_s", "amp_g", "amp_source", "nx", "ny", "no_uplift", "rocking",
    "overturn", "n_analyses", "seconds",
)  # fmt: skip

#: units of the table columns (JSON attribute ``units`` of each table group)
COLUMN_UNITS: dict[str, str] = {
    "lambda": "-", "R_m": "m", "b_m": "m", "h_m": "m", "tan_alpha": "-", "Tb_s": "s", "xi_b": "-",
    "rho": "-", "mu_b": "-", "R_b_m": "m", "min_overturn_g": "g", "min_overturn_over_tan_alpha": "-",
    "uplift_g": "g", "uplift_over_tan_alpha": "-", "amp_max_g": "g", "record_pga_g": "g",
    "scale_min": "-", "td_s": "s", "omega_p_rad_s": "rad/s", "value": "units of param", "eps": "-",
    "beta1_over_h": "-", "eps_housner": "-", "amp_g": "g", "seconds": "s", "pga_g": "g",
    "pgv_m_s": "m/s", "pgd_m": "m", "arias_m_s": "m/s", "d5_95_s": "s", "Tp_s": "s", "Tp_mp_s": "s",
    "dt_s": "s", "duration_s": "s", "table1_pga_g": "g", "table1_pgv_m_s": "m/s", "table1_tp_s": "s",
}  # fmt: skip


# --------------------------------------------------------------------------------------------- atomic files
@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, *, copy_existing: bool = False) -> Iterator[Path]:
    """A temporary path next to ``path``, renamed to ``path`` when the block ends without an error.

    The temporary name starts with a dot and ends with ``.tmp``; on any exception (including
    ``KeyboardInterrupt``) it is removed and ``path`` is left as it was. A process killed inside the
    block leaves only the dot-file, never a file under the final name.

    Parameters
    ----------
    path : path-like
        Final file name (its directory is created).
    copy_existing : bool
        Start from a copy of an existing ``path`` instead of an absent file.

    Yields
    ------
    Path
        The temporary file (absent at first unless ``copy_existing``): write it with any library,
        closing it before the block ends.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        if copy_existing and path.exists():
            import shutil

            shutil.copyfile(path, tmp)
        else:
            tmp.unlink()
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"{tmp}: nothing was written")
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise


@contextlib.contextmanager
def atomic_h5(path: str | os.PathLike, mode: str = "w") -> Iterator[h5py.File]:
    """Open an HDF5 file for writing under a temporary name; rename it to ``path`` on success.

    The root gets the attributes ``isorock_version`` and ``layout_version``.

    Parameters
    ----------
    path : path-like
        Final file name.
    mode : {"w", "a"}
        ``"a"`` copies an existing ``path`` first and adds to the copy.
    """
    with atomic_path(path, copy_existing=(mode == "a")) as tmp, h5py.File(tmp, "a") as f:
        stamp(f)
        yield f


def stamp(f: h5py.Group) -> None:
    """Write ``isorock_version`` and ``layout_version`` on a file's root group."""
    from . import __version__

    f.attrs["isorock_version"] = __version__
    f.attrs["layout_version"] = LAYOUT_VERSION


# --------------------------------------------------------------------------------------------- attributes
def _attr_value(v: Any) -> Any:
    """A value h5py can store as an attribute: None -> NaN, dict/list of non-numbers -> JSON."""
    if v is None:
        return np.nan
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
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


def config_hash(obj: Any) -> str:
    """sha256 (hex) of the canonical JSON of ``obj`` (sorted keys): the configuration hash."""
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def file_sha256(path: str | os.PathLike) -> str:
    """sha256 (hex) of a file's bytes: the record checksum."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


# --------------------------------------------------------------------------------------------- maps
def write_map(group: h5py.Group, m, attrs: Mapping[str, Any] | None = None) -> None:
    """Write a :class:`isorock.assess.RegimeMap` into ``group`` (created by the caller).

    Parameters
    ----------
    group : h5py.Group
        Empty group.
    m : RegimeMap
        The map.
    attrs : mapping, optional
        Extra attributes (source, case, ...).
    """
    units = {"lambda": "-", "R_m": "m", "Tb_s": "s", "xi_b": "-"}
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
    dx = group.create_dataset(m.x_name, data=np.asarray(m.x))
    dx.attrs["units"] = units.get(m.x_name, "")
    dy = group.create_dataset(m.y_name, data=np.asarray(m.y))
    dy.attrs["units"] = units.get(m.y_name, "")
    dc = group.create_dataset("codes", data=np.asarray(m.codes, dtype=np.int8), compression="gzip")
    dc.attrs["legend"] = OUTCOME_LEGEND
    dc.attrs["dims"] = f"{m.x_name}, {m.y_name}"
    dm = group.create_dataset(
        "max_theta_over_alpha", data=np.asarray(m.max_theta_over_alpha), compression="gzip"
    )
    dm.attrs["units"] = "-"
    dm.attrs["note"] = "partial where the outcome was decided early"
    if attrs:
        set_attrs(group, attrs)


def read_map(group: h5py.Group):
    """Read back a map written by :func:`write_map` as a :class:`isorock.assess.RegimeMap`."""
    from .assess import RegimeMap

    xn, yn = group.attrs["x_name"], group.attrs["y_name"]
    return RegimeMap(
        kind=str(group.attrs["kind"]),
        x_name=str(xn),
        y_name=str(yn),
        x=group[xn][()],
        y=group[yn][()],
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


# --------------------------------------------------------------------------------------------- tables
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
    import pandas as pd
    import tables as tb

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
    import pandas as pd
    import tables as tb

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tb.NaturalNameWarning)
        return pd.read_hdf(path, key)


# --------------------------------------------------------------------------------------------- merging
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
