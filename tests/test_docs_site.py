"""The documentation site builds with warnings as errors and every page works in a browser.

``mkdocs build --strict`` (what ``make docs`` runs) into a temporary folder, served on the
loopback address; headless Chromium (the system's, driven by Playwright) then opens every page
and checks that it renders — no console error, no script error, a title and text in the main
content, every image loaded — that every internal link and anchor resolves, and that the
site's search finds ``solve_pose``.
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import subprocess
import sys
import threading
from pathlib import Path
from urllib.parse import unquote, urljoin, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    # Without these Chromium calls home, and a closed network refuses the connections.
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site, built as ``make docs`` builds it."""
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "PYTHONPATH": str(ROOT)}
    completed = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )
    assert completed.returncode == 0, completed.stdout[-3000:] + completed.stderr[-6000:]
    return out


@pytest.fixture(scope="module")
def server(site: Path):
    """The site served on an ephemeral loopback port (search needs HTTP, not file://)."""

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args) -> None:
            pass

    httpd = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(Quiet, directory=str(site))
    )
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    httpd.shutdown()
    thread.join()


@pytest.fixture(scope="module")
def browser_context(tmp_path_factory):
    """A fresh headless Chromium profile."""
    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: apt-get install -y chromium (.ci/run does)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        context = playwright.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")),
            executable_path=str(CHROMIUM),
            args=CHROMIUM_FLAGS,
            headless=True,
        )
        yield context
        context.close()


def pages_of(site: Path) -> list[str]:
    """Every page's path in the site (``reference/redik.lie/`` for its ``index.html``)."""
    return sorted(
        path.parent.relative_to(site).as_posix() + "/" if path.parent != site else ""
        for path in site.rglob("index.html")
    )


def anchors_of(html: str) -> set[str]:
    """The ``id`` attributes of a page: the anchors a link may name."""
    return set(re.findall(r'\sid="([^"]+)"', html))


def target_file(site: Path, path: str) -> Path | None:
    """The file that serves ``path`` (a folder serves its ``index.html``), or None."""
    candidate = site / unquote(path).lstrip("/")
    if candidate.is_dir():
        candidate = candidate / "index.html"
    return candidate if candidate.is_file() else None


def check_page(context, url: str) -> tuple[list[str], list[str]]:
    """Open ``url`` in a new tab: what is wrong with the page, and its links."""
    page = context.new_page()
    problems: list[str] = []
    page.on("console", lambda m: m.type == "error" and problems.append(f"console: {m.text}"))
    page.on("pageerror", lambda error: problems.append(f"script error: {error}"))
    response = page.goto(url, wait_until="load")
    if response is None or response.status != 200:
        problems.append(f"HTTP {response.status if response else 'no response'}")
    if not page.title().strip():
        problems.append("no <title>")
    article = page.locator("article.md-content__inner")
    if article.count() != 1 or not article.inner_text().strip():
        problems.append("no main content")
    elif article.locator("h1").count() < 1:
        problems.append("no title")
    broken = page.eval_on_selector_all(
        "article img",
        "images => images.filter(i => !i.complete || i.naturalWidth === 0)"
        ".map(i => i.getAttribute('src'))",
    )
    problems += [f"image not loaded: {src}" for src in broken]
    links = page.eval_on_selector_all("a[href]", "links => links.map(a => a.href)")
    page.close()
    return problems, links


def link_problems(site: Path, server: str, links: list[str], anchors: dict) -> list[str]:
    """The internal links (and anchors) among ``links`` that lead nowhere in ``site``."""
    problems = []
    for link in links:
        parts = urlsplit(link)
        if not link.startswith(server):
            continue  # external: not followed on a closed network
        target = target_file(site, parts.path)
        if target is None:
            problems.append(f"broken link: {link}")
        elif parts.fragment and target.suffix == ".html":
            if target not in anchors:
                anchors[target] = anchors_of(target.read_text(encoding="utf-8"))
            if unquote(parts.fragment) not in anchors[target]:
                problems.append(f"broken anchor: {link}")
    return problems


def test_every_page_renders_and_every_internal_link_resolves(site, server, browser_context):
    paths = pages_of(site)
    assert len(paths) > 50, paths  # guides, course, reference: the generator ran
    anchors: dict[Path, set[str]] = {}
    failures = []
    internal = 0
    for path in paths:
        problems, links = check_page(browser_context, urljoin(server, path))
        internal += sum(link.startswith(server) for link in links)
        problems += link_problems(site, server, links, anchors)
        failures += [f"/{path}: {problem}" for problem in problems]
    assert internal > 1000
    assert not failures, "\n".join(failures[:50])


def test_search_finds_solve_pose(server, browser_context):
    page = browser_context.new_page()
    page.goto(server, wait_until="load")
    page.locator("label.md-search__icon, .md-search__input").first.click()
    page.locator("input.md-search__input").fill("solve_pose")
    results = page.locator(".md-search-result__item")
    results.first.wait_for(timeout=30_000)
    links = page.eval_on_selector_all(
        ".md-search-result__item a", "links => links.map(a => a.href)"
    )
    page.close()
    assert any("reference/redik.solvers.pose" in link for link in links), links
