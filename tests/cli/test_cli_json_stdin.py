"""``--json`` errors and records from standard input (issue 23, item 6).

With ``--json`` a user error is also one JSON object on stdout, ``{"error": ..., "exit_code": 2}``,
its message the line on stderr without the ``isorock: error:`` prefix (usage errors included, found
by ``--json`` among the arguments); without ``--json`` stdout stays empty. ``-`` where a record file
is taken (``FILE`` of ``info``/``pulse``/``records check``, ``--record`` of ``simulate``/``map``...)
reads standard input with ``--format``, through the same reader, and names it ``<stdin>``.

The record is ``tests/data/good/tiny.AT2`` (no shared records needed).
"""

from __future__ import annotations

import io
import json
import subprocess
import sys

import pytest

from isorock.cli import main
from isorock.cli.stdin import STDIN_NAME
from support.cli import run_cli, run_json

BLOCK = ["--lambda", "4", "--R", "1"]


@pytest.fixture
def at2(data_dir):
    return data_dir / "good" / "tiny.AT2"


@pytest.fixture
def stdin_of(monkeypatch):
    """Put bytes on standard input (in-process runs of :func:`isorock.cli.main`)."""

    def put(data: bytes) -> None:
        monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))

    return put


def _run(capsys, argv) -> tuple[int, str, str]:
    rc = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


def cli_ok(capsys, argv) -> str:
    """``isorock ARGV`` in this process, which must succeed: its text output."""
    rc, out, err = _run(capsys, argv)
    assert rc == 0, err
    return out


def _error_pair(out: str, err: str) -> str:
    """The message, checked to be the same in the JSON object on stdout and the line on stderr."""
    assert err.splitlines()[-1].startswith("isorock: error: "), err  # after the usage lines, if any
    message = err.splitlines()[-1].removeprefix("isorock: error: ")
    assert out.count("\n") == 1 and json.loads(out) == {"error": message, "exit_code": 2}
    return message


# ------------------------------------------------------------------------------- --json errors
@pytest.mark.parametrize(
    "argv, words",
    [
        (
            ["simulate", *BLOCK, "--pulse", "rect", "--td", "-1", "--pga", "1"],
            "--td -1 is outside 0.05 to 20 s",
        ),
        (["info", "no-such-file.AT2"], "no such file"),
        (["records", "check", "no-such-file.AT2"], "no such file"),
        (["records", "status", "no-such-dir"], "does not exist"),
        (["simulate", *BLOCK, "--pulse", "rect", "--td", "1"], "--pulse needs --pga"),
    ],
)
def test_a_user_error_with_json_is_json_on_stdout_and_the_line_on_stderr(capsys, argv, words):
    rc, out, err = _run(capsys, [*argv, "--json"])
    assert rc == 2 and words in _error_pair(out, err)
    rc, out, err2 = _run(capsys, argv)  # without --json: the same line, nothing on stdout
    assert rc == 2 and out == "" and err2 == err


@pytest.mark.parametrize(
    "argv, words",
    [
        (["simulate", "--json", "--lambda", "four", "--R", "1", "--pulse", "rect"], "invalid float value"),
        (["info", "x.AT2", "--format", "peer-at3", "--json"], "invalid choice: 'peer-at3'"),
        (["simulate", *BLOCK, "--pulse", "rect", "--td", "1", "--pga", "1", "--json", "--bogus"], "--bogus"),
        (["simulate", *BLOCK, "--pulse", "rect", "--td", "1", "--js", "--bogus"], "--bogus"),
    ],
)
def test_a_usage_error_with_json_is_json_too(capsys, argv, words):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    out, err = capsys.readouterr()
    assert err.startswith("usage: ") and words in _error_pair(out, err)


