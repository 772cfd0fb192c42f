"""The sense of a vertical component (issue 34, docs/model.md §17): a file's samples are positive in the
direction its component is named for, the engine's a_v is positive up. A ``DWN`` vertical (the Pacoima
Dam vertical of 1971 in the shared records, found by its manifest row's component, not by its file name)
has its sign reversed; an ``UP`` vertical is taken as read; the sense is said by ``isorock info`` and
``isorock simulate``, and the vertical the engine receives is the file's samples times that sign."""

from __future__ import annotations

import json

import numpy as np
import pytest

from isorock.cli import main
from isorock.constants import G
from isorock.io import read_trace
from isorock.processing import process
from isorock.records.manifest import read_manifest
from isorock.records.naming import is_vertical, vertical_polarity
from isorock.records.spec import RecordFile
from isorock.records.vertical import find_vertical
from support.records import RECORDS_SKIP, records_dir

# ----------------------------------------------------------------------------------- by name, no files


@pytest.mark.parametrize("name", ["DWN", "DOWN", "DN", "dwn", "C05DWN"])
def test_a_name_that_says_down_is_positive_down_and_reversed(name):
    p = vertical_polarity(name)
    assert (p.positive, p.sign, p.source) == ("down", -1, "name")
    assert "positive down" in p.why and "sign reversed" in p.why


def test_up_is_taken_as_read_and_a_name_without_a_sense_is_said_to_be_assumed():
    p = vertical_polarity("UP")
    assert (p.positive, p.sign, p.source) == ("up", 1, "name")
    for name in ("U-D", "UD", "V", "VERT", "Z", "HNZ", ""):
        p = vertical_polarity(name)
        assert (p.positive, p.sign, p.source) == ("up", 1, "assumed"), name
        assert "states no sense" in p.why


def test_the_sense_stated_by_the_user_overrides_the_name_and_says_so():
    p = vertical_polarity("DWN", "up")
    assert (p.positive, p.sign, p.source) == ("up", 1, "given") and "its name DWN says down" in p.why
    p = vertical_polarity("U-D", "down")
    assert (p.positive, p.sign, p.source) == ("down", -1, "given") and "says" not in p.why
    assert p.to_dict() == {"positive_in_file": "down", "sign": -1, "polarity": p.why}
    with pytest.raises(Exception, match="give 'up' or 'down'"):
        vertical_polarity("DWN", "sideways")


# ------------------------------------------------------------------------------ the shared records


def _set(component: str):
    """(directory, the vertical row named ``component``, the horizontal rows of its recording)."""
    d = records_dir()
    if d is None:
        pytest.skip(RECORDS_SKIP)
    rows = read_manifest(d / "manifest.csv")
    v = next((e for e in rows if e.component.strip().upper() == component), None)
    if v is None:
        pytest.skip(f"the manifest names no {component} vertical")
    mates = [
        e
        for e in rows
        if e is not v
        and not is_vertical(e.component)
        and (e.event, e.station, e.format) == (v.event, v.station, v.format)
    ]
    assert mates, f"{v.file}: no horizontal of its recording in the manifest"
    return d, v, mates


def _raw_values(path) -> np.ndarray:
    """The samples of a PEER AT2 file as its text gives them [g], read here without isorock's reader."""
    lines = path.read_text().splitlines()
    assert lines[3].lstrip().upper().startswith("NPTS"), lines[3]
    return np.array([float(x) for line in lines[4:] for x in line.split()])


def _found(d, v, mates):
    files = [RecordFile.from_entry(d, e) for e in [v, *mates]]
    h = files[1]
    tr = read_trace(h.path, h.format, dt=h.dt_s, units=h.units, component=h.component)
    res = find_vertical(files, tr, h.path)
    assert res.found is not None, res.describe()
    return res.found


def test_the_dwn_vertical_is_read_positive_down_and_turned_positive_up():
    d, v, mates = _set("DWN")
    header = (d / v.file).read_text().splitlines()[1]
    assert header.rstrip().upper().endswith("DWN")  # the file's own statement of its component
    vc = _found(d, v, mates)
    assert vc.component == "DWN" and vc.polarity.positive == "down" and vc.polarity.sign == -1
    raw = _raw_values(d / v.file)
    k = int(np.argmax(np.abs(raw)))
    as_read = vc.trace.data
    assert as_read[k] == pytest.approx(raw[k] * G, rel=1e-6)  # isorock reads the file's sign ...
    up = vc.motion(raw=True)
    assert up.acc[k] == pytest.approx(-raw[k] * G, rel=1e-6)  # ... and the vertical used is reversed
    np.testing.assert_allclose(up.acc, -np.asarray(as_read, dtype=float), rtol=0, atol=0)
    info = up.meta["vertical"]
    assert (info["positive_in_file"], info["sign"]) == ("down", -1) and "DWN" in info["polarity"]
    # processed: the horizontal's steps on the reversed samples (every step is linear in the samples)
    processed = vc.motion()
    np.testing.assert_allclose(processed.acc, -process(vc.trace.copy()).data, atol=1e-12)
    assert "sign reversed" in processed.meta["vertical"]["polarity"]
    # the user may state otherwise
    assert vc.__class__(vc.trace, vc.file, vc.component, vc.alignment, "up").motion(raw=True).acc[k] == (
        pytest.approx(raw[k] * G, rel=1e-6)
    )


