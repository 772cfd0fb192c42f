"""The package's rooms and what each may import (the subpackage docstrings state the rules).

* ``import isorock.records`` (and each of its modules) loads neither numba, Snakemake nor matplotlib;
* the lower rooms (physics, io, records, assessment, processing, pulse, store) never import the
  workflow (:mod:`isorock.pipeline`, :mod:`isorock.control`, :mod:`isorock.jobs`, :mod:`isorock.report`)
  or the command line; records never imports the engine (the whole order of the rooms is the
  import-linter contract of pyproject.toml, tests/packaging/test_layering.py);
* nothing outside :mod:`isorock.physics.engine` reads the compiled kernel or sets numba's threads;
* every subpackage opens with a docstring saying what it holds; the Layout of the source of
  docs/contributing.md names every module and subpackage of ``src/isorock``.
"""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "src" / "isorock"
LOWER = ("physics", "io", "records", "assessment", "processing", "pulse", "store")
#: the rooms of the workflow: the API module that gathers them, its control, its jobs, its report
WORKFLOW = ("isorock.pipeline", "isorock.control", "isorock.jobs", "isorock.report", "isorock.cli")


def _imports(path: Path) -> set[str]:
    """Absolute names of the isorock modules ``path`` imports (relative imports resolved)."""
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    package = parts[:-1] if parts[-1] != "__init__" else parts[:-1]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
    return {m for m in out if m == "isorock" or m.startswith("isorock.")}


def _modules(room: str) -> list[Path]:
    found = sorted((PKG / room).rglob("*.py"))
    assert found, f"no room {room} in {PKG}"
    return found


@pytest.mark.parametrize(
    "module",
    [
        "isorock.records",
        "isorock.records.lookup",
        "isorock.records.table1",
        "isorock.records.motion",
        "isorock.records.manifest",
        "isorock.records.components",
        "isorock.records.spec",
        "isorock.records.adding",
        "isorock.records.vertical",
    ],
)
def test_records_import_no_engine_workflow_or_plotting(module):
    code = (
        f"import json, sys; import {module}; "
        "print(json.dumps([m for m in ('numba', 'snakemake', 'matplotlib') if m in sys.modules]))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == []


@pytest.mark.parametrize("room", LOWER)
def test_lower_rooms_never_import_the_workflow_or_the_cli(room):
    bad = {
        str(p.relative_to(PKG)): sorted(m for m in _imports(p) if m.startswith(WORKFLOW))
        for p in _modules(room)
    }
    assert {k: v for k, v in bad.items() if v} == {}


def test_records_and_io_do_not_import_the_engine():
    for room in ("records", "io"):
        for p in _modules(room):
            assert not [m for m in _imports(p) if m.startswith("isorock.physics.engine")], p


def test_assessment_does_not_import_figures():
    for p in _modules("assessment"):
        assert not [m for m in _imports(p) if m.startswith("isorock.figures")], p


def test_only_the_engine_reads_the_kernel_or_sets_threads():
    offenders = []
    for p in sorted(PKG.rglob("*.py")):
        if (PKG / "physics" / "engine") in p.parents:
            continue
        text = p.read_text()
        if re.search(r"set_num_threads|\bkernel\b.*\bimport\b|import kernel|\bK\.R_|\bK\.run", text):
            offenders.append(str(p.relative_to(PKG)))
        if "isorock.physics.engine.kernel" in _imports(p):
            offenders.append(str(p.relative_to(PKG)))
    assert offenders == []


def test_every_subpackage_says_what_it_holds_and_may_import():
    for init in sorted(PKG.glob("*/__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text())) or ""
        assert len(doc.split()) >= 20, init
    for room in ("records", "assessment"):
        doc = ast.get_docstring(ast.parse((PKG / room / "__init__.py").read_text())) or ""
        assert "may import" in doc, room


def test_contributing_layout_names_every_module():
    text = (ROOT / "docs" / "contributing.md").read_text()
    layout = text.split("## Layout of the source", 1)[1].split("\n## ", 1)[0]
    names = {p.name for p in PKG.glob("*.py") if p.name != "__init__.py"}
    names |= {p.name + "/" for p in PKG.iterdir() if p.is_dir() and (p / "__init__.py").is_file()}
    for sub in (
        "records",
        "assessment",
        "physics",
        "physics/engine",
        "jobs",
        "control",
        "report",
        "cli",
        "store",
    ):
        names |= {p.name for p in (PKG / sub).glob("*.py") if p.name != "__init__.py"}
    names = {n for n in names if not n.startswith("_")}
    missing = sorted(n for n in names if not re.search(rf"(?<![\w/]){re.escape(n)}", layout))
    assert missing == []
