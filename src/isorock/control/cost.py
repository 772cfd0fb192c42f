"""What a workflow run will cost, before it runs: the analyses of each study and an expected time.

:func:`estimate` counts, from a validated configuration and the number of records, the engine analyses
(one simulation of one block on one isolation under one excitation at one amplitude) of every study the
workflow runs, as its jobs run them (:mod:`isorock.jobs.record`, :mod:`~isorock.jobs.pulses`,
:mod:`~isorock.jobs.assessment`):

* ``overturn``: records x blocks (lambda x R) x isolation cases minimum-overturning searches;
* ``maps``: records x (lambda x R x cases + Tb x xi x blocks) regime-map points;
* ``pulses``: the pulse searches of Figs 4, 5 and 7 (cases x (td x R + R x omega_p), and for Fig 5
  (R + td) x (1 + Tb + xi + rho)) and the pulse maps (excitations x cases x lambda x R);
* ``assessment``: objects x cases x records x levels full runs and one first-overturning search per
  object, case and record; the design search, objects x records x (1 + isolators of the grid) x levels
  full runs (its extension beyond the grid, when the best isolator lies on an end, adds rows not
  counted here).

A search's analyses are estimated as the engine's protocol runs them (:func:`search_analyses`): the
uplift runs, the upward scan at ratio ``growth`` from the uplift PGA over :data:`SCAN_SPAN` times it
(the first overturning PGA of the measured searches lay within 1.8 to 2.8 times the uplift PGA) or up to
``amp_max_g``, the bisection to ``rtol`` and the confirmations; the uplift PGA is taken as the fixed
base's ``tan(alpha) = 1/lambda`` [g].

The expected time is the analyses times the engine's measured CPU time per analysis of their kind
and isolation (:data:`SEARCH_MS`, :data:`PULSE_SEARCH_MS`, :data:`MAP_MS`, :data:`PULSE_MAP_MS`,
:data:`FULL_RUN_MS`; for the record studies per :data:`BENCH_RECORD_S` of record, the records'
durations being read before the run: :mod:`isorock.control.lengths`), divided by the cores; it
leaves out the jobs' start-up (about 1.5 s each), record processing, the merge, the figures and the
report (docs/scaling.md). The constants were measured with ``python benchmarks/bench_cost.py`` on
this project's 2-core development machine (warm numba cache); the time of a run on another machine
scales with its speed, the count of analyses does not.

:func:`check_cost` refuses a run of more than :data:`MAX_ANALYSES` analyses unless it is forced
(``isorock report --force``, ``prepare_run(force=True)``); ``isorock map`` applies the same limit
(:func:`check_limit`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from isorock.constants import PULSE_SHAPES
from isorock.control.config import grid_ends, grid_size, isolation_cases, ref_name
from isorock.errors import IsorockError

__all__ = [
    "SEARCH_MS",
    "MAP_MS",
    "PULSE_MAP_MS",
    "PULSE_SEARCH_MS",
    "FULL_RUN_MS",
    "SCAN_SPAN",
    "MAX_ANALYSES",
    "DEFAULT_CORES",
    "StudyCost",
    "CostEstimate",
    "search_analyses",
    "estimate",
    "check_cost",
    "check_limit",
    "format_duration",
    "profile_cores",
]

#: CPU time of one analysis of a minimum-overturning search under a record [ms], by isolation kind
#: (early decisions, one core): ``python benchmarks/bench_cost.py`` (synthetic 40 s record, lambda 4, R
#: 0.5 to 12 m; 2-core development machine, 2026-11-24, under load: the larger of two runs)
SEARCH_MS = {"none": 0.85, "linear": 0.8, "fp": 4.9}
#: the same under a pulse [ms] (``bench_cost.py``: a 0.5 s full-sine pulse)
PULSE_SEARCH_MS = {"none": 0.05, "linear": 0.08, "fp": 0.37}
#: CPU time of one point of a record's regime map [ms] (``bench_cost.py``: a 100 x 60 lambda-R map at
#: 0.5 g on one thread; the README's 6000 points in about 3 s on 2 cores agree)
MAP_MS = {"none": 1.1, "linear": 0.5, "fp": 4.4}
#: the same under a pulse [ms] (``bench_cost.py``: the 0.5 s full-sine pulse)
PULSE_MAP_MS = {"none": 0.03, "linear": 0.03, "fp": 0.13}
#: CPU time of one full run of the assessment [ms] (``bench_cost.py``: 20 blocks x 20 levels 0.05 to 1 g
#: on the 40 s record, one thread)
FULL_RUN_MS = {"none": 0.34, "linear": 0.26, "fp": 2.2}
#: how far above the uplift PGA a search's scan is counted [-] (the measured searches overturned within
#: 1.8 to 2.8 times it)
SCAN_SPAN = 3.0
#: runs of a search besides the scan and the bisection: the two confirmations of the bracket and one
#: more
CONFIRM_RUNS = 3
#: runs that find the uplift PGA, by isolation kind (none: tan(alpha); linear: one full-contact run; FP:
#: a bisection to 1e-7)
UPLIFT_RUNS = {"none": 0, "linear": 1, "fp": 25}
#: a run of more analyses than this is refused unless forced: 1 to 2 CPU-days at the speeds above (the
#: paper run, config/paper.yaml on the 17 Table 1 records, is estimated at about 1.5 million)
MAX_ANALYSES = 50_000_000
#: the cores of the estimate when neither the run nor its profile says (the default profile's)
DEFAULT_CORES = 2


#: the length of the record the per-analysis times of the record studies were measured on [s]
#: (``bench_cost.py``); a run's records count by their durations: a 120 s record as 3 such
BENCH_RECORD_S = 40.0


@dataclass(frozen=True)
class StudyCost:
    """The cost of one study of a run.

    Attributes
    ----------
    study : str
        ``overturn``, ``maps``, ``pulses`` or ``assessment``.
    analyses : int
        Engine analyses.
    cpu_s : float
        Expected CPU time [s] at the measured speeds.
    detail : str
        How the analyses are counted, in words.
    """

    study: str
    analyses: int
    cpu_s: float
    detail: str = ""


@dataclass(frozen=True)
class CostEstimate:
    """The cost of a workflow run: per study and in total.

    Attributes
    ----------
    studies : tuple of StudyCost
        The studies the run computes (those it does not run are left out).
    n_records : int
        Records of the run.
    cores : int
        Cores the expected time is given for.
    durations_s : tuple of float
        The records' durations [s] (empty: not read; each counted as :data:`BENCH_RECORD_S`).
    memory_mb : int or None
        The most memory a record job of the run declares [MB] (that of the longest record;
        :func:`isorock.control.memory.job_memory_mb`); None: not known.
    """

    studies: tuple[StudyCost, ...]
    n_records: int
    cores: int = DEFAULT_CORES
    durations_s: tuple[float, ...] = ()
    memory_mb: int | None = None

    @property
    def analyses(self) -> int:
        """Engine analyses of the whole run."""
        return sum(s.analyses for s in self.studies)

    @property
    def cpu_s(self) -> float:
        """Expected CPU time of the whole run [s]."""
        return sum(s.cpu_s for s in self.studies)

    @property
    def seconds(self) -> float:
        """Expected time on :attr:`cores` cores [s] (the analyses spread evenly over them)."""
        return self.cpu_s / max(1, self.cores)

    @property
    def over_limit(self) -> bool:
        """More analyses than :data:`MAX_ANALYSES`."""
        return self.analyses > MAX_ANALYSES

    def by_study(self) -> dict[str, int]:
        """Analyses per study."""
        return {s.study: s.analyses for s in self.studies}

    def text(self) -> str:
        """The estimate in one line (without a prefix)."""
        parts = "; ".join(f"{s.study} {s.analyses:,}" for s in self.studies) or "no study"
        lengths = ""
        if self.durations_s:
            lo, hi = min(self.durations_s), max(self.durations_s)
            span = f"{lo:.0f} s" if round(lo) == round(hi) else f"{lo:.0f} to {hi:.0f} s"
            lengths = f" of {span} ({sum(self.durations_s):,.0f} s of record in all)"
        memory = (
            f"; its record jobs declare up to {self.memory_mb:,} MB of memory each (the longest record)"
            if self.memory_mb
            else ""
        )
        return (
            f"cost estimate: {self.analyses:,} analyses ({parts}) on {self.n_records} record(s){lengths}, "
            f"about {format_duration(self.seconds)} on {self.cores} core(s) at the engine's measured speed"
            + memory
        )


def format_duration(seconds: float) -> str:
    """A duration [s] in words: ``< 1 min``, ``12 min``, ``3.4 h``, ``5.2 days``, ``3.1 years``."""
    if not math.isfinite(seconds):
        return "forever"
    if seconds < 60:
        return "< 1 min"
    if seconds < 3600:
        return f"{seconds / 60:.0f} min"
    if seconds < 86400 * 2:
        return f"{seconds / 3600:.1f} h"
    if seconds < 86400 * 365:
        return f"{seconds / 86400:.1f} days"
    return f"{seconds / (86400 * 365):.3g} years"


def search_analyses(lam: float, search: Mapping, kind: str = "none") -> int:
    """Estimated analyses of one minimum-overturning search (``min_overturn_amplitude``).

    Parameters
    ----------
    lam : float
        Slenderness of the block [-]; its uplift PGA is taken as ``1/lam`` [g].
    search : mapping
        ``amp_max_g`` [g], ``growth`` [-], ``rtol`` [-].
    kind : {"none", "linear", "fp"}
        Isolation kind (the runs that find the uplift PGA).

    Returns
    -------
    int
        Uplift runs + scan over ``min(SCAN_SPAN, amp_max_g lam)`` at ratio ``growth`` + bisection from
        ``growth - 1`` to ``rtol`` + :data:`CONFIRM_RUNS`.
    """
    growth, rtol, amp_max = float(search["growth"]), float(search["rtol"]), float(search["amp_max_g"])
    span = min(SCAN_SPAN, amp_max * lam)
    step = math.log(growth)
    scan = 0 if span <= 1 else (math.ceil(math.log(span) / step) if step > 0 else 10**18)
    width = growth - 1.0
    bisect = math.ceil(math.log2(width / rtol)) if width > rtol else 0
    return UPLIFT_RUNS.get(kind, 0) + scan + bisect + CONFIRM_RUNS


def _records_of(ref: str | Mapping, n_records: int) -> int:
    """Records a case reference (or a Tb-xi block) applies to: all, or those it names."""
    recs = [] if isinstance(ref, str) else list(ref.get("records") or [])
    return n_records if not recs else min(n_records, len(recs))


def _kinds(config: Mapping) -> dict[str, str]:
    """Isolation kind of each case name."""
    return {name: c.kind for name, c in isolation_cases(config).items()}


def _overturn(config: Mapping, n: int) -> StudyCost:
    o = config["overturn"]
    kinds = _kinds(config)
    lam = max(grid_ends(o["lambda"]))
    blocks = grid_size(o["lambda"]) * grid_size(o["R_m"])
    analyses, cpu_ms, per_search = 0, 0.0, 0
    for ref in o["cases"]:
        kind = kinds[ref_name(ref)]
        steps = search_analyses(lam, config["search"], kind)
        k = blocks * _records_of(ref, n) * steps
        analyses += k
        cpu_ms += k * SEARCH_MS[kind]
        per_search = max(per_search, steps)
    return StudyCost(
        "overturn",
        analyses,
        cpu_ms / 1000.0,
        f"{n} records x {blocks} blocks x {len(o['cases'])} cases, at most about {per_search} analyses per "
        "search",
    )


def _maps(config: Mapping, n: int) -> StudyCost:
    m = config["maps"]
    kinds = _kinds(config)
    lr, tx = m["lambda_R"], m["Tb_xi"]
    lr_points = grid_size(lr["lambda"]) * grid_size(lr["R_m"])
    tx_points = grid_size(tx["Tb_s"]) * grid_size(tx["xi_b"])
    analyses, cpu_ms = 0, 0.0
    for ref in lr["cases"]:
        k = lr_points * _records_of(ref, n)
        analyses += k
        cpu_ms += k * MAP_MS[kinds[ref_name(ref)]]
    for b in tx["blocks"]:
        k = tx_points * _records_of(b, n)
        analyses += k
        cpu_ms += k * MAP_MS["linear"]
    return StudyCost(
        "maps",
        analyses,
        cpu_ms / 1000.0,
        f"{n} records x ({lr_points} lambda-R points x {len(lr['cases'])} cases + {tx_points} Tb-xi points "
        f"x {len(tx['blocks'])} blocks)",
    )


def _pulses(config: Mapping) -> StudyCost:
    p = config["pulses"]
    kinds = _kinds(config)
    search = {**config["search"], "amp_max_g": p["amp_max_g"]}
    lam = float(p["lambda"])
    vr, vo, vi = p["vs_R"], p["vs_omega"], p["vs_isolation"]
    per_case = grid_size(vr["td_s"]) * grid_size(vr["R_m"]) + grid_size(vo["R_m"]) * grid_size(
        vo["omega_p_rad_s"]
    )
    combos = grid_size(vi["R_m"]) + grid_size(vi["td_s"])
    varied = grid_size(vi["Tb_s"]) + grid_size(vi["xi_b"]) + grid_size(vi["rho"])
    searches, analyses, cpu_ms = 0, 0, 0.0

    def add(count: int, kind: str) -> None:
        nonlocal searches, analyses, cpu_ms
        k = count * search_analyses(lam, search, kind)
        searches += count
        analyses += k
        cpu_ms += k * PULSE_SEARCH_MS[kind]

    for shape in PULSE_SHAPES:
        names = p["shapes"].get(shape) or []
        if not names:
            continue  # no job for this shape
        for c in names:
            add(per_case, kinds[c])
        if shape in vi["shapes"]:
            add(combos, "none")  # the fixed base of each curve of Fig 5
            add(combos * varied, "linear")  # the base case with one parameter varied
    sources = {(e["shape"], f"{float(e['td_s']):g}") for e in p["maps"]["excitations"]}
    lr = config["maps"]["lambda_R"]
    points = len(sources) * grid_size(lr["lambda"]) * grid_size(lr["R_m"])
    for c in p["maps"]["cases"]:
        analyses += points
        cpu_ms += points * PULSE_MAP_MS[kinds[c]]
    return StudyCost(
        "pulses",
        analyses,
        cpu_ms / 1000.0,
        f"{searches} pulse searches, {len(sources)} pulse excitations x {len(p['maps']['cases'])} cases of "
        f"{points} map points",
    )


def _object_lambda(o: Mapping) -> float:
    """The slenderness of an object (of a rigid body's weaker side)."""
    if "height_m" in o:
        return float(o["height_m"]) / float(o["width_m"])
    if "lambda" in o:
        return float(o["lambda"])
    from isorock.assessment.stripes import AssessedObject

    return AssessedObject.from_config(o).lam


def _assessment(config: Mapping, n: int, basedir: str | Path | None) -> StudyCost:
    from isorock.assessment.levels import run_levels_of

    a = config["assessment"]
    kinds = _kinds(config)
    try:
        levels = len(run_levels_of(a, basedir))
    except IsorockError:  # a hazard file relative to another directory: at most the stripes, the design
        design = a.get("design_g") or a.get("design_return_period_yr") or []  # levels and one MCE each
        levels = len(a["stripes_g"]) + 2 * len(design)
    analyses, cpu_ms = 0, 0.0
    for o in a["objects"]:
        lam = _object_lambda(o)
        for c in a["cases"]:
            kind = kinds[c]
            steps = search_analyses(lam, config["search"], kind)  # the first-overturning search
            analyses += n * (levels + steps)
            cpu_ms += n * (levels * FULL_RUN_MS[kind] + steps * SEARCH_MS[kind])
    grid = a.get("design_grid")
    isolators = 0
    if grid:
        axes = ("Tb_s", "xi_b") if grid["kind"] == "linear" else ("mu_b", "R_b_m")
        isolators = grid_size(grid[axes[0]]) * grid_size(grid[axes[1]])
        runs = len(a["objects"]) * n * levels  # per system
        analyses += runs * (1 + isolators)
        cpu_ms += runs * (FULL_RUN_MS["none"] + isolators * FULL_RUN_MS[grid["kind"]])
    detail = f"{len(a['objects'])} objects x {len(a['cases'])} cases x {n} records x {levels} levels" + (
        f", design grid of {isolators} isolators" if grid else ""
    )
    return StudyCost("assessment", analyses, cpu_ms / 1000.0, detail)


def estimate(
    config: Mapping,
    n_records: int,
    *,
    cores: int | None = None,
    basedir: str | Path | None = None,
    durations_s: Sequence[float] = (),
    memory_mb: int | None = None,
) -> CostEstimate:
    """The analyses and the expected time of a workflow run.

    Parameters
    ----------
    config : mapping
        Validated configuration (:func:`isorock.control.config.validate_config`).
    n_records : int
        Records of the run (:attr:`isorock.control.plan.Plan.records`).
    cores : int, optional
        Cores of the run (default :data:`DEFAULT_CORES`).
    basedir : path-like, optional
        Directory of the relative paths of the configuration (a hazard curve's file).
    durations_s : sequence of float
        The records' durations [s] (:func:`isorock.control.lengths.record_lengths`): the CPU time of
        the record studies (overturn, maps, assessment) grows with them, from the measured times of a
        :data:`BENCH_RECORD_S` record; empty: every record counted as that long.
    memory_mb : int, optional
        The most memory a record job declares [MB], stated with the estimate.

    Returns
    -------
    CostEstimate
        Per study (those the run computes) and in total.
    """
    studies = set(config.get("studies", ("overturn", "maps", "pulses")))
    # the record studies' time per record grows with its duration
    scale = (sum(durations_s) / len(durations_s) / BENCH_RECORD_S) if durations_s else 1.0
    out = []
    if "overturn" in studies:
        out.append(_scaled(_overturn(config, n_records), scale))
    if "maps" in studies:
        out.append(_scaled(_maps(config, n_records), scale))
    if "pulses" in studies and config["pulses"]["enabled"]:
        out.append(_pulses(config))
    if config.get("assessment"):
        out.append(_scaled(_assessment(config, n_records, basedir), scale))
    return CostEstimate(
        tuple(out), n_records, int(cores) if cores else DEFAULT_CORES, tuple(durations_s), memory_mb
    )


def _scaled(study: StudyCost, scale: float) -> StudyCost:
    return StudyCost(study.study, study.analyses, study.cpu_s * scale, study.detail)


def check_limit(
    analyses: int, seconds: float, what: str, *, force: bool = False, advice: str = "make the grid coarser"
) -> None:
    """Refuse ``analyses`` above :data:`MAX_ANALYSES` unless ``force``.

    Parameters
    ----------
    analyses : int
        Engine analyses.
    seconds : float
        Expected time [s].
    what : str
        What it is the cost of, and on how many cores (for the message).
    force : bool
        Run it anyway.
    advice : str
        What to change instead (for the message).

    Raises
    ------
    IsorockError
        One line naming the estimate, the limit and ``--force``.
    """
    if analyses > MAX_ANALYSES and not force:
        raise IsorockError(
            f"{what}, about {format_duration(seconds)}: above the limit of {MAX_ANALYSES:,} analyses; "
            f"{advice}, or rerun with --force to run it anyway"
        )


def check_cost(est: CostEstimate, *, force: bool = False) -> None:
    """Refuse a run whose estimate is above :data:`MAX_ANALYSES` unless ``force`` (:func:`check_limit`)."""
    if est.over_limit and not force:
        raise IsorockError(
            f"{est.text()}: above the limit of {MAX_ANALYSES:,} analyses; make the grids coarser, the search "
            "resolution (search.growth, search.rtol) lower or the records fewer, or rerun with --force to "
            "run it anyway"
        )


def profile_cores(profile: str | Path | None) -> int | None:
    """The ``cores`` of a workflow profile's ``config.yaml`` (None when it says none or cannot be read)."""
    if profile is None:
        return None
    import yaml

    try:
        data = yaml.safe_load((Path(profile) / "config.yaml").read_text()) or {}
    except (OSError, yaml.YAMLError, UnicodeDecodeError):
        return None
    v = data.get("cores") if isinstance(data, dict) else None
    return v if isinstance(v, int) and v >= 1 else None
