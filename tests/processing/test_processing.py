"""Record processing steps, QA marks and intensity measures (isorock.processing)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from obspy import Stream, Trace

from isorock.constants import G
from isorock.errors import IsorockError
from isorock.processing import (
    STEPS,
    ProcessingConfig,
    applied_steps,
    bandpass_filter,
    baseline_polynomial,
    check_pga,
    check_tail,
    default_config,
    detrend,
    displacement,
    load_config,
    metrics,
    process,
    qa_passed,
    qa_reasons,
    resample,
    taper,
    velocity,
)
from support.records import manifest_params, read_row

# tolerances of the invariants on the shared records (the task's acceptance limits)
PGA_CHANGE_MAX = 0.03  # relative PGA change by the default processing [-]
FINAL_DISP_MAX = 1e-3  # |final displacement| / PGD after processing [-]
FINAL_VEL_MAX = 1e-3  # |final velocity| / PGV after processing [-]


def _trace(data: np.ndarray, dt: float) -> Trace:
    return Trace(np.asarray(data, dtype=float), header={"delta": dt, "station": "SYN"})


def _bump_acc(t: np.ndarray, tc: float, s: float, amp: float) -> np.ndarray:
    """Acceleration [m/s^2] of the displacement ``amp exp(-((t - tc)/s)^2)`` [m]: starts and ends at rest."""
    x = (t - tc) / s
    return amp * np.exp(-(x**2)) * (4 * x**2 - 2) / s**2


def _quake(dt: float = 0.01, T: float = 30.0, seed: int = 1, offset: float = 0.02) -> Trace:
    """A synthetic accelerogram [m/s^2]: enveloped noise plus a 2 s pulse, with a baseline offset."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, T, dt)
    env = (t / 4.0) ** 2 * np.exp(-t / 4.0 * 2) * 4
    a = 2.0 * env * rng.normal(size=t.size)
    a += _bump_acc(t, 7.0, 0.8, 0.3)
    a += offset  # baseline error [m/s^2]: 0.02 alone gives 9 m of displacement at 30 s
    return _trace(a, dt)


# ----------------------------------------------------------------------------- invariants on the real records


@pytest.mark.parametrize("row", manifest_params())
def test_processing_keeps_pga_and_ends_at_rest(row):
    raw = read_row(row)
    out = process(raw)
    m0, m = metrics(raw), metrics(out)
    assert out.stats.npts == raw.stats.npts
    assert out.stats.delta == raw.stats.delta
    assert abs(m["pga_m_s2"] / m0["pga_m_s2"] - 1.0) < PGA_CHANGE_MAX, (m0["pga_g"], m["pga_g"])
    assert abs(m["final_disp_m"]) <= FINAL_DISP_MAX * m["pgd_m"], (m["final_disp_m"], m["pgd_m"])
    v = velocity(out)
    assert abs(v[-1]) <= FINAL_VEL_MAX * m["pgv_m_s"]
    # the raw record is untouched
    assert np.array_equal(raw.data, read_row(row).data)
    # every configured step is recorded once, in order, with its line in the history
    steps = applied_steps(out)
    assert [s.step for s in steps] == [s.name for s in default_config().steps]
    assert [s.line() for s in steps] == [h for h in out.stats.processing if h.startswith("isorock ")]


@pytest.mark.parametrize("row", manifest_params(only_table1=True))
def test_table1_records_pass_qa(row):
    out = process(read_row(row))
    assert qa_passed(out), qa_reasons(out)


# ----------------------------------------------------------------------------- single steps


def test_each_step_appends_one_history_line():
    tr = _quake()
    for name, kwargs in [
        ("detrend", {}),
        ("taper", {}),
        ("bandpass_filter", {}),
        ("baseline_polynomial", {}),
        ("check_tail", {}),
        ("check_pga", {}),
        ("resample", {"dt": 0.02}),
    ]:
        n = len(tr.stats.get("processing", []))
        STEPS[name](tr, **kwargs)
        hist = tr.stats.processing
        assert len(hist) == n + 1, (name, hist[n:])
        assert hist[-1].startswith("isorock") and f": {name}(" in hist[-1]


def test_detrend_removes_line():
    t = np.arange(1000) * 0.01
    tr = detrend(_trace(0.3 + 0.05 * t, 0.01), type="linear")
    assert np.max(np.abs(tr.data)) < 1e-12
    with pytest.raises(IsorockError, match="detrend"):
        detrend(_trace(t, 0.01), type="quadratic")


