"""The built book in a real browser: headless Chromium opens every page from a local HTTP server.

Checks, on the book the quick workflow just built (fixture ``quick_workflow``): no broken image
(every ``<img>`` decodes with ``naturalWidth > 0``), no console error or uncaught exception, no
request to any host but the local server, MathJax typesets from the bundled copy, and every figure
or table id the pipeline produced (``results/figures/<id>.png``, ``results/tables/<id>.csv`` of
``data/figure_ids.yaml``) is shown as ``data-figure-id`` on some page (CONTRIBUTING.md, "Figures
in the book"). Figures drawn for the page (issue 13): every figure link (the image and its
caption's "Full size: PNG · PDF") opens the full-size file, and no figure displays below 60 % of
its native width unless it is linked full size; the displayed-size statistics are printed.
No table is wider than the content column unless a scroll container holds it, and no table cell
is cut off ("..." or an ellipsis); every image of every page (not only the thesis figures) has a
caption and a full-size link, and no page is above 5 MB (images linked as files, issue 25); every
link of the Downloads page (each result table's CSV, each figure's PNG and PDF) opens.
Screenshots of the report page, a chapter-3 page and the own-bicycle page are saved as
``<results>/book/report.png``, ``chapter3.png`` and ``own_bicycle.png``.

Uses Debian's chromium (``apt-get install chromium chromium-driver``; ``scripts/setup.sh
--browser``) through playwright; skipped with the reason when it is missing, unless
``PEDALREPRO_REQUIRE_BROWSER=1`` (set by .ci/run), in which case it fails.
"""

from __future__ import annotations

import functools
import os
import re
import struct
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import urlparse

import pytest

from pedalrepro import report

if TYPE_CHECKING:  # playwright is imported in the test (skipped without it)
    import pandas as pd
    from playwright.sync_api import BrowserContext, Page, Route

pytestmark = pytest.mark.browser

