"""Fingerprint of the compiled engine on random cases, to prove a refactoring bit-identical.

    python tests/engine/fingerprint.py OUT.npz [N]          # write N random cases' results (default 1000)
    python tests/engine/fingerprint.py --compare A.npz B.npz [--only-reactions]

The cases are drawn from a fixed seed: every isolation model (none, linear, friction pendulum), every
pulse shape and a synthetic record (a filtered random acceleration, 10 s at 0.01 s), amplitudes from
0.5 to 4 times the uplift threshold, with and without ``early_stop``. Every scalar of each
:class:`isorock.Result` is kept; ``--compare`` requires them equal bit for bit (NaN equal to NaN) and
exits 1 with the first differences otherwise. Run it before and after a change of the engine or of the
code that packs its parameters.

The results are compared field by field, by name: a field that only one of the files holds (a file
written before a field was added) is listed and left out. ``--only-reactions`` leaves out the contact
reactions (:data:`REACTIONS`) too, for a change that is meant to alter them and nothing else; the
differences in them are then counted and shown but do not fail the comparison.
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
    "jumps",
)
REACTIONS = ("mu_required", "min_normal_over_weight", "jumps")
"""The contact reactions (docs/model.md §15), which ``--only-reactions`` lets differ."""


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
    from isorock.physics.engine import simulate

    out = np.empty((n, len(FIELDS)))
    for i, (system, exc, scale, early) in enumerate(cases(n)):
        r = simulate(system, exc, scale=scale, early_stop=early)
        row = {f: getattr(r, f, None) for f in FIELDS}
        row["outcome_code"] = OUTCOMES.index(r.outcome)
        out[i] = [math.nan if row[f] is None else float(row[f]) for f in FIELDS]
    return out


def compare(path_a: str, path_b: str, *, only_reactions: bool = False) -> int:
    """Compare two fingerprints field by field; 0 if equal bit for bit, else 1 (see the module)."""
    fa, fb = np.load(path_a), np.load(path_b)
    a, b = fa["results"], fb["results"]
    names_a, names_b = [str(f) for f in fa["fields"]], [str(f) for f in fb["fields"]]
    if a.shape[0] != b.shape[0]:
        print(f"different numbers of cases: {a.shape[0]} != {b.shape[0]}")
        return 1
    common = [f for f in names_a if f in names_b]
    for f in sorted(set(names_a) ^ set(names_b)):
        print(f"{f}: in one file only, not compared")
    n_bad = 0
    for f in common:
        x, y = a[:, names_a.index(f)], b[:, names_b.index(f)]
        bad = np.nonzero(~((x == y) | (np.isnan(x) & np.isnan(y))))[0]
        if not bad.size:
            continue
        allowed = only_reactions and f in REACTIONS
        print(f"{f}: {bad.size} cases differ" + (" (allowed: --only-reactions)" if allowed else ""))
        for i in bad[:5]:
            print(f"  case {i}: {x[i]!r} != {y[i]!r}")
        n_bad += 0 if allowed else bad.size
    print(f"{a.shape[0]} cases x {len(common)} results compared: {n_bad} differ")
    return 1 if n_bad else 0


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--compare":
        return compare(argv[1], argv[2], only_reactions="--only-reactions" in argv[3:])
    n = int(argv[1]) if len(argv) > 1 else 1000
    np.savez(argv[0], results=fingerprint(n), fields=np.array(FIELDS))
    print(f"wrote {argv[0]}: {n} cases")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
