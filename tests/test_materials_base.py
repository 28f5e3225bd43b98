"""The material interface: shapes, purity, vectorisation, validation, tangents vs finite differences."""

import copy

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from abrakit import tensors as T
from abrakit.materials import (
    LinearElastic,
    Material,
    MaterialResponse,
    ModelIDamage,
    ModelIIDamage,
    VonMisesPlasticity,
    finite_difference_tangent,
)
from abrakit.materials.base import DEVIATORIC, deviator

E, NU, R_P, K_H = 200000.0, 0.3, 60.0, 8000.0

#: (material, loading) pairs whose returned tangent is the consistent one.
CONSISTENT = {
    "elastic": (LinearElastic(E, NU), {}),
    "plastic-explicit": (VonMisesPlasticity(E, NU, R_P, K_H, "explicit"), {}),
    "plastic-implicit": (VonMisesPlasticity(E, NU, R_P, K_H, "implicit"), {}),
    "plastic-perfect": (VonMisesPlasticity(E, NU, R_P, 0.0, "explicit"), {}),
    "model-I": (ModelIDamage(E, NU, 0.05, R_P, K_H, tangent="consistent"), {}),
    "model-I-implicit": (ModelIDamage(E, NU, 0.05, R_P, K_H, integration="implicit", tangent="consistent"), {}),
    "model-II": (ModelIIDamage(E, NU, 0.1, n=5, r_p=R_P, K_H=K_H), {"external_work": 0.05}),
    "model-II-tension": (ModelIIDamage(E, NU, 0.1, n=5, damage_energy="tension"), {"external_work": 0.05}),
}
ALL = {
    **CONSISTENT,
    "model-I-split": (ModelIDamage(E, NU, 0.05, R_P, K_H), {}),
    "model-II-seed": (ModelIIDamage(E, NU, 0.1, n=5, r_p=R_P, tangent="seed"), {"external_work": 0.05}),
}


def strain_walk(seed, n_points=6, n_steps=4, size=1.5e-3):
    """A random walk of Mandel strains for a batch, large enough to yield and damage."""
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(scale=size, size=(n_steps, n_points, 6)), axis=0)


@pytest.mark.parametrize("name", ALL)
def test_every_model_follows_the_interface(name):
    material, loading = ALL[name]
    assert isinstance(material, Material)
    state = material.initial_state((3, 4))
    assert all(value.shape[:2] == (3, 4) for value in state.values())
    response = material.update(state, np.full((3, 4, 6), 1e-4), 1.0, **loading)
    assert isinstance(response, MaterialResponse)
    assert response.stress.shape == (3, 4, 6)
    assert response.tangent.shape == (3, 4, 6, 6)
    assert set(response.state) == set(state)
    assert np.all(np.isfinite(material.stored_energy(response.state)))
    assert np.all(material.dissipation(response.state) >= 0.0)


@pytest.mark.parametrize("name", ALL)
def test_update_never_mutates_the_old_state(name):
    material, loading = ALL[name]
    state = material.initial_state((6,))
    for eps in strain_walk(1):
        before = copy.deepcopy(state)
        response = material.update(state, eps, **loading)
        for key in state:
            np.testing.assert_array_equal(state[key], before[key])
            assert not np.shares_memory(response.state[key], state[key])
        # the same old state and strain give the same answer: a rejected step can be retried
        again = material.update(state, eps, **loading)
        np.testing.assert_array_equal(again.stress, response.stress)
        state = response.state


@pytest.mark.parametrize("name", CONSISTENT)
def test_returned_tangent_matches_centred_finite_differences(name):
    material, loading = CONSISTENT[name]
    state = material.initial_state((6,))
    for eps in strain_walk(2):
        response = material.update(state, eps, **loading)
        numeric = finite_difference_tangent(material, state, eps, h=1e-8, **loading)
        scale = np.abs(numeric).max(axis=(-1, -2), keepdims=True)
        np.testing.assert_allclose(response.tangent / scale, numeric / scale, atol=2e-6)
        state = response.state
    if name != "elastic":  # the walk must have exercised the inelastic branches
        assert any(np.any(state[key] > 0) for key in ("alpha_p", "d") if key in state)


@pytest.mark.parametrize("name", ["elastic", "plastic-explicit", "plastic-implicit", "model-I", "model-II"])
def test_tangent_of_associative_models_is_symmetric(name):
    material, loading = CONSISTENT[name]
    state = material.initial_state((6,))
    for eps in strain_walk(3):
        response = material.update(state, eps, **loading)
        np.testing.assert_allclose(response.tangent, np.swapaxes(response.tangent, -1, -2), atol=1e-8 * E)
        state = response.state


