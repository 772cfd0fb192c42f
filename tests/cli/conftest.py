"""Fixtures of the command-line tests."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture
def plain_file(tmp_path):
    """A headerless one-column record in g: one 1 s full-sine cycle of 0.5 g, then 5 s of rest."""
    t = np.arange(0, 6, 0.01)
    f = tmp_path / "rec.txt"
    np.savetxt(f, 0.5 * np.sin(2 * np.pi * t / 1.0) * (t < 1.0))
    return f
