"""Sphinx extension: the docstrings write norms and absolute values as |x| (readable in ``help()``); RST reads
``|x|`` as a substitution reference. Before autodoc parses a docstring, every ``|`` outside an inline literal
(``...``) is escaped, so the API reference shows the bars as written."""

import re

LITERAL = re.compile(r"(``.*?``)")


def escape_bars(line: str) -> str:
    parts = LITERAL.split(line)
    return "".join(part if part.startswith("``") else part.replace("|", r"\|") for part in parts)


def process(app, what, name, obj, options, lines):
    lines[:] = [escape_bars(line) for line in lines]


def setup(app):
    app.connect("autodoc-process-docstring", process)
    return {"parallel_read_safe": True}
