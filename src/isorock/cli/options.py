"""The options shared by the commands, each defined once, and the functions that turn them into
isorock objects.

* the record file and how to read and process it (:func:`add_record_options`): ``--format``,
  ``--dt``, ``--units``, ``--component``, ``--processing``, ``--raw``; :func:`load_from_args` reads
  it through :func:`isorock.records.motion.load_record`, the one path from a file to a ground motion;
* the block (:func:`add_block_options`: ``--lambda``/``--R`` or ``--height``/``--width``, turned into a
  :class:`~isorock.physics.model.Block` by :func:`block_from_args`) and the isolation
  (:func:`add_isolation_options`);
* a Table 1 row instead of a file (:func:`add_catalog_id_options`): ``--id ID [--records DIR]``,
  looked up by :func:`isorock.records.lookup.catalog_record` and its component chosen by
  :func:`isorock.records.components.choose_component` (:func:`choice_from_args`);
* the excitation (:func:`add_excitation_options`): ``--pulse SHAPE --td S``, ``--record FILE`` or
  ``--id ID``, with the amplitude ``--pga G`` (the PGA a pulse has or a processed record is scaled
  to; ``--amp`` is its deprecated alias) or, for a record, ``--scale F``;
  :func:`excitation_from_args` returns it as a :class:`LoadedExcitation`;
* the largest PGA a minimum-overturning search scans (:func:`add_pga_max_option`): ``--pga-max G``
  (``--amp-max`` is its deprecated alias).

Options a command would ignore are refused (:func:`check_unused`, :func:`isolation_from_args`), so
that a mistyped combination never runs silently as something else.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from isorock.constants import ISOLATION_KINDS, PULSE_SHAPES, UNITS
from isorock.errors import IsorockError, RecordError
from isorock.plausibility import (
    AMP_MAX_G,
    PERIOD_MAX_S,
    PERIOD_MIN_S,
    check_duration,
    check_finite,
    check_isolator,
    check_object,
)

__all__ = [
    "DeprecatedAlias",
    "format_type",
    "add_record_options",
    "add_catalog_id_options",
    "add_block_options",
    "add_isolation_options",
    "add_excitation_options",
    "add_pga_option",
    "add_pga_max_option",
    "RefusedOption",
    "add_json_option",
    "load_from_args",
    "isolation_from_args",
    "block_from_args",
    "block_text",
    "system_from_args",
    "excitation_from_args",
    "LoadedExcitation",
    "choice_from_args",
    "check_unused",
    "processing_text",
]

#: record options that only apply to --record (refused with --pulse)
RECORD_ONLY = ("fmt", "dt", "units", "component", "processing", "raw", "scale")
_FLAGS = {
    "fmt": "--format",
    "dt": "--dt",
    "units": "--units",
    "component": "--component",
    "processing": "--processing",
    "raw": "--raw",
    "scale": "--scale",
    "td": "--td",
}


def format_type(value: str) -> str:
    """argparse type of ``--format``: a record format by its manifest name or ObsPy name -> manifest name."""
    from isorock.io import FORMATS, OBSPY_FORMATS, obspy_format

    try:
        name = obspy_format(value)
    except RecordError:
        raise argparse.ArgumentTypeError(
            f"invalid choice: {value!r} (choose from {', '.join(FORMATS)})"
        ) from None
    return next(k for k, v in OBSPY_FORMATS.items() if v == name)


def add_record_options(p: argparse.ArgumentParser, *, positional: bool, processing: bool = True) -> None:
    """How to read and process a record file.

    The file ``-`` is standard input (:mod:`isorock.cli.stdin`), read with ``--format``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The command.
    positional : bool
        Also add the file itself as the positional ``FILE`` (``dest="file"``); otherwise the caller
        offers it (``--record FILE``, :func:`add_excitation_options`).
    processing : bool
        Add ``--processing`` and ``--raw`` (commands that analyse the record).
    """
    from isorock.io import FORMATS

    g = p.add_argument_group("record file")
    if positional:
        g.add_argument(
            "file",
            metavar="FILE",
            nargs="?",
            help="accelerogram file (or --id); - reads it from standard input (with --format)",
        )
        add_catalog_id_options(g)
    g.add_argument(
        "--format",
        dest="fmt",
        type=format_type,
        default=None,
        metavar="FORMAT",
        help=f"record format: {', '.join(FORMATS)} (detected for peer-at2, bbp, pyslammer-csv and "
        "plain numbers in one or two columns; required for a record on standard input, FILE -)",
    )
    g.add_argument("--dt", type=float, default=None, metavar="S", help="time step [s] (files that omit it)")
    g.add_argument(
        "--units",
        default=None,
        metavar="UNITS",
        help=f"units of the values: {', '.join(UNITS)} (or gal, cm/s/s, m/s^2 ...); required when the "
        "file does not state them, refused when it states others",
    )
    g.add_argument("--component", default=None, help="component of a multi-component file (e.g. N-S, 164)")
    if not processing:
        return
    g.add_argument(
        "--processing",
        default=None,
        metavar="YAML",
        help="processing steps (default: isorock's processing.yaml, the workflow's default)",
    )
    g.add_argument("--raw", action="store_true", default=None, help="analyse the record as read, unprocessed")


def add_length_options(p: argparse.ArgumentParser) -> None:
    """``--max-samples`` and ``--max-duration``: how long a record may be (``records add``, ``records
    check``; the workflow's ``records.max_samples`` and ``records.max_duration_s``)."""
    from isorock.records.directory import MAX_DURATION_S, MAX_SAMPLES

    g = p.add_argument_group("record length")
    g.add_argument(
        "--max-samples",
        type=int,
        default=MAX_SAMPLES,
        metavar="N",
        help=f"refuse a record of more samples (default {MAX_SAMPLES:,}; the record jobs' memory grows "
        "with them)",
    )
    g.add_argument(
        "--max-duration",
        type=float,
        default=MAX_DURATION_S,
        metavar="S",
        help=f"refuse a record that lasts longer [s] (default {MAX_DURATION_S:g})",
    )


def add_catalog_id_options(
    g: argparse._ActionsContainer, *, exclusive: argparse._MutuallyExclusiveGroup | None = None
) -> None:
    """A Table 1 record by its catalog id, ``--id ID [--records DIR]`` (instead of a file): the one
    definition of both options.

    Parameters
    ----------
    g : argparse group or parser
        Where the options go.
    exclusive : argparse mutually exclusive group, optional
        Where ``--id`` goes instead (beside ``--pulse`` and ``--record``, :func:`add_excitation_options`);
        ``--records`` stays in ``g``.
    """
    (exclusive if exclusive is not None else g).add_argument(
        "--id",
        dest="table1_id",
        default=None,
        metavar="ID",
        help="a record by its id: a Table 1 row (e.g. NOR94-RRS, its component as the paper used it, "
        "rotated to SN/SP when two components are there) or a record added with 'isorock records add', "
        "from --records, read and processed as the workflow does",
    )
    g.add_argument(
        "--records",
        default=None,
        metavar="DIR",
        help="records directory of --id (default $ISOROCK_RECORDS)",
    )


def add_block_options(p: argparse.ArgumentParser) -> None:
    """The object, by exactly one of three descriptions (checked by :func:`block_from_args`): a uniform
    block by ``--lambda`` (``dest="lam"``) and ``--R``, or by ``--height`` and ``--width`` (full
    dimensions, m); a rigid body of measured geometry by ``--b-left --b-right --h-cg --r-gyration``."""
    g = p.add_argument_group(
        "object (a uniform block: --lambda and --R, or --height and --width; a rigid body of measured "
        "geometry: --b-left, --b-right, --h-cg and --r-gyration)"
    )
    g.add_argument("--lambda", dest="lam", type=float, default=None, help="slenderness h/b [-]")
    g.add_argument("--R", dest="R", type=float, default=None, help="half-diagonal of the block [m]")
    g.add_argument(
        "--height",
        type=float,
        default=None,
        metavar="M",
        help="full height of the block [m] (with --width, instead of --lambda/--R)",
    )
    g.add_argument(
        "--width",
        type=float,
        default=None,
        metavar="M",
        help="full width of the block in the direction it rocks [m] (with --height)",
    )
    for flag, dest, text in (
        (
            "--b-left",
            "b_left",
            "horizontal distance from the centre of mass to the left edge of the footprint",
        ),
        ("--b-right", "b_right", "horizontal distance from the centre of mass to the right edge"),
        ("--h-cg", "h_cg", "height of the centre of mass above the base"),
        ("--r-gyration", "r_gyration", "radius of gyration about the centre of mass, sqrt(I_c / m)"),
    ):
        g.add_argument(flag, dest=dest, type=float, default=None, metavar="M", help=f"{text} [m]")
    g.add_argument(
        "--restitution",
        type=float,
        default=None,
        metavar="EPS",
        help="a measured coefficient of restitution of the rigid body [-] (default: from its geometry)",
    )


def add_isolation_options(p: argparse.ArgumentParser, *, kinds: tuple[str, ...] = ISOLATION_KINDS) -> None:
    """The isolation: ``--isolation`` and the parameters of the linear and FP models."""
    g = p.add_argument_group("isolation")
    g.add_argument(
        "--isolation", choices=kinds, default=kinds[0], help=f"isolation model (default {kinds[0]})"
    )
    g.add_argument(
        "--Tb",
        type=float,
        default=None,
        help=f"isolation period [s], {PERIOD_MIN_S:g} to {PERIOD_MAX_S:g} (linear; fp if --Rb absent)",
    )
    if "linear" in kinds:
        g.add_argument(
            "--xi", type=float, default=None, help="isolation damping ratio [-], 0 <= xi < 1 (linear)"
        )
    g.add_argument(
        "--rho",
        type=float,
        default=None,
        help="block-to-base mass ratio m/m_b [-], 0 < rho <= 10; required with --isolation linear or fp (no "
        "default here; a workflow configuration states it, isolation.rho)",
    )
    if "fp" in kinds:
        g.add_argument("--mu", type=float, default=None, help="FP friction coefficient [-], 0 < mu <= 0.3")
        g.add_argument("--Rb", type=float, default=None, help="FP radius of curvature [m]")


class DeprecatedAlias(argparse.Action):
    """Stores the value; says on stderr when a deprecated spelling (CHANGELOG.md) was used."""

    def __call__(self, parser, namespace, values, option_string=None):
        # the spelling typed: a deprecated one, or an abbreviation of one (argparse passes "--amp-m" as
        # typed), is any that does not begin the current name
        if option_string and not self.option_strings[0].startswith(option_string):
            print(
                f"isorock: warning: {option_string} is deprecated and will be removed in 0.3.0; "
                f"use {self.option_strings[0]}",
                file=sys.stderr,
            )
        setattr(namespace, self.dest, values)

    deprecated = ("--amp", "--jobs", "--amp-max")


class RefusedOption(argparse.Action):
    """A hidden option that is refused with a hint (a usage error).

    An exact option string wins over argparse's abbreviations: ``--pga`` refused where the command has
    ``--pga-max`` keeps ``--pga 0.5`` from being read, silently, as ``--pga-max 0.5``.
    """

    def __init__(self, option_strings, dest, hint: str = "", **kwargs):
        kwargs.update(nargs="?", default=argparse.SUPPRESS, help=argparse.SUPPRESS)
        super().__init__(option_strings, argparse.SUPPRESS, **kwargs)
        self.hint = hint

    def __call__(self, parser, namespace, values, option_string=None):
        parser.error(f"{option_string} does not apply to {parser.prog}: {self.hint}")


def add_pga_option(g: argparse._ActionsContainer, *, required: bool, what: str) -> None:
    """``--pga G`` (alias ``--amp``, deprecated): the peak ground acceleration of the excitation [g]."""
    g.add_argument(
        "--pga",
        "--amp",
        dest="pga",
        type=float,
        default=None,
        required=required,
        action=DeprecatedAlias,
        metavar="G",
        help=f"{what}; --amp is its deprecated alias",
    )


def add_pga_max_option(g: argparse._ActionsContainer, *, default: float, what: str) -> None:
    """``--pga-max G`` (alias ``--amp-max``, deprecated): the largest PGA a search scans [g]; ``--pga``
    and ``--amp`` are refused (:class:`RefusedOption`) instead of being read as its abbreviations."""
    g.add_argument(
        "--pga-max",
        "--amp-max",
        dest="pga_max",
        type=float,
        default=default,
        action=DeprecatedAlias,
        metavar="G",
        help=f"{what} [g], 0 < G <= {AMP_MAX_G:g} (default {default:g}); --amp-max is its deprecated alias",
    )
    g.add_argument(
        "--pga",
        "--amp",
        action=RefusedOption,
        hint="it searches for the overturning PGA; --pga-max G is the largest PGA it scans",
    )


def add_excitation_options(p: argparse.ArgumentParser) -> argparse._ArgumentGroup:
    """``--pulse SHAPE``, ``--record FILE`` or ``--id ID`` (exactly one), ``--records``, ``--td`` and the
    record options; returns the group, for the caller's amplitude options."""
    add_record_options(p, positional=False)
    g = p.add_argument_group("excitation (a pulse or a record)")
    src = g.add_mutually_exclusive_group(required=True)
    src.add_argument("--pulse", choices=PULSE_SHAPES, help="pulse shape (paper Eqs. 36-38)")
    src.add_argument("--record", metavar="FILE", help="accelerogram file (processed unless --raw)")
    add_catalog_id_options(g, exclusive=src)
    g.add_argument(
        "--td",
        type=float,
        default=None,
        metavar="S",
        help=f"pulse half-cycle duration [s], {PERIOD_MIN_S:g} to {PERIOD_MAX_S:g} (required with --pulse)",
    )
    return g


def add_json_option(p: argparse.ArgumentParser) -> None:
    """``--json``: print one JSON object."""
    p.add_argument("--json", action="store_true", help="print one JSON object")


# ------------------------------------------------------------------------------------------ checks
def check_unused(a: argparse.Namespace) -> None:
    """Refuse the options that the chosen excitation would ignore (record options with a pulse,
    ``--td`` with a record, ``--scale`` beside ``--pga``)."""
    if getattr(a, "pulse", None):
        given = [_FLAGS[k] for k in RECORD_ONLY if getattr(a, k, None) not in (None, False)]
        if given:
            raise IsorockError(f"{', '.join(given)} apply to --record, not to --pulse")
        if a.td is None:
            raise IsorockError("--pulse needs --td (half-cycle duration, s)")
    elif getattr(a, "record", None) or getattr(a, "table1_id", None):
        if getattr(a, "td", None) is not None:
            raise IsorockError("--td applies to --pulse, not to --record or --id")
    if getattr(a, "records", None) and not getattr(a, "table1_id", None):
        raise IsorockError("--records applies to --id")
    if getattr(a, "scale", None) is not None and getattr(a, "pga", None) is not None:
        raise IsorockError("give --pga (target PGA, g) or --scale (factor), not both")


# ------------------------------------------------------------------------------------------ builders
_ISOLATION_FLAGS = {"Tb_s": "--Tb", "xi_b": "--xi", "rho": "--rho", "mu_b": "--mu", "R_b_m": "--Rb"}
_USED = {"none": (), "linear": ("Tb_s", "xi_b", "rho"), "fp": ("Tb_s", "rho", "mu_b", "R_b_m")}


def choice_from_args(a: argparse.Namespace, pairs: bool = False) -> tuple[Any, Any]:
    """The record ``--id`` found in ``--records`` (:func:`isorock.records.lookup.catalog_record`: a
    Table 1 row, a record added with ``isorock records add``, read as its manifest row says, or a
    pyslammer sample) and its component (:func:`isorock.records.components.choose_component`), as
    ``(RecordSpec, ComponentChoice)``; the file options are refused with it. ``pairs``: also find the
    two horizontals of its recording (:attr:`~isorock.records.components.ComponentChoice.pair`)."""
    from isorock.records.components import choose_component
    from isorock.records.lookup import catalog_record

    given = [f for k, f in (("fmt", "--format"), ("dt", "--dt"), ("units", "--units"), ("component",
             "--component")) if getattr(a, k, None) is not None]  # fmt: skip
    if given:
        raise IsorockError(f"{', '.join(given)} describe a record file, not --id (its manifest does)")
    from isorock.processing import with_lowest_usable_frequency

    spec = catalog_record(a.table1_id, a.records)
    # as the workflow processes it: a PEER record's high-pass corner at its lowest usable frequency
    processing = with_lowest_usable_frequency(getattr(a, "processing", None), spec.metadata.luf_hz)
    choice = choose_component(
        spec.files,
        spec.target,
        processing=processing,
        raw=bool(getattr(a, "raw", False)),
        table1_pga_g=spec.table1_pga_g,
        table1_pgv_m_s=spec.table1_pgv_m_s,
        pairs=pairs,
    )
    return spec, choice


def record_arg(a: argparse.Namespace, file_attr: str = "file") -> str | None:
    """The record file of ``a``, checked against ``--id``: exactly one of the two; ``-`` (standard
    input) needs ``--format``."""
    from isorock.cli.stdin import check_stdin_format

    path = getattr(a, file_attr, None)
    rid = getattr(a, "table1_id", None)
    flag = "FILE" if file_attr == "file" else "--record FILE"
    if path and rid:
        raise IsorockError(f"give {flag} or --id, not both")
    if not path and not rid:
        raise IsorockError(f"give {flag} or --id ID (a Table 1 row or an added record)")
    if getattr(a, "records", None) and not rid:
        raise IsorockError("--records applies to --id")
    check_stdin_format(path, getattr(a, "fmt", None), flag)
    return path


def load_from_args(path: str, a: argparse.Namespace):
    """The record file ``path`` read and processed with the options of ``a``
    (:func:`isorock.records.motion.load_record`).

    ``path`` ``-`` reads the record from standard input (``--format`` required,
    :func:`isorock.cli.stdin.stdin_record`); its provenance and its errors name the file ``<stdin>``.
    """
    from dataclasses import replace

    from isorock.cli.stdin import STDIN_NAME, check_stdin_format, is_stdin, stdin_record
    from isorock.records.motion import load_record

    kwargs: dict[str, Any] = {
        "format": a.fmt,
        "dt": a.dt,
        "units": a.units,
        "component": a.component,
        "processing": a.processing,
        "raw": bool(a.raw),
    }
    if not is_stdin(path):
        return load_record(path, **kwargs)
    check_stdin_format(path, a.fmt, "FILE" if getattr(a, "file", None) == path else "--record FILE")
    with stdin_record() as tmp:
        rec = load_record(tmp, **kwargs)
    for tr in (rec.raw, rec.trace):
        if "isorock" in tr.stats:
            tr.stats.isorock.source = STDIN_NAME
    rec.source = replace(rec.source, file=STDIN_NAME)
    return rec


def processing_text(source, steps=None) -> str:
    """How a record was processed, in words, for the text outputs: ``processed (9 steps: check_pga,
    detrend x2, ...)``, the count and the names of the same steps.

    Parameters
    ----------
    source : isorock.records.motion.RecordSource
        Provenance of the record.
    steps : list of isorock.processing.AppliedStep, optional
        The steps applied (:func:`isorock.processing.applied_steps` of the processed trace); default
        ``source.steps``, the structured steps of the provenance.
    """
    if source.raw:
        return "not processed (--raw)"
    if steps is None:
        steps = source.steps or []
    return f"processed ({len(steps)} steps: {', '.join(_step_names(steps))})"


def _step_names(steps) -> list[str]:
    """The step names in the order applied, a step repeated in a row once with its count (``detrend x2``)."""
    out: list[list] = []
    for s in steps:
        if out and out[-1][0] == s.step:
            out[-1][1] += 1
        else:
            out.append([s.step, 1])
    return [name if n == 1 else f"{name} x{n}" for name, n in out]


def isolation_from_args(a: argparse.Namespace):
    """The isolation named by ``--isolation`` and its parameters
    (:func:`isorock.physics.model.make_isolation`);
    parameters that the chosen model does not take are refused, and so are values that are not finite
    or outside the bounds of real isolators (:func:`isorock.plausibility.check_isolator`: ``--mu`` in
    (0, 0.3], ``--Tb`` 0.05 to 20 s, ``--xi`` in [0, 1), ``--rho`` in (0, 10])."""
    from isorock.physics.model import make_isolation

    values = {
        "Tb_s": getattr(a, "Tb", None),
        "xi_b": getattr(a, "xi", None),
        "rho": getattr(a, "rho", None),
        "mu_b": getattr(a, "mu", None),
        "R_b_m": getattr(a, "Rb", None),
    }
    extra = [_ISOLATION_FLAGS[k] for k, v in values.items() if v is not None and k not in _USED[a.isolation]]
    if extra:
        hint = " (add --isolation linear or fp)" if a.isolation == "none" else ""
        raise IsorockError(f"{', '.join(extra)} given but --isolation is {a.isolation}: not used{hint}")
    check_finite(values, names=_ISOLATION_FLAGS)
    bounded = {k: values[k] for k in ("Tb_s", "xi_b", "rho", "R_b_m")}
    # the bounds first: their messages name the options (--xi), the model's its parameters (xi_b)
    check_isolator(a.isolation, values["mu_b"], **bounded, names=_ISOLATION_FLAGS)
    return make_isolation(a.isolation, **values, names=_ISOLATION_FLAGS)  # the model's own ranges


_BLOCK_PAIRS = ((("lam", "--lambda"), ("R", "--R")), (("height", "--height"), ("width", "--width")))
_BODY_FLAGS = (
    ("b_left", "--b-left"),
    ("b_right", "--b-right"),
    ("h_cg", "--h-cg"),
    ("r_gyration", "--r-gyration"),
)


def _body_from_args(a: argparse.Namespace) -> tuple[Any, dict[str, float]]:
    """The rigid body of ``--b-left --b-right --h-cg --r-gyration`` [``--restitution``] and its values."""
    from isorock.errors import ParameterError
    from isorock.physics.body import RigidBody

    missing = [f for d, f in _BODY_FLAGS if getattr(a, d, None) is None]
    if missing:
        raise IsorockError(
            f"a rigid body needs --b-left, --b-right, --h-cg and --r-gyration: give {', '.join(missing)}"
        )
    check_finite({f: getattr(a, d) for d, f in _BODY_FLAGS})
    for d, f in _BODY_FLAGS:
        if not getattr(a, d) > 0:
            raise IsorockError(f"{f} {getattr(a, d):g} must be > 0 m")
    eps = getattr(a, "restitution", None)
    try:
        body = RigidBody(a.b_left, a.b_right, a.h_cg, a.r_gyration, restitution=eps)
    except ParameterError as exc:
        raise IsorockError(str(exc).replace("restitution=", "--restitution ")) from None
    dims = body.as_dict()
    dims.update(tan_alpha_left=body.left.tan_alpha, tan_alpha_right=body.right.tan_alpha)
    return body, dims


def block_from_args(a: argparse.Namespace) -> tuple[Any, dict[str, float]]:
    """The block of ``--lambda``/``--R`` or ``--height``/``--width`` (exactly one pair, values > 0), and
    both descriptions of it, ``{"lambda", "R_m", "height_m", "width_m"}`` (those given as given, the
    others computed: ``lambda = height/width``, ``R = hypot(height, width)/2``).

    The block is built from lambda and R in both cases (as :class:`isorock.assessment.stripes.AssessedObject`
    does), so that the two pairs naming the same block give the same results.
    """
    from isorock.physics.model import Block

    given = [[(d, f) for d, f in pair if getattr(a, d, None) is not None] for pair in _BLOCK_PAIRS]
    body = [f for d, f in _BODY_FLAGS if getattr(a, d, None) is not None]
    if body and (given[0] or given[1]):
        flags = ", ".join([f for pair in given for _, f in pair] + body)
        raise IsorockError(
            f"{flags}: give a uniform block (--lambda/--R or --height/--width) or a rigid body, not both"
        )
    if body:
        return _body_from_args(a)
    if getattr(a, "restitution", None) is not None:
        raise IsorockError("--restitution is for a rigid body (--b-left --b-right --h-cg --r-gyration)")
    if given[0] and given[1]:
        flags = ", ".join(f for pair in given for _, f in pair)
        raise IsorockError(f"{flags}: give --lambda and --R, or --height and --width, not both pairs")
    if not given[0] and not given[1]:
        raise IsorockError(
            "give the block: --lambda and --R, or --height and --width (m), or a rigid body: --b-left, "
            "--b-right, --h-cg and --r-gyration (m)"
        )
    pair = _BLOCK_PAIRS[0] if given[0] else _BLOCK_PAIRS[1]
    have = given[0] or given[1]
    if len(have) == 1:
        missing = next(f for d, f in pair if d != have[0][0])
        raise IsorockError(f"{have[0][1]} needs {missing} (the block is named by both)")
    for d, f in pair:
        v = getattr(a, d)
        if not v > 0:
            raise IsorockError(f"{f} {v:g} must be > 0" + ("" if d == "lam" else " m"))
    check_finite({f: getattr(a, d) for d, f in pair})  # inf
    if given[0]:
        block = Block.from_lambda_R(a.lam, a.R)
        dims = {"lambda": a.lam, "R_m": a.R, "height_m": 2.0 * block.h, "width_m": 2.0 * block.b}
    else:
        check_object(a.height, a.width, names={"height_m": "--height", "width_m": "--width"})
        lam, R = a.height / a.width, 0.5 * math.hypot(a.height, a.width)
        block = Block.from_lambda_R(lam, R)
        dims = {"lambda": lam, "R_m": R, "height_m": a.height, "width_m": a.width}
    return block, dims


def all_or_errors(*steps: Callable[[], Any]) -> list[Any]:
    """The result of every step, or one error naming what each step that failed lacks (``"give the
    block ...; isolation linear needs --Tb ..., --rho ...; --pulse needs --td ..."``): a user learns what
    is missing in one try, not one option at a time."""
    from isorock.errors import IsorockError

    out: list[Any] = []
    errors: list[IsorockError] = []
    for step in steps:
        try:
            out.append(step())
        except IsorockError as exc:
            errors.append(exc)
            out.append(None)
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise IsorockError("; ".join(str(e) for e in errors))
    return out


def block_text(dims: dict[str, float]) -> str:
    """The block in both descriptions (:func:`block_from_args`), or the rigid body, for the text outputs."""
    if "h_cg_m" in dims:
        eps = f", restitution {dims['restitution']:g} (given)" if "restitution" in dims else ""
        return (
            f"rigid body: centre of mass {dims['h_cg_m']:.6g} m high, {dims['b_left_m']:.6g} m from the left "
            f"edge, {dims['b_right_m']:.6g} m from the right edge, radius of gyration "
            f"{dims['r_gyration_m']:.6g} m{eps}; uplift at {dims['tan_alpha_left']:.4g} g onto the left "
            f"edge, {dims['tan_alpha_right']:.4g} g onto the right edge (fixed base)"
        )
    return (
        f"block: lambda={dims['lambda']:.6g}, R={dims['R_m']:.6g} m (height {dims['height_m']:.6g} m, "
        f"width {dims['width_m']:.6g} m)"
    )


def system_from_args(a: argparse.Namespace):
    """The :class:`~isorock.physics.model.System` named by the block (:func:`block_from_args`) and isolation
    options."""
    from isorock.physics.model import System

    return System(block_from_args(a)[0], isolation_from_args(a))


@dataclass(frozen=True)
class LoadedExcitation:
    """The excitation named by ``--pulse``/``--record``/``--id`` (:func:`excitation_from_args`).

    Attributes
    ----------
    excitation : Pulse or GroundMotion
        The excitation (:mod:`isorock.physics.excitation`).
    scale : float
        Factor to apply to it [-] (1 for a pulse).
    source : RecordSource or None
        The record's provenance (:mod:`isorock.records.motion`); None for a pulse.
    choice : ComponentChoice or None
        For ``--id``, the component chosen (:func:`isorock.records.components.choose_component`);
        None otherwise.
    record : LoadedRecord or None
        The record read (its raw trace is what a vertical is checked against); None for a pulse.
    files : tuple of RecordFile
        The files of the record's recording (``--id``: its catalog row's; ``--record``: the file), where
        ``--vertical auto`` looks.
    """

    excitation: Any
    scale: float = 1.0
    source: Any = None
    choice: Any = None
    record: Any = None
    files: tuple = ()


def excitation_from_args(a: argparse.Namespace, *, amplitude: bool) -> LoadedExcitation:
    """The excitation of ``--pulse``/``--record``/``--id``, the factor to apply to it, the record's
    provenance (None for a pulse) and, for ``--id``, the component chosen.

    With ``amplitude``, a pulse takes its amplitude from ``--pga`` (required) and a record is scaled to
    ``--pga`` or by ``--scale`` (default: as processed); without, the pulse has unit amplitude and the
    factor is 1 (the caller scales). Numbers that are not finite are refused, and so is a pulse
    duration ``--td`` outside 0.05 to 20 s (:func:`isorock.plausibility.check_duration`).
    """
    from isorock.physics.excitation import Pulse

    check_unused(a)
    flags = {"td": "--td", "pga": "--pga", "scale": "--scale"}
    check_finite({k: getattr(a, k, None) for k in flags}, names=flags)
    for k in ("pga", "scale"):
        v = getattr(a, k, None)
        if v is not None and not v > 0:
            raise IsorockError(f"{flags[k]} {v:g} must be > 0" + (" g" if k == "pga" else ""))
    if a.pulse:
        check_duration(a.td, names=flags)  # before the model's own range (td > 0): names --td
        pulse = Pulse(a.pulse, a.td, 1.0)
        if not amplitude:
            return LoadedExcitation(pulse)
        if a.pga is None:
            raise IsorockError("--pulse needs --pga (amplitude, g)")
        return LoadedExcitation(Pulse(a.pulse, a.td, a.pga))
    choice = None
    files: tuple = ()
    if getattr(a, "table1_id", None):
        spec, choice = choice_from_args(a)
        rec = choice.record
        files = tuple(spec.files)
    else:
        rec = load_from_args(a.record, a)
    gm = rec.motion
    scale = 1.0
    if amplitude and getattr(a, "pga", None) is not None:
        if not a.pga > 0:
            raise IsorockError(f"--pga {a.pga} must be > 0 g")
        scale = a.pga / gm.pga_g
    elif amplitude and getattr(a, "scale", None) is not None:
        if not a.scale > 0:
            raise IsorockError(f"--scale {a.scale} must be > 0")
        scale = a.scale
    return LoadedExcitation(gm, scale, rec.source, choice, rec, files)
