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
    from abrakit.dem import Servo
    from abrakit.dem.neighbours import candidate_pairs
    from abrakit.dem.scenes import settling
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
    from abrakit.experiments.specimen import Specimen, SpecimenSpec

    spec = SpecimenSpec()
    x = np.array([[0.1, 0.1, 0.1], [NAN, 0.2, 0.2]])
    return [("x must", lambda: Specimen(spec, x, np.ones(2), np.ones(3))),
            ("x must", lambda: Specimen(spec, np.zeros((3, 3)), np.ones(2), np.ones(3))),
            ("radius", lambda: Specimen(spec, np.zeros((2, 3)), -np.ones(2), np.ones(3)))]


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
