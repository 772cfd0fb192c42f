"""isorock's version, as installed (the distribution's metadata)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("isorock")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
