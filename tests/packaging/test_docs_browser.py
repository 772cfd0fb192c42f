"""The documentation site as a reader sees it, in headless Chromium at 1400 px (issue 35): the
configuration reference and the validation tables fit the page (no table, cell or page wider than
its box: the nested schema tables had cut their descriptions at the content's right edge), the
formulas of the validation page render from the MathJax the site ships (no CDN: offline, they had
shown as raw LaTeX), and the command-line reference prints an option's ``--`` as typed.

The site is built once for the module, as CI builds it (``sphinx -W``); a whole build, so these
tests are of the second stage (``pytest -m e2e``). They skip, saying so, where Chromium is not
installed (Debian: ``apt-get install chromium``).
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.e2e

CHROMIUM = next(
    (shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)), None
)
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="chromium is not installed (Debian: apt-get install chromium)"
)

#: run in the page once it has loaded (and MathJax has typeset it): what overflows, what MathJax drew
MEASURE = """
const bad = [];
const root = document.scrollingElement;
if (root.scrollWidth > root.clientWidth + 1) bad.push(`page ${root.scrollWidth} > ${root.clientWidth}`);
document.querySelectorAll(".table-wrapper, td, th").forEach((el) => {
  if (el.scrollWidth > el.clientWidth + 1)
    bad.push(`${el.tagName} ${el.scrollWidth} > ${el.clientWidth}: ${el.textContent.trim().slice(0, 50)}`);
});
document.body.dataset.overflow = JSON.stringify(bad);
document.body.dataset.math = document.querySelectorAll("mjx-container").length;
document.body.dataset.raw = document.querySelectorAll(".math").length;
"""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The documentation site, built as CI builds it."""
    out = tmp_path_factory.mktemp("site")
    res = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(ROOT / "docs"),
         str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert res.returncode == 0, res.stderr[-4000:]
    return out


def _measure(page: Path) -> dict[str, str]:
    """The page at 1400 x 900 in headless Chromium, measured by :data:`MEASURE` (a copy of the page,
    beside it, with the script added)."""
    text = page.read_text(encoding="utf-8")
    hook = f"<script>addEventListener('load', () => setTimeout(() => {{ {MEASURE} }}, 500));</script>"
    head, body, tail = text.rpartition("</body>")
    view = page.with_name(f"_measured_{page.name}")
    view.write_text(head + hook + body + tail, encoding="utf-8")
    args = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--window-size=1400,900", "--virtual-time-budget=10000", "--dump-dom"]  # fmt: skip
    res = subprocess.run([*args, view.as_uri()], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    return {k: html.unescape(v) for k, v in re.findall(r'data-(overflow|math|raw)="([^"]*)"', res.stdout)}


@needs_chromium
@pytest.mark.parametrize("page", ["reference/config.html", "validation.html"])
def test_tables_fit_the_page_at_1400_px(site, page):
    """Nothing wider than its box: the page, furo's table wrapper (which would scroll, its scrollbar
    hidden, cutting the text) and every cell."""
    data = _measure(site / page)
    assert json.loads(data["overflow"]) == [], page


def test_the_site_ships_mathjax(site):
    """The formulas' script is the site's own file, not a CDN's."""
    page = (site / "validation.html").read_text(encoding="utf-8")
    srcs = re.findall(r'<script[^>]+src="([^"]*mathjax[^"]*)"', page, flags=re.I)
    assert srcs and not any(s.startswith(("http:", "https:", "//")) for s in srcs), srcs
    assert all((site / s).is_file() for s in srcs), srcs


@needs_chromium
def test_the_validation_formulas_render_offline(site):
    """MathJax typesets every formula of the validation page from the site's own files."""
    data = _measure(site / "validation.html")
    assert int(data["raw"]) > 10 and int(data["math"]) >= int(data["raw"]), data


def test_the_cli_reference_prints_options_as_typed(site):
    """No en-dash where an option's ``--`` stands ("–lambda and –R" could not be copied)."""
    text = html.unescape(
        re.sub(r"<[^>]+>", "", (site / "reference" / "cli.html").read_text(encoding="utf-8"))
    )
    assert "--lambda" in text
    assert re.findall(r"\u2013[a-z]", text) == []
