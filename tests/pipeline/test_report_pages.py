"""The pages of the report from their Jinja2 templates (isorock.report.html, isorock.report.build):
every value a page shows is escaped (autoescape), every page extends the base layout, a value a template
names and the code does not pass stops the rendering (StrictUndefined), the landing page's RST takes no
markup from a value, the long tables and the figures of a page keep it under the size limit, and the
templates are package data.

The pages are written by :func:`isorock.report.build.report_tables` from a small store made here
(a record, a block, two isolation cases), whose record id, label, source file and record directory carry
HTML: no workflow run is needed.
"""

from __future__ import annotations

import base64
import fnmatch
import tomllib
from pathlib import Path

import h5py
import jinja2
import numpy as np
import pandas as pd
import pytest

from isorock.report import build as report
from isorock.report import html as pages
from isorock.report.landing import landing_text
from isorock.store import Store
from support.records import ROOT

SCRIPT = "<script>alert(1)</script>"
ESCAPED = "&lt;script&gt;alert(1)&lt;/script&gt;"
RID = "R&D-1"  # a record id with an ampersand (file names may hold one)
TEMPLATES = ROOT / "src" / "isorock" / "report" / "templates"


def _store(path: Path) -> Path:
    """A store with one record (id, label, file and directory carrying HTML) and its overturning study."""
    rec = {k: np.nan for k in report._REC_COLS if k != "tp_error_pct"}
    rec.update(
        record=RID, label=f"Quake {SCRIPT} & co", component="SN", component_method="provided",
        component_qa="", source_file=f"/data/{SCRIPT}&x/r.at2", pulse_like=True, qa_passed=True, pga_g=0.5,
        Tp_s=1.0, Tp_method_s=1.0, table1_tp_s=1.1, substitute=False, rotated_from="",
    )  # fmt: skip
    pd.DataFrame([rec]).to_hdf(path, key="summary/records", format="table")
    ovt = pd.DataFrame(
        [
            {"record": RID, "lambda_": 4.0, "R_m": 1.0, "case": case, "isolation": kind, "min_overturn_g": g,
             "record_pga_g": 0.5, "resolution": 0.01, "b_m": 0.24, "h_m": 0.97}
            for case, kind, g in (("none", "none", 0.4), ("lin", "linear", 0.8))
        ]
    )  # fmt: skip
    ovt.to_hdf(path, key="summary/overturn", format="table")
    with h5py.File(path, "a") as f:
        f.attrs["record_source"] = f"records directory /data/{SCRIPT}&x"
        f.attrs["config_name"] = "cfg&co"
    return path


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> tuple[Path, list[Path]]:
    """The store and the pages that report_tables writes from it."""
    tmp = tmp_path_factory.mktemp("pages")
    h5 = _store(tmp / "isorock.h5")
    return h5, report.report_tables(h5, tmp / "report")


def _html(paths: list[Path]) -> dict[str, str]:
    return {p.name: p.read_text() for p in paths if p.suffix == ".html"}


def test_names_and_paths_are_escaped(written):
    """Record id, label, file and directory appear escaped on every page that shows them, never as HTML."""
    html = _html(written[1])
    assert set(html) == {"assessment.html", "records.html", "overturn.html", "maps.html", "paper.html",
                         f"{RID}.html"}  # fmt: skip
    for name, page in html.items():
        assert SCRIPT not in page, name
        assert "R&D" not in page.replace("R&amp;D", ""), name  # no bare ampersand of the id
    record = html[f"{RID}.html"]
    # the title (<title> and heading): autoescaped by the template
    assert f"<title>R&amp;D-1: Quake {ESCAPED} &amp; co</title>" in record
    assert f"<h3>R&amp;D-1: Quake {ESCAPED} &amp; co</h3>" in record
    # the records directory in a sentence of the template; the file in a table cell (escaped by pandas)
    assert f"Processed records (records directory /data/{ESCAPED}&amp;x)." in html["records.html"]
    assert "<td>r.at2</td>" in html["records.html"] and f"Quake {ESCAPED} &amp; co" in html["records.html"]
    assert "<td>R&amp;D-1</td>" in html["overturn.html"]


def test_every_page_extends_the_base_layout(written):
    """One layout: the head with its CSS, the navigation between the pages, the footer, on every page."""
    html = _html(written[1])
    for name, page in html.items():
        assert page.startswith("<!DOCTYPE html>\n<html") and page.count("<!DOCTYPE") == 1, name
        assert page.count('<nav class="pages"') == 1 and page.count("<footer>") == 1, name
        assert "th, td { border: 1px solid #bbb" in page, name
        for _, title in pages.NAV:
            assert f">{title}</a>" in page, (name, title)
    # the links of a record's page lead up to results/report; the page's own link is marked
    assert '<a href="../overturn.html">' in html[f"{RID}.html"]
    assert '<a href="records.html" aria-current="page">' in html["records.html"]
    # and every page template of the package extends it
    names = {p.name for p in TEMPLATES.glob("*.html.j2")} - {"base.html.j2", "_parts.html.j2"}
    assert {n.removesuffix(".j2") for n in names} == set(html) - {f"{RID}.html"} | {"record.html"}
    for n in names:
        assert '{% extends "base.html.j2" %}' in (TEMPLATES / n).read_text(), n


