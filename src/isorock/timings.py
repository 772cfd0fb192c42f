"""The measured timings that isorock prints and its documentation quotes: the one place they come from.

Every time a user reads ("the main job takes about 3 minutes", "compiling the engine, about 10 s") is
an entry of :data:`TIMINGS`, with the command that measured it and when. The command line's messages,
the documentation site (``docs/_generated/timings.md``, made from this module at every build) and the
README quote these entries; ``tests/packaging/test_docs.py`` checks that the README's figures are
these. Remeasure with the command of an entry and change it here, nowhere else.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Timing", "TIMINGS", "about"]


@dataclass(frozen=True)
class Timing:
    """One measured wall time.

    Attributes
    ----------
    what : str
        What was timed.
    seconds : float
        The wall time measured [s].
    command : str
        The command that measures it, from the repository root of a fresh clone.
    measured_on : str
        When, on what machine and at which state of the code.
    """

    what: str
    seconds: float
    command: str
    measured_on: str

    @property
    def text(self) -> str:
        """The time as people read it, to the precision a noisy machine gives: "about 40 s" (to 5 s
        below a minute), "about 3 min 10 s" (to 10 s below 10 minutes), "about 25 min" above."""
        s = self.seconds
        if s < 60:
            return f"about {max(5, 5 * round(s / 5)):.0f} s"
        if s < 600:
            t = 10 * round(s / 10)
            m, r = divmod(t, 60)
            return f"about {m:.0f} min" + (f" {r:.0f} s" if r else "")
        return f"about {round(s / 60):.0f} min"


_MACHINE = "this project's 2-core CI machine (Debian 12, Python 3.11)"

#: the measured timings, by key
TIMINGS: dict[str, Timing] = {
    "main_job": Timing(
        "The README's main command in a fresh clone with no ../shared: install, compile, the workflow on "
        "the 18 sample records, the report",
        254.0,
        "time (python3 -m venv .venv && .venv/bin/pip install -q --no-deps -r requirements/lock-py311.txt "
        "-e . && .venv/bin/isorock report --cores 2)",
        f"2026-11-29, {_MACHINE}, a fresh clone of d103d5b, issue 34",
    ),
    "tests": Timing(
        "The README's test command (first stage, pytest-xdist on 2 cores), with the real records of "
        "../shared: 2063 passed, 3 skipped",
        231.0,
        "time .venv/bin/python -m pytest",
        f"2026-11-29, {_MACHINE}, inside .ci/run on a fresh clone of 91bd676, issue 34",
    ),
    "e2e": Timing(
        "The second stage: whole workflow runs, the installed wheel, the report in a browser, the "
        "workflow under faults, signals, concurrent and killed additions of records, extreme inputs: "
        "the worked examples at real sites: 75 passed",
        843.0,
        "time .venv/bin/python -m pytest -m e2e",
        f"2026-11-29, {_MACHINE}, inside .ci/run on a fresh clone of 91bd676, issue 34",
    ),
    "statue": Timing(
        "The README's statue (mystatue.yaml of 'Assess your object': 18 sample records, 8 stripes, a "
        "24-isolator grid) assessed warm through the workflow on 2 cores (34.0 s at 314bba9 in the same "
        "run; per rule in the benchmark's table)",
        27.1,
        "python benchmarks/bench_workflow.py --statue --old <worktree of 314bba9>",
        f"2026-12-08, {_MACHINE}, the second part of issue 35 against 314bba9 in one run",
    ),
    "first_analysis": Timing(
        "The first analysis after an install (numba compiles the engine for its isolation model and "
        "mode): the first isorock simulate of a linear isolator, median of 3",
        10.2,
        "python benchmarks/bench_first_run.py --repeat 3",
        f"2026-11-27, {_MACHINE}, a fresh clone, issue 25",
    ),
    "warm_up": Timing(
        "isorock --warm-up: compiles every entry point of the engine and its batch kernel",
        28.4,
        "python benchmarks/bench_first_run.py --repeat 3",
        f"2026-11-27, {_MACHINE}, a fresh clone, issue 25",
    ),
}


def about(key: str) -> str:
    """The time of :data:`TIMINGS` entry ``key`` as people read it ("about 40 s")."""
    return TIMINGS[key].text
