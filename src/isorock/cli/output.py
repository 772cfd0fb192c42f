"""Output of the commands: one JSON object on stdout (``--json``)."""

from __future__ import annotations

import json
import math

__all__ = ["print_json", "json_safe"]


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
