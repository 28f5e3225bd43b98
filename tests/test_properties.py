"""Property-based checks of the public functions that every chapter leans on (hypothesis).

Two properties: finite valid input gives finite output, and invalid input (NaN, out-of-range parameters) raises a
``ValueError`` or ``TypeError`` that names the parameter, never a NaN, an inf or an exception from inside numpy.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from abrakit import identification, tensors, wear
from abrakit.dem import contact_laws
from abrakit.fatigue import BondParameters, criterion
from abrakit.fatigue.bond_law import bond_stresses, plastic_return
from abrakit.materials import LinearElastic, LinearSofteningDamage, ModelIDamage, ModelIIDamage, VonMisesPlasticity
from abrakit.materials.plasticity import plastic_step

SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
moduli = st.floats(1e3, 1e6)
poisson = st.floats(-0.9, 0.49)
strain = st.lists(st.floats(-0.05, 0.05), min_size=6, max_size=6).map(np.array)
bad_numbers = st.sampled_from([np.nan, np.inf, -np.inf])

MATERIALS = {
    "elastic": lambda E, nu: LinearElastic(E, nu),
    "plastic": lambda E, nu: VonMisesPlasticity(E, nu, r_p=E * 1e-3, K_H=E * 1e-2),
    "softening": lambda E, nu: LinearSofteningDamage(E, nu, 1e-3, 2e-2),
    "model_one": lambda E, nu: ModelIDamage(E=E, nu=nu, r_d=0.05, r_p=E * 1e-3, K_H=E * 1e-2, beta=0.1),
    "model_two": lambda E, nu: ModelIIDamage(E=E, nu=nu, r_d=0.1, n=5, dt=1.0, r_p=E * 1e-3, K_H=E * 1e-2,
                                             alpha=0.05),
}


def update(material, state, eps):
    if isinstance(material, ModelIIDamage):
        return material.update(state, eps, external_work=10.0)
    return material.update(state, eps)


@pytest.mark.parametrize("name", list(MATERIALS))
@SETTINGS
@given(E=moduli, nu=poisson, path=st.lists(strain, min_size=1, max_size=4))
def test_materials_give_finite_stresses_and_tangents_along_any_strain_path(name, E, nu, path):
    material = MATERIALS[name](E, nu)
    state = material.initial_state((1,))
    for eps in path:
        r = update(material, state, eps[None])
        assert np.all(np.isfinite(r.stress)) and np.all(np.isfinite(r.tangent))
        state = r.state


@pytest.mark.parametrize("name", list(MATERIALS))
@SETTINGS
@given(bad=bad_numbers, k=st.integers(0, 5))
def test_materials_refuse_non_finite_strains_by_name(name, bad, k):
    material = MATERIALS[name](2e5, 0.3)
    eps = np.zeros((1, 6))
    eps[0, k] = bad
    with pytest.raises(ValueError, match="eps"):
        update(material, material.initial_state((1,)), eps)


@SETTINGS
@given(nu=st.one_of(st.floats(0.5, 10.0), st.floats(-10.0, -1.0)))
def test_poisson_ratio_outside_its_range_is_refused_everywhere(nu):
    for make in (lambda: LinearElastic(1e3, nu), lambda: tensors.isotropic_stiffness(1e3, nu),
                 lambda: contact_laws.hertz_normal_coefficient(1e9, nu, 1e-3),
                 lambda: identification.contact_stiffnesses(1e9, nu, 1e9, 1e-3)):
        with pytest.raises(ValueError, match="nu|poisson"):
            make()


@SETTINGS
@given(bad=st.one_of(st.just(np.nan), st.floats(-1e6, -1e-9)))
def test_spring_stiffnesses_must_not_be_negative_or_nan(bad):
    """The series rule of Eq. (4.11)/(4.12), one function for the engine and the identification, takes 0 (no
    spring) and inf (a rigid wall) but nothing negative or NaN."""
    assert contact_laws.series_stiffness is identification.series_stiffness
    with pytest.raises(ValueError, match="k_a"):
        identification.series_stiffness(bad, 1e6)
    assert contact_laws.series_stiffness(np.inf, 1e6) == 1e6 and contact_laws.series_stiffness(0.0, 1e6) == 0.0


@SETTINGS
@given(eps=strain)
def test_plastic_step_refuses_a_nan_strain(eps):
    eps = eps.copy()
    eps[2] = np.nan
    with pytest.raises(ValueError, match="eps"):
        plastic_step(eps[None], np.zeros((1, 6)), np.zeros(1), 1e4, 10.0, 100.0, "implicit")


@SETTINGS
@given(A_g=st.floats(1e-3, 1e3), share=st.floats(0.0, 1.0))
def test_degree_of_wear_lies_in_zero_one_for_shoulders_up_to_the_groove(A_g, share):
    f_ab = wear.degree_of_wear(A_g, share * A_g)
    assert 0.0 <= f_ab <= 1.0 and wear.wear_regime(f_ab) in ("plowing", "wedging", "cutting")


@SETTINGS
@given(A_g=st.one_of(bad_numbers, st.floats(-1e3, 0.0)))
def test_wear_refuses_invalid_groove_areas_by_name(A_g):
    with pytest.raises(ValueError, match="A_g"):
        wear.degree_of_wear(A_g, 1.0)


@SETTINGS
@given(eps=strain)
def test_spectral_split_of_any_strain_adds_up(eps):
    A = tensors.from_mandel(eps)
    assert np.allclose(tensors.positive_part(A) + tensors.negative_part(A), A, atol=1e-15)


@SETTINGS
@given(bad=st.one_of(bad_numbers, st.floats(-1e3, 0.0)), which=st.integers(0, 3))
def test_critical_time_step_refuses_bad_masses_and_stiffnesses_by_name(bad, which):
    from abrakit.dem.integrate import critical_time_step

    args = [np.ones(3), np.ones(3), np.ones(3), np.ones(3)]
    if which >= 2 and bad == 0.0:
        return                                             # zero stiffness is allowed (a particle without contacts)
    args[which] = np.array([1.0, bad, 1.0])
    with pytest.raises(ValueError, match=("mass", "inertia", "k_translation", "k_rotation")[which]):
        critical_time_step(*args)


def test_erve_strains_refuse_a_fully_damaged_sub_domain_and_mean_interval_counts_what_it_drops():
    from abrakit.experiments.closed_form_checks import mean_interval
    from abrakit.materials.model_two import erve_strains

    with pytest.raises(ValueError, match="f_i"):
        erve_strains(np.ones(6), np.array([1.0, 0.0, 0.5]))
    assert np.all(np.isfinite(erve_strains(np.ones(6), np.array([1.0, 1e-6, 0.5]))))
    summary = mean_interval([1.0, np.nan, 2.0, np.inf])
    assert summary["n"] == 2 and summary["dropped"] == 2 and summary["mean"] == 1.5


@SETTINGS
@given(st.lists(st.tuples(st.floats(-5e-6, 5e-6), st.floats(-5e-6, 5e-6)), min_size=1, max_size=40))
def test_fatigue_bond_stays_admissible_along_any_displacement_path(steps):
    """Any path of displacement increments: the bond's stress never leaves its yield surface, D never decreases
    and stays in [D0, 1], nothing is NaN (seed 002 Eqs. 15–22)."""
    p = BondParameters()
    elastic, damage = np.zeros(2), p.initial_damage
    for du in steps:
        start = elastic.copy()
        elastic = elastic + du
        dn, ds, d, sn, ss = plastic_return(elastic[0], elastic[1], damage, p, start=tuple(start))
        elastic = elastic - (dn[0], ds[0])
        assert p.initial_damage <= damage <= d[0] <= 1.0
        damage = float(d[0])
        assert np.allclose(bond_stresses(*elastic, damage, p), (sn[0], ss[0]))
        assert criterion(sn[0], ss[0], damage, p) <= 1e-9 * (p.cohesion * (1 - damage)) ** 2 + 1e-12


@SETTINGS
@given(bad_numbers, st.sampled_from(["trial_n", "trial_s", "damage"]))
def test_fatigue_bond_refuses_non_finite_input_by_name(bad, which):
    values = {"trial_n": 1e-6, "trial_s": 1e-6, "damage": 0.1} | {which: bad}
    with pytest.raises(ValueError, match=which):
        plastic_return(values["trial_n"], values["trial_s"], values["damage"], BondParameters())
