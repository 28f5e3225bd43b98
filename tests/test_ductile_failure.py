"""Ductile failure at a material point: stress triaxiality η and Lode parameter ξ of the standard stress states,
Johnson–Cook's fracture strain with Bao and Wierzbicki's cut-off, the damage indicator D = ∫ dε̄ᵖ/ε_f reaching 1
at ε_f on proportional paths of the small-strain and the finite-strain plasticity, invariance under rotations,
and clear refusals."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from abrakit import tensors as T
from abrakit.compiled import HAVE_NUMBA
from abrakit.materials import LogStrainPlasticity, VonMisesPlasticity, pure_shear, ramp, uniaxial_stress
from abrakit.materials.ductile_failure import (
    BAO_WIERZBICKI_CUTOFF,
    JOHNSON_COOK_1985,
    JohnsonCookFailure,
    equivalent_plastic_strain,
    lode_parameter,
    stress_state,
    stress_triaxiality,
    von_mises_stress,
)
from abrakit.materials.finite_strain import ductile_damage_update

E, NU = 210000.0, 0.33
R_P, K_H = 355.0 / math.sqrt(1.5), 1000.0 / 1.5          # the scratch's St-52: sigma_0 = 355 MPa, H = 1000 MPa
SMALL = VonMisesPlasticity(E, NU, R_P, K_H, integration="implicit")
FINITE = LogStrainPlasticity(SMALL)
JC = JohnsonCookFailure()

STATES = {                                       # stress (MPa) and its (eta, xi)
    "uniaxial tension": (np.diag([300.0, 0.0, 0.0]), 1.0 / 3.0, 1.0),
    "pure shear": (np.array([[0.0, 200.0, 0.0], [200.0, 0.0, 0.0], [0.0, 0.0, 0.0]]), 0.0, 0.0),
    "equibiaxial tension": (np.diag([250.0, 250.0, 0.0]), 2.0 / 3.0, -1.0),
    "uniaxial compression": (np.diag([-400.0, 0.0, 0.0]), -1.0 / 3.0, -1.0),
}


def rotate(stress, rotation):
    Q = rotation.as_matrix()
    return Q @ stress @ np.swapaxes(Q, -1, -2)


@pytest.mark.parametrize("name", STATES)
def test_triaxiality_and_lode_parameter_of_the_standard_stress_states(name):
    stress, eta, xi = STATES[name]
    assert stress_triaxiality(stress) == pytest.approx(eta, abs=1e-14)
    assert lode_parameter(stress) == pytest.approx(xi, abs=1e-14)
    # a superposed pressure moves eta by p / sigma_eq and leaves xi
    shifted = stress - 50.0 * np.eye(3)
    assert stress_triaxiality(shifted) == pytest.approx(eta - 50.0 / von_mises_stress(stress), abs=1e-14)
    assert lode_parameter(shifted) == pytest.approx(xi, abs=1e-12)
    # the same state rotated, scaled and in a batch
    batch = np.stack([rotate(2.5 * stress, Rotation.from_euler("xyz", [0.3, -1.1, 2.0])), stress])
    eta_b, xi_b = stress_state(batch)
    assert np.allclose(eta_b, eta, atol=1e-12) and np.allclose(xi_b, xi, atol=1e-12)


def test_von_mises_stress_and_the_equivalent_plastic_strain_of_uniaxial_flow():
    assert von_mises_stress(np.diag([300.0, 0.0, 0.0])) == pytest.approx(300.0)
    assert von_mises_stress(STATES["pure shear"][0]) == pytest.approx(200.0 * math.sqrt(3.0))
    eps_p = np.array([1.0, -0.5, -0.5]) * 0.2                        # uniaxial plastic flow, eps_p11 = 0.2
    assert equivalent_plastic_strain(np.linalg.norm(eps_p)) == pytest.approx(0.2)


def test_a_point_without_deviator_gets_the_limits_and_no_damage_under_pressure():
    eta, xi = stress_state(np.stack([-50.0 * np.eye(3), 50.0 * np.eye(3), np.zeros((3, 3))]))
    assert eta.tolist() == [-np.inf, np.inf, 0.0] and xi.tolist() == [0.0, 0.0, 0.0]
    assert JC.update(0.2, 0.5, -50.0 * np.eye(3)) == 0.2
    assert JC.update(0.2, 0.5, 50.0 * np.eye(3)) == pytest.approx(0.2 + 0.5 / 0.05)     # eps_f -> D1


def test_johnson_cook_fracture_strain_of_4340_steel_and_the_cut_off():
    eta = np.array([1.0 / 3.0, 0.0, 2.0 / 3.0, -0.3, -1.0 / 3.0, -0.4, -5.0])
    expected = 0.05 + 3.44 * np.exp(-2.12 * eta[:4])
    strain = JC.fracture_strain(eta)
    assert np.allclose(strain[:4], expected, rtol=1e-14)
    assert strain[0] == pytest.approx(1.7469, abs=1e-4) and strain[1] == pytest.approx(3.49)
    assert np.all(np.isinf(strain[4:]))
    assert JohnsonCookFailure(cutoff=None).fracture_strain(-0.4) == pytest.approx(0.05 + 3.44 * np.exp(0.848))
    assert BAO_WIERZBICKI_CUTOFF == -1.0 / 3.0
    assert JohnsonCookFailure.of("4340 steel") == JC
    # a fit with D1 < 0 (Armco iron) falls to zero near eta = 1.9 and is held at the minimum strain
    armco = JohnsonCookFailure.of("Armco iron")
    d1, d2, d3 = JOHNSON_COOK_1985["Armco iron"][:3]
    assert armco.fracture_strain(1.0) == pytest.approx(d1 + d2 * np.exp(d3))
    assert armco.fracture_strain(3.0) == armco.minimum_strain


def test_damage_is_the_sum_of_strain_increments_over_the_fracture_strain_and_no_input_changes():
    stress = np.stack([STATES["uniaxial tension"][0], STATES["pure shear"][0], STATES["uniaxial compression"][0]])
    damage = np.array([0.1, 0.2, 0.3])
    increment = np.array([0.05, 0.05, 0.05])
    kept = (stress.copy(), damage.copy(), increment.copy())
    new = JC.update(damage, increment, stress)
    assert np.allclose(new, [0.1 + 0.05 / 1.7469029657120483, 0.2 + 0.05 / 3.49, 0.3])
    assert new is not damage
    for before, after in zip(kept, (stress, damage, increment), strict=True):
        assert np.array_equal(before, after)
    assert np.array_equal(JC.update(damage, 0.0, stress), damage)                  # no flow, no damage


def _crossing(eps_bar, damage):
    """Equivalent plastic strain at which D reaches 1 (linear interpolation between increments)."""
    k = int(np.argmax(damage >= 1.0))
    assert damage[k] >= 1.0 > damage[k - 1]
    return eps_bar[k - 1] + (1.0 - damage[k - 1]) * (eps_bar[k] - eps_bar[k - 1]) / (damage[k] - damage[k - 1])


def _damage_along(eps_bar, stress):
    damage = np.zeros(len(eps_bar))
    for n in range(1, len(eps_bar)):
        damage[n] = JC.update(damage[n - 1], eps_bar[n] - eps_bar[n - 1], stress[n])
    return damage


@pytest.mark.parametrize("path,eta", [(uniaxial_stress, 1.0 / 3.0), (pure_shear, 0.0)])
def test_small_strain_driver_reaches_failure_at_the_fracture_strain(path, eta):
    """Proportional paths in 800 increments: D = 1 where the von Mises plastic strain √(2/3) α_p reaches
    ε_f(η) (1.747 in tension, 3.49 in shear), within 10⁻³."""
    peak = 2.2 if eta > 0 else 7.0                               # eps_11, or engineering shear gamma_12
    result = path(SMALL, ramp(peak, 800))
    eps_bar = equivalent_plastic_strain(result.internal["alpha_p"])
    stress = result.stress_tensor()
    assert np.allclose(stress_triaxiality(stress[1:]), eta, atol=1e-8)
    damage = _damage_along(eps_bar, stress)
    eps_f = JC.fracture_strain(eta)
    assert _crossing(eps_bar, damage) == pytest.approx(eps_f, rel=1e-3)
    assert np.interp(eps_f, eps_bar, damage) == pytest.approx(1.0, abs=1e-3)


def _uniaxial_finite_strain(log_stretches):
    """Uniaxial stress by the finite-strain plasticity: F = diag(λ, μ, μ), μ by the secant method on P_22 = 0
    (the tangent is not needed); the states of every converged increment."""
    state = FINITE.initial_state((1,))
    states, mu, lam_old = [state], 1.0, 1.0

    def lateral(lam, mu):
        response = FINITE.update(state, np.array([[lam, 0, 0, 0, mu, 0, 0, 0, mu]]), compiled=False)
        return response, response.stress[0, 4]

    for lam in np.exp(log_stretches):
        guess = mu * np.sqrt(lam_old / lam)                      # incompressible flow
        (response, r0), m0, m1 = lateral(lam, guess), guess, guess * (1.0 + 1e-7)
        for _ in range(50):
            response, r1 = lateral(lam, m1)
            if abs(r1) <= 1e-10 * (1.0 + abs(response.stress[0, 0])):
                break
            m0, m1, r0 = m1, m1 - r1 * (m1 - m0) / (r1 - r0), r1
        else:
            raise AssertionError("lateral stretch did not converge")
        state, mu, lam_old = response.state, m1, lam
        states.append(state)
    return states


def _shear_finite_strain(gammas):
    state = FINITE.initial_state((1,))
    states = [state]
    for g in gammas:
        state = FINITE.update(state, np.array([[1.0, g, 0, 0, 1.0, 0, 0, 0, 1.0]]), compiled=False).state
        states.append(state)
    return states


@pytest.mark.parametrize("kind,eta", [("uniaxial tension", 1.0 / 3.0), ("simple shear", 0.0)])
def test_finite_strain_hook_reaches_failure_at_the_fracture_strain(kind, eta):
    """The post-processing of converged increments of LogStrainPlasticity: D = 1 at ε̄ᵖ = ε_f within 10⁻³ in
    uniaxial tension (ln λ to 2.0) and in simple shear (γ to 7; det F = 1 keeps τ_m = 0)."""
    if kind == "uniaxial tension":
        states = _uniaxial_finite_strain(ramp(2.0, 200))
    else:
        states = _shear_finite_strain(ramp(7.0, 700))
    damage = [np.zeros(1)]
    for old, new in zip(states[:-1], states[1:], strict=True):
        damage.append(ductile_damage_update(JC, damage[-1], old, new))
    damage = np.array(damage)[:, 0]
    eps_bar = equivalent_plastic_strain(np.array([s["alpha_p"][0] for s in states]))
    kirchhoff = np.array([s["cauchy"] * s["J"] for s in states[1:]])
    assert np.allclose(stress_triaxiality(T.from_mandel(kirchhoff)), eta, atol=1e-8)
    eps_f = JC.fracture_strain(eta)
    assert _crossing(eps_bar, damage) == pytest.approx(eps_f, rel=1e-3)
    if kind == "uniaxial tension":        # ln λ = ε̄ᵖ + τ/E with τ = σ_0 + H ε̄ᵖ: ε̄ᵖ is the plastic log strain
        assert eps_bar[-1] == pytest.approx((2.0 - 355.0 / E) / (1.0 + 1000.0 / E), rel=1e-10)


def test_the_hook_reads_the_states_and_changes_none():
    states = _uniaxial_finite_strain(ramp(0.05, 5))
    old, new = states[-2], states[-1]
    copies = [{k: np.array(v, copy=True) for k, v in s.items()} for s in (old, new)]
    damage = np.array(0.01)
    updated = ductile_damage_update(JC, damage, old, new)
    expected = 0.01 + math.sqrt(2.0 / 3.0) * (new["alpha_p"] - old["alpha_p"]) / JC.fracture_strain(1.0 / 3.0)
    assert updated == pytest.approx(expected, rel=1e-9) and damage == 0.01
    for copy, state in zip(copies, (old, new), strict=True):
        assert all(np.array_equal(copy[k], state[k]) for k in state)


def test_the_hook_is_vectorised_over_the_points_of_a_mesh():
    F = np.tile(np.eye(3).ravel(), (4, 8, 1))
    F[..., 0] += np.linspace(0.0, 0.3, 4)[:, None]               # elements stretched by 0 ... 30 %
    F[..., 1] += np.linspace(0.0, 0.2, 8)[None, :]               # with some shear
    old = FINITE.initial_state((4, 8))
    new = FINITE.update(old, F, compiled=False).state
    damage = ductile_damage_update(JC, np.zeros((4, 8)), old, new)
    point = ductile_damage_update(JC, 0.0, {k: v[2, 5] for k, v in old.items()}, {k: v[2, 5] for k, v in new.items()})
    assert damage.shape == (4, 8) and damage[0, 0] == 0.0 and damage[2, 5] == pytest.approx(point, rel=1e-12)
    assert damage.max() > 0.0
    if HAVE_NUMBA:                                               # the compiled update's states give the same D
        compiled = FINITE.update(old, F, compiled=True).state
        assert np.allclose(ductile_damage_update(JC, np.zeros((4, 8)), old, compiled), damage, rtol=1e-9, atol=1e-14)


def test_with_the_cut_off_no_damage_grows_at_triaxiality_minus_0_4_for_any_strain():
    """σ = σ_eq (uniaxial compression) + p I with η = −0.4: D stays 0 over 10⁴ of equivalent plastic strain;
    just above the cut-off (η = −0.3) the same increments damage."""
    def state_of(eta):
        return np.diag([-300.0, 0.0, 0.0]) + (eta + 1.0 / 3.0) * 300.0 * np.eye(3)

    assert stress_triaxiality(state_of(-0.4)) == pytest.approx(-0.4)
    damage, above = np.zeros(()), np.zeros(())
    for _ in range(100):
        damage = JC.update(damage, 100.0, state_of(-0.4))
        above = JC.update(above, 0.01, state_of(-0.3))
    assert damage == 0.0
    assert above == pytest.approx(1.0 / JC.fracture_strain(-0.3), rel=1e-12)


symmetric = st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=6, max_size=6)


@settings(max_examples=60, deadline=None)
@given(values=symmetric, angles=st.lists(st.floats(-np.pi, np.pi), min_size=3, max_size=3),
       scale=st.floats(1e-3, 1e3), increment=st.floats(0.0, 0.5))
def test_stress_state_and_damage_are_invariant_under_rotation_and_scaling(values, angles, scale, increment):
    a, b, c, d, e, f = values
    stress = np.array([[a, f, e], [f, b, d], [e, d, c]])
    eta, xi = stress_state(stress)
    if not np.isfinite(eta) or von_mises_stress(stress) < 1e-6 * (np.abs(stress).max() + 1.0):
        return                                                    # nearly hydrostatic: the ratios are ill-posed
    turned = rotate(scale * stress, Rotation.from_euler("xyz", angles))
    eta_r, xi_r = stress_state(turned)
    assert -1.0 <= xi <= 1.0
    assert eta_r == pytest.approx(eta, rel=1e-8, abs=1e-8) and xi_r == pytest.approx(xi, abs=1e-7)
    assert stress_state(-stress)[0] == pytest.approx(-eta) and stress_state(-stress)[1] == pytest.approx(-xi)
    assert JC.update(0.1, increment, turned) == pytest.approx(JC.update(0.1, increment, stress), rel=1e-9)
    assert JC.update(0.1, increment, stress) >= 0.1


def test_bad_input_is_refused_by_name():
    tension = STATES["uniaxial tension"][0]
    with pytest.raises(ValueError, match="damage"):
        JC.update(-0.1, 0.1, tension)
    with pytest.raises(ValueError, match="plastic_strain_increment"):
        JC.update(0.0, -0.1, tension)
    with pytest.raises(ValueError, match="plastic_strain_increment"):
        JC.update(0.0, np.nan, tension)
    with pytest.raises(ValueError, match="stress"):
        JC.update(0.0, 0.1, np.ones((3, 2)))
    with pytest.raises(ValueError, match="stress must be symmetric"):
        stress_state(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    with pytest.raises(ValueError, match="stress"):
        stress_state(np.full((3, 3), np.nan))
    with pytest.raises(ValueError, match="shapes"):
        JC.update(np.zeros(3), 0.1, np.stack([tension] * 2))
    with pytest.raises(ValueError, match="triaxiality"):
        JC.fracture_strain(np.nan)
    with pytest.raises(TypeError, match="triaxiality"):
        JC.fracture_strain("high")
    with pytest.raises(ValueError, match="lode"):
        JC.fracture_strain(0.3, 1.5)
    with pytest.raises(ValueError, match="alpha_p"):
        equivalent_plastic_strain(-1.0)
    for kwargs, name in (({"D2": -1.0}, "D2"), ({"minimum_strain": 0.0}, "minimum_strain"),
                         ({"cutoff": 2.0}, "cutoff"), ({"D1": np.nan}, "D1")):
        with pytest.raises(ValueError, match=name):
            JohnsonCookFailure(**kwargs)
    with pytest.raises(TypeError, match="D3"):
        JohnsonCookFailure(D3="steep")
    with pytest.raises(ValueError, match="material"):
        JohnsonCookFailure.of("St-52")


def test_the_hook_refuses_swapped_or_elastic_states_and_a_criterion_without_update():
    states = _uniaxial_finite_strain(ramp(0.05, 5))
    with pytest.raises(ValueError, match="states swapped"):
        ductile_damage_update(JC, 0.0, states[-1], states[-2])
    elastic = {k: v for k, v in states[-1].items() if k != "alpha_p"}
    with pytest.raises(ValueError, match="new_state"):
        ductile_damage_update(JC, 0.0, states[-2], elastic)
    with pytest.raises(TypeError, match="criterion"):
        ductile_damage_update(0.05, 0.0, states[-2], states[-1])
    with pytest.raises(ValueError, match="damage"):
        ductile_damage_update(JC, -1.0, states[-2], states[-1])
