"""The options shared by the commands, each defined once: the record file, the block, the isolation,
the pulse; and the functions that turn parsed options into isorock objects.

Every command that reads a record file uses :func:`add_record_options` (the same flags, choices and
destinations: ``fmt``, ``dt``, ``units``, ``component``) and :func:`read_record_trace`; every command
that analyses a block uses :func:`add_block_options` / :func:`add_isolation_options` and
:func:`system_from_args`.
"""

from __future__ import annotations

import argparse

from ..constants import ISOLATION_KINDS, PULSE_SHAPES, UNITS
from ..errors import IsorockError, RecordError

__all__ = [
    "format_type",
    "add_record_options",
    "add_block_options",
    "add_isolation_options",
    "add_pulse_options",
    "add_json_option",
    "read_record_trace",
    "isolation_from_args",
    "system_from_args",
    "excitation_from_args",
]


def format_type(value: str) -> str:
    """argparse type of ``--format``: a record format by its manifest name or ObsPy name -> manifest name."""
    from ..io import FORMATS, OBSPY_FORMATS, obspy_format

    try:
        name = obspy_format(value)
    except RecordError:
        raise argparse.ArgumentTypeError(
            f"invalid choice: {value!r} (choose from {', '.join(FORMATS)})"
        ) from None
    return next(k for k, v in OBSPY_FORMATS.items() if v == name)


def add_record_options(p: argparse.ArgumentParser, *, positional: bool) -> None:
    """How to read a record file: ``--format``, ``--dt``, ``--units``, ``--component``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The command.
    positional : bool
        Also add the file itself as the positional ``FILE`` (``dest="file"``); otherwise the caller
        offers it as ``--record FILE`` (:func:`add_excitation_options`).
    """
    from ..io import FORMATS

    g = p.add_argument_group("record file")
    if positional:
        g.add_argument("file", metavar="FILE", help="accelerogram file")
    g.add_argument(
        "--format",
        dest="fmt",
        type=format_type,
        default=None,
        metavar="FORMAT",
        help=f"record format: {', '.join(FORMATS)} (detected for peer-at2, bbp, pyslammer-csv)",
    )
    g.add_argument("--dt", type=float, default=None, metavar="S", help="time step [s] (files that omit it)")
    g.add_argument(
        "--units",
        default=None,
        metavar="UNITS",
        help=f"units of the values: {', '.join(UNITS)} (or gal, cm/s/s, m/s^2 ...); checked by the reader",
    )
    g.add_argument("--component", default=None, help="component of a multi-component file (e.g. N-S, 164)")


def add_block_options(p: argparse.ArgumentParser, *, required: bool = True) -> None:
    """The block: ``--lambda`` (``dest="lam"``) and ``--R``."""
    g = p.add_argument_group("block")
    g.add_argument("--lambda", dest="lam", type=float, required=required, help="slenderness h/b [-]")
    g.add_argument("--R", dest="R", type=float, required=required, help="half-diagonal of the block [m]")


def add_isolation_options(p: argparse.ArgumentParser, *, kinds: tuple[str, ...] = ISOLATION_KINDS) -> None:
    """The isolation: ``--isolation`` and the parameters of the linear and FP models."""
    g = p.add_argument_group("isolation")
    g.add_argument("--isolation", choices=kinds, default=kinds[0], help="isolation model")
    g.add_argument("--Tb", type=float, default=None, help="isolation period [s] (linear; fp if --Rb absent)")
    if "linear" in kinds:
        g.add_argument("--xi", type=float, default=None, help="isolation damping ratio [-] (linear)")
    g.add_argument("--rho", type=float, default=None, help="block-to-base mass ratio m/m_b [-]")
    if "fp" in kinds:
        g.add_argument("--mu", type=float, default=None, help="FP friction coefficient [-]")
        g.add_argument("--Rb", type=float, default=None, help="FP radius of curvature [m]")


def add_pulse_options(g: argparse._ArgumentGroup, *, amplitude: bool) -> None:
    """``--td`` and, with ``amplitude``, ``--amp`` [g] of a pulse (``--pulse`` is in the caller's
    mutually exclusive group with the record)."""
    g.add_argument("--td", type=float, default=None, help="pulse half-cycle duration [s]")
    if amplitude:
        g.add_argument("--amp", type=float, default=None, help="pulse amplitude [g]")


def add_excitation_options(p: argparse.ArgumentParser) -> argparse._ArgumentGroup:
    """``--pulse SHAPE`` or ``--record FILE`` (exactly one), the record-reading options and ``--td``;
    returns the group, for the caller's amplitude options."""
    add_record_options(p, positional=False)
    g = p.add_argument_group("excitation (a pulse or a record)")
    src = g.add_mutually_exclusive_group(required=True)
    src.add_argument("--pulse", choices=PULSE_SHAPES, help="pulse shape (paper Eqs. 36-38)")
    src.add_argument("--record", metavar="FILE", help="accelerogram file")
    return g


def add_json_option(p: argparse.ArgumentParser) -> None:
    """``--json``: print one JSON object."""
    p.add_argument("--json", action="store_true", help="print one JSON object")


# ------------------------------------------------------------------------------------------ builders
_ISOLATION_FLAGS = {"Tb_s": "--Tb", "xi_b": "--xi", "rho": "--rho", "mu_b": "--mu", "R_b_m": "--Rb"}


def read_record_trace(path: str, a: argparse.Namespace):
    """The one trace of the record file ``path``, read with the record options of ``a``."""
    from ..io import read_trace

    return read_trace(path, a.fmt, dt=a.dt, units=a.units, component=a.component)


def isolation_from_args(a: argparse.Namespace):
    """The isolation named by ``--isolation`` and its parameters (:func:`isorock.model.make_isolation`)."""
    from ..model import make_isolation

    values = {
        "Tb_s": a.Tb,
        "xi_b": getattr(a, "xi", None),
        "rho": a.rho,
        "mu_b": getattr(a, "mu", None),
        "R_b_m": getattr(a, "Rb", None),
    }
    return make_isolation(a.isolation, **values, names=_ISOLATION_FLAGS)


def system_from_args(a: argparse.Namespace):
    """The :class:`~isorock.model.System` named by the block and isolation options."""
    from ..model import Block, System

    return System(Block.from_lambda_R(a.lam, a.R), isolation_from_args(a))


def excitation_from_args(a: argparse.Namespace, *, amplitude: bool):
    """The excitation of ``--pulse``/``--record`` and the scale factor to apply to it.

    With ``amplitude`` a pulse takes its amplitude from ``--amp`` and a record its factor from
    ``--scale``; without, the pulse has unit amplitude and the factor is 1.
    """
    from ..excitation import Pulse
    from ..io import to_ground_motion

    if a.pulse:
        if a.td is None:
            raise IsorockError("--pulse needs --td (half-cycle duration, s)")
        if amplitude:
            if a.amp is None:
                raise IsorockError("--pulse needs --amp (amplitude, g)")
            return Pulse(a.pulse, a.td, a.amp), 1.0
        return Pulse(a.pulse, a.td, 1.0), 1.0
    gm = to_ground_motion(read_record_trace(a.record, a))
    scale = getattr(a, "scale", 1.0) if amplitude else 1.0
    if not scale > 0:
        raise IsorockError(f"--scale {scale} must be > 0")
    return gm, scale
