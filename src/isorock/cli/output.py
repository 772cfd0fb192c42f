"""Output of the commands: one JSON object on stdout (``--json``), a result or an error."""

from __future__ import annotations

import json
import math
import sys

__all__ = ["print_json", "print_json_error", "json_safe"]


def json_safe(obj: object) -> object:
    """An object made JSON-safe: NaN and infinities become null, tuples lists."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    return obj


def print_json(obj: dict) -> None:
    """Print one JSON object on stdout."""
    print(json.dumps(json_safe(obj), indent=None))


def print_json_error(message: str, exit_code: int) -> None:
    """Print a user error as one JSON object on stdout, ``{"error": message, "exit_code": exit_code}``
    (``--json``; the command prints the same message on stderr).

    Parameters
    ----------
    message : str
        The one-line message, without the ``isorock: error:`` prefix of stderr.
    exit_code : int
        The exit status of the command [-].
    """
    print_json({"error": message, "exit_code": exit_code})
    sys.stdout.flush()
