"""Compare two isorock stores (``results/isorock.h5``) number for number.

    python tests/cluster/compare_stores.py A.h5 B.h5

Every group and dataset of A must be in B and the other way round; every dataset must hold the same
values (floating point exactly, NaN equal to NaN; text equal), and every attribute the same value,
except the attributes that describe the run rather than its results: when and where it ran, how long
its jobs took and the paths of its files (``PROVENANCE``). Exit 0 when the stores hold the same numbers,
1 with the first differences listed otherwise.
"""

from __future__ import annotations

import sys

import h5py
import numpy as np

# attributes that depend on the run, not on the results: wall-clock times, the time of the merge and the
# absolute paths of the records (the two runs read the same files from two working directories)
PROVENANCE = {"created_utc", "seconds", "source_file", "record_source"}
# table columns of the same kind (/summary/* and other pandas-like tables keep them as datasets)
PROVENANCE_COLUMNS = {"seconds", "source_file"}


def _equal(a: np.ndarray, b: np.ndarray) -> bool:
    if a.shape != b.shape:
        return False
    if a.dtype.kind == "f" and b.dtype.kind == "f":
        return bool(np.array_equal(a, b, equal_nan=True))
    if a.dtype.kind == "O" or b.dtype.kind == "O":
        return [str(x) for x in a.ravel()] == [str(x) for x in b.ravel()]
    return bool(np.array_equal(a, b))


def _scales(ds: h5py.Dataset) -> list[list[str]]:
    """The names of the dimension scales attached to each axis of a dataset (store layout 5)."""
    return [[scale.name for scale in ds.dims[i].values()] for i in range(ds.ndim)]


def _attrs(name: str, x: h5py.HLObject, y: h5py.HLObject, diffs: list[str]) -> None:
    for key in sorted(set(x.attrs) | set(y.attrs)):
        if key in PROVENANCE:
            continue
        if key in ("DIMENSION_LIST", "REFERENCE_LIST") and key in x.attrs and key in y.attrs:
            # HDF5 object references, which compare by address: compared by the scales they name
            # (REFERENCE_LIST, a scale's list of the datasets attached to it, is the same relation
            # seen from the scale, compared through the datasets' DIMENSION_LIST)
            if key == "DIMENSION_LIST" and _scales(x) != _scales(y):
                diffs.append(f"{name}@{key}: scales {_scales(x)} != {_scales(y)}")
            continue
        if key not in x.attrs or key not in y.attrs:
            diffs.append(f"{name}@{key}: only in {'A' if key in x.attrs else 'B'}")
            continue
        a, b = np.asarray(x.attrs[key]), np.asarray(y.attrs[key])
        if not _equal(a, b):
            diffs.append(f"{name}@{key}: {x.attrs[key]!r:.80} != {y.attrs[key]!r:.80}")


def compare(path_a: str, path_b: str) -> tuple[int, list[str]]:
    """The number of objects compared and the differences found (empty: the same numbers)."""
    diffs: list[str] = []
    count = 0
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        names_a: list[str] = []
        names_b: list[str] = []
        fa.visit(names_a.append)
        fb.visit(names_b.append)
        diffs += [f"{n}: only in A" for n in sorted(set(names_a) - set(names_b))]
        diffs += [f"{n}: only in B" for n in sorted(set(names_b) - set(names_a))]
        _attrs("/", fa, fb, diffs)
        for name in sorted(set(names_a) & set(names_b)):
            x, y = fa[name], fb[name]
            count += 1
            _attrs(name, x, y, diffs)
            if isinstance(x, h5py.Dataset) != isinstance(y, h5py.Dataset):
                diffs.append(f"{name}: a dataset in one store, a group in the other")
                continue
            if isinstance(x, h5py.Dataset):
                if name.rsplit("/", 1)[-1] in PROVENANCE_COLUMNS:
                    continue
                if x.dtype.names:  # compound: compare column by column, leaving out provenance
                    cols = [c for c in x.dtype.names if c not in PROVENANCE_COLUMNS]
                    a, b = x[()], y[()]
                    if a.shape != b.shape or any(not _equal(a[c], b[c]) for c in cols):
                        diffs.append(f"{name}: values differ")
                elif not _equal(np.asarray(x[()]), np.asarray(y[()])):
                    diffs.append(f"{name}: values differ")
    return count, diffs


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[0], file=sys.stderr)
        return 2
    count, diffs = compare(*argv)
    print(f"compare_stores: {count} groups and datasets compared, {len(diffs)} difference(s)")
    for d in diffs[:40]:
        print(f"  {d}")
    return 1 if diffs or count == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
