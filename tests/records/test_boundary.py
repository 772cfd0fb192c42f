"""A records directory is a boundary (issue 23, item 5).

The ``file`` of a manifest row is relative to the directory and stays inside it: an absolute path, a
``..`` that leaves the directory and a symbolic link that leads out of it are refused by
:func:`~isorock.records.manifest.read_manifest` with the manifest, its line and the problem, and every
command that reads the manifest exits 2 with that one line (no traceback, nothing opened outside).
A symbolic link inside the directory to a file inside it is accepted. ``records add`` copies the
content of each file into the directory (a link's target's content, never the link) and writes its
name, relative, in the manifest.

Every directory, file and link here is real (``tmp_path``); ``$ISOROCK_RECORDS`` is unset.
"""

from __future__ import annotations

import csv
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

from isorock import cli
from isorock.errors import CatalogError
from isorock.records.adding import add_records
from isorock.records.manifest import MANIFEST_COLUMNS, outside_problem, read_manifest

ADD = ["--format", "one-column", "--dt", "0.01", "--units", "g"]


@pytest.fixture(autouse=True)
def _no_env_records(monkeypatch):
    monkeypatch.delenv("ISOROCK_RECORDS", raising=False)


def _quake(path: Path, amp: float = 0.3, n: int = 800, dt: float = 0.01) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    t = np.arange(n) * dt
    np.savetxt(path, amp * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.4 * t) * np.minimum(t, 1.0))
    return path


def _manifest(directory: Path, *files: str) -> Path:
    """A manifest listing ``files`` as records A, B, ... (one-column, g, dt 0.01 s)."""
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / "manifest.csv"
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(MANIFEST_COLUMNS))
        w.writeheader()
        for k, f in enumerate(files):
            w.writerow({"file": f, "id": "ABCDEFG"[k], "format": "one-column", "units": "g", "dt_s": "0.01"})
    return path


@pytest.fixture
def layout(tmp_path) -> dict[str, Path]:
    """``records/`` holding ``inside.txt``; ``elsewhere/outside.txt`` beside it (both real records)."""
    d = tmp_path / "records"
    return {
        "dir": d,
        "inside": _quake(d / "inside.txt"),
        "outside": _quake(tmp_path / "elsewhere" / "outside.txt", amp=0.2),
    }


def _bad_rows(layout) -> list[tuple[str, str]]:
    """(manifest path, words of the error) for each way out of the directory."""
    d = layout["dir"]
    os.symlink(layout["outside"], d / "link_out.txt")  # a link inside, leading out
    os.symlink(layout["outside"].parent, d / "sub_out")  # a folder link leading out
    return [
        ("/etc/passwd", "is outside the records folder"),
        (str(layout["outside"]), "is outside the records folder"),
        ("../elsewhere/outside.txt", "'..' leaves it"),
        ("sub/../../elsewhere/outside.txt", "'..' leaves it"),
        ("link_out.txt", f"is a symbolic link to {layout['outside'].resolve()}"),
        ("sub_out/outside.txt", "leads through a symbolic link"),
    ]


# ------------------------------------------------------------------------------- read_manifest
def test_a_path_out_of_the_directory_is_an_error_with_the_manifest_and_its_line(layout):
    d = layout["dir"]
    for name, words in _bad_rows(layout):
        mpath = _manifest(d, "inside.txt", name)
        with pytest.raises(CatalogError) as info:
            read_manifest(mpath)
        msg = str(info.value)
        assert info.value.line == 3 and msg.startswith(f"{mpath}:3: file {name!r}"), msg
        assert words in msg and f"the records folder {d.resolve()}" in msg, msg
        assert "\n" not in msg


def test_an_absolute_path_inside_the_directory_is_refused_with_its_relative_name(layout):
    mpath = _manifest(layout["dir"], str(layout["inside"]))
    with pytest.raises(CatalogError, match=r"is an absolute path: .* \(write 'inside.txt'\)"):
        read_manifest(mpath)


