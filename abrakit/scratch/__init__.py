"""The single scratch test of Ch. 8.1–8.2: rigid indenters, penalty contact with friction, groove metrics, Hertz.

* :mod:`~abrakit.scratch.indenters` — analytic sphere and sphere-tipped cone (gap, normal, closest point,
  ∂n/∂x) and the indent-slide-unload path of the tip;
* :mod:`~abrakit.scratch.contact` — the point-wise penalty/Coulomb law, Eq. (8.1)–(8.4), with its consistent
  tangent, ready to be integrated over the specimen's surface by the finite element solver;
* :mod:`~abrakit.scratch.groove` — A_g, A_s, w, f_ab (Eq. 8.5), D_p (Eq. 8.6) and the wear regime of a
  cross-section, the section itself from the deformed mesh, and the removed (fully damaged) material;
* :mod:`~abrakit.scratch.hertz` — Hertz's sphere indentation, the elastic check of the indentation step;
* :mod:`~abrakit.scratch.scene` — the scene (block, mesh grading, tip, path, material) and its specimen;
* :mod:`~abrakit.scratch.run` — the finite element run of a scene, :func:`run_scratch`, and its result;
* :mod:`~abrakit.scratch.readouts` — the groove of a run and its volume balance;
* :mod:`~abrakit.scratch.budget` — where the displaced volume goes, and the steady rates along the slide;
* :mod:`~abrakit.scratch.erosion` — material removal: elements eroded by the steel's ductile failure.

Axes as in Fig. 8.1: top surface y = 0 with the block below, indentation along −y, sliding along +z, symmetry
plane x = 0. Units: N, mm, MPa (µm values written as mm).
"""

from __future__ import annotations

from abrakit.scratch.budget import steady_rates
from abrakit.scratch.contact import contact_response, initial_state
from abrakit.scratch.erosion import Erosion
from abrakit.scratch.groove import GrooveMetrics, groove_metrics
from abrakit.scratch.hertz import hertz_sphere
from abrakit.scratch.indenters import ConicalIndenter, SphericalIndenter
from abrakit.scratch.readouts import GrooveBalance, groove_balance
from abrakit.scratch.run import ScratchResult, run_scratch
from abrakit.scratch.run_hertz import HertzCheck, hertz_indentation
from abrakit.scratch.scene import (
    DEMO_SCENE,
    MESH_LEVELS,
    ST52,
    TABLE_8_2,
    ScratchScene,
    ScratchSpecimen,
    build_specimen,
)

__all__ = [
    # the scene and its run
    "ScratchScene", "DEMO_SCENE", "MESH_LEVELS", "ST52", "TABLE_8_2", "build_specimen", "ScratchSpecimen",
    "run_scratch", "ScratchResult", "Erosion",
    # the indenters and the contact law, Eq. (8.1)-(8.4)
    "SphericalIndenter", "ConicalIndenter", "contact_response", "initial_state",
    # the groove, Eq. (8.5)-(8.6), and where its volume goes
    "groove_metrics", "GrooveMetrics", "groove_balance", "GrooveBalance", "steady_rates",
    # the Hertz check of the indentation
    "hertz_sphere", "hertz_indentation", "HertzCheck",
]
