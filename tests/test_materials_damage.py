"""Model I and Model II at a material point: closed-form limits, ERVE identities, irreversibility, hard cases."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from abrakit.materials import ModelIDamage, ModelIIDamage, finite_difference_tangent, ramp, uniaxial_strain
from abrakit.materials.model_one import damage_function_update, damage_indicator
from abrakit.materials.model_two import (
    damage_function,
    damage_sweep,
    driving_forces,
    effective_damage_function,
    erve_strains,
)

E, R_P, K_H = 200000.0, 60.0, 8000.0


def constrained_modulus(E, nu):
    """Uniaxial-strain modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu))."""
    return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))


# --- Model I -----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("nu", [0.0, 0.33])
def test_model_one_local_limit_peaks_at_sqrt_2_rd_E_in_uniaxial_strain(nu):
    """beta = 0, no plasticity: onset at Psi0+ = r_d, peak sqrt(2 r_d M) (sqrt(2 r_d E) at nu = 0), then 2 r_d / eps."""
    r_d = 0.05
    material = ModelIDamage(E, nu, r_d)
    M = constrained_modulus(E, nu)
    d_eps = 5e-6
    result = uniaxial_strain(material, ramp(3e-3, 600))
    sigma, eps = result.stress_component("11"), result.strain_component("11")
    peak = np.sqrt(2 * r_d * M)
    if nu == 0.0:
        assert peak == pytest.approx(np.sqrt(2 * r_d * E))
    # the operator split (stress with f^m) overshoots the peak by at most one elastic step
    assert peak <= sigma.max() <= peak + M * d_eps
    # after the damage update the state sits on the closed-form softening branch sigma = f M eps = 2 r_d / eps
    damaged = result.internal["d"] > 0
    assert damaged.sum() > 400
    f = np.exp(-result.internal["d"])
    np.testing.assert_allclose((f * M * eps)[damaged], 2 * r_d / eps[damaged], rtol=1e-12)
    onset = eps[np.argmax(damaged)]
    assert np.sqrt(2 * r_d / M) <= onset <= np.sqrt(2 * r_d / M) + d_eps


def test_model_one_tension_only_driving_energy():
    compression = ramp(-3e-3, 10)
    assert np.all(uniaxial_strain(ModelIDamage(E, 0.3, 0.05), compression).internal["d"] == 0.0)
    assert uniaxial_strain(ModelIDamage(E, 0.3, 0.05, damage_energy="full"), compression).internal["d"][-1] > 0.0


def test_model_one_returns_exactly_the_operator_split_tangent_f_m_E():
    """Eq. (6.63): the tangent is f^m E even while plastic flow and damage are active (inconsistent on purpose)."""
    material = ModelIDamage(E, 0.3, 0.05, R_P, K_H)
    state = material.initial_state((4,))
    rng = np.random.default_rng(5)
    checked_inconsistent = False
    for _ in range(4):
        eps = state["eps"] + rng.normal(scale=1.5e-3, size=(4, 6))
        response = material.update(state, eps)
        f_m = np.exp(-state["d"])
        np.testing.assert_array_equal(response.tangent, f_m[:, None, None] * material.stiffness)
        plastic = response.state["alpha_p"] > state["alpha_p"]
        if plastic.any():
            numeric = finite_difference_tangent(material, state, eps)
            assert np.abs(numeric[plastic] - response.tangent[plastic]).max() > 0.01 * E
            checked_inconsistent = True
        state = response.state
    assert checked_inconsistent and np.any(state["d"] > 0)


def test_model_one_newton_update_at_beta_zero_is_the_single_step_of_eq_6_77():
    rng = np.random.default_rng(0)
    f_old = rng.uniform(0.1, 1.0, 50)
    psi0 = rng.uniform(0.0, 1.0, 50)
    r_d = 0.05
    f_new = damage_function_update(f_old, psi0, 0.0, 0.0, 0.0, r_d, 1e-6)
    phi = f_old * psi0 - r_d
    one_step = np.where(phi > 0, f_old - phi / psi0, f_old)
    np.testing.assert_allclose(f_new, one_step, rtol=1e-13)


@pytest.mark.parametrize("laplacian_derivative", [-16.0, 3.0])
def test_model_one_nonlocal_update_solves_the_indicator_6_76(laplacian_derivative):
    """With Lambda_f linearised about f^m the root equals Eq. (6.77) iterated to convergence and Phi_d(f) = 0."""
    rng = np.random.default_rng(1)
    beta, r_d = 0.1, 0.05
    f_old = rng.uniform(0.3, 1.0, 200)
    psi0 = rng.uniform(0.0, 0.5, 200)
    lap = rng.uniform(-0.5, 0.5, 200)
    f_new = damage_function_update(f_old, psi0, lap, laplacian_derivative, beta, r_d, 1e-6)

    def linearised_laplacian(f):
        return lap + laplacian_derivative * (f - f_old)

    active = damage_indicator(f_old, psi0, lap, beta, r_d) > 0
    assert 20 < active.sum() < 200
    if laplacian_derivative < 0:  # the sign of a Laplacian stencil, D Lambda_f = -sum B 1 (6.75)
        f = f_old.copy()
        for _ in range(50):  # the seed's Newton step (6.77), repeated
            phi = damage_indicator(f, psi0, linearised_laplacian(f), beta, r_d)
            f = np.where(active, f - phi / (psi0 - beta * linearised_laplacian(f) - beta * f * laplacian_derivative), f)
        np.testing.assert_allclose(f_new, f, rtol=1e-10)
    # otherwise the indicator is concave and Newton from f^m may climb to the root above f^m; ours stays below
    np.testing.assert_allclose(damage_indicator(f_new, psi0, linearised_laplacian(f_new), beta, r_d)[active], 0.0,
                               atol=1e-12)
    np.testing.assert_array_equal(f_new[~active], f_old[~active])
    assert np.all((f_new > 0) & (f_new <= f_old))


def test_model_one_damage_step_can_be_split_from_the_plastic_step():
    """update(damage=False) + update_damage(...) == update(...), the two phases of Algorithm 1."""
    material = ModelIDamage(E, 0.3, 0.05, R_P, K_H, beta=0.1)
    state = material.initial_state((8,))
    eps = np.random.default_rng(2).normal(scale=1e-3, size=(8, 6))
    loading = {"laplacian": np.linspace(-1, 1, 8), "laplacian_derivative": -8.0}
    one = material.update(state, eps, **loading)
    two = material.update(state, eps, damage=False)
    two_state = material.update_damage(two.state, **loading)
    np.testing.assert_array_equal(one.stress, two.stress)
    for key in one.state:
        np.testing.assert_array_equal(one.state[key], two_state[key])
    # an element-averaged driving energy larger than the local one damages more
    more = material.update_damage(two.state, psi0_bar=2.0 * two.state["psi0"], **loading)
    assert np.all(more["d"] >= two_state["d"]) and np.any(more["d"] > two_state["d"])


def test_model_one_energy_balance_in_the_local_limit():
    """beta = 0: the work equals f Psi0 + r_d d (both 2 r_d ln(eps/eps*) + r_d) as the steps shrink."""
    gaps = []
    for n_steps in (200, 800):
        material = ModelIDamage(E, 0.0, 0.05)
        result = uniaxial_strain(material, ramp(3e-3, n_steps))
        work = np.sum(0.5 * (result.stress[1:] + result.stress[:-1]) * np.diff(result.strain, axis=0))
        final = {key: value[-1] for key, value in result.internal.items()}
        gaps.append(abs(work - material.stored_energy(final) - material.dissipation(final)) / work)
    assert gaps[1] < 0.5 * gaps[0] and gaps[1] < 0.01, gaps


# --- Model II ----------------------------------------------------------------------------------------------


def local_quadratic_damage(eps11, E, nu, r_d, increment, d_max=0.999):
    """Independent scalar implementation of local (1 - d)^2 damage with the rate-limited rule, uniaxial strain."""
    M = constrained_modulus(E, nu)
    d, stresses, damages = 0.0, [], []
    for eps in eps11:
        psi0 = 0.5 * M * eps**2
        if 2.0 * (1.0 - d) * psi0 > r_d:  # p_d = -f'(d) Psi0
            d = min(d + increment, d_max)
        stresses.append((1.0 - d) ** 2 * M * eps)
        damages.append(d)
    return np.array(stresses), np.array(damages)


def test_model_two_with_one_subdomain_is_local_quadratic_damage():
    nu, r_d, alpha, work = 0.2, 0.1, 0.05, 0.2  # increment alpha * W = 0.01 per step
    eps11 = ramp(4e-3, 2000)
    result = uniaxial_strain(ModelIIDamage(E, nu, r_d, n=1, alpha=alpha), eps11, loading={"external_work": work})
    stress, d = local_quadratic_damage(eps11, E, nu, r_d, alpha * work)
    np.testing.assert_allclose(result.stress_component("11")[1:], stress, rtol=1e-12)
    np.testing.assert_allclose(result.internal["d"][1:, 0], d, rtol=1e-12)
    # ... and tracks the rate-independent envelope d = 1 - r_d / (2 Psi0) within one increment
    M = constrained_modulus(E, nu)
    envelope = 1.0 - r_d / (M * eps11**2)
    settled = eps11 > 1.3 * np.sqrt(r_d / M)
    assert np.all(np.abs(d[settled] - envelope[settled]) <= alpha * work + 1e-12)


@settings(max_examples=40, deadline=None)
@given(
    arrays(np.float64, st.integers(1, 12), elements=st.floats(0.0, 0.99)),
    arrays(np.float64, 6, elements=st.floats(-1e-2, 1e-2)),
)
def test_erve_identities_6_87_to_6_94(d, eps):
    material = ModelIIDamage(E, 0.3, 0.1, n=d.size)
    f_i = damage_function(d)
    f_bar = effective_damage_function(f_i)
    eps_i = erve_strains(eps, f_i)
    np.testing.assert_allclose(eps_i.mean(axis=0), eps, atol=1e-15)  # compatibility of (6.86)
    psi0 = material.elastic_energy(eps)
    relaxed = np.mean(f_i * material.elastic_energy(eps_i))
    np.testing.assert_allclose(relaxed, f_bar * psi0, rtol=1e-9, atol=1e-15)  # (6.89)
    # p_d,i = -d Psi_rel / d d_i by central differences (6.94)
    h = 1e-7
    numeric = [
        -(effective_damage_function(damage_function(d + h * e)) - effective_damage_function(damage_function(d - h * e)))
        / (2 * h) * psi0
        for e in np.eye(d.size)
    ]
    np.testing.assert_allclose(driving_forces(d, psi0), numeric, rtol=1e-5, atol=1e-12 * (1 + psi0))


def test_model_two_sweep_localises_into_the_first_subdomain():
    """Equal damage, Psi0 just above onset: after d_1 grows f_bar drops and the others stay below r_d / n."""
    d = damage_sweep(np.zeros(20), psi0=0.51 * 0.1, increment=0.2, r_d=0.1)
    np.testing.assert_array_equal(d, [0.2] + [0.0] * 19)
    d = damage_sweep(np.zeros(20), psi0=0.49 * 0.1, increment=0.2, r_d=0.1)
    np.testing.assert_array_equal(d, 0.0)


def test_model_two_onset_does_not_depend_on_n():
    for n in (1, 5, 20):
        result = uniaxial_strain(ModelIIDamage(E, 0.0, 0.1, n=n), ramp(1e-3, 1000), loading={"external_work": 0.1})
        onset = result.strain_component("11")[np.argmax(result.internal["d"].max(axis=-1) > 0)]
        assert np.sqrt(0.1 / E) <= onset <= np.sqrt(0.1 / E) + 1e-6


def test_model_two_rate_limit_and_loading_arguments():
    material = ModelIIDamage(E, 0.3, 0.1, n=4, alpha=0.05)
    state = material.initial_state((3,))
    eps = np.tile([2e-3, 0, 0, 0, 0, 0], (3, 1))
    by_work = material.update(state, eps, external_work=1.0)
    by_power = material.update(state, eps, dt=0.5, external_power=2.0)
    np.testing.assert_array_equal(by_work.state["d"], by_power.state["d"])
    assert np.all(by_work.state["d"] <= 0.05) and np.any(by_work.state["d"] == 0.05)
    # the constructor's dt (Table 7.2: 1 s) is used when update gets none
    np.testing.assert_array_equal(material.update(state, eps, external_power=1.0).state["d"], by_work.state["d"])
    np.testing.assert_array_equal(material.update(state, eps, external_work=-1.0).state["d"], 0.0)
    with pytest.raises(ValueError, match="external_power"):
        material.update(state, eps)
    with pytest.raises(ValueError, match="external_work"):
        material.update(state, eps, external_work=np.inf)


def test_model_two_tension_option_does_not_damage_in_compression():
    compression = ramp(-3e-3, 20)
    tension_only = ModelIIDamage(E, 0.3, 0.1, damage_energy="tension")
    assert np.all(uniaxial_strain(tension_only, compression, loading={"external_work": 1}).internal["d"] == 0.0)
    full = ModelIIDamage(E, 0.3, 0.1)
    assert np.any(uniaxial_strain(full, compression, loading={"external_work": 1}).internal["d"] > 0.0)


def test_model_two_seed_tangent_6_105():
    """Away from a threshold the FD damage derivative (6.104) is zero and (6.105) is f_bar^m E; at one it is huge."""
    r_d, tol = 0.1, 1e-8
    material = ModelIIDamage(E, 0.0, r_d, n=3, tangent="seed", fd_tolerance=tol)
    state = material.update(material.initial_state(()), np.array([1e-4, 0, 0, 0, 0, 0]), external_work=1.0).state
    away = material.update(state, np.array([2e-4, 0, 0, 0, 0, 0]), external_work=1.0)
    np.testing.assert_array_equal(away.tangent, material.stiffness)
    eps_threshold = np.sqrt(2 * (r_d / 2 - tol / 4) / E)  # 2 Psi0 just below r_d, 2 (Psi0 + tol) above
    at = material.update(state, np.array([eps_threshold, 0, 0, 0, 0, 0]), external_work=1.0)
    assert np.all(at.state["d"] == 0.0)
    correction = at.tangent - material.stiffness
    assert np.linalg.matrix_rank(correction, tol=1e-6 * np.abs(correction).max()) == 1
    assert np.abs(correction).max() > 1e3 * E


# --- both models: irreversibility and hard cases -------------------------------------------------------------

MODELS = {
    "model-I": (ModelIDamage(E, 0.3, 0.05, R_P, K_H), {}),
    "model-I-nonlocal": (ModelIDamage(E, 0.3, 0.05, beta=1.0), {"laplacian": 0.3, "laplacian_derivative": -8.0}),
    "model-II": (ModelIIDamage(E, 0.3, 0.1, n=20, r_p=R_P, K_H=K_H), {"external_work": 0.5}),
}


@pytest.mark.parametrize("name", MODELS)
@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_damage_never_decreases_on_random_strain_paths(name, seed):
    material, loading = MODELS[name]
    rng = np.random.default_rng(seed)
    state = material.initial_state((16,))
    for _ in range(6):
        eps = state["eps"] + rng.normal(scale=rng.uniform(1e-4, 4e-3), size=(16, 6))
        new = material.update(state, eps, **loading).state
        assert np.all(new["d"] >= state["d"])
        assert np.all(new["dissipation"] >= state["dissipation"] - 1e-12)
        state = new


@pytest.mark.parametrize("name", MODELS)
def test_fully_damaged_points_stay_finite_and_capped(name):
    material, loading = MODELS[name]
    if "external_work" in loading:
        loading = {"external_work": 5.0}  # a rate limit that lets every sub-domain reach the cap
    state = material.initial_state((5,))
    direction = np.array([1.0, 0.2, -0.3, 0.4, 0.1, -0.2])
    for scale in np.geomspace(1e-3, 1.0, 40):
        response = material.update(state, scale * direction * np.arange(1, 6)[:, None], **loading)
        state = response.state
        assert np.all(np.isfinite(response.stress)) and np.all(np.isfinite(response.tangent))
    if name.startswith("model-II"):
        # one sub-domain at the cap unloads the ERVE (f_bar <= n f(0.999)), so the others need not follow
        assert np.all(state["d"] <= 0.999) and np.all(np.any(state["d"] == 0.999, axis=-1))
        f_bar = effective_damage_function(damage_function(state["d"]))
        assert np.all(f_bar <= material.n * 1e-6 * (1 + 1e-9))
        np.testing.assert_allclose(material.effective_damage(state), 1.0 - np.sqrt(f_bar), rtol=1e-12)
    else:
        assert np.all(state["d"] <= material.d_max + 1e-12) and np.all(np.exp(-state["d"]) >= 1e-6 * (1 - 1e-12))
    # the tangent stays positive definite (elastic unloading from the damaged state)
    unload = material.update(state, 0.5 * state["eps"], **loading)
    assert np.all(np.linalg.eigvalsh(unload.tangent) > 0)
