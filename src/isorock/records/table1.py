"""A Table 1 record by its catalog id: the component the paper used, from the user's records directory.

:func:`load_table1` is what ``isorock pulse --id``, ``isorock info --id`` and the workflow's
``process_record`` do for one catalog row: find the row's files in the records directory's manifest
(:func:`isorock.records.lookup.catalog_record`) and choose its component
(:func:`isorock.records.components.choose_component`: rotated to SN/SP when two components are there).

Example
-------
>>> from isorock import load_table1                                         # doctest: +SKIP
>>> ch = load_table1("IMV79-E04", "../shared/records")                      # doctest: +SKIP
>>> ch.component, ch.azimuth_deg, ch.method, ch.record.motion.pga_g         # doctest: +SKIP
('SN', 53.0, 'rotated', 0.366)
"""

from __future__ import annotations

from pathlib import Path

from isorock.processing import ProcessingConfig
from isorock.records.components import ComponentChoice, choose_component

__all__ = ["load_table1"]


def load_table1(
    rid: str,
    records: str | Path | None = None,
    *,
    processing: ProcessingConfig | str | Path | None = None,
    raw: bool = False,
    catalog: str | Path | None = None,
) -> ComponentChoice:
    """The processed component of the Table 1 row ``rid``, as the workflow analyses it.

    Parameters
    ----------
    rid : str
        Catalog id (``NOR94-RRS``; the ids are in ``data/records/catalog.csv``).
    records : path-like, optional
        Records directory with a ``manifest.csv``; default ``$ISOROCK_RECORDS``.
    processing : ProcessingConfig, path or None
        Processing steps (None: the packaged ``processing.yaml``).
    raw : bool
        Skip the processing.
    catalog : path-like, optional
        Catalog CSV (default: the paper's Table 1).

    Returns
    -------
    ComponentChoice
        ``record`` (processed trace, provenance), ``component``, ``azimuth_deg``, ``method``,
        ``qa_mark``; ``record.motion`` is the engine's ground motion.

    Raises
    ------
    IsorockError
        No records directory, an unknown id, no file of the row, or no file that can be read.
    """
    from isorock.records.lookup import catalog_record

    spec = catalog_record(rid, records, catalog=catalog)
    return choose_component(
        spec.files,
        spec.target,
        processing=processing,
        raw=raw,
        table1_pga_g=spec.table1_pga_g,
        table1_pgv_m_s=spec.table1_pgv_m_s,
    )