CHROMIUM = os.environ.get("PEDALREPRO_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                 "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync"]
LOCAL_HOSTS = {"127.0.0.1", "localhost"}
#: Smallest displayed / native width of a figure not linked to its full-size file.
MIN_DISPLAYED_FRACTION = 0.6
CHAPTER3_PAGE = "notebooks/03_2_time_frequency.html"
OWN_BICYCLE_PAGE = "notebooks/06_own_bicycle.html"
DOWNLOADS_PAGE = "notebooks/downloads.html"
#: Screenshots saved under <results>/book/ (issue 13, part 7).
SCREENSHOTS = {"notebooks/reproduction_report.html": "report.png", CHAPTER3_PAGE: "chapter3.png",
               OWN_BICYCLE_PAGE: "own_bicycle.png"}
#: Tables wider than the content column, with no scroll container between them and it.
OVERFLOWING_TABLES_JS = """() => {
    const main = document.querySelector('main') || document.body;
    const right = main.getBoundingClientRect().right + 1;
    return Array.from(main.querySelectorAll('table')).filter(t => {
        if (t.getBoundingClientRect().right <= right) return false;
        for (let p = t.parentElement; p && p !== main; p = p.parentElement) {
            const ox = getComputedStyle(p).overflowX;
            if (ox === 'auto' || ox === 'scroll') return false;
        }
        return true;
    }).map(t => (t.closest('[data-figure-id]')?.dataset.figureId || '') + ' '
                + t.innerText.slice(0, 60).replace(/\\s+/g, ' '));
}"""


#: Every image of a page's content: its figure's caption and its full-size link (issue 25, part 2).
IMAGES_JS = """() => Array.from((document.querySelector('main') || document.body)
        .querySelectorAll('img')).map(img => {
    const fig = img.closest('figure');
    const cap = fig ? fig.querySelector('figcaption') : null;
    const a = img.closest('a');
    return {name: fig ? (fig.dataset.figureId || fig.dataset.figureFile || '') : '',
            alt: img.getAttribute('alt') || '', src: img.getAttribute('src').slice(0, 80),
            captioned: !!(cap && cap.innerText.trim().length > 0),
            linked: !!(a && a.getAttribute('href') && !a.getAttribute('href').startsWith('data:')),
            inlined: img.getAttribute('src').startsWith('data:')};
})"""
#: Cells cut off: shown as "..." (pandas' truncation) or clipped with an ellipsis; and the
#: widest table against the content column (its full width, scrolled or not).
TABLE_CELLS_JS = """() => {
    const main = document.querySelector('main') || document.body;
    const col = main.querySelector('article') || main;
    const width = col.getBoundingClientRect().width;
    const truncated = [];
    let widest = 0, widestText = '';
    for (const t of main.querySelectorAll('table')) {
        if (t.scrollWidth > widest) {
            widest = t.scrollWidth;
            widestText = (t.closest('[data-figure-id]')?.dataset.figureId || '') + ' '
                         + t.innerText.slice(0, 40).replace(/\\s+/g, ' ');
        }
        for (const c of t.querySelectorAll('td, th')) {
            const text = c.innerText.trim();
            const cs = getComputedStyle(c);
            if (text === '...' || text === '\u2026'
                || (cs.textOverflow === 'ellipsis' && c.scrollWidth > c.clientWidth + 1))
                truncated.push(text.slice(0, 30));
        }
    }
    return {truncated: truncated, widest: widest, column: width, widestText: widestText};
}"""
#: Largest HTML page (bytes): images are linked as files, not inlined (issue 25, part 6).
MAX_PAGE_BYTES = 5_000_000


def _require_browser() -> None:
    missing = None
    if not (Path(CHROMIUM).is_file() and os.access(CHROMIUM, os.X_OK)):
        missing = f"{CHROMIUM} not found (apt-get install chromium chromium-driver)"
    else:
        try:
            import playwright.sync_api  # noqa: F401
        except ImportError as exc:  # pragma: no cover - the lock installs it
            missing = f"playwright not importable: {exc}"
    if missing:
        if os.environ.get("PEDALREPRO_REQUIRE_BROWSER") == "1":
            pytest.fail(f"browser required (PEDALREPRO_REQUIRE_BROWSER=1) but {missing}")
        pytest.skip(missing)


class _QuietHandler(SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:  # keep pytest output clean
        pass


@pytest.fixture(scope="module")
def served_book(quick_workflow):
    _require_browser()
    assert quick_workflow.returncode == 0, "the quick workflow failed (see test_workflow)"
    html_root = quick_workflow.results / "book" / "_build" / "html"
    handler = functools.partial(_QuietHandler, directory=str(html_root))
    server = ThreadingHTTPServer(("127.0.0.1", 0), handler)  # port 0: a free port
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}", html_root, quick_workflow.results
    finally:
        server.shutdown()
        server.server_close()


def _png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()[:24]
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


def _listen(page, rel: str, problems: list[str]) -> None:
    """Record console errors, uncaught exceptions, failed requests and HTTP errors of a page."""
    def console(m) -> None:
        if m.type == "error":
            problems.append(f"{rel}: console error: {m.text}")

    def response(r) -> None:
        if r.status >= 400:
            problems.append(f"{rel}: HTTP {r.status} {r.url[:120]}")

    page.on("console", console)
    page.on("pageerror", lambda e: problems.append(f"{rel}: exception {e}"))
    page.on("requestfailed", lambda r: problems.append(f"{rel}: request failed {r.url[:120]}"))
    page.on("response", response)


@dataclass
class _Findings:
    """What the pages of the book show, collected page by page in the browser."""

    problems: list[str] = field(default_factory=list)
    shown: dict[str, str] = field(default_factory=dict)  # figure id -> the first page showing it
    mathjax_pages: int = 0
    n_tables: int = 0
    downloads: list[str] = field(default_factory=list)
    sizes: list[dict] = field(default_factory=list)  # one per figure image: id, widths, links
    images: list[dict] = field(default_factory=list)  # every image: caption, full-size link
    # the widest table: width / column, width, column (px), where
    widest: list = field(default_factory=lambda: [0.0, 0, 0, ""])
    page_bytes: dict[str, int] = field(default_factory=dict)
    anchors: list[tuple[str, str]] = field(default_factory=list)  # (page, href) to an anchor


def _offline_route(foreign: list[str]) -> Callable[[Route], None]:
    """A route handler that lets local requests through and records and blocks the others.

    Parameters
    ----------
    foreign
        The URLs of blocked requests, appended to.

    Returns
    -------
    callable
        The handler, for ``context.route``.
    """
    def route(r: Route) -> None:
        url = urlparse(r.request.url)
        if url.scheme in ("data", "blob", "about") or url.hostname in LOCAL_HOSTS:
            r.continue_()
        else:  # record and block: the book must read fully offline
            foreign.append(r.request.url)
            r.abort()

    return route


def _read_figures(page: Page, rel: str, found: _Findings) -> None:
    """Broken images, the figure ids shown and each figure image's sizes and links of a page.

    Parameters
    ----------
    page
        The loaded playwright page.
    rel
        Its path in the book.
    found
        The findings, appended to.
    """
    broken = page.evaluate("""async () => {
        const imgs = Array.from(document.images);
        imgs.forEach(i => { i.loading = 'eager'; });
        await Promise.all(imgs.map(i => i.decode().catch(() => null)));
        return imgs.filter(i => !(i.complete && i.naturalWidth > 0))
                   .map(i => (i.getAttribute('alt') || '') + ' ' + i.src.slice(0, 80));
    }""")
    found.problems.extend(f"{rel}: broken image {b}" for b in broken)
    for fid in page.eval_on_selector_all(
            "[data-figure-id]", "els => els.map(e => e.dataset.figureId)"):
        found.shown.setdefault(fid, rel)
    for fig in page.eval_on_selector_all("figure.pedalrepro-figure", """els => els
            .filter(e => e.querySelector('img'))
            .map(e => { const img = e.querySelector('img');
                        const a = img.closest('a');
                        return {id: e.dataset.figureId,
                                natural: img.naturalWidth,
                                displayed: img.getBoundingClientRect().width,
                                image_link: a ? a.href : null,
                                links: Array.from(e.querySelectorAll('a[href]'))
                                            .map(x => x.href)}; })"""):
        fig["page"] = rel
        found.sizes.append(fig)


def _check_math(page: Page, rel: str, found: _Findings) -> None:
    """On a page with math, wait for MathJax and record a page it did not typeset.

    Parameters
    ----------
    page
        The loaded playwright page.
    rel
        Its path in the book.
    found
        The findings, appended to (and the count of pages with math).
    """
    if page.evaluate("() => document.querySelector('.math') !== null"):
        page.wait_for_function("() => window.MathJax && MathJax.startup"
                               " && MathJax.startup.promise", timeout=15_000)
        page.evaluate("() => MathJax.startup.promise")
        n_typeset = page.evaluate("() => document.querySelectorAll('mjx-container').length")
        if n_typeset == 0:
            found.problems.append(f"{rel}: math not typeset by MathJax")
        found.mathjax_pages += 1


def _read_layout(page: Page, rel: str, html_root: Path, found: _Findings) -> None:
    """Overflowing tables, every image, cut-off cells, the widest table, the page's size, its
    links to figure anchors and its tables.

    Parameters
    ----------
    page
        The loaded playwright page.
    rel
        Its path in the book.
    html_root
        The built HTML, for the page's size in bytes.
    found
        The findings, appended to.
    """
    found.problems.extend(f"{rel}: table overflows the column without a scroll container: {t}"
                          for t in page.evaluate(OVERFLOWING_TABLES_JS))
    for img in page.evaluate(IMAGES_JS):
        img["page"] = rel
        found.images.append(img)
    cells = page.evaluate(TABLE_CELLS_JS)
    found.problems.extend(f"{rel}: truncated table cell {c!r}" for c in cells["truncated"])
    if cells["widest"] / cells["column"] > found.widest[0]:
        found.widest[:] = [cells["widest"] / cells["column"], cells["widest"], cells["column"],
                           f"{rel} {cells['widestText']}"]
    found.page_bytes[rel] = (html_root / rel).stat().st_size
    found.anchors.extend((rel, h) for h in page.eval_on_selector_all(
        "main a[href*='#pedalrepro-']", "els => els.map(e => e.getAttribute('href'))"))
    found.n_tables += page.evaluate("() => document.querySelectorAll('main table').length")


def _read_page(context: BrowserContext, base: str, rel: str, html_root: Path, results: Path,
               found: _Findings) -> None:
    """Open one page of the book and collect what it shows; screenshot it when listed in
    :data:`SCREENSHOTS`, and read the Downloads page's links.

    Parameters
    ----------
    context
        The playwright browser context.
    base
        The local server's URL.
    rel
        The page's path in the book.
    html_root
        The built HTML.
    results
        The results folder (screenshots go to ``<results>/book/``).
    found
        The findings, appended to.
    """
    page = context.new_page()
    _listen(page, rel, found.problems)
    response = page.goto(f"{base}/{rel}", wait_until="networkidle")
    assert response is not None and response.ok, f"{rel}: {response and response.status}"
    _read_figures(page, rel, found)
    _check_math(page, rel, found)
    _read_layout(page, rel, html_root, found)
    if rel in SCREENSHOTS:
        page.screenshot(path=str(results / "book" / SCREENSHOTS[rel]), full_page=True)
    if rel == DOWNLOADS_PAGE:
        found.downloads = page.eval_on_selector_all(
            "main a[href$='.csv'], main a[href$='.png'], main a[href$='.pdf']",
            "els => els.map(e => e.href)")
    page.close()


def _check_downloads(context: BrowserContext, downloads: list[str], results: Path) -> None:
    """The Downloads page links every result table (CSV) and figure (PNG, PDF); each opens.

    Parameters
    ----------
    context
        The playwright browser context.
    downloads
        The Downloads page's links.
    results
        The results folder.
    """
    expected = ({p.relative_to(results / "tables").as_posix()
                 for p in (results / "tables").rglob("*.csv")}
                | {p.relative_to(results / "figures").as_posix()
                   for p in (results / "figures").rglob("*.p[nd][gf]")})
    linked = {h.split("/tables/", 1)[-1] if "/tables/" in h else h.split("/figures/", 1)[-1]
              for h in downloads}
    assert expected and expected <= linked, sorted(expected - linked)[:10]
    bad_downloads = [h for h in downloads if not context.request.get(h).ok]
    assert not bad_downloads, bad_downloads[:10]


def _figure_link_problems(context: BrowserContext, sizes: list[dict]) -> list[str]:
    """Every figure link opens the full-size file: the PNG at least as wide as the image shown,
    the PDF a PDF.

    Parameters
    ----------
    context
        The playwright browser context.
    sizes
        The figure images (:attr:`_Findings.sizes`).

    Returns
    -------
    list of str
        One line per link that does not.
    """
    link_problems = []
    for fig in sizes:
        for href in fig["links"]:
            r = context.request.get(href)
            body = r.body() if r.ok else b""
            if href.endswith(".png"):
                ok = (r.ok and body[:8] == b"\x89PNG\r\n\x1a\n"
                      and struct.unpack(">I", body[16:20])[0] >= fig["natural"])
            elif href.endswith(".pdf"):
                ok = r.ok and body[:5] == b"%PDF-"
            else:
                ok = r.ok
            if not ok:
                link_problems.append(f"{fig['page']} {fig['id']}: link {href} ({r.status})")
    return link_problems


def _bare_images(images: list[dict]) -> list[str]:
    """Every image, not only the thesis figures, needs a caption and a full-size link (issue
    25, part 2).

    Parameters
    ----------
    images
        Every image of every page (:attr:`_Findings.images`).

    Returns
    -------
    list of str
        One line per image without either, saying which it lacks.
    """
    return [f"{i['page']} {i['name'] or i['alt'] or i['src']}: "
            + ", ".join(w for w, ok in (("no caption", i["captioned"]),
                                        ("no full-size link", i["linked"])) if not ok)
            for i in images if not (i["captioned"] and i["linked"])]


def _check_page_sizes(found: _Findings) -> None:
    """Print the largest page and the widest table; no page above :data:`MAX_PAGE_BYTES`.

    Parameters
    ----------
    found
        The findings.
    """
    page_bytes, widest = found.page_bytes, found.widest
    largest = max(page_bytes, key=page_bytes.get)
    print(f"largest page: {largest} {page_bytes[largest] / 1e6:.2f} MB; widest table "
          f"{widest[1]} px in a {widest[2]:.0f} px column ({widest[0]:.2f}x): {widest[3]}")
    heavy = {p: f"{b / 1e6:.1f} MB" for p, b in page_bytes.items() if b > MAX_PAGE_BYTES}
    assert not heavy, f"pages above {MAX_PAGE_BYTES / 1e6:g} MB (inlined images?): {heavy}"


def _check_anchors(anchors: list[tuple[str, str]], html_root: Path,
                   coverage_ids: list[str]) -> None:
    """Links to figure anchors land on them, and the Appendices page links every appendix
    figure.

    Parameters
    ----------
    anchors
        ``(page, href)`` of every link to a figure anchor.
    html_root
        The built HTML.
    coverage_ids
        The thesis's figure and table ids (``data/figure_ids.yaml``).
    """
    broken_anchors = []
    for rel, href in anchors:
        target, _, anchor = href.partition("#")
        path = (html_root / rel).parent / target if target else html_root / rel
        if f'id="{anchor}"' not in path.resolve().read_text(encoding="utf-8"):
            broken_anchors.append(f"{rel}: {href}")
    assert not broken_anchors, broken_anchors
    appendix_links = {h.partition("#")[2] for r, h in anchors if r == "appendices.html"}
    appendix_ids = {f"pedalrepro-{i}" for i in coverage_ids if re.match(r"(fig|table)_[a-h]_", i)}
    assert appendix_ids <= appendix_links, sorted(appendix_ids - appendix_links)


def _check_figure_sizes(sizes: list[dict], results: Path) -> None:
    """Figures drawn for the page: each figure the pipeline wrote is linked to its full-size
    PNG and PDF, and none shows below 60 % of its native width unless linked full size; the
    displayed-size statistics are printed.

    Parameters
    ----------
    sizes
        The figure images (:attr:`_Findings.sizes`).
    results
        The results folder.
    """
    fractions = [f["displayed"] / f["natural"] for f in sizes]
    small = [f"{f['page']} {f['id']}: {f['displayed'] / f['natural']:.0%}" for f in sizes
             if f["displayed"] / f["natural"] < MIN_DISPLAYED_FRACTION and not f["image_link"]]
    assert not small, f"figures shown below {MIN_DISPLAYED_FRACTION:.0%} without a link: {small}"
    unlinked = sorted(f["id"] for f in sizes if (results / "figures" / f"{f['id']}.png").exists()
                      and not (f["image_link"] or "").endswith(f"/figures/{f['id']}.png"))
    assert not unlinked, f"figures not linked to their full-size PNG: {unlinked}"
    import statistics

    print(f"\nfigures: {len(sizes)} images; displayed / native width min "
          f"{min(fractions):.2f}, median {statistics.median(fractions):.2f}, max "
          f"{max(fractions):.2f}; {sum(bool(f['image_link']) for f in sizes)} linked full size; "
          f"{len({h for f in sizes for h in f['links']})} links opened")


def _check_shown(shown: dict[str, str], results: Path) -> pd.DataFrame:
    """Every id the pipeline produced is shown; every id shown is a thesis id or a registered
    figure beyond the thesis (shown under its own label).

    Parameters
    ----------
    shown
        Figure id -> the first page showing it.
    results
        The results folder.

    Returns
    -------
    pandas.DataFrame
        :func:`pedalrepro.report.figure_coverage` of the results.
    """
    coverage = report.figure_coverage(results)
    produced = set(coverage.loc[coverage["present"], "id"])
    produced |= {p.stem for p in (results / "figures").glob("fig_*.png")}
    not_shown = sorted(produced - set(shown))
    assert not not_shown, f"produced but not shown in the book (figures.show): {not_shown}"
    from pedalrepro import book

    unknown = sorted(s for s in set(shown) - set(coverage["id"])
                     if book.thesis_label(s) != book.BEYOND_THESIS)
    assert not unknown, f"shown ids not in data/figure_ids.yaml: {unknown}"
    return coverage


def test_every_page_in_a_browser(served_book):
    from playwright.sync_api import sync_playwright

    base, html_root, results = served_book
    pages = [doc + ".html" for doc in report.book_pages()]
    found = _Findings()
    foreign: list[str] = []

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        context = browser.new_context(viewport={"width": 1280, "height": 900})
        context.route("**/*", _offline_route(foreign))
        for rel in pages:
            _read_page(context, base, rel, html_root, results, found)
        _check_downloads(context, found.downloads, results)
        link_problems = _figure_link_problems(context, found.sizes)
        browser.close()

    assert not foreign, f"requests to other hosts: {sorted(set(foreign))}"
    coverage_ids = list(report.figure_ids()["id"])
    images = found.images
    bare = _bare_images(images)
    good = len(images) - len(bare)
    print(f"\nimages: {good} of {len(images)} with a caption and a full-size link; "
          f"{sum(i['inlined'] for i in images)} inlined")
    _check_page_sizes(found)
    _check_anchors(found.anchors, html_root, coverage_ids)
    assert not bare, "images without a caption or a full-size link:\n" + "\n".join(bare)
    assert not found.problems, "\n".join(found.problems)
    assert not link_problems, "\n".join(link_problems)
    _check_figure_sizes(found.sizes, results)
    from pedalrepro.figures import coverage as figure_coverage

    coverage_status = figure_coverage.coverage(results)["status"].value_counts().to_dict()
    print(f"figure ids: {coverage_status}")
    # the appendices page has math: MathJax ran from _static/mathjax
    assert found.mathjax_pages >= 1
    coverage = _check_shown(found.shown, results)
    width, height = _png_size(results / "book" / "report.png")
    assert width >= 1000 and height >= 600
    assert _png_size(results / "book" / "chapter3.png")[1] >= 2000  # a long page, full
    assert _png_size(results / "book" / "own_bicycle.png")[1] >= 900
    print(f"\ntables: {found.n_tables} on {len(pages)} pages, none overflowing without a scroll "
          f"container; downloads: {len(found.downloads)} links opened")
    print(f"\nbrowser: {len(pages)} pages, {len(found.shown)} of {len(coverage)} figure ids shown, "
          f"screenshot {width}x{height} px at {results / 'book' / 'report.png'}")