def test_taper_only_touches_the_ends():
    tr = taper(_trace(np.ones(1000), 0.01), max_percentage=0.05)
    assert tr.data[0] == pytest.approx(0.0, abs=1e-12)
    assert tr.data[-1] == pytest.approx(0.0, abs=1e-12)
    assert np.all(tr.data[60:940] == 1.0)
    assert np.all(np.diff(tr.data[:50]) >= 0)


def test_bandpass_is_zero_phase_and_keeps_the_passband():
    dt = 0.01
    t = np.arange(0, 60, dt)
    burst = np.exp(-(((t - 30) / 2.0) ** 2)) * np.sin(2 * np.pi * 1.0 * t)  # 1 Hz, in the passband
    slow = 0.5 * np.sin(np.pi * t / 60.0)  # half cycle over the record: 0.008 Hz, far below 0.05 Hz
    tr = bandpass_filter(_trace(burst + slow, dt), freqmin=0.05, freqmax=3.0, corners=4)
    inner = (t > 10) & (t < 50)
    assert np.max(np.abs(tr.data - burst)[inner]) < 0.01
    # zero phase: the filtered burst is not delayed (a causal filter delays it by several samples)
    lags = np.arange(-20, 21)
    xc = [np.dot(tr.data[inner], np.roll(burst, k)[inner]) for k in lags]
    assert lags[int(np.argmax(xc))] == 0
    causal = bandpass_filter(_trace(burst + slow, dt), freqmin=0.05, freqmax=3.0, corners=4, zerophase=False)
    xc = [np.dot(causal.data[inner], np.roll(burst, k)[inner]) for k in lags]
    assert lags[int(np.argmax(xc))] > 0


def test_bandpass_caps_the_high_corner_below_nyquist():
    tr = bandpass_filter(_quake(dt=0.02), freqmin=0.1, freqmax=40.0, max_nyquist_fraction=0.8)
    assert "freqmax=20" in tr.stats.processing[-1]  # 0.8 * 25 Hz
    with pytest.raises(IsorockError, match="not above"):
        bandpass_filter(_quake(dt=0.02), freqmin=30.0, freqmax=40.0)
    with pytest.raises(IsorockError):
        bandpass_filter(_quake(), freqmin=None, freqmax=None)


def test_baseline_removes_a_constant_acceleration_offset():
    dt = 0.01
    t = np.arange(0, 20, dt)
    sig = _bump_acc(t, 8.0, 1.0, 0.2)  # starts and ends at rest
    tr = baseline_polynomial(_trace(sig + 0.01, dt), order=6)  # the offset alone: 2 m at 20 s
    assert abs(displacement(tr)[-1]) < 1e-4  # trapezoid vs analytic derivative: O(dt^2)
    assert abs(velocity(tr)[-1]) < 1e-5
    assert np.max(np.abs(tr.data - sig)) < 0.02  # the correction is the slow offset, not the signal


def test_baseline_without_end_constraints_is_plain_least_squares():
    dt = 0.01
    t = np.arange(0, 20, dt)
    tr = baseline_polynomial(_trace(0.01 + 0.0 * t, dt), order=6, end_constraints=False)
    # a constant acceleration gives d = 0.005 t^2: exactly a polynomial of the basis
    assert np.max(np.abs(tr.data)) < 1e-9
    with pytest.raises(IsorockError, match="order"):
        baseline_polynomial(_trace(t, dt), order=2)


@pytest.mark.parametrize("method", ["lanczos", "fft"])
def test_resample_keeps_a_smooth_signal(method):
    dt = 0.01
    t = np.arange(0, 20, dt)
    f = lambda tt: np.sin(2 * np.pi * 0.7 * tt) * np.sin(np.pi * tt / 20) ** 2  # noqa: E731
    tr = resample(_trace(f(t), dt), dt=0.005, method=method)
    assert tr.stats.delta == 0.005
    t2 = np.arange(tr.stats.npts) * 0.005
    inner = (t2 > 1) & (t2 < 19)
    assert np.max(np.abs(tr.data[inner] - f(t2[inner]))) < 1e-3
    assert resample(_trace(f(t), dt), dt=None).stats.npts == t.size


def test_check_pga_marks_wrong_units_without_raising():
    tr = _quake()
    tr.data = tr.data * 100.0  # cm/s^2 read as m/s^2
    out = process(tr)
    assert not qa_passed(out)
    assert any("check_pga" in r and "wrong units" in r for r in qa_reasons(out))
    ok = process(_quake())
    assert qa_passed(ok), qa_reasons(ok)


