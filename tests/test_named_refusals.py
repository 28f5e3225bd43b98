"""Issue 38's examples of bad input that was accepted, hung or failed deep inside numpy/scipy: each now raises a
``ValueError``/``TypeError`` that names the parameter (one case per line, each cheap)."""

import numpy as np
import pytest

NAN, INF = float("nan"), float("inf")


def _cases():
    import skfem

    from abrakit import evolution, wear
    from abrakit.damage.laplacian import element_laplacian
    from abrakit.damage.model_one_fe import coupled_damage_function
    from abrakit.dem.neighbours import candidate_pairs
    from abrakit.dem.scenes import settling
    from abrakit.dem.walls import Servo
    from abrakit.experiments.contacting import pressed_bed
    from abrakit.fem import Solver
    from abrakit.fem.kinematics import vector_basis
    from abrakit.fem.linsolve import AMGSolver
    from abrakit.materials import LinearElastic
    from abrakit.materials.base import finite_difference_tangent
    from abrakit.materials.model_one import damage_function_update

    def laplacian():
        return element_laplacian(skfem.MeshQuad().refined(1))

    def solver_with(force):
        return Solver(vector_basis(skfem.MeshQuad().refined(1)), LinearElastic(1.0, 0.3), external_force=force)

    elastic = LinearElastic(1.0, 0.3)
    return [
        ("normal_force", lambda: wear.G65Test(normal_force=-1.0)),
        ("rpm", lambda: wear.G65Test(rpm=NAN)),
        ("grain_sizes", lambda: wear.G65Test(grain_sizes=(4e-4, 1e-4))),
        ("x must", lambda: candidate_pairs(np.array([[0.0, 0, 0], [INF, 0, 0]]), np.ones(2), 0.1)),
        ("rtol", lambda: AMGSolver(rtol=NAN)),
        ("maxiter", lambda: AMGSolver(maxiter=-5)),
        ("max_speed", lambda: Servo(0, 1e6, 1.0, max_speed=-INF)),
        ("external_force", lambda: solver_with(NAN)),
        ("r_d", lambda: damage_function_update(0.5, 1.0, 0.0, 0.0, 1.0, 0.0, 1e-6)),
        ("h", lambda: finite_difference_tangent(elastic, elastic.initial_state(()), np.zeros(6), h=0.0)),
        ("r_d", lambda: coupled_damage_function(np.full(4, 0.9), np.ones(4), laplacian(), 1.0, -1.0, 1e-6)),
        ("laplacian", lambda: coupled_damage_function(np.full(4, 0.9), np.ones(4), None, 1.0, 1.0, 1e-6)),
        ("time must", lambda: evolution.reference_solution(None, None, [0.0, NAN], _rate_dissipation())),
        ("rtol", lambda: evolution.reference_solution(None, None, [0.0, 1.0], _rate_dissipation(), rtol=NAN)),
        ("balance", lambda: pressed_bed(0.01, box=0.05, balance=NAN)),
        ("balance", lambda: pressed_bed(0.01, box=0.05, balance=0.0)),
        ("max_steps", lambda: settling(10, max_steps=None)),
    ]


def _rate_dissipation():
    from abrakit.evolution import Dissipation

    return Dissipation(r1=1.0, r2=1.0)


def _specimen_cases():
    from abrakit.experiments.specimen import DemSpecimen, SpecimenSpec

    spec = SpecimenSpec()
    x = np.array([[0.1, 0.1, 0.1], [NAN, 0.2, 0.2]])
    return [("x must", lambda: DemSpecimen(spec, x, np.ones(2), np.ones(3))),
            ("x must", lambda: DemSpecimen(spec, np.zeros((3, 3)), np.ones(2), np.ones(3))),
            ("radius", lambda: DemSpecimen(spec, np.zeros((2, 3)), -np.ones(2), np.ones(3)))]


@pytest.mark.parametrize("index", range(17))
def test_bad_input_is_refused_by_name(index):
    name, call = _cases()[index]
    with pytest.raises((ValueError, TypeError), match=name):
        call()


@pytest.mark.parametrize("index", range(3))
def test_a_specimen_refuses_non_finite_or_mismatched_positions_by_name(index):
    name, call = _specimen_cases()[index]
    with pytest.raises((ValueError, TypeError), match=name):
        call()


