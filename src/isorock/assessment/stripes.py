"""The object and its runs: multiple-stripe analysis, failure modes per run, counts per stripe.

An object (a statue, a cabinet) is a rigid block of full height ``h`` and width ``w`` (in the direction
it may rock): slenderness ``lambda = h / w``, size ``R = sqrt(h^2 + w^2) / 2``, with a friction
coefficient ``mu`` against its floor. Every record, processed as everywhere else, is scaled to each
intensity level (a *stripe*: the record's PGA set to the level) and analysed in a full run
(:func:`isorock.engine.simulate` semantics: peaks and reactions over the whole motion, the free
vibration included). Per run: the outcome, ``max theta / alpha``, the peak isolator displacement and
the contact-force demands ``mu_required`` and ``min_normal_over_weight``
(:class:`isorock.result.Result`): a run is *outside the model* when ``mu_required > mu`` (the object
would slide) or the normal force vanishes (it would jump).

:func:`classify_runs` names the failure modes of every run (overturn; isolator displacement beyond the
capacity; failure, either of the two; outside the model); :func:`stripe_table` counts them per stripe;
:func:`outcome_matrices` gives the per-record outcomes the fragility fits and their bootstrap take
(:mod:`isorock.assessment.case`).

The analyses of one record run in parallel threads (:func:`isorock.engine.run_many`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd

from ..excitation import GroundMotion
from ..model import Block, System

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
    "pga_g", "scale", "outcome", "outcome_code", "max_theta_over_alpha", "max_base_disp_m", "mu_required",
    "min_normal_over_weight", "slides", "jumps", "outside_model", "decided",
)  # fmt: skip


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
    """

    name: str
    lam: float
    R_m: float
    friction: float
    height_m: float | None = None
    width_m: float | None = None

    @classmethod
    def from_config(cls, d: Mapping[str, Any]) -> AssessedObject:
        """From a configuration entry: ``{name, height_m, width_m, friction}`` or ``{name, lambda, R_m,
        friction}``."""
        if "height_m" in d:
            h, w = float(d["height_m"]), float(d["width_m"])
            return cls(d["name"], h / w, 0.5 * math.hypot(h, w), float(d["friction"]), h, w)
        return cls(d["name"], float(d["lambda"]), float(d["R_m"]), float(d["friction"]))

    def block(self) -> Block:
        return Block.from_lambda_R(self.lam, self.R_m)

    def columns(self) -> dict[str, Any]:
        """Table columns: object, lambda_, R_m, height_m, width_m (NaN if not given), friction, tan_alpha."""
        blk = self.block()
        return {
            "object": self.name,
            "lambda_": self.lam,
            "R_m": self.R_m,
            "height_m": math.nan if self.height_m is None else self.height_m,
            "width_m": math.nan if self.width_m is None else self.width_m,
            "friction": self.friction,
            "tan_alpha": blk.tan_alpha,
        }

    def to_dict(self) -> dict:
        return asdict(self)


def run_levels(
    systems: Sequence[System],
    gm: GroundMotion,
    levels_g: Sequence[float],
    friction: float,
    *,
    threads: int | None = None,
    progress: Callable[[str], None] | None = None,
) -> pd.DataFrame:
    """Full runs of every system with the record scaled to every level, in parallel.

    Parameters
    ----------
    systems : sequence of System
        The object on each isolation to analyse (one row block per system).
    gm : GroundMotion
        The processed record [m/s^2].
    levels_g : sequence of float
        PGA the record is scaled to [g].
    friction : float
        The object's friction coefficient [-] (for the ``slides`` and ``outside_model`` flags).
    threads : int, optional
        Parallel threads (default: numba's setting, all cores).
    progress : callable, optional
        Called with one line per system.

    Returns
    -------
    pandas.DataFrame
        One row per (system, level), in that order, with ``system`` (its index) and
        :data:`RUN_COLUMNS`.
    """
    from ..engine import run_many

    pga = gm.pga_g
    rows = [(si, float(x), float(x) / pga) for si in range(len(systems)) for x in levels_g]
    res = run_many(
        [systems[si] for si, _, _ in rows], gm, [sc for _, _, sc in rows], early_stop=False, threads=threads
    )
    out = []
    for i, (si, x, scale) in enumerate(rows):
        mu = float(res.mu_required[i])
        nmin = float(res.min_normal_over_weight[i])
        jumps = bool(res.jumps[i])
        slides = (not jumps) and mu > friction
        code = int(res.outcome_code[i])
        out.append(
            {
                "system": si,
                "pga_g": x,
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
            }
        )
    if progress is not None:
        for si in range(len(systems)):
            sel = [o for o in out if o["system"] == si]
            n_ov = sum(o["outcome_code"] == 2 for o in sel)
            progress(f"system {si + 1}/{len(systems)}: {len(sel)} runs, {n_ov} overturn")
    return pd.DataFrame(out)


def _p84(v: np.ndarray) -> float:
    return float(np.percentile(v, 84.0)) if v.size else math.nan


def classify_runs(runs: pd.DataFrame, capacity_m: float | None) -> pd.DataFrame:
    """The failure modes of every run, as columns added to a copy of ``runs``.

    ``overturn`` (the object overturns), ``uplift`` (it rocks or overturns), ``exceeds_capacity`` (the
    peak isolator displacement is beyond ``capacity_m`` [m]; never for a fixed base, whose displacement
    is 0), ``failure`` (overturn or beyond the capacity), and, already there, ``outside_model`` (the
    object would slide, ``slides``, or jump, ``jumps``: the rocking model does not describe it).
    """
    out = runs.copy()
    d = out["max_base_disp_m"].to_numpy(dtype=float)
    out["overturn"] = out["outcome_code"].to_numpy() == 2
    out["uplift"] = out["outcome_code"].to_numpy() >= 1
    out["exceeds_capacity"] = (d > capacity_m) if capacity_m else np.zeros(len(out), dtype=bool)
    out["failure"] = out["overturn"].to_numpy() | out["exceeds_capacity"].to_numpy()
    return out


def stripe_table(runs: pd.DataFrame, capacity_m: float | None = None) -> pd.DataFrame:
    """Per intensity level (``pga_g``) of one object and isolation: the runs and what they did.

    Columns: ``n_records``; ``n_overturn``, ``n_uplift`` (rocking or overturn), ``n_exceed_capacity``
    (peak isolator displacement beyond ``capacity_m``), ``n_failure`` (overturn or beyond the capacity),
    counted over every run as ``isorock simulate`` gives it; ``n_outside_model`` (would slide or jump),
    ``n_slides``, ``n_jumps``; ``disp_median_m``, ``disp_p84_m``, ``disp_mean_m``, ``disp_max_m``
    (isolator displacement over the records [m]).
    """
    r = classify_runs(runs, capacity_m)
    out = []
    for x, g in r.groupby("pga_g", sort=True):
        d = g["max_base_disp_m"].to_numpy(dtype=float)
        out.append(
            {
                "pga_g": float(x),
                "n_records": len(g),
                "n_overturn": int(g["overturn"].sum()),
                "n_uplift": int(g["uplift"].sum()),
                "n_exceed_capacity": int(g["exceeds_capacity"].sum()),
                "n_failure": int(g["failure"].sum()),
                "n_outside_model": int(g["outside_model"].sum()),
                "n_slides": int(g["slides"].sum()),
                "n_jumps": int(g["jumps"].sum()),
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
        The runs of one object and case (columns ``record``, ``pga_g`` and :data:`RUN_COLUMNS`).
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
        j = np.flatnonzero(np.isclose(lv, row.pga_g, rtol=1e-12))
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
