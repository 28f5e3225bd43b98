"""Tests of the closed-form wear-rate model, Ch. 8.2–8.4 (Eq. 8.5–8.14, Table 8.4)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from abrakit import wear as W

fraction = st.floats(0.0, 1.0)
diameter = st.floats(1e-6, 1e-2)


# --- Eq. (8.5), (8.6) and the regimes ----------------------------------------------------------------------


def test_degree_of_wear_values_and_limits():
    assert W.degree_of_wear(10.0, 4.0) == pytest.approx(0.6, rel=1e-15)
    assert W.degree_of_wear(88.4, 0.0) == 1.0          # ideal micro-cutting: no shoulders
    assert W.degree_of_wear(88.4, 88.4) == 0.0         # ideal micro-plowing: all material in the shoulders
    np.testing.assert_allclose(W.degree_of_wear([10.0, 20.0], [1.0, 15.0]), [0.9, 0.25], rtol=1e-15)


@given(A_g=st.floats(1e-12, 1e3), share=fraction)
def test_degree_of_wear_is_the_removed_share(A_g, share):
    f_ab = W.degree_of_wear(A_g, (1.0 - share) * A_g)
    assert 0.0 <= f_ab <= 1.0
    assert f_ab == pytest.approx(share, abs=1e-12)


def test_degree_of_wear_rejects_bad_areas():
    with pytest.raises(ValueError, match="A_g must lie in"):
        W.degree_of_wear(0.0, 0.0)
    with pytest.raises(ValueError, match="A_g must lie in"):
        W.degree_of_wear(-1.0, 0.0)
    with pytest.raises(ValueError, match="A_s must lie in"):
        W.degree_of_wear(1.0, -0.1)
    with pytest.raises(ValueError, match="A_s must not exceed A_g"):
        W.degree_of_wear(1.0, 1.5)
    with pytest.raises(ValueError, match="A_s must not exceed A_g"):
        W.degree_of_wear([1.0, 2.0], [0.5, 2.5])
    with pytest.raises(ValueError, match="A_s must be finite"):
        W.degree_of_wear(1.0, np.nan)


def test_degree_of_penetration():
    assert W.degree_of_penetration(2.0, 8.0) == 0.5
    # spherical tip of radius R at depth d cuts a groove of width w = 2 sqrt(2 R d - d^2): at d = R, D_p = 1
    R, d = 50.0, np.array([1.0, 2.0, 5.0, 50.0])
    w = 2.0 * np.sqrt(2.0 * R * d - d**2)
    np.testing.assert_allclose(W.degree_of_penetration(d, w), d / np.sqrt(2.0 * R * d - d**2), rtol=1e-15)
    assert W.degree_of_penetration(R, 2.0 * R) == 1.0
    assert W.degree_of_penetration(0.0, 1.0) == 0.0
    with pytest.raises(ValueError, match="w must lie in"):
        W.degree_of_penetration(1.0, 0.0)
    with pytest.raises(ValueError, match="d must lie in"):
        W.degree_of_penetration(-1.0, 1.0)


def test_penetration_regime_follows_hokkirigawa_kato_bands_and_refuses_negative_depths():
    assert W.penetration_regime(0.0) == "plowing"
    assert W.penetration_regime(np.nextafter(0.1, 0.0)) == "plowing"
    assert W.penetration_regime(0.1) == "plowing or wedge"
    assert W.penetration_regime(0.2) == "plowing or wedge"               # the bands meet at 0.2
    assert W.penetration_regime(0.25) == "wedge or cutting"
    assert W.penetration_regime(0.3) == "wedge or cutting"
    assert W.penetration_regime(np.nextafter(0.3, 1.0)) == "cutting"
    assert W.penetration_regime([[0.05, 0.15], [0.25, 0.5]]).tolist() == [["plowing", "plowing or wedge"],
                                                                          ["wedge or cutting", "cutting"]]
    R, d = 50.0, 2.0                                                       # the seed's sphere: D_p = sqrt(d/2R)
    assert W.penetration_regime(W.degree_of_penetration(d, 2 * np.sqrt(2 * R * d - d * d))) == "plowing or wedge"
    with pytest.raises(ValueError, match="D_p"):
        W.penetration_regime(-0.1)


def test_wear_regime_thresholds_and_seed_examples():
    assert W.wear_regime(0.0) == "plowing"
    assert W.wear_regime(np.nextafter(0.2, 0.0)) == "plowing"
    assert W.wear_regime(0.2) == "wedging"      # "between 0.2 and 0.7": ends belong to wedging
    assert W.wear_regime(0.7) == "wedging"
    assert W.wear_regime(np.nextafter(0.7, 1.0)) == "cutting"   # "larger than 0.7"
    assert W.wear_regime(1.0) == "cutting"
    assert W.wear_regime(W.GRAIN_100UM.f_ab) == "wedging"   # seed: "a combination of plowing and wedging"
    assert W.wear_regime(W.GRAIN_200UM.f_ab) == "plowing"   # seed: "pure plastic behavior"
    regimes = W.wear_regime([[0.1, 0.5], [0.9, 0.2]])
    assert regimes.shape == (2, 2)
    assert regimes.tolist() == [["plowing", "wedging"], ["cutting", "wedging"]]
    with pytest.raises(ValueError, match=r"f_ab must lie in \[0, 1\]"):
        W.wear_regime(1.2)


# --- Eq. (8.7)–(8.12) ---------------------------------------------------------------------------------------


def test_contacting_particles_seed_value_and_scaling():
    assert W.contacting_particles(100e-6) == pytest.approx(9e7, rel=1e-12)      # seed, Sec. 8.4
    np.testing.assert_allclose(W.contacting_particles([1e-4, 2e-4, 4e-4]), [9e7, 2.25e7, 5.625e6], rtol=1e-12)
    with pytest.raises(ValueError, match="D must lie in"):
        W.contacting_particles(0.0)
    with pytest.raises(ValueError, match="D must lie in"):
        W.contacting_particles(-1e-4)


def test_mixture_reproduces_the_worked_example():
    N_A, N_B = W.contacting_particles_mixture(200e-6, 100e-6, 0.7)
    assert N_A == pytest.approx(1.32e7, rel=5e-3)     # seed values, printed to three digits
    assert N_B == pytest.approx(4.93e7, rel=5e-3)
    assert N_A == pytest.approx(0.9 * 0.7**1.5 / 200e-6**2, rel=1e-14)
    assert N_B == pytest.approx(0.9 * 0.3**0.5 / 100e-6**2, rel=1e-14)


@given(D_A=diameter, ratio=st.floats(1.0, 20.0))
def test_mixture_limits_reduce_to_eq_8_7(D_A, ratio):
    D_B = D_A / ratio
    N_A, N_B = W.contacting_particles_mixture(D_A, D_B, 1.0)
    assert N_A == pytest.approx(W.contacting_particles(D_A), rel=1e-13) and N_B == 0.0
    N_A, N_B = W.contacting_particles_mixture(D_A, D_B, 0.0)
    assert N_A == 0.0 and N_B == pytest.approx(W.contacting_particles(D_B), rel=1e-13)


@given(D=diameter, theta=fraction)
def test_equal_sizes_reduce_to_the_monodisperse_case(D, theta):
    N_a, N_b = W.contacting_particles_mixture(D, D, theta)
    assert N_a == pytest.approx(theta * W.contacting_particles(D), rel=1e-12, abs=1e-300)
    assert N_a + N_b == pytest.approx(W.contacting_particles(D), rel=1e-12)


@given(D_a=diameter, D_b=diameter, theta=st.integers(0, 1024).map(lambda k: k / 1024))
def test_grain_order_is_swapped_explicitly(D_a, D_b, theta):
    # dyadic fractions so that 1 - (1 - theta) == theta exactly
    forward = W.contacting_particles_mixture(D_a, D_b, theta)
    backward = W.contacting_particles_mixture(D_b, D_a, 1.0 - theta)
    np.testing.assert_allclose(forward, backward[::-1], rtol=1e-12)


def test_swap_follows_eq_8_12_with_the_coarse_grain_as_A():
    # grain a is the fine one: it plays B with theta_B = theta_a, exponent 1/r_AB = 1/4
    N_a, N_b = W.contacting_particles_mixture(50e-6, 200e-6, 0.25)
    assert N_a == pytest.approx(0.9 * 0.25**0.25 / 50e-6**2, rel=1e-14)
    assert N_b == pytest.approx(0.9 * 0.75**1.75 / 200e-6**2, rel=1e-14)


@pytest.mark.parametrize("r_AB", [1.0, 1.5, 2.0, 4.0])
def test_mixture_exponents_by_log_log_slope(r_AB):
    """Independent check of alpha (Eq. 8.11): slope of log N_c,i over log theta_i by central differences."""
    theta, h = 0.4, 1e-6
    N_plus = np.array(W.contacting_particles_mixture(r_AB * 1e-4, 1e-4, theta * (1 + h)))
    N_minus = np.array(W.contacting_particles_mixture(r_AB * 1e-4, 1e-4, theta * (1 - h)))
    slope_A = (np.log(N_plus[0]) - np.log(N_minus[0])) / (np.log1p(h) - np.log1p(-h))
    theta_B_plus, theta_B_minus = 1 - theta * (1 + h), 1 - theta * (1 - h)
    slope_B = (np.log(N_plus[1]) - np.log(N_minus[1])) / (np.log(theta_B_plus) - np.log(theta_B_minus))
    assert slope_A == pytest.approx(2.0 - 1.0 / r_AB, rel=1e-8)
    assert slope_B == pytest.approx(1.0 / r_AB, rel=1e-8)


def test_mixture_is_vectorised_and_validated():
    theta = np.linspace(0, 1, 5)
    N_a, N_b = W.contacting_particles_mixture(200e-6, 100e-6, theta)
    assert N_a.shape == N_b.shape == (5,)
    assert np.all(np.diff(N_a) > 0) and np.all(np.diff(N_b) < 0)
    with pytest.raises(ValueError, match=r"theta_a must lie in \[0, 1\]"):
        W.contacting_particles_mixture(200e-6, 100e-6, 1.1)
    with pytest.raises(ValueError, match=r"theta_a must lie in \[0, 1\]"):
        W.contacting_particles_mixture(200e-6, 100e-6, -0.1)
    with pytest.raises(ValueError, match="D_a must lie in"):
        W.contacting_particles_mixture(-200e-6, 100e-6, 0.5)
    with pytest.raises(ValueError, match="D_b must lie in"):
        W.contacting_particles_mixture(200e-6, 0.0, 0.5)
    with pytest.raises(ValueError, match="shapes do not broadcast"):
        W.contacting_particles_mixture([1e-4, 2e-4], 1e-4, [0.1, 0.2, 0.3])


# --- Eq. (8.13), (8.14) -------------------------------------------------------------------------------------


def test_particle_wear_rate_is_eq_8_13():
    assert W.particle_wear_rate(0.37, 88.4e-12, 2.0) == pytest.approx(0.37 * 88.4e-12 * 2.0, rel=1e-15)
    assert W.particle_wear_rate(0.5, 1e-12, 0.0) == 0.0
    with pytest.raises(ValueError, match="f_ab must lie in"):
        W.particle_wear_rate(1.5, 1e-12, 1.0)
    with pytest.raises(ValueError, match="A_g must lie in"):
        W.particle_wear_rate(0.5, -1e-12, 1.0)
    with pytest.raises(ValueError, match="v_t must lie in"):
        W.particle_wear_rate(0.5, 1e-12, -1.0)


def test_wear_rate_sums_over_grain_types_and_scales_by_area():
    N_c, f_ab, A_g, v_t = [1e7, 5e7], [0.12, 0.37], [60e-12, 88.4e-12], 2.0
    expected = (1e7 * 0.12 * 60e-12 + 5e7 * 0.37 * 88.4e-12) * 2.0
    assert W.wear_rate(N_c, f_ab, A_g, v_t) == pytest.approx(expected, rel=1e-14)
    assert W.wear_rate(N_c, f_ab, A_g, v_t, area=1e-4) == pytest.approx(1e-4 * expected, rel=1e-14)
    # one grain type given as scalars
    assert W.wear_rate(9e7, 0.37, 88.4e-12, 2.0) == pytest.approx(9e7 * 0.37 * 88.4e-12 * 2.0, rel=1e-14)
    # batch axis in front of the grain-type axis
    batch = W.wear_rate(np.array([[1e7, 5e7], [2e7, 0.0]]), f_ab, A_g, v_t)
    assert batch.shape == (2,)
    assert batch[1] == pytest.approx(2e7 * 0.12 * 60e-12 * 2.0, rel=1e-14)
    with pytest.raises(ValueError, match="N_c must lie in"):
        W.wear_rate([-1.0, 1.0], f_ab, A_g, v_t)
    with pytest.raises(ValueError, match="area must lie in"):
        W.wear_rate(N_c, f_ab, A_g, v_t, area=0.0)
    with pytest.raises(ValueError, match="shapes do not broadcast"):
        W.wear_rate([1.0, 2.0, 3.0], f_ab, A_g, v_t)


@given(theta=fraction)
def test_mixture_wear_rate_matches_hand_composition(theta):
    fine, coarse, v_t = W.GRAIN_100UM, W.GRAIN_200UM, 2.5
    N_c, N_f = W.contacting_particles_mixture(coarse.D, fine.D, theta)
    expected = (N_c * coarse.f_ab * coarse.A_g + N_f * fine.f_ab * fine.A_g) * v_t
    assert W.mixture_wear_rate(theta, coarse, fine, v_t) == pytest.approx(expected, rel=1e-13, abs=1e-300)
    # grain order does not matter
    assert W.mixture_wear_rate(1 - theta, fine, coarse, v_t) == pytest.approx(expected, rel=1e-12, abs=1e-300)


def test_grain_validates_its_fields():
    with pytest.raises(ValueError, match="f_ab must lie in"):
        W.Grain(D=1e-4, A_g=1e-12, f_ab=-0.1)
    with pytest.raises(ValueError, match="D must lie in"):
        W.Grain(D=0.0, A_g=1e-12, f_ab=0.1)


# --- ASTM G65 and Table 8.4 ---------------------------------------------------------------------------------


def test_wheel_surface_speed():
    assert W.wheel_surface_speed(200, 0.2285) == pytest.approx(math.pi * 0.2285 * 200 / 60, rel=1e-15)
    assert W.wheel_surface_speed(200, 0.2285) == pytest.approx(2.3928, abs=1e-4)
    assert W.wheel_surface_speed(60, 1 / math.pi) == pytest.approx(1.0, rel=1e-15)   # one circumference / s
    assert W.ASTM_G65.wheel_speed == W.wheel_surface_speed(200, 0.2285)
    assert W.ASTM_G65.specimen_area == pytest.approx(18e-3 * 12.7e-3, rel=1e-15)
    with pytest.raises(ValueError, match="diameter must lie in"):
        W.wheel_surface_speed(200, -0.2)
    with pytest.raises(ValueError, match="rpm must lie in"):
        W.wheel_surface_speed(-1, 0.2)


def _table_by_hand(area):
    """Independent implementation of Table 8.4 with the math module, one row at a time."""
    v_t = math.pi * 0.2285 * 200 / 60
    rows = []
    for theta_200 in (0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0):
        N_200 = 0.9 * theta_200 ** (2 - 1 / 2) / (200e-6) ** 2
        N_100 = 0.9 * (1 - theta_200) ** (1 / 2) / (100e-6) ** 2
        rows.append(area * v_t * (N_200 * 0.12 * 60e-12 + N_100 * 0.37 * 88.4e-12))
    return rows


def test_table_8_4_every_row_within_one_percent_and_to_the_printed_digits():
    table = W.astm_g65_table()
    seed = np.array([8.07, 7.67, 6.83, 5.87, 4.68, 2.93, 0.44]) * 1e-7
    np.testing.assert_allclose(table["seed"], seed, rtol=1e-15)
    np.testing.assert_array_equal(table["theta_coarse"], [0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0])
    assert np.all(np.abs(table["deviation"]) < 0.01)                       # acceptance criterion
    np.testing.assert_allclose(np.round(table["ours"] * 1e7, 2), seed * 1e7, rtol=1e-15)   # printed digits
    np.testing.assert_allclose(table["ours"], _table_by_hand(W.G65_CONTACT_AREA), rtol=1e-13)
    assert np.all(np.diff(table["ours"]) < 0)       # more coarse grains, less wear
    # the worked examples of Sec. 8.4
    assert table["ours"][0] * 1e7 == pytest.approx(8.07, abs=0.005)
    assert table["ours"][4] * 1e7 == pytest.approx(4.68, abs=0.005)


def test_scaling_area_is_derived_from_the_table():
    table = W.astm_g65_table(area=1.0)          # per-area rates
    fit = W.fit_scaling_area(table["per_area"], table["seed"])
    assert fit.consistent
    assert fit.low == pytest.approx(114.600e-6, abs=1e-9)
    assert fit.high == pytest.approx(114.639e-6, abs=1e-9)
    assert fit.low <= W.G65_CONTACT_AREA <= fit.high
    assert W.G65_CONTACT_AREA == pytest.approx(fit.midpoint, abs=0.01e-6)
    assert fit.least_squares == pytest.approx(114.44e-6, rel=1e-4)
    # physical reading: half the specimen face, to 0.3 %; with exactly half the face all rows stay within 1 %
    half_face = W.ASTM_G65.specimen_area / 2
    assert W.G65_CONTACT_AREA / half_face - 1 == pytest.approx(0.0028, abs=1e-4)
    assert np.all(np.abs(W.astm_g65_table(area=half_face)["deviation"]) < 0.0071)


def test_fit_scaling_area_recovers_a_known_area_and_flags_inconsistent_data():
    q = np.array([3.0, 2.0, 0.5])
    fit = W.fit_scaling_area(q, 7.0 * q, resolution=1e-9)
    assert fit.least_squares == pytest.approx(7.0, rel=1e-14)
    assert fit.consistent and fit.low <= 7.0 <= fit.high
    bad = W.fit_scaling_area(q, 7.0 * q * np.array([1.0, 1.0, 1.2]), resolution=0.01)   # a "misprint"
    assert not bad.consistent
    with pytest.raises(ValueError, match="printed_rate must lie in"):
        W.fit_scaling_area(q, -q)
