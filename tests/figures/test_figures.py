"""The paper figures (isorock.figures) drawn from a small store built here; skipped cleanly without data."""

from __future__ import annotations

import logging
import math
import os

import h5py
import numpy as np
import pandas as pd
import pytest

from isorock import Block, FPIsolation, GroundMotion, LinearIsolation, NoIsolation, Pulse, System
from isorock import figures as F
from isorock.figures.style import _match_record
from isorock.physics.overturning import min_overturn_amplitude
from isorock.physics.regime_maps import regime_map_lambda_R, regime_map_Tb_xi
from isorock.store import OVERTURN_COLUMNS, PULSE_COLUMNS, Store, atomic_h5, write_map, write_tables

PNG = b"\x89PNG\r\n\x1a\n"
LIN = LinearIsolation(3.0, 0.35, 0.5)
FP = FPIsolation(0.11, 2.24, 0.5)
CASES = {"none": NoIsolation(), "linear": LIN, "fp": FP}


def _case_cols(name: str) -> dict:
    iso = CASES[name]
    nan = math.nan
    return {
        "case": name,
        "isolation": iso.kind,
        "Tb_s": iso.Tb if iso.kind != "none" else nan,
        "xi_b": iso.xi_b if iso.kind == "linear" else nan,
        "rho": iso.rho if iso.kind != "none" else nan,
        "mu_b": iso.mu_b if iso.kind == "fp" else nan,
        "R_b_m": iso.R_b if iso.kind == "fp" else nan,
    }


def _search(system: System, exc) -> dict:
    m = min_overturn_amplitude(system, exc, amp_max=10.0, growth=1.05, rtol=1e-3)
    tan_a = system.block.tan_alpha
    mo = math.nan if m.min_overturn_g is None else m.min_overturn_g
    return {
        "lambda_": system.block.lam,
        "R_m": system.block.R,
        "b_m": system.block.b,
        "h_m": system.block.h,
        "tan_alpha": tan_a,
        "min_overturn_g": mo,
        "overturns": m.min_overturn_g is not None,
        "min_overturn_over_tan_alpha": mo / tan_a,
        "uplift_g": m.uplift_g,
        "uplift_over_tan_alpha": m.uplift_g / tan_a,
        "n_analyses": m.n_analyses,
        "amp_max_g": 10.0,
    }


def _record(seed: int, tp: float) -> GroundMotion:
    """A synthetic pulse-like accelerogram: one velocity pulse of period tp plus noise [m/s^2]."""
    rng = np.random.default_rng(seed)
    dt = 0.01
    t = np.arange(0, 12.0, dt)
    env = np.exp(-(((t - 4.0) / 2.0) ** 2))
    acc = 3.0 * np.sin(2 * np.pi * t / tp) * env + 0.8 * rng.standard_normal(t.size) * env
    return GroundMotion(dt, acc, f"synthetic-{seed}")


def _pulse_rows(shape: str, cases: list[str]) -> tuple[list, list, list]:
    lam = 4.0
    rows_R, rows_w, rows_i = [], [], []
    for case in cases:
        for td in (0.2, 0.5):
            for R in (1.0, 3.0, 8.0):
                s = System(Block.from_lambda_R(lam, R), CASES[case])
                rows_R.append(
                    {
                        "pulse": shape,
                        "td_s": td,
                        "omega_p_rad_s": math.pi / td,
                        "series": "td",
                        "param": "",
                        "value": math.nan,
                        **_case_cols(case),
                        **_search(s, Pulse(shape, td)),
                    }
                )
        for R in (1.0, 5.0):
            for w in (2.0, 6.0, 15.0):
                td = math.pi / w
                s = System(Block.from_lambda_R(lam, R), CASES[case])
                rows_w.append(
                    {
                        "pulse": shape,
                        "td_s": td,
                        "omega_p_rad_s": w,
                        "series": "R",
                        "param": "",
                        "value": math.nan,
                        **_case_cols(case),
                        **_search(s, Pulse(shape, td)),
                    }
                )
    if shape == "fullsine":
        for series, R, td in (("R", 1.0, 0.5), ("R", 3.0, 0.5), ("td", 3.0, 0.25), ("td", 3.0, 1.0)):
            blk = Block.from_lambda_R(lam, R)
            base = {"pulse": shape, "td_s": td, "omega_p_rad_s": math.pi / td, "series": series}
            rows_i.append(
                {
                    **base,
                    "param": "none",
                    "value": math.nan,
                    **_case_cols("none"),
                    **_search(System(blk, NoIsolation()), Pulse(shape, td)),
                }
            )
            for param, values in (("Tb_s", (1.5, 3.0, 4.5)), ("xi_b", (0.05, 0.35)), ("rho", (0.2, 1.0))):
                for v in values:
                    kw = {"Tb": 3.0, "xi_b": 0.35, "rho": 0.5}
                    kw[{"Tb_s": "Tb"}.get(param, param)] = v
                    iso = LinearIsolation(**kw)
                    cols = _case_cols("linear") | {"Tb_s": iso.Tb, "xi_b": iso.xi_b, "rho": iso.rho}
                    rows_i.append(
                        {
                            **base,
                            "param": param,
                            "value": v,
                            **cols,
                            **_search(System(blk, iso), Pulse(shape, td)),
                        }
                    )
    return rows_R, rows_w, rows_i


