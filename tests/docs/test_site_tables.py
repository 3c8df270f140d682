"""Tables on the site render as HTML tables, never as raw pipe text.

A Markdown table that reaches the HTML as text (a notebook output rendered as CommonMark, which
has no tables, or a table printed to stdout) shows as lines of ``| a | b |``; Sphinx turns its
``|---|`` row into ``|—|`` (``---`` is an em dash to it), so the scan reads both forms.
"""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))

#: a row of a pipe table: starts and ends with a pipe, with at least one more between
_ROW = re.compile(r"\|[^|\n]*\|.*\|")
#: a separator row: ``|---|``, ``|:--|`` or, after Sphinx's smart quotes, ``|—|`` and ``|–|``
_SEPARATOR = re.compile(r"\|\s*:?(?:-{3,}|[\u2013\u2014]+)\s*:?\s*\|")
#: elements without an end tag
_VOID = frozenset("area base br col embed hr img input link meta source wbr".split())


class _VisibleText(HTMLParser):
    """The text of a page a reader sees, without scripts, styles and notebook cells' code."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[bool] = []  # per open element: whether its text is skipped
        self.parts: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag in _VOID:
            return
        classes = (dict(attrs).get("class") or "").split()
        skipped = tag in ("script", "style") or "cell_input" in classes
        self.stack.append(skipped or (bool(self.stack) and self.stack[-1]))

    def handle_endtag(self, tag: str) -> None:
        if tag not in _VOID and self.stack:
            self.stack.pop()

    def handle_data(self, data: str) -> None:
        if not (self.stack and self.stack[-1]):
            self.parts.append(data)


def raw_table_lines(html: str) -> list[str]:
    """Return the lines of a page's visible text that are pipe-table syntax.

    Parameters
    ----------
    html
        The page's HTML.

    Returns
    -------
    list of str
        Each line (stripped) that is a table row (``| a | b |``) or a separator row
        (``|---|``, ``|—|``); code inputs of notebook cells, scripts and styles are not read.
    """
    parser = _VisibleText()
    parser.feed(html)
    parser.close()
    lines = (line.strip() for line in "".join(parser.parts).splitlines())
    return [
        line
        for line in lines
        if line.startswith("|") and (_ROW.fullmatch(line) or _SEPARATOR.search(line))
    ]


@pytest.mark.parametrize(
    "html",
    [
        "<p>| physics | goal yaw |\n|---|---|\n| kinematic | 0 |</p>",
        "<p>| physics | goal yaw |\n|\u2014|\u2014|\n| kinematic | 0 |</p>",
        "<div class='output stream'><pre>| a | b |\n|:--|--:|\n</pre></div>",
        "<p>|\u2013|\u2013|</p>",
    ],
)
def test_the_scan_finds_a_raw_table(html: str) -> None:
    assert raw_table_lines(f"<html><body>{html}</body></html>")


def test_the_scan_passes_tables_text_and_code() -> None:
    html = """<html><head><style>td { border: 1px; }</style></head><body>
    <table><tr><th>physics</th><th>goal yaw</th></tr><tr><td>kinematic</td><td>0</td></tr></table>
    <p>max |x_n(eq. 7) - x_n(eq. 9)| = 2.8e-16<br>|v*| / (lambda |t|) = 0.680</p>
    <div class="cell_input docutils container"><div><pre>lines = [
    "| policy | camera |",
    "|---|---|",
    ]
| a | b |</pre></div></div>
    <script>const t = "| a | b |";</script></body></html>"""
    assert raw_table_lines(html) == []


def test_notebook_tables_are_markdown_outputs_that_the_site_parses_with_tables() -> None:
    """A table an output prints is a ``text/markdown`` display (``display(Markdown(...))``), and
    myst-nb renders such outputs with a parser that has tables (its default, CommonMark, has
    none)."""
    printed = []
    for path in NOTEBOOKS:
        for k, cell in enumerate(json.loads(path.read_text())["cells"]):
            for output in cell.get("outputs", []):
                data = output.get("data", {})
                text = "".join(output.get("text", "")) + "".join(data.get("text/plain", ""))
                table = [line for line in text.splitlines() if _SEPARATOR.search(line)]
                if table and "text/markdown" not in data:
                    printed.append(f"{path.name} cell {k}")
    assert not printed, f"tables printed as text: {printed}"
    conf = (ROOT / "docs" / "conf.py").read_text()
    assert re.search(r"""^nb_render_markdown_format\s*=\s*["'](myst|gfm)["']""", conf, re.M)


@pytest.mark.slow
def test_no_page_of_the_site_shows_a_raw_pipe_table(site: Path) -> None:
    bad = {}
    for page in sorted(site.rglob("*.html")):
        if "_modules" in page.parts or page.name.startswith("_check_"):
            continue
        found = raw_table_lines(page.read_text())
        if found:
            bad[str(page.relative_to(site))] = found[:3]
    assert not bad, bad


@pytest.mark.slow
@pytest.mark.parametrize(
    ("page", "header"),
    [
        ("notebooks/02_features_and_interaction_matrices.html", "feature"),
        ("notebooks/03_ibvs_parking.html", "goal yaw [deg]"),
        ("notebooks/04_ibvs_vs_ppo.html", "success (95% CI)"),
        ("notebooks/04_ibvs_vs_ppo.html", "within 10 cm / 5 deg"),
    ],
)
def test_the_notebook_pages_render_their_tables_as_html_tables(
    site: Path, page: str, header: str
) -> None:
    html = (site / page).read_text()
    headers = re.findall(r"<th[^>]*>(.*?)</th>", html, flags=re.S)
    assert any(header in re.sub(r"<[^>]+>", "", h) for h in headers), (page, headers[:20])
