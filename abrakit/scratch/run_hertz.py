"""The elastic check of the scratch's indentation step: a rigid sphere pressed into an elastic block, against Hertz.

:func:`hertz_indentation` runs the frictionless indentation of an elastic St-52 quarter block with the scratch's
contact term and solver (:func:`~abrakit.scratch.run.scene_solver`) and compares the force–depth curve
F = (4/3) E* √R d^{3/2} and the contact radius a = √(R d) of Hertz (:func:`~abrakit.scratch.hertz.hertz_sphere`).
Units: N, mm, MPa.

Example::

    check = hertz_indentation(h=0.005, penalty=3.0)       # elements of about a = sqrt(R d), c_N = 3 E/h
    check.error                                            # relative force error at the final depth
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np
import skfem

from abrakit.fem.boundary import Dirichlet
from abrakit.fem.kinematics import vector_basis
from abrakit.fem.solver import NewtonOptions, StepControl
from abrakit.materials import LogStrainPlasticity
from abrakit.scratch.contact import penalty_from_stiffness
from abrakit.scratch.contact_term import IndenterContact
from abrakit.scratch.hertz import hertz_sphere
from abrakit.scratch.indenters import ScratchPath, SphericalIndenter
from abrakit.scratch.run import scene_solver
from abrakit.scratch.scene import ST52, st52_material, zoned_axis
from abrakit.validation import check_integer, check_option, check_positive, check_range, number_arguments


class HertzCheck(NamedTuple):
    """FE indentation of an elastic quarter block against Hertz (lengths mm, forces N for the whole sphere).

    depth, force: the FE force–depth curve; hertz_force: (4/3) E* √R d^{3/2} at the same depths; error: relative
    force error at the final depth; contact_radius: √(A_c/π) from the closed nodes' surface share A_c;
    radius_bracket: (last closed, first open) node along the x axis; hertz_radius √(R d); max_penetration and
    the penetration the penalty allows at Hertz's peak pressure, p_0/c_N; elements, dofs, wall_time.
    """

    depth: np.ndarray
    force: np.ndarray
    hertz_force: np.ndarray
    error: float
    contact_radius: float
    radius_bracket: tuple[float, float]
    hertz_radius: float
    max_penetration: float
    allowed_penetration: float
    elements: int
    dofs: int
    wall_time: float


@number_arguments
def hertz_indentation(h: float, penalty: float = 1.0, *, R: float = 0.05, d: float = 5e-4, steps: int = 4,
                      extent: float = 30.0, growth: float = 1.4, linear_solver: str = "auto",
                      kinematics: str = "small") -> HertzCheck:
    """Frictionless sphere pressed into an elastic St-52 quarter block, the elastic check of the indentation step.

    The quarter x ≥ 0, z ≥ 0 (symmetry planes x = 0 and z = 0 through the tip's axis) of a block reaching
    ``extent`` contact radii a = √(R d) in every direction, the bottom fixed and the far sides free (the
    half-space of Hertz, truncated); elements of about ``h`` (mm) over (2.25 a)³ under the tip, growing by
    ``growth`` outside; penalty c_N = ``penalty`` · E / h. The depth is reached in ``steps`` increments. The
    truncation stiffens the block by about 0.4 a/L in depth (< 2 % for ``extent`` = 30), the nodal contact
    and the trilinear elements by O((h/a)²), the penalty softens it by the penetration p/c_N. ``kinematics``:
    "small" or "finite" (Hencky material, total Lagrangian; at d/R = 1 % the two agree to O(d/R)).
    """
    t0 = time.perf_counter()
    check_positive("h", h)
    check_positive("penalty", penalty)
    check_positive("R", R)
    check_positive("d", d)
    check_integer("steps", steps, 1)
    check_range("extent", extent, 2.25, None, low_open=True)          # beyond the fine zone of 2.25 a
    check_range("growth", growth, 1.0, None)
    a = math.sqrt(R * d)
    L = extent * a
    # fine zone 2.25 a: nodes then never fall on the contact edge r = a for h = a, a/2, a/4, ...
    axis = zoned_axis(0.0, L, 0.0, 2.25 * a, h, growth)
    ys = zoned_axis(-L, 0.0, -2.25 * a, 0.0, h, growth)
    mesh = skfem.MeshHex.init_tensor(axis, ys, axis)
    tol = 1e-9 * L
    mesh = mesh.with_boundaries({"x0": lambda x: x[0] < tol, "z0": lambda x: x[2] < tol,
                                 "bottom": lambda x: x[1] < -L + tol})
    basis = vector_basis(mesh)
    conditions = [Dirichlet.on(basis, "x0", "x"), Dirichlet.on(basis, "z0", "z"), Dirichlet.on(basis, "bottom")]
    path = ScratchPath(depth=d, slide=0.0, z_start=0.0, unload=False)
    c_N = penalty_from_stiffness(ST52["E"], h, penalty)
    contact = IndenterContact(basis, SphericalIndenter(R), path.position, c_N=c_N, mu=0.0, symmetry_factor=4.0)
    check_option("kinematics", kinematics, ("small", "finite"))
    finite = kinematics == "finite"
    material = LogStrainPlasticity(st52_material("elastic")) if finite else st52_material("elastic")
    solver = scene_solver(basis, material, conditions, contact, finite_strain=finite,
                          control=StepControl(initial=1.0 / steps, maximum=1.0 / steps, minimum=1e-4),
                          newton=NewtonOptions(residual_tol=1e-8, max_iterations=30, divergence_check_after=30),
                          linear_solver=linear_solver, inexact=False)                 # the Hertz check: exact
    depths, forces = [0.0], [0.0]

    def on_step(result):
        contact.on_step(result)
        depths.append(-float(path.position(result.load_factors[-1])[1]))
        forces.append(contact.forces.normal)

    contact.reset(0.0, np.zeros(basis.N))
    solver.run(end=1.0, progress=False, on_step=on_step)
    depths, forces = np.array(depths), np.array(forces)
    hertz = hertz_sphere(ST52["E"], ST52["nu"], R, depths)
    closed = contact.pressure > 0.0
    on_axis = np.abs(contact.reference[:, 2]) < tol
    bracket = (float(contact.reference[closed & on_axis, 0].max(initial=0.0)),
               float(contact.reference[~closed & on_axis, 0].min(initial=np.inf)))
    p0 = hertz_sphere(ST52["E"], ST52["nu"], R, d).max_pressure
    return HertzCheck(
        depth=depths, force=forces, hertz_force=np.asarray(hertz.force), error=float(forces[-1] / hertz.force[-1] - 1),
        contact_radius=math.sqrt(contact.forces.area / math.pi), radius_bracket=bracket, hertz_radius=a,
        max_penetration=contact.forces.max_penetration, allowed_penetration=p0 / c_N,
        elements=int(mesh.t.shape[1]), dofs=int(basis.N), wall_time=time.perf_counter() - t0)
