"""Element tangents reused where the deformation has not moved (abrakit.fem.tangent_reuse).

Exactness at tolerance 0 (the full tangent to round-off, only moved or yielding elements recomputed), the partial
material tangent and the element-subset F-bar tangents against the full ones, the same converged solution with a
positive tolerance, and clear refusals.
"""

import numpy as np
import pytest
import skfem

from abrakit.compiled import HAVE_NUMBA
from abrakit.fem import Assembler, Dirichlet, Kinematics, NewtonOptions, Solver, StepControl, vector_basis
from abrakit.fem.tangent_reuse import ElementTangentReuse
from abrakit.materials import LinearElastic, LogStrainPlasticity, ModelIIDamage, VonMisesPlasticity

E, NU = 210000.0, 0.33
PLASTIC = LogStrainPlasticity(VonMisesPlasticity(E, NU, 289.9, 666.7, integration="implicit"))
ELASTIC = LogStrainPlasticity(LinearElastic(E, NU))


def block(n=(4, 3, 3)):
    axes = [np.linspace(0.0, 1.0, k + 1) for k in n]
    mesh = skfem.MeshHex.init_tensor(*axes)
    tol = 1e-9
    return mesh.with_boundaries({"x0": lambda x: x[0] < tol, "y0": lambda x: x[1] < tol,
                                 "z0": lambda x: x[2] < tol, "x1": lambda x: x[0] > 1 - tol})


def fbar(mesh):
    basis = vector_basis(mesh)
    return basis, Kinematics.from_basis(basis, bbar=True, finite_strain=True)


def test_at_tolerance_zero_the_kept_tangent_is_the_full_one_and_only_moved_elements_are_recomputed():
    mesh = block()
    basis, kin = fbar(mesh)
    asm = Assembler(kin)
    reuse = ElementTangentReuse(asm, 0.0)
    state = ELASTIC.initial_state((kin.nel, kin.nqp))
    rng = np.random.default_rng(3)
    u = 1e-3 * rng.standard_normal(basis.N)
    response = ELASTIC.update(state, kin.strain(u))
    reuse.data(response, u)
    assert reuse.refreshed == kin.nel                                   # the first call computes every element
    for _ in range(3):
        node = rng.integers(mesh.p.shape[1])
        u = u.copy()
        u[basis.nodal_dofs[:, node]] += 1e-3 * rng.standard_normal(3)
        response = ELASTIC.update(state, kin.strain(u))
        before = reuse.refreshed
        kept = reuse.data(response, u)
        full = asm.tangent_data(response.tangent, u, response.stress)
        assert np.abs(kept - full).max() <= 1e-13 * np.abs(full).max()
        touching = int(np.sum(np.any(mesh.t == node, axis=0)))
        assert reuse.refreshed - before == touching                     # the elements around the moved node only


def test_yielding_elements_are_always_recomputed_and_the_tangent_stays_exact():
    mesh = block()
    basis, kin = fbar(mesh)
    asm = Assembler(kin)
    reuse = ElementTangentReuse(asm, 1.0)                  # F never "moves" by 1: only yielding decides
    state = PLASTIC.initial_state((kin.nel, kin.nqp))
    u = 0.01 * basis.doflocs[0] * (basis.doflocs[1] > 0.5)                # stretch the upper half past yield
    response = PLASTIC.update(state, kin.strain(u))
    assert response.yielding.any() and not response.yielding.all()
    reuse.data(response, u)
    again = reuse.data(response, u)
    yielding = response.yielding.any(axis=1)
    assert reuse.refreshed == kin.nel + int(yielding.sum())
    full = asm.tangent_data(response.tangent, u, response.stress)
    assert np.abs(again - full).max() <= 1e-13 * np.abs(full).max()


@pytest.mark.parametrize("compiled", [False] + ([True] if HAVE_NUMBA else []))
def test_the_tangents_of_selected_elements_are_the_rows_of_the_full_ones(compiled):
    mesh = block()
    basis, kin = fbar(mesh)
    rng = np.random.default_rng(5)
    u = 0.01 * rng.standard_normal(basis.N)
    state = PLASTIC.initial_state((kin.nel, kin.nqp))
    response = PLASTIC.update(state, kin.strain(u), compiled=compiled)
    assert response.yielding.any()
    chosen = np.array([0, 5, 17, kin.nel - 1])
    partial = response.tangent_of(chosen)                 # before the full tangent exists: computed for them alone
    assert np.abs(partial - response.tangent[chosen]).max() <= 1e-12 * np.abs(response.tangent).max()
    whole = kin.element_tangents(response.tangent, response.stress, u, compiled=compiled)
    some = kin.element_tangents(partial, response.stress[chosen], u, compiled=compiled, elements=chosen)
    assert np.abs(some - whole[chosen]).max() <= 1e-13 * np.abs(whole).max()


def test_a_reused_tangent_converges_to_the_same_plastic_solution():
    """Tension past yield of a graded block: the reused tangent changes the Newton matrix, not the residual,
    so the load curve is the full tangent's to the Newton tolerance."""
    mesh = block((4, 4, 2))
    runs = {}
    for tol in (None, 1e-4):
        basis = vector_basis(mesh)
        bcs = [Dirichlet.on(basis, "x0", "x"), Dirichlet.on(basis, "y0", "y"), Dirichlet.on(basis, "z0", "z"),
               Dirichlet.on(basis, "x1", "x", 0.02, name="end")]
        solver = Solver(basis, PLASTIC, bcs, finite_strain=True, bbar=True,
                        control=StepControl(initial=0.1, maximum=0.1),
                        newton=NewtonOptions(residual_tol=1e-9, tangent_reuse=tol))
        runs[tol] = solver.run(progress=False)
    full, kept = runs[None], runs[1e-4]
    assert np.allclose(kept.curves["F_end"], full.curves["F_end"], rtol=1e-7)
    assert kept.iterations.sum() <= full.iterations.sum() + 2


def test_bad_options_and_unsupported_kinematics_are_refused_by_name():
    with pytest.raises(ValueError, match="tangent_reuse"):
        NewtonOptions(tangent_reuse=-1e-5)
    basis = vector_basis(block())
    small = Assembler(Kinematics.from_basis(basis))
    with pytest.raises(TypeError, match="F-bar"):
        ElementTangentReuse(small, 1e-5)
    with pytest.raises(ValueError, match="tolerance"):
        ElementTangentReuse(Assembler(fbar(block())[1]), -1.0)


def test_damage_responses_take_the_full_tangent():
    damaged = LogStrainPlasticity(ModelIIDamage(E, NU, r_d=0.1, n=4))
    kin = fbar(block((1, 1, 1)))[1]
    response = damaged.update(damaged.initial_state((kin.nel, kin.nqp)), kin.strain(np.zeros(kin.ndof)),
                              external_work=0.0)
    assert not ElementTangentReuse.applies(response)
    assert ElementTangentReuse.applies(PLASTIC.update(PLASTIC.initial_state((1, 8)), kin.strain(np.zeros(kin.ndof))))
