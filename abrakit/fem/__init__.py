"""Finite elements on scikit-fem (Ch. 4.2): kinematics, assembly, boundary conditions, Newton solver, meshes.

Example (``material`` is any :mod:`abrakit.materials` model)::

    from abrakit.fem import Dirichlet, Solver, meshes, vector_basis

    mesh = meshes.plate_with_hole()
    basis = vector_basis(mesh)                      # 2x2 Gauss on bilinear quadrilaterals
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
           Dirichlet.on(basis, "top", "y", 0.05, name="top")]
    result = Solver(basis, material, bcs).run(output="results/plate")
    result.curves["u_top"], result.curves["F_top"]
"""

from __future__ import annotations

from . import meshes
from .assembly import Assembler, skfem_internal_force, skfem_tangent
from .boundary import Constraints, Dirichlet, boundary_dofs, node_row_dofs, surface_load
from .kinematics import Kinematics, TotalLagrangianKinematics, vector_basis
from .linsolve import AMGSolver, DirectSolver, LinearSolveError, pardiso_available
from .output import load_checkpoint
from .pathfollow import (
    ArcLength,
    DissipationControl,
    LoadFactorControl,
    OpeningControl,
    PathControl,
    PathFollowingSolver,
)
from .solver import NewtonOptions, Solver, SolveResult, StepContext, StepControl, StepFailed, solve
from .tangent_reuse import ElementTangentReuse

__all__ = [
    "AMGSolver", "ArcLength", "Assembler", "Constraints", "Dirichlet", "DirectSolver", "DissipationControl",
    "ElementTangentReuse", "Kinematics", "LinearSolveError", "LoadFactorControl", "NewtonOptions", "OpeningControl",
    "PathControl", "PathFollowingSolver", "SolveResult", "Solver", "StepContext", "StepControl", "StepFailed",
    "TotalLagrangianKinematics", "boundary_dofs", "demo", "load_checkpoint", "meshes", "node_row_dofs",
    "pardiso_available", "skfem_internal_force", "skfem_tangent", "solve", "surface_load", "vector_basis",
]


def demo() -> str:
    """Elastoplastic quarter plate with a hole (Table 7.1 plasticity, plane strain): a few seconds."""
    import time

    import numpy as np

    from ..materials import VonMisesPlasticity
    from .problems import TABLE_7_1_PLASTICITY, plate_with_hole_problem

    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY, integration="implicit")
    solver = plate_with_hole_problem(material, displacement=0.05, control=StepControl(initial=0.1, maximum=0.1))
    start = time.perf_counter()
    result = solver.run(progress=False)
    elapsed = time.perf_counter() - start
    tangent = result.response.tangent
    t0 = time.perf_counter()
    for _ in range(5):
        solver.assembler.tangent(tangent)
    rate = 5 * solver.kin.ndof / (time.perf_counter() - t0)
    plastic = np.mean(result.state["alpha_p"].max(axis=1) > 0)
    return (
        f"Quarter plate with a hole (50 x 50 mm, R = 10 mm), plane strain, von Mises (Table 7.1), "
        f"{solver.kin.nel} bilinear quads / {solver.kin.ndof} DOF: top edge pulled to "
        f"{result.curves['u_top'][-1]:.3f} mm in {len(result.load_factors) - 1} steps "
        f"({int(result.iterations.sum())} Newton iterations, {result.cutbacks} cutbacks, {elapsed:.2f} s); "
        f"reaction {result.curves['F_top'][-1]:.1f} N/mm, {100 * plastic:.0f} % of the elements plastic. "
        f"Tangent assembly {rate:.3g} DOF/s."
    )
