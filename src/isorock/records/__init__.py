"""Records: from a catalog row or a file to the ground motion the engine analyses.

One concern per module, read in one direction: the manifest, then the lookup, then the files, then
the components (each module imports only those above it in this list):

* :mod:`~isorock.records.metadata`, :mod:`~isorock.records.catalog` (the paper's Table 1,
  ``data/records/catalog.csv``), :mod:`~isorock.records.directory` (where the record files are:
  the records directory, ``$ISOROCK_RECORDS``, the pyslammer samples; the checks of a usable file)
  and :mod:`~isorock.records.naming` (what a component's name says: azimuth, vertical, polarity);
* the manifest: :mod:`~isorock.records.manifest` (a records directory's ``manifest.csv``, which
  catalog rows it provides) and :mod:`~isorock.records.adding` (``isorock records add``, atomic and
  locked), :mod:`~isorock.records.peer_search` (a PEER search folder added at once);
* the lookup: :mod:`~isorock.records.spec` (what it answers: :class:`RecordSpec`, :class:`RecordFile`,
  :class:`Target`), :mod:`~isorock.records.rows` (the catalog rows and the added records of a
  directory) and :mod:`~isorock.records.lookup` (which records a run has,
  :func:`~isorock.records.lookup.find_records`; one record by its id,
  :func:`~isorock.records.lookup.catalog_record`);
* the files: :mod:`~isorock.records.motion` (the one path from a file to a processed ground motion,
  :func:`load_record`, :func:`load_motion`) and :mod:`~isorock.records.files` (the horizontals of a
  file, the time alignment of two);
* the components: :mod:`~isorock.records.candidates` (single and rotated candidates),
  :mod:`~isorock.records.components` (the component a catalog row asks for: provided, rotated,
  aligned or as recorded), :mod:`~isorock.records.vertical` (the vertical beside it) and
  :mod:`~isorock.records.table1` (a Table 1 row's processed component by its id, :func:`load_table1`).

It may import the readers (:mod:`isorock.io`), the processing steps (:mod:`isorock.processing`, the
rotation of two horizontals included), the store's file helpers (:mod:`isorock.store`), the physics'
excitation and the base modules (constants, errors, resources); never the engine, the workflow
(:mod:`isorock.pipeline`, :mod:`isorock.control`, :mod:`isorock.jobs`), the figures or the command line,
which import it. ``import isorock.records`` loads neither numba, Snakemake nor matplotlib.
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
