"""Where the record files are: the user's records directory, its manifest, and the built-in samples.

* :func:`records_dir` says which directory holds the user's record files: a value from the
  configuration or the command line, else the ``ISOROCK_RECORDS`` environment variable (the one
  place that reads it);
* :func:`read_manifest` reads the ``manifest.csv`` describing the files of such a directory
  (columns ``file, table1_id, event, station, component, format, units, dt_s, column, note``);
* :func:`check_file` / :func:`check_manifest_files` read records and check them;
* :func:`catalog_status` says which catalog rows are present, missing or only substituted there;
* :func:`sample_records` lists the built-in default record set: the ground motions shipped with the
  optional ``pyslammer`` package (GPL; install ``isorock[samples]``), read in place, never copied.
"""

from __future__ import annotations

import importlib.util
import math
import os
import re
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from . import resources
from .catalog import load_catalog, read_csv
from .constants import ENV_RECORDS, G
from .errors import CatalogError, IsorockError, RecordError
from .io import FORMATS, normalize_units, read_record

__all__ = [
    "ENV_RECORDS",
    "MANIFEST_COLUMNS",
    "ManifestEntry",
    "RowStatus",
    "FileCheck",
    "SampleRecord",
    "records_dir",
    "read_manifest",
    "catalog_status",
    "check_file",
    "check_trace",
    "check_manifest_files",
    "sample_records",
    "samples_dir",
]

MANIFEST_COLUMNS: tuple[str, ...] = (
    "file", "table1_id", "event", "station", "component", "format", "units", "dt_s", "column", "note",
)  # fmt: skip
_MANIFEST_REQUIRED = ("file", "table1_id", "format", "units", "dt_s", "column")

# limits of a plausible record used by check_file (the readers refuse PGA > 10 g outright)
MIN_PGA_G = 0.005
MIN_DURATION_S = 1.0


# --------------------------------------------------------------------------- records directory
def records_dir(config_value: str | Path | None = None, *, must_exist: bool = True) -> Path | None:
    """The directory holding the user's record files.

    Parameters
    ----------
    config_value : str or Path, optional
        Directory named in the configuration or on the command line; it wins over the environment.
    must_exist : bool
        Raise if the named directory does not exist.

    Returns
    -------
    Path or None
        ``config_value``, else ``$ISOROCK_RECORDS``, else None (meaning: use :func:`sample_records`).

    Raises
    ------
    IsorockError
        The named directory does not exist or is not a directory.
    """
    source = "records directory"
    value: str | Path | None = config_value
    if value is None or str(value).strip() == "":
        env = os.environ.get(ENV_RECORDS, "").strip()
        if not env:
            return None
        value, source = env, f"{ENV_RECORDS}"
    path = Path(value).expanduser()
    if must_exist and not path.is_dir():
        raise IsorockError(f"{path}: {source} does not exist or is not a directory")
    return path


# --------------------------------------------------------------------------- manifest
@dataclass(frozen=True)
class ManifestEntry:
    """One row of a records-directory manifest.

    Parameters
    ----------
    file : str
        File name relative to the directory.
    table1_id : str
        Catalog id the file belongs to ("" if none).
    format : str
        Manifest format name (see :data:`isorock.io.FORMATS`).
    units : str
        Units of the values in the file.
    dt_s : float or None
        Time step [s] when the file does not state it.
    column : str
        Component to read from a multi-component file ("" if one).
    event, station, component, note : str
        Descriptions.
    line : int
        Line of the manifest.
    """

    file: str
    table1_id: str = ""
    format: str = ""
    units: str = ""
    dt_s: float | None = None
    column: str = ""
    event: str = ""
    station: str = ""
    component: str = ""
    note: str = ""
    line: int = 0

    @property
    def is_substitute(self) -> bool:
        """The note says the file stands in for the catalog row (another station)."""
        return self.note.strip().lower().startswith("substitute")

    def read_kwargs(self) -> dict[str, Any]:
        """Keyword arguments for :func:`isorock.io.read_record`."""
        return {
            "format": self.format or None,
            "dt": self.dt_s,
            "units": self.units or None,
            "component": self.column or (self.component if self.format != "bbp" else None) or None,
        }


