"""Sphinx extension: one caption per figure.

A code cell's ``mystnb: figure:`` metadata (caption, name) is a property of the cell, but MyST-NB (1.x) wraps every
rich output of that cell (``display_data`` and ``execute_result``) in its own numbered figure carrying the caption:
a cell that displays a table and then a plot showed the caption twice, under two figure numbers. Here the figure
wraps one output of the cell: its last image output (``image/*``), or, in a cell without an image, its last rich
output. The cell's other outputs render as they would without figure metadata.
"""

from __future__ import annotations

from contextlib import contextmanager

from myst_nb import sphinx_ as nb_sphinx

DISPLAY = ("display_data", "execute_result")


def figure_output(outputs) -> int | None:
    """Index (into ``outputs``) of the output that carries a cell's figure caption, or None for no rich output."""
    rich = [i for i, output in enumerate(outputs) if output.get("output_type") in DISPLAY]
    images = [i for i in rich if any(mime.startswith("image/") for mime in outputs[i].get("data", {}))]
    return (images or rich or [None])[-1]


def install(renderer_class=None, module=nb_sphinx) -> None:
    """Patch MyST-NB's Sphinx renderer so that a cell's figure options apply to :func:`figure_output` only."""
    renderer_class = renderer_class or module.SphinxNbRenderer
    if getattr(renderer_class, "_figure_once", False):
        return
    render_outputs = renderer_class._render_nb_cell_code_outputs
    figure_context = module.create_figure_context

    def _render_nb_cell_code_outputs(self, token, outputs):
        target = figure_output(outputs)
        # MyST-NB opens one figure context per rich output, in order: say which of them is the figure
        self._figure_calls = iter([i == target for i, output in enumerate(outputs)
                                   if output.get("output_type") in DISPLAY])
        try:
            return render_outputs(self, token, outputs)
        finally:
            self._figure_calls = iter(())

    @contextmanager
    def create_figure_context(self, figure_options, line):
        wrap = next(getattr(self, "_figure_calls", iter(())), True)
        with figure_context(self, figure_options if wrap else None, line):
            yield

    renderer_class._render_nb_cell_code_outputs = _render_nb_cell_code_outputs
    renderer_class._figure_once = True
    module.create_figure_context = create_figure_context


def setup(app):
    install()
    return {"parallel_read_safe": True}