def test_autoescape_is_on_for_every_html_template():
    env = pages.html_env()
    for p in TEMPLATES.glob("*.j2"):
        assert env.autoescape(p.name) is (not p.name.endswith(".rst.j2")), p.name
    out = pages.render_html(
        "overturn.html.j2", title=SCRIPT, current="", root="", back="", note="a & b", overturn=None
    )
    assert SCRIPT not in out and f"<h3>{ESCAPED}</h3>" in out and "<p>a &amp; b</p>" in out


def test_a_missing_value_stops_the_rendering(tmp_path):
    values = {"title": "t", "current": "", "root": "", "back": "", "note": "n"}  # no 'overturn'
    with pytest.raises(jinja2.UndefinedError, match="overturn"):
        pages.render_html("overturn.html.j2", **values)
    with pytest.raises(jinja2.UndefinedError, match="tp_agreement"):
        report._Page(tmp_path / "records.html").write("records.html.j2", "Records", source="s", tp_note="",
                                                      records=None)  # fmt: skip
    assert not (tmp_path / "records.html").exists()
    with pytest.raises(jinja2.UndefinedError, match="sections"):
        pages.render_rst("landing.rst.j2")


def test_tables_are_the_only_html_marked_safe():
    """pandas escapes the cells and headers of the one piece of HTML inserted as it is."""
    df = pd.DataFrame({f"a {SCRIPT}": [f"{SCRIPT} & co", "x"], "v": [1.23456, np.nan]})
    out = pages.table_html(df, lambda x: f"{x:.3g}")
    assert SCRIPT not in out and f"<th>a {ESCAPED}</th>" in out and f"<td>{ESCAPED} &amp; co</td>" in out
    assert "<td>1.23</td>" in out and "<td>-</td>" in out
    sources = [*Path(report.__file__).parent.glob("*.py")]
    uses = [p.name for p in sources if "Markup(" in p.read_text()]
    assert uses == ["html.py"] and Path(pages.__file__).read_text().count("Markup(") == 1
    for p in TEMPLATES.glob("*.j2"):  # nor do the templates mark anything safe
        text = p.read_text().replace(" ", "")
        assert "|safe" not in text and "autoescapefalse" not in text and "Markup" not in text, p.name


def _docutils(rst: str) -> str:
    """The HTML that Snakemake's report makes of the landing RST (docutils, as snakemake.report does)."""
    from docutils.core import publish_parts

    return publish_parts(rst, writer="html")["html_body"]


def test_landing_values_are_plain_rst(written):
    """A value of the landing page (names, paths) opens no directive, link, markup or Jinja2 tag."""
    text = landing_text(Store(written[0]), None, pd.DataFrame({"x": [1]}))
    assert "(R&D-1)" in text  # the record that overturns its block on the ground
    html = _docutils(text)
    assert SCRIPT not in html and ESCAPED in html and "R&amp;D-1" in html
    hostile = [
        "x\n\n.. raw:: html\n\n   <script>alert(1)</script>",
        ".. include:: /etc/passwd",
        "`click <javascript:alert(1)>`_",
        "javascript:alert(1)",
        "{{ 7 * 7 }} {% if 1 %} *bold* |sub| name_ C:\\new",
    ]
    for value in hostile:
        rst = pages.render_rst("landing.rst.j2", sections=[{"title": "T", "text": value, "bullets": [value],
                                                            "after": [value]}], title="T")  # fmt: skip
        html = _docutils(rst)
        assert "<script" not in html and "href" not in html and "system-message" not in html, value
        assert html.count("<strong>") == 1 and "<em>" not in html, value  # the title's only
        assert "{{" not in rst and "{%" not in rst, value
        assert rst.count(".. raw:: html") == 1 and ("/etc/passwd" in html) is ("passwd" in value), value
    assert "C:\\new" in _docutils(pages.render_rst("landing.rst.j2", sections=[
        {"title": "T", "text": "C:\\new", "bullets": [], "after": []}], title="T"))  # fmt: skip


def test_landing_page_opens_at_the_top(written):
    """Snakemake centres its landing view vertically; the page's style puts it at the top, the answer
    first (the screen itself: test_report_browser.test_landing_answer_at_the_top_of_the_window)."""
    text = (written[1][-1]).read_text()
    assert written[1][-1].name == "landing.rst" and text.startswith("isorock results\n")
    body, _, style = text.partition(".. raw:: html")
    assert ".. " not in body and sum(1 for ln in body.splitlines() if ln.strip()) <= 20
    css = style.strip()
    assert css.startswith('<style id="isorock-landing">') and "align-items: flex-start" in css
    assert "<style" in _docutils(text)  # docutils passes it through, as the report does