def read_manifest(path: str | Path) -> list[ManifestEntry]:
    """Read a manifest CSV (columns :data:`MANIFEST_COLUMNS`).

    Raises
    ------
    CatalogError
        Missing columns, an unknown format or units, a bad ``dt_s``, a repeated file (with the line).
    """
    path = Path(path)
    header, raw = read_csv(path, "manifest")
    missing = [c for c in _MANIFEST_REQUIRED if c not in header]
    if missing:
        raise CatalogError(
            path, f"missing columns {missing}: a manifest has {', '.join(MANIFEST_COLUMNS)}", 1
        )
    out: list[ManifestEntry] = []
    seen: set[str] = set()
    for k, row in enumerate(raw):
        line = k + 2
        cell = {c: (row.get(c) or "").strip() for c in MANIFEST_COLUMNS}
        if not cell["file"]:
            raise CatalogError(path, "empty file name", line)
        if cell["file"] in seen:
            raise CatalogError(path, f"file {cell['file']!r} listed twice", line)
        seen.add(cell["file"])
        if cell["format"] not in FORMATS:
            raise CatalogError(path, f"unknown format {cell['format']!r}: valid {', '.join(FORMATS)}", line)
        if cell["units"]:
            try:
                normalize_units(cell["units"], path, line)
            except RecordError as exc:
                raise CatalogError(path, exc.problem, line) from None
        dt = None
        if cell["dt_s"]:
            try:
                dt = float(cell["dt_s"])
            except ValueError:
                dt = float("nan")
            if not (math.isfinite(dt) and dt > 0):
                raise CatalogError(path, f"dt_s={cell['dt_s']!r} is not a time step > 0 s", line)
        out.append(ManifestEntry(dt_s=dt, line=line, **{c: cell[c] for c in MANIFEST_COLUMNS if c != "dt_s"}))
    return out


# --------------------------------------------------------------------------- checks
@dataclass
class FileCheck:
    """Result of checking one record file.

    Parameters
    ----------
    file : str
        The file (as listed).
    ok : bool
        Readable and plausible.
    problem : str
        What is wrong ("" if ok).
    format : str
        Format used.
    npts : int
        Samples [-].
    dt : float
        Time step [s].
    pga_g : float
        Peak ground acceleration [g].
    duration : float
        ``(npts - 1) dt`` [s].
    component : str
        Component read.
    table1_id : str
        Catalog row it belongs to.
    """

    file: str
    ok: bool
    problem: str = ""
    format: str = ""
    npts: int = 0
    dt: float = math.nan
    pga_g: float = math.nan
    duration: float = math.nan
    component: str = ""
    table1_id: str = ""


def check_file(
    path: str | Path,
    format: str | None = None,
    *,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
    label: str | None = None,
) -> FileCheck:
    """Read a record and check it is usable: readable, units plausible, dt sane, long enough.

    Returns a :class:`FileCheck`; reading errors become ``ok=False`` with the error message.
    See :func:`check_trace` for the checks after reading.
    """
    label = label or str(path)
    try:
        st = read_record(path, format, dt=dt, units=units, component=component)
    except RecordError as exc:
        return FileCheck(label, False, str(exc), format or "")
    return check_trace(st[0], label)


def check_trace(tr, label: str = "") -> FileCheck:
    """Check a trace read by :func:`isorock.io.read_record`.

    A PGA below :data:`MIN_PGA_G` (a file in g read as cm/s^2?) or a record shorter than
    :data:`MIN_DURATION_S` fails; the readers already refuse PGA > 10 g and a bad dt.
    """
    info = tr.stats.get("isorock", {})
    src = info.get("source", label)
    pga_g = float(np.max(np.abs(tr.data))) / G
    dur = (tr.stats.npts - 1) * tr.stats.delta
    fc = FileCheck(
        label or src,
        True,
        "",
        info.get("format", ""),
        int(tr.stats.npts),
        float(tr.stats.delta),
        pga_g,
        dur,
        tr.stats.channel,
    )
    if pga_g < MIN_PGA_G:
        fc.ok, fc.problem = (
            False,
            (
                f"{src}: PGA {pga_g:.3g} g is implausibly small for a strong-motion record "
                f"(units {info.get('units')}): wrong units?"
            ),
        )
    elif dur < MIN_DURATION_S:
        fc.ok, fc.problem = False, f"{src}: record lasts only {dur:.3g} s (< {MIN_DURATION_S:g} s)"
    return fc


def check_manifest_files(directory: str | Path, manifest: list[ManifestEntry]) -> list[FileCheck]:
    """Check every file a manifest lists (missing files fail with 'no such file')."""
    directory = Path(directory)
    out = []
    for e in manifest:
        fc = check_file(directory / e.file, label=e.file, **e.read_kwargs())
        fc.table1_id = e.table1_id
        out.append(fc)
    return out


