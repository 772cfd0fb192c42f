"""The README and the documentation site: short README, links that resolve, timings from one place.

The site itself is built with warnings as errors by ``.ci/run`` (``sphinx -W``); these tests keep the
README honest between builds.
"""

from __future__ import annotations

import re
from pathlib import Path

from isorock.timings import TIMINGS, Timing

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()

#: a time as the README and the docs print it: "about 3 min 10 s", "about 35 s", "about 25 min"
TIME_RE = re.compile(r"about \d+ (?:min(?: \d+ s)?|s)\b")


def test_readme_is_at_most_150_lines():
    assert len(README.splitlines()) <= 150


def test_readme_gives_the_two_commands():
    install = (
        "python3 -m venv .venv && .venv/bin/pip install -q --no-deps -r requirements/lock-py311.txt -e ."
    )
    assert f"{install} && .venv/bin/isorock report --cores 2" in README
    assert f"{install} && .venv/bin/python -m pytest\n" in README
    assert ".venv/bin/python -m pytest -m e2e" in README


def test_every_time_the_readme_quotes_is_a_measured_one():
    """Each "about ..." time of the README is the text of an entry of isorock.timings, and the four
    times a newcomer needs are all quoted."""
    measured = {t.text for t in TIMINGS.values()}
    quoted = TIME_RE.findall(README)
    assert quoted, "the README quotes no time"
    assert [q for q in quoted if q not in measured] == []
    for key in ("main_job", "tests", "e2e", "first_analysis"):
        assert TIMINGS[key].text in README, key


def test_the_engine_compile_message_quotes_the_measured_time():
    from isorock.physics.engine._cache import MESSAGE

    assert TIMINGS["first_analysis"].text in MESSAGE


def test_timing_text_has_the_precision_of_a_noisy_machine():
    t = lambda s: Timing("x", s, "c", "m").text  # noqa: E731
    assert (t(37.0), t(2.0), t(192.0), t(442.0), t(1530.0)) == (
        "about 35 s",
        "about 5 s",
        "about 3 min 10 s",
        "about 7 min 20 s",
        "about 26 min",
    )
    assert t(300.0) == "about 5 min"


def test_readme_links_resolve():
    links = re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README)
    assert links
    missing = [link for link in links if not link.startswith("http") and not (ROOT / link).exists()]
    assert missing == []


def test_docs_pages_are_in_the_site():
    """Every Markdown page of docs/ is reachable from a toctree (Sphinx warns about an orphan only for
    .rst and .md pages it reads: this names the page)."""
    pages = {
        p.relative_to(ROOT / "docs").with_suffix("").as_posix()
        for p in (ROOT / "docs").rglob("*")
        if p.suffix in (".md", ".rst")
        and not any(part.startswith("_") for part in p.relative_to(ROOT / "docs").parts)
    }
    text = "\n".join(p.read_text() for p in (ROOT / "docs").rglob("*.md"))
    listed = set()
    for block in re.findall(r"```\{toctree\}(.*?)```", text, flags=re.S):
        listed |= {line.strip() for line in block.splitlines() if line.strip() and not line.startswith(":")}
    names = {p.rsplit("/", 1)[-1] for p in pages} - {"index"}
    assert sorted(n for n in names if n not in listed) == []


def test_the_docs_print_options_as_typed():
    """docutils' smart quotes turn ``--lambda`` into an en-dash (issue 35, item 3): they are off."""
    import runpy

    from docutils.core import publish_parts

    conf = runpy.run_path(str(ROOT / "docs" / "conf.py"))
    smart = conf.get("smartquotes", True)
    html = publish_parts("give --lambda and --R", writer="html", settings_overrides={"smart_quotes": smart})
    assert "--lambda and --R" in html["body"] and "\u2013" not in html["body"]


def test_tutorials_install_from_the_lock_file():
    """Issue 35, item 9: every tutorial installs isorock from the lock file first, as the README does."""
    for page in sorted((ROOT / "docs" / "tutorials").glob("*.md")):
        text = page.read_text()
        for line in text.splitlines():
            if "pip install" in line and "-e" in line and "lock-py" not in line:
                assert "lock-py311.txt" in text.split(line)[0], (page.name, line)


def test_tutorial_commands_are_those_of_the_readme():
    """Issue 35, item 9: a tutorial's command runs the clone's isorock, ``.venv/bin/isorock``, as the
    README's do (a bare ``isorock`` is not on a newcomer's PATH)."""
    for page in sorted((ROOT / "docs" / "tutorials").glob("*.md")):
        bare = [ln for ln in page.read_text().splitlines() if ln.startswith("isorock ")]
        assert not bare, (page.name, bare)


def test_the_slurm_tutorial_installs_the_cluster_extra_from_its_lock_file():
    """Issue 35, item 9: the SLURM plugins come from requirements/lock-cluster.txt with --no-deps (the
    extra resolved by pip, ``pip install -e ".[cluster]"``, could move a package of the tested lock)."""
    text = (ROOT / "docs" / "tutorials" / "slurm.md").read_text()
    blocks = "\n".join(re.findall(r"```bash\n(.*?)```", text, flags=re.S))
    installs = [ln for ln in blocks.splitlines() if "pip install" in ln]
    assert not [ln for ln in installs if "[cluster]" in ln], installs
    assert any("--no-deps -r requirements/lock-cluster.txt" in ln for ln in installs), installs
    assert (ROOT / "requirements" / "lock-cluster.txt").is_file()


def _blocks(text: str) -> list[tuple[str, str]]:
    """The fenced blocks of a page: (language, content), in order."""
    return re.findall(r"```(\w*)\n(.*?)```", text, flags=re.S)


def test_the_worked_example_of_add_your_records_is_what_its_commands_print(tmp_path):
    """Issue 35, item 9: the tutorial's worked example (a plain-text record derived from a pyslammer
    sample, ``records add`` with ``--dt``/``--units``, ``records status``, ``info --id``) is run here
    as written, and prints what the page shows."""
    import os
    import subprocess
    import sys

    import pytest

    pytest.importorskip("pyslammer")
    venv = tmp_path / ".venv" / "bin"  # the page's .venv/bin: this interpreter and its isorock
    venv.mkdir(parents=True)
    for name, run in (("python", ""), ("isorock", " -m isorock.cli")):
        (venv / name).write_text(f'#!/bin/sh\nexec "{sys.executable}"{run} "$@"\n')
        (venv / name).chmod(0o755)
    blocks = _blocks((ROOT / "docs" / "tutorials" / "add-your-records.md").read_text())
    start = next(i for i, (_, b) in enumerate(blocks) if "pacoima.txt" in b and "tail -n +3" in b)
    env = {k: v for k, v in os.environ.items() if k != "ISOROCK_RECORDS"}
    shown = 0
    for (lang, cmd), (out_lang, out) in zip(blocks[start::2], blocks[start + 1 :: 2], strict=False):
        if lang != "bash" or out_lang != "text" or "isorock report" in cmd:
            break
        res = subprocess.run(["bash", "-ec", cmd], cwd=tmp_path, capture_output=True, text=True, env=env,
                             timeout=300)  # fmt: skip
        assert res.returncode == 0, res.stderr
        assert res.stdout == out, (cmd, res.stdout)
        shown += 1
    assert shown == 3  # the file, records add and status, info
