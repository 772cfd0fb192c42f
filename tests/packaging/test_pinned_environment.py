"""The pinned environment: the lock files of requirements/, the conda environment of the workflow's rules
(workflow/envs/isorock.yaml) that matches them, and ``snakemake --lint`` clean."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml

from isorock import environment

ROOT = Path(__file__).resolve().parents[2]
LOCKS = {v: ROOT / "requirements" / f"lock-py3{v}.txt" for v in (11, 12, 13)}
ENV = ROOT / "workflow" / "envs" / "isorock.yaml"
#: conda-forge's names of the PyPI distributions whose names differ
CONDA_NAMES = {"pytables": "tables", "matplotlib-base": "matplotlib"}


def _norm(name: str) -> str:
    """A distribution name normalised as PEP 503 does (PyWavelets -> pywavelets, ...)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def _pins(path: Path) -> dict[str, str]:
    """The ``name==version`` lines of a lock file."""
    pins = {}
    for line in path.read_text().splitlines():
        if line and not line.startswith((" ", "#")):
            name, version = line.split("==")
            pins[_norm(name)] = version.strip()
    return pins


@pytest.mark.parametrize("minor", sorted(LOCKS))
def test_each_lock_says_how_it_is_made_and_pins_every_requirement(minor):
    lock = LOCKS[minor]
    head = lock.read_text().splitlines()[:2]
    command = (
        "uv pip compile pyproject.toml --extra test --extra workflow --extra samples --extra docs "
        f"--python-version 3.{minor} --python-platform x86_64-unknown-linux-gnu "
        f"-o requirements/lock-py3{minor}.txt"
    )
    assert head[1].strip("# ") == command
    assert command in (ROOT / "requirements" / "README.md").read_text()
    pins = _pins(lock)
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    wanted = project["dependencies"] + [
        r
        for extra in ("test", "workflow", "samples", "docs")
        for r in project["optional-dependencies"][extra]
    ]
    names = {_norm(re.split(r"[<>=!~; \[]", r, maxsplit=1)[0]) for r in wanted}
    assert sorted(names - set(pins)) == []
    assert "isorock" not in pins  # installed from the source tree, after the lock
    assert all(re.fullmatch(r"[0-9][0-9A-Za-z.+]*", v) for v in pins.values())


def test_the_locks_pin_the_same_versions():
    # the same wheels exist for 3.11 to 3.13; only dependencies behind a Python marker may differ
    pins = {minor: _pins(lock) for minor, lock in LOCKS.items()}
    for minor in (12, 13):
        common = set(pins[11]) & set(pins[minor])
        assert {n: pins[minor][n] for n in common} == {n: pins[11][n] for n in common}
        assert {"numpy", "scipy", "numba", "llvmlite", "obspy", "h5py", "pandas", "snakemake"} <= common


def test_the_conda_environment_pins_the_lock():
    env = yaml.safe_load(ENV.read_text())
    lock = _pins(LOCKS[11])
    assert env["channels"][0] == "conda-forge"
    conda = [d for d in env["dependencies"] if isinstance(d, str)]
    pip = next(d["pip"] for d in env["dependencies"] if isinstance(d, dict))
    assert "python =3.11" in conda and "pip" in conda
    pinned = {}
    for spec in conda:
        if "==" in spec:
            name, version = (s.strip() for s in spec.split("=="))
            pinned[_norm(CONDA_NAMES.get(name, name))] = version
    for spec in pip:
        if "==" in spec:
            name, version = spec.split("==")
            pinned[_norm(name)] = version
    assert {n: lock.get(n) for n in pinned} == pinned
    assert {*environment.PACKAGES[1:], "pyslammer"} <= set(pinned)
    # every runtime dependency of isorock is pinned (by conda or by pip under the lock)
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    runtime = {_norm(re.split(r"[<>=!~; \[]", r, maxsplit=1)[0]) for r in project["dependencies"]}
    assert sorted(runtime - set(pinned)) == []
    # the lock constrains pip, then isorock itself: paths from <working directory>/.snakemake/conda/
    assert pip[0] == "-c ../../requirements/lock-py311.txt" and pip[-1] == "-e ../.."


def test_every_rule_runs_in_the_conda_environment():
    for smk in sorted((ROOT / "workflow" / "rules").glob("*.smk")):
        text = smk.read_text()
        rules = re.findall(r"^rule (\w+):", text, flags=re.M)
        assert text.count('    conda:\n        "../envs/isorock.yaml"\n') == len(rules), smk.name
        if smk.name != "common.smk":  # Snakemake's lint: functions with the rules of a file are not
            assert not re.search(r"^def ", text, flags=re.M), smk.name


def test_snakemake_lint_is_clean(tmp_path):
    # the default configuration (the pyslammer samples where no records directory is set), run in an
    # empty directory so that nothing is written beside the sources
    out = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--lint", "--cores", "1",
         "--directory", str(tmp_path)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert out.returncode == 0, out.stdout + out.stderr
    assert "Lints for" not in out.stdout + out.stderr
    assert "Congratulations, your workflow is in a good condition!" in out.stdout + out.stderr


CLUSTER_LOCK = ROOT / "requirements" / "lock-cluster.txt"


def _requires(path: Path) -> dict[str, list[str]]:
    """The ``# requires:`` lines of ``lock-cluster.txt``, by the package pinned above them."""
    out: dict[str, list[str]] = {}
    name = ""
    for line in path.read_text().splitlines():
        if line and not line.startswith((" ", "#")):
            name = _norm(line.split("==")[0])
            out[name] = []
        elif line.strip().startswith("# requires:"):
            out[name].append(line.split("# requires:", 1)[1].strip())
    return out


@pytest.mark.parametrize("minor", sorted(LOCKS))
def test_the_cluster_extra_is_pinned_by_the_locks(minor):
    """Issue 35, item 9: the SLURM tutorial installs the extra "cluster" from lock-cluster.txt over a
    lock-py3XX.txt, with --no-deps: every requirement of the extra is pinned there at a version that
    meets it, and so is every requirement of the plugins pinned (nothing is resolved at install time)."""
    from packaging.requirements import Requirement

    pins = {**_pins(LOCKS[minor]), **_pins(CLUSTER_LOCK)}
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    wanted = [Requirement(r) for r in project["optional-dependencies"]["cluster"]]
    wanted += [Requirement(r) for reqs in _requires(CLUSTER_LOCK).values() for r in reqs]
    assert all(_requires(CLUSTER_LOCK).values())  # each plugin says what it requires
    for req in wanted:
        name = _norm(req.name)
        assert name in pins, f"{req} is not pinned"
        assert req.specifier.contains(pins[name], prereleases=True), f"{name}=={pins[name]} fails {req}"
    assert set(_pins(CLUSTER_LOCK)).isdisjoint(_pins(LOCKS[minor]))  # no package pinned twice


def test_the_cluster_lock_says_what_the_installed_plugins_require():
    """Where a plugin of lock-cluster.txt is installed, its version and requirements are those noted."""
    from importlib import metadata

    from packaging.requirements import Requirement

    noted = _requires(CLUSTER_LOCK)
    found = 0
    for name, version in _pins(CLUSTER_LOCK).items():
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            continue
        found += 1
        assert dist.version == version
        got = sorted(str(Requirement(r)) for r in dist.requires or [])
        assert got == sorted(str(Requirement(r)) for r in noted[name])
    if not found:
        pytest.skip("no SLURM plugin installed here (pip install --no-deps -r requirements/lock-cluster.txt)")
