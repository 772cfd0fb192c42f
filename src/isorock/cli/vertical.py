"""``--vertical auto|FILE``: the vertical ground motion beside the record analysed (docs/model.md §17).

``auto`` looks among the files of the recording (``--id``: its catalog row's files; ``--record``: the
file itself and the files beside it that a name marks vertical) with
:func:`isorock.records.vertical.find_vertical`; ``FILE`` reads the one given. Either way the vertical is
refused when it repeats a horizontal or is not aligned with the one analysed, processed by the
horizontal's steps and attached to its ground motion sample for sample, positive up: a vertical whose
file names it ``DWN`` (positive down) has its sign reversed, and ``--vertical-positive up|down`` states
the sense of the file's samples where its name does not, or not rightly
(:func:`isorock.records.vertical.vertical_polarity`).
"""

from __future__ import annotations

import argparse
from typing import Any

from isorock.errors import IsorockError

__all__ = ["add_vertical_option", "attach_vertical"]


def add_vertical_option(p: argparse.ArgumentParser) -> None:
    """``--vertical auto|FILE``."""
    p.add_argument(
        "--vertical",
        metavar="auto|FILE",
        default=None,
        help="add the vertical ground motion (g becomes g + a_v in the block's equations, uplift and slip "
        "thresholds and the FP isolator's forces): 'auto' finds it beside the record (a PEER UP/DWN/V "
        "file, a BBP U-D column, a MiniSEED Z channel; a copy of a horizontal is refused), or give its "
        "file (read with the record's --format, --dt and --units); it is processed like the horizontal "
        "and scaled with it; it is taken positive up, its sign reversed where its file names it DWN "
        "(positive down). Default: horizontal input only",
    )
    p.add_argument(
        "--vertical-positive",
        choices=("up", "down"),
        default=None,
        help="the sense of the --vertical file's samples, when you know it better than its name says: "
        "'down' reverses their sign, 'up' takes them as read. Default: from the component's name (DWN, "
        "DOWN: down; UP and names that state no sense, U-D, V, Z: up)",
    )


def attach_vertical(a: argparse.Namespace, loaded: Any) -> tuple[Any, dict | None]:
    """The excitation of ``loaded`` with its vertical when ``--vertical`` asks, and what was attached.

    Returns
    -------
    excitation : GroundMotion or Pulse
        ``loaded.excitation``, carrying its vertical when asked.
    info : dict or None
        ``file``, ``component``, ``peak_g`` (processed, before any scaling), ``alignment``, the
        samples cut or padded, and the polarity (``positive_in_file``, ``sign``, ``polarity``: the
        sense of the file's samples, the sign applied to make them positive up, and why); None without
        ``--vertical``.
    """
    choice = getattr(a, "vertical", None)
    positive = getattr(a, "vertical_positive", None)
    if choice is None:
        if positive is not None:
            raise IsorockError("--vertical-positive states the sense of a vertical: give --vertical too")
        return loaded.excitation, None
    if loaded.record is None:
        raise IsorockError("--vertical applies to --record or --id, not to --pulse")
    from isorock.records.vertical import find_vertical, sibling_files, vertical_from_file, with_vertical

    rec = loaded.record
    raw = bool(getattr(a, "raw", False))
    processing = getattr(a, "processing", None)
    if choice == "auto":
        files = list(loaded.files) or sibling_files(rec.source.file, getattr(a, "fmt", None))
        found = find_vertical(files, rec.raw, rec.source.file, positive)
        if found.found is None:
            raise IsorockError(f"--vertical auto: {rec.source.file}: {found.describe()}")
        vc = found.found
    else:
        # read as the record's file is: the same --format, --dt and --units (its sibling)
        opts = {k: getattr(a, k, None) for k in ("fmt", "dt", "units")}
        vc = vertical_from_file(choice, rec.raw, **opts, positive=positive)
    vm = vc.motion(processing, raw=raw)
    gm = with_vertical(loaded.excitation, vm, f"--vertical {vc.file}")
    info = dict(gm.meta["vertical"])
    info.update(file=str(vc.file), component=vc.component, alignment=vc.alignment.describe())
    return gm, info
