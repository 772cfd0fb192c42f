"""isorock.parallel.fork_map: the results of one process, in the order of the tasks, on forked workers."""

from __future__ import annotations

import os

import pytest

from isorock.parallel import fork_map


def _square_and_pid(x: int) -> tuple[int, int]:
    return x * x, os.getpid()


def test_fork_map_returns_the_serial_results_in_order_from_other_processes():
    tasks = list(range(23))
    serial = fork_map(_square_and_pid, tasks, workers=1)
    forked = fork_map(_square_and_pid, tasks, workers=3)
    assert [v for v, _ in forked] == [v for v, _ in serial] == [x * x for x in tasks]
    assert {p for _, p in serial} == {os.getpid()}
    assert os.getpid() not in {p for _, p in forked}  # the work was done by the workers


def test_fork_map_runs_closures_and_in_process_for_one_task_or_one_worker():
    k = 7
    assert fork_map(lambda x: x + k, [1, 2, 3], workers=2) == [8, 9, 10]  # not pickled: inherited
    assert fork_map(_square_and_pid, [4], workers=4)[0][1] == os.getpid()
    assert fork_map(_square_and_pid, [], workers=4) == []


def test_a_fork_map_inside_a_worker_runs_there_and_an_error_reaches_the_caller():
    def inner(x: int) -> list[int]:
        return [v for v, _ in fork_map(_square_and_pid, [x, x + 1], workers=2)]

    assert fork_map(inner, [1, 3], workers=2) == [[1, 4], [9, 16]]

    def fails(x: int) -> int:
        if x == 2:
            raise ValueError("task 2 failed")
        return x

    with pytest.raises(ValueError, match="task 2 failed"):
        fork_map(fails, [1, 2, 3], workers=2)
