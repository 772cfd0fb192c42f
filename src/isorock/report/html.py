"""The templates of the report (``isorock/report/templates/``, package data) and the two Jinja2
environments that render them: the code computes every value, the templates only lay them out.

* The HTML pages (``<page>.html.j2``, each extending ``base.html.j2``: the head and its CSS, the
  navigation between the pages, the footer) are rendered with autoescaping: every value a page shows
  (record ids and labels, object names, file names, all the text) is escaped. The one piece of HTML
  inserted as it is, a table that pandas writes, is marked safe in one place, :func:`table_html`
  (pandas escapes the cells and headers itself); a figure is laid out by the template from its base64
  data.
* The landing page (``landing.rst.j2``) is RST, which Snakemake renders with its own Jinja2 and then
  docutils (which escapes HTML): no HTML escaping there, but every value goes through :func:`rst_text`
  (``finalize``), so that no value can end a line, open a directive, a link or inline markup, or a
  Jinja2 tag.

Both environments use :class:`jinja2.StrictUndefined`: a value that a template names and the code does
not pass stops the rendering (:class:`jinja2.UndefinedError`) instead of leaving a blank.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import jinja2
import pandas as pd
from markupsafe import Markup

from isorock.version import __version__

__all__ = ["html_env", "rst_env", "render_html", "render_rst", "table_html", "rst_text", "NAV"]

#: the pages of ``results/report`` in the navigation of every page (the order of the report's categories)
NAV = (
    ("assessment.html", "Assessment"),
    ("overturn.html", "Minimum overturning PGA"),
    ("records.html", "Records"),
    ("maps.html", "Regime maps"),
    ("paper.html", "The paper"),
)

_LOADER = jinja2.PackageLoader("isorock.report", "templates")


def _env(**kw: Any) -> jinja2.Environment:
    env = jinja2.Environment(
        loader=_LOADER,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        **kw,
    )
    env.globals.update(version=__version__, nav=[{"href": h, "title": t} for h, t in NAV])
    return env


def html_env() -> jinja2.Environment:
    """The environment of the HTML pages: autoescaped (any template but the RST ones)."""
    return _env(autoescape=jinja2.select_autoescape(disabled_extensions=("rst.j2",), default=True))


#: escaped by RST's backslash: an underscore that could end a reference (``name_``, ``name__``) and a
#: colon followed by a character (``javascript:...``, a URI docutils would make a link of)
_RST_ESCAPE = re.compile(r"_(?![0-9A-Za-z])|:(?=\S)")


def rst_text(value: Any) -> str:
    """A value as plain RST text, and safe for Snakemake's Jinja2 rendering of the landing page.

    One line (a line break could start a directive such as ``.. raw:: html``); no Jinja2 delimiter
    (``{`` and ``}`` become brackets), no emphasis or substitution (``*`` becomes ``x``, ``|`` a slash),
    no interpreted text or embedded link (a backquote becomes an apostrophe); backslashes, reference
    ends and URI colons escaped; a leading ``..`` escaped, so that it opens no directive.
    """
    text = " ".join(str(value).splitlines())  # the line ends docutils splits on
    text = text.replace("{", "(").replace("}", ")").replace("*", "x").replace("|", "/").replace("`", "'")
    text = _RST_ESCAPE.sub(lambda m: "\\" + m.group(0), text.replace("\\", "\\\\"))
    return "\\" + text if text.startswith("..") else text


def rst_env() -> jinja2.Environment:
    """The environment of the landing page (RST): no HTML escaping, every value through :func:`rst_text`."""
    return _env(autoescape=False, finalize=rst_text)


_HTML = html_env()
_RST = rst_env()


def render_html(template: str, **values: Any) -> str:
    """The page ``template`` (``<page>.html.j2``) with ``values``."""
    return _HTML.get_template(template).render(**values)


def render_rst(template: str, **values: Any) -> str:
    """The RST page ``template`` (``landing.rst.j2``) with ``values``."""
    return _RST.get_template(template).render(**values)


def table_html(
    df: pd.DataFrame,
    float_format: Callable[[float], str],
    formatters: dict[str, Callable[[Any], str]] | None = None,
) -> Markup:
    """A table as HTML, to insert as it is: the one place where the report marks HTML safe.

    Safe because pandas writes it with ``escape=True``: every cell and header (record ids, object
    names, file names) is escaped by pandas, after ``float_format`` or the column's ``formatters``
    made its text; the markup around them is pandas' own.
    """
    html = df.to_html(
        index=False, na_rep="-", float_format=float_format, formatters=formatters, border=0, escape=True
    )
    return Markup(html)
