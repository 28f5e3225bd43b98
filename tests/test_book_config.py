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


def _load(name: str, path: Path):
    import importlib.util
    import sys

    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module                                  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_mathjax_and_the_page_assets_are_configured_once_and_thebe_is_off():
    """MathJax comes from the book's own copy only (Sphinx's mathjax extension, one ``mathjax_path``, no second
    copy in ``html_js_files``); thebe is off, and ``page_assets`` removes sphinx-thebe and repeated scripts."""
    book = yaml.safe_load((BOOK / "_config.yml").read_text())
    config = book["sphinx"]["config"]
    assert config["mathjax_path"] == "mathjax/tex-chtml-full.js"
    assert not [js for js in config.get("html_js_files", []) if "mathjax" in str(js).lower()]
    assert book["launch_buttons"]["thebe"] is False
    assert book["sphinx"]["local_extensions"]["page_assets"] == "_ext"
    assert config["html_context"]["default_mode"] in ("auto", "light", "dark")


def test_page_assets_drops_thebe_and_repeated_inline_scripts():
    from types import SimpleNamespace

    from sphinx.builders.html._assets import _JavaScript
    from sphinx.events import EventListener

    ext = _load("page_assets", BOOK / "_ext" / "page_assets.py")

    def thebe_handler(*args):
        pass

    def other_handler(*args):
        pass

    thebe_handler.__module__ = "sphinx_thebe"
    listeners = {"env-before-read-docs": [EventListener(1, thebe_handler, 500), EventListener(2, other_handler, 500)],
                 "doctree-resolved": [EventListener(3, thebe_handler, 500)]}
    app = SimpleNamespace(events=SimpleNamespace(listeners=listeners),
                          registry=SimpleNamespace(css_files=[("sphinx-thebe.css", {}), ("abrakit.css", {})]))
    assert ext.drop_thebe(app, SimpleNamespace(html_theme_options={"launch_buttons": {"thebe": False}})) == 2
    assert [x.id for x in listeners["env-before-read-docs"]] == [2] and listeners["doctree-resolved"] == []
    assert app.registry.css_files == [("abrakit.css", {})]
    wanted = SimpleNamespace(events=SimpleNamespace(listeners={"x": [EventListener(1, thebe_handler, 500)]}),
                             registry=SimpleNamespace(css_files=[]))
    assert ext.drop_thebe(wanted, SimpleNamespace(html_theme_options={"launch_buttons": {"thebe": True}})) == 0
    # Sphinx 7.4 registers a late inline script under the names None and "": one script, not two
    inline = dict(body="const THEBE_JS_URL = 1")
    scripts = [_JavaScript("_static/a.js"), _JavaScript(None, **inline), _JavaScript("", **inline),
               _JavaScript("_static/mathjax/tex-chtml-full.js", defer="defer"),
               _JavaScript("_static/mathjax/tex-chtml-full.js", defer="defer"),
               _JavaScript("_static/mathjax/tex-chtml-full.js")]   # the built pages had this third copy too
    context = {"script_files": scripts}
    ext.dedupe_page_scripts(None, "p", "page.html", context, None)
    assert context["script_files"] == [scripts[0], scripts[1], scripts[3]]


def test_a_cell_with_a_table_and_a_plot_gets_one_caption():
    """MyST-NB opens a figure for every rich output of a cell; ``figure_once`` lets only the cell's last image
    (or, without an image, its last rich output) carry the caption."""
    from contextlib import contextmanager
    from types import SimpleNamespace

    ext = _load("figure_once", BOOK / "_ext" / "figure_once.py")
    table = {"output_type": "execute_result", "data": {"text/html": "<table/>", "text/plain": "t"}}
    plot = {"output_type": "display_data", "data": {"image/png": "...", "text/plain": "<Figure>"}}
    text = {"output_type": "stream", "name": "stdout", "text": "x"}
    assert ext.figure_output([text, table, plot]) == 2
    assert ext.figure_output([plot, table, plot, text]) == 2
    assert ext.figure_output([text, table]) == 1
    assert ext.figure_output([text]) is None

    opened = []

    @contextmanager
    def create_figure_context(self, figure_options, line):
        opened.append(figure_options)
        yield

    class Renderer:                      # MyST-NB's loop: one figure context per rich output, in order
        def _render_nb_cell_code_outputs(self, token, outputs):
            for output in outputs:
                if output["output_type"] in ("display_data", "execute_result"):
                    with module.create_figure_context(self, {"caption": "c"}, 0):
                        pass

    module = SimpleNamespace(SphinxNbRenderer=Renderer, create_figure_context=create_figure_context)
    ext.install(module=module)
    ext.install(module=module)                                            # installing twice patches once
    Renderer()._render_nb_cell_code_outputs(None, [text, table, plot])
    assert opened == [None, {"caption": "c"}]


