"""The engine's compiled-code cache: kept fresh for the engine's sources, and announced when built.

numba caches each compiled function beside its source (``__pycache__``, or ``NUMBA_CACHE_DIR``)
and checks only the file that defines it: the kernel's entry points live in ``kernel.py``, but their
code is mostly inlined from ``_contact.py``, ``_rocking.py``, ``_series.py`` ..., so an upgrade or an
edit that changes only those would load a stale kernel. :func:`refresh` keeps a digest of all the
engine's sources beside the cache and drops the engine's cache files when it changes.

The engine is compiled once per installation (and machine), an entry point at a time: the first
analysis compiles that of its isolation model and mode (about 10 s), the first analysis of another
model or mode its own (a few seconds more: the regime loops are shared). A compilation says so on
stderr (:func:`announce`), once per process, where it would otherwise pause silently.
``isorock --warm-up`` compiles them all ahead of use.
"""

from __future__ import annotations

import hashlib
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

from numba.core import event

from isorock.timings import about

__all__ = ["ENGINE_SOURCES", "source_digest", "refresh", "announce", "MESSAGE"]

ENGINE_SOURCES = (
    "_layout.py",
    "_model.py",
    "_numerics.py",
    "_series.py",
    "_contact.py",
    "_rocking.py",
    "_sliding.py",
    "kernel.py",
    "_filter.py",
)
"""The engine modules compiled by numba (their digest keys the cache)."""

_STAMP = "isorock-engine.sha256"
MESSAGE = (
    "isorock: compiling the engine, first run only (of this isolation model and mode: "
    f"{about('first_analysis')}; the compiled code is kept in {{where}} and loaded in well under a second "
    "from then on)"
)


def source_digest() -> str:
    """SHA-256 of the engine's compiled sources (:data:`ENGINE_SOURCES`), hex."""
    here = Path(__file__).parent
    h = hashlib.sha256()
    for name in ENGINE_SOURCES:
        h.update(name.encode())
        h.update((here / name).read_bytes())
    return h.hexdigest()


def _cache_dir(dispatcher: Any) -> Path | None:
    cache = getattr(dispatcher, "_cache", None)
    path = getattr(cache, "_cache_path", None)
    return Path(path) if path else None


def refresh(dispatcher: Any) -> bool:
    """Drop the engine's cached code where it was compiled from other sources than these.

    Parameters
    ----------
    dispatcher : numba dispatcher
        A cached engine function (its cache directory is that of every engine function).

    Returns
    -------
    bool
        True if stale cache files were removed. A cache directory that cannot be read or written is
        left alone (numba then compiles in memory or uses its own fallback).
    """
    where = _cache_dir(dispatcher)
    if where is None or not where.is_dir():
        return False
    stamp = where / _STAMP
    digest = source_digest()
    try:
        if stamp.is_file() and stamp.read_text().strip() == digest:
            return False
        removed = False
        stems = tuple(Path(n).stem + "." for n in ENGINE_SOURCES)
        for f in where.iterdir():
            if f.name.startswith(stems) and f.suffix in (".nbi", ".nbc"):
                f.unlink(missing_ok=True)
                removed = True
        fd, tmp = tempfile.mkstemp(dir=where, prefix=".stamp-")
        with os.fdopen(fd, "w") as fh:
            fh.write(digest + "\n")
        os.replace(tmp, stamp)
        return removed
    except OSError:
        return False


class _Announcer(event.Listener):
    """Prints :data:`MESSAGE` once, when numba starts compiling an engine function."""

    def __init__(self, where: Path | None) -> None:
        self.where = where
        self.done = False

    def on_start(self, ev: event.Event) -> None:
        if self.done:
            return
        disp = (ev.data or {}).get("dispatcher")
        module = getattr(getattr(disp, "py_func", None), "__module__", "") or ""
        if module.startswith("isorock.physics.engine"):
            self.done = True
            where = str(self.where) if self.where else "numba's cache"
            print(MESSAGE.format(where=where), file=sys.stderr, flush=True)

    def on_end(self, ev: event.Event) -> None:
        pass


def announce(dispatcher: Any) -> None:
    """Say once on stderr when the engine starts compiling (numba's ``numba:compile`` event)."""
    event.register("numba:compile", _Announcer(_cache_dir(dispatcher)))
