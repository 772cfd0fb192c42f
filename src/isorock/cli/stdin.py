"""A record read from standard input: ``FILE`` (or ``--record FILE``) given as ``-``.

The bytes of standard input are written to a temporary file, read with the same reader as any file
(:func:`isorock.io.read_trace`, through :func:`isorock.records.motion.load_record` for the commands
that process the record), and the temporary file is removed. Standard input has no name to detect
a format from and cannot be read twice, so ``--format`` is required with it; the errors and the
provenance name the file ``<stdin>``::

    isorock info - --format peer-at2 < RSN77_SFERN_PUL164-hor1.AT2
    cat quake.txt | isorock simulate --record - --format one-column --dt 0.01 --units g ...
"""

from __future__ import annotations

import contextlib
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

from isorock.errors import IsorockError, _Located

__all__ = ["STDIN", "STDIN_NAME", "is_stdin", "check_stdin_format", "stdin_record"]

#: the file name that reads the record from standard input
STDIN = "-"
#: how messages and provenance name standard input
STDIN_NAME = "<stdin>"


def is_stdin(path: object) -> bool:
    """Whether the file argument ``path`` means standard input (``-``)."""
    return isinstance(path, str) and path == STDIN


def check_stdin_format(path: object, fmt: str | None, flag: str = "FILE") -> None:
    """Refuse ``-`` (standard input) without ``--format``.

    Parameters
    ----------
    path : object
        The file argument.
    fmt : str or None
        The ``--format`` given.
    flag : str
        How the command names its file argument (``FILE``, ``--record FILE``), for the message.

    Raises
    ------
    IsorockError
        ``path`` is ``-`` and ``fmt`` is None.
    """
    if is_stdin(path) and fmt is None:
        from isorock.io import FORMATS

        raise IsorockError(
            f"{flag} '-' reads the record from standard input: give its --format ({', '.join(FORMATS)})"
        )


@contextlib.contextmanager
def stdin_record() -> Iterator[Path]:
    """The bytes of standard input in a temporary file, removed when the block ends.

    An :class:`~isorock.errors.IsorockError` raised in the block that names the temporary file names
    ``<stdin>`` instead (same class, same line).

    Yields
    ------
    Path
        The temporary file.

    Raises
    ------
    IsorockError
        Standard input is a terminal or closed (nothing piped or redirected into it).
    """
    stream = sys.stdin
    if stream is None or stream.closed or stream.isatty():
        raise IsorockError(
            "'-' reads the record from standard input, but nothing is piped or redirected into it "
            "(e.g. isorock info - --format peer-at2 < FILE)"
        )
    buffer = getattr(stream, "buffer", None)
    data = buffer.read() if buffer is not None else stream.read().encode("utf-8")
    with tempfile.TemporaryDirectory(prefix="isorock-stdin-") as tmpdir:
        tmp = Path(tmpdir) / "stdin"
        tmp.write_bytes(data)
        try:
            yield tmp
        except IsorockError as exc:
            renamed = _renamed(exc, tmp)
            if renamed is exc:
                raise
            raise renamed from None


def _renamed(exc: IsorockError, tmp: Path) -> IsorockError:
    """``exc`` with the temporary file ``tmp`` named ``<stdin>`` (``exc`` itself when it does not
    name it)."""
    names = (str(tmp.resolve()), str(tmp))
    if not any(n in str(exc) for n in names):
        return exc

    def sub(text: str) -> str:
        for n in names:
            text = text.replace(n, STDIN_NAME)
        return text

    if isinstance(exc, _Located):
        return type(exc)(sub(exc.path), sub(exc.problem), exc.line)
    try:
        return type(exc)(sub(str(exc)))
    except TypeError:  # an error class with another signature
        return IsorockError(sub(str(exc)))
