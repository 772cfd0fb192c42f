"""The isolation design search: the isolators of a grid, ranked by the probability of overturning
among those whose displacement stays within the capacity.

:func:`design_table` fits, for each isolator of the grid,
the fragility of overturning on the stripes and gives the probability and the 84th-percentile
displacement at each design level; :func:`recommend` ranks them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from ..model import Isolation
from .fragility import fit_fragility
from .stripes import _p84, stripe_table

__all__ = ["design_table", "recommend"]


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
