"""Where the files that come with isorock are: the workflow, its configurations and the record catalog.

The workflow that ``isorock report`` runs (``Snakefile``, ``workflow/``, ``config/``) and the Table 1
catalog (``data/records/``) live at the top of the repository, as the Snakemake workflow template
lays them out. A wheel carries a copy of that tree inside the package, ``isorock/_workflow/``, made
by the build step in ``setup.py``; an editable install (``pip install -e``) reads the source tree
itself, so that an edit there takes effect at once. :func:`workflow_root` returns whichever is
present; every other function here is a path below it.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from isorock.errors import IsorockError

__all__ = [
    "PACKAGED_TREE",
    "workflow_root",
    "snakefile",
    "config_schema",
    "default_config",
    "config_file",
    "catalog_csv",
    "catalog_schema",
    "profile_dir",
]

PACKAGED_TREE = "_workflow"
"""Folder of the package that holds the copy of the workflow tree in a wheel."""

_SOURCE_TREE = Path(__file__).resolve().parents[2]


def _is_tree(path: Path) -> bool:
    return (path / "Snakefile").is_file() and (path / "workflow" / "rules").is_dir()


def workflow_root() -> Path:
    """The folder holding ``Snakefile``, ``workflow/``, ``config/`` and ``data/records/``.

    Returns
    -------
    Path
        ``isorock/_workflow`` of an installed wheel, else the source tree of an editable install.

    Raises
    ------
    IsorockError
        Neither is present (a broken installation).
    """
    packaged = Path(str(resources.files("isorock").joinpath(PACKAGED_TREE)))
    for root in (packaged, _SOURCE_TREE):
        if _is_tree(root):
            return root
    raise IsorockError(
        f"the isorock workflow files are missing (looked in {packaged} and {_SOURCE_TREE}): reinstall isorock"
    )


def snakefile() -> Path:
    """The workflow's ``Snakefile``."""
    return workflow_root() / "Snakefile"


def config_schema() -> Path:
    """JSON Schema (YAML) of the workflow configuration."""
    return workflow_root() / "workflow" / "schemas" / "config.schema.yaml"


def config_file(name: str) -> Path:
    """A shipped workflow configuration, ``config/<name>`` (``config.yaml``, ``ci.yaml``, ``paper.yaml``)."""
    return workflow_root() / "config" / name


def default_config() -> Path:
    """The default workflow configuration ``config/config.yaml``."""
    return config_file("config.yaml")


def catalog_csv() -> Path:
    """The Table 1 record catalog ``data/records/catalog.csv``."""
    return workflow_root() / "data" / "records" / "catalog.csv"


def catalog_schema() -> Path:
    """JSON Schema (YAML) of one catalog row."""
    return workflow_root() / "data" / "records" / "catalog.schema.yaml"


def profile_dir(name: str = "default") -> Path:
    """A Snakemake workflow profile, ``workflow/profiles/<name>``."""
    return workflow_root() / "workflow" / "profiles" / name
