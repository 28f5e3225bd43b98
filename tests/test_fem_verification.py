"""Verification of abrakit.fem against closed-form solutions: Kirsch hole, thick cylinder, 2D = 3D plane strain."""

import numpy as np
import pytest

from abrakit.fem import (
    Dirichlet,
    Kinematics,
    NewtonOptions,
    Solver,
    StepControl,
    StepFailed,
    boundary_dofs,
    meshes,
    vector_basis,
)
from abrakit.fem.problems import (
    TABLE_7_1_PLASTICITY,
    kirsch_displacement,
    kirsch_stress,
    plate_with_hole_problem,
    thick_cylinder_problem,
    thick_cylinder_solution,
)
from abrakit.materials import LinearElastic, VonMisesPlasticity

E, NU, SIGMA, RADIUS = 200000.0, 0.3, 100.0, 1.0


def kirsch_run(n, triangles=False):
    """Quarter plate 10R x 10R, symmetry on the axes, the exact Kirsch displacement on the outer edges."""
    mesh = meshes.plate_with_hole(10 * RADIUS, 10 * RADIUS, RADIUS, n_angular=n, n_radial=n, grading=8.0,
                                  triangles=triangles)
    basis = vector_basis(mesh)
    ux, uy = kirsch_displacement(*basis.doflocs, remote_stress=SIGMA, radius=RADIUS, E=E, nu=NU)
    exact = np.where(np.isin(np.arange(basis.N), basis.nodal_dofs[0]), ux, uy)
    outer = np.union1d(boundary_dofs(basis, "right"), boundary_dofs(basis, "top"))
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"), Dirichlet(outer, exact[outer])]
    solver = Solver(basis, LinearElastic(E, NU), bcs, control=StepControl(initial=1.0, maximum=1.0))
    result = solver.run(progress=False)
    sxx = result.response.stress[..., 0]
    exact_sxx = kirsch_stress(*solver.kin.quadrature_points, remote_stress=SIGMA, radius=RADIUS)[0]
    qp_error = np.abs(sxx - exact_sxx).max() / (3 * SIGMA)
    top_of_hole = np.argmin(np.hypot(mesh.p[0], mesh.p[1] - RADIUS))
    kt = solver.kin.project(sxx)[top_of_hole] / SIGMA
    return qp_error, kt


def test_kirsch_displacement_gives_kirsch_stress():
    """The two closed forms used below agree: Hooke's law (plane strain) of the FD strain of u is sigma."""
    x, y, h = np.array([1.3, 2.0, 0.4]), np.array([0.5, 1.1, 1.7]), 1e-6
    u = lambda x, y: kirsch_displacement(x, y, remote_stress=SIGMA, radius=RADIUS, E=E, nu=NU)  # noqa: E731
    exx = (u(x + h, y)[0] - u(x - h, y)[0]) / (2 * h)
    eyy = (u(x, y + h)[1] - u(x, y - h)[1]) / (2 * h)
    gxy = (u(x, y + h)[0] - u(x, y - h)[0] + u(x + h, y)[1] - u(x - h, y)[1]) / (2 * h)
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    sxx, syy, sxy = kirsch_stress(x, y, remote_stress=SIGMA, radius=RADIUS)
    assert np.allclose(sxx, lam * (exx + eyy) + 2 * mu * exx, rtol=1e-6)
    assert np.allclose(syy, lam * (exx + eyy) + 2 * mu * eyy, rtol=1e-6)
    assert np.allclose(sxy, mu * gxy, rtol=1e-6)
    assert kirsch_stress(0.0, RADIUS, remote_stress=SIGMA, radius=RADIUS)[0] == pytest.approx(3 * SIGMA)


