"""One small scene per book chapter: what ``abrakit demo`` runs and :func:`abrakit.demo` returns.

:data:`DEMOS` maps each chapter with code, by its file name in ``book/`` (the order of ``book/_toc.yml``), to a
function that runs a scene of that chapter in seconds and returns a plain-text summary of it. ``intro`` is the
book's introduction: its demo prints the reproduction verdicts the package recomputes itself. The reference
pages (``decisions``, ``api``, ``bibliography``) have no scene and no demo. The scenes are smaller than the
chapters' own (coarser meshes, shorter runs), so their numbers are the chapters' only where the chapter runs
the same scene.
"""

from __future__ import annotations

from collections.abc import Callable

from .basics import (
    demo_dem,
    demo_dem_identification,
    demo_evolution,
    demo_identification,
    demo_intro,
    demo_tensors,
)
from .bonds import demo_fatigue, demo_four_point_bending
from .continuum import (
    demo_anisotropic_damage,
    demo_comparison,
    demo_fem,
    demo_localisation,
    demo_model_one,
    demo_model_two,
    demo_plasticity,
)
from .wear_chain import (
    demo_contacting,
    demo_material_removal,
    demo_scratch,
    demo_scratch_to_wear,
    demo_scratch_volume,
    demo_wear,
)

__all__ = ["DEMOS", "REFERENCE_PAGES", "demo"]

DEMOS: dict[str, Callable[[], str]] = {
    "intro": demo_intro,
    "tensors": demo_tensors,
    "evolution": demo_evolution,
    "dem": demo_dem,
    "identification": demo_identification,
    "dem_identification": demo_dem_identification,
    "fem": demo_fem,
    "plasticity": demo_plasticity,
    "localisation": demo_localisation,
    "model_one": demo_model_one,
    "model_two": demo_model_two,
    "comparison": demo_comparison,
    "anisotropic_damage": demo_anisotropic_damage,
    "contacting": demo_contacting,
    "wear": demo_wear,
    "scratch": demo_scratch,
    "scratch_volume": demo_scratch_volume,
    "scratch_to_wear": demo_scratch_to_wear,
    "material_removal": demo_material_removal,
    "fatigue": demo_fatigue,
    "four_point_bending": demo_four_point_bending,
}
"""Book chapter (file name in ``book/``) -> its demo, in the order of the book."""

REFERENCE_PAGES = ("decisions", "api", "bibliography")
"""The book's pages without a demo: reference material, not chapters with a scene."""


def demo(chapter: str) -> str:
    """Run the demo of ``chapter`` (a key of :data:`DEMOS`) and return its plain-text summary."""
    if not isinstance(chapter, str):
        raise TypeError(f"chapter must be a chapter name (str), one of {list(DEMOS)}; got {chapter!r}")
    if chapter not in DEMOS:
        raise ValueError(f"unknown demo {chapter!r}; chapter must be one of {list(DEMOS)}")
    return DEMOS[chapter]()
