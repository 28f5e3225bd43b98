"""Sphinx extension: each page loads each of its scripts once, and no thebe.

- Sphinx (7.4) adds a script registered after the builder started (``app.add_js_file(None, body=...)``, as
  sphinx-togglebutton and sphinx-thebe do) twice: once as it was registered (file name ``None``) and once from the
  registry (file name ``""``); the two do not compare equal. A page loaded the inline ``const THEBE_JS_URL``
  twice, and the second declaration is a SyntaxError. MathJax's file came twice as well, once with ``defer`` and
  once without, and its second load fails ("Cannot set property Package of #<Object> which has only a getter").
  Here the page's scripts are deduplicated, first one kept: a file by its name, an inline script (``None`` and
  ``""`` read as the same) by its body and attributes.
- Jupyter Book always loads sphinx-thebe, which adds a configuration script naming a CDN, a script and a
  stylesheet to every page and a Binder configuration block to every executed page, even with
  ``launch_buttons: thebe: false`` (the book runs offline and offers no live kernel). With thebe off, the
  extension's event handlers and stylesheet are removed before the build starts.
"""

from __future__ import annotations

THEBE_MODULE = "sphinx_thebe"
THEBE_CSS = "sphinx-thebe.css"


def thebe_wanted(config) -> bool:
    """Whether the book asks for thebe (``launch_buttons: thebe: true`` in ``_config.yml``)."""
    options = getattr(config, "html_theme_options", None) or {}
    return bool((options.get("launch_buttons") or {}).get("thebe"))


def drop_thebe(app, config=None) -> int:
    """Disconnect sphinx-thebe's event handlers and drop its stylesheet, unless thebe is wanted; returns how many
    handlers were disconnected."""
    if thebe_wanted(config if config is not None else app.config):
        return 0
    dropped = 0
    for listeners in app.events.listeners.values():
        for listener in list(listeners):
            if getattr(listener.handler, "__module__", "").split(".")[0] == THEBE_MODULE:
                listeners.remove(listener)
                dropped += 1
    app.registry.css_files[:] = [(name, attrs) for name, attrs in app.registry.css_files if name != THEBE_CSS]
    return dropped


def script_key(script) -> tuple:
    """What makes two page scripts the same: a script file is its file name alone (loaded twice it runs twice,
    whatever its attributes), an inline script (file name ``None`` or ``""``) its priority and attributes, which
    hold its body."""
    filename = getattr(script, "filename", script) or ""
    if filename:
        return ("file", str(filename))
    attributes = getattr(script, "attributes", {}) or {}
    return ("inline", getattr(script, "priority", 500), tuple(sorted(attributes.items())))


def unique_scripts(scripts) -> list:
    """``scripts`` without repeats, in order (the first of equal scripts is kept)."""
    seen, kept = set(), []
    for script in scripts:
        key = script_key(script)
        if key not in seen:
            seen.add(key)
            kept.append(script)
    return kept


def dedupe_page_scripts(app, pagename, templatename, context, doctree):
    if "script_files" in context:
        context["script_files"] = unique_scripts(context["script_files"])


def setup(app):
    app.connect("config-inited", drop_thebe)
    # after every handler that adds a script to the page (MathJax's runs at the default priority, 500)
    app.connect("html-page-context", dedupe_page_scripts, priority=900)
    return {"parallel_read_safe": True}
