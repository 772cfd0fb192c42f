"""Design candidates with evaluations built from designed resamples (tests of the design decision and of
its words): each test controls what the paired and the unpaired rules see."""

from __future__ import annotations

import numpy as np
import pandas as pd

from isorock.assessment.case import CaseEvaluation
from isorock.assessment.design import Candidate
from isorock.assessment.fragility import clopper_pearson, resample_weights


def candidate(
    name,
    source,
    samples,
    est=None,
    period=None,
    within=True,
    grid=None,
    shape=None,
    observed=None,
    fitted=True,
    p_mce=None,
    n=20,
):
    """A candidate with these resampled values of P(failure) at the design level (fitted, unless
    ``fitted`` is False); ``observed``: (count of failing records of 20, resampled fractions) at that
    level (default: 1 of 20, :func:`observed` of record 0); ``p_mce``: (estimate, [lo, hi]) of P(failure) at
    the MCE (default: the design level's estimate and interval, so that the target of 10 % is met where
    the estimate is at most 10 %)."""
    s = np.asarray(samples, dtype=float)
    e = float(np.median(s)) if est is None else est
    lo, hi = np.percentile(s, [2.5, 97.5])
    z, obs = observed if observed is not None else _observed([0], n_boot=s.size, n=n)
    lvl = {
        "level": 0.3, "p_failure": e if fitted else None,
        "p_failure_ci95": [float(lo), float(hi)] if fitted else None,
        "p_failure_observed": z / n, "p_failure_observed_ci95": list(clopper_pearson(z, n)),
        "p_failure_upper95": clopper_pearson(z, n, side="upper")[1], "n_failure_observed": z,
        "n_failure_counted": n, "p_overturn": None, "estimable": fitted, "mce_g": 0.45,
        "disp_mce_m": 0.0 if source == "floor" else 0.1, "mce_within_capacity": within,
        "disp_mce_ci95_m": None if source == "floor" else [0.08, 0.12], "n_mce_records": 20,
        "disp_mce_statistic": "fixed base" if source == "floor" else "mean of 20 records",
        "n_mce_overturn": 3 if source == "floor" else 1,
        "n_mce_exceed_capacity": 0 if source == "floor" else 2,
        "p_mce_exceed_capacity": None if source == "floor" else 0.1,
        "p_failure_mce": (p_mce or (e, [float(lo), float(hi)]))[0],
        "p_failure_mce_ci95": (p_mce or (e, [float(lo), float(hi)]))[1],
        "gamma_x": 1.2, "disp_mce_factored_m": 0.0 if source == "floor" else 0.12, "disp_fractile": 0.9,
        "disp_mce_fractile_m": 0.0 if source == "floor" else 0.11,
        "p_failure_mce_basis": "fitted", "n_failure_mce_observed": 1, "n_failure_mce_counted": 20,
    }  # fmt: skip
    ev = CaseEvaluation(
        stripes=pd.DataFrame(), estimates={}, levels=[lvl], hazard=None, n_records=n, n_excluded=0,
        records=[f"r{i}" for i in range(n)],
        samples={"p_failure_fitted": [s if fitted else None], "p_failure_observed": [np.asarray(obs, float)]},
    )  # fmt: skip
    kind = "none" if source == "floor" else "linear"
    params = {"isolation": kind, "Tb_s": period, "xi_b": None if period is None else 0.2, "mu_b": None,
              "R_b_m": None, "rho": None if period is None else 0.5}  # fmt: skip
    c = Candidate(name, source, params, pd.DataFrame({"record": []}), grid, shape)
    c.evaluation = ev
    return c


def _observed(fails, n_boot, n=20):
    return observed(fails, n=n, n_boot=n_boot)


def observed(fails: list[int], n: int = 20, n_boot: int = 2000, seed: int = 0) -> tuple[int, np.ndarray]:
    """(count, resampled fractions) of the failing records ``fails`` among ``n`` records, on the resamples
    of :func:`isorock.assessment.fragility.resample_weights` (the same for every call with ``seed``)."""
    W = resample_weights(n, n_boot, seed)
    f = np.zeros(n)
    f[list(fails)] = 1.0
    return len(fails), (W @ f) / n
