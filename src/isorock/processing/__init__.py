"""Record processing as a list of named steps (the USGS gmprocess pattern).

A processing configuration is a YAML list of steps, each a step name with keyword
parameters::

    processing:
      - detrend: {type: linear}
      - taper: {type: hann, max_percentage: 0.05}
      - bandpass_filter: {freqmin: 0.05, freqmax: 40.0, corners: 4}
      - check_tail: {duration: 5.0}

Every step is a plain function ``step(trace, **params) -> trace`` on an ObsPy
:class:`~obspy.core.trace.Trace` holding ground acceleration in m/s^2. A step works
in place, returns the trace, and records what it did once (:mod:`isorock.processing.history`):
an :class:`AppliedStep` (``step`` name, ``parameters`` dict, ``note`` text) appended to
``trace.stats.processing_steps`` (read it with :func:`applied_steps`; :func:`steps_to_json` is the
form the store keeps), and the same step as one human-readable line appended to ObsPy's history
``trace.stats.processing`` (ObsPy's own history lines of the methods it calls are folded into that
one line). Readers use the structured steps; the lines are for people.

QA steps (``check_*``) never raise on a bad record: they mark it failed with a
reason (:func:`fail`), as gmprocess does; :func:`qa_passed` and :func:`qa_reasons`
read the marks. Processing goes on after a failure so that the caller can still
look at the record; it decides what to do with failed records.

The default configuration ``processing.yaml`` ships with the package (in this folder). Its steps
(order as applied):

1. ``check_pga`` on the input (plausible range 0.001 g to 5 g);
2. ``detrend`` (linear) and ``detrend`` (demean);
3. ``taper``: Hann window on 5 % of the record at each end (at most 2 s);
4. ``bandpass_filter``: acausal (zero-phase, forward and backward) Butterworth,
   4 corners, 0.05 Hz to 40 Hz (the high corner capped at 0.8 of the Nyquist
   frequency), applied to the record padded with zeros of total length
   ``1.5 * corners / freqmin`` (Converse & Brady 1992; Boore 2005), pads removed after;
5. ``baseline_polynomial``: the NGA-West2 / gmprocess baseline correction: a
   polynomial of order 6 without constant and linear terms is fitted by least squares
   to the displacement and its second derivative is removed from the acceleration;
6. ``check_tail`` (gmprocess: velocity and displacement in the last 5 s against
   PGV and PGD) and ``check_pga`` on the result;
7. ``resample``: only when a target ``dt`` is given (ObsPy Lanczos or FFT).

References
----------
Boore, D. M. (2005). On pads and filters: processing strong-motion data. BSSA 95(2), 745-750.
Ancheta, T. D. et al. (2014). NGA-West2 database. Earthquake Spectra 30(3), 989-1005.
Hearne, M. et al. (2019). gmprocess. USGS software release, doi:10.5066/P9ANQXN3.
"""

from isorock.processing.config import (
    DEFAULT_CONFIG_NAME,
    ProcessingConfig,
    ProcessingStep,
    default_config,
    load_config,
    process,
    with_lowest_usable_frequency,
)
from isorock.processing.history import (
    AppliedStep,
    applied_steps,
    steps_from_json,
    steps_to_json,
)
from isorock.processing.intensity import (
    MEASURE_DESCRIPTIONS,
    MEASURE_UNITS,
    MEASURES,
    Intensities,
    intensities,
    intensity,
    pseudo_spectral_acceleration,
)
from isorock.processing.legacy import parse_history
from isorock.processing.metrics import displacement, metrics, velocity
from isorock.processing.orientation import fault_azimuth, rotate_horizontal
from isorock.processing.qa import fail, qa_passed, qa_reasons
from isorock.processing.steps import (
    STEPS,
    bandpass_filter,
    baseline_polynomial,
    check_pga,
    check_tail,
    detrend,
    resample,
    taper,
)

__all__ = [
    "rotate_horizontal",
    "fault_azimuth",
    "STEPS",
    "DEFAULT_CONFIG_NAME",
    "ProcessingStep",
    "ProcessingConfig",
    "AppliedStep",
    "applied_steps",
    "steps_to_json",
    "steps_from_json",
    "parse_history",
    "default_config",
    "load_config",
    "process",
    "with_lowest_usable_frequency",
    "metrics",
    "velocity",
    "displacement",
    "MEASURES",
    "MEASURE_UNITS",
    "MEASURE_DESCRIPTIONS",
    "Intensities",
    "intensity",
    "intensities",
    "pseudo_spectral_acceleration",
    "fail",
    "qa_passed",
    "qa_reasons",
    "detrend",
    "taper",
    "bandpass_filter",
    "baseline_polynomial",
    "resample",
    "check_pga",
    "check_tail",
]
