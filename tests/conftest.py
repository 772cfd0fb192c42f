"""Shared fixtures of the test suite.

The tests mirror the package (``tests/engine`` tests ``isorock.physics.engine``, ...). Helpers importable by
every test module live in ``tests/support`` (``support.records``: the real records directory and its
manifest; ``support.reference``: the closed-form references of docs/model.md §14).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from support import records as _records


@pytest.fixture
def records_dir() -> Path:
    """The real records directory (``$ISOROCK_RECORDS``, else ``../shared/records``); skips when absent."""
    return _records.need_records()


@pytest.fixture(scope="session")
def data_dir() -> Path:
    """The small record files of the tests (``tests/data/good``, ``tests/data/bad``)."""
    return _records.DATA
