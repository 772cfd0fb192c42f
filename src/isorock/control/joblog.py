"""How a job reports to the run: its log file, its progress lines and the one line that says its
input was at fault, which the run (:mod:`isorock.control.run`) reads back and repeats."""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import time
import traceback
from collections.abc import Iterator
from pathlib import Path

from isorock.errors import IsorockError
from isorock.version import __version__

__all__ = ["JOB_ERROR", "script_logging", "say"]


#: the start of the line a job writes in its log when its input is at fault (an
#: :class:`~isorock.errors.IsorockError`): :func:`isorock.control.run.run_snakemake` repeats it
JOB_ERROR = "isorock: error: "


@contextlib.contextmanager
def script_logging(log: str | os.PathLike | None, what: str = "") -> Iterator[None]:
    """Send the output of a workflow script to its log file; record the traceback of a failure there.

    A job stopped by Ctrl-C (SIGINT: a ``snakemake`` run by hand in a terminal) says so in one line of
    its log and exits with code 130, without a traceback on the terminal. A job whose input is at fault
    (an :class:`~isorock.errors.IsorockError`: a record with one horizontal for a RotD scaling) writes
    one line starting with :data:`JOB_ERROR` and exits with code 1, without a traceback.

    Parameters
    ----------
    log : path-like or None
        Log file (appended to); None: leave stdout and stderr alone.
    what : str
        Name of the job, for the first and last lines.
    """
    if log is None:
        yield
        return
    Path(log).parent.mkdir(parents=True, exist_ok=True)
    with open(log, "a", encoding="utf-8") as fh:
        old_out, old_err = sys.stdout, sys.stderr
        sys.stdout = sys.stderr = fh
        t0 = time.perf_counter()
        print(f"isorock {__version__}: {what} started", flush=True)
        try:
            yield
        except KeyboardInterrupt:  # Ctrl-C of a snakemake run by hand: one line, not a traceback
            print(f"{what} stopped by SIGINT after {time.perf_counter() - t0:.2f} s", flush=True)
            sys.stdout, sys.stderr = old_out, old_err
            raise SystemExit(128 + signal.SIGINT) from None
        except IsorockError as exc:  # the input's fault (a record, a value): one line, read by the run
            print(f"{JOB_ERROR}{str(exc).splitlines()[0]}", flush=True)
            sys.stdout, sys.stderr = old_out, old_err
            raise SystemExit(1) from None
        except BaseException:
            traceback.print_exc(file=fh)
            fh.flush()
            raise
        else:
            print(f"{what} done in {time.perf_counter() - t0:.2f} s", flush=True)
        finally:
            sys.stdout, sys.stderr = old_out, old_err


def say(msg: str) -> None:
    """Print one progress line of a job (into its log under :func:`script_logging`)."""
    print(msg, flush=True)
