"""The software of a run on the store's root: versions of Python, the numerical packages and the platform
(isorock.environment, written by the merge)."""

from __future__ import annotations

import platform
from importlib import metadata

import h5py
import pytest

from isorock import __version__, environment
from isorock.environment import NOT_INSTALLED, PACKAGES, store_attrs, versions
from isorock.jobs.merge import merge
from isorock.store import Store

#: the root attributes of the versions, in the order written
VERSION_ATTRS = (
    "version_python", "version_numpy", "version_scipy", "version_numba", "version_llvmlite",
    "version_obspy", "version_h5py", "version_pandas", "version_snakemake", "platform", "platform_machine",
)  # fmt: skip


def test_versions_name_python_the_packages_and_the_platform():
    v = versions()
    assert list(v) == ["python", *PACKAGES, "platform", "machine"]
    assert {"numpy", "scipy", "numba", "obspy", "h5py", "pandas", "snakemake"} <= set(PACKAGES)
    assert v["python"] == platform.python_version()
    assert v["isorock"] == __version__
    for name in ("numpy", "scipy", "numba", "llvmlite", "obspy", "h5py", "pandas"):
        assert v[name] == metadata.version(name)
    assert v["platform"] == platform.platform() and v["machine"] == platform.machine()
    assert all(isinstance(s, str) and s for s in v.values())


def test_a_package_not_installed_is_said_so(monkeypatch):
    real = metadata.version

    def version(name):
        if name == "snakemake":
            raise metadata.PackageNotFoundError(name)
        return real(name)

    monkeypatch.setattr(environment.metadata, "version", version)
    assert versions()["snakemake"] == NOT_INSTALLED
    assert store_attrs()["version_snakemake"] == NOT_INSTALLED


def test_store_attrs_are_the_versions_less_isorock():
    v, a = versions(), store_attrs()
    assert tuple(a) == VERSION_ATTRS
    assert a["version_numba"] == v["numba"] and a["platform_machine"] == v["machine"]
    assert not any("isorock" in k for k in a)  # isorock's own is the root attribute isorock_version


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    """A store merged from no job file: the root attributes only (plus the restitution table)."""
    out = tmp_path_factory.mktemp("versions") / "isorock.h5"
    merge([], out, config={"studies": []}, source="none", config_name="versions")
    return out


def test_the_merge_writes_the_versions_on_the_root(store):
    with h5py.File(store, "r") as f:
        attrs = {k: f.attrs[k] for k in VERSION_ATTRS}
        assert f.attrs["isorock_version"] == __version__
    assert attrs == store_attrs()
    assert Store(store).root_attrs["version_numpy"] == metadata.version("numpy")  # the reader sees them
