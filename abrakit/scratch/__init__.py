"""The single scratch test of Ch. 8.1–8.2: rigid indenters, penalty contact with friction, groove metrics, Hertz.

* :mod:`~abrakit.scratch.indenters` — analytic sphere and sphere-tipped cone (gap, normal, closest point,
  ∂n/∂x) and the indent-slide-unload path of the tip;
* :mod:`~abrakit.scratch.contact` — the point-wise penalty/Coulomb law, Eq. (8.1)–(8.4), with its consistent
  tangent, ready to be integrated over the specimen's surface by the finite element solver;
* :mod:`~abrakit.scratch.groove` — A_g, A_s, w, f_ab (Eq. 8.5), D_p (Eq. 8.6) and the wear regime of a
  cross-section, the section itself from the deformed mesh, and the removed (fully damaged) material;
* :mod:`~abrakit.scratch.hertz` — Hertz's sphere indentation, the elastic check of the indentation step.

Axes as in Fig. 8.1: top surface y = 0 with the block below, indentation along −y, sliding along +z, symmetry
plane x = 0. Units: N, mm, MPa (µm values written as mm).
"""

from __future__ import annotations

import numpy as np

from abrakit.scratch.contact import ContactResponse, contact_response, initial_state, penalty_from_stiffness
from abrakit.scratch.groove import (
    GrooveMetrics,
    Profile,
    RemovedMaterial,
    groove_metrics,
    profile_from_surface_nodes,
    removed_material,
)
from abrakit.scratch.hertz import HertzContact, effective_modulus, hertz_depth, hertz_sphere
from abrakit.scratch.indenters import (
    ConicalIndenter,
    FineZone,
    ScratchPath,
    SphericalIndenter,
    SurfaceGap,
    check_path,
)

__all__ = [
    "ConicalIndenter",
    "ContactResponse",
    "FineZone",
    "GrooveMetrics",
    "HertzContact",
    "Profile",
    "RemovedMaterial",
    "ScratchPath",
    "SphericalIndenter",
    "SurfaceGap",
    "check_path",
    "contact_response",
    "demo",
    "effective_modulus",
    "groove_metrics",
    "hertz_depth",
    "hertz_sphere",
    "initial_state",
    "penalty_from_stiffness",
    "profile_from_surface_nodes",
    "removed_material",
]

STEEL_E, STEEL_NU = 210000.0, 0.33
"""St-52 of Table 8.1/8.2: E in MPa, Poisson's ratio."""


def demo() -> str:
    """The scratch building blocks on the seed's default tip (R = 50 µm, d = 2 µm), without the FE solver."""
    R, d = 0.05, 0.002
    tip = SphericalIndenter(R)
    path = check_path(ScratchPath(depth=d, slide=0.1, z_start=0.05), FineZone(0.02, 0.18, x_max=0.03), tip)
    hertz = hertz_sphere(STEEL_E, STEEL_NU, R, d)

    # A surface point 10 nm inside the tip's apex at the end of the indentation, then dragged in 0.3 nm steps:
    # it sticks until the elastic slip reaches mu p / c_T = 1 nm, then slips at |t_T| = mu p.
    c_N = penalty_from_stiffness(STEEL_E, 0.001)
    x = path.position(1.0)[None] + [0.0, 1e-5, 0.0]
    state, lines = initial_state(1), []
    for step in range(6):
        old, new = path.position(1.0 + step * 3e-6), path.position(1.0 + (step + 1) * 3e-6)
        gap = tip.gap(x, new)
        response = contact_response(gap.gap, gap.normal, -(new - old)[None], state, c_N=c_N, mu=0.1,
                                    normal_gradient=gap.normal_gradient)
        state = response.state
        t_T = response.traction - np.sum(response.traction * gap.normal, axis=1)[:, None] * gap.normal
        ratio = np.linalg.norm(t_T) / response.pressure[0]
        lines.append(f"    step {step + 1}: p = {response.pressure[0]:7.1f} MPa, |t_T|/p = {ratio:.4f}, "
                     f"{['open', 'stick', 'slip'][state['status'][0]]}")

    # A groove shaped by the tip (parabola of depth d) with triangular pile-ups of 1.7 µm.
    a = np.sqrt(2 * R * d)
    xs = np.linspace(0.0, 2 * a, 401)
    ys = np.where(xs <= a, xs**2 / (2 * R) - d, np.maximum(0.0017 * (1 - abs(xs - 1.5 * a) / (0.5 * a)), 0.0))
    groove = groove_metrics(xs, ys, half=True)
    return "\n".join([
        f"Single scratch building blocks: sphere R = {R * 1e3:g} um, depth d = {d * 1e3:g} um, slide "
        f"{path.slide * 1e3:g} um, footprint radius {tip.footprint_radius(d) * 1e3:.2f} um",
        f"Hertz (elastic St-52, rigid tip): F = {hertz.force:.3f} N (half model {hertz.force / 2:.3f} N), "
        f"a = {hertz.contact_radius * 1e3:.2f} um, p0 = {hertz.max_pressure / 1e3:.1f} GPa",
        f"penalty c_N = E/h at h = 1 um: {c_N:.3g} N/mm3; a point under the sliding tip (mu = 0.1):",
        *lines,
        f"synthetic groove: A_g = {groove.groove_area * 1e6:.1f} um2, A_s = {groove.shoulder_area * 1e6:.1f} um2, "
        f"w = {groove.width * 1e3:.2f} um, f_ab = {groove.degree_of_wear:.3f} ({groove.regime}), "
        f"D_p = {groove.degree_of_penetration:.3f}",
    ])
