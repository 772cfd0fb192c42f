"""The searches for the uplift amplitude and the minimum overturning amplitude (docs/model.md §13).

Amplitudes are peak ground accelerations in g: the pulse amplitude ``A_g0/g``, or the
PGA of a record after scaling. The regime maps are :mod:`isorock.physics.regime_maps`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from isorock.constants import G
from isorock.errors import ParameterError
from isorock.physics.engine import max_contact_acceleration, simulate
from isorock.physics.excitation import Excitation
from isorock.physics.model import System

__all__ = [
    "MinOverturn",
    "uplift_amplitude",
    "min_overturn_amplitude",
    "check_search",
]


@dataclass
class MinOverturn:
    """Result of the minimum-overturning search.

    Attributes
    ----------
    min_overturn_g : float or None
        Smallest amplitude (PGA) that overturns the block [g]; None if nothing up to ``amp_max`` does.
    uplift_g : float
        Amplitude at which rocking starts [g].
    min_overturn_over_tan_alpha : float or None
        ``min_overturn_g / tan(alpha)`` [-] (1 = uplift threshold of the non-isolated block).
    n_analyses : int
        Engine runs the search took.
    resolution : float or None
        Relative uncertainty of ``min_overturn_g`` [-]: the step of the scan grid that bracketed it,
        ``growth - 1`` (0.005 at the paper's 1.005). The overturning set need not be an interval, so
        an overturning band narrower than one scan step below the reported value can be missed; the
        bisection inside the bracket is far finer (``bisection_width``). None when nothing overturns.
    bisection_width : float or None
        Relative width of the final bisection bracket [-] (about ``rtol``).
    growth : float
        Ratio of the upward scan grid [-].
    rtol : float
        Relative width the bisection stops at [-].
    amp_max_g : float
        Largest amplitude scanned [g].
    full_runs_only : bool
        True when an early-stopped run and a full run disagreed at a bracket end, so that the whole
        search was run again with full runs (the answer is theirs).
    stalls : int
        Uplifts skipped by the engine's zero-progress guard over all the runs (see
        :attr:`isorock.physics.result.Result.stalls`); 0 in a sound search.
    polarity : float
        1 for the input as given, -1 reversed.
    """

    min_overturn_g: float | None
    uplift_g: float
    min_overturn_over_tan_alpha: float | None
    n_analyses: int
    resolution: float | None
    bisection_width: float | None
    growth: float
    rtol: float
    amp_max_g: float
    full_runs_only: bool = False
    stalls: int = 0
    polarity: float = 1.0

    def to_dict(self) -> dict:
        return asdict(self)


def _unit(excitation: Excitation) -> Excitation:
    """The excitation scaled to a PGA of 1 g."""
    return excitation.with_pga(1.0)


def _check_polarity(polarity: float) -> None:
    if polarity not in (1.0, -1.0):
        raise ParameterError(f"polarity={polarity!r} is out of range: valid 1 (as given) or -1 (reversed)")


def uplift_amplitude(
    system: System, excitation: Excitation, *, rtol: float = 1e-7, polarity: float = 1.0
) -> tuple[float, int]:
    """Smallest amplitude (PGA) at which the block starts to rock [g].

    Non-isolated: ``tan(alpha)``. Linear isolator: ``g tan(alpha) / max|A_1|`` from one full-contact run
    (exact, docs/model.md §13). FP isolator, and any base under a record with a vertical (whose
    threshold ``(g + a_v) tan(alpha)`` scales with the record too, docs/model.md §17): bisection on the
    occurrence of uplift, which is monotone in the amplitude (uplift at ``s`` means
    ``s (|A_1| - a_v1 tan(alpha)) > g tan(alpha)`` somewhere, true for every larger ``s``). A rigid body
    whose two sides differ (docs/model.md §18) has a threshold per direction: bisection too, for the
    input as given (``polarity`` 1) or reversed (-1).

    Returns
    -------
    amplitude : float
        Uplift amplitude [g] (``inf`` if none is found up to 1000 g for the FP isolator).
    n_analyses : int
        Engine runs used.
    """
    _check_polarity(polarity)
    unit = _unit(excitation)
    tan_a = system.block.tan_alpha
    kind = system.isolation.kind
    vertical = getattr(unit, "vertical", None) is not None
    closed = vertical or not getattr(system.block, "symmetric", True)
    if kind == "none" and not closed:
        return tan_a, 0
    if kind == "linear" and not closed:
        amax = max_contact_acceleration(system, unit)
        return (G * tan_a / amax if amax > 0 else math.inf), 1
    n = 0

    def uplifts(a: float) -> bool:
        nonlocal n
        n += 1
        res = simulate(system, unit, scale=a * polarity, stop_at_uplift=True, early_stop=True)
        return res.t_uplift_s is not None

    lo, hi = 0.0, tan_a
    while not uplifts(hi):
        lo, hi = hi, 2.0 * hi
        if hi > 1000.0:
            return math.inf, n
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if uplifts(mid):
            hi = mid
        else:
            lo = mid
    return hi, n


def check_search(amp_max: float = 5.0, growth: float = 1.005, rtol: float = 1e-6) -> None:
    """Check the settings of :func:`min_overturn_amplitude` (largest amplitude ``amp_max`` [g], scan
    ratio ``growth`` [-], bracket width ``rtol`` [-]).

    Raises
    ------
    ParameterError
        A setting out of its range.
    """
    if not growth > 1.0:
        raise ParameterError(f"growth={growth!r} is out of range: valid growth > 1")
    if not 0 < amp_max < math.inf:
        raise ParameterError(f"amp_max={amp_max!r} is out of range: valid a finite amp_max > 0 g")
    if not growth < math.inf:
        raise ParameterError(f"growth={growth!r} is out of range: valid a finite growth > 1")
    if not 0 < rtol < 1:
        raise ParameterError(f"rtol={rtol!r} is out of range: valid 0 < rtol < 1")


def min_overturn_amplitude(
    system: System,
    excitation: Excitation,
    *,
    amp_max: float = 5.0,
    growth: float = 1.005,
    rtol: float = 1e-6,
    polarity: float = 1.0,
) -> MinOverturn:
    """Minimum overturning amplitude by the scan/bisection protocol of docs/model.md §13.

    The overturning set is not an interval in general, so the search scans upward from the uplift
    amplitude on the geometric grid ``A_up growth^k`` and bisects only the first bracket
    (last safe, first overturning grid amplitude) to a relative width ``rtol``. Runs use the exact
    early decisions of §9; the two bracket ends are confirmed with full runs, and if either
    disagrees the whole search is run again with full runs only, whose answer is returned.

    Parameters
    ----------
    system : System
        Block and isolation.
    excitation : Pulse or GroundMotion
        Shape of the input; its own amplitude is ignored (the search scales it).
    amp_max : float
        Largest amplitude tried [g].
    growth : float
        Ratio of the scan grid [-] (> 1); ``growth - 1`` is the relative resolution of the answer.
    rtol : float
        Relative width of the final bracket [-].
    polarity : {1, -1}
        The input as given or reversed: a body whose sides differ (docs/model.md §18) has a minimum
        overturning amplitude per direction.
    """
    check_search(amp_max, growth, rtol)
    unit = _unit(excitation)
    a_up, n_up = uplift_amplitude(system, excitation, polarity=polarity)
    search = _Search(system, unit, a_up, amp_max, growth, n_up, polarity)
    full_only = False
    lo, hi = search.scan(early=True)
    if hi is not None and not search.confirmed(lo, hi):
        full_only = True
        lo, hi = search.scan(early=False)
    if hi is not None:
        lo, hi = search.bisect(lo, hi, rtol, early=not full_only)
    tan_a = system.block.tan_alpha
    return MinOverturn(
        min_overturn_g=hi,
        uplift_g=a_up,
        min_overturn_over_tan_alpha=None if hi is None else hi / tan_a,
        n_analyses=search.n,
        resolution=None if hi is None else round(growth - 1.0, 12),
        bisection_width=None if hi is None else (hi - lo) / hi,
        growth=growth,
        rtol=rtol,
        amp_max_g=amp_max,
        full_runs_only=full_only,
        stalls=search.stalls,
        polarity=polarity,
    )


class _Search:
    """Runs of one minimum-overturning search (counted), its upward scan and its bisection."""

    def __init__(
        self,
        system: System,
        unit: Excitation,
        a_up: float,
        amp_max: float,
        growth: float,
        n: int,
        polarity: float = 1.0,
    ):
        self.system, self.unit, self.a_up = system, unit, a_up
        self.polarity = polarity
        self.amp_max, self.growth = amp_max, growth
        self.n = n
        self.stalls = 0

    def overturns(self, a: float, early: bool) -> bool:
        self.n += 1
        res = simulate(self.system, self.unit, scale=a * self.polarity, early_stop=early)
        self.stalls += res.stalls
        return res.outcome == "overturn"

    def scan(self, early: bool) -> tuple[float, float | None]:
        """(last safe, first overturning) grid amplitudes [g]; (last scanned, None) when none overturns."""
        lo = self.a_up
        if not math.isfinite(self.a_up) or self.a_up >= self.amp_max:
            return lo, None
        k = 1
        while True:
            a = min(self.a_up * self.growth**k, self.amp_max)
            if self.overturns(a, early):
                return lo, a
            lo = a
            if a >= self.amp_max:
                return lo, None
            k += 1

    def confirmed(self, lo: float, hi: float) -> bool:
        """Whether full runs agree with the early-stopped ones at both ends of a bracket."""
        if not self.overturns(hi, early=False):
            return False
        return not (lo > self.a_up and self.overturns(lo, early=False))

    def bisect(self, lo: float, hi: float, rtol: float, early: bool) -> tuple[float, float]:
        while hi - lo > rtol * hi:
            mid = 0.5 * (lo + hi)
            if self.overturns(mid, early):
                hi = mid
            else:
                lo = mid
        return lo, hi
