"""Von Mises plasticity of Table 6.1 at a material point: closed forms, limits, step-size behaviour, energy."""

import numpy as np
import pytest

from abrakit.materials import (
    VonMisesPlasticity,
    cycles,
    plane_strain_tension,
    pure_shear,
    ramp,
    uniaxial_hardening_modulus,
    uniaxial_strain,
    uniaxial_stress,
    uniaxial_yield_stress,
)
from abrakit.materials.base import deviator
from abrakit.materials.driver import drive

E, NU, R_P, K_H = 200000.0, 0.3, 60.0, 8000.0
SIGMA_0 = np.sqrt(1.5) * R_P


def closed_form_uniaxial(eps):
    """Uniaxial stress-strain curve: elastic, then slope E H / (E + H) with H = 1.5 K_H (REFERENCE Ch. 6)."""
    H = 1.5 * K_H
    eps_y = SIGMA_0 / E
    return np.where(eps < eps_y, E * eps, SIGMA_0 + E * H / (E + H) * (eps - eps_y))


def test_uniaxial_yield_stress_and_hardening_modulus_of_the_yield_function():
    assert uniaxial_yield_stress(R_P) == pytest.approx(SIGMA_0)
    assert uniaxial_hardening_modulus(K_H) == 1.5 * K_H
    # elastic up to sigma_0, plastic just beyond, for both integrations
    for integration in ("explicit", "implicit"):
        material = VonMisesPlasticity(E, NU, R_P, K_H, integration)
        below = uniaxial_stress(material, [0.999 * SIGMA_0 / E])
        above = uniaxial_stress(material, [1.001 * SIGMA_0 / E])
        assert below.internal["alpha_p"][-1] == 0.0
        assert above.internal["alpha_p"][-1] > 0.0


def test_implicit_uniaxial_hardening_curve_equals_the_closed_form():
    result = uniaxial_stress(VonMisesPlasticity(E, NU, R_P, K_H, "implicit"), ramp(0.01, 40))
    eps11 = result.strain_component("11")
    np.testing.assert_allclose(result.stress_component("11"), closed_form_uniaxial(eps11), atol=1e-8)
    # lateral stresses vanish, plastic flow is isochoric, alpha_p = |eps_p| = sqrt(3/2) eps_p,11
    np.testing.assert_allclose(result.stress[:, 1:], 0.0, atol=1e-7)
    eps_p = result.internal["eps_p"]
    np.testing.assert_allclose(eps_p[:, :3].sum(axis=1), 0.0, atol=1e-15)
    np.testing.assert_allclose(result.internal["alpha_p"], np.sqrt(1.5) * eps_p[:, 0], rtol=1e-12)


def test_explicit_uniaxial_curve_converges_to_the_closed_form_at_first_order():
    errors = []
    for n_steps in (200, 400, 800):
        result = uniaxial_stress(VonMisesPlasticity(E, NU, R_P, K_H, "explicit"), ramp(0.01, n_steps))
        exact = closed_form_uniaxial(result.strain_component("11"))
        errors.append(np.max(np.abs(result.stress_component("11") - exact)))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((rates > 0.85) & (rates < 1.15)), (errors, rates)
    assert errors[-1] > 1.0  # a measurable lag of the seed's explicit hardening: > 1 MPa at 800 steps to 1 %


def test_explicit_update_satisfies_the_consistency_condition_6_61():
    material = VonMisesPlasticity(E, NU, R_P, K_H, "explicit")
    state = material.initial_state((50,))
    rng = np.random.default_rng(0)
    for _ in range(3):
        eps = state["eps"] + rng.normal(scale=2e-3, size=(50, 6))
        response = material.update(state, eps)
        plastic = response.state["alpha_p"] > state["alpha_p"]
        assert plastic.sum() > 10
        excess = np.linalg.norm(deviator(response.stress), axis=-1) - (R_P + K_H * response.state["alpha_p"])
        np.testing.assert_allclose(excess[plastic], 0.0, atol=1e-9)
        assert np.all(excess <= 1e-9)
        state = response.state


def test_explicit_and_implicit_coincide_for_perfect_plasticity():
    """With K_H = 0 the seed's Eq. (6.61) gives the same stress as the radial return."""
    paths = {i: uniaxial_stress(VonMisesPlasticity(E, NU, R_P, 0.0, i), ramp(0.01, 7))
             for i in ("explicit", "implicit")}
    np.testing.assert_allclose(paths["explicit"].stress, paths["implicit"].stress, atol=1e-9)


@pytest.mark.parametrize("integration", ["explicit", "implicit"])
def test_plane_strain_perfect_plasticity_limits(integration):
    """sigma_xx -> 2 sigma_0/sqrt(3), sigma_zz -> sigma_0/sqrt(3), sigma_yy = 0 under plane strain tension."""
    result = plane_strain_tension(VonMisesPlasticity(E, NU, R_P, 0.0, integration), ramp(0.05, 100))
    np.testing.assert_allclose(result.stress_component("11")[-1], 2 * SIGMA_0 / np.sqrt(3), rtol=1e-8)
    np.testing.assert_allclose(result.stress_component("33")[-1], SIGMA_0 / np.sqrt(3), rtol=1e-8)
    np.testing.assert_allclose(result.stress_component("22"), 0.0, atol=1e-6)
    np.testing.assert_allclose(result.strain_component("33"), 0.0)


