"""The book's configuration: MathJax ships with it (equations render offline), and the offline check finds
external scripts."""

from pathlib import Path

import yaml

BOOK = Path(__file__).resolve().parent.parent / "book"


def test_mathjax_is_vendored_with_its_fonts():
    config = yaml.safe_load((BOOK / "_config.yml").read_text())["sphinx"]["config"]
    assert "_static" in config["html_static_path"]
    script = BOOK / "_static" / config["mathjax_path"]
    assert script.is_file() and script.stat().st_size > 1_000_000
    assert list((BOOK / "_static/mathjax/output/chtml/fonts/woff-v2").glob("MathJax_Main-Regular.woff"))


def test_offline_check_finds_a_cdn_script(tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("check_offline", BOOK / "check_offline.py")
    check = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(check)
    (tmp_path / "a.html").write_text('<script defer src="https://cdn.example.org/x.js"></script>'
                                     '<script src="_static/local.js"></script>')
    (tmp_path / "b.html").write_text('<link rel="stylesheet" href="_static/theme.css">')
    assert check.external_references(tmp_path) == {"a.html": {"https://cdn.example.org/x.js"}}


def test_an_executed_chapter_is_offered_as_a_notebook(tmp_path):
    import importlib.util
    from types import SimpleNamespace

    spec = importlib.util.spec_from_file_location("notebook_download", BOOK / "_ext" / "notebook_download.py")
    ext = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ext)
    config = yaml.safe_load((BOOK / "_config.yml").read_text())["sphinx"]
    assert config["local_extensions"]["notebook_download"] == "_ext"
    html = tmp_path / "_build" / "html"
    (tmp_path / "_build" / "jupyter_execute").mkdir(parents=True)
    (tmp_path / "_build" / "jupyter_execute" / "dem.ipynb").write_text('{"cells": []}')
    app = SimpleNamespace(outdir=str(html))
    context = {"sourcename": "dem.md"}
    ext.offer_notebook(app, "dem", "page.html", context, None)
    assert context["ipynb_source"] == "dem.ipynb" and (html / "_sources" / "dem.ipynb").read_text() == '{"cells": []}'
    plain = {"sourcename": "api.rst"}
    ext.offer_notebook(app, "api", "page.html", plain, None)           # no executed notebook: nothing offered
    assert "ipynb_source" not in plain


def test_every_figure_of_the_book_has_a_caption():
    """A cell that shows one figure also names it (``fig-<chapter>-<k>``, numbered and citable); a cell that shows
    several images (a loop, or a figure beside a stored plot) has a caption only, as one name cannot label two."""
    import re

    missing = []
    for chapter in sorted(BOOK.glob("*.md")):
        for cell in re.finditer(r"```\{code-cell\} ipython3\n(.*?)```", chapter.read_text(), re.S):
            body = cell.group(1)
            if ("plt.subplots" in body or "plt.figure" in body) and not re.search(
                    r"^mystnb:\n  figure:\n    caption: \|\n      \S.+\n", body, re.M):
                missing.append(f"{chapter.name}: {body.splitlines()[0][:60]}")
    assert missing == [], missing


def test_no_chapter_contains_control_characters():
    """A TeX command written into a Python string without a raw prefix turns into a control character (``\\beta``
    into a backspace and "eta", ``\\varepsilon`` into a vertical tab): no chapter may contain one."""
    import re

    found = [f"{chapter.name}:{number}" for chapter in sorted(BOOK.glob("*.md"))
             for number, line in enumerate(chapter.read_text().splitlines(), 1)
             if re.search(r"[\x00-\x08\x0b\x0c\x0e-\x1f\t]", line)]
    assert found == [], found


def test_code_cells_link_to_the_api_and_a_section_without_title_pops_nothing():
    """sphinx-codeautolink links names in code cells to the API reference; sphinx-exercise's sections without a
    title made it pop a title it never pushed (book/_ext/codeautolink_sections.py mends that)."""
    import importlib.util
    from types import SimpleNamespace

    import pytest
    from docutils import nodes

    pytest.importorskip("sphinx_codeautolink")
    config = yaml.safe_load((BOOK / "_config.yml").read_text())["sphinx"]
    assert "sphinx_codeautolink" in config["extra_extensions"]
    assert config["local_extensions"]["codeautolink_sections"] == "_ext"
    spec = importlib.util.spec_from_file_location("codeautolink_sections", BOOK / "_ext" / "codeautolink_sections.py")
    ext = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ext)
    body = nodes.section(ids=["exercise-content"])                         # sphinx-exercise's: no title
    chapter = nodes.section("", nodes.title(text="Exercises"), body, ids=["exercises"])
    visitor = SimpleNamespace(title_stack=["Exercises"])
    ext.depart_section(visitor, body)
    assert visitor.title_stack == ["Exercises"]
    ext.depart_section(visitor, chapter)
    assert visitor.title_stack == []


def test_every_code_cell_line_fits_the_page():
    """Code cells are read on the page: at most 88 characters a line (the cells are kept in ruff's format at that
    width; strings and comments that it cannot split are wrapped by hand)."""
    import re

    def code(cell: str) -> list[str]:                  # without the cell's options (a YAML block or ":key:" lines)
        if cell.startswith("---\n"):
            cell = cell.split("\n---\n", 1)[1]
        return [line for line in cell.splitlines() if not re.match(r":\w+:", line)]

    long_lines = [f"{chapter.name}: {line[:50]}…" for chapter in sorted(BOOK.glob("*.md"))
                  for cell in re.finditer(r"```\{code-cell\} ipython3\n(.*?)```", chapter.read_text(), re.S)
                  for line in code(cell.group(1)) if len(line) > 88]
    assert long_lines == [], long_lines
