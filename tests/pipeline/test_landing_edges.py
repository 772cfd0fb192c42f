"""The landing page's minimum-overturning paragraph copes with what the runs produced (issue 32, item 3):
a block that never overturns on any record, here R = 5 m beside R = 1 m, once raised ``KeyError: 5.0``
in ``landing._overturn_section`` and left no report."""

from __future__ import annotations

import math

import pandas as pd

from isorock.report.landing import _overturn_section


def _rows(R: float, overturns: bool) -> list[dict]:
    return [
        {"record": "r0", "case": c, "isolation": c, "lambda_": 4.0, "R_m": R, "h_m": R / math.sqrt(17) * 4,
         "record_pga_g": 0.35, "min_overturn_g": (0.3 if c == "none" else 0.4) if overturns else math.nan}
        for c in ("none", "linear")
    ]  # fmt: skip


def test_a_block_that_never_overturns_gets_its_line():
    ovt = pd.DataFrame(_rows(1.0, True) + _rows(5.0, False))
    section = _overturn_section(ovt, 10)
    assert len(section.bullets) == 2
    assert section.bullets[1].startswith("R 5 m") and "ground 0" in section.bullets[1]
    assert "(+33 %)" in section.bullets[0]  # 0.4 g on the isolator against 0.3 g on the ground
