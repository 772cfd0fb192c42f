"""The processing history of stores of layout 2, kept as ObsPy's history lines only: the lines read back
as :class:`~isorock.processing.history.AppliedStep` (every later store keeps the steps themselves)."""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Iterable
from typing import Any

from isorock.processing.history import AppliedStep
from isorock.processing.steps import STEPS

__all__ = ["parse_history"]


_LINE = re.compile(r"^isorock(?: \S+)?: (?P<step>\w+)\((?P<args>.*?)\)(?:: (?P<note>.*))?$", re.DOTALL)
_NAMES = {"inf": math.inf, "nan": math.nan}


def _value(node: ast.expr) -> Any:
    if isinstance(node, ast.Name) and node.id in _NAMES:
        return _NAMES[node.id]
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        return -_value(node.operand)
    return ast.literal_eval(node)


def parse_history(lines: Iterable[str]) -> list[AppliedStep]:
    """The processing steps of old history lines (``isorock <version>: name(param=value, ...): note``).

    Only for results written before the steps were kept as :class:`AppliedStep` (store layout 2):
    everything else reads the structured steps. Floating-point parameters come back as printed
    (6 significant digits; ``5.0`` as the integer ``5``). Lines that are not steps of
    :data:`isorock.processing.STEPS` (the rotation of two components, ObsPy's own history) are left out.

    Parameters
    ----------
    lines : iterable of str
        History lines, in order.

    Returns
    -------
    list of AppliedStep
    """
    out = []
    for line in lines:
        m = _LINE.match(str(line))
        if m is None or m["step"] not in STEPS:
            continue
        try:
            call = ast.parse(f"f({m['args']})", mode="eval").body
            assert isinstance(call, ast.Call)
            params = {kw.arg: _value(kw.value) for kw in call.keywords if kw.arg}
        except (SyntaxError, ValueError, AssertionError):
            params = {}
        out.append(AppliedStep(m["step"], params, m["note"] or ""))
    return out
