"""Contact laws of Ch. 4.1.3: Eq. (4.6)–(4.14), slip (4.8), dashpots (4.9, 4.10), contact bonds (Fig. 4.3)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.dem import HertzMindlin, Linear, Particles, force_displacement, series_stiffness
from abrakit.dem.contact_laws import _cross, _dot, _turn_into_plane, hertz_normal_coefficient, hertz_shear_coefficient


def test_series_stiffness_eq_4_11():
    assert series_stiffness(2e6, 2e6) == pytest.approx(1e6)
    assert series_stiffness(1e6, 3e6) == pytest.approx(0.75e6)
    assert series_stiffness(np.inf, 5e5) == pytest.approx(5e5)          # rigid wall
    assert series_stiffness(0.0, 5e5) == 0.0
    assert series_stiffness(0.0, 0.0) == 0.0 and series_stiffness(0.0, np.inf) == 0.0      # no spring: no force
    assert series_stiffness(np.inf, np.inf) == np.inf                                       # rigid on rigid
    np.testing.assert_array_equal(series_stiffness([0.0, 2e6, np.inf], [1e6, 2e6, 3e6]), [0.0, 1e6, 3e6])
    assert series_stiffness(np.zeros(0), np.zeros(0)).shape == (0,)
    for bad in (np.nan, -1.0):
        with pytest.raises(ValueError, match="k_b must lie in"):
            series_stiffness([1e6, 1e6], [1e6, bad])


def test_hertz_eq_4_13_is_textbook_hertz():
    """F = c_n U^{3/2} equals (4/3) E* √R* U^{3/2} with E* = E/(2(1−ν²)) for two spheres of one material."""
    G, nu, rA, rB, U = 30e9, 0.25, 0.004, 0.006, 1e-6
    E = 2 * G * (1 + nu)
    R_star = rA * rB / (rA + rB)
    E_star = E / (2 * (1 - nu**2))
    cn = hertz_normal_coefficient(G, nu, 2 * R_star)
    assert cn * U**1.5 == pytest.approx(4 / 3 * E_star * np.sqrt(R_star) * U**1.5, rel=1e-12)


def test_hertz_eq_4_14_is_mindlin():
    """K^t = c_t |F^n|^{1/3} equals Mindlin's 8 G* a with G* = G/(2(2−ν)), a = √(R* U)."""
    G, nu, R_star, U = 30e9, 0.3, 0.0025, 2e-6
    fn = hertz_normal_coefficient(G, nu, 2 * R_star) * U**1.5
    kt = hertz_shear_coefficient(G, nu, 2 * R_star) * np.cbrt(fn)
    assert kt == pytest.approx(8 * G / (2 * (2 - nu)) * np.sqrt(R_star * U), rel=1e-12)


@pytest.mark.parametrize("law", [Linear(), HertzMindlin()])
def test_normal_force_tangent_and_energy_are_consistent(law):
    """dF/dU returned by the law and d(energy)/dU = F, checked by central differences."""
    p = Particles.spheres([[0, 0, 0], [0.0095, 0, 0]], [0.005, 0.004], kn=[1e6, 3e6])
    prm = law.pair_parameters(p, np.array([0]), np.array([1]))
    U, h = np.array([2e-5]), 1e-9
    f, k = law.normal_force(U, prm)
    df = (law.normal_force(U + h, prm)[0] - law.normal_force(U - h, prm)[0]) / (2 * h)
    de = (law.normal_energy(U + h, prm) - law.normal_energy(U - h, prm)) / (2 * h)
    assert k * np.ones(1) == pytest.approx(df, rel=1e-6)
    assert de == pytest.approx(f, rel=1e-6)
    assert law.normal_force(np.array([-1e-5]), prm)[0] == pytest.approx(0.0)     # no tension


def _one_contact(law=None, **kw):
    p = Particles.spheres([[0, 0, 0], [0.02, 0, 0]], 0.01, kn=1e6, kt=5e5, friction=0.5, **kw)
    law = law or Linear()
    return law, law.pair_parameters(p, np.array([0]), np.array([1]))


