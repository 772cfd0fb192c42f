"""isorock: rocking of free-standing rigid blocks on seismically isolated bases."""

from isorock.constants import G
from isorock.physics.excitation import GroundMotion, Pulse
from isorock.physics.model import Block, FPIsolation, LinearIsolation, NoIsolation, System
from isorock.physics.result import Result
from isorock.version import __version__

__all__ = [
    "G",
    "Block",
    "NoIsolation",
    "LinearIsolation",
    "FPIsolation",
    "System",
    "Pulse",
    "GroundMotion",
    "Result",
    "simulate",
    "load_motion",
    "load_record",
    "load_table1",
    "__version__",
]


def simulate(*args, **kwargs) -> Result:
    """Run one analysis with the compiled engine; see :func:`isorock.physics.engine.simulate`.

    The engine (and numba) is imported on the first call, so that ``import isorock`` stays light.
    """
    from isorock.physics.engine import simulate as _simulate

    return _simulate(*args, **kwargs)


def __getattr__(name: str):
    """``isorock.load_motion``, ``isorock.load_record`` (:mod:`isorock.records.motion`) and
    ``isorock.load_table1`` (:mod:`isorock.records.table1`), imported on first use: reading records needs
    ObsPy, which ``import isorock`` does not load."""
    if name in ("load_motion", "load_record"):
        import isorock.records.motion as motion

        return getattr(motion, name)
    if name == "load_table1":
        from isorock.records.table1 import load_table1

        return load_table1
    raise AttributeError(f"module 'isorock' has no attribute {name!r}")
