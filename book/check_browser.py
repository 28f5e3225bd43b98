"""After a build: open every page of the built book in headless Chromium, as a reader does at a 1280 px window.

Each HTML page of ``book/_build/html`` (the site's own pages; not ``_static``, ``_sources``, ``_images``) is opened
from ``file://`` in a fresh Chromium profile (Debian's ``/usr/bin/chromium``, driven by Playwright over its pipe;
no browser is downloaded). After the page has loaded, MathJax has typeset it and its images have loaded, the page
fails on

- a console error or an uncaught script error;
- an untypeset equation: a MathJax error (``mjx-merror``), or raw TeX (``$$``, ``\\(``, ``\\[``, ``\\begin{``,
  ``$\\name``) left in the text outside code;
- a broken image (loaded with no pixels);
- a request to the network: any URL other than ``file:``, ``data:``, ``blob:``, ``about:`` or localhost (such
  requests are also refused, so the check runs offline);
- a code block (``pre``, source or output) wider than its box (``scrollWidth > clientWidth``: it scrolls sideways),
  or content cut off at the column's edge (a table, image, inline code or equation reaching past the text column
  outside a horizontally scrolling box).

It prints one line per page (equations typeset, console errors, overflowing code blocks of all code blocks),
the details below a page that fails, and the totals; it exits non-zero when any page fails. ``make book-check``
runs it after ``make book``. ``python book/check_browser.py [page.html ...]`` checks only the pages named.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import urlsplit

HTML = Path(__file__).resolve().parent / "_build" / "html"
WIDTH, HEIGHT = 1280, 900                     # px, the window a reader's laptop gives the book
SKIP = ("_static", "_sources", "_images", "_downloads")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]
LOCAL_SCHEMES = {"file", "data", "blob", "about"}
LOCAL_HOSTS = {"localhost", "127.0.0.1", "::1"}
MATHJAX_TIMEOUT = 60_000                      # ms for MathJax to typeset one page
REDIRECT = re.compile(r"""<meta\s+http-equiv=["']?refresh["']?[^>]*url=([^"' >]+)""", re.I)

# Runs in the page; returns what the reader sees. A block "overflows" when it scrolls sideways; an element is
# "cut off" when its right edge passes the text column's and no box between them scrolls horizontally.
PROBE = r"""() => {
  const column = document.querySelector('article.bd-article') || document.querySelector('main') || document.body;
  const right = column.getBoundingClientRect().right + 1;
  const visible = el => el.getClientRects().length > 0;
  const scrolls = el => {
    for (let e = el.parentElement; e && e !== column; e = e.parentElement) {
      const x = getComputedStyle(e).overflowX;
      if ((x === 'auto' || x === 'scroll') && e.getBoundingClientRect().right <= right) return true;
    }
    return false;
  };
  const label = el => {
    const sec = el.closest('section[id]');
    const text = (el.innerText || el.textContent || el.getAttribute('src') || '').trim();
    const lines = text.split('\n');
    return {section: sec ? sec.id : '', first: lines[0].slice(0, 60),
            chars: Math.max(0, ...lines.map(l => l.length))};
  };
  const blocks = [...column.querySelectorAll('pre')].filter(visible);
  const overflowing = blocks.filter(p => p.scrollWidth > p.clientWidth + 1)
    .map(p => Object.assign(label(p), {scroll: p.scrollWidth, client: p.clientWidth}));
  const cut = [...column.querySelectorAll('table, img, code, mjx-container[display="true"], .figure, figure')]
    .filter(el => visible(el) && !el.closest('pre') && el.getBoundingClientRect().right > right && !scrolls(el))
    .map(el => Object.assign(label(el), {tag: el.tagName.toLowerCase(),
                                         overshoot: Math.round(el.getBoundingClientRect().right - right)}));
  const skip = 'pre, code, kbd, samp, script, style, textarea, mjx-container, .highlight';
  const raw = [];
  const tex = /\$\$|\\\(|\\\[|\\begin\{|\$\\[A-Za-z]/;
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    if (tex.test(n.textContent) && !(n.parentElement && n.parentElement.closest(skip)))
      raw.push(n.textContent.trim().slice(0, 60));
  }
  const broken = [...document.images].filter(i => i.complete && i.naturalWidth === 0)
    .map(i => i.getAttribute('src'));
  return {equations: document.querySelectorAll('mjx-container').length,
          merrors: document.querySelectorAll('mjx-merror').length,
          raw: raw, broken: broken, blocks: blocks.length, overflowing: overflowing, cut: cut};
}"""

# MathJax 3 typesets after load: wait for its startup promise (pages without equations do not load it)
SETTLE = """async (timeout) => {
  const late = new Promise(r => setTimeout(r, timeout));
  const typeset = (window.MathJax && MathJax.startup && MathJax.startup.promise) || null;
  const images = Promise.all([...document.images].map(i => i.complete ? null :
      new Promise(r => { i.addEventListener('load', r); i.addEventListener('error', r); })));
  await Promise.race([Promise.all([typeset, images, document.fonts.ready]), late]);
}"""


def is_local(url: str) -> bool:
    """Whether loading ``url`` stays on this machine (a file, inline data, or a server on localhost)."""
    parts = urlsplit(url)
    return parts.scheme in LOCAL_SCHEMES or (parts.scheme in ("http", "https", "ws", "wss")
                                              and parts.hostname in LOCAL_HOSTS)


@dataclass
class PageReport:
    """What one page showed in the browser."""

    page: str
    equations: int = 0
    blocks: int = 0
    console: list[str] = field(default_factory=list)
    network: list[str] = field(default_factory=list)
    merrors: int = 0
    raw_tex: list[str] = field(default_factory=list)
    broken: list[str] = field(default_factory=list)
    overflowing: list[dict] = field(default_factory=list)
    cut: list[dict] = field(default_factory=list)

    @property
    def failed(self) -> bool:
        return bool(self.console or self.network or self.merrors or self.raw_tex or self.broken
                    or self.overflowing or self.cut)

    def summary(self) -> str:
        line = (f"{self.page}: {self.equations} equations typeset, {len(self.console)} console errors, "
                f"{len(self.overflowing)}/{self.blocks} code blocks overflow")
        extra = [f"{n} {what}" for n, what in [(len(self.cut), "cut off"), (self.merrors, "MathJax errors"),
                                               (len(self.raw_tex), "raw TeX"), (len(self.broken), "broken images"),
                                               (len(self.network), "network requests")] if n]
        return line + (", " + ", ".join(extra) if extra else "") + (" FAIL" if self.failed else "")

    def details(self) -> list[str]:
        out = [f"  console: {text}" for text in self.console]
        out += [f"  network: {url}" for url in self.network]
        out += [f"  raw TeX: {text!r}" for text in self.raw_tex]
        out += [f"  broken image: {src}" for src in self.broken]
        out += [f"  overflow: #{b['section']} {b['chars']} chars, {b['scroll']} px in {b['client']} px: "
                f"{b['first']!r}" for b in self.overflowing]
        out += [f"  cut off: <{c['tag']}> #{c['section']} {c['overshoot']} px past the column: {c['first']!r}"
                for c in self.cut]
        return out


def pages(root: Path, names: list[str] | None = None) -> list[Path]:
    """The site's HTML pages under ``root`` (or the ``names`` given, relative to ``root``), sorted."""
    if names:
        return [root / name for name in names]
    return sorted(p for p in root.rglob("*.html") if p.relative_to(root).parts[0] not in SKIP)


def redirect_target(path: Path) -> str | None:
    """Where a page that only redirects (Jupyter Book's ``index.html``) sends the reader, else None."""
    text = path.read_text(errors="replace")
    found = REDIRECT.search(text) if len(text) < 2000 else None
    return found.group(1) if found else None


def find_chromium() -> str | None:
    """Chromium's executable: ``$CHROMIUM``, else the first of chromium / chromium-browser on ``PATH``."""
    return os.environ.get("CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")


def check_page(context, path: Path, root: Path) -> PageReport:
    """Open ``path`` in a new tab of ``context`` and collect its :class:`PageReport`."""
    report = PageReport(str(path.relative_to(root)))
    page = context.new_page()

    def on_console(message):
        if message.type == "error" and is_local(message.location.get("url", "") or "file:"):
            report.console.append(message.text[:200])

    page.on("console", on_console)
    page.on("pageerror", lambda error: report.console.append(f"uncaught: {str(error)[:200]}"))
    page.on("request", lambda request: None if is_local(request.url) else report.network.append(request.url))
    try:
        page.goto(path.as_uri(), wait_until="load")
        page.wait_for_function("() => !window.MathJax || !MathJax.startup || !!MathJax.startup.document",
                               timeout=MATHJAX_TIMEOUT)
        page.evaluate(SETTLE, MATHJAX_TIMEOUT)
        seen = page.evaluate(PROBE)
    except Exception as error:                 # a page that does not load or settle fails, the others go on
        report.console.append(f"page did not settle: {str(error).splitlines()[0][:200]}")
        return report
    finally:
        page.close()
    report.equations, report.merrors, report.blocks = seen["equations"], seen["merrors"], seen["blocks"]
    report.raw_tex, report.broken = seen["raw"], seen["broken"]
    report.overflowing, report.cut = seen["overflowing"], seen["cut"]
    return report


def run(root: Path, names: list[str] | None = None, chromium: str | None = None) -> list[PageReport]:
    """Check every page of the book under ``root`` in one headless Chromium; returns one report per page."""
    from playwright.sync_api import sync_playwright

    reports = []
    with tempfile.TemporaryDirectory(prefix="book-check-") as profile, sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            profile, executable_path=chromium, headless=True, args=FLAGS[1:],
            viewport={"width": WIDTH, "height": HEIGHT}, service_workers="block")
        context.route(lambda url: not is_local(url), lambda route: route.abort())
        try:
            for path in pages(root, names):
                if (target := redirect_target(path)) is not None:
                    print(f"{path.relative_to(root)}: redirects to {target} (checked there)", flush=True)
                    continue
                report = check_page(context, path, root)
                print(report.summary(), flush=True)
                for line in report.details():
                    print(line, flush=True)
                reports.append(report)
        finally:
            context.close()
    return reports


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pages", nargs="*", help="pages to check, relative to the HTML folder (default: all)")
    parser.add_argument("--html", type=Path, default=HTML, help="the built book's HTML folder")
    args = parser.parse_args(argv)
    if not (args.html / "index.html").exists():
        print(f"no built book at {args.html}: run `make book` first")
        return 1
    chromium = find_chromium()
    if chromium is None:
        print("no Chromium found: install Debian's `chromium` package, or set CHROMIUM to its executable")
        return 1
    reports = run(args.html, args.pages, chromium)
    failed = [r for r in reports if r.failed]
    print(f"book-check: {len(reports)} pages, {sum(r.equations for r in reports)} equations typeset, "
          f"{sum(len(r.console) for r in reports)} console errors, "
          f"{sum(len(r.overflowing) for r in reports)}/{sum(r.blocks for r in reports)} code blocks overflow, "
          f"{sum(len(r.cut) for r in reports)} cut off, {sum(r.merrors + len(r.raw_tex) for r in reports)} "
          f"untypeset, {sum(len(r.broken) for r in reports)} broken images, "
          f"{sum(len(r.network) for r in reports)} network requests; {len(failed)} pages fail")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
