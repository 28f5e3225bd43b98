"""Erosion by ductile failure in the scratch: the eroding material, the nonlocal damage, the staggered step and a
scene that removes material with its volume budget closed.

- the eroding material is its base where nothing is eroded, and a residual spring c (F − I) where it is, with a
  tangent that a finite difference confirms and ``tangent_of`` that agrees with the whole tangent;
- the nonlocal average is a partition of unity (a uniform damage averages to itself), ℓ = 0 is local, and the
  weights fall with distance;
- the step erodes exactly the elements whose damage reached 1, releases their stored energy and leaves eroded
  elements out of the average;
- a brittle steel under the seed's tip erodes tens of elements: the run finishes without NaN (eroded elements
  crushed through themselves included), the budget closes to round-off at every increment with the eroded volume
  as ``removed``, eroded surface nodes leave the contact.
"""

import math

import numpy as np
import pytest

from abrakit.fem import Kinematics
from abrakit.materials import LinearElastic, LogStrainPlasticity, VonMisesPlasticity
from abrakit.materials.ductile_failure import JohnsonCookFailure
from abrakit.scratch.erosion import ErodingMaterial, Erosion, ErosionStep, nonlocal_weights
from abrakit.scratch.readouts import surface_nodes_of
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import DEMO_SCENE, ScratchScene, build_specimen

E, NU = 210000.0, 0.33
BASE = LogStrainPlasticity(VonMisesPlasticity(E, NU, 355.0 / math.sqrt(1.5), 1000.0 / 1.5, integration="implicit"))
ERODING = ErodingMaterial(BASE, 1e-6)


def deformation(rng, shape, size=0.02):
    return (np.eye(3) + size * rng.standard_normal((*shape, 3, 3))).reshape(*shape, 9)


def test_without_eroded_elements_the_material_is_its_base():
    rng = np.random.default_rng(0)
    F = deformation(rng, (5, 8))
    state = ERODING.initial_state((5, 8))
    ours, base = ERODING.update(state, F), BASE.update(BASE.initial_state((5, 8)), F)
    assert np.array_equal(ours.stress, base.stress) and np.array_equal(ours.tangent, base.tangent)
    assert {"ductile", "eroded", "released"} <= ours.state.keys()


def test_eroded_elements_carry_the_residual_spring_and_the_rest_is_the_base():
    rng = np.random.default_rng(1)
    F = deformation(rng, (6, 8))
    F[2, 3] = np.array([1.0, 0, 0, 0, -0.2, 0, 0, 0, 1.0])          # an inverted point in an eroded element
    state = ERODING.initial_state((6, 8))
    state["eroded"][[2, 4]] = True
    response = ERODING.update(state, F)
    intact = [0, 1, 3, 5]
    base = BASE.update(BASE.initial_state((4, 8)), F[intact])
    assert np.allclose(response.stress[intact], base.stress, rtol=1e-12, atol=1e-9)
    c = 1e-6 * E
    assert np.allclose(response.stress[[2, 4]], c * (F[[2, 4]] - np.eye(3).ravel()), rtol=1e-12)
    assert np.allclose(response.tangent[[2, 4]], c * np.eye(9)) and np.all(response.yielding[[2, 4]])
    assert np.allclose(response.tangent_of(np.array([4, 1])), response.tangent[[4, 1]], rtol=1e-12)
    for key in ("alpha_p", "Cp_inv", "eps_e"):                             # the eroded state is frozen
        assert np.array_equal(response.state[key][[2, 4]], state[key][[2, 4]])
    h = 1e-7                                                              # the tangent by central differences
    for k in (0, 4):
        dF = np.zeros_like(F)
        dF[..., k] = h
        fd = (ERODING.update(state, F + dF).stress - ERODING.update(state, F - dF).stress) / (2 * h)
        assert np.allclose(fd, response.tangent[..., :, k], rtol=1e-5, atol=1e-3)


def test_nonlocal_weights_are_a_partition_of_unity_falling_with_distance():
    rng = np.random.default_rng(2)
    centres, volumes = rng.random((200, 3)), 0.5 + rng.random(200)
    W = nonlocal_weights(centres, volumes, 0.3)
    uniform = (W @ np.full(200, 0.7)) / (W @ np.ones(200))
    assert np.allclose(uniform, 0.7, rtol=1e-12)
    assert np.allclose(W.diagonal(), volumes)                            # each element weighs itself with w = 1
    i, j = W.nonzero()
    r = np.linalg.norm(centres[i] - centres[j], axis=1)
    w = np.asarray(W[i, j]).ravel() / volumes[j]
    assert np.all(r < 0.3) and np.allclose(w, (1 - (r / 0.3) ** 2) ** 2, rtol=1e-12)
    local = nonlocal_weights(centres, volumes, 0.0)
    assert local.nnz == 200 and np.allclose(local.diagonal(), volumes)


@pytest.fixture(scope="module")
def mesh_kinematics():
    spec = build_specimen(DEMO_SCENE)
    return Kinematics.from_basis(spec.basis)


