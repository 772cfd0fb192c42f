"""The cluster simulation of benchmarks/scaling.py (docs/scaling.md) on job graphs small enough to
schedule by hand."""

from __future__ import annotations

import sys

import pytest

from support.records import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
from scaling import Job, grouped, simulate, width  # noqa: E402


def _chain_and_fan() -> list[Job]:
    # a (10 s) -> b (5 s) and c (5 s), 1 thread each; d (20 s, 2 threads) on its own
    return [
        Job("process_record", "a", 10.0, 100.0, 1, "a"),
        Job("extract_pulse", "b", 5.0, 100.0, 1, "a", [0]),
        Job("min_overturn", "c", 5.0, 100.0, 1, "a", [0]),
        Job("pulse_maps", "d", 20.0, 100.0, 2),
    ]


@pytest.mark.parametrize(
    ("cpus", "overhead", "expected"),
    [
        (1, 0.0, 40.0),  # d runs alone on 1 CPU (its 2 threads capped), then a, b, c one after another
        (2, 0.0, 35.0),  # d (critical, 20 s) holds both CPUs, then a, then b and c side by side: 20 + 10 + 5
        (3, 0.0, 20.0),  # d on two CPUs while a then b, c share the third: 20 vs 10 + 5 + 5
        (4, 0.0, 20.0),  # d alone is the longest path
        (4, 2.0, 22.0),  # every job pays 2 s: d 22 s; a, b 12 + 7 = 19 s
    ],
)
def test_simulated_makespan(cpus, overhead, expected):
    assert simulate(_chain_and_fan(), cpus, overhead) == pytest.approx(expected)


def test_width_and_groups():
    jobs = _chain_and_fan()
    assert width(jobs) == 3  # b, c and d at once
    jobs.append(Job("merge", "merge", 1.0, 100.0, 1, None, [0, 1, 2, 3]))
    jobs.append(Job("figures", "figures", 2.0, 100.0, 1, None, [4]))
    jobs.append(Job("report_tables", "report_tables", 3.0, 100.0, 1, None, [4, 5]))
    g = grouped(jobs, cpus=8)
    # one record group (a, b, c on 2 CPUs: 10 + 5), the pulse group (d on 2 CPUs: 20), the end (1 + 2 + 3)
    assert [(j.key, j.seconds, j.threads) for j in g] == [
        ("record-0", 15.0, 2),
        ("pulses", 20.0, 2),
        ("final", 6.0, 1),
    ]
    assert simulate(g, 4) == pytest.approx(26.0)
