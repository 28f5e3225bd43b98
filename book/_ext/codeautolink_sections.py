"""Sphinx extension: sphinx-exercise wraps the body of every exercise and solution in a section without a title,
and sphinx-codeautolink (0.20) pops a section title at the end of every section although it pushed one only for
sections with a title: the first exercise of a chapter emptied its stack (``IndexError: pop from empty list``) and
stopped the build. Here a section pops only the title it pushed."""

from docutils import nodes
from sphinx_codeautolink.extension.block import CodeBlockAnalyser


def has_title(section: nodes.section) -> bool:
    """Whether codeautolink's visitor pushed a title for ``section``: it does for a child node of type ``title``."""
    return any(type(child) is nodes.title for child in section.children)


def depart_section(self, node) -> None:
    if has_title(node):
        self.title_stack.pop()


def setup(app):
    CodeBlockAnalyser.depart_section = depart_section
    return {"parallel_read_safe": True}
