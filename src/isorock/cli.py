"""The ``isorock`` command line.

Each group of subcommands lives in its own module exposing ``register(subparsers)``;
this module only builds the parser, dispatches, and turns user errors into one
line on stderr with exit code 2 (no traceback).
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import sys
from collections.abc import Sequence

from .errors import IsorockError

# modules that add subcommands; a module that is not present is skipped
_COMMAND_MODULES = (
    "isorock.cli_engine",
    "isorock.cli_records",
    "isorock.cli_signal",
    "isorock.cli_assess",
    "isorock.cli_report",
)

EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # argparse exits 2 with a usage line: keep that
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"isorock: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = _Parser(prog="isorock", description="Rocking of free-standing blocks on isolated bases.")
    parser.add_argument("--version", action="version", version=f"isorock {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in _COMMAND_MODULES:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:
                continue
            raise
        mod.register(sub)
    return parser


def _clean(obj: object) -> object:
    """Make an object JSON-safe: NaN/inf become null."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    return obj


def print_json(obj: dict) -> None:
    """Print one JSON object on stdout."""
    print(json.dumps(_clean(obj), indent=None))


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(args.func(args) or 0)
    except (IsorockError, ValueError, FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        msg = str(exc) or exc.__class__.__name__
        if isinstance(exc, (FileNotFoundError, IsADirectoryError, PermissionError)) and exc.filename:
            msg = f"{exc.filename}: {exc.strerror}"
        print(f"isorock: error: {msg.splitlines()[0] if msg else msg}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("isorock: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into a program that stopped reading (e.g. head)
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
