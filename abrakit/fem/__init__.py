"""Finite elements on scikit-fem (Ch. 4.2): kinematics, assembly, boundary conditions, Newton solver, meshes.

Example (``material`` is any :mod:`abrakit.materials` model)::

    from abrakit.fem import Dirichlet, Solver, plate_with_hole, vector_basis

    mesh = plate_with_hole()
    basis = vector_basis(mesh)                      # 2x2 Gauss on bilinear quadrilaterals
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
           Dirichlet.on(basis, "top", "y", 0.05, name="top")]
    result = Solver(basis, material, bcs).run(output="results/plate")
    result.curves["u_top"], result.curves["F_top"]
"""

from __future__ import annotations

from .assembly import Assembler, skfem_tangent
from .boundary import Dirichlet, boundary_dofs
from .kinematics import Kinematics, vector_basis
from .linsolve import DirectSolver
from .meshes import check_quality, double_notched_specimen, plate_with_hole, sharp_notch_specimen
from .pathfollow import PathControl, PathFollowingSolver
from .problems import (
    TABLE_7_1_PLASTICITY,
    SofteningBar,
    kirsch_displacement,
    kirsch_stress,
    plate_with_hole_problem,
    thick_cylinder_problem,
    thick_cylinder_solution,
)
from .solver import NewtonOptions, Solver, StepControl, StepFailed

__all__ = [
    # kinematics, assembly and boundary conditions (Ch. 4.2)
    "vector_basis", "Kinematics", "Assembler", "skfem_tangent", "Dirichlet", "boundary_dofs",
    # the Newton solver, load stepping and path following
    "Solver", "NewtonOptions", "StepControl", "StepFailed", "PathFollowingSolver", "PathControl", "DirectSolver",
    # meshes of the chapters
    "plate_with_hole", "double_notched_specimen", "sharp_notch_specimen", "check_quality",
    # verification problems with closed forms
    "thick_cylinder_problem", "thick_cylinder_solution", "plate_with_hole_problem", "kirsch_stress",
    "kirsch_displacement", "TABLE_7_1_PLASTICITY", "SofteningBar",
]
