"""Each command imports what it needs when it needs it (issue: every command waited for its imports).

Importing a package of isorock loads no scipy.signal and no matplotlib (and the engine no ObsPy): the
heavy libraries are imported by the functions that use them. Reading and processing a record loads
neither matplotlib nor ObsPy's signal package (whose ``__init__`` imports matplotlib), a regime map of
a pulse no scipy.signal, a simulation no plotting; reading a record file whose format isorock
recognises loads no other ObsPy format plugin. Each check runs in a fresh interpreter, where
``sys.modules`` holds only what the code under test imported.

The numbers are unchanged: the functions that now stand in for ObsPy's (the Butterworth filter, the
rotation) and scipy's (the cumulative trapezoid) are checked against them, bit for bit, in
``tests/processing/test_same_samples.py``.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

#: never loaded by importing a package of isorock
PLOTTING_AND_SIGNAL = ("scipy.signal", "matplotlib")
HEAVY = (
    "scipy",
    "scipy.signal",
    "scipy.integrate",
    "matplotlib",
    "obspy",
    "obspy.signal",
    "numba",
    "pandas",
    "h5py",
    "tables",
    "pywt",
    "snakemake",
)


def _loaded(code: str) -> list[str]:
    """The modules of :data:`HEAVY` that ``code``, run in a fresh interpreter, leaves in sys.modules."""
    probe = (
        f"{code}\nimport json as _j, sys as _s\nprint(_j.dumps([m for m in {HEAVY!r} if m in _s.modules]))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


#: module -> what importing it must not load, besides scipy.signal and matplotlib
IMPORTS = {
    "isorock": ("scipy", "obspy", "numba", "pandas", "h5py"),
    "isorock.records": ("scipy", "obspy", "numba", "pandas", "h5py"),
    "isorock.physics.engine": ("scipy.integrate", "obspy", "pandas", "h5py"),  # numba imports scipy's base
    "isorock.cli": ("scipy", "obspy", "numba", "pandas", "h5py"),
    "isorock.processing": ("scipy", "numba", "pandas", "h5py"),
    "isorock.records.motion": ("scipy", "numba", "pandas", "h5py", "tables"),
    "isorock.records.table1": ("scipy", "numba", "pandas", "h5py", "tables"),
    "isorock.pulse": ("scipy", "obspy", "pywt", "numba"),
    "isorock.processing.orientation": ("scipy", "pywt", "numba"),
    "isorock.store": ("pandas", "h5py", "tables"),
    "isorock.physics.regime_maps": ("scipy.integrate", "obspy", "pandas", "h5py"),
}


@pytest.mark.parametrize("module", sorted(IMPORTS))
def test_import_loads_no_signal_processing_or_plotting(module):
    loaded = _loaded(f"import {module}")
    bad = sorted(set(loaded) & set(PLOTTING_AND_SIGNAL + IMPORTS[module]))
    assert bad == [], f"import {module} loads {bad}"


def test_public_names_still_import():
    """The lazy packages give the names they gave (PEP 562): processing, pulse, store."""
    code = (
        "from isorock.processing import STEPS, intensity, intensities, metrics, process, velocity\n"
        "from isorock.processing import pseudo_spectral_acceleration, MEASURES, qa_passed\n"
        "from isorock.pulse import extract_pulse, TP_METHODS, fit_mp, cwt_db4\n"
        "from isorock.processing import rotate_horizontal, fault_azimuth\n"
        "from isorock.store import Store, file_sha256, atomic_path, write_map, LAYOUT_VERSION, RECORD_ATTRS\n"
        "import isorock.processing as P, isorock.pulse as U, isorock.store as S\n"
        "assert callable(P.metrics) and callable(P.intensity)  # the functions, not the modules\n"
        "assert all(hasattr(m, n) for m in (P, U, S) for n in m.__all__)\n"
        "assert set(U.__all__) <= set(dir(U)) and set(S.__all__) <= set(dir(S))\n"
        "# the submodules as attributes, as when the packages imported them at once\n"
        "assert S.hdf.__name__ == 'isorock.store.hdf' and U.extract.__name__ == 'isorock.pulse.extract'\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr


def _at2(path: Path, n: int = 3000, dt: float = 0.01) -> Path:
    """A PEER AT2 file (format recognised by its header) of ``n`` samples: a decaying 1.2 Hz sine [g]."""
    t = np.arange(n) * dt
    acc = 0.3 * np.sin(2 * np.pi * 1.2 * t) * np.exp(-0.2 * t) * np.minimum(t, 1.0)
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Lazy Test, 1/1/2000, Test Station, 090",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {n:6d}, DT= {dt:7.4f} SEC,",
    ]
    lines += ["".join(f"{v:15.7E}" for v in acc[k : k + 5]) for k in range(0, n, 5)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _cli_loaded(argv: list[str]) -> list[str]:
    """What ``isorock ARGV``, run in a fresh interpreter (it must succeed), leaves in sys.modules."""
    code = (
        "import io, contextlib\nfrom isorock.cli import main\n"
        f"with contextlib.redirect_stdout(io.StringIO()):\n    assert main({argv!r}) == 0"
    )
    return _loaded(code)


def test_reading_and_processing_a_record_loads_no_plotting(tmp_path):
    """The band-pass filter and the rotation are computed without importing ObsPy's signal package."""
    f = _at2(tmp_path / "r.AT2")
    loaded = _cli_loaded(["info", str(f), "--json"])
    assert "matplotlib" not in loaded and "obspy.signal" not in loaded
    assert "scipy.signal" in loaded  # the Butterworth filter of the processing needs it


def test_a_record_of_a_known_format_loads_no_other_obspy_plugin(tmp_path):
    """Detected by isorock, the format is named to obspy.read, which then loads that plugin alone."""
    f = _at2(tmp_path / "r.AT2", n=50)
    code = (
        "import sys\nfrom isorock.io import read_record\n"
        f"tr = read_record({str(f)!r})[0]\nassert tr.stats.isorock.obspy_format == 'PEERAT2'\n"
        "print([m for m in sys.modules if m.startswith('obspy.io.')])"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


def test_a_pulse_map_loads_no_signal_processing_or_tables():
    loaded = _cli_loaded(
        ["map", "lambda-R", "--pulse", "fullsine", "--td", "0.5", "--pga", "0.5", "--n-lambda", "2",
         "--n-R", "2", "--json"]
    )  # fmt: skip
    # ObsPy's core comes with isorock.pipeline (the cost model's package); numba imports scipy's base
    assert (
        sorted(set(loaded) & {"scipy.signal", "scipy.integrate", "matplotlib", "pandas", "h5py", "tables"})
        == []
    )


def test_a_simulation_loads_no_plotting(tmp_path):
    f = _at2(tmp_path / "r.AT2")
    loaded = _cli_loaded(
        ["simulate", "--lambda", "4", "--R", "1.5", "--isolation", "linear", "--Tb", "3", "--xi", "0.2",
         "--rho", "0.5", "--record", str(f), "--pga", "0.4", "--json"]
    )  # fmt: skip
    assert "matplotlib" not in loaded and "obspy.signal" not in loaded


def test_a_table1_row_rotated_loads_no_plotting(records_dir):
    """``info --id`` of a row rotated from its two components (IMV79-EMO) loads no matplotlib."""
    loaded = _cli_loaded(["info", "--id", "IMV79-EMO", "--records", str(records_dir), "--json"])
    assert "matplotlib" not in loaded and "obspy.signal" not in loaded
