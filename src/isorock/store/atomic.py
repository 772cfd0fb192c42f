"""Atomic writes (a temporary name, renamed when complete), the locks that serialise the writers of a
file, and the hashes that identify inputs."""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from isorock.version import __version__

if TYPE_CHECKING:
    import h5py

# h5py and the layout (pandas) are imported where a file is written: the hashes and atomic_path, which
# reading a record uses, need neither

__all__ = ["atomic_path", "atomic_h5", "try_lock", "locked", "stamp", "config_hash", "file_sha256"]


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, *, copy_existing: bool = False) -> Iterator[Path]:
    """A temporary path next to ``path``, renamed to ``path`` when the block ends without an error.

    The temporary name starts with a dot and ends with ``.tmp``; on any exception (including
    ``KeyboardInterrupt``) it is removed and ``path`` is left as it was. A process killed inside the
    block leaves only the dot-file, never a file under the final name.

    Parameters
    ----------
    path : path-like
        Final file name (its directory is created).
    copy_existing : bool
        Start from a copy of an existing ``path`` instead of an absent file.

    Yields
    ------
    Path
        The temporary file (absent at first unless ``copy_existing``): write it with any library,
        closing it before the block ends.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        if copy_existing and path.exists():
            shutil.copyfile(path, tmp)
        else:
            tmp.unlink()
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"{tmp}: nothing was written")
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise


@contextlib.contextmanager
def atomic_h5(path: str | os.PathLike, mode: str = "w") -> Iterator[h5py.File]:
    """Open an HDF5 file for writing under a temporary name; rename it to ``path`` on success.

    The root gets the attributes ``isorock_version`` and ``layout_version``.

    Parameters
    ----------
    path : path-like
        Final file name.
    mode : {"w", "a"}
        ``"a"`` copies an existing ``path`` first and adds to the copy.
    """
    import h5py

    with atomic_path(path, copy_existing=(mode == "a")) as tmp, h5py.File(tmp, "a") as f:
        stamp(f)
        yield f


def try_lock(path: str | os.PathLike) -> int | None:
    """Take an exclusive ``flock`` on the lock file ``path`` (created) without waiting.

    The kernel lets the lock go when its holder ends, ``kill -9`` included, so that a lock is never
    left behind by a killed process. The run lock (:mod:`isorock.control.runlock`) and the lock of a
    records directory's manifest (:func:`locked`) are this one.

    Returns
    -------
    int or None
        The descriptor holding the lock (close it to let the lock go), or None when another process
        holds it. On a file system without ``flock`` (some network mounts) the descriptor is returned
        without a lock.
    """
    import fcntl

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        return None
    except OSError:  # no flock on this file system: nothing more can be done here
        return fd
    return fd


@contextlib.contextmanager
def locked(path: str | os.PathLike, waiting: Callable[[], None] | None = None) -> Iterator[None]:
    """Hold an exclusive ``flock`` on the lock file ``path`` for the block, waiting for another holder.

    Parameters
    ----------
    path : path-like
        The lock file (created, never removed: removing it would let two processes hold locks on two
        different files of the same name).
    waiting : callable, optional
        Called once, before waiting, when another process holds the lock (to say so).
    """
    import fcntl

    fd = try_lock(path)
    if fd is None:
        if waiting is not None:
            waiting()
        fd = os.open(Path(path), os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except BaseException:
            os.close(fd)
            raise
    try:
        yield
    finally:
        os.close(fd)


def stamp(f: h5py.Group) -> None:
    """Write ``isorock_version`` and ``layout_version`` on a file's root group."""
    from isorock.store.layout import LAYOUT_VERSION

    f.attrs["isorock_version"] = __version__
    f.attrs["layout_version"] = LAYOUT_VERSION


def config_hash(obj: Any) -> str:
    """sha256 (hex) of the canonical JSON of ``obj`` (sorted keys): the configuration hash."""
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def file_sha256(path: str | os.PathLike) -> str:
    """sha256 (hex) of a file's bytes: the record checksum."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
