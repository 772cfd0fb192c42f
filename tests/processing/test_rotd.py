"""RotD50 and RotD100 (isorock.processing.imt.rotd) against an independent brute-force rotation.

The reference is written apart from the package: for every angle of 0 to 179 degrees the two
horizontals are combined into the motion along it and its peak is taken; PGA on the rotated
acceleration, PGV on its cumulative trapezoid, SA(T) on the response of the 5 %-damped oscillator
computed by :func:`scipy.signal.lsim` (a first-order hold: exact for an input linear between samples,
on a grid four times finer than the record's, with the record followed by zeros for its free
vibration), not by the package's recurrence. The oscillator's response to the rotated motion is checked
to equal the rotated combination of the two responses at a few angles (the linearity the package uses),
and the median and maximum over the angles are compared. Real pairs: every recording of the records
manifest with two horizontals of numeric azimuths 90 degrees apart (at least three needed).
"""

from __future__ import annotations

import math
from collections import defaultdict

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid
from scipy.signal import lsim

from isorock.constants import G
from isorock.physics.excitation import GroundMotion
from isorock.processing.imt import parse_imt, rotd

from ..support.records import manifest, need_records, read_row

MEASURES = ("PGA", "PGV", "SA(1.0)", "SA(0.5)")


def _pairs() -> list[tuple[dict, dict]]:
    """Two rows of one recording (same catalog row, station and format) with azimuths 90 deg apart."""
    by: dict[tuple, list[dict]] = defaultdict(list)
    for r in manifest():
        try:
            float(r["component"])
        except ValueError:
            continue
        by[(r["table1_id"], r["station"], r["format"])].append(r)
    out = []
    for rows in by.values():
        for i in range(len(rows)):
            for j in range(i + 1, len(rows)):
                d = abs(float(rows[i]["component"]) - float(rows[j]["component"])) % 180.0
                if abs(d - 90.0) < 1e-6:
                    out.append((rows[i], rows[j]))
    return out


def _motions(r1: dict, r2: dict) -> tuple[GroundMotion, GroundMotion]:
    t1, t2 = read_row(r1), read_row(r2)
    assert math.isclose(t1.stats.delta, t2.stats.delta)
    n = min(t1.stats.npts, t2.stats.npts)
    dt = float(t1.stats.delta)
    return (
        GroundMotion(dt=dt, acc=np.asarray(t1.data[:n], float), name=r1["file"]),
        GroundMotion(dt=dt, acc=np.asarray(t2.data[:n], float), name=r2["file"]),
    )


def _oscillator(acc: np.ndarray, dt: float, T: float, xi: float = 0.05) -> np.ndarray:
    """Relative displacement [m] of the oscillator under ``acc`` by scipy's lsim, on a 4x finer grid,
    the record followed by zeros for 3 periods (its free vibration)."""
    w = 2.0 * math.pi / T
    pad = np.concatenate([acc, np.zeros(int(math.ceil(3.0 * T / dt)) + 1)])
    t = np.arange(pad.size) * dt
    fine = np.linspace(0.0, t[-1], 4 * (pad.size - 1) + 1)
    u = np.interp(fine, t, pad)
    system = (
        np.array([[0.0, 1.0], [-(w**2), -2.0 * xi * w]]),
        np.array([[0.0], [-1.0]]),
        np.array([[1.0, 0.0]]),
        0.0,
    )
    _, y, _ = lsim(system, u, fine, interp=True)
    return np.asarray(y)


def _series(gm: GroundMotion, name: str) -> tuple[np.ndarray, float]:
    """The series whose peak is the measure, and its factor to the measure's unit."""
    if name == "PGA":
        return gm.acc, 1.0 / G
    if name == "PGV":
        return cumulative_trapezoid(gm.acc, dx=gm.dt, initial=0.0), 100.0
    T = float(name[3:-1])
    return _oscillator(gm.acc, gm.dt, T), (2.0 * math.pi / T) ** 2 / G


def _brute(g1: GroundMotion, g2: GroundMotion, name: str) -> tuple[float, float]:
    x1, f = _series(g1, name)
    x2, _ = _series(g2, name)
    peaks = []
    for deg in range(180):
        th = math.radians(deg)
        peaks.append(f * float(np.max(np.abs(math.cos(th) * x1 + math.sin(th) * x2))))
    return float(np.median(peaks)), float(np.max(peaks))


def test_at_least_three_real_pairs_in_the_manifest():
    need_records()
    assert len(_pairs()) >= 3, [(a["file"], b["file"]) for a, b in _pairs()]


@pytest.mark.parametrize("k", range(3))
def test_rotd50_and_rotd100_equal_a_brute_force_rotation_of_a_real_pair(k):
    need_records()
    r1, r2 = _pairs()[k]
    g1, g2 = _motions(r1, r2)
    got = rotd(g1, g2, [parse_imt(m) for m in MEASURES])
    for m in MEASURES:
        med, top = _brute(g1, g2, m)
        tol = 1e-9 if m in ("PGA", "PGV") else 2e-3  # SA: two integrators, peaks at the grid's points
        assert got["rotd50"][m] == pytest.approx(med, rel=tol), (r1["file"], m)
        assert got["rotd100"][m] == pytest.approx(top, rel=tol), (r1["file"], m)
        assert got["rotd50"][m] <= got["rotd100"][m]


def test_the_response_to_the_rotated_motion_is_the_rotation_of_the_responses():
    need_records()
    g1, g2 = _motions(*_pairs()[0])
    u1, u2 = _oscillator(g1.acc, g1.dt, 1.0), _oscillator(g2.acc, g2.dt, 1.0)
    for deg in (0.0, 37.0, 90.0, 143.0):
        c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        ur = _oscillator(c * g1.acc + s * g2.acc, g1.dt, 1.0)
        assert np.max(np.abs(ur - (c * u1 + s * u2))) <= 1e-9 * np.max(np.abs(ur))


def test_rotd100_of_a_component_and_a_silent_one_is_its_own_peak_and_rotd50_a_cosine_of_it():
    t = np.arange(0.0, 20.0, 0.01)
    a = np.sin(2.0 * math.pi * t) * np.exp(-0.2 * t)
    g1, g2 = GroundMotion(dt=0.01, acc=a, name="a"), GroundMotion(dt=0.01, acc=0.0 * a, name="b")
    got = rotd(g1, g2, [parse_imt("PGA")])
    assert got["rotd100"]["PGA"] == pytest.approx(np.max(np.abs(a)) / G, rel=1e-12)
    # the rotated peaks are |cos theta| PGA at the angles 0, 1, ..., 179 degrees: their median
    expected = np.median(np.abs(np.cos(np.radians(np.arange(180.0)))))
    assert got["rotd50"]["PGA"] == pytest.approx(expected * np.max(np.abs(a)) / G, rel=1e-12)
    assert 0.70 < expected < 0.72
