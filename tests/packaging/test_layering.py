"""The rooms of the package and which may import which: the import-linter contracts of pyproject.toml
(``[tool.importlinter]``; docs/contributing.md, "The rooms"), checked on the package as it is, and shown
to break on a copy of it with one import that climbs a room and one that closes a circle in a room."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LINT = Path(sys.executable).with_name("lint-imports")


def _lint(tree: Path) -> subprocess.CompletedProcess:
    """``lint-imports`` with the contracts of pyproject.toml on the package found in ``tree``."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return subprocess.run(
        [str(LINT), "--no-cache", "--config", str(ROOT / "pyproject.toml")],
        cwd=tree,
        env=env,
        capture_output=True,
        text=True,
    )


@pytest.fixture(scope="module")
def lint() -> Path:
    if not LINT.exists():  # the lock file installs import-linter with the test extra
        pytest.fail(f"{LINT} not found: install the lock file (requirements/lock-py311.txt)")
    return LINT


def test_the_rooms_keep_their_contracts(lint, tmp_path):
    shutil.copytree(ROOT / "src" / "isorock", tmp_path / "isorock")
    out = _lint(tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "3 kept, 0 broken" in out.stdout


def test_a_climbing_import_and_a_circle_break_them(lint, tmp_path):
    pkg = tmp_path / "isorock"
    shutil.copytree(ROOT / "src" / "isorock", pkg)
    with open(pkg / "physics" / "model.py", "a") as fh:  # the physics reading the command line
        fh.write("\nimport isorock.cli.records  # noqa: E402\n")
    with open(pkg / "records" / "naming.py", "a") as fh:  # the bottom of records/ reading its top
        fh.write("\nimport isorock.records.components  # noqa: E402\n")
    out = _lint(tmp_path)
    assert out.returncode != 0
    assert "isorock.physics is not allowed to import isorock.cli" in out.stdout
    assert "No cycles are allowed in isorock.records" in out.stdout
    assert ".naming -> .components" in out.stdout
