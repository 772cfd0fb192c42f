"""Records: from a catalog row or a file to the ground motion the engine analyses.

This subpackage holds everything about strong-motion records, one concern per module:

* :mod:`~isorock.records.catalog`: the record catalog (the paper's Table 1, ``data/records/catalog.csv``);
* :mod:`~isorock.records.manifest`: a records directory's ``manifest.csv``, adding records to it, and
  which catalog rows it provides;
* :mod:`~isorock.records.directory`: where the record files are (the records directory,
  ``$ISOROCK_RECORDS``, the pyslammer samples) and the checks of a usable record;
* :mod:`~isorock.records.components`: the component a catalog row asks for, from the files of its
  station (provided, rotated with ObsPy, aligned or as recorded);
* :mod:`~isorock.records.motion`: the one path from a file to a processed ground motion
  (:func:`load_record`, :func:`load_motion`);
* :mod:`~isorock.records.lookup`: the record lookup, which records a run has
  (:func:`~isorock.records.lookup.find_records`) and one catalog row by its id
  (:func:`~isorock.records.lookup.catalog_record`);
* :mod:`~isorock.records.table1`: a Table 1 row's processed component by its id (:func:`load_table1`).

It may import the readers (:mod:`isorock.io`), the processing steps (:mod:`isorock.processing`), the
store's file helpers (:mod:`isorock.store`) and the base modules (constants, errors, excitation,
resources); never the engine, the workflow (:mod:`isorock.pipeline`), the figures or the command
line, which import it. ``import isorock.records`` loads neither numba, Snakemake nor matplotlib.
"""

from __future__ import annotations

from typing import Any

__all__ = ["load_record", "load_motion", "load_table1", "find_records", "catalog_record"]


def __getattr__(name: str) -> Any:
    """The main entry points, imported on first use (reading records needs ObsPy)."""
    if name in ("load_record", "load_motion"):
        import isorock.records.motion as motion

        return getattr(motion, name)
    if name == "load_table1":
        from isorock.records.table1 import load_table1

        return load_table1
    if name in ("find_records", "catalog_record"):
        import isorock.records.lookup as lookup

        return getattr(lookup, name)
    raise AttributeError(f"module 'isorock.records' has no attribute {name!r}")
