"""Format detection (issue 17): a ``%``-header file that states its sample count and time step is
read without a format; a file of no recognised format is refused with what its first lines look like."""

from __future__ import annotations

import numpy as np
import pytest

from isorock.errors import MissingUnitsError, UnknownFormatError
from isorock.io import plain as plain_mod
from isorock.io import read_record


def _values(n: int = 1200, per_line: int = 6) -> list[str]:
    t = np.arange(n) * 0.004
    a = 30.0 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.5 * t) * np.minimum(t, 1.0)  # cm/s^2
    return ["".join(f"{x:14.5E}" for x in a[i : i + per_line]) for i in range(0, n, per_line)]


def _write(path, header: list[str], n: int = 1200, per_line: int = 6):
    path.write_text("\n".join(header + _values(n, per_line)) + "\n")
    return path


def test_percent_header_with_count_and_step_is_detected(tmp_path):
    f = _write(
        tmp_path / "luc_fn.dat", ["%luc fn Lucerne, Landers 28 Jun 1992", "%1200 0.004000 0 0 cm/s2 text"]
    )
    assert plain_mod._is_percent_header(str(f))
    tr = read_record(f, units="cm/s2")[0]
    info = tr.stats.isorock
    assert info.format == "percent-header" and info.obspy_format == "PERCENTHEADER"
    assert tr.stats.delta == pytest.approx(0.004) and tr.stats.npts == 1200 and info.dt_source == "header"
    assert info.event.startswith("luc fn Lucerne")
    with pytest.raises(MissingUnitsError):  # detected, but the units are still needed
        read_record(f)


def test_percent_header_with_points_line_is_detected(tmp_path):
    hdr = [
        "% CORRECTED ACCELEROGRAM",
        "% 1200 POINTS OF ACCEL DATA EQUALLY SPACED AT  .004 SEC.  (UNITS: CM/SEC/SEC)",
    ]
    f = _write(tmp_path / "sta_360.dat", hdr)
    tr = read_record(f)[0]
    assert tr.stats.isorock.format == "percent-header" and tr.stats.isorock.units == "cm/s2"


def test_percent_files_without_a_time_step_are_not_claimed(tmp_path):
    one = tmp_path / "one.txt"
    one.write_text("% acceleration [g]\n0.1\n-0.2\n0.05\n")
    assert not plain_mod._is_percent_header(str(one))
    assert read_record(one, dt=0.01, units="g")[0].stats.isorock.format == "one-column"
    text = tmp_path / "text.dat"
    text.write_text("%1200 0.004000\nnot numbers here\n")
    assert not plain_mod._is_percent_header(str(text))


def test_undetected_format_names_the_first_lines(tmp_path):
    f = _write(tmp_path / "elcen.dat", ["% *", "% E050A", "%      1979  10  15    2316 Imperial Valley"])
    with pytest.raises(UnknownFormatError) as info:
        read_record(f, units="cm/s2")
    msg = str(info.value)
    assert "cannot tell the format" in msg and "\n" not in msg
    assert "the file begins '% *' | '% E050A' | '%      1979" in msg
    assert "3 '%' header lines stating no time step, then 6 numbers per line" in msg
    assert "percent-header" in msg
    three = tmp_path / "three.txt"
    three.write_text("0.0 0.1 0.2\n0.01 0.1 0.2\n")
    with pytest.raises(UnknownFormatError, match=r"begins '0.0 0.1 0.2' .*\(3 numbers per line, no header\)"):
        read_record(three, dt=0.01, units="g")
    words = tmp_path / "words.txt"
    words.write_text("station ABC\nsome words\n")
    with pytest.raises(UnknownFormatError, match="text that is not numbers"):
        read_record(words)
