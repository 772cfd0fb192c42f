"""HDF5 store: self-describing results, written atomically.

Layout (one file per job, merged into ``results/isorock.h5``)::

    /maps/<name>        axes, outcome codes (0 no uplift, 1 rocking, 2 overturn), fixed parameters
    /records/<id>       processed acceleration, dt, PGA, PGV, Tp, processing history
    /overturn/<id>      minimum overturning PGA table

Every file carries the isorock version; arrays carry their units as attributes. Writers go
through :func:`atomic_h5`, which writes to a temporary name and renames it only when complete,
so a killed run never leaves a half-written file that looks complete.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

import h5py
import numpy as np

__all__ = ["atomic_h5", "write_map", "read_map"]

OUTCOME_LEGEND = "0 = no uplift, 1 = rocking, 2 = overturn"


@contextlib.contextmanager
def atomic_h5(path: str | os.PathLike, mode: str = "w") -> Iterator[h5py.File]:
    """Open an HDF5 file for writing under a temporary name; rename it to ``path`` on success.

    Parameters
    ----------
    path : path-like
        Final file name.
    mode : {"w", "a"}
        ``"a"`` copies an existing ``path`` first and adds to the copy.
    """
    from . import __version__

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        if mode == "a" and path.exists():
            import shutil

            shutil.copyfile(path, tmp)
            f = h5py.File(tmp, "a")
        else:
            f = h5py.File(tmp, "w")
        with f:
            f.attrs["isorock_version"] = __version__
            yield f
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def write_map(group: h5py.Group, m) -> None:
    """Write a :class:`isorock.assess.RegimeMap` into ``group`` (created by the caller)."""
    units = {"lambda": "-", "R_m": "m", "Tb_s": "s", "xi_b": "-"}
    group.attrs["kind"] = m.kind
    group.attrs["x_name"] = m.x_name
    group.attrs["y_name"] = m.y_name
    group.attrs["amp_g"] = m.amp_g
    group.attrs["amp_units"] = "g"
    group.attrs["n_analyses"] = m.n_analyses
    group.attrs["seconds"] = m.seconds
    group.attrs["fixed"] = json.dumps(m.fixed)
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
    dm = group.create_dataset("max_theta_over_alpha", data=np.asarray(m.max_theta_over_alpha),
                              compression="gzip")
    dm.attrs["units"] = "-"
    dm.attrs["note"] = "partial where the outcome was decided early"


def read_map(group: h5py.Group):
    """Read back a map written by :func:`write_map`."""
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
