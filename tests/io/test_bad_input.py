"""Bad record files: every case must give a RecordError naming the file, the line and the problem.

The corpus is ``tests/data/bad/`` (small committed text files); binary junk, directories and
missing files are made by the tests. Each case is also run through the command line: exit code 2,
one line on stderr, no traceback.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import obspy
import pytest

from isorock import cli
from isorock.errors import IsorockError, RecordError
from isorock.io import (
    BinaryFileError,
    ColumnCountError,
    EmptyRecordError,
    HeaderError,
    NonFiniteError,
    NonNumericError,
    NptsMismatchError,
    TimeStepError,
    TruncatedRecordError,
    UnitsError,
    UnknownFormatError,
    read_record,
)
from isorock.io import bbp as bbp_mod
from isorock.io import peer as peer_mod
from isorock.io import plain as plain_mod
from support.records import DATA

BAD = DATA / "bad"

# file, format, keyword arguments, error class, line named in the message (None: none), words in the problem
CASES = [
    ("truncated.AT2", None, {}, TruncatedRecordError, 6, "NPTS=12"),
    ("npts_extra.AT2", None, {}, NptsMismatchError, 6, "NPTS=8"),
    ("zero_dt.AT2", None, {}, TimeStepError, 4, "must be > 0"),
    ("missing_dt.AT2", None, {}, HeaderError, 4, "no DT"),
    ("nonnumeric.AT2", None, {}, NonNumericError, 6, ".80x0000E-01"),
    ("nan.AT2", None, {}, NonFiniteError, 6, "NaN"),
    ("header_only.AT2", None, {}, EmptyRecordError, 4, "no data values"),
    ("velocity.AT2", None, {}, UnitsError, 3, "velocity"),
    ("header_pga_mismatch.AT2", None, {}, HeaderError, 3, "PGA=0.5"),
    ("short_header.AT2", None, {}, UnknownFormatError, None, "cannot tell the format"),
    ("short_header.AT2", "peer-at2", {}, HeaderError, 2, "4 header lines"),
    ("empty.AT2", None, {}, EmptyRecordError, None, "empty"),
    ("empty.AT2", "one-column", {"dt": 0.01, "units": "g"}, EmptyRecordError, None, "empty"),
    ("nan_values.txt", "one-column", {"dt": 0.01, "units": "g"}, NonFiniteError, 3, "nan"),
    ("inf_values.txt", "one-column", {"dt": 0.01, "units": "g"}, NonFiniteError, 3, "inf"),
    ("cm_s2_values.txt", "one-column", {"dt": 0.01, "units": "g"}, UnitsError, 2, "implausible"),
    ("all_zero.txt", "one-column", {"dt": 0.01, "units": "g"}, UnitsError, None, "all values are zero"),
    ("two_values_on_a_line.txt", "one-column", {"dt": 0.01, "units": "g"}, ColumnCountError, 2, "1 column"),
    ("nonuniform_time.txt", "two-column", {"units": "g"}, TimeStepError, 2, "non-uniform"),
    ("decreasing_time.txt", "two-column", {"units": "g"}, TimeStepError, 4, "does not increase"),
    ("two_column_text_header.txt", "two-column", {"units": "g"}, NonNumericError, 1, "'time'"),
    ("velocity.bbp", None, {}, UnitsError, 1, "velocity"),
    ("short_row.bbp", None, {}, ColumnCountError, 3, "4 columns"),
    ("percent_truncated.dat", "percent-header", {}, TruncatedRecordError, 4, "16 of the 20"),
    ("percent_no_dt.dat", "percent-header", {"units": "cm/s2"}, TimeStepError, None, "time step not given"),
    ("percent_extra_values.dat", "percent-header", {}, NptsMismatchError, 3, "not zero padding"),
    ("bad_value.csv", None, {}, NonNumericError, 5, "'abc'"),
    ("unknown_format.txt", None, {}, UnknownFormatError, None, "cannot tell the format"),
    # missing, zero, negative, implausible time steps and units given by the caller
    ("nan_values.txt", "one-column", {"units": "g"}, TimeStepError, None, "time step not given"),
    ("cm_s2_values.txt", "one-column", {"dt": 0.0, "units": "cm/s2"}, TimeStepError, None, "must be > 0"),
    ("cm_s2_values.txt", "one-column", {"dt": -0.01, "units": "cm/s2"}, TimeStepError, None, "must be > 0"),
    # issue 32 item 9: "--dt inf" was told "must be > 0"
    (
        "cm_s2_values.txt",
        "one-column",
        {"dt": float("inf"), "units": "cm/s2"},
        TimeStepError,
        None,
        "dt=inf is not a finite number of seconds",
    ),
    (
        "cm_s2_values.txt",
        "one-column",
        {"dt": float("nan"), "units": "cm/s2"},
        TimeStepError,
        None,
        "dt=nan is not a finite number of seconds",
    ),
    ("cm_s2_values.txt", "one-column", {"dt": 5.0, "units": "cm/s2"}, TimeStepError, None, "implausible"),
    ("cm_s2_values.txt", "one-column", {"dt": 0.01}, UnitsError, None, "units not given"),
    ("cm_s2_values.txt", "one-column", {"dt": 0.01, "units": "furlongs"}, UnitsError, None, "unknown units"),
    ("cm_s2_values.txt", "one-column", {"dt": 0.01, "units": "cm/s"}, UnitsError, None, "velocity"),
    ("cm_s2_values.txt", "peer-at3", {"dt": 0.01, "units": "g"}, UnknownFormatError, None, "unknown format"),
    ("truncated.AT2", None, {"dt": 0.02}, TimeStepError, 4, "header (line 4) says 0.01"),
    ("truncated.AT2", "peer-at2", {"units": "cm/s2"}, UnitsError, 3, "states g"),
    ("npts_extra.AT2", "peer-at2-body", {"dt": 0.01, "units": "g"}, NonNumericError, 1, "'PEER'"),
]

IDS = [f"{c[0]}-{c[1] or 'auto'}-{'-'.join(f'{k}={v}' for k, v in c[2].items())}".rstrip("-") for c in CASES]


def _check_message(exc: RecordError, path: Path, line: int | None, words: str) -> None:
    msg = str(exc)
    assert "\n" not in msg
    assert exc.path == str(path)
    assert exc.line == line
    prefix = f"{path}:{line}: " if line is not None else f"{path}: "
    assert msg.startswith(prefix), msg
    assert words in exc.problem, msg


@pytest.mark.parametrize(("name", "fmt", "kwargs", "cls", "line", "words"), CASES, ids=IDS)
def test_bad_file_gives_clear_record_error(name, fmt, kwargs, cls, line, words):
    path = BAD / name
    with pytest.raises(cls) as info:
        read_record(path, fmt, **kwargs)
    assert isinstance(info.value, RecordError)
    _check_message(info.value, path, line, words)


@pytest.mark.parametrize(
    ("name", "fmt", "kwargs", "cls", "line", "words"),
    [c for c in CASES if c[1] != "peer-at3" and c[3] is not UnknownFormatError],
    ids=[i for i, c in zip(IDS, CASES, strict=True) if c[1] != "peer-at3" and c[3] is not UnknownFormatError],
)
def test_obspy_read_raises_the_same_error(name, fmt, kwargs, cls, line, words):
    """The plugins themselves raise the RecordError when called through obspy.read."""
    from isorock.io import obspy_format

    path = BAD / name
    if fmt is None and not (
        peer_mod._is_peer_at2(str(path))
        or bbp_mod._is_bbp(str(path))
        or plain_mod._is_pyslammer_csv(str(path))
    ):
        pytest.skip("not detectable without a format: covered by read_record")
    with pytest.raises(cls) as info:
        obspy.read(str(path), format=obspy_format(fmt) if fmt else None, **kwargs)
    _check_message(info.value, path, line, words)


def test_binary_junk(tmp_path):
    rng = np.random.default_rng(1)
    junk = tmp_path / "junk.AT2"
    junk.write_bytes(rng.integers(0, 256, 4000, dtype=np.uint8).tobytes())
    for fmt in (None, "peer-at2", "one-column", "bbp"):
        with pytest.raises(BinaryFileError) as info:
            read_record(junk, fmt, dt=0.01, units="g")
        assert str(info.value) == f"{junk}: binary data, not a text record file"
    # control characters without NUL bytes are junk too
    ctrl = tmp_path / "ctrl.txt"
    ctrl.write_bytes(b"0.1\n" + bytes(range(1, 9)) * 50 + b"\n0.2\n")
    with pytest.raises(BinaryFileError):
        read_record(ctrl, "one-column", dt=0.01, units="g")


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(RecordError, match="no such file") as info:
        read_record(tmp_path / "nope.AT2")
    assert info.value.path == str(tmp_path / "nope.AT2")
    with pytest.raises(RecordError, match="is a directory"):
        read_record(tmp_path)


def test_component_not_in_file(tmp_path):
    path = BAD.parent / "good" / "tiny.AT2"
    with pytest.raises(RecordError, match=r"no component '254' in this file: it holds 090"):
        read_record(path, component="254")
    assert read_record(path, component="090")[0].stats.channel == "090"


def test_is_format_functions_never_raise(tmp_path):
    junk = tmp_path / "junk.bin"
    junk.write_bytes(bytes(range(256)) * 10)
    odd = [
        str(tmp_path / "nope"),
        str(tmp_path),
        str(junk),
        str(BAD / "empty.AT2"),
        None,
        42,
        b"\x00\x01",
        io.BytesIO(b"\xff\xfe\x00junk"),
        io.StringIO("PEER\nx\nUNITS OF G\nNPTS=1, DT=.01\n1.0\n"),
    ]
    funcs = [
        peer_mod._is_peer_at2,
        peer_mod._is_peer_at2_body,
        bbp_mod._is_bbp,
        plain_mod._is_one_column,
        plain_mod._is_two_column,
        plain_mod._is_percent_header,
        plain_mod._is_pyslammer_csv,
    ]
    for f in funcs:
        for x in odd:
            assert f(x) in (True, False)
    assert peer_mod._is_peer_at2(odd[-1]) is True  # the text stream is an AT2 header
    assert not any(f(str(junk)) for f in funcs)


def test_record_error_is_an_isorock_error():
    with pytest.raises(IsorockError):
        read_record(BAD / "truncated.AT2")


# --------------------------------------------------------------------------- through the command line
def _cli_args(name, fmt, kwargs):
    args = ["records", "check", str(BAD / name)]
    if fmt is not None:
        args += ["--format", fmt]
    for k, v in kwargs.items():
        args += [f"--{k}", str(v)]
    return args


CLI_CASES = [c for c in CASES if c[1] != "peer-at3"]


@pytest.mark.parametrize(
    ("name", "fmt", "kwargs", "cls", "line", "words"),
    CLI_CASES,
    ids=[i for i, c in zip(IDS, CASES, strict=True) if c[1] != "peer-at3"],
)
def test_cli_one_line_exit_2(capsys, name, fmt, kwargs, cls, line, words):
    rc = cli.main(_cli_args(name, fmt, kwargs))
    out, err = capsys.readouterr()
    assert rc == 2
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    where = f"{BAD / name}:{line}: " if line is not None else f"{BAD / name}: "
    assert lines[0].startswith(f"isorock: error: {where}"), lines[0]
    assert words in lines[0]
    assert "Traceback" not in err


def test_cli_unknown_format_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["records", "check", str(BAD / "cm_s2_values.txt"), "--format", "peer-at3"])
    assert info.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_cli_binary_and_missing(tmp_path, capsys):
    junk = tmp_path / "junk.AT2"
    junk.write_bytes(b"\x00\x01\x02" * 300)
    for path, words in ((junk, "binary data"), (tmp_path / "nope.AT2", "no such file")):
        rc = cli.main(["records", "check", str(path)])
        err = capsys.readouterr().err
        assert rc == 2 and err.count("\n") == 1 and words in err and "Traceback" not in err


def test_cli_subprocess_no_traceback():
    """The installed ``isorock`` entry point (real process): exit 2, one stderr line."""
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    proc = subprocess.run(
        [sys.executable, "-m", "isorock.cli", "records", "check", str(BAD / "truncated.AT2")],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.splitlines() == [
        f"isorock: error: {BAD / 'truncated.AT2'}:6: "
        "file ends after 10 of the NPTS=12 values declared on line 4 (truncated file?)"
    ]


@pytest.mark.parametrize("token", ["1.5.3", "1-2", "0.1e", "--0.1", "0x10", "1,5"])
def test_junk_tokens_are_not_split_into_numbers(tmp_path, token):
    p = tmp_path / "a.txt"
    p.write_text(f"0.1\n{token}\n0.2\n")
    with pytest.raises(NonNumericError) as info:
        read_record(p, "one-column", dt=0.01, units="g")
    assert info.value.line == 2 and repr(token) in str(info.value)
