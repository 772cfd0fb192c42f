"""Build step of isorock: ship the workflow and the record catalog inside the wheel.

Everything else is configured in pyproject.toml. The workflow that the ``isorock`` command runs
(``Snakefile``, ``workflow/``, ``config/``) and the Table 1 catalog (``data/records/``) live at the
top of the repository, as the Snakemake workflow template lays them out; this build step copies
them into the package as ``isorock/_workflow/``, so that a wheel installed anywhere finds them
(:mod:`isorock.resources`). An editable install reads the source tree instead.
"""

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
TREE = ("Snakefile", "workflow", "config", "data/records")
IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", ".snakemake", "*.tmp")


class BuildPyWithWorkflow(build_py):
    """``build_py`` that also copies the workflow tree into ``isorock/_workflow``."""

    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        dst = Path(self.build_lib) / "isorock" / "_workflow"
        for name in TREE:
            src, target = ROOT / name, dst / name
            if src.is_dir():
                shutil.copytree(src, target, ignore=IGNORE, dirs_exist_ok=True)
            else:
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(src, target)


setup(cmdclass={"build_py": BuildPyWithWorkflow})
