"""Where a run's caches go (issue 32 item 5): the user's cache folder when it can be written, else the
run folder with one line, else one line naming HOME."""

from __future__ import annotations

import pytest

from isorock.control.caches import RUN_CACHE, cache_environment, user_cache_dir
from isorock.errors import IsorockError


def test_a_writable_cache_folder_changes_nothing(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    said = []
    assert cache_environment(tmp_path / "run", said.append) == {}
    assert said == [] and (tmp_path / "cache" / "snakemake").is_dir()


def test_xdg_wins_over_home_and_a_relative_xdg_is_ignored():
    where, source = user_cache_dir({"XDG_CACHE_HOME": "/x/c", "HOME": "/h"})
    assert (where.as_posix(), source) == ("/x/c", "XDG_CACHE_HOME")
    assert user_cache_dir({"XDG_CACHE_HOME": "rel", "HOME": "/h"})[0].as_posix() == "/h/.cache"


def test_a_home_that_cannot_be_written_sends_the_caches_to_the_run_folder(tmp_path, monkeypatch):
    home = tmp_path / "home"
    home.write_text("")  # a file: no folder can be made in it, whoever runs the test
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.delenv("MPLCONFIGDIR", raising=False)
    monkeypatch.setenv("HOME", str(home))
    run = tmp_path / "run"
    said = []
    env = cache_environment(run, said.append)
    assert env["XDG_CACHE_HOME"] == str((run / RUN_CACHE).resolve())
    assert env["MPLCONFIGDIR"].startswith(env["XDG_CACHE_HOME"])
    assert len(said) == 1 and f"(HOME={home}) cannot be written (Not a directory)" in said[0]
    # neither: one line naming HOME
    (run / RUN_CACHE).rmdir()
    (run / RUN_CACHE).write_text("")
    with pytest.raises(IsorockError, match="set HOME or XDG_CACHE_HOME to a folder that can be written"):
        cache_environment(run, said.append)