def test_relative_paths_and_links_inside_the_directory_are_accepted(layout):
    d = layout["dir"]
    _quake(d / "sub" / "deep.txt", amp=0.25)
    os.symlink("inside.txt", d / "alias.txt")  # a relative link inside, to a file inside
    os.symlink(d / "sub", d / "sub_alias")  # an absolute link to a folder inside
    names = ["inside.txt", "sub/deep.txt", "./sub/../inside2.txt", "alias.txt", "sub_alias/deep.txt"]
    (d / "inside2.txt").write_bytes(layout["inside"].read_bytes())
    rows = read_manifest(_manifest(d, *names))
    assert [r.file for r in rows] == names
    assert all(outside_problem(n, d) is None for n in names)


def test_the_records_directory_may_itself_be_a_link(layout, tmp_path):
    """The boundary is the directory the link leads to: its files are inside, the link's siblings not."""
    alias = tmp_path / "records_alias"
    os.symlink(layout["dir"], alias)
    assert [r.file for r in read_manifest(_manifest(alias, "inside.txt"))] == ["inside.txt"]
    with pytest.raises(CatalogError, match="'..' leaves it"):
        read_manifest(_manifest(alias, "../elsewhere/outside.txt"))


def test_a_manifest_elsewhere_is_checked_against_the_records_directory(layout, tmp_path):
    """``records status DIR --manifest CSV``: the paths are relative to DIR, not to the CSV's folder."""
    mpath = _manifest(tmp_path / "lists", "inside.txt")
    assert [r.file for r in read_manifest(mpath, layout["dir"])] == ["inside.txt"]
    with pytest.raises(CatalogError, match="outside the records folder"):
        read_manifest(_manifest(tmp_path / "lists", "../records/inside.txt"), layout["dir"])


# ------------------------------------------------------------------------------- the commands
@pytest.mark.parametrize("command", ["status", "info", "status-json", "info-json", "add"])
def test_every_command_reading_the_manifest_exits_2_with_one_line(layout, capsys, command):
    d = layout["dir"]
    for name, words in _bad_rows(layout):
        mpath = _manifest(d, "inside.txt", name)
        argv = {
            "status": ["records", "status", str(d)],
            "status-json": ["records", "status", str(d), "--json"],
            "info": ["info", "--id", "B", "--records", str(d)],
            "info-json": ["info", "--id", "A", "--records", str(d), "--json"],
            "add": ["records", "add", str(_quake(d.parent / "new.txt", amp=0.1)), "--records", str(d), *ADD],
        }[command]
        assert cli.main(argv) == 2, name
        out, err = capsys.readouterr()
        assert err.count("\n") == 1 and err.startswith("isorock: error: ") and "Traceback" not in err
        assert f"manifest.csv:3: file {name!r}" in err and words in err, err
        if command.endswith("json"):
            assert json.loads(out) == {
                "error": err.removeprefix("isorock: error: ").rstrip("\n"),
                "exit_code": 2,
            }
        else:
            assert out == ""
        assert mpath.read_text().count("\n") == 3  # nothing added to it


def test_workflow_planning_refuses_the_manifest(layout):
    """``report``/``assess`` plan their records with :func:`isorock.records.lookup.find_records`."""
    from isorock.pipeline import load_config
    from isorock.records.lookup import find_records

    _manifest(layout["dir"], "inside.txt", "/etc/passwd")
    rc = load_config({"records": {"dir": str(layout["dir"]), "include": ["added"]}})["records"]
    with pytest.raises(CatalogError, match=r"manifest.csv:3: file '/etc/passwd' is outside the records"):
        find_records(rc)


