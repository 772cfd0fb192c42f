"""The errors isorock reports to its users.

The command line turns every :class:`IsorockError` into one line on stderr and exit code 2, without a
traceback; any other exception is a bug and keeps its traceback. The errors of invalid input that
are also ``ValueError`` (:class:`ParameterError`, :class:`RecordError`) stay so, for the callers
that catch ``ValueError``.

A command stopped by a signal (``kill PID``, ``timeout``, Ctrl-C, a closed terminal) raises
:class:`Stopped`, a ``KeyboardInterrupt``: one line, and the exit code of that signal (128 + its
number).

Hierarchy::

    IsorockError
    ├── ParameterError (ValueError) an invalid physical parameter (block, isolation, excitation)
    ├── ConfigError                 a workflow configuration that fails its schema or cross-checks
    ├── CatalogError                a record catalog or manifest that is malformed
    └── RecordError (ValueError)    a record file that cannot be read or fails a check
        ├── EmptyRecordError, BinaryFileError, HeaderError, NonNumericError, NonFiniteError,
        ├── NptsMismatchError ── TruncatedRecordError
        ├── TimeStepError ── MissingTimeStepError
        ├── UnitsError ── MissingUnitsError
        └── ColumnCountError, UnknownFormatError
"""

from __future__ import annotations

__all__ = [
    "Stopped",
    "IsorockError",
    "ParameterError",
    "ConfigError",
    "CatalogError",
    "RecordError",
    "EmptyRecordError",
    "BinaryFileError",
    "HeaderError",
    "NonNumericError",
    "NonFiniteError",
    "NptsMismatchError",
    "TruncatedRecordError",
    "TimeStepError",
    "UnitsError",
    "MissingTimeStepError",
    "MissingUnitsError",
    "ColumnCountError",
    "UnknownFormatError",
]


class IsorockError(Exception):
    """Base class of the errors isorock reports to its users."""


class Stopped(KeyboardInterrupt):
    """A command stopped by a signal: SIGINT (Ctrl-C), SIGTERM (``kill PID``, ``timeout``) or SIGHUP
    (a closed terminal). A ``KeyboardInterrupt``, so that whatever cleans up after Ctrl-C (a file
    written under a temporary name is removed) cleans up after these too.

    Parameters
    ----------
    signum : int
        The signal.
    detail : str
        What was done about it (that Snakemake ended its jobs), for the message.
    """

    def __init__(self, signum: int, detail: str = "") -> None:
        import signal

        self.signum = int(signum)
        self.name = signal.Signals(self.signum).name
        self.detail = detail
        super().__init__(f"stopped by {self.name}" + (f": {detail}" if detail else ""))

    @property
    def exit_code(self) -> int:
        """128 + the signal's number, as a shell reports a process ended by it."""
        return 128 + self.signum


class ParameterError(IsorockError, ValueError):
    """An invalid physical parameter: out of its range, missing, or of an unknown kind.

    Raised by the model (:mod:`isorock.physics.model`), the excitations (:mod:`isorock.physics.excitation`)
    and the
    searches that check their arguments; the message names the parameter and its valid range
    (``"td=-1 is out of range: valid td > 0 s"``). A ``ValueError`` too, so that code catching
    ``ValueError`` keeps working.
    """


class ConfigError(IsorockError):
    """A workflow configuration that fails its schema or a cross-check (the message names the key)."""


class _Located(IsorockError):
    """An error about a file, with the 1-based line where the problem is when it is tied to one.

    Parameters
    ----------
    path : str
        The file.
    problem : str
        What is wrong.
    line : int, optional
        1-based line number.
    """

    def __init__(self, path: object, problem: str, line: int | None = None) -> None:
        self.path = str(path)
        self.line = line
        self.problem = problem
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {problem}")


class CatalogError(_Located):
    """A catalog or manifest file that is malformed or fails its schema."""


class RecordError(_Located, ValueError):
    """A record file that cannot be read or fails a check."""


class EmptyRecordError(RecordError):
    """The file is empty or holds no data values."""


class BinaryFileError(RecordError):
    """The file is not text (NUL bytes, control characters)."""


class HeaderError(RecordError):
    """A header line is missing or cannot be understood."""


class NonNumericError(RecordError):
    """A data token is not a number."""


class NonFiniteError(RecordError):
    """A data value is NaN or infinite."""


class NptsMismatchError(RecordError):
    """The number of values disagrees with the declared number of points (NPTS)."""


class TruncatedRecordError(NptsMismatchError):
    """The file ends before the declared number of points."""


class TimeStepError(RecordError):
    """The time step is missing, zero, negative, implausible or inconsistent."""


class UnitsError(RecordError):
    """Units are missing, unknown, not an acceleration, or give an implausible PGA."""


class MissingTimeStepError(TimeStepError):
    """The file does not state its time step and none was given."""


class MissingUnitsError(UnitsError):
    """The file does not state its units and none were given."""


class ColumnCountError(RecordError):
    """A data line holds the wrong number of columns."""


class UnknownFormatError(RecordError):
    """The format is not known or cannot be detected."""
