"""The functions that stand in for ObsPy's and scipy's, so that reading and processing a record imports
neither ObsPy's signal package (which loads matplotlib) nor scipy.integrate, give the same samples,
bit for bit: the Butterworth filters of the band-pass step (:func:`isorock.processing.steps._butterworth`
against :mod:`obspy.signal.filter`), the cumulative trapezoid (:func:`isorock.processing.metrics.
cumulative_trapezoid` against :func:`scipy.integrate.cumulative_trapezoid`) and the rotation of two
horizontal components (:func:`isorock.processing.orientation._rotate2zne` against
:func:`obspy.signal.rotate.rotate2zne`). The imports themselves: ``tests/packaging/test_lazy_imports.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from obspy import Trace

from isorock.processing import default_config, orientation, process
from isorock.processing import steps as steps_mod
from isorock.processing.metrics import cumulative_trapezoid

RNG = np.random.default_rng(20261127)


def _same(a: np.ndarray, b: np.ndarray) -> None:
    assert a.dtype == b.dtype and a.shape == b.shape
    assert np.array_equal(a, b), f"largest difference {np.max(np.abs(a - b)):.3g}"


@pytest.mark.parametrize("n", [1, 2, 3, 10, 7720])
@pytest.mark.parametrize("dx", [0.005, 0.01, 0.02, 1.0 / 3.0])
def test_cumulative_trapezoid_is_scipys(n, dx):
    from scipy.integrate import cumulative_trapezoid as scipy_cumtrapz

    y = RNG.normal(size=n)
    _same(cumulative_trapezoid(y, dx=dx, initial=0.0), scipy_cumtrapz(y, dx=dx, initial=0.0))
    k = RNG.integers(-5, 5, size=n)  # integer samples as scipy takes them
    _same(cumulative_trapezoid(k, dx=dx, initial=0.0), scipy_cumtrapz(k, dx=dx, initial=0.0))


def test_cumulative_trapezoid_refuses_as_scipy():
    with pytest.raises(ValueError, match="At least one point"):
        cumulative_trapezoid(np.array([]), dx=0.01)
    with pytest.raises(ValueError, match="initial"):
        cumulative_trapezoid(np.ones(3), dx=0.01, initial=1.0)


def _obspy_filtered(data: np.ndarray, delta: float, kind: str, freqs: tuple, corners: int, zerophase: bool):
    """ObsPy's own: ``Trace.filter`` on a trace of that time step."""
    tr = Trace(data=data.copy(), header={"delta": delta})
    if kind == "bandpass":
        tr.filter(kind, freqmin=freqs[0], freqmax=freqs[1], corners=corners, zerophase=zerophase)
    else:
        tr.filter(kind, freq=freqs[0], corners=corners, zerophase=zerophase)
    return tr.data


FILTERS = [("bandpass", (0.05, 40.0)), ("bandpass", (0.1, 10.0)), ("highpass", (0.05,)), ("lowpass", (5.0,))]


@pytest.mark.parametrize("delta", [0.005, 0.01, 0.02])
@pytest.mark.parametrize(("kind", "freqs"), FILTERS)
@pytest.mark.parametrize("corners", [2, 4])
@pytest.mark.parametrize("zerophase", [True, False])
def test_butterworth_is_obspys(delta, kind, freqs, corners, zerophase):
    nyq = 0.5 / delta
    freqs = tuple(min(f, 0.8 * nyq) for f in freqs)  # the step's Nyquist cap
    data = RNG.normal(size=3001)
    df = Trace(header={"delta": delta}).stats.sampling_rate
    ours = steps_mod._butterworth(data.copy(), df, kind, freqs, corners, zerophase)
    _same(ours, _obspy_filtered(data, delta, kind, freqs, corners, zerophase))


def test_butterworth_refuses_and_warns_as_obspy():
    data = RNG.normal(size=500)
    with pytest.raises(ValueError, match="above Nyquist"):
        steps_mod._butterworth(data, 100.0, "highpass", (60.0,), 4, True)
    with pytest.warns(UserWarning, match="Applying a high-pass instead"):
        ours = steps_mod._butterworth(data.copy(), 100.0, "bandpass", (0.1, 50.0), 4, True)
    with pytest.warns(UserWarning):
        theirs = _obspy_filtered(data, 0.01, "bandpass", (0.1, 50.0), 4, True)
    _same(ours, theirs)


def test_processing_gives_the_samples_and_history_of_obspys_filter(monkeypatch):
    """The whole default processing of a record, with the filter computed by ObsPy and as now."""
    from obspy.signal import filter as obspy_filter

    t = np.arange(6000) * 0.005
    acc = 2.0 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.15 * t) * np.minimum(t, 1.0)
    acc += 0.2 * RNG.normal(size=t.size)
    tr = Trace(data=acc, header={"delta": 0.005, "station": "X"})
    now = process(tr, default_config())

    def by_obspy(data, df, kind, freqs, corners, zerophase):
        f = getattr(obspy_filter, kind)
        if kind == "bandpass":
            return f(data, freqs[0], freqs[1], df=df, corners=corners, zerophase=zerophase)
        return f(data, freqs[0], df=df, corners=corners, zerophase=zerophase)

    monkeypatch.setattr(steps_mod, "_butterworth", by_obspy)
    before = process(tr, default_config())
    _same(now.data, before.data)
    assert list(now.stats.processing) == list(before.stats.processing)


AZIMUTHS = [(270.0, 0.0), (140.0, 230.0), (164.0, 254.0), (22.5, 100.3), (10.0, 350.0)]


@pytest.mark.parametrize(("az1", "az2"), AZIMUTHS)
def test_rotation_is_obspys_rotate2zne(az1, az2):
    from obspy.signal.rotate import rotate2zne

    n = 2000
    x1, x2, z = RNG.normal(size=n), RNG.normal(size=n), np.zeros(n)
    x1[:5] = -0.0  # negative zeros come out as zeros, as ObsPy's do
    ours = orientation._rotate2zne(x1, az1, 0.0, x2, az2, 0.0, z, 0.0, -90.0)
    theirs = rotate2zne(x1, az1, 0.0, x2, az2, 0.0, z, 0.0, -90.0)
    for a, b in zip(ours, theirs, strict=True):
        _same(a, b)
        assert np.array_equal(np.signbit(a), np.signbit(b))


def test_rotation_refuses_parallel_directions_as_obspy():
    n = 10
    with pytest.raises(ValueError, match="not linearly independent"):
        orientation._rotate2zne(np.ones(n), 0.0, 0.0, np.ones(n), 0.0, 0.0, np.zeros(n), 0.0, -90.0)
    with pytest.raises(ValueError, match="same length"):
        orientation._rotate2zne(np.ones(n), 0.0, 0.0, np.ones(n + 1), 90.0, 0.0, np.zeros(n), 0.0, -90.0)