def test_pure_shear_yields_at_sigma_0_over_sqrt_3():
    material = VonMisesPlasticity(E, NU, R_P, 0.0, "implicit")
    result = pure_shear(material, ramp(0.01, 10))
    np.testing.assert_allclose(result.stress_component("12")[-1], SIGMA_0 / np.sqrt(3), rtol=1e-12)
    np.testing.assert_allclose(result.stress[:, :5], 0.0, atol=1e-9)


@pytest.mark.parametrize("direction", [[1, 0, 0, 0, 0, 0], [0.3, -0.7, 0.2, 0.5, -0.1, 0.9]])
def test_implicit_radial_return_is_step_size_invariant_on_radial_paths(direction):
    material = VonMisesPlasticity(E, NU, R_P, K_H, "implicit")
    direction = np.asarray(direction) / np.linalg.norm(direction)
    finals = []
    for n_steps in (1, 3, 17, 200):
        result = drive(material, ramp(0.02, n_steps)[:, None] * direction)
        finals.append((result.stress[-1], result.internal["alpha_p"][-1]))
    for stress, alpha in finals[1:]:
        np.testing.assert_allclose(stress, finals[0][0], atol=1e-9)
        np.testing.assert_allclose(alpha, finals[0][1], rtol=1e-12)


def test_explicit_step_size_error_is_measured_and_vanishes_with_the_step():
    """The seed's scheme on the same radial path: the error shrinks like the step and is far from round-off."""
    direction = np.array([0.3, -0.7, 0.2, 0.5, -0.1, 0.9])
    direction /= np.linalg.norm(direction)
    reference = drive(VonMisesPlasticity(E, NU, R_P, K_H, "implicit"), ramp(0.02, 1)[:, None] * direction).stress[-1]
    errors = []
    for n_steps in (200, 400, 800, 1600):
        result = drive(VonMisesPlasticity(E, NU, R_P, K_H, "explicit"), ramp(0.02, n_steps)[:, None] * direction)
        errors.append(np.linalg.norm(result.stress[-1] - reference))
    errors = np.array(errors)
    assert np.all(np.diff(errors) < 0)
    np.testing.assert_allclose(errors[:-1] / errors[1:], 2.0, rtol=0.1)
    assert errors[-1] > 1e3 * 1e-12 * E


def test_cyclic_loading_keeps_stress_on_or_inside_the_expanding_yield_surface():
    material = VonMisesPlasticity(E, NU, R_P, K_H, "implicit")
    result = uniaxial_stress(material, cycles(0.004, 2, 20))
    alpha = result.internal["alpha_p"]
    yield_radius = R_P + K_H * alpha
    dev_norm = np.linalg.norm(deviator(result.stress), axis=-1)
    assert np.all(np.diff(alpha) >= 0)
    assert np.all(dev_norm <= yield_radius + 1e-9)
    flowing = np.flatnonzero(np.diff(alpha) > 0) + 1
    np.testing.assert_allclose(dev_norm[flowing], yield_radius[flowing], rtol=1e-10)
    # isotropic hardening: compressive yield after the first tension is the hardened yield stress
    sigma = result.stress_component("11")
    first_reverse_flow = flowing[sigma[flowing] < 0][0]
    np.testing.assert_allclose(-sigma[first_reverse_flow], np.sqrt(1.5) * yield_radius[first_reverse_flow], rtol=1e-10)
    # unloading is elastic with Young's modulus
    eps = result.strain_component("11")
    np.testing.assert_allclose((sigma[21] - sigma[20]) / (eps[21] - eps[20]), E, rtol=1e-9)


def test_work_equals_stored_energy_plus_dissipation_as_steps_shrink():
    gaps = []
    for n_steps in (50, 200):
        material = VonMisesPlasticity(E, NU, R_P, K_H, "implicit")
        result = uniaxial_strain(material, cycles(0.004, 1, n_steps // 4))
        d_eps = np.diff(result.strain, axis=0)
        work = np.sum(0.5 * (result.stress[1:] + result.stress[:-1]) * d_eps)
        final = {key: value[-1] for key, value in result.internal.items()}
        gaps.append(abs(work - material.stored_energy(final) - material.dissipation(final)) / work)
    assert gaps[1] < gaps[0] and gaps[1] < 2e-3, gaps


@pytest.mark.parametrize("integration", ["explicit", "implicit"])
def test_compiled_update_equals_the_numpy_return_map(integration):
    """The numba loop of ``VonMisesPlasticity.update`` (the default where numba is installed) gives the vectorised
    return map's stress, tangent and state to round-off, at elastic and plastic points of one batch, from a state
    with plastic strain and hardening."""
    from abrakit.compiled import HAVE_NUMBA

    if not HAVE_NUMBA:
        pytest.skip("numba (extra 'fast') not installed")
    m = VonMisesPlasticity(200000.0, 0.3, 200.0, 2000.0, integration=integration)
    rng = np.random.default_rng(4)
    state = m.initial_state((40, 4))
    state["eps_p"] = deviator(rng.standard_normal((40, 4, 6)) * 1e-3)
    state["alpha_p"] = rng.random((40, 4)) * 1e-3
    state["dissipation"] = rng.random((40, 4))
    eps = state["eps_p"] + rng.standard_normal((40, 4, 6)) * 5e-4
    a, b = m.update(state, eps, compiled=False), m.update(state, eps, compiled=True)
    plastic = a.state["alpha_p"] > state["alpha_p"]
    assert 0.2 < plastic.mean() < 0.8
    for x, y in ((a.stress, b.stress), (a.tangent, b.tangent), *((a.state[k], b.state[k]) for k in a.state)):
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-13 * np.abs(x).max())
