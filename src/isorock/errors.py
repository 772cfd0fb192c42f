"""Exception classes of isorock.

The command line turns every :class:`IsorockError` (and ``ValueError`` raised by
parameter validation) into one line on stderr and exit code 2.
"""

from __future__ import annotations

__all__ = ["IsorockError", "RecordError"]


class IsorockError(Exception):
    """Base class of the errors isorock reports to its users."""


class RecordError(IsorockError, ValueError):
    """A record file that cannot be read or fails a check.

    Parameters
    ----------
    path : str
        The file.
    problem : str
        What is wrong.
    line : int, optional
        1-based line number where the problem is, if it is tied to a line.
    """

    def __init__(self, path: object, problem: str, line: int | None = None) -> None:
        self.path = str(path)
        self.line = line
        self.problem = problem
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {problem}")
