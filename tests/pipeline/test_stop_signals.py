"""A run stopped by a signal (issue 32 item 8): the wrapper passes the first SIGINT/SIGTERM/SIGHUP on
to Snakemake as SIGINT, the second as SIGTERM, and kills it with its jobs at the third; then it raises
:class:`~isorock.errors.Stopped` (one line, the signal's exit code). Snakemake is stood in for by a
program that notes each signal it gets and ignores it."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from pathlib import Path

import pytest

from isorock.control.run import run_snakemake
from isorock.errors import Stopped

STUBBORN = r"""
import signal, sys, time
from pathlib import Path
notes = Path(sys.argv[1])
def note(signum, frame):
    with open(notes, "a") as fh:
        fh.write(signal.Signals(signum).name + "\n")
signal.signal(signal.SIGINT, note)
signal.signal(signal.SIGTERM, note)
notes.write_text("ready\n")
while True:
    time.sleep(0.05)
"""


def _wait_for(path: Path, line: str, limit: float = 120.0) -> None:
    t0 = time.monotonic()
    while time.monotonic() - t0 < limit:  # only a hang fails here
        if path.is_file() and line in path.read_text().split():
            return
        time.sleep(0.02)
    raise AssertionError(f"{line} never reached {path}")


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGHUP], ids=lambda s: s.name)
def test_three_signals_escalate_to_a_kill_of_snakemake_and_its_jobs(tmp_path, sig, capsys):
    notes = tmp_path / "notes.txt"
    before = signal.getsignal(sig)

    def signaller() -> None:
        for seen in ("ready", "SIGINT", "SIGTERM"):
            _wait_for(notes, seen)
            os.kill(os.getpid(), sig)

    t = threading.Thread(target=signaller, daemon=True)
    t.start()
    with pytest.raises(Stopped) as exc:
        run_snakemake([sys.executable, "-c", STUBBORN, str(notes)], "run")
    t.join(timeout=60)
    assert exc.value.signum == sig and exc.value.exit_code == 128 + sig
    assert notes.read_text().split() == ["ready", "SIGINT", "SIGTERM"]  # then SIGKILL, unseen
    err = capsys.readouterr().err
    assert f"isorock: {sig.name}: stopping snakemake and its jobs" in err
    assert "asked a third time: snakemake and its jobs are killed" in err
    assert str(exc.value).startswith(f"stopped by {sig.name}: snakemake run ended its jobs (exit code -9)")
    assert signal.getsignal(sig) is before  # this process's handler is back as it was