def _door_cases():
    """Bad input at public names that gave NaN or infinity from finite input, was accepted, failed deep or ran
    long: each is refused with an error naming the parameter (one case per entry, each cheap)."""
    import skfem

    from abrakit.damage.metrics import band_width
    from abrakit.damage.model_two_fe import rate_limit_work
    from abrakit.dem import Particles, Simulation, Walls
    from abrakit.dem.neighbours import candidate_pairs
    from abrakit.dem.periodic import voigt_strain
    from abrakit.experiments.compression import sphere_stress
    from abrakit.experiments.cyclic import stage_slopes
    from abrakit.experiments.disk_packing import wall_stress
    from abrakit.fatigue.single_bond import BondTest
    from abrakit.fem import Solver
    from abrakit.fem.kinematics import FBarKinematics, Kinematics, vector_basis
    from abrakit.g65 import G65Standard
    from abrakit.materials import LinearElastic
    from abrakit.materials.driver import PathResult
    from abrakit.materials.finite_strain import DeferredTangentResponse
    from abrakit.materials.plasticity import plastic_step
    from abrakit.materials.strength_statistics import weibull_cdf

    def scene():
        p = Particles.spheres([[0.0, 0.0, 0.0], [0.019, 0.0, 0.0]], 0.01)
        return Simulation(p, walls=Walls.box((-0.02, -0.02, -0.02), (0.04, 0.02, 0.02)), dt=1e-6)

    square = skfem.MeshQuad().refined(1)
    basis = vector_basis(skfem.MeshHex())
    fbar = FBarKinematics.from_basis(basis)
    eps = np.zeros((2, 6))
    curve = dict(time=np.arange(3.0), strain=np.zeros((3, 6)), stress=np.zeros((3, 6)), internal={},
                 iterations=np.zeros(2, int))
    u = np.arange(4.0)

    def tangent():
        return np.zeros((1, 9, 9))

    return [
        ("values", lambda: band_width(square, -np.ones(4))),
        ("measured_at", lambda: stage_slopes(np.zeros(5), np.ones(5), 10.0)),
        ("measured_at", lambda: stage_slopes(-np.arange(5.0), np.ones(5), 10.0)),
        ("radius", lambda: sphere_stress(scene(), np.zeros(3), 0.0)),
        ("thickness", lambda: wall_stress(scene(), 0.0)),
        ("strain", lambda: voigt_strain(0, None)),
        ("k", lambda: voigt_strain(6, 1e-3)),
        ("rubber_shore_a", lambda: G65Standard(rubber_shore_a=(NAN, 62.0))),
        ("rubber_shore_a", lambda: G65Standard(rubber_shore_a=(58.0, 120.0))),
        ("sand_sizes", lambda: G65Standard(sand_sizes=(0.0, 3e-4))),
        ("u_old", lambda: rate_limit_work(u, np.full(4, NAN), u, np.array([0, 3]))),
        ("prescribed", lambda: rate_limit_work(u, u, u, np.array([0, 7]))),
        ("force_scale", lambda: rate_limit_work(u, u, u, np.array([0, 3]), INF)),
        ("stress", lambda: DeferredTangentResponse("abc", {}, tangent)),
        ("tangent", lambda: DeferredTangentResponse(np.zeros((1, 9)), {}, NAN)),
        ("state", lambda: DeferredTangentResponse(np.zeros((1, 9)), None, tangent)),
        ("grad_N", lambda: FBarKinematics(basis, np.full_like(fbar.grad_N, NAN), fbar.dx, fbar.element_dofs)),
        ("dx", lambda: FBarKinematics(basis, fbar.grad_N, fbar.dx[:, :1], fbar.element_dofs)),
        ("basis", lambda: Kinematics(None, fbar.grad_N, fbar.dx, fbar.element_dofs)),
        ("internal", lambda: PathResult(**{**curve, "internal": {"alpha": np.array([0.0, NAN, 0.0])}})),
        ("iterations", lambda: PathResult(**{**curve, "iterations": np.array([1.5, 2.0])})),
        ("stress", lambda: PathResult(**{**curve, "stress": np.zeros((2, 6))})),
        ("x must", lambda: candidate_pairs(np.array([[INF, 0.0, 0.0]]), np.ones(1), 0.1)),
        ("radius", lambda: candidate_pairs(np.zeros((2, 3)), -np.ones(2), 0.1)),
        ("control", lambda: Solver(vector_basis(square), LinearElastic(1.0, 0.3), control=NAN)),
        ("material", lambda: Solver(vector_basis(square), None)),
        ("shape", lambda: weibull_cdf(1.0, 0.0)),
        ("r must", lambda: weibull_cdf(-1.0, 2.0)),
        ("V0", lambda: weibull_cdf(1.0, 2.0, V0=NAN)),
        ("eps_p", lambda: plastic_step(eps, np.full((2, 6), INF), np.zeros(2), 1e5, 60.0, 0.0, "explicit")),
        ("alpha_p", lambda: plastic_step(eps, eps, -np.ones(2), 1e5, 60.0, 0.0, "explicit")),
        ("r_p", lambda: plastic_step(eps, eps, np.zeros(2), 1e5, -60.0, 0.0, "explicit")),
        ("integration", lambda: plastic_step(eps, eps, np.zeros(2), 1e5, 60.0, 0.0, "euler")),
        ("p must", lambda: BondTest(None, "tension")),
    ]


@pytest.mark.parametrize("index", range(34))
def test_bad_input_at_the_door_is_refused_by_name(index):
    name, call = _door_cases()[index]
    with pytest.raises((ValueError, TypeError), match=name):
        call()
