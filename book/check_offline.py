"""After a build: the pages must load no script or stylesheet from the network (the book is read offline too).

Scans ``book/_build/html/**/*.html`` for ``<script src=...>`` and ``<link rel="stylesheet" href=...>`` that point to
``http(s)://`` or ``//`` and exits non-zero naming them; ``make book`` runs it after ``jupyter-book build``.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

HTML = Path(__file__).resolve().parent / "_build" / "html"
EXTERNAL = re.compile(r"""<(?:script[^>]*\ssrc|link[^>]*rel=["']?(?:stylesheet|preload)[^>]*\shref)"""
                      r"""=["']?((?:https?:)?//[^"' >]+)""")


def external_references(root: Path = HTML) -> dict[str, set[str]]:
    found: dict[str, set[str]] = {}
    for page in sorted(root.rglob("*.html")):
        urls = set(EXTERNAL.findall(page.read_text(errors="replace")))
        if urls:
            found[str(page.relative_to(root))] = urls
    return found


def main() -> int:
    if not HTML.exists():
        print(f"no built book at {HTML}: run `make book` first")
        return 1
    found = external_references()
    for page, urls in found.items():
        print(f"{page}: {', '.join(sorted(urls))}")
    if found:
        print(f"{len(found)} page(s) load scripts or stylesheets from the network")
        return 1
    print("book: no page loads a script or stylesheet from the network")
    return 0


if __name__ == "__main__":
    sys.exit(main())
