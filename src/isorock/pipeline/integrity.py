"""Damaged outputs are rebuilt, never trusted: find the files of ``results/`` that do not open.

Snakemake decides what to rerun from the files' presence and times, not from their content: a store
truncated by a full disk or a copy cut short (``truncate -s 100000 results/isorock.h5``) looks newer
than its inputs, so Snakemake reruns the figures on it, which then fail on a "truncated file". Before
a run, :func:`remove_damaged` opens every HDF5 file of ``results/`` (the store and the job files:
HDF5 checks at opening that the file is as long as its superblock says), and takes every empty file
for damaged; each damaged file is removed, with one line saying so, so that Snakemake makes it again
with everything that depends on it. A damaged file inside a folder that one job writes whole
(``results/figures``, ``results/report/records``) removes that folder.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path

__all__ = ["damaged", "remove_damaged", "check_writable", "WHOLE_FOLDERS"]

#: folders of ``results/`` that one job writes whole (Snakemake ``directory()`` outputs)
WHOLE_FOLDERS = ("results/figures", "results/report/records")
#: what is not an output of a job: benchmark tables are rewritten by every job, hidden files are the
#: temporary files of jobs (never under a final name)
_SKIP = ("results/benchmarks",)


def check_writable(directory: Path) -> None:
    """Refuse a working directory whose run folders cannot be written (read-only disk, permissions),
    before Snakemake reports it as "write-protected output files".

    Raises
    ------
    IsorockError
        ``directory`` or one of its ``results``, ``logs``, ``.snakemake`` folders (those that exist)
        cannot be written.
    """
    import os

    from ..errors import IsorockError

    for sub in ("", "results", "logs", ".snakemake"):
        path = directory / sub
        if path.exists() and not os.access(path, os.W_OK | os.X_OK):
            raise IsorockError(
                f"{path} cannot be written (a read-only disk or its permissions): make it writable, or "
                "run in another folder (--directory DIR)"
            )


def _opens(path: Path) -> str | None:
    """None when the HDF5 file ``path`` opens and its objects can be listed, else why not."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            f.visit(lambda name: None)
    except Exception as exc:  # h5py raises OSError, KeyError or RuntimeError for a damaged file
        return str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__
    return None


def damaged(directory: Path) -> list[tuple[Path, str]]:
    """The damaged outputs under ``directory/results``: (path, why), in path order."""
    results = directory / "results"
    if not results.is_dir():
        return []
    out = []
    for path in sorted(results.rglob("*")):
        rel = path.relative_to(directory).as_posix()
        if not path.is_file() or path.name.startswith(".") or rel.startswith(_SKIP):
            continue
        if path.stat().st_size == 0:
            out.append((path, "empty"))
        elif path.suffix == ".h5":
            why = _opens(path)
            if why is not None:
                out.append((path, why))
    return out


def remove_damaged(directory: Path, notify: Callable[[str], None]) -> list[Path]:
    """Remove the damaged outputs of ``directory`` (one line each), so that the run makes them again.

    Returns
    -------
    list of Path
        What was removed (files, or the folders of :data:`WHOLE_FOLDERS` holding a damaged file).
    """
    removed: list[Path] = []
    for path, why in damaged(directory):
        rel = path.relative_to(directory).as_posix()
        whole = next((w for w in WHOLE_FOLDERS if rel.startswith(w + "/")), None)
        target = directory / whole if whole else path
        if target in removed:
            continue
        if whole:
            shutil.rmtree(target, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
        removed.append(target)
        notify(f"isorock: {rel} is damaged ({why}): removed, it is made again")
    return removed
