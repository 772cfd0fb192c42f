"""Speed of the compiled engine against the scipy oracle, measured in one run.

Cases (issue #2):
  (a) a 0.5 s full-sine pulse, linear isolation, a block that rocks;
  (b) a 40 s sampled record at dt = 0.005 s, linear isolation, a block that rocks.
Also reported: the same record with no isolation and with the FP isolator (rocking analysis, and
the sliding mode: ``friction`` below ``tan(alpha)``).

The record is synthetic and deterministic (band-limited noise under an envelope plus a
velocity pulse), so that the benchmark runs on a fresh clone without record files.

Usage::

    python benchmarks/bench_engine.py [--repeat 50] [--oracle-repeat 3] [--json out.json]
    python benchmarks/bench_engine.py --baseline-tree ../base --cases FP [--rounds 7] [--repeat 50]

``--baseline-tree PATH`` times the engine of another source tree (``PATH/src``, e.g. a
``git worktree`` of the commit to compare with) against this one on the same cases: each of
``--rounds`` rounds runs both in fresh subprocesses of this script, alternating which goes first,
and the table gives the median over the rounds of each one's median time and the median of the
rounds' ratios new / old (the two runs of a round are back to back: the ratio of a round is the least
disturbed by the machine's load).
``--cases TEXT`` keeps the cases whose name contains ``TEXT``.

Absolute times depend on the machine; quote the ratios, which are measured in the same run.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from isorock import Block, FPIsolation, GroundMotion, LinearIsolation, Pulse, System

try:
    from isorock.physics.engine import simulate
except ModuleNotFoundError:  # a --baseline-tree from before the physics room (isorock.engine then)
    from isorock.engine import simulate  # type: ignore[no-redef]


def synthetic_record(duration: float = 40.0, dt: float = 0.005, seed: int = 1) -> GroundMotion:
    """Deterministic 40 s accelerogram with a strong-motion envelope and a 1.5 s velocity pulse [m/s^2]."""
    from scipy.signal import butter, sosfiltfilt

    rng = np.random.default_rng(seed)
    n = int(round(duration / dt)) + 1
    t = np.arange(n) * dt
    sos = butter(4, [0.2, 10.0], btype="band", fs=1.0 / dt, output="sos")
    noise = sosfiltfilt(sos, rng.standard_normal(n))
    env = (t / 3.0) ** 2 * np.exp(-t / 3.0) / (4.0 * np.exp(-2.0))
    acc = noise / np.max(np.abs(noise)) * env + 0.6 * np.sin(2 * np.pi * t / 1.5) * np.exp(
        -(((t - 8.0) / 1.5) ** 2)
    )
    acc = acc / np.max(np.abs(acc)) * 9.81
    return GroundMotion(dt, acc, "synthetic-40s")


def timed(fn, repeat: int) -> tuple[float, object]:
    """Median wall time of ``fn()`` over ``repeat`` calls [s], and its last result."""
    times = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def cases() -> list[tuple[str, System, object, float, dict]]:
    """The timed cases: name, system, excitation, scale and the extra arguments of ``simulate``."""
    rec = synthetic_record()
    lin = LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5)
    fp = System(Block.from_lambda_R(4.0, 1.5), FPIsolation(0.11, 2.24, 0.5))
    return [
        (
            "(a) full-sine 0.5 s, linear",
            System(Block.from_lambda_R(4.0, 1.0), lin),
            Pulse("fullsine", 0.5, 0.55),
            1.0,
            {},
        ),
        ("(b) 40 s record, linear", System(Block.from_lambda_R(4.0, 1.5), lin), rec, 0.7, {}),
        ("(c) 40 s record, none", System(Block.from_lambda_R(4.0, 1.5)), rec, 0.3, {}),
        ("(d) 40 s record, FP", fp, rec, 0.5, {}),
        # tan(alpha) = 0.25: the object slides on the base (the contact loop runs it while it sticks)
        ("(e) 40 s record, FP, sliding 0.15", fp, rec, 0.5, {"friction": 0.15}),
    ]


def _worker(names: list[str], repeat: int) -> None:
    """Print, as one JSON line, the median engine time [s] of each named case (the subprocess of
    ``--baseline-tree``, run with the ``isorock`` of the tree being timed on its path)."""
    import isorock

    selected = [c for c in cases() if c[0] in names]
    for _, system, exc, scale, kw in selected:
        simulate(system, exc, scale=scale, **kw)  # compile (or load the cache) outside the timings
    out = {"isorock": isorock.__file__}
    for name, system, exc, scale, kw in selected:
        out[name] = timed(lambda s=system, e=exc, k=scale, w=kw: simulate(s, e, scale=k, **w), repeat)[0]
    print(json.dumps(out))


def _run_tree(src: Path, names: list[str], repeat: int) -> dict:
    """:func:`_worker` in a subprocess with ``src`` first on the path."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(src), os.environ.get("PYTHONPATH", "")]))
    cmd = [sys.executable, __file__, "--worker", json.dumps(names), "--repeat", str(repeat)]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    expect = (src / "isorock" / "__init__.py").resolve()
    if Path(out.pop("isorock")).resolve() != expect:
        raise SystemExit(f"the subprocess did not import the isorock of {src}")
    return out