@dataclass
class RowStatus:
    """Whether a catalog row has a record file in a directory.

    Parameters
    ----------
    id : str
        Catalog id.
    status : {"present", "substituted", "missing"}
        ``present``: at least one file of that station; ``substituted``: only files of a stand-in
        station (manifest note starting with "substitute"); ``missing``: no usable file.
    files : list of str
        The files (present or substitute) for the row.
    failed : list of str
        Files listed for the row that are absent or fail :func:`check_file`.
    """

    id: str
    status: Literal["present", "substituted", "missing"]
    files: list[str] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def catalog_status(
    directory: str | Path | None,
    manifest: list[ManifestEntry] | None = None,
    catalog=None,
    checks: list[FileCheck] | None = None,
) -> list[RowStatus]:
    """Which catalog rows are present, missing or substituted in a records directory.

    Parameters
    ----------
    directory : str or Path or None
        The records directory (None: only user-added rows with a ``file`` can be present).
    manifest : list of ManifestEntry, optional
        Default: ``directory/manifest.csv`` if it exists, else none.
    catalog : pandas.DataFrame, optional
        Default: :func:`load_catalog` (Table 1).
    checks : list of FileCheck, optional
        Results of :func:`check_manifest_files`; a file that failed does not count as present.
        Without them a file counts when it exists.

    Returns
    -------
    list of RowStatus
        In catalog order.
    """
    if catalog is None:
        catalog = load_catalog()
    directory = Path(directory) if directory is not None else None
    if manifest is None and directory is not None and (directory / "manifest.csv").is_file():
        manifest = read_manifest(directory / "manifest.csv")
    manifest = manifest or []
    failed = {c.file for c in (checks or []) if not c.ok}
    cat_dir = Path(catalog.attrs.get("path", resources.catalog_csv())).parent
    out: list[RowStatus] = []
    for row in catalog.to_dict("records"):
        rid = row["id"]
        good: list[str] = []
        subs: list[str] = []
        bad: list[str] = []
        for e in manifest:
            if e.table1_id != rid:
                continue
            exists = directory is not None and (directory / e.file).is_file()
            if not exists or e.file in failed:
                bad.append(e.file)
            elif e.is_substitute:
                subs.append(e.file)
            else:
                good.append(e.file)
        own = row.get("file")
        if isinstance(own, str) and own:
            p = Path(own) if Path(own).is_absolute() else cat_dir / own
            (good if p.is_file() and own not in failed else bad).append(own)
        if good:
            out.append(RowStatus(rid, "present", good + subs, bad))
        elif subs:
            out.append(RowStatus(rid, "substituted", subs, bad))
        else:
            out.append(RowStatus(rid, "missing", [], bad))
    return out


# --------------------------------------------------------------------------- default record set
_SAMPLE_NAME = re.compile(r"^(?P<event>.+)_(?P<year>\d{4})_(?P<station>[^_]+)-(?P<component>[^-_]+)$")

SAMPLES_MISSING = (
    "no records directory given (set {env} or name one) and the built-in sample record set needs the "
    "optional package pyslammer: pip install 'isorock[samples]'"
)


@dataclass(frozen=True)
class SampleRecord:
    """A ground motion of the built-in default set (pyslammer's sample motions).

    Parameters
    ----------
    name : str
        File stem, e.g. ``Imperial_Valley_1979_BCR-230``.
    path : Path
        The CSV file inside the installed pyslammer package.
    event : str
        Earthquake, e.g. ``Imperial Valley``.
    year : int or None
        Year of the earthquake.
    station, component : str
        Station code and component.
    format : str
        Always ``pyslammer-csv`` (time [s], acceleration [g]).
    """

    name: str
    path: Path
    event: str
    year: int | None
    station: str
    component: str
    format: str = "pyslammer-csv"


def samples_dir() -> Path:
    """Folder of pyslammer's sample ground motions (found without importing pyslammer).

    Raises
    ------
    IsorockError
        pyslammer is not installed, or its data folder is missing.
    """
    spec = importlib.util.find_spec("pyslammer")
    if spec is None or not spec.submodule_search_locations:
        raise IsorockError(SAMPLES_MISSING.format(env=ENV_RECORDS))
    for loc in spec.submodule_search_locations:
        d = Path(loc) / "sample_ground_motions"
        if d.is_dir():
            return d
    raise IsorockError("pyslammer is installed but has no sample_ground_motions folder: reinstall it")


def sample_records() -> list[SampleRecord]:
    """The built-in default record set: pyslammer's sample ground motions, sorted by name.

    Raises
    ------
    IsorockError
        With installation advice when pyslammer is not installed.
    """
    out = []
    for p in sorted(samples_dir().glob("*.csv")):
        m = _SAMPLE_NAME.match(p.stem)
        if m:
            out.append(
                SampleRecord(
                    p.stem, p, m["event"].replace("_", " "), int(m["year"]), m["station"], m["component"]
                )
            )
        else:
            out.append(SampleRecord(p.stem, p, p.stem.replace("_", " "), None, "", ""))
    return out
