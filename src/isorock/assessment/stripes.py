"""The object and its runs: multiple-stripe analysis, failure modes per run, counts per stripe.

An object (a statue, a cabinet) is a rigid block of full height ``h`` and width ``w`` (in the direction
it may rock): slenderness ``lambda = h / w``, size ``R = sqrt(h^2 + w^2) / 2``, with a friction
coefficient ``mu`` against its floor. Every record, processed as everywhere else, is scaled to each
intensity level (a *stripe*: the record's measure, ``assessment.imt`` of its component definition,
set to the level: :mod:`isorock.assessment.scaling`) and analysed in a full run
(:func:`isorock.physics.engine.simulate` semantics: peaks and reactions over the whole motion, the free
vibration included). Per run: the outcome, ``max theta / alpha``, the peak isolator displacement and
the contact-force demands ``mu_required`` and ``min_normal_over_weight``
(:class:`isorock.physics.result.Result`): a run is *outside the model* when ``mu_required > mu`` (the object
would slide) or the normal force vanishes (it would jump).

An object whose friction is below ``tan(alpha)`` slides and never rocks (docs/model.md §16): its runs
are sliding analyses (``mode`` ``sliding``), exact for that object, with the peak and residual slip
and the number of slips; it fails when it slides farther than its allowance ``slide_allow_m`` (to
its plinth's edge or a neighbour) or its isolator goes beyond the capacity.

:func:`classify_runs` names the failure modes of every run (overturn; isolator displacement beyond the
capacity; failure, either of the two; outside the model); :func:`stripe_table` counts them per stripe;
:func:`outcome_matrices` gives the per-record outcomes the fragility fits and their bootstrap take
(:mod:`isorock.assessment.case`).

The analyses of one record run in parallel threads (:func:`isorock.physics.engine.run_many`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd

from isorock.physics.body import RigidBody, parts_from_config
from isorock.physics.excitation import GroundMotion
from isorock.physics.model import Block, System

__all__ = [
    "AssessedObject",
    "run_levels",
    "classify_runs",
    "stripe_table",
    "outcome_matrices",
    "RUN_COLUMNS",
]

#: the per-run columns of :func:`run_levels`
RUN_COLUMNS = (
    "level", "pga_g", "scale", "outcome", "outcome_code", "max_theta_over_alpha", "max_base_disp_m",
    "mu_required", "min_normal_over_weight", "slides", "jumps", "outside_model", "decided", "mode",
    "sliding_peak_m", "sliding_residual_m", "n_slips", "slide_allow_m", "polarity",
)  # fmt: skip

POLARITIES = ("both", "as_recorded")
"""``assessment.objects[].polarity``: an asymmetric body is analysed with each record as recorded and
reversed, and each run is the worse of the two (``both``, the default), or as recorded only."""


@dataclass(frozen=True)
class AssessedObject:
    """An object to assess.

    Parameters
    ----------
    name : str
        Name used in tables and figures.
    lam : float
        Slenderness ``h / w`` [-].
    R_m : float
        Half-diagonal [m].
    friction : float
        Friction coefficient between the object and its floor [-].
    height_m, width_m : float or None
        Full height and width [m], when given that way.
    slide_allow_m : float or None
        How far the object may slide on its base [m] (to the plinth's edge or a neighbour): a slide
        beyond it is a failure. Required for an object that slides (friction below ``tan(alpha)``).
    body : RigidBody, optional
        A rigid body of measured geometry (docs/model.md §18); ``lam`` and ``R_m`` are then those of its
        weaker side (``h_cg / b``, ``sqrt(b^2 + h_cg^2)``).
    polarity : {"both", "as_recorded"}
        For an asymmetric body: each record as recorded and reversed, each run the worse of the two
        (``both``), or as recorded only. A symmetric object responds to a reversed record as its mirror
        image, with the same outcome and peaks: it is analysed once.
    """

    name: str
    lam: float
    R_m: float
    friction: float
    height_m: float | None = None
    width_m: float | None = None
    slide_allow_m: float | None = None
    body: RigidBody | None = None
    polarity: str = "both"

    @classmethod
    def from_config(cls, d: Mapping[str, Any]) -> AssessedObject:
        """From a configuration entry: ``{name, height_m, width_m, friction}``, ``{name, lambda, R_m,
        friction}``, ``{name, b_left_m, b_right_m, h_cg_m, r_gyration_m, friction}`` or ``{name, parts,
        friction}``, with ``slide_allow_m`` [m], ``restitution`` and ``polarity`` if given."""
        allow = d.get("slide_allow_m")
        allow = None if allow is None else float(allow)
        body = body_from_config(d, f"object {d.get('name', '?')}")
        if body is not None:
            side = body.left if body.left.tan_alpha <= body.right.tan_alpha else body.right
            # the outline of a body of parts: its footprint and its top
            parts = d.get("parts") or []
            top = max((float(p["y_m"]) + float(p["height_m"]) for p in parts), default=None)
            return cls(
                d["name"],
                body.lam,
                side.R,
                float(d["friction"]),
                height_m=top,
                width_m=body.width if top is not None else None,
                slide_allow_m=allow,
                body=body,
                polarity=str(d.get("polarity", "both")),
            )
        if "height_m" in d:
            h, w = float(d["height_m"]), float(d["width_m"])
            return cls(d["name"], h / w, 0.5 * math.hypot(h, w), float(d["friction"]), h, w, allow)
        return cls(d["name"], float(d["lambda"]), float(d["R_m"]), float(d["friction"]), slide_allow_m=allow)

    def block(self) -> Block | RigidBody:
        """The uniform block, or the rigid body of measured geometry."""
        if self.body is not None:
            return self.body
        return Block.from_lambda_R(self.lam, self.R_m)

    @property
    def polarities(self) -> tuple[float, ...]:
        """The polarities each record is analysed in: ``(1, -1)`` for an asymmetric body (unless
        ``polarity: as_recorded``), else ``(1,)``."""
        if self.body is not None and not self.body.symmetric and self.polarity == "both":
            return (1.0, -1.0)
        return (1.0,)

    def system(self, isolation: Any) -> System:
        """The object on ``isolation``: a sliding object is marked ``sliding_only`` (a squat one below the
        no-bounce limit of an isolated base is then accepted: it never rocks)."""
        return System(self.block(), isolation, sliding_only=self.slides)

    @property
    def slides(self) -> bool:
        """Friction below ``tan(alpha)``: the object slides and never rocks (docs/model.md §16)."""
        return self.friction < self.block().tan_alpha

    def columns(self) -> dict[str, Any]:
        """Table columns: object, lambda_, R_m, height_m, width_m (NaN if not given), friction, tan_alpha,
        mode (``sliding`` or ``rocking``), slide_allow_m (NaN if not given)."""
        blk = self.block()
        return {
            "object": self.name,
            "lambda_": self.lam,
            "R_m": self.R_m,
            "height_m": math.nan if self.height_m is None else self.height_m,
            "width_m": math.nan if self.width_m is None else self.width_m,
            "friction": self.friction,
            "tan_alpha": blk.tan_alpha,
            "mode": "sliding" if self.slides else "rocking",
            "slide_allow_m": math.nan if self.slide_allow_m is None else self.slide_allow_m,
            **body_columns(self.body),
            "polarities": len(self.polarities),
        }

    def to_dict(self) -> dict:
        return asdict(self)

    def runs(
        self,
        systems: Sequence[System],
        gm: GroundMotion,
        levels_g: Sequence[float],
        *,
        basis: float | None = None,
        threads: int | None = None,
    ) -> pd.DataFrame:
        """:func:`run_levels` of this object: its friction, sliding allowance and polarities."""
        return run_levels(
            systems,
            gm,
            levels_g,
            self.friction,
            slide_allow_m=self.slide_allow_m,
            basis=basis,
            threads=threads,
            polarities=self.polarities,
        )


def body_from_config(d: Mapping[str, Any], where: str) -> RigidBody | None:
    """The rigid body of a configuration entry (``b_left_m, b_right_m, h_cg_m, r_gyration_m`` or
    ``parts``, with ``restitution``), or None for a uniform block."""
    eps = d.get("restitution")
    eps = None if eps is None else float(eps)
    if "parts" in d:
        return RigidBody.from_parts(parts_from_config(d["parts"], f"{where}: parts"), restitution=eps)
    if "b_left_m" in d:
        return RigidBody(
            float(d["b_left_m"]), float(d["b_right_m"]), float(d["h_cg_m"]), float(d["r_gyration_m"]), eps
        )
    return None


def body_columns(body: RigidBody | None) -> dict[str, float]:
    """The rigid body's columns of the objects table (NaN for a uniform block): b_left_m, b_right_m,
    h_cg_m, r_gyration_m [m], tan_alpha_left, tan_alpha_right [-]."""
    if body is None:
        keys = ("b_left_m", "b_right_m", "h_cg_m", "r_gyration_m", "tan_alpha_left", "tan_alpha_right")
        return dict.fromkeys(keys, math.nan)
    return {
        **{k: v for k, v in body.as_dict().items() if k != "restitution"},
        "tan_alpha_left": body.left.tan_alpha,
        "tan_alpha_right": body.right.tan_alpha,
    }


def run_levels(
    systems: Sequence[System],
    gm: GroundMotion,
    levels_g: Sequence[float],
    friction: float,
    *,
    slide_allow_m: float | None,
    basis: float | None = None,
    threads: int | None = None,
    progress: Callable[[str], None] | None = None,
    polarities: Sequence[float] = (1.0,),
) -> pd.DataFrame:
    """Full runs of every system with the record scaled to every level, in parallel.

    A system whose ``tan(alpha)`` is above ``friction`` is analysed sliding (docs/model.md §16).

    Parameters
    ----------
    systems : sequence of System
        The object on each isolation to analyse (one row block per system).
    gm : GroundMotion
        The processed record [m/s^2].
    levels_g : sequence of float
        Levels of the stripes' intensity measure the record is scaled to (g for PGA and SA, cm/s
        for PGV).
    basis : float, optional
        The record's value of that measure as it is (its component definition's: RotD50 of the two
        horizontals, or the analysed component's; :mod:`isorock.assessment.scaling`): the scale of a
        level ``x`` is ``x / basis``. Default: the analysed component's PGA [g].
    friction : float
        The object's friction coefficient [-]: below ``tan(alpha)`` a sliding analysis, else a rocking
        one with the ``slides`` and ``outside_model`` flags.
    threads : int, optional
        Parallel threads (default: numba's setting, all cores).
    progress : callable, optional
        Called with one line per system.
    slide_allow_m : float or None
        The object's sliding allowance [m] (None: none given), kept as a column for
        :func:`classify_runs`; required, so that no caller forgets it.
    polarities : sequence of float
        ``(1,)``: the record as recorded; ``(1, -1)``: also reversed, and each row is the worse of the
        two (:func:`_worse`), its ``polarity`` the one that governs (an asymmetric body).

    Returns
    -------
    pandas.DataFrame
        One row per (system, level), in that order, with ``system`` (its index) and
        :data:`RUN_COLUMNS`.
    """
    from isorock.physics.engine import run_many

    ref = gm.pga_g if basis is None else float(basis)
    base = [(si, float(x), float(x) / ref) for si in range(len(systems)) for x in levels_g]
    rows = [(si, x, sc, pol) for pol in polarities for si, x, sc in base]
    res = run_many(
        [systems[si] for si, _, _, _ in rows],
        gm,
        [sc * pol for _, _, sc, pol in rows],
        early_stop=False,
        threads=threads,
        friction=friction,
    )
    allow = math.nan if slide_allow_m is None else float(slide_allow_m)
    out: list[dict[str, Any]] = []
    for i, (si, x, scale, pol) in enumerate(rows):
        mu = float(res.mu_required[i])
        nmin = float(res.min_normal_over_weight[i])
        jumps = bool(res.jumps[i])
        sliding = friction < systems[si].block.tan_alpha
        # in a sliding analysis the slip is the motion analysed, not a departure from the model
        slides = (not jumps) and mu > friction and not sliding
        code = int(res.outcome_code[i])
        out.append(
            {
                "system": si,
                "level": x,
                "pga_g": scale * gm.pga_g,
                "scale": scale,
                "outcome": res.outcome[i],
                "outcome_code": code,
                "max_theta_over_alpha": float(res.max_theta_over_alpha[i]),
                "max_base_disp_m": float(res.max_base_disp_m[i]),
                "mu_required": mu,
                "min_normal_over_weight": nmin,
                "slides": bool(slides),
                "jumps": bool(jumps),
                "outside_model": bool(slides or jumps),
                "decided": bool(res.decided[i]),
                "mode": "sliding" if sliding else "rocking",
                "sliding_peak_m": float(res.sliding_peak_m[i]) if sliding else math.nan,
                "sliding_residual_m": float(res.sliding_residual_m[i]) if sliding else math.nan,
                "n_slips": int(res.n_slips[i]) if sliding else 0,
                "slide_allow_m": allow,
                "polarity": pol,
            }
        )
    if len(polarities) > 1:
        n = len(base)
        out = [_worse([out[i + k * n] for k in range(len(polarities))]) for i in range(n)]
    if progress is not None:
        for si in range(len(systems)):
            sel = [o for o in out if o["system"] == si]
            n_ov = sum(o["outcome_code"] == 2 for o in sel)
            n_sl = sum(o["n_slips"] > 0 for o in sel)
            what = f"{n_sl} slide" if sel and sel[0]["mode"] == "sliding" else f"{n_ov} overturn"
            progress(f"system {si + 1}/{len(systems)}: {len(sel)} runs, {what}")
    return pd.DataFrame(out)


def _worse(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """The envelope of one record's runs in several polarities: the worse outcome and, each apart, the
    larger peaks (rotation, displacement, slip, friction demand), the least normal force, any flag; the
    ``polarity`` and residual slip of the run with the worse outcome (then the larger displacement)."""
    gov = max(runs, key=lambda r: (r["outcome_code"], r["max_base_disp_m"], r["max_theta_over_alpha"]))
    out = dict(gov)
    for k in ("max_theta_over_alpha", "max_base_disp_m", "mu_required", "sliding_peak_m", "n_slips"):
        vals = [r[k] for r in runs if r[k] == r[k]]
        out[k] = max(vals) if vals else gov[k]
    out["min_normal_over_weight"] = min(r["min_normal_over_weight"] for r in runs)
    for k in ("slides", "jumps", "outside_model"):
        out[k] = any(r[k] for r in runs)
    out["decided"] = all(r["decided"] for r in runs)
    return out


def _p84(v: np.ndarray) -> float:
    return float(np.percentile(v, 84.0)) if v.size else math.nan


def _finite(g: pd.DataFrame, col: str, fn: Callable[[np.ndarray], Any]) -> float:
    """``fn`` of the finite values of column ``col`` (NaN when it has none: a rocking object)."""
    if col not in g:
        return math.nan
    v = g[col].to_numpy(dtype=float)
    v = v[np.isfinite(v)]
    return float(fn(v)) if v.size else math.nan


def classify_runs(runs: pd.DataFrame, capacity_m: float | None) -> pd.DataFrame:
    """The failure modes of every run, as columns added to a copy of ``runs``.

    ``overturn`` (the object overturns), ``uplift`` (it rocks or overturns), ``exceeds_capacity`` (the
    peak isolator displacement is beyond ``capacity_m`` [m]; never for a fixed base, whose displacement
    is 0), ``slides_beyond`` (a sliding object's peak slip is beyond its ``slide_allow_m``), ``failure``
    (overturn, beyond the capacity or slid beyond the allowance), and, already there,
    ``outside_model`` (the object would slide, ``slides``, or jump, ``jumps``: the rocking model does
    not describe it).
    """
    out = runs.copy()
    d = out["max_base_disp_m"].to_numpy(dtype=float)
    out["overturn"] = out["outcome_code"].to_numpy() == 2
    out["uplift"] = out["outcome_code"].to_numpy() >= 1
    out["exceeds_capacity"] = (d > capacity_m) if capacity_m else np.zeros(len(out), dtype=bool)
    if "sliding_peak_m" in out and "slide_allow_m" in out:
        peak = out["sliding_peak_m"].to_numpy(dtype=float)
        allow = out["slide_allow_m"].to_numpy(dtype=float)
        with np.errstate(invalid="ignore"):
            out["slides_beyond"] = np.nan_to_num(peak, nan=0.0) > np.nan_to_num(allow, nan=np.inf)
    else:
        out["slides_beyond"] = np.zeros(len(out), dtype=bool)
    out["failure"] = (
        out["overturn"].to_numpy() | out["exceeds_capacity"].to_numpy() | out["slides_beyond"].to_numpy()
    )
    return out


def stripe_table(runs: pd.DataFrame, capacity_m: float | None = None) -> pd.DataFrame:
    """Per intensity level (``level``) of one object and isolation: the runs and what they did.

    Columns: ``n_records``; ``n_overturn``, ``n_uplift`` (rocking or overturn), ``n_exceed_capacity``
    (peak isolator displacement beyond ``capacity_m``), ``n_failure`` (overturn or beyond the capacity),
    counted over every run as ``isorock simulate`` gives it; ``n_outside_model`` (would slide or jump),
    ``n_slides``, ``n_jumps``; for a sliding object ``n_slid`` (runs with a slip), ``n_slides_beyond``
    (beyond the allowance) and ``slide_median_m``, ``slide_p84_m``, ``slide_max_m`` (peak slip over the
    records [m]; NaN for a rocking object); ``disp_median_m``, ``disp_p84_m``, ``disp_mean_m``, ``disp_max_m``
    (isolator displacement over the records [m]).
    """
    r = classify_runs(runs, capacity_m)
    out = []
    for x, g in r.groupby("level", sort=True):
        d = g["max_base_disp_m"].to_numpy(dtype=float)
        out.append(
            {
                "level": float(x),
                "n_records": len(g),
                "n_overturn": int(g["overturn"].sum()),
                "n_uplift": int(g["uplift"].sum()),
                "n_exceed_capacity": int(g["exceeds_capacity"].sum()),
                "n_failure": int(g["failure"].sum()),
                "n_outside_model": int(g["outside_model"].sum()),
                "n_slides": int(g["slides"].sum()),
                "n_jumps": int(g["jumps"].sum()),
                "n_slid": int((g["n_slips"] > 0).sum()) if "n_slips" in g else 0,
                "n_slides_beyond": int(g["slides_beyond"].sum()),
                "slide_median_m": _finite(g, "sliding_peak_m", np.median),
                "slide_p84_m": _finite(g, "sliding_peak_m", _p84),
                "slide_max_m": _finite(g, "sliding_peak_m", np.max),
                "disp_median_m": float(np.median(d)),
                "disp_p84_m": _p84(d),
                "disp_mean_m": float(np.mean(d)),
                "disp_max_m": float(np.max(d)),
            }
        )
    return pd.DataFrame(out)


def outcome_matrices(
    runs: pd.DataFrame,
    levels: Sequence[float],
    capacity_m: float | None,
    outside_model: str = "exclude",
    records: Sequence[str] | None = None,
) -> tuple[list[str], dict[str, tuple[np.ndarray, np.ndarray]]]:
    """Per record and level, whether each damage state was reached and whether the run enters its fit.

    Parameters
    ----------
    runs : pandas.DataFrame
        The runs of one object and case (columns ``record``, ``level`` and :data:`RUN_COLUMNS`).
    levels : sequence of float
        The levels (columns of the matrices) [g].
    capacity_m : float or None
        Isolator displacement capacity [m].
    outside_model : {"exclude", "failure"}
        A run outside the model (sliding, jumping) is left out of every fit (``exclude``), or counted
        as a failure (``failure``; it is then still left out of the overturning and uplift fits, which
        the model cannot describe for it).
    records : sequence of str, optional
        The rows, in this order (default: the records of ``runs``, sorted); a record without runs is
        a row that enters no fit.

    Returns
    -------
    records : list of str
        The rows.
    matrices : dict
        ``{"overturn" | "failure" | "uplift": (damaged, included)}``, boolean (records x levels).
    """
    r = classify_runs(runs, capacity_m)
    records = sorted(r["record"].unique()) if records is None else list(records)
    lv = np.asarray(levels, dtype=float)
    ri = {rid: i for i, rid in enumerate(records)}
    shape = (len(records), lv.size)
    have = np.zeros(shape, dtype=bool)
    outside = np.zeros(shape, dtype=bool)
    dam = {k: np.zeros(shape, dtype=bool) for k in ("overturn", "failure", "uplift")}
    for row in r.itertuples(index=False):
        j = np.flatnonzero(np.isclose(lv, row.level, rtol=1e-12))
        if j.size == 0:
            continue
        i = ri.get(row.record)
        if i is None:
            continue
        have[i, j[0]] = True
        outside[i, j[0]] = bool(row.outside_model)
        for k in dam:
            dam[k][i, j[0]] = bool(getattr(row, k))
    inside = have & ~outside
    mats = {k: (dam[k], inside) for k in ("overturn", "uplift")}
    if outside_model == "failure":
        mats["failure"] = (dam["failure"] | outside, have)
    else:
        mats["failure"] = (dam["failure"], inside)
    return records, mats