def test_the_step_erodes_the_elements_that_failed_and_releases_their_stored_energy(mesh_kinematics):
    kin = mesh_kinematics
    step = ErosionStep(Erosion(JohnsonCookFailure(0.1, 0.0, 0.0), length=0.0), kin, ERODING)
    shape = (kin.nel, kin.nqp)
    old = ERODING.initial_state(shape)
    F = np.broadcast_to(np.array([1.002, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]), (*shape, 9)).copy()
    new = ERODING.update(old, F).state                                 # elastic: no damage grows
    assert step(old, new).size == 0 and not new["eroded"].any()
    new["alpha_p"] = old["alpha_p"] + np.where(np.arange(kin.nel)[:, None] < 3, 0.2, 0.01)
    new["cauchy"] = np.broadcast_to(np.array([300.0, 0, 0, 0, 0, 0]), (*shape, 6)).copy()   # eta = 1/3
    failed = step(old, new)
    eps = math.sqrt(2 / 3) * 0.2                                     # eps_bar = 0.163 > eps_f = 0.1 in three
    assert np.array_equal(failed, [0, 1, 2]) and eps > 0.1
    assert np.array_equal(ErosionStep.removed(new), np.arange(kin.nel) < 3)
    expected = 2.0 * np.sum(BASE.stored_energy({k: v[:3] for k, v in new.items()}) * kin.dx[:3])
    assert step.released(new) == pytest.approx(expected, rel=1e-12) and expected > 0
    again = {**new, "alpha_p": new["alpha_p"] + 0.0}
    assert step(new, again).size == 0                                  # no new strain: nothing more erodes


def test_eroded_elements_are_left_out_of_the_nonlocal_average(mesh_kinematics):
    kin = mesh_kinematics
    step = ErosionStep(Erosion(length=0.02), kin, ERODING)
    state = ERODING.initial_state((kin.nel, kin.nqp))
    state["ductile"][:] = 0.5
    state["ductile"][:10], state["eroded"][:10] = 5.0, True
    assert np.allclose(step.nonlocal_damage(state)[10:], 0.5, rtol=1e-12)


def test_bad_erosion_settings_are_refused_by_name():
    with pytest.raises(ValueError, match="length"):
        Erosion(length=-1.0)
    with pytest.raises(ValueError, match="residual"):
        Erosion(residual=0.0)
    with pytest.raises(TypeError, match="criterion"):
        Erosion(criterion="johnson-cook")
    with pytest.raises(ValueError, match="kinematics='finite'"):
        ScratchScene(erosion=Erosion(), kinematics="small")
    with pytest.raises(ValueError, match="damage=False"):
        ScratchScene(erosion=Erosion(), damage=True)
    with pytest.raises(TypeError, match="erosion"):
        ScratchScene(erosion=0.1)
    with pytest.raises(ValueError, match="plastic"):
        ErodingMaterial(LogStrainPlasticity(LinearElastic(E, NU)), 1e-6)
    with pytest.raises(TypeError, match="base"):
        ErodingMaterial(BASE.base, 1e-6)


BRITTLE = DEMO_SCENE.with_(slide=0.02, erosion=Erosion(JohnsonCookFailure(0.1, 0.0, 0.0), length=0.0))
"""The seed's tip and depth with a brittle steel (ε_f = 0.1 above the cut-off), local erosion, demo mesh: tens of
elements erode, some eroded elements are crushed through themselves (the plain gradient lets them), and the run
must still reach its end."""


@pytest.fixture(scope="module")
def cutting():
    return run_scratch(BRITTLE, vtu_every=0)


def test_a_cutting_scratch_erodes_elements_and_keeps_its_budget_closed(cutting):
    r = cutting
    assert r.erosion["eroded_elements"] >= 10 and r.erosion["erosion_energy"] > 0
    c = r.curves
    assert np.all(np.isfinite(c["normal_force"])) and np.all(np.isfinite(r.u))
    assert np.all(np.abs(c["V_residual"]) <= 1e-6 * c["V_groove"].max())
    eroded = ErosionStep.removed(r.state)
    kin = Kinematics.from_basis(r.specimen.basis)
    # the removed term is the eroded material's own volume, whatever the residual spring lets its neighbours
    # do to it; the eroded elements are those of the final state
    assert r.budget.removed == pytest.approx(2.0 * np.sum(kin.dx[eroded]), rel=1e-12) and r.budget.removed > 0
    assert np.all(np.diff(c["V_removed"]) >= 0.0)                 # material once removed stays removed


def test_eroded_surface_nodes_leave_the_contact(cutting):
    r = cutting
    of = surface_nodes_of(r.specimen.mesh, r.contact.nodes)
    gone = of(ErosionStep.removed(r.state))
    assert gone.any() and not np.any(r.contact.active[gone]) and np.any(r.contact.active)
    assert of(np.ones(r.n_elements, dtype=bool)).all()


def test_the_removal_fraction_is_the_removed_rate_over_the_groove_rate():
    """Synthetic steady curves: groove 3 µm²·slide, removed 0.6 µm²·slide, shoulders 2 µm²·slide: the removal
    fraction is 0.2 (the chain's f_ab), Eq. (8.5) in rates 1/3 (it also counts what is neither removed nor in the
    shoulders)."""
    from abrakit.scratch.budget import steady_rates
    slide = np.linspace(0.0, 0.02, 21)
    curves = {"phase": np.ones(21), "slide": slide, "V_groove": 3e-6 * slide, "V_removed": 0.6e-6 * slide,
              "V_shoulders": 2e-6 * slide, **{f"V_{k}": 0 * slide for k in ("prow", "sink", "faces",
                                                                               "volume_change")}}
    rates = steady_rates(curves)
    assert rates.removal_fraction == pytest.approx(0.2, rel=1e-9)
    assert rates.degree_of_wear == pytest.approx(1 / 3, rel=1e-9)
