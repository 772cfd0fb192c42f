"""Records processed in batches (rule process_record: one job per batch, isorock.pipeline.process_batches):
every record in exactly one batch, the same batches every time, and a batch job writes what one job per
record writes."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from isorock import pipeline
from isorock.errors import ConfigError
from isorock.resources import workflow_root


@pytest.mark.parametrize("n", [0, 1, 2, 3, 5, 18, 19, 20, 21, 40, 41, 97])
@pytest.mark.parametrize("per_job", [1, 2, 7, 20])
@pytest.mark.parametrize("spread", [1, 2, 3, 8])
def test_every_record_in_one_batch_in_order_of_balanced_sizes(n, per_job, spread):
    ids = [f"r{k:03d}" for k in range(n)]
    batches = pipeline.process_batches(ids, per_job, spread)
    assert batches == pipeline.process_batches(list(ids), per_job, spread)  # deterministic
    assert list(batches) == [f"p{k}" for k in range(len(batches))]
    assert [r for b in batches.values() for r in b] == ids  # each record once, in the run's order
    sizes = [len(b) for b in batches.values()]
    assert all(1 <= s <= per_job for s in sizes)
    assert not sizes or max(sizes) - min(sizes) <= 1
    assert len(batches) >= min(spread, n)  # every core busy where there are records enough


def test_the_readme_statue_is_two_jobs_on_two_threads():
    ids = [f"r{k}" for k in range(18)]
    assert [len(b) for b in pipeline.process_batches(ids, 20, 2).values()] == [9, 9]


def test_a_spread_below_one_is_refused():
    with pytest.raises(ConfigError, match="map_threads"):
        pipeline.process_batches(["a"], 20, 0)
    with pytest.raises(ConfigError, match="records_per_job"):
        pipeline.process_batches(["a"], 0, 2)


def _compare_stores():
    path = workflow_root() / "tests" / "cluster" / "compare_stores.py"
    spec = importlib.util.spec_from_file_location("compare_stores", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("compare_stores", mod)
    spec.loader.exec_module(mod)
    return mod


def test_a_batch_job_writes_what_one_job_per_record_writes(tmp_path, monkeypatch):
    """process_records over three sample records gives, file for file, the numbers of process_record
    then extract_pulse of each record alone (compare_stores: every dataset and attribute but the
    provenance, such as each job's seconds)."""
    pytest.importorskip("pyslammer")
    monkeypatch.delenv("ISOROCK_RECORDS", raising=False)  # the samples, with or without ../shared
    cfg = pipeline.load_config({})
    plan = pipeline.plan(cfg, basedir=tmp_path)
    specs = plan.records[:3]
    assert len(specs) == 3 and plan.source == "pyslammer samples"
    batch = [pipeline.params_process(cfg, s, plan.processing) for s in specs]
    recs = [tmp_path / "batch" / f"{s.id}.h5" for s in specs]
    pulses = [tmp_path / "batch" / f"{s.id}.pulse.h5" for s in specs]
    recs[0].parent.mkdir()
    pipeline.process_records(batch, recs, pulses, pulse=pipeline.params_pulse(cfg))
    compare = _compare_stores().compare
    for s, p, rec, pul in zip(specs, batch, recs, pulses, strict=True):
        one = tmp_path / "one" / s.id
        one.mkdir(parents=True)
        pipeline.process_record(out=one / "rec.h5", **p)
        pipeline.extract_pulse(one / "rec.h5", one / "pulse.h5", **pipeline.params_pulse(cfg))
        for a, b in ((one / "rec.h5", rec), (one / "pulse.h5", pul)):
            n, diffs = compare(str(a), str(b))
            assert n > 0 and diffs == [], (s.id, diffs[:5])


def test_a_batch_needs_two_files_per_record(tmp_path):
    with pytest.raises(pipeline_error(), match="one of each per record"):
        pipeline.process_records([{}], [tmp_path / "a.h5"], [], pulse={})


def pipeline_error():
    from isorock.errors import IsorockError

    return IsorockError


def test_the_rules_name_the_batches_of_the_plan():
    """The workflow defines one process_record rule per batch, with the batches of the plan."""
    text = (workflow_root() / "workflow" / "rules" / "records.smk").read_text()
    assert "for _batch, _ids in PROCESS_BATCHES.items():" in text
    assert 'f"process_record_{_batch}"' in text
    common = (workflow_root() / "workflow" / "rules" / "common.smk").read_text()
    assert "pipeline.process_batches(RECORDS" in common
    assert Path(workflow_root() / "workflow" / "scripts" / "process_record.py").is_file()