def test_check_tail_marks_a_record_that_does_not_end_at_rest():
    dt = 0.01
    t = np.arange(0, 30, dt)
    a = np.where((t > 28.0), 1.0, 0.0) + np.where((t > 2) & (t < 3), 1.0, 0.0)  # velocity step at the end
    tr = check_tail(_trace(a, dt), duration=5.0)
    assert not qa_passed(tr)
    assert any("velocity" in r for r in qa_reasons(tr))
    assert qa_passed(check_tail(_trace(_bump_acc(t, 8.0, 1.0, 0.2), dt)))


def test_check_pga_range():
    assert not qa_passed(check_pga(_trace(np.full(100, 6.0 * G), 0.01)))
    assert not qa_passed(check_pga(_trace(np.full(100, 1e-5 * G), 0.01)))
    assert qa_passed(check_pga(_trace(np.full(100, 0.3 * G), 0.01)))


# ----------------------------------------------------------------------------- configuration


def test_default_config_is_the_packaged_yaml():
    cfg = default_config()
    names = [s.name for s in cfg.steps]
    assert names[0] == "check_pga" and "bandpass_filter" in names and "baseline_polynomial" in names
    filt = next(s for s in cfg.steps if s.name == "bandpass_filter")
    assert filt.params["zerophase"] is True and filt.params["pad"] is True
    assert ProcessingConfig.from_obj(cfg.to_obj()) == cfg


def test_config_from_yaml_file_and_errors(tmp_path):
    p = tmp_path / "proc.yaml"
    p.write_text(
        yaml.safe_dump(
            {"processing": [{"detrend": {"type": "demean"}}, "check_pga", {"resample": {"dt": 0.02}}]}
        )
    )
    cfg = load_config(p)
    assert [s.name for s in cfg.steps] == ["detrend", "check_pga", "resample"]
    out = process(_quake(), p)
    assert out.stats.delta == 0.02
    with pytest.raises(IsorockError, match="unknown"):
        ProcessingConfig.from_obj({"processing": [{"smooth": {}}]})
    with pytest.raises(IsorockError, match="unknown parameter"):
        ProcessingConfig.from_obj([{"taper": {"percentage": 0.1}}])
    with pytest.raises(IsorockError, match="processing"):
        ProcessingConfig.from_obj({"steps": []})
    bad = tmp_path / "bad.yaml"
    bad.write_text("processing: [detrend: {type: linear}\n")
    with pytest.raises(IsorockError, match="YAML"):
        load_config(bad)


def test_with_step_overrides_parameters():
    cfg = default_config().with_step("resample", dt=0.02)
    assert next(s for s in cfg.steps if s.name == "resample").params["dt"] == 0.02
    assert process(_quake(), cfg).stats.delta == 0.02


def test_process_stream_and_copy():
    tr = _quake()
    before = tr.data.copy()
    st = process(Stream([tr, _quake(seed=2)]))
    assert isinstance(st, Stream) and len(st) == 2
    assert np.array_equal(tr.data, before)
    with pytest.raises(IsorockError):
        process(np.zeros(10))  # type: ignore[arg-type]


def test_process_removes_the_baseline_error_of_a_synthetic_record():
    raw = _quake(offset=0.02)
    clean = process(_quake(offset=0.0))
    out = process(raw)
    assert abs(displacement(raw)[-1] - displacement(_quake(offset=0.0))[-1]) > 8.0  # the offset's 9 m
    m = metrics(out)
    assert abs(m["final_disp_m"]) < FINAL_DISP_MAX * m["pgd_m"]
    # the processed velocity does not depend on the baseline error
    assert np.max(np.abs(velocity(out) - velocity(clean))) < 0.02 * metrics(clean)["pgv_m_s"]


# ----------------------------------------------------------------------------- metrics


def test_metrics_of_a_sine():
    dt, A, T, n = 0.001, 2.0, 0.5, 10  # 10 full cycles of a 0.5 s sine of 2 m/s^2
    t = np.arange(0, n * T + dt / 2, dt)
    m = metrics(_trace(A * np.sin(2 * np.pi * t / T), dt))
    assert m["pga_m_s2"] == pytest.approx(A, rel=1e-4)
    assert m["pga_g"] == pytest.approx(A / G, rel=1e-4)
    assert m["pgv_m_s"] == pytest.approx(A * T / math.pi, rel=1e-4)  # v = A T/(2 pi) (1 - cos)
    assert m["pgd_m"] == pytest.approx(A * T / (2 * math.pi) * n * T, rel=1e-3)  # drift of the mean velocity
    assert m["arias_m_s"] == pytest.approx(math.pi / (2 * G) * A**2 * n * T / 2, rel=1e-4)
    assert m["d5_95_s"] == pytest.approx(0.9 * n * T, abs=T / 4)
    assert m["npts"] == t.size and m["dt_s"] == dt
