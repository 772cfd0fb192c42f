"""Independent tasks of one job on several processes: :func:`fork_map`.

The fits of a merge and of a design search's extension, and the figures, are many independent calls
of one function (a candidate's fragilities and their bootstrap, a figure) that hold the GIL; a job
given several cores (its rule's ``threads``) runs them on forked processes. Forked, the workers start
with the job's modules and data already in memory: only each task's index goes to them, and only its
result comes back. Every task is the same call as in one process, so the results are the same numbers
whatever the number of workers.

:class:`concurrent.futures.ProcessPoolExecutor` does the work; this module only keeps the tasks where
the forked workers find them (a module-level list), which an executor of a library would pickle one
by one.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Callable, Iterable
from typing import Any, TypeVar

__all__ = ["fork_map"]

T = TypeVar("T")
R = TypeVar("R")

#: the function and the tasks of the :func:`fork_map` under way (read by the forked workers)
_TASKS: tuple[Callable[[Any], Any], list[Any]] | None = None


def _run(i: int) -> Any:
    assert _TASKS is not None
    fn, items = _TASKS
    return fn(items[i])


def fork_map(fn: Callable[[T], R], items: Iterable[T], workers: int = 1) -> list[R]:
    """``[fn(x) for x in items]``, on up to ``workers`` forked processes.

    Parameters
    ----------
    fn : callable
        Applied to every item; its results must pickle (they come back from the workers).
    items : iterable
        The tasks (not pickled: the workers inherit them).
    workers : int
        Processes [-]; 1 (or one task, or a platform without ``fork``): in this process.

    Returns
    -------
    list
        The results, in the order of ``items``.
    """
    global _TASKS
    tasks = list(items)
    n = min(int(workers), len(tasks))
    if n <= 1 or "fork" not in multiprocessing.get_all_start_methods() or _TASKS is not None:
        return [fn(x) for x in tasks]
    from concurrent.futures import ProcessPoolExecutor

    _TASKS = (fn, tasks)
    try:
        with ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("fork")) as pool:
            return list(pool.map(_run, range(len(tasks))))
    finally:
        _TASKS = None