@pytest.fixture(scope="module")
def store(tmp_path_factory) -> str:
    """A small store with every kind of data the figures read (layout of isorock.store)."""
    path = tmp_path_factory.mktemp("store") / "isorock.h5"
    lams, Rs = np.linspace(1.5, 8.0, 6), np.linspace(0.5, 10.0, 5)
    Tbs, xis = np.linspace(0.5, 5.0, 5), np.linspace(0.0, 0.5, 4)
    recs = {
        "IMV79-EMO": _record(1, 2.9),
        "NOR94-PKC": _record(2, 0.6),
        "IMV79-E05": _record(3, 3.9),
        "NOR94-NWS": _record(4, 2.7),
    }
    with atomic_h5(path) as f:
        for shape in ("halfsine", "fullsine"):
            for td in (0.2, 0.5):
                src = f"pulse-{shape}-td{td:g}"
                for case in ("none", "linear"):
                    m = regime_map_lambda_R(Pulse(shape, td), CASES[case], lams, Rs, 0.5, threads=1)
                    attrs = {
                        "source": src,
                        "source_kind": "pulse",
                        "pulse_shape": shape,
                        "td_s": td,
                        **_case_cols(case),
                    }
                    write_map(f.create_group(f"maps/{src}/lambda_R-{case}"), m, attrs)
        for rid, gm in recs.items():
            g = f.create_group(f"records/{rid}")
            g.attrs.update(
                {
                    "label": f"test record {rid}",
                    "pga_g": gm.pga_g,
                    "Tp_s": 1.0,
                    "Tp_mp_s": 1.1,
                    "table1_tp_s": 0.61 if "PKC" in rid else 2.94,
                }
            )
            d = g.create_dataset("acc", data=gm.acc)
            d.attrs["dt_s"] = gm.dt
            p = g.create_group("pulse")
            vel = np.cumsum(gm.acc) * gm.dt
            p.create_dataset("velocity", data=vel)
            p.create_dataset("pulse_velocity", data=0.8 * vel)
            p.create_dataset("mp_velocity", data=0.7 * vel)
            cases = ("none", "linear", "fp") if rid in ("IMV79-EMO", "IMV79-E05") else ("none", "linear")
            for case in cases:
                m = regime_map_lambda_R(gm, CASES[case], lams, Rs, gm.pga_g, threads=1)
                attrs = {"source": rid, "source_kind": "record", **_case_cols(case)}
                write_map(f.create_group(f"maps/{rid}/lambda_R-{case}"), m, attrs)
            blocks = [(4.0, 6.0)] + ([(3.0, 2.0), (3.0, 6.0)] if rid == "NOR94-PKC" else [])
            for lam, R in blocks:
                m = regime_map_Tb_xi(gm, Block.from_lambda_R(lam, R), Tbs, xis, 0.5, gm.pga_g, threads=1)
                attrs = {
                    "source": rid,
                    "source_kind": "record",
                    "isolation": "linear",
                    "lambda": lam,
                    "R_m": R,
                }
                write_map(f.create_group(f"maps/{rid}/Tb_xi-lam{lam:g}-R{R:g}"), m, attrs)
    tables = {}
    all_R, all_w, all_i = [], [], []
    for shape, cases in (
        ("rect", ["none", "linear"]),
        ("halfsine", ["none", "linear"]),
        ("fullsine", ["none", "linear", "fp"]),
    ):
        r, w, i = _pulse_rows(shape, cases)
        all_R += r
        all_w += w
        all_i += i
    tables["pulses/overturn_R"] = pd.DataFrame(all_R, columns=list(PULSE_COLUMNS))
    tables["pulses/overturn_omega"] = pd.DataFrame(all_w, columns=list(PULSE_COLUMNS))
    tables["pulses/overturn_isolation"] = pd.DataFrame(all_i, columns=list(PULSE_COLUMNS))
    for rid in ("IMV79-EMO", "NOR94-PKC"):
        rows = []
        for R in (1.0, 4.0):
            for case in ("none", "linear"):
                s = System(Block.from_lambda_R(4.0, R), CASES[case])
                rows.append(
                    {
                        "record": rid,
                        **_case_cols(case),
                        **_search(s, recs[rid]),
                        "record_pga_g": recs[rid].pga_g,
                        "scale_min": math.nan,
                    }
                )
        tables[f"overturn/{rid}"] = pd.DataFrame(rows, columns=list(OVERTURN_COLUMNS))
    write_tables(path, tables)
    return str(path)