def test_long_tables_are_cut_and_figures_left_out_to_keep_a_page_small(tmp_path, monkeypatch):
    png = tmp_path / f"fig {SCRIPT}.png".replace("/", "_")
    png.write_bytes(b"\x89PNG" + bytes(range(256)) * 40)
    page = report._Page(tmp_path / "assessment.html")
    long = pd.DataFrame({"object": [f"o{i}" for i in range(report.MAX_TABLE_ROWS + 5)]})
    table, again = page.table(long), page.table(long)
    first, second = page.figure(png), page.figure(png)
    assert page.figure(tmp_path / "absent.png") is None and page.table(None) is None
    assert (table.csv, again.csv) == ("assessment.csv", "assessment-2.csv")
    assert (tmp_path / "assessment-2.csv").read_text().count("\n") == len(long) + 1
    values = {"assessed": True, "conclusions": [], "legend": "", "assumptions": "a", "site": "",
              "details": [], "summary": table,
              "objects": [{"figures": [first, second], "candidates": []}], "glossary": []}  # fmt: skip
    full = page.write("assessment.html.j2", "Assessment", **values).read_text()
    assert full.count(base64.b64encode(png.read_bytes()).decode()) == 2
    assert f"The first {report.MAX_TABLE_ROWS} of {len(long)} rows; all of them in assessment.csv" in full
    monkeypatch.setattr(report, "MAX_PAGE_BYTES", len(full.encode()) - 10)
    out = page.write("assessment.html.j2", "Assessment", **values).read_text()
    assert second.left_out and not first.left_out and out.count("base64,") == 1  # the last figure first
    name = png.name.replace("<", "&lt;").replace(">", "&gt;")
    assert f'<p class="note">Figure {name} left out to keep this page small' in out


def test_templates_are_package_data():
    """A non-editable install gets every template (setuptools package-data of pyproject.toml)."""
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]
    files = [p.relative_to(ROOT / "src" / "isorock").as_posix() for p in TEMPLATES.iterdir()]
    assert files and all(any(fnmatch.fnmatch(f, g) for g in data["isorock"]) for f in files), files
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    assert any(d.lower().startswith("jinja2") for d in deps)