def test_incremental_shear_force_eq_4_7_and_slip_eq_4_8():
    law, prm = _one_contact()
    n = np.array([[1.0], [0.0], [0.0]])
    ft = np.zeros((3, 1))
    dt, vt = 1e-5, 0.01
    overlap = np.array([1e-4])                     # F^n = K^n U = 5e5 · 1e-4 = 50 N, μF^n = 25 N
    for step in range(1, 4):
        r = force_displacement(law, prm, overlap, n, np.array([[0.0], [vt], [0.0]]), ft, dt)
        ft = r.ft
        assert ft[1, 0] == pytest.approx(-prm["kt"][0] * vt * dt * step)        # ΔF^t = −K^t V^t Δt
    assert r.fn[0] == pytest.approx(50.0)
    big = force_displacement(law, prm, overlap, n, np.array([[0.0], [1e3], [0.0]]), ft, dt)
    assert np.linalg.norm(big.ft[:, 0]) == pytest.approx(25.0)                # |F^t| = μ F^n
    assert big.sliding[0]


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=9, max_size=9), st.floats(0, 2e-4))
def test_coulomb_limit_never_exceeded(values, overlap):
    law, prm = _one_contact()
    n = np.array(values[:3]).reshape(3, 1)
    if np.linalg.norm(n) < 1e-3:
        return
    n /= np.linalg.norm(n)
    r = force_displacement(law, prm, np.array([overlap]), n, np.array(values[3:6]).reshape(3, 1) * 10,
                           np.array(values[6:]).reshape(3, 1) * 100, 1e-4)
    assert np.linalg.norm(r.ft) <= prm["mu"][0] * r.fn[0] * (1 + 1e-12) + 1e-12
    assert abs(_dot(r.ft, n)[0]) <= 1e-9 * (1 + np.linalg.norm(r.ft))            # shear force in the plane


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-10, 10), min_size=6, max_size=6))
def test_turn_into_plane_keeps_length_and_is_in_plane(values):
    vec = np.array(values[:3]).reshape(3, 1)
    n = np.array(values[3:]).reshape(3, 1)
    if np.linalg.norm(n) < 1e-3 or np.linalg.norm(np.cross(vec[:, 0], n[:, 0])) < 1e-6:
        return
    n /= np.linalg.norm(n)
    out = _turn_into_plane(vec, n)
    assert np.linalg.norm(out) == pytest.approx(np.linalg.norm(vec), rel=1e-9)
    assert abs(_dot(out, n)[0]) <= 1e-9 * np.linalg.norm(vec)


def test_a_spring_nearly_along_the_new_normal_is_turned_into_the_plane_to_round_off():
    """Found by the property test above: spring (0, 4, 0), normal along (2.93e-7, 5, 0). Its in-plane remainder is
    6e-8 of its length; one projection left 2e-9 |vec| along n after the rescaling, two leave round-off."""
    vec = np.array([[0.0], [4.0], [0.0]])
    n = np.array([[2.93e-7], [5.0], [0.0]])
    n /= np.linalg.norm(n)
    out = _turn_into_plane(vec, n)
    assert np.linalg.norm(out) == pytest.approx(4.0, rel=1e-9)
    assert abs(_dot(out, n)[0]) <= 1e-12 * 4.0


def test_cross_matches_numpy():
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(3, 7)), rng.normal(size=(3, 7))
    assert np.allclose(_cross(a, b), np.cross(a.T, b.T).T)


def test_dashpot_is_fraction_of_critical_damping_eq_4_10():
    law, prm = _one_contact(Linear(damping_normal=0.3))
    m_eff = prm["mass"][0]
    assert prm["beta_n"][0] == pytest.approx(0.3 * 2 * np.sqrt(m_eff * prm["kn"][0]))
    n = np.array([[1.0], [0.0], [0.0]])
    r = force_displacement(law, prm, np.array([1e-5]), n, np.array([[-0.2], [0.0], [0.0]]), np.zeros((3, 1)),
                           1e-6)
    # approaching (v_n < 0): the dashpot pushes B away, D = −β v_n (Eq. 4.9)
    assert r.force[0, 0] == pytest.approx(prm["kn"][0] * 1e-5 + prm["beta_n"][0] * 0.2)


def test_contact_bond_carries_tension_then_breaks():
    law, prm = _one_contact()
    n = np.array([[1.0], [0.0], [0.0]])
    args = dict(bonded=np.array([True]), bond_gap=np.array([0.0]), bond_normal_strength=np.array([10.0]),
                bond_shear_strength=np.array([10.0]))
    r = force_displacement(law, prm, np.array([-1e-5]), n, np.zeros((3, 1)), np.zeros((3, 1)), 1e-6, **args)
    assert r.fn[0] == pytest.approx(-prm["kn"][0] * 1e-5)                      # tension K^n U, U < 0
    assert not r.tension_failure[0]
    r = force_displacement(law, prm, np.array([-3e-5]), n, np.zeros((3, 1)), np.zeros((3, 1)), 1e-6, **args)
    assert r.tension_failure[0] and r.fn[0] == 0.0 and np.all(r.force == 0.0)


def test_hertz_is_not_bondable():
    from abrakit.dem import Simulation, install_contact_bonds

    p = Particles.spheres([[0, 0, 0], [0.02, 0, 0]], 0.01)
    sim = Simulation(p, law=HertzMindlin())
    with pytest.raises(ValueError, match="cannot be bonded"):
        install_contact_bonds(sim, 1.0, 1.0)


def test_negative_damping_ratio_rejected():
    with pytest.raises(ValueError, match="damping_normal"):
        Linear(damping_normal=-0.1)


def test_a_spring_along_the_new_normal_is_dropped_not_rescaled_round_off():
    """The example hypothesis found: a tangential spring exactly along the turned normal leaves only round-off
    in the plane; rescaling that to the old length pointed the spring along n. It is dropped instead, and the
    compiled law agrees."""
    n = np.array([0.0, 1.0, 1.0]).reshape(3, 1) / np.sqrt(2.0)
    turned = _turn_into_plane(np.array([0.0, 100.0, 100.0]).reshape(3, 1), n)
    assert np.all(turned == 0.0)
    law, prm = _one_contact()
    r = force_displacement(law, prm, np.array([2e-5]), n, np.zeros((3, 1)), np.array([[0.0], [100.0], [100.0]]),
                           1e-4)
    assert np.all(r.ft == 0.0)
