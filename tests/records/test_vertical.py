"""The vertical component beside a horizontal one (isorock.records.vertical): found in the real record
sets the manifest of the shared records names (their files are not hard-coded here), refused where a
BBP file's U-D column repeats its N-S column, checked for alignment, processed like the horizontal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from obspy import Trace

from isorock.io import read_record, read_trace
from isorock.records.manifest import read_manifest
from isorock.records.motion import load_record
from isorock.records.naming import is_vertical
from isorock.records.spec import RecordFile
from isorock.records.vertical import COPY_CORRELATION, find_vertical, is_copy
from support.records import RECORDS_SKIP, records_dir


def _rows():
    d = records_dir()
    if d is None:
        pytest.skip(RECORDS_SKIP)
    return d, read_manifest(d / "manifest.csv")


def _vertical_sets():
    """(vertical row, the other rows of its recording in its format) for each vertical file."""
    d, rows = _rows()
    out = []
    for v in rows:
        if is_vertical(v.component):
            mates = [
                e
                for e in rows
                if e is not v and (e.event, e.station, e.format) == (v.event, v.station, v.format)
            ]
            out.append((v, mates))
    return d, out


def test_every_vertical_file_is_found_beside_each_horizontal_of_its_set():
    d, sets = _vertical_sets()
    assert sets, "the manifest names no vertical file"
    for v, mates in sets:
        assert mates, f"{v.file}: no horizontal of its set"
        files = [RecordFile.from_entry(d, e) for e in [v, *mates]]
        for h in mates:
            f = RecordFile.from_entry(d, h)
            tr = read_trace(f.path, f.format, dt=f.dt_s, units=f.units, component=f.component)
            res = find_vertical(files, tr, f.path)
            assert res.found is not None, f"{h.file}: {res.describe()}"
            assert Path(res.found.file).name == v.file and res.found.component == v.component
            assert res.found.alignment.ok and res.found.alignment.lag_s is not None
            assert 0.01 < res.found.pga_g < 2.0


def test_a_bbp_u_d_column_is_a_vertical_unless_it_repeats_n_s():
    d, rows = _rows()
    bbp = [e for e in rows if e.format == "bbp"]
    assert bbp
    copies = 0
    for e in bbp:
        f = RecordFile.from_entry(d, e)
        st = read_record(f.path, "bbp", units=f.units)
        res = find_vertical([f], st[0], f.path)
        repeats = "duplicates N-S" in e.note or "repeats N-S" in e.note
        ud = next(tr for tr in st if is_vertical(tr.stats.channel) or tr.stats.channel == "U-D")
        # the manifest's note and the data agree
        assert repeats == np.array_equal(ud.data, st[0].data), e.file
        if repeats:
            copies += 1
            assert res.found is None and "repeats the horizontal N-S" in res.refused[0], res.describe()
        else:
            assert res.found is not None and res.found.component == "U-D", res.describe()
            assert res.found.alignment.describe() == "time-aligned (one file, one time column)"
    assert 0 < copies < len(bbp)


def test_the_vertical_is_processed_by_the_steps_of_the_horizontal():
    d, sets = _vertical_sets()
    v, mates = sets[0]
    files = [RecordFile.from_entry(d, e) for e in [v, *mates]]
    f = files[1]
    res = find_vertical(files, read_trace(f.path, f.format, dt=f.dt_s, units=f.units), f.path)
    gm = res.found.motion()
    raw = res.found.motion(raw=True)
    # as read, put positive up (the first vertical of the manifest is the DWN one: sign -1, issue 34)
    sign = res.found.polarity.sign
    assert raw.meta["vertical"]["processing"] == [] and np.array_equal(raw.acc, sign * res.found.trace.data)
    horizontal = load_record(f.path, format=f.format, dt=f.dt_s, units=f.units)

    def names(steps):
        return [str(x).split("(")[0].split(":")[0].split()[0] for x in steps]

    steps = gm.meta["vertical"]["processing"]
    assert len(steps) >= 3 and names(steps) == names(horizontal.trace.stats.processing)
    assert 0.5 < gm.pga_g / res.found.pga_g < 1.5


def _trace(x, dt=0.01, **isorock) -> Trace:
    tr = Trace(np.asarray(x, dtype=float), header={"delta": dt})
    tr.stats.isorock = {"component": isorock.get("component", "")}
    return tr


def test_is_copy_sees_repeats_and_sign_flips_but_not_real_components():
    rng = np.random.default_rng(3)
    h = rng.standard_normal(2000)
    assert is_copy(h, h) and is_copy(-h, h) and is_copy(2.0 * h + 0.001, h)
    other = 0.2 * h + rng.standard_normal(2000)  # correlated as two real components are, and more
    assert not is_copy(other, h)
    # at the threshold
    r = COPY_CORRELATION
    near = r * h / h.std() + np.sqrt(1 - r * r) * 0.999 * rng.standard_normal(2000)
    assert not is_copy(near, h) or np.corrcoef(near, h)[0, 1] > r
    assert not is_copy(np.zeros(10), np.ones(10))


def _file(path: Path, dt: float, component: str) -> RecordFile:
    return RecordFile(path=str(path), format="one-column", dt_s=dt, units="g", component_name=component)


def test_a_vertical_of_another_time_step_is_refused_with_why(tmp_path):
    t = np.arange(3000) * 0.01
    h = np.sin(2 * np.pi * t) * np.exp(-0.2 * t)
    v = np.cos(3 * np.pi * t[::2]) * np.exp(-0.2 * t[::2])
    files = []
    for name, x, dt, comp in (("h-090.txt", h, 0.01, "090"), ("v-UP.txt", v, 0.02, "UP")):
        np.savetxt(tmp_path / name, x)
        files.append(_file(tmp_path / name, dt, comp))
    tr = read_trace(files[0].path, "one-column", dt=0.01, units="g")
    res = find_vertical(files, tr, files[0].path)
    assert res.found is None
    assert res.refused == ["v-UP.txt:UP not time-aligned: time steps differ (0.01 and 0.02 s)"]


def test_a_recording_without_vertical_finds_none(tmp_path):
    t = np.arange(1000) * 0.01
    np.savetxt(tmp_path / "h-090.txt", np.sin(t))
    f = RecordFile(
        path=str(tmp_path / "h-090.txt"), format="one-column", dt_s=0.01, units="g", component_name="090"
    )
    res = find_vertical([f], read_trace(f.path, "one-column", dt=0.01, units="g"), f.path)
    assert res.found is None and res.refused == [] and res.describe() == "no vertical component"