def compare_trees(baseline: Path, names: list[str], rounds: int, repeat: int, json_path: str | None) -> None:
    """Old (``baseline/src``) against new (this tree's ``src``), alternated over ``rounds`` rounds."""
    new_src = Path(__file__).resolve().parents[1] / "src"
    old_src = baseline.resolve() / "src"
    if not (old_src / "isorock").is_dir():
        raise SystemExit(f"{old_src} holds no isorock package")
    times: dict[str, dict[str, list[float]]] = {n: {"old": [], "new": []} for n in names}
    for r in range(rounds):
        order = (("old", old_src), ("new", new_src)) if r % 2 == 0 else (("new", new_src), ("old", old_src))
        for tag, src in order:
            for n, t in _run_tree(src, names, repeat).items():
                times[n][tag].append(t)
    print(f"old: {old_src}\nnew: {new_src}")
    print(f"{rounds} rounds x {repeat} runs per case; times: the median over the rounds of each median;")
    print("new/old: the median of the rounds' ratios (old and new of a round run back to back)")
    print(f"{'case':36s} {'old ms':>9s} {'new ms':>9s} {'new/old':>8s}  per-round ratios")
    rows = []
    for n in names:
        old, new = statistics.median(times[n]["old"]), statistics.median(times[n]["new"])
        per = [b / a for a, b in zip(times[n]["old"], times[n]["new"], strict=True)]
        ratio = statistics.median(per)
        rows.append({"case": n, "old_ms": 1e3 * old, "new_ms": 1e3 * new, "ratio": ratio, "rounds": per})
        print(f"{n:36s} {1e3 * old:9.3f} {1e3 * new:9.3f} {ratio:8.3f}  " + " ".join(f"{x:.3f}" for x in per))
    if json_path:
        with open(json_path, "w") as fh:
            json.dump(rows, fh, indent=2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=50, help="engine runs per case")
    ap.add_argument("--oracle-repeat", type=int, default=3, help="oracle runs per case")
    ap.add_argument("--no-oracle", action="store_true", help="time the engine only")
    ap.add_argument("--json", help="write the figures to this JSON file")
    ap.add_argument("--cases", default="", help="only the cases whose name contains this text")
    ap.add_argument("--baseline-tree", type=Path, help="time this source tree too (old vs new)")
    ap.add_argument("--rounds", type=int, default=7, help="alternations old/new with --baseline-tree")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    a = ap.parse_args()

    if a.worker is not None:
        _worker(json.loads(a.worker), a.repeat)
        return
    selected = [c for c in cases() if a.cases in c[0]]
    if a.baseline_tree is not None:
        compare_trees(a.baseline_tree, [c[0] for c in selected], a.rounds, a.repeat, a.json)
        return
    oracle = None
    if not a.no_oracle:
        from isorock.physics.engine import oracle as oracle_mod

        oracle = oracle_mod.simulate

    for _, system, exc, scale, kw in selected:
        simulate(system, exc, scale=scale, **kw)  # compile (or load the cache) outside the timings
    rows = []
    print(f"{'case':34s} {'outcome':10s} {'engine ms':>10s} {'an./s':>9s} {'oracle ms':>11s} {'ratio':>8s}")
    for name, system, exc, scale, kw in selected:
        t_e, r_e = timed(lambda s=system, e=exc, k=scale, w=kw: simulate(s, e, scale=k, **w), a.repeat)
        row = {
            "case": name,
            "outcome": r_e.outcome,
            "max_theta_over_alpha": r_e.max_theta_over_alpha,
            "engine_ms": 1e3 * t_e,
            "engine_per_s": 1.0 / t_e,
        }
        if oracle is not None and not kw:
            ex = exc.scaled(scale) if isinstance(exc, GroundMotion) else exc
            t_o, r_o = timed(lambda s=system, e=ex: oracle(s, e), a.oracle_repeat)
            row.update(
                oracle_ms=1e3 * t_o,
                oracle_outcome=r_o.outcome,
                ratio=t_o / t_e,
                oracle_max_theta_over_alpha=r_o.max_theta_over_alpha,
            )
        rows.append(row)
        o_ms = f"{row['oracle_ms']:11.1f}" if "oracle_ms" in row else f"{'-':>11s}"
        ratio = f"{row['ratio']:8.0f}" if "ratio" in row else f"{'-':>8s}"
        print(
            f"{name:34s} {r_e.outcome:10s} {row['engine_ms']:10.3f} {row['engine_per_s']:9.0f} {o_ms} {ratio}"
        )
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=2)


if __name__ == "__main__":
    main()
