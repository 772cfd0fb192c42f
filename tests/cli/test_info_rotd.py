"""``isorock info --id``: the RotD50 and RotD100 of the record's two horizontals (JSON keys rotd50,
rotd100: a mapping from the measure's string to its value)."""

from __future__ import annotations

import json
import subprocess
import sys

from ..support.records import need_records


def _info(rid: str, records) -> dict:
    out = subprocess.run(
        [sys.executable, "-m", "isorock.cli", "info", "--id", rid, "--records", str(records), "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout)


def test_info_gives_rotd50_and_rotd100_of_a_pair_and_none_for_one_horizontal():
    d = need_records()
    pair = _info("IMV79-E06", d)  # rotated from its 230 and 140 components
    assert set(pair["rotd50"]) == {"PGA", "PGV", "SA(0.2)", "SA(1.0)", "SA(3.0)"}
    for k, v in pair["rotd50"].items():
        assert 0.0 < v <= pair["rotd100"][k]
    # the analysed (strike-normal) PGA lies between the median and the maximum over orientations
    assert pair["rotd50"]["PGA"] <= pair["pga_g"] <= pair["rotd100"]["PGA"] * (1 + 1e-9)
    assert "230" in pair["rotd_pair"] and "140" in pair["rotd_pair"]
    one = _info("IMV79-E05", d)  # one strike-normal file only
    assert one["rotd50"] == {} and one["rotd100"] == {} and one["rotd_pair"] == ""