def test_an_up_vertical_is_taken_as_read():
    d, v, mates = _set("UP")
    vc = _found(d, v, mates)
    assert vc.polarity.positive == "up" and vc.polarity.source == "name"
    raw = _raw_values(d / v.file)
    up = vc.motion(raw=True)
    k = int(np.argmax(np.abs(raw)))
    assert up.acc[k] == pytest.approx(raw[k] * G, rel=1e-6)
    np.testing.assert_array_equal(up.acc, np.asarray(vc.trace.data, dtype=float))
    assert up.meta["vertical"]["sign"] == 1


def _run(capsys, *argv):
    rc = main([str(a) for a in argv])
    out = capsys.readouterr()
    assert rc == 0, out.err
    return out.out


def test_info_states_the_sense_of_a_vertical_file_and_of_a_records_vertical(capsys):
    d, v, mates = _set("DWN")
    text = _run(capsys, "info", d / v.file)
    line = next(x for x in text.splitlines() if x.startswith("vertical polarity:"))
    assert "positive down" in line and "DWN" in line and "sign reversed" in line
    js = json.loads(_run(capsys, "info", d / v.file, "--json"))
    assert js["vertical"]["positive_in_file"] == "down" and js["vertical"]["sign"] == -1
    # an horizontal file says nothing of a vertical
    assert "vertical" not in json.loads(_run(capsys, "info", d / mates[0].file, "--json"))
    if v.table1_id:  # the recording's row: info --id names its vertical and the sense taken
        js = json.loads(_run(capsys, "info", "--id", v.table1_id, "--records", d, "--json"))
        assert js["vertical"]["component"] == f"{v.file}:DWN" and js["vertical"]["sign"] == -1
        text = _run(capsys, "info", "--id", v.table1_id, "--records", d)
        assert any(x.startswith(f"vertical: {v.file}:DWN, positive down") for x in text.splitlines())


def test_the_engine_receives_the_dwn_vertical_positive_up(capsys, monkeypatch):
    """``simulate --vertical auto``: the vertical handed to the engine is minus the file's samples (raw,
    scale 1), the JSON and the text say so, and ``--vertical-positive up`` hands it as read."""
    import isorock.physics.engine

    d, v, mates = _set("DWN")
    raw = _raw_values(d / v.file) * G
    seen = []
    real = isorock.physics.engine.simulate

    def spy(system, exc, *args, **kw):
        seen.append(np.array(exc.vertical, dtype=float))
        return real(system, exc, *args, **kw)

    monkeypatch.setattr(isorock.physics.engine, "simulate", spy)
    args = ["simulate", "--lambda", 4, "--R", 1.03, "--raw", "--scale", 1, "--record", d / mates[0].file]
    out = json.loads(_run(capsys, *args, "--vertical", "auto", "--json"))
    assert out["vertical"]["sign"] == -1 and out["vertical"]["positive_in_file"] == "down"
    n = min(raw.size, seen[0].size)
    np.testing.assert_allclose(seen[0][:n], -raw[:n], rtol=1e-6, atol=1e-9)
    text = _run(capsys, *args, "--vertical", "auto")
    assert "vertical polarity: positive down in the file" in text
    _run(capsys, *args, "--vertical", "auto", "--vertical-positive", "up", "--json")
    np.testing.assert_allclose(seen[-1][:n], raw[:n], rtol=1e-6, atol=1e-9)


def test_the_issue_34_case_pacoima_dam_164_at_twice_its_scale(capsys):
    """The case of issue 34: lambda 4, R 1.03 m, the 164 component as read, scale 2, its DWN vertical:
    102 impacts and uplift at 0.849 s with the vertical as read, 75 and 0.932 s turned positive up."""
    d, v, mates = _set("DWN")
    h = next((e for e in mates if e.component.strip() == "164"), None)
    if h is None:
        pytest.skip("the DWN vertical's recording has no 164 component in the manifest")
    args = ["simulate", "--lambda", 4, "--R", 1.03, "--raw", "--scale", 2, "--record", d / h.file, "--json"]
    up = json.loads(_run(capsys, *args, "--vertical", "auto"))
    assert up["n_impacts"] == 75 and up["t_uplift_s"] == pytest.approx(0.9316, abs=5e-4)
    as_read = json.loads(_run(capsys, *args, "--vertical", "auto", "--vertical-positive", "up"))
    assert as_read["n_impacts"] == 102 and as_read["t_uplift_s"] == pytest.approx(0.8493, abs=5e-4)


def test_vertical_positive_without_vertical_is_refused(capsys):
    rc = main(["simulate", "--lambda", "4", "--R", "1", "--pulse", "rect", "--td", "0.5", "--pga", "0.5",
               "--vertical-positive", "down"])  # fmt: skip
    assert rc != 0 and "give --vertical too" in capsys.readouterr().err
