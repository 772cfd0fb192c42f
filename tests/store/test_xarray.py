"""The store read by xarray (h5netcdf) and by pandas (layout 5): the axes of the maps and the sample times of
the records are HDF5 dimension scales, so that xarray names every dimension and coordinate without a
warning; the tables stay pandas (PyTables) tables that pandas reads without a warning, each beside the
dimension ``row`` that xarray gives it.

xarray and h5netcdf are test requirements: a missing one fails here, it is not skipped.
"""

from __future__ import annotations

import math
import warnings

import h5py
import numpy as np
import pandas as pd
import pytest

from isorock.jobs import record as jobs
from isorock.jobs.merge import merge
from isorock.jobs.pulses import pulse_maps
from isorock.pipeline import load_config, params_process, plan
from isorock.records.adding import add_records
from isorock.store import (
    LAYOUT_VERSION,
    Store,
    atomic_h5,
    atomic_path,
    map_paths,
    merge_h5,
    read_map,
    write_map,
    write_tables,
)
from isorock.store.layout import MAP_AXIS_UNITS
from isorock.store.maps import node_name

try:
    import h5netcdf  # noqa: F401
    import xarray as xr
except ImportError as exc:  # a test requirement (the lock file): fail, never skip
    raise ImportError(
        f"tests/store/test_xarray.py needs xarray and h5netcdf ({exc}): pip install xarray h5netcdf"
    ) from exc

RID = "MY-QUAKE"


def _quake(path, amp=0.3, n=1500, dt=0.01):
    t = np.arange(n) * dt
    np.savetxt(path, amp * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.3 * t) * np.minimum(t, 1.0))
    return path


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    """A store merged from the jobs of one record of the user's own (record, pulse, maps of both kinds,
    overturn table) and a pulse's maps: every kind of group the workflow writes, on small grids."""
    d = tmp_path_factory.mktemp("xr")
    mine = d / "mine"
    add_records([_quake(d / "quake.txt")], mine, ids=[RID], dt=0.01, units="g", event="My quake")
    cfg = load_config({"records": {"dir": str(mine)}})
    pl = plan(cfg, d)
    pp = params_process(cfg, pl.spec(RID), pl.processing)
    rec, pulse, maps, over, pmaps = (d / f"{n}.h5" for n in ("rec", "pulse", "maps", "over", "pmaps"))
    jobs.process_record(pp["spec"], rec, processing=pp["processing"], choose=pp["choose"])
    jobs.extract_pulse(rec, pulse, pulse={"tp_min_s": 0.25, "tp_max_s": 15.0, "fit_mp": False})
    cases = [{"name": "none", "kind": "none"}, {"name": "lin", "kind": "linear", "Tb_s": 3.0, "xi_b": 0.2}]
    jobs.regime_maps(
        rec, maps, amplitude=0.3, table1_pga_g=None, pulse_h5=pulse,
        lambda_R={"lambdas": [2.0, 4.0, 6.0], "Rs": [1.0, 3.0], "cases": cases},
        Tb_xi={"Tbs": [1.0, 2.0, 3.0, 4.0], "xis": [0.1, 0.3], "rho": 0.5,
               "blocks": [{"lambda": 4.0, "R_m": 3.0}]},
    )  # fmt: skip
    jobs.min_overturn(
        rec, over, lambdas=[4.0], Rs=[1.0], cases=cases[:1], pulse_h5=pulse,
        search={"amp_max_g": 2.0, "growth": 1.2, "rtol": 1e-2},
    )  # fmt: skip
    pulse_maps(
        pmaps, source="pulse-halfsine-td0.5", shape="halfsine", td_s=0.5, amp_g=0.5,
        lambdas=[2.0, 4.0], Rs=[1.0, 2.0, 3.0], cases=cases,
    )  # fmt: skip
    out = d / "isorock.h5"
    merge([rec, pulse, maps, over, pmaps], out, config=cfg, source=f"records {mine}", config_name="xr")
    return out