@pytest.fixture
def empty_store(tmp_path) -> str:
    path = tmp_path / "empty.h5"
    with atomic_h5(path):
        pass
    return str(path)


def _is_png(path) -> bool:
    with open(path, "rb") as fh:
        head = fh.read(8)
    return head == PNG and path.stat().st_size > 5000


FIGS = [F.fig_3, F.fig_4, F.fig_5, F.fig_6, F.fig_7, F.fig_8, F.fig_9, F.fig_10, F.fig_11, F.fig_12, F.fig_13]


@pytest.mark.parametrize("fn", FIGS, ids=lambda f: f.__name__)
def test_figure_written(store, tmp_path, fn):
    out = fn(store, tmp_path / f"{fn.__name__}.png")
    assert out is not None, f"{fn.__name__} skipped on a store that has its data"
    assert _is_png(out)


def test_record_figure(store, tmp_path):
    out = F.fig_record(store, "NOR94-PKC", tmp_path / "rec.png")
    assert out is not None and _is_png(out)


def test_pdf_output(store, tmp_path):
    out = F.fig_6(store, tmp_path / "fig6.pdf")
    assert out is not None and out.read_bytes()[:4] == b"%PDF"


@pytest.mark.parametrize("fn", FIGS[1:], ids=lambda f: f.__name__)
def test_absent_data_skips(empty_store, tmp_path, fn, caplog):
    with caplog.at_level(logging.WARNING, logger="isorock.figures"):
        out = fn(empty_store, tmp_path / "x.png")
    assert out is None
    assert not (tmp_path / "x.png").exists()
    assert any("skipped" in r.getMessage() for r in caplog.records)


def test_missing_file_skips(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="isorock.figures"):
        assert F.fig_6(tmp_path / "nope.h5", tmp_path / "x.png") is None
        assert F.fig_record(tmp_path / "nope.h5", "A", tmp_path / "y.png") is None
    assert any("no store" in r.getMessage() for r in caplog.records)


def test_fig3_needs_no_store(tmp_path):
    """Fig 3 is closed-form: drawn even without a store."""
    out = F.fig_3(tmp_path / "nope.h5", tmp_path / "f3.png")
    assert out is not None and _is_png(out)


def test_absent_records_named(store, tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="isorock.figures"):
        assert F.fig_8(store, tmp_path / "x.png", records=("BUC77-BRI",)) is None
        assert F.fig_12(store, tmp_path / "y.png", lam=7.0) is None
    msgs = " ".join(r.getMessage() for r in caplog.records)
    assert "BUC77-BRI" in msgs and "IMV79-EMO" in msgs  # asked for, and what is there
    assert "lambda = 7" in msgs


