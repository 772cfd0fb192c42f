"""The software a result was computed with: versions of Python, the numerical packages and the platform.

:func:`versions` is the one list: the merge writes it on the root of ``results/isorock.h5``
(:func:`store_attrs`: ``version_<name>``, ``platform``, ``platform_machine``; see :mod:`isorock.store`)
and ``isorock info --versions`` prints it. The versions are read from the installed distributions'
metadata (:mod:`importlib.metadata`), so nothing is imported: asking costs milliseconds, not the
seconds that loading numba, ObsPy or Snakemake takes. The exact versions the project is tested with
are pinned in ``requirements/lock-py3*.txt``.
"""

from __future__ import annotations

import platform
from importlib import metadata

from isorock.version import __version__

__all__ = ["PACKAGES", "NOT_INSTALLED", "versions", "store_attrs"]

#: the distributions whose versions are recorded, in the order printed: isorock itself, the numerical
#: stack that decides the numbers (numba compiles the engine with llvmlite's LLVM), the readers and
#: writers of records and of the store, and the workflow manager
PACKAGES: tuple[str, ...] = (
    "isorock",
    "numpy",
    "scipy",
    "numba",
    "llvmlite",
    "obspy",
    "h5py",
    "pandas",
    "snakemake",
)

#: the version given for a distribution that is not installed (Snakemake is optional outside the workflow)
NOT_INSTALLED = "not installed"


def _version(name: str) -> str:
    """The installed version of distribution ``name``, or :data:`NOT_INSTALLED`."""
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return NOT_INSTALLED


def versions() -> dict[str, str]:
    """Versions of Python and of :data:`PACKAGES`, then the platform, as text.

    Returns
    -------
    dict of str to str
        ``python`` (:func:`platform.python_version`), one key per name of :data:`PACKAGES` (its
        version, or ``"not installed"``), ``platform`` (:func:`platform.platform`, e.g.
        ``Linux-6.1.0-x86_64-with-glibc2.36``) and ``machine`` (:func:`platform.machine`, e.g.
        ``x86_64``), in that order.
    """
    out = {"python": platform.python_version()}
    # isorock's own: the version it reports (__version__, the store's isorock_version), also when it
    # runs from a source tree that is not installed
    out.update({name: __version__ if name == "isorock" else _version(name) for name in PACKAGES})
    out["platform"] = platform.platform()
    out["machine"] = platform.machine()
    return out


def store_attrs() -> dict[str, str]:
    """The root attributes of the store that record :func:`versions`.

    Returns
    -------
    dict of str to str
        ``version_<name>`` for Python and every package of :data:`PACKAGES` but isorock (already the
        root attribute ``isorock_version``), then ``platform`` and ``platform_machine``.
    """
    v = versions()
    out = {f"version_{k}": s for k, s in v.items() if k not in ("isorock", "platform", "machine")}
    out["platform"] = v["platform"]
    out["platform_machine"] = v["machine"]
    return out
