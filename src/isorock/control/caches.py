"""Where a run's caches go: the user's cache folder when it can be written, else the run folder.

Snakemake keeps a cache of the workflow's sources in the user's cache folder
(``platformdirs.user_cache_dir``: ``$XDG_CACHE_HOME``, else ``$HOME/.cache``) and stops with a
traceback when it cannot create it (a ``HOME`` on a read-only disk, or of another user, as on some
cluster nodes and containers). :func:`cache_environment` tries that folder first; when it cannot be
written, the run's caches go to ``.snakemake/cache`` of the run folder (``XDG_CACHE_HOME`` and, for
matplotlib's font cache, ``MPLCONFIGDIR`` are set for Snakemake and its jobs) and one line says so;
when neither can be written, the run stops with one line naming ``HOME``.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path

from isorock.errors import IsorockError

__all__ = ["user_cache_dir", "cache_environment", "RUN_CACHE"]

#: the caches of a run whose user cache folder cannot be written, relative to the run folder
RUN_CACHE = ".snakemake/cache"


def user_cache_dir(environ: Mapping[str, str] | None = None) -> tuple[Path | None, str]:
    """The user's cache folder as Snakemake finds it, and what names it.

    Returns
    -------
    (Path or None, str)
        ``$XDG_CACHE_HOME`` when set (an absolute path), else ``$HOME/.cache``; None when neither is
        set. The second item says where it comes from (``XDG_CACHE_HOME``, ``HOME``).
    """
    env = os.environ if environ is None else environ
    xdg = env.get("XDG_CACHE_HOME", "").strip()
    if xdg and os.path.isabs(xdg):
        return Path(xdg), "XDG_CACHE_HOME"
    home = env.get("HOME", "").strip() or os.path.expanduser("~")
    return (Path(home) / ".cache", "HOME") if home and home != "~" else (None, "HOME")


def _writable(folder: Path) -> str | None:
    """None when a file can be created in ``folder`` (created with its parents), else why not."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


def cache_environment(directory: Path, notify: Callable[[str], None]) -> dict[str, str]:
    """The environment variables that send Snakemake's and its jobs' caches where they can be written.

    Parameters
    ----------
    directory : Path
        The run folder.
    notify : callable
        Called with the line saying that the caches go to the run folder.

    Returns
    -------
    dict
        Empty when the user's cache folder can be written; else ``XDG_CACHE_HOME`` (and
        ``MPLCONFIGDIR`` when not set) under :data:`RUN_CACHE` of ``directory``.

    Raises
    ------
    IsorockError
        Neither the user's cache folder nor the run folder can be written.
    """
    cache, source = user_cache_dir()
    why = _writable(cache / "snakemake") if cache is not None else "it is not set"
    if why is None:
        return {}
    where = f"{source}={os.environ.get(source, '')}" if source in os.environ else source
    here = directory / RUN_CACHE
    if _writable(here) is not None:
        raise IsorockError(
            f"the cache folder {cache} ({where}) cannot be written ({why}), nor can {here}: set HOME or "
            "XDG_CACHE_HOME to a folder that can be written"
        )
    notify(
        f"isorock: the cache folder {cache} ({where}) cannot be written ({why}): this run's caches go to "
        f"{here} (set XDG_CACHE_HOME to choose another)"
    )
    env = {"XDG_CACHE_HOME": str(here.resolve())}
    if not os.environ.get("MPLCONFIGDIR"):
        env["MPLCONFIGDIR"] = str((here / "matplotlib").resolve())
    return env
