"""Reading the files of a record: the horizontal components of one file, raw, with their azimuths, and
whether two components of one recording are time-aligned (:func:`check_alignment`) before a rotation."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from obspy import Trace

from isorock.io import read_record, read_trace, trace_component
from isorock.records.naming import is_vertical, parse_azimuth
from isorock.records.spec import RecordFile

__all__ = [
    "PAIR_MAX_LAG_S",
    "PAIR_MIN_DEG",
    "read_horizontals",
    "azimuth_of",
    "Alignment",
    "check_alignment",
]

#: two components are rotated only if their azimuths are at least this far from parallel [deg]
PAIR_MIN_DEG = 60.0


#: two files of one recording: lengths within this fraction
_PAIR_NPTS_RTOL = 0.005


#: two files of one recording: their energy envelopes peak together within this lag [s] ...
PAIR_MAX_LAG_S = 1.0


#: ... or their zero-lag correlation is at least this fraction of the best one [-]
_PAIR_ZERO_LAG_FRACTION = 0.8


#: two files of one recording: their energy envelopes correlate at least this well [-]
_PAIR_MIN_ENVELOPE_CORR = 0.5


#: moving-average window of the energy envelopes compared [s]
_ENVELOPE_S = 1.0


@dataclass(frozen=True)
class Alignment:
    """Whether two horizontal components are time-aligned (see :func:`check_alignment`).

    Attributes
    ----------
    ok : bool
        They may be rotated together.
    problem : str
        Why not, in words ("" when ``ok``).
    lag_s : float or None
        Lag [s] at which the energy envelopes of the two correlate best; positive when the energy of
        the second arrives later (None when not measured: one file, or refused before).
    envelope_corr : float or None
        That correlation [-] (1: the envelopes are the same function of time).
    npts : tuple of int
        Number of samples of each.
    """

    ok: bool
    problem: str = ""
    lag_s: float | None = None
    envelope_corr: float | None = None
    npts: tuple[int, int] = (0, 0)

    def describe(self) -> str:
        """``"time-aligned (energy envelopes peak 0.50 s apart, correlation 0.94)"``."""
        if not self.ok:
            return f"not time-aligned: {self.problem}"
        if self.lag_s is None:
            return "time-aligned (one file, one time column)"
        return (
            f"time-aligned (energy envelopes peak {abs(self.lag_s):.2f} s apart, "
            f"correlation {self.envelope_corr:.2f})"
        )


def _stated_start(tr: Trace) -> float | None:
    """The start [s, epoch] a file states (an absolute start time, or the first value of a time
    column), or None when the format states none (ObsPy's default start and no time column)."""
    t0 = tr.stats.get("isorock", {}).get("t0")
    start = float(tr.stats.starttime.timestamp)
    if t0 is None and start == 0.0:
        return None
    return start + float(t0 or 0.0)


def _envelope(x: Any, dt: float) -> Any:
    """Energy envelope [(m/s^2)^2]: the squared, linearly detrended signal averaged over
    :data:`_ENVELOPE_S`."""
    import numpy as np
    from scipy.signal import detrend

    a = detrend(np.asarray(x, dtype=float), type="linear")
    k = max(1, int(round(_ENVELOPE_S / dt)))
    return np.convolve(a * a, np.ones(k) / k, mode="same")


def check_alignment(
    tr1: Trace,
    tr2: Trace,
    *,
    one_file: bool = False,
    envelopes: bool = True,
    length_rtol: float | None = None,
) -> Alignment:
    """Whether two horizontal components of one recording are time-aligned sample for sample.

    A rotation combines the two sample by sample, so sample ``k`` of both must be the same instant.
    Two components of one file (the N-S and E-W columns of a BBP file) share its time column and are
    aligned by construction. Two files carry no common clock (most formats state no start time), so
    the check uses what they state and what the motion itself shows:

    1. the same time step (to 1e-6);
    2. the same start, when both formats state one (an absolute start time, or the first value of a
       time column), within half a time step;
    3. lengths within 0.5 % (two files of one recording are cut alike; a longer trailer is allowed,
       the rotation stops at the shorter one);
    4. the energy envelopes agree without a shift: the normalised cross-correlation of the squared,
       linearly detrended accelerations averaged over 1 s (:data:`_ENVELOPE_S`) reaches at least
       0.5 (else the two are not one recording), and it peaks within :data:`PAIR_MAX_LAG_S` (1 s) of
       zero lag, or its zero-lag value is at least 0.8 of its peak. A pair is refused only when a
       shift of more than 1 s makes the envelopes agree clearly better.

    Why the envelopes and not the signed traces: two horizontal components are projections of one
    motion on two directions; their signed cross-correlation depends on the polarisation (near zero
    for a motion along one of them, a quarter period off for an elliptical one), so where it peaks
    says little about alignment (on the pairs of the shared records it peaks anywhere from -1.8 s to
    +0.6 s). Their energy rises and falls with the arrival of the wave groups whatever the
    polarisation, and a shift of one file moves the envelope peak by the shift. Measured on the
    shared records: the two-file pairs peak within 0.65 s of zero lag, at zero-lag values of at
    least 0.88 of the peak (correlations 0.89-0.97); the N-S and E-W columns of one BBP file
    (Sylmar Converter Station East), aligned by their time column, peak 2.9 s apart, at a zero-lag
    value of 0.86 of the peak: the natural difference can exceed 1 s (hence the second condition);
    a 2 s shift of any of these pairs drops the zero-lag value below 0.75 of a peak moved by the
    shift. Shifts of about 2 s or more are thus detected; shifts under about 1 s cannot be told from
    the natural difference between two directions of one motion and are not.

    Parameters
    ----------
    tr1, tr2 : obspy.Trace
        The two components (acceleration, any units; raw or processed).
    one_file : bool
        Both come from one file with one time column: items 1 and 3 are checked, not 2 and 4.
    envelopes : bool
        Judge item 4. False for a vertical beside a horizontal: its energy arrives with the P waves,
        before the S waves that carry most of the horizontal energy (measured: 1.2 s on El Centro 1940
        UP against 180, 1.5 s on the U-D and N-S columns of the Jensen BBP file, which share one time
        column), so the envelopes' lag is measured and reported but tells nothing of the alignment.
    length_rtol : float, optional
        The largest relative difference of the lengths (default 0.5 %, item 3).

    Returns
    -------
    Alignment
        ``ok``, the ``problem`` in words, the envelope lag [s] and correlation [-] (None for
        ``one_file``).
    """
    d1, d2 = float(tr1.stats.delta), float(tr2.stats.delta)
    n1, n2 = int(tr1.stats.npts), int(tr2.stats.npts)
    npts = (n1, n2)
    if not math.isclose(d1, d2, rel_tol=1e-6):
        return Alignment(False, f"time steps differ ({d1:g} and {d2:g} s)", npts=npts)
    rtol = _PAIR_NPTS_RTOL if length_rtol is None else length_rtol
    if abs(n1 - n2) > rtol * max(n1, n2):
        why = (
            f"lengths differ by {abs(n1 - n2)} samples ({abs(n1 - n2) / max(n1, n2):.1%}, at most {rtol:.1%})"
        )
        return Alignment(False, why, npts=npts)
    if one_file:
        return Alignment(True, npts=npts)
    s1, s2 = _stated_start(tr1), _stated_start(tr2)
    if s1 is not None and s2 is not None and abs(s2 - s1) > 0.5 * d1:
        return Alignment(False, f"their files state starts {s2 - s1:+.3f} s apart", npts=npts)
    lag, corr, corr0 = _envelope_lag(tr1, tr2)
    if corr is None:
        return Alignment(False, "a component is constant", npts=npts)
    if not envelopes:
        return Alignment(True, "", lag, corr, npts)
    if corr < _PAIR_MIN_ENVELOPE_CORR:
        why = f"their energy envelopes do not correlate (at most {corr:.2f}): not one recording?"
        return Alignment(False, why, lag, corr, npts)
    if abs(lag) > PAIR_MAX_LAG_S and corr0 < _PAIR_ZERO_LAG_FRACTION * corr:
        why = (
            f"the energy of the second arrives {abs(lag):.2f} s {'after' if lag > 0 else 'before'} that "
            f"of the first (energy envelopes correlate at {corr:.2f} with that shift, {corr0:.2f} without)"
        )
        return Alignment(False, why, lag, corr, npts)
    return Alignment(True, "", lag, corr, npts)


def _envelope_lag(tr1: Trace, tr2: Trace) -> tuple[float, float | None, float]:
    """Lag [s] of the peak of the normalised cross-correlation of the energy envelopes of two traces
    of one time step (positive: the second later), that peak and the zero-lag value [-]."""
    import numpy as np
    from scipy.signal import correlate, correlation_lags

    dt = float(tr1.stats.delta)
    n = max(tr1.stats.npts, tr2.stats.npts)
    e1, e2 = (np.pad(_envelope(t.data, dt), (0, n - t.stats.npts)) for t in (tr1, tr2))
    e1, e2 = e1 - e1.mean(), e2 - e2.mean()
    norm = math.sqrt(float(np.dot(e1, e1)) * float(np.dot(e2, e2)))
    if norm == 0.0:
        return 0.0, None, 0.0
    c = correlate(e2, e1, mode="full") / norm
    lags = correlation_lags(n, n, mode="full")
    k = int(np.argmax(c))
    return float(lags[k]) * dt, float(c[k]), float(c[lags == 0][0])


def read_horizontals(f: RecordFile) -> list[Trace]:
    """The horizontal components of one file, raw [m/s^2]: all of a multi-component file (BBP),
    whichever column its manifest row names."""
    if f.format in (None, "bbp"):
        st = read_record(f.path, f.format, dt=f.dt_s, units=f.units)
        traces = [tr for tr in st if not is_vertical(trace_component(tr))]
        if len(traces) > 1:
            return traces
    return [read_trace(f.path, f.format, dt=f.dt_s, units=f.units, component=f.component)]


def azimuth_of(f: RecordFile, tr: Trace, single: bool) -> float | None:
    name = trace_component(tr)
    if single and f.azimuth_deg is not None:
        return float(f.azimuth_deg) % 360.0
    az = parse_azimuth(name)
    if az is None and single:
        az = parse_azimuth(f.component_name)
    return az
