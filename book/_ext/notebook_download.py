"""Sphinx extension: every executed chapter can be downloaded as a Jupyter notebook (.ipynb, with its outputs).

MyST-NB executes each MyST-markdown chapter into ``_build/jupyter_execute/<page>.ipynb``. sphinx-book-theme offers
such a notebook in its download menu only when a launch service (Binder, JupyterHub, Colab) is configured; the book
has none (it builds and reads offline), so this copies the notebook beside the page's source in ``_sources`` and
names it in the page context, where the theme's download menu picks it up (``.ipynb`` beside ``.md`` and ``.pdf``).
The notebook runs where the chapter does: in ``book/`` of a clone, with the package installed.
"""

from pathlib import Path
from shutil import copy2


def executed_notebook(outdir, pagename: str) -> Path:
    """Where MyST-NB left the executed notebook of ``pagename`` (``outdir`` is the HTML output folder)."""
    return Path(outdir).parent / "jupyter_execute" / f"{pagename}.ipynb"


def offer_notebook(app, pagename, templatename, context, doctree):
    """Copy the executed notebook of a chapter to ``_sources`` and set ``ipynb_source`` for the download menu."""
    notebook = executed_notebook(app.outdir, pagename)
    if not notebook.is_file() or not context.get("sourcename", "").endswith((".md", ".md.txt")):
        return
    target = Path(app.outdir) / "_sources" / f"{pagename}.ipynb"
    target.parent.mkdir(parents=True, exist_ok=True)
    copy2(notebook, target)
    context["ipynb_source"] = f"{pagename}.ipynb"


def setup(app):
    app.connect("html-page-context", offer_notebook, priority=500)   # before the theme's header buttons (501)
    return {"parallel_read_safe": True}
