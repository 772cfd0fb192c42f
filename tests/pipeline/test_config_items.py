"""Bad input as a user makes it, each refused in one line or read as meant (issue 32, items 7 and 9,
in part): a key given twice in a YAML configuration, an object name of any length, a manifest saved
with a byte-order mark."""

from __future__ import annotations

import pytest

from isorock.errors import CatalogError, ConfigError
from isorock.pipeline import load_config, validate_config
from isorock.records.manifest import read_manifest


def test_a_key_given_twice_is_refused_naming_the_line(tmp_path):
    f = tmp_path / "twice.yaml"
    f.write_text("isolation:\n  rho: 0.5\n  rho: 5.0\n")
    with pytest.raises(ConfigError) as e:
        load_config(f)
    msg = str(e.value)
    assert msg == f"{f}:line 3: the key 'rho' is given twice (the last one would win silently): keep one"
    assert "\n" not in msg


def test_a_key_once_in_each_mapping_is_no_repeat(tmp_path):
    f = tmp_path / "ok.yaml"
    f.write_text("isolation:\n  rho: 0.5\nsearch:\n  rtol: 0.01\n")
    assert load_config(f)["isolation"]["rho"] == 0.5


def test_a_huge_object_name_is_refused_before_anything_runs():
    """A 10 MB name once passed validation and hung Snakemake's DAG building."""
    obj = {"name": "s" * 10_000_000, "height_m": 1.8, "width_m": 0.5, "friction": 0.5}
    cfg = {"studies": [], "assessment": {"objects": [obj], "cases": ["none"], "stripes_g": [0.1, 0.2]}}
    with pytest.raises(ConfigError, match="a string of 10,000,000 characters") as e:
        load_config(cfg)
    assert "assessment.objects.0.name" in str(e.value) and len(str(e.value)) < 300


def test_a_manifest_with_a_byte_order_mark_is_read(tmp_path):
    """A spreadsheet saves UTF-8 with a BOM: it was refused with "missing columns ['file']"."""
    (tmp_path / "a.txt").write_text("0.0\n0.1\n0.0\n")
    text = (
        "file,table1_id,id,event,station,component,azimuth_deg,format,units,dt_s,column,note,sha256\n"
        "a.txt,,MINE-1,,,,,one-column,g,0.01,,,\n"
    )
    (tmp_path / "manifest.csv").write_bytes(b"\xef\xbb\xbf" + text.encode())
    (entry,) = read_manifest(tmp_path / "manifest.csv")
    assert entry.file == "a.txt" and entry.id == "MINE-1"


def test_one_file_under_two_spellings_is_one_file(tmp_path):
    """ "good.AT2" and "./good.AT2" under two ids counted as two records."""
    (tmp_path / "a.txt").write_text("0.0\n0.1\n0.0\n")
    head = "file,table1_id,id,event,station,component,azimuth_deg,format,units,dt_s,column,note,sha256\n"
    rows = "a.txt,,A1,,,,,one-column,g,0.01,,,\n./a.txt,,A2,,,,,one-column,g,0.01,,,\n"
    (tmp_path / "manifest.csv").write_text(head + rows)
    with pytest.raises(CatalogError, match=r"file './a.txt' listed twice \(first on line 2\)"):
        read_manifest(tmp_path / "manifest.csv")


def test_a_huge_string_anywhere_is_refused_by_its_length():
    from isorock.control.bounds import MAX_STRING

    for cfg, where in (
        ({"records": {"dir": "d" * (MAX_STRING + 1)}}, "records.dir"),
        ({"records": {"select": ["ok", "s" * 10_000_000]}}, "records.select.1"),
    ):
        with pytest.raises(ConfigError) as e:
            validate_config(cfg)
        msg = str(e.value)
        assert msg.startswith(f"configuration: {where}: a string of ") and len(msg) < 200, msg[:300]


def _assessment(**kw) -> dict:
    obj = {"name": "s", "height_m": 1.8, "width_m": 0.5, "friction": 0.5}
    return {"studies": [], "assessment": {"objects": [obj], "cases": ["none"], **kw}}


def test_levels_are_in_the_unit_of_the_measure():
    """PGV stripes are in cm/s (as the hazard models give PGV): 50 cm/s is a level, 50 g is not."""
    cfg = load_config(_assessment(imt="PGV", stripes_g=[10, 50, 120], design_g=[50], mce_g=[100]))
    assert cfg["assessment"]["stripes_g"] == [10, 50, 120]
    with pytest.raises(ConfigError, match=r"assessment.stripes_g: 50 g is beyond 10 g, the range of PGA"):
        load_config(_assessment(stripes_g=[10, 50], design_g=[10], mce_g=[10]))
    with pytest.raises(ConfigError, match=r"assessment.mce_g.0: 1200 is out of range"):
        load_config(_assessment(imt="PGV", stripes_g=[10, 50], design_g=[10], mce_g=[1200]))
    with pytest.raises(ConfigError, match=r"assessment.imt: 'SA' is not an intensity measure"):
        load_config(_assessment(imt="SA", stripes_g=[0.1, 0.2], design_g=[0.1], mce_g=[0.2]))