def test_the_book_stylesheet_is_registered_and_fits_88_characters():
    """``abrakit.css`` is in ``html_css_files`` and sets the code font and padding that let an 88-character line
    fit the text column at 1280 px: 88 x 0.6 em (a monospace advance) + both paddings within the column the
    stylesheet leaves (1280 px less the 20 % primary sidebar, the secondary one and 2 x 2 rem of margins)."""
    import re

    config = yaml.safe_load((BOOK / "_config.yml").read_text())["sphinx"]["config"]
    assert "abrakit.css" in config["html_css_files"] and "_static" in config["html_static_path"]
    css = (BOOK / "_static" / "abrakit.css").read_text()
    rem = 16
    font = float(re.search(r"--abrakit-code-font-size:\s*([\d.]+)rem", css).group(1)) * rem
    padding = float(re.search(r"--abrakit-code-padding:\s*([\d.]+)rem", css).group(1)) * rem
    secondary = float(re.search(r"--pst-sidebar-secondary:\s*([\d.]+)rem", css).group(1)) * rem
    column = 1280 - 0.2 * 1280 - secondary - 4 * rem
    assert 88 * 0.6 * font + 2 * padding <= column
    assert font >= 12                                          # still readable
    assert "overflow-x: auto" in css and "overflow-wrap: anywhere" in css


def test_the_browser_check_target_installs_chromium_and_playwright():
    import re

    makefile = (BOOK.parent / "Makefile").read_text()
    target = makefile.split("\nbook-check:", 1)[1].split("\n\n", 1)[0]
    assert "command -v chromium" in target and "apt-get install -y chromium" in target
    assert "book/check_browser.py" in target and "book-check" in makefile.split("\n.PHONY:", 1)[1].split("\n")[0]
    assert "browser" in re.search(r"pip install --quiet -e '\.\[([\w,]+)\]'", makefile).group(1).split(",")
    pyproject = (BOOK.parent / "pyproject.toml").read_text()
    assert re.search(r'^browser = \["playwright', pyproject, re.M)


def test_the_browser_check_tells_local_from_network_addresses():
    check = _load("check_browser", BOOK / "check_browser.py")
    for url in ["file:///book/index.html", "data:image/png;base64,AA", "about:blank", "http://localhost:8000/a",
                "http://127.0.0.1/x.js"]:
        assert check.is_local(url), url
    for url in ["https://unpkg.com/thebe@0.8.2/lib/index.js", "https://cdn.jsdelivr.net/npm/mathjax@3",
                "http://example.org/", "wss://example.org/socket"]:
        assert not check.is_local(url), url
    report = check.PageReport("a.html", equations=3, blocks=2)
    assert not report.failed and report.summary().startswith("a.html: 3 equations typeset, 0 console errors, 0/2")
    report.overflowing.append({"section": "s", "chars": 99, "scroll": 800, "client": 700, "first": "x"})
    assert report.failed and report.summary().endswith("FAIL") and "99 chars" in report.details()[0]


def test_the_browser_check_finds_what_a_reader_would_see_broken(tmp_path):
    """A page with a console error, a network image, raw TeX and a code line wider than its box fails on each;
    a plain page passes (in Debian's Chromium; skipped where it or Playwright is missing)."""
    import pytest

    pytest.importorskip("playwright.sync_api")
    check = _load("check_browser", BOOK / "check_browser.py")
    chromium = check.find_chromium()
    if chromium is None:
        pytest.skip("no Chromium on this machine (make book-check installs it)")
    style = "<style>pre { width: 300px; overflow-x: auto }</style>"
    (tmp_path / "index.html").write_text(f"<html><head>{style}</head><body><main><p>Fine.</p>"
                                         "<pre>short</pre></main></body></html>")
    (tmp_path / "bad.html").write_text(
        f"<html><head>{style}</head><body><main><p>Raw $$E = mc^2$$ here.</p><pre>{'x' * 200}</pre>"
        '<img src="https://example.org/a.png"><img src="missing.png">'
        "<script>console.error('boom')</script></main></body></html>")
    reports = {r.page: r for r in check.run(tmp_path, chromium=chromium)}
    assert not reports["index.html"].failed, reports["index.html"].details()
    bad = reports["bad.html"]
    assert any("boom" in line for line in bad.console)
    assert bad.network == ["https://example.org/a.png"]
    assert bad.raw_tex and "missing.png" in bad.broken
    assert len(bad.overflowing) == 1 and bad.overflowing[0]["chars"] == 200


def test_ci_opens_the_built_book_in_a_browser():
    """``.ci/run`` runs ``make book-check`` after ``make book``: a page with a script error, an untypeset
    equation or code that scrolls sideways fails CI."""
    commands = [line.strip() for line in (BOOK.parent / ".ci" / "run").read_text().splitlines()
                if line.startswith("make ")]
    assert commands.index("make book") < commands.index("make book-check")


def test_no_display_equation_puts_a_tag_inside_a_split():
    """Sphinx wraps a ``$$`` block that holds a line break (``\\\\``) in ``split``, where MathJax refuses
    ``\\tag`` ("\\tag not allowed in split environment"): such an equation is written as an amsmath
    ``equation`` block instead."""
    import re

    found = [(page.name, block[:60]) for page in sorted(BOOK.glob("*.md"))
             for block in re.findall(r"\$\$(.*?)\$\$", page.read_text(), re.S)
             if "\\tag" in block and "\\\\" in block]
    assert found == []
