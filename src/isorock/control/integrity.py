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
#: the outputs checked for being empty: what the jobs write (a file of the user's own in results/ is left)
_OUTPUTS = (".h5", ".png", ".html", ".csv", ".rst", ".svg")
#: what HDF5 says of a file that is damaged (cut short, overwritten, never finished), as opposed to one it
#: cannot open for another reason (in use, permissions, too many open files): the first is made again,
#: the second stops the run with its reason
_DAMAGE = ("truncated file", "file signature not found", "bad object header", "addr overflow",
           "bad symbol table", "wrong B-tree signature", "address of object past end")  # fmt: skip


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

    from isorock.errors import IsorockError

    for sub in ("", "results", "logs", ".snakemake"):
        path = directory / sub
        if path.exists() and not os.access(path, os.W_OK | os.X_OK):
            raise IsorockError(
                f"{path} cannot be written (a read-only disk or its permissions): make it writable, or "
                "run in another folder (--directory DIR)"
            )


def _opens(path: Path) -> str | None:
    """None when the HDF5 file ``path`` opens and its objects can be listed, else why not.

    Raises
    ------
    IsorockError
        It cannot be opened for a reason other than damage (another program holds it, permissions).
    """
    import h5py

    from isorock.errors import IsorockError

    try:
        # without HDF5's file lock: a viewer that holds the store open is no damage
        with h5py.File(path, "r", locking=False) as f:
            f.visit(lambda name: None)
    except Exception as exc:  # h5py raises OSError, KeyError or RuntimeError
        why = str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__
        if any(d in why for d in _DAMAGE):
            return why.split("(", 1)[-1].rstrip(")") if "(" in why else why
        raise IsorockError(
            f"{path} cannot be opened ({why}): if another program has it open, close that program; then "
            "run the same command again"
        ) from None
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
        if path.stat().st_size == 0 and path.suffix in _OUTPUTS:
            out.append((path, "empty"))
        elif path.suffix == ".h5":
            why = _opens(path)
            if why is not None:
                out.append((path, why))
    return out


def remove_damaged(directory: Path, notify: Callable[[str], None]) -> list[Path]:
    """Remove the damaged outputs of ``directory`` (one line each), so that the run makes them again.

    A damaged job file (``results/jobs``) removes the store too: Snakemake does not remake a job file
    whose store is newer, but makes a missing store from every job file it needs, the removed one
    among them (and none of an earlier configuration's).

    Returns
    -------
    list of Path
        What was removed (files, or the folders of :data:`WHOLE_FOLDERS` holding a damaged file).
    """
    removed: list[Path] = []
    store = directory / "results" / "isorock.h5"
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
        if rel.startswith("results/jobs/") and store.is_file() and store not in removed:
            store.unlink()
            removed.append(store)
            notify("isorock: results/isorock.h5 is merged again, with the job file made again")
    return removed
