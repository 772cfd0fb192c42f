"""The ``isorock`` command line.

Each group of commands lives in its own module with a ``register(subparsers)`` function:
:mod:`~.engine` (``simulate``, ``min-overturn``, ``demo``), :mod:`~.maps` (``map``),
:mod:`~.records` (``records``), :mod:`~.signal` (``info``, ``pulse``), :mod:`~.report`
(``report``) and :mod:`~.assessment` (``assess``); the options they share are defined once in
:mod:`~.options`. This module builds the parser, dispatches, and turns user errors into one line on
stderr with exit code 2 (no traceback): an :class:`~isorock.errors.IsorockError` (among them
:class:`~isorock.errors.ParameterError`, an invalid physical parameter), a usage error (argparse),
or a file that cannot be opened or written (any ``OSError``: a full disk, a read-only folder). A
command stopped by SIGINT (Ctrl-C), SIGTERM (``kill``, ``timeout``) or SIGHUP is one line too, with
that signal's exit code (:class:`~isorock.errors.Stopped`). Any other exception, a bare
``ValueError`` included, is a bug: it keeps its traceback. With ``--json`` a user error is also
one JSON object on stdout, ``{"error": "<the message>", "exit_code": 2}``
(:func:`~.output.print_json_error`), so that a program reading the JSON output always gets an
object; the line on stderr is the same.

The command modules import the numerical library inside their command functions, so that
``isorock --help`` and a mistyped option answer at once instead of after loading numba, ObsPy and
matplotlib.
"""

from __future__ import annotations

import argparse
import os
import signal as _signal
import sys
import threading
from collections.abc import Sequence
from contextvars import ContextVar
from typing import NoReturn

from isorock.cli import assessment, engine, maps, records, report, signal
from isorock.cli.output import print_json, print_json_error
from isorock.errors import IsorockError, Stopped
from isorock.timings import about
from isorock.version import __version__

__all__ = ["main", "build_parser", "print_json", "EXIT_USAGE"]

EXIT_USAGE = 2
_COMMANDS = (engine, records, signal, maps, report, assessment)

#: whether a usage error is also printed as JSON (``--json`` in the arguments of :func:`main`)
_JSON_ERRORS: ContextVar[bool] = ContextVar("isorock_json_errors", default=False)


#: the arguments :func:`main` parses, for the usage error of a mistyped option
_ARGV: ContextVar[tuple[str, ...]] = ContextVar("isorock_argv", default=())


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # argparse exits 2 with a usage line: keep that
        message, parser = _suggest(self, message)
        if _JSON_ERRORS.get():
            print_json_error(message, EXIT_USAGE)
        parser.print_usage(sys.stderr)
        parser.exit(EXIT_USAGE, f"isorock: error: {message}\n")


def _suggest(parser: argparse.ArgumentParser, message: str) -> tuple[str, argparse.ArgumentParser]:
    """An unrecognized option with the command's option it most resembles (``--lamda``: did you mean
    ``--lambda``?), and the parser of the command given, whose usage is then printed (argparse reports
    unknown options from the top-level parser)."""
    import difflib

    if not message.startswith("unrecognized arguments: "):
        return message, parser
    sub = parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            name = next((a for a in _ARGV.get() if a in action.choices), None)
            if name is not None:
                sub = action.choices[name]
    options = [o for a in sub._actions for o in a.option_strings if o.startswith("--")]
    hints = []
    for token in message.split(": ", 1)[1].split():
        if token.startswith("--"):
            close = difflib.get_close_matches(token.split("=")[0], options, n=1, cutoff=0.6)
            if close:
                hints.append(f"{token}: did you mean {close[0]}?")
    return (message + (f" ({'; '.join(hints)})" if hints else "")), sub


def _wants_json(argv: Sequence[str]) -> bool:
    """Whether ``--json`` (or an abbreviation argparse accepts, ``--js``...) is among the options of
    ``argv`` (before a ``--``), before they are parsed."""
    for arg in argv:
        if arg == "--":
            return False
        if arg.startswith("--js") and "--json".startswith(arg):
            return True
    return False


def build_parser() -> argparse.ArgumentParser:
    """The ``isorock`` argument parser with every command."""
    parser = _Parser(prog="isorock", description="Rocking of free-standing blocks on isolated bases.")
    parser.add_argument("--version", action="version", version=f"isorock {__version__}")
    parser.add_argument(
        "--warm-up",
        action="store_true",
        help="compile the whole rocking engine now and exit, "
        f"{about('warm_up')} (once per installation: otherwise the first analysis of each isolation "
        f"model compiles what it needs, {about('first_analysis')})",
    )
    sub = parser.add_subparsers(
        dest="command",
        metavar="COMMAND",
        parser_class=_Parser,
        help="'isorock COMMAND --help' shows its options",
    )
    for module in _COMMANDS:
        module.register(sub)
    return parser


def _warm_up() -> int:
    """``isorock --warm-up``: compile (or load) the engine's entry points and say how long it took."""
    from isorock.physics.engine import warm_up

    t = warm_up()
    where = t["cache"] or "numba's cache"
    print(
        f"isorock: engine ready: simulate {t['simulate_s']:.1f} s, batch kernel {t['run_many_s']:.1f} s "
        f"(compiled code in {where})",
        file=sys.stderr,
    )
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``isorock`` command; returns the exit code (2 for a user error).

    A user error (:class:`~isorock.errors.IsorockError`, a usage error, or a file that cannot be
    opened) is one line on stderr and exit code 2, and with ``--json`` also the JSON object
    ``{"error": "<the same message>", "exit_code": 2}`` on stdout; any other exception propagates with
    its traceback.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    token = _JSON_ERRORS.set(_wants_json(argv))
    given = _ARGV.set(tuple(argv))
    try:
        args = parser.parse_args(argv)
    finally:
        _JSON_ERRORS.reset(token)
        _ARGV.reset(given)
    if args.warm_up:
        return _warm_up()
    handlers = _stop_on_signals()
    if not getattr(args, "func", None):
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:  # output piped into a program that stopped reading (e.g. head)
        _silence_stdout()
        return 0
    except (IsorockError, OSError) as exc:  # OSError: a file that cannot be read or written, a full disk
        msg = str(exc) or exc.__class__.__name__
        if isinstance(exc, OSError) and not isinstance(exc, IsorockError):
            msg = f"{exc.filename}: {exc.strerror}" if exc.filename else (exc.strerror or msg)
        line = msg.splitlines()[0] if msg else msg
        if getattr(args, "json", False):
            try:
                print_json_error(line, EXIT_USAGE)
            except BrokenPipeError:  # stdout piped into a program that stopped reading
                _silence_stdout()
        print(f"isorock: error: {line}", file=sys.stderr)
        return EXIT_USAGE
    except Stopped as exc:
        print(f"isorock: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("isorock: interrupted", file=sys.stderr)
        return 130
    finally:
        _restore(handlers)


def _raise_stopped(signum: int, frame: object) -> None:
    raise Stopped(signum)


def _stop_on_signals() -> dict:
    """SIGTERM and SIGHUP stop a command as Ctrl-C does (:class:`~isorock.errors.Stopped`): what it was
    writing under a temporary name is removed, and it ends with one line instead of at once. Returns
    the handlers to restore (none outside the main thread, where Python cannot set them)."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    return {s: _signal.signal(s, _raise_stopped) for s in (_signal.SIGTERM, _signal.SIGHUP)}


def _restore(handlers: dict) -> None:
    for s, h in handlers.items():
        _signal.signal(s, h)


def _silence_stdout() -> None:
    """Send what is left of stdout to the null device (its reader is gone: no error at exit)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
