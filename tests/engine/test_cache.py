"""The engine's compiled-code cache: fresh for its sources, and a first compilation that says so."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

from isorock.physics.engine import _cache
from isorock.physics.engine import kernel as K


def _fake_dispatcher(where: Path) -> SimpleNamespace:
    return SimpleNamespace(_cache=SimpleNamespace(_cache_path=str(where)))


def test_cache_of_other_sources_is_dropped(tmp_path: Path) -> None:
    stale = [tmp_path / "kernel.run-388.py311.nbi", tmp_path / "_contact._contact_phase-466.py311.1.nbc"]
    other = tmp_path / "mymodule.f-10.py311.nbi"  # not the engine's: kept
    for f in (*stale, other):
        f.write_bytes(b"x")
    (tmp_path / "isorock-engine.sha256").write_text("0" * 64 + "\n")
    assert _cache.refresh(_fake_dispatcher(tmp_path)) is True
    assert not any(f.exists() for f in stale)
    assert other.exists()
    assert (tmp_path / "isorock-engine.sha256").read_text().strip() == _cache.source_digest()
    # a fresh cache is left alone
    stale[0].write_bytes(b"x")
    assert _cache.refresh(_fake_dispatcher(tmp_path)) is False
    assert stale[0].exists()


def test_digest_covers_every_compiled_module() -> None:
    engine = Path(K.__file__).parent
    njit_modules = {p.name for p in engine.glob("*.py") if "@njit" in p.read_text()}
    assert njit_modules == set(_cache.ENGINE_SOURCES)


def test_first_analysis_says_it_compiles_once(tmp_path: Path) -> None:
    """A fresh install's first analysis (empty cache) says so on stderr; the next one loads the cache
    and says nothing."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    cmd = [sys.executable, "-m", "isorock.cli", "simulate", "--lambda", "4", "--R", "1.5", "--pulse", "rect",
           "--td", "0.2", "--pga", "0.4", "--isolation", "linear", "--Tb", "3", "--xi", "0.2",
           "--rho", "0.5"]  # fmt: skip
    first = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    assert first.stderr.count("compiling the engine, first run only") == 1, first.stderr
    second = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    assert "compiling" not in second.stderr
    assert second.stdout == first.stdout