def test_kirsch_stress_concentration_converges():
    """Stress at a hole in plane strain: max quadrature-point error of sigma_xx (relative to the peak 3 sigma)
    below 14 %, 10 %, 6.5 % on 8, 16, 32 elements per edge; the recovered K_t at the hole within 3 %, 2 %."""
    errors, kts = zip(*(kirsch_run(n) for n in (8, 16, 32)), strict=True)
    assert np.all(np.array(errors) < [0.14, 0.10, 0.065]), errors
    assert errors[0] > errors[1] > errors[2]
    assert abs(kts[1] - 3) < 0.03 * 3 and abs(kts[2] - 3) < 0.02 * 3, kts
    tri_error, _ = kirsch_run(32, triangles=True)  # constant-strain triangles: converging, more slowly
    assert tri_error < 0.11


@pytest.mark.slow
def test_kirsch_fine_mesh():
    error, kt = kirsch_run(64)
    assert error < 0.035 and abs(kt - 3) < 0.012 * 3


def run_cylinder(n, nu=0.49, K_H=0.0, end=1.3):
    r_p = 200.0
    material = VonMisesPlasticity(70000.0, nu, r_p, K_H, integration="implicit")
    solution = thick_cylinder_solution(10.0, 20.0, 70000.0, nu, np.sqrt(1.5) * r_p)
    solver = thick_cylinder_problem(material, pressure=solution.limit_pressure, n_radial=n, n_angular=n,
                                    control=StepControl(initial=0.1, maximum=0.1, minimum=1e-4))
    try:
        return solver.run(end=end, progress=False), solution, None
    except StepFailed as failure:
        return failure.result, solution, failure.load_factor


def test_thick_cylinder_follows_the_elastic_plastic_solution():
    """Outer radial displacement against pressure up to 0.9 of the collapse load (nu = 0.49, where Hill's solution
    is exact up to 1e-4): error below 2.5 % of the largest value on 6 x 6 and 0.6 % on 12 x 12 elements."""
    for n, tol in ((6, 0.025), (12, 0.006)):
        result, solution, _ = run_cylinder(n, end=0.9)
        p = result.load_factors * solution.limit_pressure
        exact = np.array([solution.outer_displacement(pi) for pi in p])
        fe = result.curves["u_outer"]
        assert np.abs(fe - exact).max() < tol * exact.max()
        assert p[-1] > 1.5 * solution.yield_pressure  # the path went well into the plastic range


def test_thick_cylinder_collapses_at_the_limit_load():
    """Perfect plasticity: no equilibrium beyond p_L = (2/sqrt 3) sigma_0 ln(b/a); with B-bar the last converged
    load is within 0.6 % (6 x 6) and 0.2 % (12 x 12) above it. Without B-bar the mesh locks and carries more."""
    for n, tol in ((6, 0.006), (12, 0.002)):
        _, _, collapse = run_cylinder(n)
        assert collapse is not None and 1.0 - 1e-3 <= collapse <= 1.0 + tol, collapse
    material = VonMisesPlasticity(70000.0, 0.49, 200.0, 0.0, integration="implicit")
    locked = thick_cylinder_problem(material, pressure=1.0, n_radial=6, n_angular=6, bbar=False)
    result = locked.run(end=thick_cylinder_solution(10, 20, 7e4, 0.49, np.sqrt(1.5) * 200).limit_pressure * 1.1,
                        progress=False)
    assert result.load_factors[-1] > 1.09  # locking: 10 % above the collapse load still "converges"


def test_thick_cylinder_solution_limits():
    s = thick_cylinder_solution(10.0, 20.0, 70000.0, 0.3, 300.0)
    assert s.plastic_radius(s.yield_pressure) == pytest.approx(10.0)
    assert s.plastic_radius(s.limit_pressure) == pytest.approx(20.0)
    assert s.limit_pressure == pytest.approx(2 / np.sqrt(3) * 300.0 * np.log(2.0))
    p = s.yield_pressure  # continuity of the displacement at first yield
    assert s.outer_displacement(p * (1 - 1e-9)) == pytest.approx(s.outer_displacement(p * (1 + 1e-9)), rel=1e-6)
    with pytest.raises(ValueError, match="pressure"):
        s.plastic_radius(1.01 * s.limit_pressure)