def test_a_record_page_shows_its_figures(tmp_path):
    """Issue 35, item 1: a record's page shows its figures (an ``<img>`` each, linked from
    results/figures, whose file the link reaches), not only their names."""
    import re

    h5 = _store(tmp_path / "isorock.h5")
    figdir = tmp_path / "figures"
    figdir.mkdir()
    safe = report._safe(RID)
    for kind in ("record", "overturn"):
        (figdir / f"{kind}_{safe}.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    written = report.report_tables(h5, tmp_path / "report", figdir)
    page = next(p for p in written if p.name == f"{RID}.html")
    srcs = re.findall(r'<img src="([^"]+)"', page.read_text())
    assert len(srcs) == 2
    for src in srcs:
        assert (page.parent / src).resolve().is_file(), src
    # the note names the figures drawn, not the maps this run did not draw
    note = re.search(r"also under 'Figures' \(per record\): ([^<]*)\.</p>", page.read_text())
    assert note is not None and note.group(1) == f"record_{safe}.png, overturn_{safe}.png"


def test_every_page_links_back_to_the_report(tmp_path):
    """Issue 35, item 1: every page of results/report links back to the report it belongs to, by a
    link that reaches the report's file from the page (results/report/records/ one level deeper)."""
    import re

    h5 = _store(tmp_path / "isorock.h5")
    rep = tmp_path / "report-cfg.html"
    rep.write_text("<html></html>")
    written = report.report_tables(h5, tmp_path / "results" / "report", report=rep)
    html = [p for p in written if p.suffix == ".html"]
    assert len(html) == 6
    for p in html:
        links = re.findall(r'<a href="([^"]+)" class="back" rel="home">([^<]*)</a>', p.read_text())
        assert len(links) == 1, p.name
        href, text = links[0]
        assert (p.parent / href).resolve() == rep.resolve(), (p.name, href)
        assert "report-cfg.html" in text
    # without a report named, no link that leads nowhere
    alone = report.report_tables(h5, tmp_path / "alone")
    assert not any('class="back"' in p.read_text() for p in alone if p.suffix == ".html")


def test_the_maps_page_shows_the_maps(tmp_path):
    """Issue 35, item 1: maps.html shows each record's regime maps (an ``<img>`` that reaches the
    figure), not a sentence naming where the pictures are."""
    import re

    h5 = _store(tmp_path / "isorock.h5")
    maps = pd.DataFrame(
        [{"source": RID, "map": "lambda_R", "kind": "lambda_R", "case": "none", "amp_g": 0.5,
          "amp_source": "table1", "nx": 2, "ny": 2, "no_uplift": 1, "rocking": 2, "overturn": 1,
          "seconds": 0.1}]
    )  # fmt: skip
    maps.to_hdf(h5, key="summary/maps", format="table")
    figdir = tmp_path / "figures"
    figdir.mkdir()
    (figdir / f"maps_{report._safe(RID)}.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    written = report.report_tables(h5, tmp_path / "report", figdir)
    page = next(p for p in written if p.name == "maps.html")
    text = page.read_text()
    srcs = re.findall(r'<img src="([^"]+)"', text)
    assert len(srcs) == 1 and (page.parent / srcs[0]).resolve().is_file(), srcs
    assert "pictures under 'Figures'" not in text


def test_a_record_quantity_prints_alike_on_every_page(tmp_path):
    """Issue 35, item 8: a record's PGA of 0.2996 g printed 0.2996 on the records page and 0.3 on the
    record's own page and beside its overturning PGA: one precision for a record's quantities."""
    import re

    h5 = _store(tmp_path / "isorock.h5")
    rec = pd.read_hdf(h5, "summary/records")
    rec["pga_g"] = 0.29963
    rec.to_hdf(h5, key="summary/records", format="table")
    ovt = pd.read_hdf(h5, "summary/overturn")
    ovt["record_pga_g"] = 0.29963
    ovt.to_hdf(h5, key="summary/overturn", format="table")
    html = _html(report.report_tables(h5, tmp_path / "report"))
    for name in ("records.html", f"{RID}.html", "overturn.html"):
        cells = re.findall(r"<td>(0\.3|0\.29\d*)</td>", html[name])
        assert cells and set(cells) == {"0.2996"}, (name, cells)


def test_an_empty_qa_column_is_left_out(tmp_path):
    """Issue 35, item 8: the QA mark is written only where the direction analysed is not the catalog
    row's; a column empty on every row is left out, one with a mark is shown."""
    h5 = _store(tmp_path / "isorock.h5")
    html = _html(report.report_tables(h5, tmp_path / "empty"))
    for name in ("records.html", f"{RID}.html"):
        assert "QA mark" not in html[name], name
    rec = pd.read_hdf(h5, "summary/records")
    rec["component_qa"] = "as recorded, azimuth 065 instead of SN (15 deg off)"
    rec.to_hdf(h5, key="summary/records", format="table")
    html = _html(report.report_tables(h5, tmp_path / "marked"))
    for name in ("records.html", f"{RID}.html"):
        assert "QA mark" in html[name] and "azimuth 065 instead of SN" in html[name], name


def test_the_glossary_lists_the_words_a_page_uses():
    """Issue 35, item 8: the assessment page explains its words and symbols (MCE, S_DS, lambda, tan
    alpha, beta, 'not eligible' ...): each one the page uses, none it does not."""
    text = "P(failure) at the MCE; x not eligible; beta 0.4; g tan alpha; S_DS; lambda 4; gamma_x"
    terms = [g["term"] for g in report.glossary(text)]
    for t in ("MCE", "not eligible (x)", "beta", "alpha, tan alpha", "S_DS, S_MS", "lambda", "gamma_x"):
        assert t in terms, t
    assert "Tb, xi" not in terms and "adj. p" not in terms
    assert all(g["meaning"] for g in report.glossary(text))


def test_the_assessment_page_has_its_glossary(tmp_path):
    """The page renders the glossary it is given, a definition list of the terms."""
    page = report._Page(tmp_path / "assessment.html")
    values = {"assessed": True, "conclusions": [], "legend": "", "assumptions": "a", "site": "",
              "details": [], "summary": None, "objects": [],
              "glossary": report.glossary("the MCE & beta")}  # fmt: skip
    out = page.write("assessment.html.j2", "Assessment", **values).read_text()
    assert '<details class="glossary" open>' in out
    assert "<dt>MCE</dt><dd>maximum considered earthquake" in out and "<dt>beta</dt>" in out


def test_the_report_tab_names_the_answer(written):
    """Issue 35, item 8: the report's tab says what the answer is about, not 'Snakemake Report': the
    landing page's raw HTML sets it (plain words only: it sits in an HTML attribute)."""
    from isorock.report.landing import report_title

    title = report_title(Store(written[0]), pd.DataFrame({"x": [1]}))
    assert title == "minimum overturning PGA of 1 record - isorock report"
    text = landing_text(Store(written[0]), None, pd.DataFrame({"x": [1]}))
    html = _docutils(text)
    assert f'data-title="{title}" onerror="document.title = this.dataset.title"' in html