def _open(path, **kwargs):
    """``xarray.open_datatree(path, engine="h5netcdf")``, h5netcdf's defaults, every warning an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return xr.open_datatree(path, engine="h5netcdf", **kwargs)


def _pandas_keys(path) -> list[str]:
    """The groups of the pandas tables (attribute pandas_type)."""
    keys: list[str] = []

    def visit(name, obj):
        if obj.attrs.get("pandas_type") is not None:
            keys.append(name)

    with h5py.File(path, "r") as f:
        f.visititems(visit)
    return keys


def _phony(tree) -> list[tuple[str, str, tuple]]:
    """(group, variable, dimensions) of every variable with a dimension h5netcdf had to invent."""
    return [
        (node.path, name, var.dims)
        for node in tree.subtree
        for name, var in node.to_dataset(inherit=False).variables.items()
        if any(str(d).startswith("phony_dim") for d in var.dims)
    ]


# ------------------------------------------------------------------------------------------ the whole store
def test_the_whole_store_opens_without_a_warning_and_names_every_dimension(store):
    tree = _open(store)  # a warning (phony_dims, a decoding) would be an error
    assert _phony(tree) == []
    assert sum(1 for n in tree["maps"].subtree if "codes" in n.data_vars) == 5
    assert {"time_s", "line"} <= set(tree[f"records/{RID}"].dims)
    tables = _pandas_keys(store)
    assert {
        "summary/records",
        "summary/maps",
        "summary/overturn",
        "pulses/restitution",
        f"overturn/{RID}",
    } <= set(tables)
    for key in tables:  # a PyTables table: one record per row, along the dimension row of its group
        node = tree[key]
        assert node["table"].dims == ("row",) and list(node.data_vars) == ["table"], key
        assert node.sizes["row"] == len(pd.read_hdf(store, key)), key


def test_pandas_reads_every_table_without_a_warning(store):
    keys = _pandas_keys(store)
    assert len(keys) >= 5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pd.HDFStore(store, "r") as hs:
            assert sorted(k.strip("/") for k in hs.keys()) == sorted(keys)
            assert len(hs.select("summary/maps", where="kind == 'lambda-R'")) == 4
        for key in keys:
            df = pd.read_hdf(store, key)
            assert isinstance(df, pd.DataFrame) and len(df), key
    assert pd.read_hdf(store, "summary/maps")["path"].str.startswith("/maps/").all()


# ------------------------------------------------------------------------------------------ maps and records
def test_map_coordinates_are_the_grid_the_store_says(store):
    tree = _open(store)
    st = Store(store)
    infos = st.maps()
    assert len(infos) == 3 + 2  # the record's lambda-R (2 cases) and Tb-xi, the pulse's lambda-R (2 cases)
    for info in infos:
        m = st.read_map(info)  # the reader of the store, which knows nothing of the scales
        ds = tree[info.path].to_dataset()
        x, y = (node_name(n) for n in (m.x_name, m.y_name))  # lambda_, R_m or Tb_s, xi_b
        assert ds["codes"].dims == (x, y) and ds["max_theta_over_alpha"].dims == (x, y)
        assert set(ds.coords) == {x, y} and set(ds.data_vars) == {"codes", "max_theta_over_alpha"}
        np.testing.assert_array_equal(ds[x].values, m.x)
        np.testing.assert_array_equal(ds[y].values, m.y)
        np.testing.assert_array_equal(ds["codes"].values, m.codes)
        np.testing.assert_array_equal(ds["max_theta_over_alpha"].values, m.max_theta_over_alpha)
        for n, c in ((m.x_name, x), (m.y_name, y)):
            assert ds[c].attrs["units"] == MAP_AXIS_UNITS[n] and ds[c].attrs["long_name"]
        assert ds.attrs["kind"] == info.kind and math.isclose(ds.attrs["amp_g"], info.amp_g)
    lr = next(i for i in infos if i.kind == "lambda-R" and i.source == RID and i.case == "lin")
    ds = tree[lr.path]
    np.testing.assert_array_equal(ds["lambda_"].values, [2.0, 4.0, 6.0])
    np.testing.assert_array_equal(ds["R_m"].values, [1.0, 3.0])
    assert ds["R_m"].attrs["units"] == "m" and ds["lambda_"].attrs["units"] == "-"
    tx = tree[next(i.path for i in infos if i.kind == "Tb-xi")]
    np.testing.assert_array_equal(tx["Tb_s"].values, [1.0, 2.0, 3.0, 4.0])
    np.testing.assert_array_equal(tx["xi_b"].values, [0.1, 0.3])
    assert tx["Tb_s"].attrs["units"] == "s" and tx["codes"].sel(Tb_s=2.0, xi_b=0.3).ndim == 0


def test_records_have_a_time_axis(store):
    tree = _open(store, group="records")  # a subtree opens alike
    rec = tree[RID].to_dataset()
    series = Store(store).record_series(RID)
    n, dt = len(series["acc"]), series["dt_s"]
    assert rec["acc"].dims == ("time_s",) and rec["time_s"].attrs["units"] == "s"
    np.testing.assert_allclose(rec["time_s"].values, np.arange(n) * dt)
    np.testing.assert_array_equal(rec["acc"].values, series["acc"])
    assert rec["processing"].dims == ("line",) and "line" not in rec.coords  # a count, no values
    assert rec.attrs["id"] == RID
    pulse = tree[f"{RID}/pulse"].to_dataset()  # its own time_s, equal to the record's
    for k in ("velocity", "pulse_velocity", "mp_velocity"):
        assert pulse[k].dims == ("time_s",)
        np.testing.assert_array_equal(pulse[k].values, series[k])
    np.testing.assert_array_equal(pulse["time_s"].values, rec["time_s"].values)


def test_the_layout_version_and_the_readers(store):
    st = Store(store)
    assert st.layout_version == LAYOUT_VERSION == 7
    assert [s.step for s in st.record_processing(RID)][:2] == ["check_pga", "detrend"]
    with h5py.File(store, "r") as f:
        assert len(map_paths(f)) == 5
        for path in map_paths(f):  # the scales are the datasets of the axes that read_map reads
            g = f[path]
            axes = [node_name(str(g.attrs[k])) for k in ("x_name", "y_name")]
            for k in ("codes", "max_theta_over_alpha"):
                assert [d[0].name for d in g[k].dims] == [f"{path}/{a}" for a in axes], (path, k)
        assert f[f"records/{RID}/line"].id.get_storage_size() == 0  # a dimension without values: no space


# ------------------------------------------------------------------------------------------ write and merge
def test_a_map_written_alone_opens_with_its_coordinates(tmp_path):
    """``isorock map --out`` writes one map with write_map: a file xarray opens by itself."""
    from isorock.physics.regime_maps import RegimeMap

    codes = np.array([[0, 1, 2], [1, 1, 2]], dtype=np.int8)
    m = RegimeMap("Tb-xi", "Tb_s", "xi_b", np.array([2.0, 4.0]), np.array([0.0, 0.1, 0.2]), codes,
                  np.ones((2, 3)), 0.5, {"isolation": "linear"}, 6, 0.1)  # fmt: skip
    out = tmp_path / "map.h5"
    with atomic_h5(out) as f:
        write_map(f.create_group("maps/mine"), m, {"source": "mine"})
    ds = _open(out)["maps/mine"].to_dataset()
    assert ds["codes"].dims == ("Tb_s", "xi_b") and ds["xi_b"].values.tolist() == [0.0, 0.1, 0.2]
    assert ds["Tb_s"].attrs["long_name"] == "isolation period Tb"
    with h5py.File(out, "r") as f:
        back = read_map(f["maps/mine"])
    assert np.array_equal(back.codes, codes) and back.x.tolist() == [2.0, 4.0]


def test_the_merge_attaches_the_scales_again(tmp_path):
    """A copy between HDF5 files keeps references into the file it came from: the merge attaches the
    scales again, by path, also in a group two files have."""
    from isorock.store import attach_dims, coordinate, dimension  # layout 5

    a, b, m = tmp_path / "a.h5", tmp_path / "b.h5", tmp_path / "m.h5"
    with atomic_h5(a) as f:
        g = f.create_group("records/R1")
        t = coordinate(g, "time_s", [0.0, 0.5, 1.0], units="s")
        attach_dims(g.create_dataset("acc", data=[1.0, 2.0, 3.0]), t)
        lines = g.create_dataset("processing", data=np.array(["a", "b"], dtype=h5py.string_dtype()))
        attach_dims(lines, dimension(g, "line", 2))
    with atomic_h5(b) as f:
        p = f.create_group("records/R1/pulse")
        attach_dims(
            p.create_dataset("velocity", data=[0.0, 1.0, 0.0]),
            coordinate(p, "time_s", [0, 0.5, 1], units="s"),
        )
    with atomic_h5(m) as f:
        merge_h5([a, b], f)
    with h5py.File(m, "r") as f:
        assert f["records/R1/acc"].dims[0][0].name == "/records/R1/time_s"
        assert f["records/R1/pulse/velocity"].dims[0][0].name == "/records/R1/pulse/time_s"
        assert f["records/R1/processing"].dims[0][0].name == "/records/R1/line"
    node = _open(m)["records/R1"]
    assert node["acc"].dims == ("time_s",) and node.sizes["line"] == 2
    assert node["pulse"]["velocity"].dims == ("time_s",)
    with pytest.raises(ValueError, match="axis 0 has 2 values"):
        with atomic_h5(tmp_path / "bad.h5") as f:
            attach_dims(f.create_dataset("x", data=[1.0, 2.0]), coordinate(f, "t", [0.0], units="s"))


def test_a_table_written_again_has_its_new_length(tmp_path):
    out = tmp_path / "t.h5"
    with atomic_path(out) as tmp:
        write_tables(tmp, {"summary/x": pd.DataFrame({"a": [1.0, 2.0, 3.0]})})
        write_tables(tmp, {"summary/x": pd.DataFrame({"a": [1.0, 2.0]})})
    node = _open(out)["summary/x"]
    assert node.sizes["row"] == 2 and node["table"].values["a"].tolist() == [1.0, 2.0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert pd.read_hdf(out, "summary/x")["a"].tolist() == [1.0, 2.0]
