"""Helpers of the command-line tests: run ``isorock`` in this process (its JSON) or as a subprocess."""

from __future__ import annotations

import json
import subprocess
import sys

from isorock.cli import main


def run_json(capsys, argv: list[str]) -> dict:
    """``isorock ARGV`` in this process, which must succeed: its JSON output."""
    assert main(argv) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def run_cli(argv: list[str]) -> subprocess.CompletedProcess:
    """``isorock ARGV`` as a separate process (exit code, stdout, stderr)."""
    return subprocess.run([sys.executable, "-m", "isorock.cli", *argv], capture_output=True, text=True)
