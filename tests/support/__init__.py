"""Helpers of the tests: real records (:mod:`support.records`) and closed-form references
(:mod:`support.reference`); importable because ``tests`` is on the test path (pyproject.toml)."""
