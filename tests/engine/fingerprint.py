"""Fingerprint of the compiled engine on random cases, to prove a refactoring bit-identical.

    python tests/engine/fingerprint.py OUT.npz [N]          # write N random cases' results (default 1000)
    python tests/engine/fingerprint.py --compare A.npz B.npz

The cases are drawn from a fixed seed: every isolation model (none, linear, friction pendulum), every
pulse shape and a synthetic record (a filtered random acceleration, 10 s at 0.01 s), amplitudes from
0.5 to 4 times the uplift threshold, with and without ``early_stop``. Every scalar of each
:class:`isorock.Result` is kept; ``--compare`` requires them equal bit for bit (NaN equal to NaN) and
exits 1 with the first differences otherwise. Run it before and after a change of the engine or of the
code that packs its parameters.
"""

from __future__ import annotations

import math
import sys

import numpy as np

FIELDS = (
    "outcome_code",
    "max_theta_over_alpha",
    "n_impacts",
    "max_base_disp_m",
    "t_uplift_s",
    "t_overturn_s",
    "t_end_s",
    "decided",
    "n_steps",
    "stalls",
    "mu_required",
    "min_normal_over_weight",
)


def _record(rng: np.random.Generator):
    from isorock import GroundMotion

    raw = rng.standard_normal(1000)
    kernel = np.exp(-0.5 * (np.arange(-30, 31) / 8.0) ** 2)
    acc = np.convolve(raw, kernel, mode="same") * np.hanning(1000)
    return GroundMotion(0.01, acc / np.max(np.abs(acc)), name="synthetic")


def cases(n: int, seed: int = 20261125):
    """``n`` random (system, excitation, scale, early_stop) tuples."""
    from isorock import Block, FPIsolation, LinearIsolation, NoIsolation, Pulse, System
    from isorock.constants import G

    rng = np.random.default_rng(seed)
    gm = _record(rng)
    for i in range(n):
        kind = ("none", "linear", "fp")[i % 3]
        rho = float(rng.uniform(0.2, 2.0))
        if kind == "none":
            iso = NoIsolation()
        elif kind == "linear":
            iso = LinearIsolation(Tb=float(rng.uniform(1.0, 4.0)), xi_b=float(rng.uniform(0.0, 0.5)), rho=rho)
        else:
            iso = FPIsolation.from_period(
                mu_b=float(rng.uniform(0.05, 0.15)), Tb=float(rng.uniform(2.0, 4.0)), rho=rho
            )
        lam = float(rng.uniform(1.5, 8.0))
        R = float(np.exp(rng.uniform(math.log(0.3), math.log(10.0))))
        system = System(Block.from_lambda_R(lam, R), iso)
        amp = system.block.tan_alpha * float(rng.uniform(0.5, 4.0))
        early = bool(rng.integers(2))
        if i % 4 == 3:
            yield system, gm, amp * G, early
        else:
            shape = ("rect", "halfsine", "fullsine")[int(rng.integers(3))]
            td = float(np.exp(rng.uniform(math.log(0.1), math.log(2.0))))
            yield system, Pulse(shape, td, amp), 1.0, early


def fingerprint(n: int) -> np.ndarray:
    """Results of the ``n`` cases, one row each, columns :data:`FIELDS`."""
    from isorock.constants import OUTCOMES
    from isorock.engine import simulate

    out = np.empty((n, len(FIELDS)))
    for i, (system, exc, scale, early) in enumerate(cases(n)):
        r = simulate(system, exc, scale=scale, early_stop=early)
        row = {f: getattr(r, f, None) for f in FIELDS}
        row["outcome_code"] = OUTCOMES.index(r.outcome)
        out[i] = [math.nan if row[f] is None else float(row[f]) for f in FIELDS]
    return out


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--compare":
        a, b = np.load(argv[1])["results"], np.load(argv[2])["results"]
        if a.shape != b.shape:
            print(f"different numbers of cases: {a.shape} != {b.shape}")
            return 1
        bad = np.argwhere(~((a == b) | (np.isnan(a) & np.isnan(b))))
        for i, j in bad[:20]:
            print(f"case {i} {FIELDS[j]}: {a[i, j]!r} != {b[i, j]!r}")
        print(f"{a.shape[0]} cases x {a.shape[1]} results: {len(bad)} differ")
        return 1 if len(bad) else 0
    n = int(argv[1]) if len(argv) > 1 else 1000
    np.savez(argv[0], results=fingerprint(n), fields=np.array(FIELDS))
    print(f"wrote {argv[0]}: {n} cases")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
