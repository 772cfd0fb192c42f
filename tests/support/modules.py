"""A module of the tests loaded from its file (the independent oracles beside their tests)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType


def load_beside(test_file: str, name: str) -> ModuleType:
    """The module ``name`` (``name.py`` in the folder of ``test_file``), registered in ``sys.modules``
    (the dataclasses of a module look themselves up there)."""
    spec = importlib.util.spec_from_file_location(name, Path(test_file).with_name(f"{name}.py"))
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod
