"""Assessment of a real object: multiple-stripe analysis, fragility, isolator displacement, validity,
and the choice of an isolator.

An object (a statue, a cabinet) is a rigid block of full height ``h`` and width ``w`` (in the direction
it may rock): slenderness ``lambda = h / w``, size ``R = sqrt(h^2 + w^2) / 2``, with a friction
coefficient ``mu`` against its floor. Every record, processed as everywhere else, is scaled to each
intensity level (a *stripe*: the record's PGA set to the level) and analysed in a full run
(:func:`isorock.engine.simulate` semantics: peaks and reactions over the whole motion, the free
vibration included). Per run: the outcome, ``max theta / alpha``, the peak isolator displacement and
the contact-force demands ``mu_required`` and ``min_normal_over_weight``
(:class:`isorock.result.Result`): a run is *outside the model* when ``mu_required > mu`` (the object
would slide) or the normal force vanishes (it would jump).

From the stripes (:func:`stripe_table`): per level the counts of overturning and uplift, the median
and 84th-percentile isolator displacement. :func:`fragility_rows` fits lognormal fragility functions
(:func:`isorock.fragility.fit_fragility`, Baker 2015) for overturning and for uplift;
:func:`design_level_rows` gives, at each design level, the probabilities from the fits, the displacement
demand and the fraction of records that exceed the isolator's displacement capacity. The design search
(:func:`design_table`, :func:`recommend`) repeats this over a grid of isolators and picks the one with
the lowest probability of overturning whose 84th-percentile displacement stays within the capacity.

The analyses of one record run in parallel threads (:func:`isorock.engine.kernel.run_many`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd

from .excitation import GroundMotion
from .fragility import fit_fragility
from .model import Block, Isolation, System

__all__ = [
    "AssessedObject",
    "run_levels",
    "stripe_table",
    "fragility_rows",
    "design_level_rows",
    "design_table",
    "recommend",
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
    progress : callable, optional
        Called with one line per system.

    Returns
    -------
    pandas.DataFrame
        One row per (system, level), in that order, with ``system`` (its index) and
        :data:`RUN_COLUMNS`.
    """
    from .constants import OUTCOMES
    from .engine import kernel as K
    from .engine import pack_parameters

    pga = gm.pga_g
    rows = []
    ekind, acc = None, None
    Ps = []
    for si, system in enumerate(systems):
        for x in levels_g:
            P, ekind, acc = pack_parameters(system, gm, scale=float(x) / pga, early_stop=False)
            Ps.append(P)
            rows.append((si, float(x), float(x) / pga))
    res = K.run_many(np.ascontiguousarray(np.array(Ps)), ekind, acc)
    out = []
    for (si, x, scale), r in zip(rows, res, strict=True):
        mu = float(r[K.R_MUREQ])
        nmin = float(r[K.R_NMIN])
        slides, jumps = mu > friction, nmin <= 0.0
        code = int(r[K.R_OUTCOME])
        out.append(
            {
                "system": si,
                "pga_g": x,
                "scale": scale,
                "outcome": OUTCOMES[code],
                "outcome_code": code,
                "max_theta_over_alpha": float(r[K.R_MAXTH]),
                "max_base_disp_m": float(r[K.R_MAXU]),
                "mu_required": mu,
                "min_normal_over_weight": nmin,
                "slides": bool(slides),
                "jumps": bool(jumps),
                "outside_model": bool(slides or jumps),
                "decided": bool(r[K.R_DECIDED]),
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


def stripe_table(runs: pd.DataFrame, capacity_m: float | None = None) -> pd.DataFrame:
    """Per intensity level (``pga_g``) of one object and isolation: ``n_records``, ``n_overturn``,
    ``n_uplift`` (rocking or overturn), ``disp_median_m``, ``disp_p84_m`` (isolator displacement over
    the records [m]), ``n_exceed_capacity`` (records whose displacement exceeds ``capacity_m``) and
    ``n_outside_model``."""
    out = []
    for x, g in runs.groupby("pga_g", sort=True):
        d = g["max_base_disp_m"].to_numpy(dtype=float)
        out.append(
            {
                "pga_g": float(x),
                "n_records": len(g),
                "n_overturn": int((g["outcome_code"] == 2).sum()),
                "n_uplift": int((g["outcome_code"] >= 1).sum()),
                "disp_median_m": float(np.median(d)),
                "disp_p84_m": _p84(d),
                "n_exceed_capacity": int((d > capacity_m).sum()) if capacity_m else 0,
                "n_outside_model": int(g["outside_model"].sum()),
            }
        )
    return pd.DataFrame(out)


def fragility_rows(stripes: pd.DataFrame) -> list[dict[str, Any]]:
    """Lognormal fragility of overturning and of uplift from a :func:`stripe_table` [g]."""
    out = []
    for damage, col in (("overturn", "n_overturn"), ("uplift", "n_uplift")):
        f = fit_fragility(stripes["pga_g"], stripes["n_records"], stripes[col])
        out.append(
            {
                "damage": damage,
                "median_g": f.median,
                "beta": f.beta,
                "n_levels": f.n_levels,
                "n_runs": f.n_runs,
                "n_damaged": f.n_damaged,
                "note": f.note,
                "_fit": f,
            }
        )
    return out


def design_level_rows(
    stripes: pd.DataFrame,
    design_runs: pd.DataFrame,
    fits: Mapping[str, Any],
    design_g: Iterable[float],
    capacity_m: float | None,
) -> list[dict[str, Any]]:
    """At each design level [g]: ``p_overturn`` and ``p_uplift`` from the fitted fragilities, the
    fractions observed (``p_overturn_observed``), the median and 84th-percentile displacement [m],
    and the fraction of records whose displacement exceeds the capacity."""
    out = []
    for x in design_g:
        g = design_runs[np.isclose(design_runs["pga_g"], x, rtol=1e-12)]
        d = g["max_base_disp_m"].to_numpy(dtype=float)
        n = len(g)
        out.append(
            {
                "pga_g": float(x),
                "p_overturn": float(fits["overturn"].probability(x)),
                "p_uplift": float(fits["uplift"].probability(x)),
                "p_overturn_observed": float((g["outcome_code"] == 2).mean()) if n else math.nan,
                "disp_median_m": float(np.median(d)) if n else math.nan,
                "disp_p84_m": _p84(d),
                "frac_exceed_capacity": float((d > capacity_m).mean()) if (n and capacity_m) else math.nan,
                "n_records": n,
            }
        )
    return out


def design_table(
    runs: pd.DataFrame,
    isolations: Sequence[Isolation],
    stripes_g: Sequence[float],
    design_g: Sequence[float],
    capacity_m: float | None,
) -> pd.DataFrame:
    """One row per isolator of the grid and design level: fragility of overturning (fitted on the
    stripes), ``p_overturn`` at the level, ``disp_p84_m`` there and ``within_capacity``.

    ``runs`` holds the runs of every record on every isolator (column ``system``, the isolator's index
    in ``isolations``) at the stripes and design levels.
    """
    out = []
    stripes = np.asarray(stripes_g, dtype=float)
    for si, iso in enumerate(isolations):
        r = runs[runs["system"] == si]
        on_stripe = np.isclose(r["pga_g"].to_numpy(dtype=float)[:, None], stripes[None, :], rtol=1e-12).any(
            axis=1
        )
        st = stripe_table(r[on_stripe], capacity_m)
        f = fit_fragility(st["pga_g"], st["n_records"], st["n_overturn"])
        for x in design_g:
            d = r[np.isclose(r["pga_g"], x, rtol=1e-12)]["max_base_disp_m"].to_numpy(dtype=float)
            p84 = _p84(d)
            out.append(
                {
                    "isolator": si,
                    "isolation": iso.kind,
                    "Tb_s": float(iso.Tb) if iso.kind != "none" else math.nan,
                    "xi_b": float(getattr(iso, "xi_b", math.nan)) if iso.kind == "linear" else math.nan,
                    "mu_b": float(iso.mu_b) if iso.kind == "fp" else math.nan,
                    "R_b_m": float(iso.R_b) if iso.kind == "fp" else math.nan,
                    "design_g": float(x),
                    "median_g": f.median,
                    "beta": f.beta,
                    "p_overturn": float(f.probability(x)),
                    "disp_p84_m": p84,
                    "within_capacity": bool(capacity_m is None or p84 <= capacity_m),
                    "n_records": int(d.size),
                }
            )
    return pd.DataFrame(out)


def recommend(design: pd.DataFrame, n: int = 3) -> pd.DataFrame:
    """Per design level, the isolators within capacity ranked by ``p_overturn`` (then by the
    displacement): column ``rank`` 1 is the recommended one, 2 and 3 the runners-up; 0 = not ranked."""
    design = design.copy()
    design["rank"] = 0
    for _x, g in design.groupby("design_g"):
        ok = g[g["within_capacity"]].sort_values(["p_overturn", "disp_p84_m"], kind="stable")
        for k, idx in enumerate(ok.index[:n], start=1):
            design.loc[idx, "rank"] = k
    return design