def test_plane_strain_equals_one_layer_of_hexes():
    """The extruded plate with u_z = 0 on both faces reproduces the plane-strain solution exactly (per mm), B-bar
    in both (ε_zz = 0 throughout, so the element mean dilatations agree). Full Newton in both: a chord step
    (NewtonOptions.chord_check) taken in one and not the other, where the residual sits at its tolerance, would
    end the two on iterates 1e-9 apart."""
    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY, integration="implicit")
    control, newton = StepControl(initial=0.25, maximum=0.25), NewtonOptions(chord_check=False)
    plane = plate_with_hole_problem(material, n_angular=6, n_radial=4, control=control,
                                    newton=newton).run(progress=False)
    mesh = meshes.extrude(meshes.plate_with_hole(n_angular=6, n_radial=4), thickness=3.0)
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"), Dirichlet.on(basis, "front", "z"),
           Dirichlet.on(basis, "back", "z"), Dirichlet.on(basis, "top", "y", 0.05, name="top")]
    solid = Solver(basis, material, bcs, control=control, newton=newton, bbar=True).run(progress=False)
    assert solid.curves["F_top"] == pytest.approx(3.0 * plane.curves["F_top"], rel=1e-9)
    assert Kinematics.from_basis(basis).nqp == 8


def test_quadratic_plate_elements_on_the_curved_hole_converge_faster():
    """Elastic plate with a hole: on the same coarse 8 × 6 mesh, Q8 and Q9 on the curved geometry are within 0.05 %
    of a fine Q9 reference, the bilinear Q4 (B-bar) more than 0.2 % off; unknown elements and a quadratic plate
    extruded into hexahedra are refused."""
    material = LinearElastic(**{k: TABLE_7_1_PLASTICITY[k] for k in ("E", "nu")})
    control = StepControl(initial=1.0, maximum=1.0)

    def force(element, n_angular, n_radial):
        solver = plate_with_hole_problem(material, n_angular=n_angular, n_radial=n_radial, element=element,
                                         control=control)
        return solver.run(progress=False).curves["F_top"][-1]

    reference = force("Q9", 32, 24)
    errors = {e: abs(force(e, 8, 6) / reference - 1) for e in ("Q4", "Q8", "Q9")}
    assert errors["Q8"] < 5e-4 and errors["Q9"] < 5e-4 < 2e-3 < errors["Q4"]
    with pytest.raises(ValueError, match="element"):
        plate_with_hole_problem(material, element="Q5")
    with pytest.raises(ValueError, match="thickness"):
        plate_with_hole_problem(material, element="Q9", thickness=3.0)


FELUPE_PLATE = {0.01: 2040.7, 0.02: 3509.0, 0.05: 4191.2, 0.10: 4992.7}
"""FElupe's converged top-edge forces (N/mm) of the same quarter plate (100 × 100 mm plate, hole radius 10 mm,
plane strain, Table 7.1 plasticity, uniaxial hardening 1.5 K_H = 12 000 MPa), an independent implementation."""


@pytest.mark.parametrize("element", ["Q8", "Q9"])
def test_plastic_plate_matches_an_independent_code(element):
    """Q8/Q9 on the curved 16 × 12 mesh, 20 load steps: the force–displacement curve within 0.1 % of FElupe's."""
    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY)
    solver = plate_with_hole_problem(material, n_angular=16, n_radial=12, element=element, displacement=0.1,
                                     control=StepControl(initial=0.05, maximum=0.05))
    result = solver.run(progress=False)
    u = np.array(list(FELUPE_PLATE))
    F = np.interp(u, result.curves["u_top"], result.curves["F_top"])
    np.testing.assert_allclose(F, list(FELUPE_PLATE.values()), rtol=1e-3)