def test_status_lists_a_link_inside_as_a_record(layout, capsys):
    d = layout["dir"]
    os.symlink("inside.txt", d / "alias.txt")
    _manifest(d, "alias.txt")
    assert cli.main(["records", "status", str(d), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["added"] == ["A"] and [f["ok"] for f in data["files"]] == [True]


# ------------------------------------------------------------------------------- records add
def test_add_copies_the_file_in_and_writes_its_relative_name(layout, tmp_path):
    d = tmp_path / "mine"
    (e,) = add_records([layout["outside"]], d, ids=["OUT"], format="one-column", dt=0.01, units="g")
    assert e.file == "outside.txt" and not Path(e.file).is_absolute()
    copy = d / "outside.txt"
    assert copy.is_file() and not copy.is_symlink()
    assert copy.read_bytes() == layout["outside"].read_bytes()
    assert [r.file for r in read_manifest(d / "manifest.csv")] == ["outside.txt"]


def test_add_of_a_link_copies_its_content_not_the_link(layout, tmp_path, capsys):
    d = tmp_path / "mine"
    link = tmp_path / "link.txt"
    os.symlink(layout["outside"], link)
    assert cli.main(["records", "add", str(link), "--records", str(d), *ADD, "--json"]) == 0
    (added,) = json.loads(capsys.readouterr().out)["added"]
    assert added["file"] == "link.txt"
    assert not (d / "link.txt").is_symlink()
    assert (d / "link.txt").read_bytes() == layout["outside"].read_bytes()
    assert cli.main(["records", "status", str(d)]) == 0
    capsys.readouterr()


def test_add_of_a_link_in_the_directory_leading_out_replaces_it_by_the_content(layout):
    d = layout["dir"]
    link = d / "link_out.txt"
    os.symlink(layout["outside"], link)
    before = layout["outside"].read_bytes()
    (e,) = add_records([link], d, ids=["L"], format="one-column", dt=0.01, units="g")
    assert e.file == "link_out.txt" and not link.is_symlink() and link.read_bytes() == before
    assert layout["outside"].read_bytes() == before  # the file outside is untouched
    assert [r.file for r in read_manifest(d / "manifest.csv")] == ["link_out.txt"]


def test_add_of_a_file_already_in_the_directory_registers_it_there(layout):
    d = layout["dir"]
    (e,) = add_records([layout["inside"]], d, ids=["IN"], format="one-column", dt=0.01, units="g")
    assert e.file == "inside.txt" and sorted(p.name for p in d.iterdir()) == [
        ".manifest.csv.lock",
        "inside.txt",
        "manifest.csv",
    ]


def test_add_of_a_link_inside_to_a_file_inside_keeps_the_link(layout):
    d = layout["dir"]
    os.symlink("inside.txt", d / "alias.txt")
    (e,) = add_records([d / "alias.txt"], d, ids=["AL"], format="one-column", dt=0.01, units="g")
    assert e.file == "alias.txt" and (d / "alias.txt").is_symlink()
    assert [r.file for r in read_manifest(d / "manifest.csv")] == ["alias.txt"]


def test_replace_never_writes_through_a_link_out_of_the_directory(layout, tmp_path):
    """``--replace`` over a registered name that is a link out: the link is replaced, the file it
    pointed to is left as it was."""
    d = layout["dir"]
    os.symlink(layout["outside"], d / "rec.txt")
    _manifest(d)  # an empty manifest: the link is not registered
    before = layout["outside"].read_bytes()
    new = _quake(tmp_path / "new" / "rec.txt", amp=0.15)
    (e,) = add_records([new], d, ids=["R"], format="one-column", dt=0.01, units="g", replace=True)
    assert e.file == "rec.txt" and not (d / "rec.txt").is_symlink()
    assert (d / "rec.txt").read_bytes() == new.read_bytes()
    assert layout["outside"].read_bytes() == before


def test_add_from_standard_input_is_refused(tmp_path, capsys):
    assert cli.main(["records", "add", "-", "--records", str(tmp_path / "d"), *ADD]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "standard input" in err and not (tmp_path / "d").exists()


def test_status_of_own_records_does_not_read_as_a_failure(layout, tmp_path, capsys):
    """Issue 35, item 7: after a correct ``records add``, ``records status`` of the user's own directory
    says the paper's catalog is optional instead of listing 22 'missing' rows."""
    d = tmp_path / "mine"
    assert cli.main(["records", "add", str(layout["outside"]), "--records", str(d), *ADD]) == 0
    capsys.readouterr()
    assert cli.main(["records", "status", str(d)]) == 0
    out = capsys.readouterr().out
    assert "which is fine: they are optional; records added with 'records add': 1" in out
    assert not re.search(r"^  missing ", out, re.M)
