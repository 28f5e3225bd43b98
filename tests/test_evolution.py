"""Tests of abrakit.evolution: dissipation potentials, closed-form and variational updates, Δt convergence."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

from abrakit import evolution as ev

PLAST = ev.Plasticity1D(E=200_000.0, K=8_000.0)  # MPa, Table 7.1 (E, K_H)
DAMAGE = ev.Damage1D(E=200_000.0)
DAMAGE_Q = ev.Damage1D(E=200_000.0, damage_function="quadratic")
VISCO_PLAST = ev.elasto_viscoplastic(60.0, 10_000.0)  # r1 [MPa], r2 [MPa s]
VISCO_DAMAGE = ev.elasto_viscoplastic(0.05, 0.05)  # r_d = 0.05 MPa (Table 7.1)

finite = st.floats(-1e3, 1e3, allow_nan=False)
positive = st.floats(1e-2, 1e2)


def pmdp_rate(diss, p):
    """Independent PMDP: the rate minimising D(λ̇) - p λ̇ (Eqs. 2.104, 2.106), by bounded Brent search."""
    bound = 10 * (abs(p) + diss.r1 + 1) / diss.r2
    res = minimize_scalar(lambda x: diss.value(x) - p * x, bounds=(-bound, bound), method="bounded",
                          options={"xatol": 1e-12})
    return res.x


def cyclic(amp, t):
    return amp * np.sin(2 * np.pi * t)


# ------------------------------------------------------------------ potentials, Eqs. (2.78)-(2.80)


def test_potentials_have_the_published_values():
    x = np.array([-2.0, 0.0, 0.5])
    np.testing.assert_allclose(ev.rate_independent(3.0).value(x), 3.0 * np.abs(x))  # Eq. 2.78
    np.testing.assert_allclose(ev.rate_dependent(4.0).value(x), 2.0 * x**2)  # Eq. 2.79
    np.testing.assert_allclose(ev.elasto_viscoplastic(3.0, 4.0).value(x), 3 * np.abs(x) + 2 * x**2)  # Eq. 2.80
    assert ev.rate_independent(3.0).is_rate_independent
    assert not ev.rate_dependent(4.0).is_rate_independent


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: ev.Dissipation(r1=-1.0), "r1"),
        (lambda: ev.rate_independent(-0.1), "r1"),
        (lambda: ev.elasto_viscoplastic(-1.0, 1.0), "r1"),
        (lambda: ev.rate_dependent(0.0), "r2"),
        (lambda: ev.rate_dependent(-2.0), "r2"),
        (lambda: ev.elasto_viscoplastic(1.0, 0.0), "r2"),
        (lambda: ev.Dissipation(r2=-1.0), "r2"),
        (lambda: ev.rate_dependent_update(0.0, 1.0, 0.0, VISCO_DAMAGE), "dt"),
        (lambda: ev.rate_dependent_update(0.0, 1.0, -1.0, VISCO_DAMAGE), "dt"),
        (lambda: ev.variational_update(lambda e, l: l**2, VISCO_DAMAGE, 0.0, 0.0, 0.0), "dt"),
        (lambda: PLAST.update(PLAST.initial_state(), 0.0, 1e-3, -1.0, VISCO_PLAST), "dt"),
        (lambda: PLAST.update(PLAST.initial_state(), 0.0, 1e-3, 0.1, VISCO_PLAST, "forward"), "scheme"),
        (lambda: ev.Plasticity1D(E=0.0), "E"),
        (lambda: ev.Plasticity1D(E=1.0, K=-1.0), "K"),
        (lambda: ev.Damage1D(E=1.0, damage_function="linear"), "damage_function"),
        (lambda: ev.variational_update(lambda e, l: l**2, VISCO_DAMAGE, 0.0, 0.0, 1.0, on_nonconvex="x"),
         "on_nonconvex"),
        (lambda: ev.simulate(PLAST, [0.0, 1e-3], [0.0, 0.0], VISCO_PLAST), "time"),
    ],
)
def test_invalid_parameters_raise_naming_the_parameter(make, name):
    with pytest.raises(ValueError, match=name):
        make()


@given(r1=positive, r2=positive, x=finite)
def test_subdifferential_is_the_derivative_away_from_zero(r1, r2, x):
    diss = ev.Dissipation(r1, r2)
    lower, upper = diss.subdifferential(x)
    if x == 0:
        assert (lower, upper) == (-r1, r1)
    else:
        assert lower == upper == pytest.approx(r1 * np.sign(x) + r2 * x)
        h = 1e-6 * max(abs(x), 1.0)
        if abs(x) > 2 * h:  # central difference on the smooth side
            fd = (diss.value(x + h) - diss.value(x - h)) / (2 * h)
            assert diss.derivative(x) == pytest.approx(fd, rel=1e-6, abs=1e-6)


# ------------------------------------------------------------------ conjugate and yield function, Eqs. (2.106)-(2.108)


@pytest.mark.parametrize("diss", [ev.rate_dependent(2.0), ev.elasto_viscoplastic(1.5, 0.5)])
def test_conjugate_equals_a_numerical_supremum(diss):
    for p in np.linspace(-5.0, 5.0, 23):
        res = minimize_scalar(lambda x, p=p: diss.value(x) - p * x, bounds=(-100, 100), method="bounded",
                              options={"xatol": 1e-12})
        grid = np.linspace(-30, 30, 600_001)
        assert diss.conjugate(p) == pytest.approx(-res.fun, abs=1e-10)
        assert diss.conjugate(p) == pytest.approx(np.max(p * grid - diss.value(grid)), abs=1e-8)


def test_rate_independent_conjugate_is_the_indicator_of_the_elastic_domain():
    diss = ev.rate_independent(2.0)
    for p in (-2.0, -0.3, 0.0, 1.99, 2.0):
        assert diss.conjugate(p) == 0.0
        assert max(np.max(p * x - diss.value(x)) for x in (np.linspace(-L, L, 1001) for L in (1, 1e3))) <= 1e-12
    for p in (-2.5, 3.0):
        assert diss.conjugate(p) == np.inf
        sups = [np.max(p * x - diss.value(x)) for x in (np.linspace(-L, L, 1001) for L in (1.0, 1e3))]
        assert sups[1] == pytest.approx(1e3 * sups[0])  # grows with the interval: unbounded


@settings(max_examples=200)
@given(r1=st.floats(0, 1e2), r2=positive, x=finite, p=finite)
def test_fenchel_young_with_equality_at_the_evolution_law(r1, r2, x, p):
    diss = ev.Dissipation(r1, r2)
    assert diss.value(x) + diss.conjugate(p) >= p * x - 1e-9 * (1 + abs(p * x))
    rate = diss.rate(p)  # Eq. 2.111 is the maximiser of Eq. 2.106 ...
    assert diss.value(rate) + diss.conjugate(p) == pytest.approx(p * rate, rel=1e-9, abs=1e-9)
    lower, upper = diss.subdifferential(rate)  # ... i.e. Biot's equation (2.101): p ∈ ∂D(λ̇)
    assert lower - 1e-9 * (1 + abs(p)) <= p <= upper + 1e-9 * (1 + abs(p))


@given(r1=st.floats(0, 10), r2=positive, p=st.floats(-20, 20))
def test_rate_is_the_derivative_of_the_conjugate(r1, r2, p):
    diss = ev.Dissipation(r1, r2)
    h = 1e-6
    assume(abs(abs(p) - r1) > 2 * h)  # D* has a kink in its second derivative at |p| = r1
    fd = (diss.conjugate(p + h) - diss.conjugate(p - h)) / (2 * h)
    assert diss.rate(p) == pytest.approx(fd, rel=1e-5, abs=1e-5)


def test_rate_law_matches_an_independent_pmdp_minimisation():
    diss = ev.elasto_viscoplastic(1.0, 0.25)
    for p in (-3.0, -1.2, -0.5, 0.0, 0.9, 1.0, 1.7, 4.0):
        assert diss.rate(p) == pytest.approx(pmdp_rate(diss, p), abs=1e-6)
    assert diss.rate(3.0) == pytest.approx((3.0 - 1.0) / 0.25)  # Eq. 2.111


def test_rate_independent_rate_is_set_valued_and_refused():
    with pytest.raises(ValueError, match="r2 must be > 0"):
        ev.rate_independent(1.0).rate(2.0)
    with pytest.raises(ValueError, match="r2 must be > 0"):
        PLAST.state_rate(1e-3, PLAST.initial_state(), ev.rate_independent(60.0))


@given(r1=st.floats(0, 1e2), p=finite)
def test_yield_functions_2107_and_2108_agree_in_sign(r1, p):
    diss = ev.rate_independent(r1)
    phi, phi_sq = diss.yield_function(p), diss.yield_function(p, squared=True)
    assert phi == abs(p) - r1
    assert np.sign(phi) == np.sign(phi_sq) or abs(phi) < 1e-12 * (1 + r1)
    assert (diss.conjugate(p) == 0.0) == (phi <= 0)  # Eq. 2.106: D* is the indicator of Φ ≤ 0


# ------------------------------------------------------------------ misprint decisions, Eqs. (2.112) and (4.53)


def printed_2112(lam_m, p, dt, r1, r2):
    return lam_m + np.where(np.abs(p) > r2, dt / r2 * (np.abs(p) - r1), 0.0)


def printed_453(lam_m, p, dt, r1, r2):
    return lam_m + dt / r2 * p - r1


def test_eq_2112_switches_on_r1_not_r2():
    dt = 0.1
    # r1 < |p| < r2: the printed switch freezes λ although the PMDP (2.104) makes it evolve
    diss = ev.elasto_viscoplastic(1.0, 5.0)
    ours = ev.rate_dependent_update(0.0, 3.0, dt, diss)
    assert ours == pytest.approx(dt * pmdp_rate(diss, 3.0), abs=1e-9)
    assert ours == pytest.approx(dt / 5.0 * (3.0 - 1.0))
    assert printed_2112(0.0, 3.0, dt, 1.0, 5.0) == 0.0 != ours
    # r2 < |p| < r1: the printed switch lets λ decrease (negative dissipation) inside the elastic domain
    diss = ev.elasto_viscoplastic(5.0, 1.0)
    assert ev.rate_dependent_update(0.0, 3.0, dt, diss) == 0.0 == pytest.approx(dt * pmdp_rate(diss, 3.0))
    assert printed_2112(0.0, 3.0, dt, 5.0, 1.0) < 0.0


@given(p=st.floats(0, 10), lam_m=st.floats(0, 5), r1=st.floats(0.01, 5), r2=positive, dt=st.floats(1e-3, 1))
def test_eq_453_reads_with_the_bracket(p, lam_m, r1, r2, dt):
    ours = ev.rate_dependent_update(lam_m, p, dt, ev.elasto_viscoplastic(r1, r2))
    assert ours == pytest.approx(lam_m + dt / r2 * max(p - r1, 0.0))
    assert ours >= lam_m  # the dissipation r1|Δλ| + ... is never negative
    if p <= r1:
        assert ours == lam_m


def test_eq_453_as_printed_moves_lambda_without_driving_force():
    diss = ev.elasto_viscoplastic(0.05, 0.5)
    assert ev.rate_dependent_update(0.3, 0.0, 0.1, diss) == 0.3
    assert printed_453(0.3, 0.0, 0.1, 0.05, 0.5) == pytest.approx(0.25)  # damage would heal at p = 0
    assert ev.rate_dependent_update(0.3, 0.55, 0.1, diss) == pytest.approx(0.3 + 0.1 / 0.5 * 0.5)
    assert printed_453(0.3, 0.55, 0.1, 0.05, 0.5) == pytest.approx(0.3 + 0.1 / 0.5 * 0.55 - 0.05)


# ------------------------------------------------------------------ the 1D models


@pytest.mark.parametrize("model", [DAMAGE, DAMAGE_Q, PLAST])
def test_stress_and_driving_force_are_derivatives_of_psi(model):
    rng = np.random.default_rng(1)
    eps = rng.uniform(-2e-3, 2e-3, 5)
    if isinstance(model, ev.Damage1D):
        state = ev.DamageState(rng.uniform(0.0, 0.8, 5))
        shift = ev.DamageState
        h = 1e-6
        dpsi = (model.free_energy(eps, shift(state.d + h)) - model.free_energy(eps, shift(state.d - h))) / (2 * h)
    else:
        state = ev.PlasticState(rng.uniform(-1e-3, 1e-3, 5), rng.uniform(0, 1e-3, 5))
        h = 1e-9
        up = model.free_energy(eps, ev.PlasticState(state.eps_p + h, state.alpha))
        dn = model.free_energy(eps, ev.PlasticState(state.eps_p - h, state.alpha))
        dpsi = (up - dn) / (2 * h)
    np.testing.assert_allclose(model.driving_force(eps, state), -dpsi, rtol=1e-6)  # Eq. 2.76
    he = 1e-9
    dsig = (model.free_energy(eps + he, state) - model.free_energy(eps - he, state)) / (2 * he)
    np.testing.assert_allclose(model.stress(eps, state), dsig, rtol=1e-6)  # Eq. 2.72


@pytest.mark.parametrize("model", [DAMAGE, DAMAGE_Q])
@pytest.mark.parametrize("r2", [1e-3, 0.05, 10.0])
def test_damage_backward_step_solves_its_implicit_equation(model, r2):
    diss, dt = ev.elasto_viscoplastic(0.05, r2), 0.1
    eps = np.linspace(0.0, 3e-3, 13)
    state_m = ev.DamageState(np.full(13, 0.2))
    new = model.backward_step(eps, state_m, dt, diss)
    residual = new.d - (state_m.d + dt / r2 * np.maximum(model.driving_force(eps, new) - 0.05, 0.0))
    np.testing.assert_allclose(residual, 0.0, atol=1e-12)
    assert np.all(new.d >= state_m.d)


@pytest.mark.parametrize("r2", [0.0, 10.0, 1e4])
def test_plasticity_backward_step_solves_its_implicit_equation(r2):
    diss, dt = ev.Dissipation(60.0, r2), 0.05
    eps = np.linspace(-3e-3, 3e-3, 13)
    state_m = ev.PlasticState(np.full(13, 2e-4), np.full(13, 3e-4))
    new = PLAST.backward_step(eps, state_m, dt, diss)
    step = new.alpha - state_m.alpha
    phi_new = PLAST.yield_function(eps, new, diss)
    np.testing.assert_allclose(r2 / dt * step, np.where(step > 0, phi_new, 0.0), atol=1e-9)  # Eq. 2.111
    np.testing.assert_allclose(new.eps_p - state_m.eps_p, np.sign(PLAST.stress(eps, new)) * step, atol=1e-15)


def kuhn_tucker(model, diss, amp, n=97):
    time = np.linspace(0, 1, n)
    strain = cyclic(amp, time) * (0.5 + time)
    hist = ev.simulate(model, strain, time, diss, "implicit")
    fields = type(model.initial_state())
    for m in range(n - 1):
        old = fields(*(hist[f][m] for f in fields._fields))
        new = fields(*(hist[f][m + 1] for f in fields._fields))
        rho = model.consistency_parameter(strain[m + 1], old, new)
        phi = model.yield_function(strain[m + 1], new, diss)
        yield rho, phi, old, new, strain[m + 1]


@pytest.mark.parametrize(("model", "r1", "amp"), [(DAMAGE, 0.05, 2e-3), (DAMAGE_Q, 0.05, 2e-3), (PLAST, 60.0, 3e-3)])
def test_rate_independent_update_meets_kuhn_tucker(model, r1, amp):
    diss = ev.rate_independent(r1)
    active = 0
    for rho, phi, old, new, eps in kuhn_tucker(model, diss, amp):
        threshold = r1 if isinstance(model, ev.Damage1D) else r1 + model.K * new.alpha
        assert rho >= 0 and phi <= 1e-10 * threshold  # Eq. 2.110
        assert abs(rho * phi) <= 1e-12
        if rho > 0:
            active += 1
            assert phi == pytest.approx(0.0, abs=1e-10 * threshold)
            assert rho == pytest.approx(abs(new[0] - old[0]) / threshold, rel=1e-9)  # Δρ = |Δλ|/r1 (2.105)
            p_new = model.driving_force(eps, new)
            assert new[0] - old[0] == pytest.approx(rho * p_new, rel=1e-9)  # Eq. 2.109
    assert active > 10


def test_rate_independent_updates_are_exact():
    time = np.linspace(0, 1, 41)
    strain = cyclic(2e-3, time)
    hist = ev.simulate(DAMAGE, strain, time, ev.rate_independent(0.05), "implicit")
    exact = np.maximum.accumulate(np.maximum(np.log(0.5 * 2e5 * strain**2 / 0.05, where=strain != 0,
                                                    out=np.full(41, -np.inf)), 0.0))
    np.testing.assert_allclose(hist["d"], exact, atol=1e-13)
    eps = np.linspace(0, 4e-3, 9)  # monotonic plasticity: σ = r1 + K εp and σ = E (ε - εp)
    hist = ev.simulate(PLAST, eps, np.linspace(0, 1, 9), ev.rate_independent(60.0), "implicit")
    exact_p = np.maximum(200_000.0 * eps - 60.0, 0.0) / (200_000.0 + 8_000.0)
    np.testing.assert_allclose(hist["eps_p"], exact_p, atol=1e-15)


def test_rate_independent_explicit_lags_by_one_step():
    time = np.linspace(0, 1, 41)
    strain = 2e-3 * time
    diss = ev.rate_independent(60.0)
    implicit = ev.simulate(PLAST, strain, time, diss, "implicit")["eps_p"]
    explicit = ev.simulate(PLAST, strain, time, diss, "explicit")["eps_p"]
    np.testing.assert_allclose(explicit[1:], implicit[:-1], atol=1e-16)  # consistency at ε^m
    np.testing.assert_allclose(ev.simulate(PLAST, strain, time, diss, "split")["eps_p"], implicit, atol=1e-16)


def test_damage_never_heals_and_updates_are_pure():
    state = ev.DamageState(np.array([0.3, 0.3]))
    before = state.d.copy()
    new = DAMAGE.update(state, np.array([2e-3, 2e-3]), np.array([0.0, 1e-4]), 0.1, VISCO_DAMAGE, "implicit")
    np.testing.assert_array_equal(new.d, before)  # unloading: p < r1, no change, and no healing
    np.testing.assert_array_equal(state.d, before)  # the old state is untouched


def test_quadratic_damage_forward_step_refuses_to_leave_the_admissible_range():
    with pytest.raises(RuntimeError, match="reduce dt"):
        DAMAGE_Q.forward_step(5e-3, ev.DamageState(np.array(0.9)), 10.0, VISCO_DAMAGE)


def test_rate_independent_damage_needs_a_threshold():
    with pytest.raises(ValueError, match="r1 must be > 0"):
        DAMAGE.backward_step(1e-3, DAMAGE.initial_state(), 0.1, ev.rate_independent(0.0))


# ------------------------------------------------------------------ closed form vs numerical variational update


@pytest.mark.parametrize(
    ("model", "diss", "amp"),
    [
        (DAMAGE, VISCO_DAMAGE, 2e-3),
        (DAMAGE, ev.rate_independent(0.05), 2e-3),
        (DAMAGE, ev.rate_dependent(0.05), 2e-3),
        (DAMAGE_Q, VISCO_DAMAGE, 2e-3),
        (DAMAGE_Q, ev.rate_independent(0.05), 2e-3),
        (PLAST, VISCO_PLAST, 3e-3),
        (PLAST, ev.rate_independent(60.0), 3e-3),
        (ev.Plasticity1D(E=200_000.0), ev.rate_dependent(500.0), 3e-3),
    ],
)
def test_closed_form_and_numerical_variational_update_agree(model, diss, amp):
    time = np.linspace(0, 1, 49)
    strain = np.stack([cyclic(amp, time) * (0.5 + time), -cyclic(0.7 * amp, time)], axis=1)  # 2 points
    closed = ev.simulate(model, strain, time, diss, "implicit")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the incremental potentials are convex: no warning
        numeric = ev.simulate(model, strain, time, diss, "variational")
    for name in model.initial_state()._fields:
        scale = max(np.max(np.abs(closed[name])), 1e-300)
        np.testing.assert_allclose(numeric[name], closed[name], rtol=0, atol=1e-8 * scale)
        assert np.max(np.abs(closed[name])) > 0  # something did evolve


def test_variational_update_is_vectorised_and_respects_bounds():
    eps = np.array([[0.0, 1e-3], [2e-3, 5e-3]])
    d = ev.variational_update(lambda e, d: (1 - d) ** 2 * 1e5 * e**2, ev.rate_independent(0.05), eps,
                              0.0, 1.0, bounds=(0.0, 1.0))
    assert d.shape == (2, 2)
    expected = DAMAGE_Q.backward_step(eps, ev.DamageState(np.zeros((2, 2))), 1.0, ev.rate_independent(0.05)).d
    np.testing.assert_allclose(d, expected, atol=1e-9)
    assert np.all((d >= 0) & (d <= 1))


def test_variational_update_accepts_a_free_energy_that_is_not_vectorised():
    def psi(eps, d):
        return math.exp(-d) * 0.5 * 200_000.0 * eps**2  # math.exp refuses arrays

    d = ev.variational_update(psi, VISCO_DAMAGE, 2e-3, 0.1, 0.1, bounds=(0.0, np.inf))
    expected = DAMAGE.backward_step(2e-3, ev.DamageState(np.array(0.1)), 0.1, VISCO_DAMAGE).d
    assert d == pytest.approx(expected, abs=1e-9)


def tilted_double_well(eps, lam):
    return (lam**2 - 1.0) ** 2 - eps * lam


def test_variational_update_finds_the_global_minimum_of_a_nonconvex_potential_and_warns():
    diss, dt = ev.elasto_viscoplastic(0.1, 0.01), 1.0
    lam = np.linspace(-3, 3, 3_000_001)
    brute = lam[np.argmin(tilted_double_well(0.5, lam) + dt * diss.value((lam + 1.0) / dt))]
    assert brute > 0  # the global minimum is in the far well, across a barrier from λ_m = -1
    for width in (0.1, 1.0, 3.0):  # a narrow start finds the far well by probing
        with pytest.warns(ev.NonConvexWarning, match="non-convex: 2 local minima"):
            result = ev.variational_update(tilted_double_well, diss, 0.5, -1.0, dt, width=width)
        assert result == pytest.approx(brute, abs=2e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # near well global for a negative tilt: no lower value, no warning
        assert ev.variational_update(tilted_double_well, diss, -0.5, -1.0, dt, width=0.5) < 0
    with pytest.raises(RuntimeError, match="non-convex"):
        ev.variational_update(tilted_double_well, diss, 0.5, -1.0, dt, on_nonconvex="raise")


def test_variational_update_refuses_an_unbounded_potential():
    with pytest.raises(RuntimeError, match="bounded below"):
        ev.variational_update(lambda e, lam: -(lam**3), ev.rate_dependent(1.0), 0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="non-finite"):
        with np.errstate(invalid="ignore", divide="ignore"):
            ev.variational_update(lambda e, lam: np.log(lam), ev.rate_dependent(1.0), 0.0, 0.5, 1.0)


# ------------------------------------------------------------------ limits and convergence


@pytest.mark.parametrize(("model", "r1", "eps"), [(DAMAGE, 0.05, 2e-3), (DAMAGE_Q, 0.05, 2e-3), (PLAST, 60.0, 3e-3)])
def test_rate_dependent_update_tends_to_the_rate_independent_one(model, r1, eps):
    state_m, dt = model.initial_state(), 0.01
    ri = model.backward_step(eps, state_m, dt, ev.rate_independent(r1))[0]
    gaps = []
    for r2 in 10.0 ** -np.arange(2, 13, 2):
        rd = model.backward_step(eps, state_m, dt, ev.elasto_viscoplastic(r1, r2))[0]
        assert np.isfinite(rd) and rd <= ri + 1e-15
        gaps.append(ri - rd)
    gaps = np.array(gaps)
    assert gaps[-1] < 1e-8 * abs(ri)  # the gap is ≈ (r2/Δt) Δλ / |∂p/∂λ|
    ratio = gaps[3:5] / gaps[2:4]  # once r2/Δt << |∂p/∂λ|: linear in r2, 100x smaller per two decades
    np.testing.assert_allclose(ratio, 1e-2, rtol=0.1)


def test_rate_dependent_path_tends_to_the_rate_independent_path():
    time = np.linspace(0, 1, 65)
    strain = cyclic(3e-3, time)
    ri = ev.simulate(PLAST, strain, time, ev.rate_independent(60.0))["stress"]
    gaps = [np.max(np.abs(ev.simulate(PLAST, strain, time, ev.elasto_viscoplastic(60.0, r2))["stress"] - ri))
            for r2 in (1e3, 1e1, 1e-1)]
    assert gaps[0] > 1.0  # MPa: a visible viscous overstress at r2 = 1000 MPa s
    np.testing.assert_allclose([gaps[1] / gaps[0], gaps[2] / gaps[1]], 1e-2, rtol=0.2)  # linear in r2


def test_observed_order_of_synthetic_data():
    dt = np.array([0.1, 0.05, 0.025, 0.0125])
    assert ev.observed_order(dt, 3 * dt**2) == pytest.approx(2.0)


@pytest.mark.parametrize(("model", "diss", "amp"), [(PLAST, VISCO_PLAST, 2e-3), (DAMAGE, VISCO_DAMAGE, 1.5e-3)])
def test_all_time_discretisations_converge_with_first_order(model, diss, amp):
    study = ev.convergence_study(model, diss, lambda t: cyclic(amp, t), 1.0, n_steps=(64, 128, 256))
    for scheme, order in study["orders"].items():
        assert 0.9 < order < 1.1, (scheme, order)
        assert np.all(np.diff(study[scheme]["error"]) < 0)
    np.testing.assert_allclose(study["variational"]["error"], study["implicit"]["error"], rtol=1e-6)


def test_reference_solution_is_converged_and_refuses_rate_independence():
    time = np.linspace(0, 1, 33)
    f = lambda t: cyclic(1.5e-3, t)
    fine = ev.reference_solution(DAMAGE, f, time, VISCO_DAMAGE)["d"]
    coarse = ev.reference_solution(DAMAGE, f, time, VISCO_DAMAGE, rtol=1e-9, atol=1e-12)["d"]
    assert np.max(np.abs(fine - coarse)) < 1e-7 and np.max(fine) > 0.5
    with pytest.raises(ValueError, match="r2 must be > 0"):
        ev.reference_solution(DAMAGE, f, time, ev.rate_independent(0.05))


def test_explicit_step_overshoots_beyond_the_relaxation_time_implicit_never():
    tau = VISCO_PLAST.r2 / (PLAST.E + PLAST.K)  # relaxation time of the overstress Φ
    state, eps = PLAST.initial_state(), 3e-3
    phi0 = PLAST.yield_function(eps, state, VISCO_PLAST)
    for q in (0.5, 1.1, 3.0):
        explicit = PLAST.update(state, eps, eps, q * tau, VISCO_PLAST, "explicit")
        implicit = PLAST.update(state, eps, eps, q * tau, VISCO_PLAST, "implicit")
        assert PLAST.yield_function(eps, implicit, VISCO_PLAST) == pytest.approx(phi0 / (1 + q))
        assert PLAST.stress(eps, implicit) > 0
        if q < 1.15:  # Φ → (1 - q) Φ0: monotone for q < 1, overshoot into the elastic domain for q > 1
            assert PLAST.yield_function(eps, explicit, VISCO_PLAST) == pytest.approx((1 - q) * phi0)
        else:  # so far that the stress reverses sign under tensile strain
            assert PLAST.stress(eps, explicit) < 0


# ------------------------------------------------------------------ bad input is refused at the door, by name

NAN, INF = float("nan"), float("inf")
T4 = np.linspace(0.0, 1.0, 4)
E4 = np.array([0.0, 1e-3, 2e-3, 3e-3])


def _with(array, index, value):
    bad = np.array(array, dtype=float)
    bad[index] = value
    return bad


def _psi(e, lam):
    return 0.5 * 1e3 * (e - lam) ** 2


def _study(**kw):
    call = {"model": PLAST, "dissipation": VISCO_PLAST, "strain_fn": lambda t: cyclic(2e-3, t), "t_end": 1.0,
            "n_steps": (4, 8), "schemes": ("implicit",)} | kw
    return ev.convergence_study(**call)


REFUSALS = {
    # the states built by hand
    "PlasticState eps_p nan": (lambda: ev.PlasticState(_with(np.zeros(3), 0, NAN), np.zeros(3)), "eps_p"),
    "PlasticState eps_p inf": (lambda: ev.PlasticState(_with(np.zeros(3), 1, INF), np.zeros(3)), "eps_p"),
    "PlasticState alpha nan": (lambda: ev.PlasticState(np.zeros(3), _with(np.zeros(3), 0, NAN)), "alpha"),
    "PlasticState alpha inf": (lambda: ev.PlasticState(np.zeros(3), _with(np.zeros(3), 2, INF)), "alpha"),
    "PlasticState alpha < 0": (lambda: ev.PlasticState(0.0, -1e-3), "alpha"),
    "PlasticState alpha None": (lambda: ev.PlasticState(0.0, None), "alpha"),
    "PlasticState eps_p str": (lambda: ev.PlasticState("abc", 0.0), "eps_p"),
    "PlasticState shapes": (lambda: ev.PlasticState(np.zeros(3), np.zeros(2)), "eps_p"),
    "DamageState d nan": (lambda: ev.DamageState(np.array([0.1, NAN])), "d"),
    "DamageState d inf": (lambda: ev.DamageState(INF), "d"),
    "DamageState d < 0": (lambda: ev.DamageState(-0.1), "d"),
    # the explicit update, Eq. (4.53)
    "rdu lam_m inf": (lambda: ev.rate_dependent_update(INF, 1.0, 0.1, VISCO_DAMAGE), "lam_m"),
    "rdu lam_m nan entry": (lambda: ev.rate_dependent_update([0.0, NAN], 1.0, 0.1, VISCO_DAMAGE), "lam_m"),
    "rdu p inf": (lambda: ev.rate_dependent_update(0.0, INF, 0.1, VISCO_DAMAGE), "p"),
    "rdu p -inf entry": (lambda: ev.rate_dependent_update(0.0, [1.0, -INF], 0.1, VISCO_DAMAGE), "p"),
    "rdu dt inf": (lambda: ev.rate_dependent_update(0.0, 1.0, INF, VISCO_DAMAGE), "dt"),
    "rdu shapes": (lambda: ev.rate_dependent_update(np.zeros(2), np.zeros(3), 0.1, VISCO_DAMAGE), "lam_m"),
    "rdu dissipation None": (lambda: ev.rate_dependent_update(0.0, 1.0, 0.1, None), "dissipation"),
    # the numerical variational update
    "var free_energy None": (lambda: ev.variational_update(None, VISCO_DAMAGE, 0.0, 0.0, 1.0), "free_energy"),
    "var dissipation None": (lambda: ev.variational_update(_psi, None, 0.0, 0.0, 1.0), "dissipation"),
    "var eps inf": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, INF, 0.0, 1.0), "eps"),
    "var lam_m nan": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, NAN, 1.0), "lam_m"),
    "var dt inf": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, INF), "dt"),
    "var width inf": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, width=INF), "width"),
    "var width 0": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, width=0.0), "width"),
    "var grid nan": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, grid=NAN), "grid"),
    "var grid 3": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, grid=3), "grid"),
    "var max_expansions 0": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, max_expansions=0),
                             "max_expansions"),
    "var bounds None": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, bounds=None), "bounds"),
    "var bounds nan": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, bounds=(NAN, 1.0)),
                       "bounds"),
    "var bounds 3": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, 0.0, 0.0, 1.0, bounds=(0, 1, 2)), "bounds"),
    "var args nan": (lambda: ev.variational_update(lambda e, l, k: k * l**2, VISCO_DAMAGE, 0.0, 0.0, 1.0,
                                                   args=(NAN,)), "args"),
    "var shapes": (lambda: ev.variational_update(_psi, VISCO_DAMAGE, np.zeros(2), np.zeros(3), 1.0), "eps"),
    # the driver
    "simulate model None": (lambda: ev.simulate(None, E4, T4, VISCO_PLAST), "model"),
    "simulate strain nan": (lambda: ev.simulate(PLAST, _with(E4, 2, NAN), T4, VISCO_PLAST), "strain"),
    "simulate strain inf": (lambda: ev.simulate(PLAST, _with(E4, 0, INF), T4, VISCO_PLAST), "strain"),
    "simulate strain str": (lambda: ev.simulate(PLAST, "abc", T4, VISCO_PLAST), "strain"),
    "simulate strain shape": (lambda: ev.simulate(PLAST, E4[:3], T4, VISCO_PLAST), "strain"),
    "simulate time nan": (lambda: ev.simulate(PLAST, E4, _with(T4, 1, NAN), VISCO_PLAST), "time"),
    "simulate time inf": (lambda: ev.simulate(PLAST, E4, _with(T4, 3, INF), VISCO_PLAST), "time"),
    "simulate time None": (lambda: ev.simulate(PLAST, E4, None, VISCO_PLAST), "time"),
    "simulate time 2D": (lambda: ev.simulate(PLAST, E4, T4[None], VISCO_PLAST), "time"),
    "simulate dissipation None": (lambda: ev.simulate(PLAST, E4, T4, None), "dissipation"),
    "simulate scheme": (lambda: ev.simulate(PLAST, E4[:1], T4[:1], VISCO_PLAST, "forward"), "scheme"),
    "simulate option": (lambda: ev.simulate(PLAST, E4, T4, VISCO_PLAST, "implicit", grid=11), "grid"),
    "simulate state0 kind": (lambda: ev.simulate(PLAST, E4, T4, VISCO_PLAST, state0=DAMAGE.initial_state()),
                             "state0"),
    "simulate state0 nan": (lambda: ev.simulate(PLAST, E4, T4, VISCO_PLAST,
                                                state0=ev.PlasticState._make((NAN, 0.0))), "state0.eps_p"),
    "simulate state0 shape": (lambda: ev.simulate(PLAST, E4, T4, VISCO_PLAST,
                                                  state0=ev.PlasticState(np.zeros(2), 0.0)), "state0.eps_p"),
    # the reference solution and the convergence study
    "reference model None": (lambda: ev.reference_solution(None, np.sin, T4, VISCO_PLAST), "model"),
    "reference strain_fn None": (lambda: ev.reference_solution(PLAST, None, T4, VISCO_PLAST), "strain_fn"),
    "reference dissipation None": (lambda: ev.reference_solution(PLAST, np.sin, T4, None), "dissipation"),
    "reference time inf": (lambda: ev.reference_solution(PLAST, np.sin, _with(T4, 3, INF), VISCO_PLAST), "time"),
    "reference atol inf": (lambda: ev.reference_solution(PLAST, np.sin, T4, VISCO_PLAST, atol=INF), "atol"),
    "order dt inf": (lambda: ev.observed_order([0.1, 0.05, INF], [1.0, 0.5, 0.2]), "dt"),
    "order dt 0": (lambda: ev.observed_order([0.1, 0.05, 0.0], [1.0, 0.5, 0.2]), "dt"),
    "order error 0": (lambda: ev.observed_order([0.1, 0.05, 0.02], [1.0, 0.5, 0.0]), "error"),
    "order error inf": (lambda: ev.observed_order([0.1, 0.05, 0.02], [1.0, INF, 0.2]), "error"),
    "order shapes": (lambda: ev.observed_order([0.1, 0.05, 0.02], [1.0, 0.5]), "dt and error"),
    "order last 1": (lambda: ev.observed_order([0.1, 0.05, 0.02], [1.0, 0.5, 0.2], last=1), "last"),
    "order last nan": (lambda: ev.observed_order([0.1, 0.05, 0.02], [1.0, 0.5, 0.2], last=NAN), "last"),
    "order one dt": (lambda: ev.observed_order([0.1, 0.1, 0.1], [1.0, 0.5, 0.2]), "dt"),
    "study model None": (lambda: _study(model=None), "model"),
    "study dissipation None": (lambda: _study(dissipation=None), "dissipation"),
    "study strain_fn None": (lambda: _study(strain_fn=None), "strain_fn"),
    "study t_end inf": (lambda: _study(t_end=INF), "t_end"),
    "study n_steps nan": (lambda: _study(n_steps=(4, NAN)), "n_steps"),
    "study n_steps None": (lambda: _study(n_steps=None), "n_steps"),
    "study n_steps one": (lambda: _study(n_steps=(8,)), "n_steps"),
    "study schemes None": (lambda: _study(schemes=None), "schemes"),
    "study schemes str": (lambda: _study(schemes="implicit"), "schemes"),
    "study scheme": (lambda: _study(schemes=("forward",)), "scheme"),
    "study repeats 0": (lambda: _study(repeats=0), "repeats"),
    "study reference_kw": (lambda: _study(reference_kw=1e-9), "reference_kw"),
    "study on_result": (lambda: _study(on_result=3), "on_result"),
    "study elastic path": (lambda: _study(strain_fn=lambda t: 0.0), "strain_fn"),
}


@pytest.mark.parametrize("case", list(REFUSALS))
def test_bad_input_is_refused_naming_the_parameter(case):
    call, name = REFUSALS[case]
    with pytest.raises((ValueError, TypeError), match=name.replace(".", r"\.")):
        call()


def test_states_built_by_hand_keep_their_entries_and_the_models_build_theirs_unchecked():
    eps_p, alpha = np.array([-1e-3, 2e-3]), np.array([0.0, 3e-3])
    state = ev.PlasticState(eps_p, alpha)
    assert state.eps_p is eps_p and state.alpha is alpha and state == ev.PlasticState(eps_p=eps_p, alpha=alpha)
    assert state._replace(alpha=0.0).alpha == 0.0 and ev.PlasticState(0.0, 0.0)._fields == ("eps_p", "alpha")
    assert ev.DamageState(0.0).d == 0.0 and ev.DamageState([0.2, 0.5]).d == [0.2, 0.5]
    assert type(PLAST.initial_state((2,))) is ev.PlasticState and type(DAMAGE.initial_state()) is ev.DamageState
    rate = PLAST.state_rate(-3e-3, PLAST.initial_state(), VISCO_PLAST)  # a rate of εp may be negative
    assert type(rate) is ev.PlasticState and rate.eps_p < 0 < rate.alpha


@pytest.mark.parametrize("scheme", [*ev.SCHEMES, "variational"])
def test_guarded_driver_gives_the_same_history_from_a_checked_initial_state(scheme):
    strain = 3e-3 * np.sin(2 * np.pi * T4)
    fresh = ev.simulate(PLAST, strain, T4, VISCO_PLAST, scheme)
    given_state0 = ev.simulate(PLAST, list(strain), list(T4), VISCO_PLAST, scheme, state0=ev.PlasticState(0.0, 0.0))
    for key, value in fresh.items():
        assert np.array_equal(value, given_state0[key]), key
    assert np.all(np.isfinite(fresh["stress"])) and np.max(fresh["alpha"]) > 0
    assert ev.simulate(PLAST, strain[:1], T4[:1], VISCO_PLAST, scheme)["eps_p"].shape == (1,)
