"""Tests of abrakit.identification: Eq. (5.9), (5.20)–(5.26), (5.29), (4.11)–(4.14) and the numerical
solution of the constrained minimisation (5.12) that verifies Eq. (5.20) independently."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit import identification as I
from abrakit.tensors import isotropic_stiffness, sphere_quadrature, to_voigt

# a realistic SI scene: r = 1 mm, c = 6, porosity 35 % -> rho_c ~ 4.7e8 1/m^3, Kn ~ 1e7 N/m
RADIUS = 1.0e-3
RHO_C = I.contact_density(6.0, 0.35, RADIUS)
KN = 1.0e7

stiffness_ratio = st.floats(1e-3, 1e3)  # Kt / Kn
rng = np.random.default_rng(1)


def random_gradient(scale=1e-3):
    return rng.normal(size=(3, 3)) * scale


# --- contact density ----------------------------------------------------------------------------------


def test_contact_density_eq_5_9_by_hand():
    # c/2 (1 - eta) / (4/3 pi r^3) with c = 6, eta = 0.35, r = 1: 3 * 0.65 / (4.18879...)
    assert I.contact_density(6.0, 0.35, 1.0) == pytest.approx(3 * 0.65 / (4 * np.pi / 3), rel=1e-15)
    assert I.contact_density(6.0, 0.35, 2.0) == pytest.approx(3 * 0.65 / (4 * np.pi / 3) / 8, rel=1e-15)
    # each contact belongs to two particles: c/2 contacts per particle
    assert I.contact_density(4.0, 0.4, 0.5) == pytest.approx(2.0 * I.particle_number_density(0.4, 0.5))


def test_measured_contact_density_eq_5_29():
    assert I.measured_contact_density(1200, 2.0e-6) == pytest.approx(6.0e8)
    assert I.measured_contact_density(0, 1.0) == 0.0


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: I.contact_density(6.0, 1.0, 1.0), "porosity"),
        (lambda: I.contact_density(6.0, -0.1, 1.0), "porosity"),
        (lambda: I.contact_density(0.0, 0.3, 1.0), "coordination"),
        (lambda: I.contact_density(6.0, 0.3, 0.0), "radius"),
        (lambda: I.measured_contact_density(-1, 1.0), "n_contacts"),
        (lambda: I.measured_contact_density(10, 0.0), "volume"),
    ],
)
def test_contact_density_refuses_unphysical_input(call, name):
    with pytest.raises(ValueError, match=name):
        call()


# --- Eq. (5.20) and (5.21) ------------------------------------------------------------------------------


def test_eq_5_20_by_hand():
    # Kn = 2, Kt = 1, rho_c r^2 = 1: E = 15 / (3/2 + 2) = 30/7, nu = 1/7
    E, nu = I.elastic_constants(2.0, 1.0, 1.0, 1.0)
    assert (E, nu) == (pytest.approx(30 / 7, rel=1e-15), pytest.approx(1 / 7, rel=1e-15))
    # Kn = Kt: nu = 0 in every variant, E = 3, 4/3, 4/3 rho_c r^2 K
    for variant, E_expected in (("published", 3.0), ("consistent", 4.0 / 3.0), ("affine", 4.0 / 3.0)):
        E, nu = I.elastic_constants(5.0, 5.0, 2.0, 0.5, variant)
        assert E == pytest.approx(E_expected * 2.0 * 0.25 * 5.0, rel=1e-15)
        assert nu == pytest.approx(0.0, abs=1e-16)


def test_elastic_constants_broadcast():
    E, nu = I.elastic_constants(KN, KN * np.array([0.1, 1.0, 10.0]), RHO_C, RADIUS)
    assert E.shape == nu.shape == (3,)
    assert np.all(np.diff(nu) < 0)  # stiffer tangential springs lower Poisson's ratio


@pytest.mark.parametrize("variant", I.VARIANTS)
@given(ratio=stiffness_ratio, scale=st.floats(1e-3, 1e3))
@settings(max_examples=40, deadline=None)
def test_eq_5_20_agrees_with_the_numerical_minimisation(variant, ratio, scale):
    """Acceptance: Eq. (5.20) (and its variants) vs the discretised minimisation (5.12) to 1e-10 relative."""
    kn = KN * scale
    E, nu = I.elastic_constants(kn, ratio * kn, RHO_C, RADIUS, variant)
    num = I.numerical_elastic_constants(kn, ratio * kn, RHO_C, RADIUS, variant, degree=4)
    assert num.E == pytest.approx(E, rel=1e-10)
    assert num.nu == pytest.approx(nu, rel=1e-10, abs=1e-12)
    assert num.anisotropy < 1e-12
    np.testing.assert_allclose(num.stiffness, isotropic_stiffness(E, nu, "voigt"), rtol=0, atol=1e-10 * E)


@pytest.mark.parametrize("degree", [2, 3])
def test_a_rule_that_is_not_exact_for_degree_4_gives_an_anisotropic_wrong_answer(degree):
    # Eq. (5.18) needs <n n n n> exactly; below degree 4 the verification fails visibly
    E, _ = I.elastic_constants(KN, 0.4 * KN, RHO_C, RADIUS)
    num = I.numerical_elastic_constants(KN, 0.4 * KN, RHO_C, RADIUS, degree=degree)
    assert num.anisotropy > 1e-3
    assert abs(num.E / E - 1) > 1e-3


@pytest.mark.parametrize("degree", [0, 1])
def test_direction_sets_that_do_not_span_space_are_refused(degree):
    with pytest.raises(ValueError, match="span three dimensions"):
        I.numerical_elastic_constants(KN, KN, RHO_C, RADIUS, degree=degree)


def test_compliance_eq_5_19():
    # eps = 1/(rho_c r^2) [1/15 (1/Kn - 1/Kt) tr(sigma) I + (2/15/Kn + 1/5/Kt) sigma]
    kt = 0.3 * KN
    num = I.numerical_elastic_constants(KN, kt, RHO_C, RADIUS, degree=6)
    sigma = np.array([[2.0, 0.5, 0.0], [0.5, -1.0, 0.3], [0.0, 0.3, 0.5]]) * 1e6
    eps = (np.trace(sigma) * np.eye(3) / 15 * (1 / KN - 1 / kt) + (2 / 15 / KN + 1 / 5 / kt) * sigma) / (
        RHO_C * RADIUS**2
    )
    np.testing.assert_allclose(num.stiffness @ to_voigt(eps, "strain"), to_voigt(sigma, "stress"), atol=1e-6)


@pytest.mark.parametrize("variant", I.VARIANTS)
@given(ratio=stiffness_ratio, E=st.floats(1e6, 1e11))
@settings(max_examples=60, deadline=None)
def test_eq_5_21_inverts_eq_5_20(variant, ratio, E):
    E0, nu0 = I.elastic_constants(KN, ratio * KN, RHO_C, RADIUS, variant)
    kn, kt = I.contact_stiffnesses(E0, nu0, RHO_C, RADIUS, variant)
    assert kn == pytest.approx(KN, rel=1e-9)
    assert kt == pytest.approx(ratio * KN, rel=1e-9)
    low, high = I.POISSON_RANGE[variant]
    nu = low + (high - low) * ratio / (1 + ratio)  # anywhere inside the open range
    kn, kt = I.contact_stiffnesses(E, nu, RHO_C, RADIUS, variant)
    assert kn > 0 and kt > 0
    E1, nu1 = I.elastic_constants(kn, kt, RHO_C, RADIUS, variant)
    assert (E1, nu1) == (pytest.approx(E, rel=1e-9), pytest.approx(nu, rel=1e-9, abs=1e-12))


def test_eq_5_21_by_hand():
    # nu = 0.25, rho_c r^2 = 1: Kn = E / (3 * 0.5), Kt = E / (3 * 1.75)
    kn, kt = I.contact_stiffnesses(21.0, 0.25, 1.0, 1.0)
    assert (kn, kt) == (pytest.approx(14.0), pytest.approx(4.0))


@pytest.mark.parametrize("variant", I.VARIANTS)
def test_poisson_limits_of_eq_5_21(variant):
    low, high = I.POISSON_RANGE[variant]
    # Kt/Kn -> 0 reaches the upper, Kt/Kn -> inf the lower limit of nu
    assert I.elastic_constants(1.0, 1e-12, 1.0, 1.0, variant)[1] == pytest.approx(high, abs=1e-11)
    assert I.elastic_constants(1.0, 1e12, 1.0, 1.0, variant)[1] == pytest.approx(low, abs=1e-11)
    # close to a limit the stiffnesses are finite, positive and huge or tiny, never NaN
    kn, kt = I.contact_stiffnesses(1.0, high - 1e-12, 1.0, 1.0, variant)
    assert np.isfinite(kn) and kt > 0 and kt / kn < 1e-10
    kn, kt = I.contact_stiffnesses(1.0, low + 1e-12, 1.0, 1.0, variant)
    assert np.isfinite(kt) and kn > 0 and kt / kn > 1e10
    for nu in (low, high, high + 0.1, low - 0.1):
        with pytest.raises(ValueError, match=r"nu must lie in \("):
            I.contact_stiffnesses(1.0, nu, 1.0, 1.0, variant)


def test_affine_estimate_cannot_reach_granite_poisson_ratio():
    # Table 5.1: granite nu = 0.26, Chende sand nu = 0.32 lie above the affine limit 1/4
    for nu in (0.26, 0.32):
        I.contact_stiffnesses(69e9, nu, RHO_C, RADIUS, "published")
        with pytest.raises(ValueError, match=r"nu must lie in \(-1, 0.25\)"):
            I.contact_stiffnesses(69e9, nu, RHO_C, RADIUS, "affine")


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"E": 0.0}, "E"),
        ({"E": -1.0}, "E"),
        ({"rho_c": 0.0}, "rho_c"),
        ({"radius": -1.0}, "radius"),
        ({"nu": float("nan")}, "nu"),
    ],
)
def test_contact_stiffnesses_refuse_bad_input(kwargs, name):
    args = {"E": 1e9, "nu": 0.2, "rho_c": RHO_C, "radius": RADIUS} | kwargs
    with pytest.raises(ValueError, match=name):
        I.contact_stiffnesses(**args)


@pytest.mark.parametrize(("kn", "kt", "name"), [(0.0, 1.0, "kn"), (1.0, -1.0, "kt"), (np.inf, 1.0, "kn")])
def test_elastic_constants_refuse_bad_stiffness(kn, kt, name):
    with pytest.raises(ValueError, match=name):
        I.elastic_constants(kn, kt, RHO_C, RADIUS)


def test_unknown_variant_is_refused():
    with pytest.raises(ValueError, match="variant"):
        I.elastic_constants(1.0, 1.0, 1.0, 1.0, "voigt")
    with pytest.raises(ValueError, match="variant"):
        I.failure_stresses(1.0, 1.0, 1.0, 1.0, "affine")


# --- the kinematic constraint (5.10) and the three variants -------------------------------------------


def test_affine_field_violates_the_published_constraint_and_meets_the_consistent_one():
    n, w = sphere_quadrature(4)
    grad_u = random_gradient()
    u = I.affine_contact_displacements(grad_u, n, RADIUS)
    published = I.constraint_gradient(u, n, w, RADIUS, "published")
    consistent = I.constraint_gradient(u, n, w, RADIUS, "consistent")
    np.testing.assert_allclose(published, 2 / 3 * grad_u, atol=1e-18)
    np.testing.assert_allclose(consistent, grad_u, atol=1e-18)


def test_consistent_variant_is_the_published_one_scaled_by_one_over_alpha_squared():
    for ratio in (0.01, 0.4, 1.0, 7.0):
        Ep, nup = I.elastic_constants(KN, ratio * KN, RHO_C, RADIUS, "published")
        Ec, nuc = I.elastic_constants(KN, ratio * KN, RHO_C, RADIUS, "consistent")
        assert Ec == pytest.approx(4 / 9 * Ep, rel=1e-14)
        assert nuc == nup


def _bulk_shear(E, nu):
    return E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))


@given(ratio=stiffness_ratio)
def test_consistent_and_affine_are_reuss_and_voigt_means_of_the_contact_springs(ratio):
    """Same bulk modulus 4/9 rho_c r^2 Kn; shear moduli are the harmonic/arithmetic means of Kn, Kt (2:3)."""
    kt = ratio * KN
    s = RHO_C * RADIUS**2
    Kc, muc = _bulk_shear(*I.elastic_constants(KN, kt, RHO_C, RADIUS, "consistent"))
    Ka, mua = _bulk_shear(*I.elastic_constants(KN, kt, RHO_C, RADIUS, "affine"))
    assert Kc == pytest.approx(4 / 9 * s * KN, rel=1e-12)
    assert Ka == pytest.approx(4 / 9 * s * KN, rel=1e-12)
    assert muc == pytest.approx(2 / 3 * s / (2 / 5 / KN + 3 / 5 / kt), rel=1e-12)
    assert mua == pytest.approx(2 / 3 * s * (2 / 5 * KN + 3 / 5 * kt), rel=1e-12)
    assert muc <= mua * (1 + 1e-12)  # the affine field is admissible for the consistent minimisation


def test_published_modulus_exceeds_the_affine_upper_bound_above_a_critical_ratio():
    critical = (10 * np.sqrt(5) - 22) / 3  # root of 9 k^2 + 132 k - 16 = 0
    for ratio, above in ((0.5 * critical, False), (1.01 * critical, True), (1.0, True), (100.0, True)):
        Ep, _ = I.elastic_constants(KN, ratio * KN, RHO_C, RADIUS, "published")
        Ea, _ = I.elastic_constants(KN, ratio * KN, RHO_C, RADIUS, "affine")
        assert (Ep > Ea) is above
    Ep, _ = I.elastic_constants(KN, critical * KN, RHO_C, RADIUS, "published")
    Ea, _ = I.elastic_constants(KN, critical * KN, RHO_C, RADIUS, "affine")
    assert Ep == pytest.approx(Ea, rel=1e-12)


def test_affine_stiffness_by_quadrature_matches_the_energy_of_the_affine_field():
    # independent of the stress formula: Psi = rho_c <1/2 e.A e> with e = 2 r eps n on a finer rule
    kt = 0.3 * KN
    n, w = sphere_quadrature(10)
    eps = random_gradient()
    eps = (eps + eps.T) / 2
    e = I.affine_contact_displacements(eps, n, RADIUS)
    e_n = np.einsum("mi,mi->m", e, n)
    psi = RHO_C * np.sum(w * 0.5 * (KN * e_n**2 + kt * (np.sum(e * e, axis=1) - e_n**2)))
    v = to_voigt(eps, "strain")
    C = I.affine_stiffness(KN, kt, RHO_C, RADIUS, degree=4)
    assert 0.5 * v @ C @ v == pytest.approx(psi, rel=1e-12)


# --- the minimiser itself -----------------------------------------------------------------------------


@pytest.mark.parametrize(("variant", "alpha"), [("published", 1.0), ("consistent", 1.5)])
def test_rigid_rotation_costs_no_energy_and_fixes_omega(variant, alpha):
    spin = np.array([0.3, -0.2, 1.0]) * 1e-3
    W = np.array([[0, -spin[2], spin[1]], [spin[2], 0, -spin[0]], [-spin[1], spin[0], 0]])
    sol = I.minimise_contact_energy(W, KN, 0.5 * KN, RHO_C, RADIUS, variant)
    scale = RHO_C * RADIUS**2 * KN * 1e-3
    assert abs(sol.energy) < 1e-20 * scale
    assert np.abs(sol.sigma).max() < 1e-12 * scale
    # with the sign of Eq. (5.12), omega is minus the particle rotation; consistent: exactly the spin
    np.testing.assert_allclose(sol.omega, -1.5 / alpha * spin, rtol=1e-12)


@pytest.mark.parametrize("variant", ["published", "consistent"])
def test_minimiser_satisfies_constraint_stationarity_and_moment_balance(variant):
    grad_u = random_gradient()
    sol = I.minimise_contact_energy(grad_u, KN, 0.3 * KN, RHO_C, RADIUS, variant, degree=6)
    n, w = sol.directions, sol.weights
    np.testing.assert_allclose(I.constraint_gradient(sol.u, n, w, RADIUS, variant), grad_u, atol=1e-15)
    stress_scale = RHO_C * RADIUS**2 * KN * 1e-3
    # multiplier = Cauchy stress: symmetric, depends on sym(grad u) only, and Psi = 1/2 sigma : grad u
    np.testing.assert_allclose(sol.sigma, sol.sigma.T, atol=1e-13 * stress_scale)
    sym = I.minimise_contact_energy((grad_u + grad_u.T) / 2, KN, 0.3 * KN, RHO_C, RADIUS, variant, degree=6)
    np.testing.assert_allclose(sol.sigma, sym.sigma, atol=1e-13 * stress_scale)
    assert sol.energy == pytest.approx(0.5 * np.sum(sol.sigma * grad_u), rel=1e-12)
    # Eq. (5.15) corrected: <(u x n)> = 4r/3 omega (the seed prints 2r omega, using (w x n) x n = -w)
    u_cross_n = np.einsum("m,mi->i", w, np.cross(sol.u, n))
    np.testing.assert_allclose(u_cross_n, 4 * RADIUS / 3 * sol.omega, rtol=1e-10)
    assert np.linalg.norm(sol.omega) > 1e-6


@pytest.mark.parametrize("variant", ["published", "consistent"])
def test_contact_forces_of_the_minimiser_are_eq_5_24(variant):
    grad_u = random_gradient()
    sol = I.minimise_contact_energy(grad_u, KN, 0.3 * KN, RHO_C, RADIUS, variant, degree=6)
    n = sol.directions
    e = sol.u + 2 * RADIUS * np.cross(sol.omega, n)
    e_n = np.einsum("mi,mi->m", e, n)
    t_n, t_t = KN * e_n[:, None] * n, 0.3 * KN * (e - e_n[:, None] * n)
    t_n_524, t_t_524 = I.contact_forces(sol.sigma, n, RHO_C, RADIUS, variant)
    scale = np.abs(t_n).max()
    np.testing.assert_allclose(t_n, t_n_524, atol=1e-12 * scale)
    np.testing.assert_allclose(t_t, t_t_524, atol=1e-12 * scale)


@pytest.mark.parametrize(("variant", "factor"), [("published", 2 / 3), ("consistent", 1.0)])
def test_love_weber_average_of_eq_5_24_forces(variant, factor):
    sigma = random_gradient(1e6)
    sigma = (sigma + sigma.T) / 2
    n, w = sphere_quadrature(4)
    t_n, t_t = I.contact_forces(sigma, n, RHO_C, RADIUS, variant)
    love_weber = RHO_C * np.einsum("m,mi,mj->ij", w, t_n + t_t, 2 * RADIUS * n)
    np.testing.assert_allclose(love_weber, factor * sigma, atol=1e-9 * np.abs(sigma).max())


def test_finite_random_fabric_converges_and_bad_fabrics_are_refused():
    errors = []
    E, nu = I.elastic_constants(KN, 0.4 * KN, RHO_C, RADIUS)
    for m in (50, 5000):
        d = rng.normal(size=(m, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        d = np.concatenate([d, -d])  # every contact seen from both particles
        num = I.numerical_elastic_constants(KN, 0.4 * KN, RHO_C, RADIUS, directions=d)
        errors.append(abs(num.E / E - 1) + num.anisotropy)
    assert errors[1] < errors[0] and errors[1] < 0.05
    with pytest.raises(ValueError, match="unit vectors"):
        I.numerical_elastic_constants(KN, KN, RHO_C, RADIUS, directions=2 * np.eye(3))
    with pytest.raises(ValueError, match="sum to 1"):
        I.numerical_elastic_constants(KN, KN, RHO_C, RADIUS, directions=np.eye(3), weights=[1, 1, 1])
    with pytest.raises(ValueError, match="weights"):
        I.numerical_elastic_constants(KN, KN, RHO_C, RADIUS, directions=np.eye(3), weights=[1.5, 0, -0.5])


def test_isotropic_part_recovers_an_isotropic_stiffness():
    E, nu, defect = I.isotropic_part(isotropic_stiffness(70e9, 0.23, "voigt"))
    assert (E, nu) == (pytest.approx(70e9, rel=1e-13), pytest.approx(0.23, rel=1e-13))
    assert defect < 1e-14


# --- bonded material, Eq. (5.24)–(5.26) ----------------------------------------------------------------


def test_failure_stresses_eq_5_26_and_inverse():
    sR, sT = I.failure_stresses(100.0, 40.0, 2.0e8, 1.0e-3)
    assert (sR, sT) == (pytest.approx(2.0e7), pytest.approx(8.0e6))
    assert I.bond_strengths(sR, sT, 2.0e8, 1.0e-3) == (pytest.approx(100.0), pytest.approx(40.0))
    sRc, sTc = I.failure_stresses(100.0, 40.0, 2.0e8, 1.0e-3, "consistent")
    assert (sRc, sTc) == (pytest.approx(2 / 3 * sR), pytest.approx(2 / 3 * sT))
    f_n, f_t = I.bond_strengths(sRc, sTc, 2.0e8, 1.0e-3, "consistent")
    assert (f_n, f_t) == (pytest.approx(100.0), pytest.approx(40.0))
    with pytest.raises(ValueError, match="f_t"):
        I.failure_stresses(1.0, 0.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="sigma_rankine"):
        I.bond_strengths(-1.0, 1.0, 1.0, 1.0)


@pytest.mark.parametrize("variant", ["published", "consistent"])
def test_failure_stresses_are_the_critical_principal_and_shear_stress(variant):
    """sigma_y^Rankine = critical max principal stress, sigma_y^Tresca = critical (sigma_1 - sigma_3)/2."""
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    principal = np.array([3.0, 1.0, -2.0]) * 1e6
    sigma = rotation @ np.diag(principal) @ rotation.T
    n, _ = sphere_quadrature(40)
    n = np.concatenate([n, rotation.T[[0]], (rotation.T[[0]] + rotation.T[[2]]) / np.sqrt(2)])
    t_n, t_t = I.contact_forces(sigma, n, RHO_C, RADIUS, variant)
    max_tn = np.max(np.einsum("mi,mi->m", t_n, n))
    max_tt = np.max(np.linalg.norm(t_t, axis=1))
    f_n, f_t = I.bond_strengths(principal[0], (principal[0] - principal[2]) / 2, RHO_C, RADIUS, variant)
    assert max_tn == pytest.approx(f_n, rel=1e-12)
    assert max_tt == pytest.approx(f_t, rel=1e-12)


def test_table_5_3_which_criterion_governs():
    f = 10.0
    tests = {1: (f, f), 2: (100 * f, f), 3: (f, 100 * f)}  # (f_n, f_t)
    governs = {}
    for k, (f_n, f_t) in tests.items():
        sR, sT = I.failure_stresses(f_n, f_t, RHO_C, RADIUS)
        governs[k] = "equal" if np.isclose(sR, sT) else ("Tresca" if sT < sR else "Rankine")
    assert governs == {1: "equal", 2: "Tresca", 3: "Rankine"}


# --- contact stiffness rules, Eq. (4.11)–(4.14) --------------------------------------------------------


@given(st.floats(1e-3, 1e9), st.floats(1e-3, 1e9))
def test_series_stiffness_eq_4_11(k_a, k_b):
    K = I.series_stiffness(k_a, k_b)
    assert 1 / K == pytest.approx(1 / k_a + 1 / k_b, rel=1e-12)
    assert K == pytest.approx(I.series_stiffness(k_b, k_a), rel=1e-15)
    assert K <= min(k_a, k_b)


def test_series_stiffness_equal_particles_and_bad_input():
    assert I.series_stiffness(4.0e7, 4.0e7) == pytest.approx(2.0e7)
    assert I.series_stiffness(1.0, 0.0) == 0.0 and I.series_stiffness(np.inf, 3.0) == 3.0   # no spring; rigid side
    with pytest.raises(ValueError, match="k_b"):
        I.series_stiffness(1.0, -1.0)


@given(G=st.floats(1e6, 1e11), nu=st.floats(-0.5, 0.49), r=st.floats(1e-5, 1e-1), depth=st.floats(1e-6, 1e-2))
@settings(max_examples=50)
def test_hertz_stiffnesses_eq_4_13_4_14_against_hertz_mindlin_theory(G, nu, r, depth):
    overlap = depth * r
    # Hertz for two equal spheres: F = 4/3 E* sqrt(R*) U^(3/2), E* = E / (2 (1 - nu^2)), R* = r/2
    E = 2 * G * (1 + nu)
    E_star, R_star = E / (2 * (1 - nu**2)), r / 2
    force = 4 / 3 * E_star * np.sqrt(R_star) * overlap**1.5
    r_tilde = I.hertz_contact_radius(r, r)
    assert r_tilde == pytest.approx(r)
    assert I.hertz_normal_stiffness(G, nu, r_tilde, overlap) * overlap == pytest.approx(force, rel=1e-12)
    # Mindlin: tangential stiffness 8 G* a with G* = G / (2 (2 - nu)) and contact radius a = sqrt(R* U)
    a = np.sqrt(R_star * overlap)
    kt = 8 * G / (2 * (2 - nu)) * a
    assert I.hertz_shear_stiffness(G, nu, r_tilde, force) == pytest.approx(kt, rel=1e-12)
    assert I.hertz_shear_stiffness(G, nu, r_tilde, -force) == pytest.approx(kt, rel=1e-12)


def test_hertz_contact_radius_and_bad_input():
    assert I.hertz_contact_radius(1.0, 3.0) == pytest.approx(1.5)
    assert I.hertz_contact_radius(2.0) == 2.0  # ball-wall
    assert I.hertz_normal_stiffness(1e9, 0.2, 1e-3, 0.0) == 0.0
    with pytest.raises(ValueError, match="overlap"):
        I.hertz_normal_stiffness(1e9, 0.2, 1e-3, -1e-6)
    with pytest.raises(ValueError, match="poisson"):
        I.hertz_normal_stiffness(1e9, 0.5, 1e-3, 1e-6)
    with pytest.raises(ValueError, match="shear_modulus"):
        I.hertz_shear_stiffness(0.0, 0.2, 1e-3, 1.0)
    with pytest.raises(ValueError, match="normal_force"):
        I.hertz_shear_stiffness(1e9, 0.2, 1e-3, np.nan)
