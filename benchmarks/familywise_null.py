"""The null simulation of the design search's test (issue 31), with its rates printed.

Sites where every isolator has the fixed base's fragility (median 0.54 g, beta 0.33), 17 records, the
worked example's stripes, 24 isolators, the correlations of the stored runs: the share of sites in
which the search would call an isolator better than the fixed base, by the familywise test
(Westfall-Young max-T, :func:`isorock.assessment.paired.familywise`), by one comparison alone
(:func:`~isorock.assessment.paired.one_sided_p`), and by the rule of earlier versions (better in 95 %
of the resamples, candidate by candidate). The simulation is the one of
``tests/assessment/test_familywise.py``, which asserts the bounds; this script prints the rates.

Run: ``.venv/bin/python benchmarks/familywise_null.py [--sites 120]`` (about 30 s per 120 sites).
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _simulation():
    spec = importlib.util.spec_from_file_location(
        "familywise_sim", ROOT / "tests/assessment/test_familywise.py"
    )
    mod = importlib.util.module_from_spec(spec)
    sys.modules["familywise_sim"] = mod
    spec.loader.exec_module(mod)
    return mod


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sites", type=int, default=120, help="null sites simulated (default 120)")
    ap.add_argument("--seed", type=int, default=20261129, help="seed of the sites (the test's)")
    args = ap.parse_args()
    from isorock.assessment.fragility import resample_weights
    from isorock.assessment.paired import ALPHA, familywise, one_sided_p

    sim = _simulation()
    rng = np.random.default_rng(args.seed)
    W = resample_weights(sim.N_RECORDS, sim.N_BOOT, 0)
    sites = [s for s in (sim._site(rng, W) for _ in range(args.sites)) if s is not None]
    n = len(sites)
    fw = sum(
        any(p is not None and p <= ALPHA and d < 0 for p, d in zip(familywise(a, b), a, strict=True))
        for a, b in sites
    )
    one = sum((p := one_sided_p(a[0], b[0])) is not None and p <= ALPHA and a[0] < 0 for a, b in sites)
    old = sum(any(d < 0 and np.mean(s < 0) >= 0.95 for d, s in zip(a, b, strict=True)) for a, b in sites)
    se = math.sqrt(ALPHA * (1 - ALPHA) / n)
    print(f"{n} null sites, {sim.N_ISOLATORS} isolators, {sim.N_RECORDS} records, {sim.N_BOOT} resamples")
    print(f"familywise test (max-T):       {fw / n:.3f}  ({fw} sites)")
    print(f"one comparison (p_single):     {one / n:.3f}  ({one} sites)")
    print(f"earlier rule (95 % of resamples): {old / n:.3f}  ({old} sites)")
    print(f"nominal {ALPHA:.2f}, Monte Carlo standard error {se:.3f}")


if __name__ == "__main__":
    main()
