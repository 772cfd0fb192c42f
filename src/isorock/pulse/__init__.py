"""Velocity-pulse period of a near-fault record: wavelet (db4), Mavroeidis-Papageorgiou and
Bray-Rodriguez-Marek methods.

Three estimates of the pulse period ``Tp`` of a ground-velocity history, one per definition found
in the literature (a published ``Tp`` should be compared with the estimate of its own definition):

**Wavelet method** (Baker 2007; the pulse extraction of Shahi & Baker 2014).
The continuous wavelet transform (CWT) of the velocity ``v_k`` with the Daubechies-4
mother wavelet ``psi`` is, for a scale ``a`` [samples] and a position ``b`` [sample],
``C(a, b) = a^(-1/2) sum_k v_k psi((k - b)/a + x_c)``, with ``x_c = 3.5`` the middle of
the support [0, 7] of db4 (so ``b`` is where the wavelet is centred). PyWavelets'
``cwt`` only takes continuous wavelets, so the transform is built here from
``pywt.Wavelet("db4").wavefun``: the wavelet function is interpolated at each scale
and correlated with the signal by FFT. The pseudo-period of scale ``a`` is
``a dt / f_c`` with ``f_c = pywt.central_frequency("db4") = 0.714`` (MATLAB's
``scal2frq``). Steps:

1. CWT over scales whose pseudo-periods cover ``tp_min`` to ``tp_max`` (0.25-15 s),
   log-spaced; the largest ``|C|`` picks the pulse scale and position; the scale is then
   refined on a fine grid between the neighbouring scales (Shahi & Baker zoom in the
   same way), keeping the position within ``0.4 a`` samples;
2. the pulse is built from up to ``n_wavelets`` (10) wavelets at that scale: at each
   iteration the CWT of the residual (record minus pulse so far) is computed at the
   pulse scale, its largest ``|C|`` within ``0.4 a`` samples of the first position is
   taken, and ``C psi((k - b)/a + x_c) / sqrt(a)`` is added to the pulse;
3. ``Tp`` is the pseudo-period of the pulse scale;
4. classification (Baker 2007): pulse indicator
   ``PI = 1 / (1 + exp(-23.3 + 14.6 PGV_ratio + 20.5 energy_ratio))`` with
   ``PGV_ratio = PGV(residual) / PGV(record)`` and ``energy_ratio`` the same ratio of
   ``sum v^2`` (cumulative squared velocity; equal to the sum of squared DWT
   coefficients Baker uses, by Parseval); the record is pulse-like when ``PI > 0.85``,
   the pulse arrives early and ``PGV >= 0.30 m/s`` (Baker's three criteria).
   Early arrival: the pulse reaches 10 % of its cumulative squared velocity before the
   record reaches 20 % of its own, ``t10%,pulse < t20%,orig`` (a late pulse is one that
   starts after a fifth of the record's energy has passed).

**Mavroeidis-Papageorgiou (2003) model** (MP), fitted by least squares
(:func:`scipy.optimize.least_squares`, :func:`fit_mp`)::

    v(t) = A/2 [1 + cos(2 pi fp (t - t0) / gamma)] cos(2 pi fp (t - t0) + nu)
           for |t - t0| <= gamma / (2 fp), zero otherwise,

so that ``Tp_mp = 1 / fp``. MP (2003) chose the parameters so that the model matches the
recorded velocity *and displacement* waveforms of the pulse; the fit here does the same
in the least-squares sense, by these general rules (the same for every record):

* fit window: centred on the energy centroid of the extracted wavelet pulse, of total
  length ``gamma_max * Tp_wavelet`` (the support of the widest admissible MP pulse at the
  wavelet period: 3 ``Tp_wavelet`` for ``gamma_max = 3``);
* misfit: velocity residual divided by the largest ``|v|`` in the window, and displacement
  residual (record and model displacement each taken about its mean over the window, so
  that the displacement level at the window start does not matter) divided by the largest
  ``|d - mean(d)|`` in the window, both with equal weight;
* bounds: ``1 <= gamma <= 3`` (MP require ``gamma > 1``; the upper bound keeps the model
  to about one and a half cycles, the directivity pulse MP describe; with a larger
  ``gamma`` the model absorbs neighbouring cycles that are not part of it), ``nu`` free,
  ``fp`` within a factor 2 of ``1 / Tp_wavelet``, ``t0`` inside the window,
  ``0 <= A <= 3 max|v|``;
* multi-start: 672 trial pulses (8 phases, 4 values of ``gamma``, 7 frequencies from 0.6
  to 1.5 times ``1 / Tp_wavelet``, 3 times); the 2 best of each frequency are refined by
  least squares and the best fit is kept;
* fit quality: RMS of the velocity and of the displacement misfit over the RMS of the
  record, in the window (``mp_rms_ratio``, ``mp_disp_rms_ratio``).

``PulseConfig(mp_displacement=False)`` fits the velocity only. On 60 synthetic records (MP
pulses, 0.6-8 s, ``1.2 <= gamma <= 3``, plus omega-square stochastic motion of 30-90 % of
the pulse PGV, processed like real records) both criteria recover ``1 / fp`` with a median
error of 3 %; the displacement term gives a heavier tail (90th percentile of the error 22 %
against 13 %): it lengthens the period when long-period motion outside the pulse dominates
the displacement in the window (``python benchmarks/tp_table.py --synthetic 60``). The
joint fit is the default because it is what MP did.

**Bray & Rodriguez-Marek (2004) pulse period** ``Tv`` (:func:`tp_bray_rodriguez_marek`):
the period of the velocity pulse of largest amplitude, measured on the velocity history
itself: twice the time between the zero crossings that bracket the PGV (the duration of
the half-cycle holding the PGV, linearly interpolated between samples). It equals the
duration of the full cycle of largest amplitude when that cycle is symmetric; no
smoothing, so high-frequency wiggles that cross zero shorten it (that is the definition).

**Orientation**: published ``Tp`` are usually for the strike-normal (SN) or strike-parallel
(SP) component. :func:`rotate_horizontal` turns two horizontal components of known
azimuths into the component along any azimuth (ObsPy's ``rotate2zne``); :func:`fault_azimuth`
gives the SN or SP azimuth of a fault strike. :func:`isorock.records.components.choose_component` uses
them to give the workflow, ``isorock pulse --id`` and ``benchmarks/tp_table.py`` the component
of a Table 1 row as the paper used it. :func:`tp_method_of` names the definition of a published
value from its source (``mp``, ``br``) and :func:`tp_by_method` gives the period by it.

Simplifications with respect to the published methods:

* one component only: Shahi & Baker (2014) rotate two horizontal components to the
  orientation of the largest coefficient and try up to 5 candidate pulses; here the
  given component (for a Table 1 row, its SN/SP direction) is used and only the largest
  pulse is extracted;
* the energy ratio uses the time-domain sum of squared velocity instead of squared
  DWT coefficients (equal up to the DWT boundary treatment);
* the scale grid is log-spaced (then refined) instead of linear in samples;
* Baker's early-arrival test is read as ``t10%,pulse < t20%,orig`` (with the opposite
  reading, ``t20%,pulse < t10%,orig``, a record that is nothing but a pulse would be
  "late"); Shahi & Baker (2014) use 5 % / 17 % instead;
* MP (2003) fitted their model by trial and error, by eye (velocity and displacement
  waveforms, and response spectra of the full synthetic record); here by least squares
  on velocity and displacement in the window above, without the response spectra;
* Bray & Rodriguez-Marek (2004) read ``Tv`` off plots of the velocity history; here the
  zero crossings around the PGV are computed from the samples.

References
----------
Baker, J. W. (2007). Quantitative classification of near-fault ground motions using wavelet
analysis. BSSA 97(5), 1486-1501.
Shahi, S. K. & Baker, J. W. (2014). An efficient algorithm to identify strong-velocity pulses in
multicomponent ground motions. BSSA 104(5), 2456-2466.
Mavroeidis, G. P. & Papageorgiou, A. S. (2003). A mathematical representation of near-fault
ground motions. BSSA 93(3), 1099-1131.
Bray, J. D. & Rodriguez-Marek, A. (2004). Characterization of forward-directivity ground
motions in the near-fault region. Soil Dynamics and Earthquake Engineering 24(11), 815-828.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the names below are imported on first use (:func:`__getattr__`)
    from isorock.pulse.bray import tp_bray_rodriguez_marek
    from isorock.pulse.extract import (
        TP_METHODS,
        PulseConfig,
        PulseResult,
        extract_pulse,
        tp_by_method,
        tp_method_of,
    )
    from isorock.pulse.mp import MPFit, MPParameters, fit_mp, mp_acceleration, mp_displacement, mp_velocity
    from isorock.pulse.wavelet import central_frequency, cwt_db4, pseudo_period, pulse_indicator

#: public name -> module of this package that defines it. The modules are imported on first use of a
#: name (PEP 562): the extraction needs PyWavelets, scipy.signal and scipy.optimize (about 1 s to
#: import), which the module's other users do not all need.
_WHERE = {
    "tp_bray_rodriguez_marek": "bray",
    **dict.fromkeys(
        ("TP_METHODS", "PulseConfig", "PulseResult", "extract_pulse", "tp_by_method", "tp_method_of"),
        "extract",
    ),
    **dict.fromkeys(
        ("MPFit", "MPParameters", "fit_mp", "mp_acceleration", "mp_displacement", "mp_velocity"), "mp"
    ),
    **dict.fromkeys(("central_frequency", "cwt_db4", "pseudo_period", "pulse_indicator"), "wavelet"),
}

__all__ = [
    "TP_METHODS",
    "tp_by_method",
    "tp_method_of",
    "PulseConfig",
    "MPParameters",
    "PulseResult",
    "extract_pulse",
    "cwt_db4",
    "pseudo_period",
    "central_frequency",
    "pulse_indicator",
    "mp_velocity",
    "mp_acceleration",
    "mp_displacement",
    "MPFit",
    "fit_mp",
    "tp_bray_rodriguez_marek",
]


def __getattr__(name: str) -> Any:
    """A public name of the package, imported from its module on first use."""
    mod = _WHERE.get(name)
    if mod is None:
        if name in set(_WHERE.values()):  # a submodule as an attribute (isorock.pulse.extract)
            return importlib.import_module(f".{name}", __name__)
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{mod}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