@settings(max_examples=25, deadline=None)
@given(arrays(np.float64, (5, 6), elements=st.floats(-5e-3, 5e-3)))
def test_batch_update_equals_point_by_point_update(eps):
    material = VonMisesPlasticity(E, NU, R_P, K_H)
    batch = material.update(material.initial_state((5,)), eps)
    for i in range(5):
        single = material.update(material.initial_state(()), eps[i])
        np.testing.assert_allclose(batch.stress[i], single.stress, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(batch.tangent[i], single.tangent, rtol=1e-12, atol=1e-6)


@given(arrays(np.float64, (3, 3), elements=st.floats(-1.0, 1.0)))
def test_mandel_deviator_and_product_match_the_tensor_forms(A):
    S = 0.5 * (A + A.T)
    np.testing.assert_allclose(deviator(T.to_mandel(S)), T.to_mandel(T.dev(S)), atol=1e-14)
    np.testing.assert_allclose(DEVIATORIC @ T.to_mandel(S), T.to_mandel(T.dev(S)), atol=1e-14)
    sigma = LinearElastic(E, NU).update({}, T.to_mandel(S)).stress
    np.testing.assert_allclose(T.from_mandel(sigma), T.ddot42(T.isotropic_stiffness(E, NU), S), rtol=1e-12, atol=1e-9)


def test_elastic_energy_is_half_stress_times_strain():
    material = LinearElastic(E, NU)
    eps = strain_walk(4)[-1]
    response = material.update(material.initial_state((6,)), eps)
    np.testing.assert_allclose(material.stored_energy(response.state), 0.5 * np.sum(response.stress * eps, -1))
    np.testing.assert_array_equal(material.dissipation(response.state), 0.0)


@pytest.mark.parametrize(
    "factory, message",
    [
        (lambda: LinearElastic(-1.0, 0.3), "E"),
        (lambda: LinearElastic(E, 0.5), "nu"),
        (lambda: VonMisesPlasticity(E, NU, 0.0), "r_p"),
        (lambda: VonMisesPlasticity(E, NU, R_P, -1.0), "K_H"),
        (lambda: VonMisesPlasticity(E, NU, R_P, K_H, integration="rk4"), "integration"),
        (lambda: ModelIDamage(E, NU, 0.0), "r_d"),
        (lambda: ModelIDamage(E, NU, 0.05, beta=-0.1), "beta"),
        (lambda: ModelIDamage(E, NU, 0.05, f_min=1.0), "f_min"),
        (lambda: ModelIDamage(E, NU, 0.05, tangent="secant"), "tangent"),
        (lambda: ModelIDamage(E, NU, 0.05, r_p=np.nan), "r_p"),
        (lambda: ModelIIDamage(E, NU, 0.1, n=0), "n"),
        (lambda: ModelIIDamage(E, NU, 0.1, n=2.5), "n"),
        (lambda: ModelIIDamage(E, NU, 0.1, alpha=0.0), "alpha"),
        (lambda: ModelIIDamage(E, NU, 0.1, dt=0.0), "dt"),
        (lambda: ModelIIDamage(E, NU, 0.1, d_max=1.0), "d_max"),
        (lambda: ModelIIDamage(E, NU, 0.1, damage_energy="deviatoric"), "damage_energy"),
    ],
)
def test_invalid_parameters_raise_value_error_naming_them(factory, message):
    with pytest.raises(ValueError, match=message):
        factory()


@pytest.mark.parametrize("name", ["elastic", "plastic-explicit", "model-I", "model-II"])
def test_bad_strain_input_is_stopped_with_a_clear_message(name):
    material, loading = ALL[name]
    state = material.initial_state((2,))
    with pytest.raises(ValueError, match="eps"):
        material.update(state, np.full((2, 6), np.nan), **loading)
    with pytest.raises(ValueError, match="eps"):
        material.update(state, np.zeros((2, 3)), **loading)


@pytest.mark.parametrize("kind", ["full", "tension"])
def test_driving_energy_and_its_gradient(kind):
    """Psi0+ (6.56) by eigenvalues equals the energy of abrakit.tensors.positive_part; gradient vs differences."""
    material = LinearElastic(E, NU)
    eps = np.random.default_rng(6).normal(scale=1e-3, size=(20, 6))
    psi = material.driving_energy(eps, kind)
    if kind == "tension":
        eps_plus = T.to_mandel(T.positive_part(T.from_mandel(eps)))
        np.testing.assert_allclose(psi, material.elastic_energy(eps_plus), rtol=1e-12)
        assert np.all(material.driving_energy(-np.abs(eps) * [1, 1, 1, 0, 0, 0], kind) == 0.0)
    else:
        np.testing.assert_allclose(psi, 0.5 * np.einsum("ni,ij,nj->n", eps, material.stiffness, eps), rtol=1e-12)
    h = 1e-9
    numeric = np.stack(
        [(material.driving_energy(eps + h * e, kind) - material.driving_energy(eps - h * e, kind)) / (2 * h)
         for e in np.eye(6)], axis=-1)
    np.testing.assert_allclose(material.driving_energy_gradient(eps, kind), numeric, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("nu", [0.0, 0.2, 0.33, 0.4])
def test_tension_energy_of_pure_shear_is_eq_6_56_not_the_positive_part_of_the_trace(nu):
    """Psi0+ = 1/2 eps+ : E : eps+ (Eq. 6.56) in pure shear is (lambda + 2 mu) gamma^2 / 8, i.e. the fraction
    (1 - nu) / (2 (1 - 2 nu)) of Psi0: 1/2 only for nu = 0, above 1 for nu > 1/3 (the split of Miehe et al., with
    the positive part of the trace, would give 1/2 for every nu)."""
    material = LinearElastic(200000.0, nu)
    eps = np.zeros((3, 3))
    eps[0, 1] = eps[1, 0] = 1e-3
    mandel = T.to_mandel(eps)
    ratio = material.tension_energy(mandel) / material.elastic_energy(mandel)
    assert ratio == pytest.approx((1 - nu) / (2 * (1 - 2 * nu)), rel=1e-12)