def test_a_usage_error_without_json_keeps_stdout_empty(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--lambda", "four"])
    out, err = capsys.readouterr()
    assert out == "" and "isorock: error:" in err


def test_json_errors_in_a_separate_process():
    p = run_cli(["info", "no-such-file.AT2", "--json"])
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert json.loads(p.stdout) == {"error": "no-such-file.AT2: no such file", "exit_code": 2}
    assert p.stderr == "isorock: error: no-such-file.AT2: no such file\n"


# ------------------------------------------------------------------------------- standard input
def test_info_reads_a_record_from_standard_input(at2):
    """``isorock info - --format PEERAT2 < file.AT2``: the same record as the file, named <stdin>."""
    cmd = [sys.executable, "-m", "isorock.cli", "info", "-", "--format", "PEERAT2", "--json"]
    p = subprocess.run(cmd, input=at2.read_bytes(), capture_output=True)
    assert p.returncode == 0, p.stderr
    got = json.loads(p.stdout)
    q = run_cli(["info", str(at2), "--json"])
    ref = json.loads(q.stdout)
    assert got["file"] == STDIN_NAME and got["record"]["file"] == STDIN_NAME
    assert got["record"]["sha256"] == ref["record"]["sha256"]
    for key in ("npts", "dt_s", "pga_g", "pgv_m_s", "arias_m_s", "pga_raw_g", "component"):
        assert got[key] == ref[key], key
    assert got["record"]["processing"] == ref["record"]["processing"]
    text = subprocess.run(cmd[:-1], input=at2.read_bytes(), capture_output=True, text=False)
    assert text.returncode == 0 and text.stdout.decode().startswith("record: <stdin> [090], processed")


def test_pulse_and_records_check_read_standard_input(capsys, stdin_of, at2, plain_file):
    stdin_of(plain_file.read_bytes())
    argv = ["records", "check", "-", "--format", "one-column", "--dt", "0.01", "--units", "g", "--json"]
    got = run_json(capsys, argv)
    ref = run_json(capsys, [*argv[:2], str(plain_file), *argv[3:]])
    assert got["file"] == STDIN_NAME and ref["file"] == str(plain_file)
    assert (got["station"], ref["station"]) == ("stdin", "rec")  # a headerless file's station: its name
    same = {k for k in ref if k not in ("file", "station")}
    assert {k: got[k] for k in same} == {k: ref[k] for k in same}
    stdin_of(plain_file.read_bytes())
    text = cli_ok(capsys, ["pulse", "-", *argv[3:-1]])
    assert text.startswith("record: <stdin>, processed") and "Tp (db4 wavelet" in text
    stdin_of(b"")
    rc, out, err = _run(capsys, ["pulse", "-", "--format", "peer-at2", "--json"])
    assert rc == 2 and _error_pair(out, err) == "<stdin>: file is empty"


def test_simulate_reads_its_record_from_standard_input(capsys, stdin_of, at2):
    argv = ["simulate", *BLOCK, "--pga", "0.3", "--json"]
    ref = run_json(capsys, [*argv, "--record", str(at2)])
    stdin_of(at2.read_bytes())
    got = run_json(capsys, [*argv, "--record", "-", "--format", "peer-at2"])
    assert got["record"]["file"] == STDIN_NAME and got["record"]["sha256"] == ref["record"]["sha256"]
    same = {k for k in ref if k not in ("record", "seconds")}
    assert {k: got[k] for k in same} == {k: ref[k] for k in same}


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["info", "-"], "FILE '-'"),
        (["pulse", "-", "--raw"], "FILE '-'"),
        (["records", "check", "-"], "FILE '-'"),
        (["simulate", *BLOCK, "--pga", "0.3", "--record", "-"], "--record FILE '-'"),
    ],
)
def test_standard_input_needs_format(capsys, stdin_of, at2, argv, flag):
    stdin_of(at2.read_bytes())
    rc, out, err = _run(capsys, [*argv, "--json"])
    msg = _error_pair(out, err)
    assert rc == 2 and msg.startswith(flag) and "standard input" in msg and "--format (peer-at2" in msg


def test_errors_of_a_record_on_standard_input_name_it_stdin(capsys, stdin_of, at2):
    stdin_of(b"0.1\n0.2\nabc\n")
    rc, out, err = _run(capsys, ["info", "-", "--format", "one-column", "--dt", "0.01", "--units", "g"])
    assert rc == 2 and out == "" and err == "isorock: error: <stdin>:3: non-numeric value 'abc'\n"
    stdin_of(b"0.1\n0.2\n")
    rc, out, err = _run(capsys, ["info", "-", "--format", "one-column"])
    assert rc == 2 and err.startswith("isorock: error: <stdin>: units not given") and "tmp" not in err


def test_a_terminal_on_standard_input_is_refused(capsys, monkeypatch):
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    monkeypatch.setattr(sys, "stdin", Terminal())
    rc, out, err = _run(capsys, ["info", "-", "--format", "peer-at2"])
    assert rc == 2 and "nothing is piped or redirected" in err and err.count("\n") == 1


def test_a_record_too_short_to_process_is_one_line(tmp_path):
    """Two samples on standard input: one line naming the record and the least it needs (it was a
    LinAlgError traceback from the baseline fit)."""
    import subprocess
    import sys

    res = subprocess.run(
        [sys.executable, "-m", "isorock.cli", "info", "-", "--format", "one-column", "--dt", "0.01",
         "--units", "g"], input="0\n0.1\n", capture_output=True, text=True)  # fmt: skip
    assert res.returncode == 2 and "Traceback" not in res.stderr
    assert res.stderr.strip().splitlines() == [
        "isorock: error: record stdin has 2 samples: too short to process (a record needs at least 8)"
    ]
