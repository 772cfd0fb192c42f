"""``isorock info --versions``: the versions of Python, the numerical packages and the platform, with no
record (isorock.cli.signal, isorock.environment)."""

from __future__ import annotations

from isorock.environment import versions
from support.cli import run_cli, run_json


def test_versions_prints_one_name_version_line_each():
    out = run_cli(["info", "--versions"])
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    v = versions()
    assert lines == [f"{name} {text}" for name, text in v.items()]
    assert [line.split(" ", 1)[0] for line in lines][:4] == ["python", "isorock", "numpy", "scipy"]


def test_versions_json_is_one_object(capsys):
    assert run_json(capsys, ["info", "--versions", "--json"]) == versions()


def test_versions_reads_no_record(plain_file):
    out = run_cli(["info", "--versions", str(plain_file)])
    assert out.returncode == 2
    assert out.stderr.strip() == "isorock: error: --versions reads no record: leave out FILE"
    out = run_cli(["info", "--versions", "--id", "TAB78-TAB"])
    assert out.returncode == 2 and "leave out --id" in out.stderr


def test_info_without_a_record_still_asks_for_one():
    out = run_cli(["info"])
    assert out.returncode == 2 and "give FILE or --id" in out.stderr