def test_make_all(store, tmp_path):
    paths = F.make_all(store, tmp_path / "figs")
    names = {p.name for p in paths}
    assert {name for _, name in F.FIGURES.values()} <= names
    assert {f"record_{rid}.png" for rid in ("IMV79-EMO", "NOR94-PKC", "IMV79-E05", "NOR94-NWS")} <= names
    assert all(_is_png(p) for p in paths)


def test_make_all_empty_store(empty_store, tmp_path):
    paths = F.make_all(empty_store, tmp_path / "figs")
    assert [p.name for p in paths] == ["fig03_restitution.png"]


def test_map_colours_follow_codes(store, tmp_path):
    """Regime cells use the paper's colours: cyan no uplift, green rocking, red overturning."""
    from matplotlib.colors import to_rgb

    rgb = [to_rgb(c) for c in F.REGIME_COLORS]
    assert rgb[0][2] > 0.8 and rgb[0][1] > 0.8 and rgb[0][0] < 0.2  # cyan
    assert rgb[1][1] > 0.6 and rgb[1][0] < 0.4  # green
    assert rgb[2][0] > 0.8 and rgb[2][1] < 0.3  # red
    assert F.REGIME_LABELS == ("No uplift", "Rocking", "Overturning")


def test_record_matching():
    assert _match_record("NOR94-PKC", ["IMV79-EMO", "NOR94-PKC"]) == "NOR94-PKC"
    assert _match_record("IMV79-EMO", ["ImperialValley_EMO-270"]) == "ImperialValley_EMO-270"
    assert _match_record("PKF04-CH3W", ["IMV79-EMO"]) is None


def test_maps_found_by_attributes(store):
    with h5py.File(store, "r") as f:
        assert "maps/pulse-fullsine-td0.5/lambda_R-linear" in f
    maps = Store(store).maps()
    pm = [m for m in maps if m.source_kind == "pulse"]
    assert {(m.pulse, m.td_s, m.isolation) for m in pm} >= {
        ("fullsine", 0.5, "linear"),
        ("halfsine", 0.2, "none"),
    }
    tx = [m for m in maps if m.kind == "Tb-xi" and m.source == "NOR94-PKC"]
    assert sorted((m.lam, m.R_m) for m in tx) == [(3.0, 2.0), (3.0, 6.0), (4.0, 6.0)]


def _note_finished(p):
    """A ``finish`` of make_all: appends the image's name and the drawing process to a file."""
    with open(os.environ["ISOROCK_TEST_FINISHED"], "a") as fh:
        fh.write(f"{p.name} {os.getpid()}\n")


def test_make_all_in_two_processes_draws_the_same(store, tmp_path, monkeypatch):
    """The figures job draws with several processes: the same images, in the same order, each finished
    (here: its name recorded) by the process that drew it."""
    serial = F.make_all(store, tmp_path / "one")
    seen = tmp_path / "finished.txt"
    monkeypatch.setenv("ISOROCK_TEST_FINISHED", str(seen))
    parallel = F.make_all(store, tmp_path / "two", workers=2, finish=_note_finished)
    assert [p.name for p in parallel] == [p.name for p in serial]
    assert all(_is_png(p) for p in parallel)
    lines = seen.read_text().split("\n")[:-1]
    assert sorted(line.split()[0] for line in lines) == sorted(p.name for p in serial)
    assert os.getpid() not in {int(line.split()[1]) for line in lines}  # drawn in the workers


def test_record_figure_prints_the_pga_as_the_report_does(store, tmp_path, monkeypatch):
    """Issue 35, item 8: a record's PGA and PGV in its figure's title with the report's precision for
    a record's quantities (isorock.report.build.RECORD_DIGITS), not 3 decimals beside 4 digits."""
    import h5py

    from isorock.figures import records as figrec
    from isorock.report.build import RECORD_DIGITS

    titles = []
    save = figrec._save
    monkeypatch.setattr(
        figrec, "_save", lambda fig, out: (titles.append(fig._suptitle.get_text()), save(fig, out))[1]
    )
    assert F.fig_record(store, "NOR94-PKC", tmp_path / "rec.png") is not None
    with h5py.File(store, "r") as f:
        pga = float(f["records/NOR94-PKC"].attrs["pga_g"])
    assert f"PGA = {pga:.{RECORD_DIGITS}g} g, PGV = " in titles[0], (pga, titles)
