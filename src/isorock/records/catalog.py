"""The record catalog: the paper's Table 1 (or a catalog of the same columns named by the
configuration's ``records.catalog``).

:func:`load_catalog` reads and validates a catalog CSV (default: the Table 1 catalog
``data/records/catalog.csv``, :func:`isorock.resources.catalog_csv`) against its schema
``data/records/catalog.schema.yaml``, one row per record with its Table 1 values. The user's own
records are not catalog rows: ``isorock records add`` registers them in a records directory's
manifest (:mod:`isorock.records.manifest`).

Where the record *files* are (records directory, manifest, built-in samples) is
:mod:`isorock.records`.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any

import yaml

import isorock.resources as resources
from isorock.errors import CatalogError

__all__ = [
    "CATALOG_COLUMNS",
    "CatalogError",
    "load_catalog",
    "validate_rows",
    "read_csv",
]


CATALOG_COLUMNS: tuple[str, ...] = (
    "id", "event", "year", "region", "station", "station_name", "component", "strike_deg", "strike_source",
    "mw", "dist_km", "pga_g", "pgv_m_s", "tp_s", "tp_source", "file", "format", "dt_s", "units", "column",
    "note",
)  # fmt: skip


# --------------------------------------------------------------------------- catalog
def _schema() -> dict:
    with open(resources.catalog_schema(), encoding="utf-8") as fh:
        return yaml.safe_load(fh)


def _typed(value: str, spec: dict) -> Any:
    """CSV cell -> int/float/str/None following the schema's type."""
    v = value.strip()
    if v == "":
        return None
    types = spec.get("type", [])
    types = [types] if isinstance(types, str) else list(types)
    try:
        if "integer" in types:
            return int(v)
        if "number" in types:
            x = float(v)
            return x if math.isfinite(x) else v
    except ValueError:
        return v  # left as text: the schema check reports it
    return v


def validate_rows(rows: list[dict[str, str]], path: object, first_line: int = 2) -> list[dict[str, Any]]:
    """Type and validate catalog rows read as text.

    Parameters
    ----------
    rows : list of dict
        Rows as read by :class:`csv.DictReader` (all values text).
    path : str or Path
        The file, for messages.
    first_line : int
        Line number of the first row.

    Returns
    -------
    list of dict
        Typed rows (numbers as int/float, empty cells as None).

    Raises
    ------
    CatalogError
        The first schema violation or duplicate id, with its line.
    """
    import jsonschema  # here: importing the catalog module (isorock.pipeline does) reads no catalog

    schema = _schema()
    props = schema["properties"]
    validator = jsonschema.Draft202012Validator(schema)
    out: list[dict[str, Any]] = []
    seen: dict[str, int] = {}
    for k, row in enumerate(rows):
        line = first_line + k
        if None in row:
            raise CatalogError(path, "more cells than columns in the header", line)
        typed = {c: _typed(v or "", props.get(c, {})) for c, v in row.items()}
        present = {c: v for c, v in typed.items() if v is not None}
        errors = sorted(validator.iter_errors(present), key=lambda e: list(e.path))
        if errors:
            e = errors[0]
            col = ".".join(str(p) for p in e.path)
            raise CatalogError(path, f"column {col}: {e.message}" if col else e.message, line)
        rid = typed["id"]
        if rid in seen:
            raise CatalogError(path, f"duplicate id {rid!r} (first on line {seen[rid]})", line)
        seen[rid] = line
        out.append({c: typed.get(c) for c in CATALOG_COLUMNS})
    return out


def read_csv(path: Path, what: str) -> tuple[list[str], list[dict[str, str]]]:
    try:
        # utf-8-sig: a spreadsheet's byte-order mark is no part of the first column's name
        with open(path, newline="", encoding="utf-8-sig") as fh:
            reader = csv.DictReader(fh)
            rows = list(reader)
            header = list(reader.fieldnames or [])
    except FileNotFoundError:
        raise CatalogError(path, f"no such {what} file") from None
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise CatalogError(path, f"cannot read {what}: {exc}") from None
    if not header:
        raise CatalogError(path, f"empty {what} file")
    return header, rows


def load_catalog(path: str | Path | None = None):
    """Read and validate a record catalog.

    Parameters
    ----------
    path : str or Path, optional
        Catalog CSV; default the Table 1 catalog (:func:`isorock.resources.catalog_csv`).

    Returns
    -------
    pandas.DataFrame
        One row per record, columns :data:`CATALOG_COLUMNS`; ``strike_deg`` [deg], ``mw`` [-],
        ``dist_km`` [km], ``pga_g`` [g], ``pgv_m_s`` [m/s], ``tp_s`` [s], ``dt_s`` [s]; missing values
        NaN/None.

    Raises
    ------
    CatalogError
        Unknown columns, schema violations or duplicate ids (with the line).
    """
    import pandas as pd  # here: pandas (about 0.2 s to import) only where a catalog is read

    path = Path(path) if path is not None else resources.catalog_csv()
    header, raw = read_csv(path, "catalog")
    unknown = [c for c in header if c not in CATALOG_COLUMNS]
    if unknown:
        raise CatalogError(path, f"unknown columns {unknown}: valid {', '.join(CATALOG_COLUMNS)}", 1)
    for c in ("id", "event", "station", "component"):
        if c not in header:
            raise CatalogError(path, f"missing column {c!r}", 1)
    rows = validate_rows(raw, path)
    df = pd.DataFrame(rows, columns=list(CATALOG_COLUMNS))
    for c in ("strike_deg", "mw", "dist_km", "pga_g", "pgv_m_s", "tp_s", "dt_s"):
        df[c] = pd.to_numeric(df[c])
    df["year"] = df["year"].astype("Int64")
    df.attrs["path"] = str(path)
    return df
