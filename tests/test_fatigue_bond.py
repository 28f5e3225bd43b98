"""The fatigue bond of seed 002 (Nguyen et al. 2018): constitutive law, Paris law, cycle jump, bad input."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from abrakit.compiled import HAVE_NUMBA
from abrakit.fatigue import BondParameters, criterion, cyclic_test, geometric_factor, monotonic_test, softening_energy
from abrakit.fatigue.bond_law import bond_stresses, damage_after, flow_direction, plastic_return
from abrakit.fatigue.paris import (
    cycle_jump,
    cycle_update,
    fatigue_displacements,
    paris_increment,
    stress_intensity_range,
)
from abrakit.fatigue.single_bond import jump_reduction_percent

P = BondParameters()


def test_table_one_reading_agrees_with_the_prose():
    """The prose fixes the strengths the garbled Table 1 lists: the 60 kPa cycles stay below the tensile yield
    at D = 0.4 (σ_t (1 − 0.4) = 72 kPa) and 'have just reached' the shear yield there (c (1 − 0.4) = 60 kPa)."""
    assert criterion(60e3, 0.0, 0.4, P) < 0.0
    assert criterion(0.0, 60e3, 0.4, P) == pytest.approx(0.0, abs=1e-6 * P.cohesion**2)
    # the threshold lets the same cycles grow fatigue damage in tension and in shear from D0 on (a < 0.505)
    assert criterion(60e3, 0.0, P.initial_damage, P, level=P.threshold) > 0.0
    assert criterion(0.0, 60e3, P.initial_damage, P, level=P.threshold) > 0.0


@pytest.mark.parametrize("damage", [0.0, 0.01, 0.4, 0.9])
@pytest.mark.parametrize("level", [1.0, 0.5])
def test_yield_surface_passes_through_the_tensile_strength_and_the_cohesion(damage, level):
    """Eq. (18)/(23) with α = √(2cσ_t tan φ − σ_t² tan² φ)/c: apex at level·σ_t(1 − D), level·c(1 − D) at σ_n = 0,
    the origin inside, and a large tensile stress outside (the far branch continued)."""
    intact = 1.0 - damage
    scale = P.cohesion**2
    assert criterion(level * P.tensile_strength * intact, 0.0, damage, P, level) == pytest.approx(0, abs=1e-9 * scale)
    assert criterion(0.0, level * P.cohesion * intact, damage, P, level) == pytest.approx(0, abs=1e-9 * scale)
    assert criterion(0.0, 0.0, damage, P, level) < 0.0
    far = 3.0 * P.cohesion / P.tan_phi            # beyond the second root of the printed hyperbola
    assert criterion(far, 0.0, damage, P, level) > 0.0
    sigma = np.linspace(-5, 1, 200) * P.tensile_strength
    assert np.all(np.diff(criterion(sigma, 0.0, damage, P, level)) > 0.0)      # monotone in σ_n


def test_a_fully_damaged_bond_carries_no_tension_or_shear_but_compression():
    sn, ss = bond_stresses(np.array([1e-5, -1e-5]), np.array([1e-5, 1e-5]), 1.0, P)
    assert sn[0] == 0.0 and np.all(ss == 0.0)
    assert sn[1] == pytest.approx(-P.kn * 1e-5)                 # Eq. (15): full stiffness in compression


def test_damage_law_composes_and_stays_below_one():
    """D' = 1 − (1 − D) e^{−Δκ}: two increments equal their sum in one, and D → 1 only in the limit."""
    d1 = damage_after(damage_after(0.01, 1e-5, 2e-6, P), 3e-6, 4e-6, P)
    assert d1 == pytest.approx(damage_after(0.01, 1.3e-5, 6e-6, P), rel=1e-13)
    huge = damage_after(0.01, 1.0, 1.0, P)
    assert 0.0 < huge <= 1.0
    assert damage_after(P.initial_damage, 0.0, 0.0, P) == P.initial_damage


@pytest.mark.parametrize("mode, strength", [("tension", "tensile_strength"), ("shear", "cohesion")])
def test_monotonic_tests_peak_at_the_strengths_and_dissipate_the_softening_area(mode, strength):
    """Fig. 7a/8a monotonic curves: linear to the strength × (1 − D0), then exponential softening; the work to
    failure equals the closed-form softening area (:func:`softening_energy`) to 0.1 %."""
    test = monotonic_test(P, mode, increment=1e-7)
    u, s = np.array(test.displacement), np.array(test.stress)
    assert s.max() == pytest.approx(getattr(P, strength) * (1.0 - P.initial_damage), rel=1e-9)
    peak = np.argmax(s)
    stiffness = P.kn if mode == "tension" else P.ks
    assert np.allclose(s[:peak], stiffness * (1 - P.initial_damage) * u[:peak], rtol=1e-9)
    assert np.all(np.diff(s[peak:]) <= 1e-9 * s.max())                         # softening only
    work = np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(u))
    assert work == pytest.approx(softening_energy(P, mode), rel=1e-3)
    assert s[-1] < 1e-5 * s.max() and test.damage > 1.0 - 1e-5


def test_softening_energy_converges_with_the_step_to_the_closed_form():
    errors = []
    for du in (8e-7, 4e-7, 2e-7):
        t = monotonic_test(P, "shear", increment=du)
        u, s = np.array(t.displacement), np.array(t.stress)
        errors.append(abs(np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(u)) / softening_energy(P, "shear") - 1))
    assert errors[2] < errors[1] < errors[0]


def test_plastic_return_of_mixed_trial_states_satisfies_yield_flow_and_damage_law():
    """Random mixed-mode trial states beyond the surface: the returned state lies on F = 0 (Eq. 18) at the
    end-of-step damage, the plastic increments follow the flow rule at the returned stress (Eq. 19, 20) and the
    damage follows Eq. (21) — each checked here independently of the solver's residual."""
    rng = np.random.default_rng(3)
    n = 200
    en = rng.uniform(-2e-5, 1.5e-5, n)
    es = rng.uniform(-2e-5, 2e-5, n)
    d0 = rng.uniform(0.01, 0.8, n)
    dn, ds, d, sn, ss = plastic_return(en, es, d0, P)
    sn0, ss0 = bond_stresses(en, es, d0, P)
    yielded = criterion(sn0, ss0, d0, P) > 0
    assert yielded.sum() > 50
    assert np.allclose(criterion(sn, ss, d, P)[yielded] / P.cohesion**2, 0.0, atol=1e-10)
    fn, fs = flow_direction(sn, ss, d, P)
    cross = dn * fs - ds * fn                                        # Δuᵖ ∥ (∂G/∂σ_n, ∂G/∂σ_s)
    assert np.allclose(cross[yielded] / (np.hypot(dn, ds) * np.hypot(fn, fs))[yielded], 0.0, atol=1e-8)
    assert np.all(dn[yielded] * fn[yielded] + ds[yielded] * fs[yielded] > 0)
    assert np.allclose(d, damage_after(d0, dn, ds, P), rtol=1e-12)
    sn1, ss1 = bond_stresses(en - dn, es - ds, d, P)
    assert np.allclose(sn1, sn, atol=1e-6 * P.cohesion) and np.allclose(ss1, ss, atol=1e-6 * P.cohesion)
    assert np.all(dn[~yielded] == 0.0) and np.all(d[~yielded] == d0[~yielded])


def test_stress_update_at_the_onset_of_unloading_is_eq_38_39():
    """Eq. (38): σⁿ = σᵖʳᵉ (1 − Dⁿ)/(1 − Dⁿ⁻¹) − Δu_nᶠ (1 − Dⁿ) k_n — what Eq. (15) gives with the new internal
    variables, so a displacement-driven engine needs no separate correction."""
    elastic, d_old, d_new, duf = 2.5e-6, 0.05, 0.06, 1e-7
    before, _ = bond_stresses(elastic, 0.0, d_old, P)
    after, _ = bond_stresses(elastic - duf, 0.0, d_new, P)
    assert after == pytest.approx(before * (1 - d_new) / (1 - d_old) - duf * (1 - d_new) * P.kn, rel=1e-13)


def test_geometric_factor_is_the_centre_cracked_strip():
    """Eq. (31): Y(0) = 1 (Griffith) and Isida's exact values of the centre-cracked strip to 0.1 % (the accuracy
    Tada et al. state for this form); without the square root of sec it would miss them by 19 % at D = 0.5."""
    assert geometric_factor(0.0) == 1.0
    isida = {0.1: 1.0060, 0.2: 1.0246, 0.3: 1.0577, 0.4: 1.1094, 0.5: 1.1867, 0.6: 1.3033, 0.7: 1.4882}
    for ratio, value in isida.items():
        assert geometric_factor(ratio) == pytest.approx(value, rel=1e-3)


def test_mixed_mode_range_adds_in_quadrature():
    """Eq. (28): ΔK² = ΔK_I² + ΔK_II²; the mode I range counts only tension (a closed crack has no K_I)."""
    k1 = stress_intensity_range(0.2, 30e3, 0.0, P)
    k2 = stress_intensity_range(0.2, 0.0, 40e3, P)
    assert stress_intensity_range(0.2, 30e3, 40e3, P) == pytest.approx(np.hypot(k1, k2), rel=1e-14)
    assert k1 == pytest.approx(geometric_factor(0.2) * np.sqrt(np.pi * P.width * 0.2) * 30e3, rel=1e-14)


def test_fatigue_displacements_raise_damage_by_the_increment_in_the_flow_ratio():
    """Eqs. (36), (37): the displacements reproduce ΔD_f through the damage law and stand in the ratio
    Δu_nᶠ/|Δu_sᶠ| = tan ψ [a c (1 − D) − σ_n tan ψ]/|σ_s|; pure mode I opens only the normal direction."""
    d, inc = 0.2, 3e-3
    for sn, ss in ((40e3, 0.0), (0.0, -60e3), (20e3, 30e3)):
        dn, ds = fatigue_displacements(d, inc, sn, ss, P)
        assert damage_after(d, dn, ds, P) == pytest.approx(d + inc, rel=1e-13)
        ratio = P.tan_psi * (P.threshold * P.cohesion * (1 - d) - sn * P.tan_psi)
        if ss == 0.0:
            assert ds == 0.0 and dn > 0
        else:
            assert dn / abs(ds) == pytest.approx(ratio / abs(ss), rel=1e-12)
            assert np.sign(ds) == np.sign(ss)


def test_tension_and_shear_fatigue_histories_coincide():
    """Sec. 4.2: 'the results of fatigue damage evolution … in these tests exactly match'."""
    t = cyclic_test(P, "tension", to_failure=False)
    s = cyclic_test(P, "shear", to_failure=False)
    assert np.array_equal(t.cycles, s.cycles) and np.array_equal(t.cycle_damage, s.cycle_damage)
    assert t.cycle_damage[-1] >= 0.4 > t.cycle_damage[-2]


def test_cycle_by_cycle_damage_matches_an_independent_integration_of_paris_law():
    """Eq. (27) per cycle against scipy's solve_ivp of dD/dN = (C/L) ΔK(D)ᵐ: within 0.5 % over the whole history
    (the difference is the unit cycle acting as an Euler step)."""
    t = cyclic_test(P, "tension", to_failure=False)
    n, d = np.array(t.cycles), np.array(t.cycle_damage)
    ode = solve_ivp(lambda _, y: paris_increment(np.minimum(y, 0.99), 40e3, 0.0, P), (0, n[-1]),
                    [P.initial_damage], dense_output=True, rtol=1e-10, atol=1e-13)
    assert np.max(np.abs(d / ode.sol(n)[0] - 1.0)) < 5e-3


def test_paris_coefficient_scales_the_cycle_count_inversely():
    """Fig. 11b: the damage increment is proportional to C, so the cycles to D = 0.4 scale as 1/C."""
    n = {c: cyclic_test(P.replace(paris_coefficient=c), "tension", to_failure=False).cycles[-1]
         for c in (0.5e-8, 1.0e-8, 1.5e-8)}
    assert n[0.5e-8] == pytest.approx(2 * n[1.0e-8], rel=0.01)
    assert n[1.5e-8] == pytest.approx(n[1.0e-8] / 1.5, rel=0.01)


@pytest.mark.parametrize("m, paper", [(0.8, 2008), (1.2, 50)])
def test_papers_cycle_counts_are_those_of_a_zero_to_peak_stress_range(m, paper):
    """Fig. 11a: 2008 cycles (m = 0.8) and 50 (m = 1.2) from D = 0.01 to 0.4 are reproduced to the cycle when ΔK
    takes the 60 kPa peak as the range (a 0–60 kPa cycle); the printed 20–60 kPa range gives 2777 and 80."""
    p = P.replace(paris_exponent=m)
    assert cyclic_test(p, "tension", stress_min=0.0, to_failure=False).cycles[-1] == paper
    printed = cyclic_test(p, "tension", to_failure=False).cycles[-1]
    assert printed == {0.8: 2777, 1.2: 80}[m]


@pytest.mark.parametrize("jump", [0.005, 0.01])
def test_cycle_jump_lands_on_the_cycle_by_cycle_history(jump):
    """Eq. (41) iterates Eq. (27) with the range frozen; under a constant stress range that is exact, so at every
    jump's end D equals the cycle-by-cycle D at the same cycle (to round-off), with 5–11× fewer simulated cycles."""
    full = cyclic_test(P, "tension", to_failure=False)
    jumped = cyclic_test(P, "tension", to_failure=False, jump=jump)
    reference = dict(zip(full.cycles, full.cycle_damage, strict=True))
    common = [(d, reference[n]) for n, d in zip(jumped.cycles, jumped.cycle_damage, strict=True) if n in reference]
    assert len(common) >= len(jumped.cycles) - 1
    assert np.allclose(*np.array(common).T, rtol=1e-12)
    assert full.simulated_cycles / jumped.simulated_cycles > (5 if jump == 0.005 else 10)


def test_papers_cycle_jump_counts_are_ratios_of_a_zero_to_peak_run():
    """Sec. 4.1: the jumps 0.005 and 0.01 'reduce the simulated cycles by 388.8 % and 797.4 %'. With ΔK from the
    60 kPa peak (311 cycles, as Fig. 11 implies), N_jump rounded and no jump passing the cycle that reaches the
    target damage (that cycle is simulated), the full-to-simulated ratios are 311/80 = 388.8 % and 311/39 = 797.4 %,
    both to the digit, in tension and in shear."""
    full = cyclic_test(P, "tension", stress_min=0.0, to_failure=False)
    assert full.simulated_cycles == 311
    for mode in ("tension", "shear"):
        ratio = {jump: jump_reduction_percent(P, jump, mode=mode) for jump in (0.005, 0.01)}
        assert round(ratio[0.005], 1) == 388.8 and round(ratio[0.01], 1) == 797.4


@pytest.mark.parametrize("jump", [None, 0.005, 0.01, 0.05])
def test_a_jump_never_skips_the_cycle_that_fails_the_bond_and_the_peak_stays_on_the_surface(jump):
    """Issue 38's hard case: pure shear 0 -> 60 kPa fails the bond in cycle 311 (its damage passes 1 - 60/c = 0.4).
    A jump of 0.01 from D = 0.3992 used to land at 314 cycles and D = 0.4086, and the peak was recorded at 60 kPa
    on a surface of 59.85 kPa. Every jump now ends before the failing cycle, which is simulated: the last cycle and
    its damage are the cycle-by-cycle run's, and no recorded stress lies outside the damaged yield surface."""
    full = cyclic_test(P, "shear", stress_min=0.0, to_failure=False)
    run = cyclic_test(P, "shear", stress_min=0.0, to_failure=False, jump=jump)
    assert full.cycles[-1] == 311 and full.cycle_damage[-2] < run.failure_damage(60e3) <= full.cycle_damage[-1]
    assert run.cycles[-1] == 311
    assert run.cycle_damage[-1] == pytest.approx(full.cycle_damage[-1], rel=1e-12)
    assert run.stress[-2] == pytest.approx(run.strength, rel=1e-12) and run.stress[-2] < 60e3
    assert P.cohesion * (1.0 - run.failure_damage(60e3)) == pytest.approx(60e3, rel=1e-12)
    assert criterion(0.0, run.stress[-2], run.damage, P) == pytest.approx(0.0, abs=1e-6 * P.cohesion**2)


def test_a_limited_jump_stops_before_the_cycle_that_passes_the_limit():
    n, increment = cycle_jump([0.1], [0.01], 0.1, exponent=0.0)                   # m = 0: 0.01 per cycle
    assert n == 10 and increment[0] == pytest.approx(0.1)
    n, increment = cycle_jump([0.1], [0.01], 0.1, exponent=0.0, limit=0.135)
    assert n == 3 and increment[0] == pytest.approx(0.03)                         # the 4th cycle reaches 0.14
    assert cycle_jump([0.1], [0.05], 0.1, exponent=0.0, limit=0.12)[0] == 1       # the failing cycle itself


def test_cycle_jump_takes_the_largest_increment_and_at_least_one_cycle():
    n, inc = cycle_jump([0.1, 0.2], [1e-3, 2e-3], 0.01, exponent=1.0)
    assert n == 5 and inc[1] > 0.01 > inc[0] > 0.005
    assert cycle_jump([0.1], [0.05], 0.01, exponent=1.0)[0] == 1
    assert cycle_jump([0.1], [0.004], 0.01, exponent=1.0)[0] == 2          # 2.5 rounds to even, 2
    assert cycle_jump([0.1], [0.0035], 0.01, exponent=1.0)[0] == 3         # 2.86 rounds to 3
    assert cycle_jump([0.1], [1e-4], 0.01, exponent=1.0, max_cycles=7)[0] == 7


def test_ratcheting_in_the_jump_repeats_the_sampled_plastic_increment_and_bounds_the_jump():
    """Decision "ratcheting in the cycle jump": bond 0 is fatigued below yield, bond 1 yielded and ratcheted by
    Δuᵖ in the sampled cycle. Without ``ratchet`` (the paper) bond 1 stands still; with it, N_jump bounds either
    damage rate by ΔD_jump, and bond 1 gains Eq. (22)'s damage for (N − 1) Δuᵖ on top of the sampled cycle."""
    damage = np.array([0.1, 0.1])
    peak, low = (np.array([80e3, 80e3]), np.zeros(2)), (np.zeros(2), np.zeros(2))
    eligible = np.array([True, False])
    paper = cycle_update(damage, peak, low, P, eligible=eligible, jump=0.01)
    unchanged = cycle_update(damage, peak, low, P, eligible=eligible, jump=0.01, ratchet=np.zeros((2, 2)))
    for a, b in zip(paper, unchanged, strict=True):
        assert np.array_equal(a, b)
    assert paper[1][1] == 0.0 and np.all(paper[4] == 0.0)
    ratchet = np.array([[0.0, 4e-8], [0.0, 2e-8]])                  # |Δuᵖ| normal, shear of the sampled cycle
    rate = damage_after(0.1, 4e-8, 2e-8, P) - 0.1                  # plastic damage per cycle of bond 1
    fatigue_rate = cycle_update(damage, peak, low, P, eligible=eligible)[1][0]
    assert rate > fatigue_rate > 0.0
    n, increment, du_n, du_s, skipped = cycle_update(damage, peak, low, P, eligible=eligible, jump=0.01,
                                                     ratchet=ratchet)
    assert n == round(0.01 / rate) > 1
    assert np.allclose(skipped, (n - 1) * ratchet, rtol=0, atol=1e-30)
    assert damage[1] + increment[1] == pytest.approx(damage_after(0.1, (n - 1) * 4e-8, (n - 1) * 2e-8, P), rel=1e-12)
    assert increment[1] == pytest.approx((n - 1) * rate, rel=1e-2)          # ≈ linear for a small jump
    assert du_n[1] == du_s[1] == 0.0                                        # no fatigue displacement: it yielded
    # the fatigued bond follows Eq. (41) over the same N
    assert increment[0] == pytest.approx(cycle_jump(damage, [fatigue_rate, 0.0], 0.01, max_cycles=n,
                                                    exponent=P.paris_exponent)[1][0], rel=1e-12)
    with pytest.raises(ValueError, match="ratchet"):
        cycle_update(damage, peak, low, P, jump=0.01, ratchet=np.zeros(2))


def test_no_fatigue_damage_below_the_threshold():
    low = cyclic_test(P, "tension", stress_min=5e3, stress_max=50e3, to_failure=False)
    assert low.cycle_damage == [P.initial_damage]


def test_after_cycling_tension_rises_to_the_reduced_strength_and_shear_softens_at_once():
    """Figs. 7a, 8a: at D = 0.4 the tension test is still elastic up to σ_t(1 − D), the shear test is on its yield
    surface already."""
    t = cyclic_test(P, "tension")
    d_end = t.cycle_damage[-1]
    start = len(t.stress) - 1 - t.stress[::-1].index(20e3)
    u, s = np.array(t.displacement[start:]), np.array(t.stress[start:])
    peak = np.argmax(s)
    assert P.tensile_strength * (1 - d_end) * 0.99 < s[peak] <= P.tensile_strength * (1 - d_end) * (1 + 1e-9)
    assert np.allclose(np.diff(s[:peak]) / np.diff(u[:peak]), P.kn * (1 - d_end), rtol=1e-6)   # elastic rise
    s = cyclic_test(P, "shear")
    start = len(s.stress) - 1 - s.stress[::-1].index(20e3)
    assert max(s.stress[start:]) <= 60e3 * (1 + 1e-9)
    assert t.damage > 0.999 and s.damage > 0.999
    assert 0.0 <= min(t.cycle_damage) and max(s.cycle_damage) <= 1.0


@pytest.mark.parametrize("change, name", [({"threshold": 1.2}, "threshold"), ({"threshold": 0.0}, "threshold"),
                                          ({"paris_exponent": 0.0}, "paris_exponent"),
                                          ({"paris_exponent": -1.0}, "paris_exponent"),
                                          ({"tensile_strength": -1.0}, "tensile_strength"),
                                          ({"cohesion": -5.0}, "cohesion"), ({"kn": 0.0}, "kn"),
                                          ({"initial_damage": 0.0}, "initial_damage"),
                                          ({"dilatancy_angle": 15.0}, "dilatancy_angle"),
                                          ({"friction_angle": 89.0}, "tensile_strength")])
def test_bad_parameters_raise_value_error_naming_them(change, name):
    with pytest.raises(ValueError, match=name):
        P.replace(**change)


def test_bad_driver_input_raises_value_error():
    with pytest.raises(ValueError, match="jump"):
        cyclic_test(P, "tension", jump=0.0)
    with pytest.raises(ValueError, match="jump"):
        cycle_jump([0.1], [1e-3], -0.01, exponent=1.0)
    with pytest.raises(ValueError, match="mode"):
        cyclic_test(P, "torsion")
    with pytest.raises(ValueError, match="damage"):
        geometric_factor(1.0)


def test_a_trial_far_beyond_the_strength_is_substepped_or_refused_with_a_message():
    """Hard case: elastic trials 5–20 times the current strength at D up to 1 − 10⁻⁶. Without the start of the
    step Newton may fail and says so; given it, the step is split in halves until every bond returns onto F = 0 with
    D in [D_start, 1], never NaN."""
    rng = np.random.default_rng(5)
    n = 300
    en, es = rng.uniform(-1e-4, 1e-4, n), rng.uniform(-1e-4, 1e-4, n)
    d0 = 1 - 10 ** rng.uniform(-6, -0.01, n)
    with pytest.raises(RuntimeError, match="smaller steps"):
        plastic_return(en, es, d0, P)
    dn, ds, d, sn, ss = plastic_return(en, es, d0, P, start=(0.0, 0.0))
    assert np.all(np.isfinite([dn, ds, d, sn, ss]))
    assert np.all((d >= d0) & (d <= 1.0))
    assert np.max(criterion(sn, ss, d, P) / (P.cohesion * (1 - d0)) ** 2) < 1e-9


def test_a_nearly_broken_bond_carrying_shear_by_friction_is_returned():
    """Hard case from the 95 % beam with extrapolated ratcheting: D = 0.995 in compression, where friction
    (−σ_n tan φ ≈ 24 kPa) dwarfs the remaining cohesion c(1 − D) ≈ 0.4 kPa. Scaling F by the cohesion alone put
    the Newton tolerance below round-off and the return failed at every substep; scaled by the surface's size
    (cohesion plus friction) it converges onto the surface."""
    from abrakit.experiments.bending import table_two

    p = table_two()
    trial, start = (-4.221070187981062e-07, 9.520765342589138e-05), (-4.236137435108127e-07, 9.50608697926103e-05)
    stiffness = (np.array([155896422505.04425]), np.array([64956842710.435104]))
    du_n, du_s, d, sn, ss = plastic_return(*trial, 0.9948761913007647, p, start=start, stiffness=stiffness,
                                           max_halvings=0)
    assert sn[0] < -60e3 and ss[0] > 30e3 and d[0] > 0.9948761913007647 and du_s[0] > 0
    surface = p.cohesion * (1 - d[0]) - sn[0] * p.tan_phi
    assert abs(criterion(sn, ss, d, p)[0]) < 1e-9 * surface**2


@pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled return needs numba (extra 'fast')")
def test_the_compiled_return_equals_the_numpy_return_to_its_tolerance():
    """:func:`abrakit.fatigue._return_kernel.plastic_return_bonds` runs the NumPy return's algorithm per bond (same
    first guess, difference Jacobian, line search and tolerance) and stops each bond at its own tolerance: the
    converged bonds agree with :func:`plastic_return` within 10⁻¹⁰ of each field's largest value (measured 1·10⁻¹²),
    per-bond stiffnesses included. Trials far beyond the strength (the hard case above) that its Newton iteration
    cannot return are flagged, with finite values, for the caller's NumPy return, which splits their steps; the
    nearly broken bond in friction converges."""
    from abrakit.fatigue._return_kernel import plastic_return_bonds
    from abrakit.fatigue.bond_law import _bond_stresses, _criterion, _yield_scale

    def compiled(en, es, d0, p, kn, ks):                      # no split: Newton's failures are flagged
        return plastic_return_bonds(en, es, d0, kn, ks, p.un, p.us, p.cohesion, p.tensile_strength, p.tan_phi,
                                    p.tan_psi, p.alpha, 1e-12, 60, np.zeros_like(en), np.zeros_like(es), 0)

    rng = np.random.default_rng(3)
    n = 400
    en, es, d0 = rng.uniform(-2e-5, 1.5e-5, n), rng.uniform(0, 2e-5, n), rng.uniform(0.01, 0.8, n)
    kn = P.kn * rng.uniform(0.5, 2.0, n)
    ks = kn / rng.uniform(1.5, 3.0, n)
    sn0, ss0 = _bond_stresses(en, es, d0, P, kn, ks)
    outside = _criterion(sn0, ss0, d0, P) > 1e-12 * _yield_scale(sn0, d0, P) ** 2
    assert outside.sum() > 100
    args = (en[outside], es[outside], d0[outside])
    *ours, converged = compiled(*args, P, kn[outside], ks[outside])
    assert converged.mean() > 0.98                  # one of 162 needs a split step, in the NumPy return too
    with pytest.raises(RuntimeError, match="did not converge for 1 bond"):
        plastic_return(*args, P, stiffness=(kn[outside], ks[outside]))
    reference = plastic_return(*args, P, stiffness=(kn[outside], ks[outside]), start=(0.0, 0.0))
    for a, b in zip(reference, ours, strict=True):
        assert np.abs(b - a)[converged].max() <= 1e-10 * np.abs(a).max()

    rng = np.random.default_rng(5)                  # the far trials of the hard case above
    en, es = rng.uniform(-1e-4, 1e-4, 300), np.abs(rng.uniform(-1e-4, 1e-4, 300))
    d0 = 1 - 10 ** rng.uniform(-6, -0.01, 300)
    *ours, converged = compiled(en, es, d0, P, np.full(300, P.kn), np.full(300, P.ks))
    assert 0 < converged.sum() < 300 and np.all(np.isfinite(ours))
    d = ours[2][converged]
    assert np.all((d >= d0[converged]) & (d <= 1.0))

    from abrakit.experiments.bending import table_two

    p = table_two()                                 # the nearly broken bond carrying shear by friction
    trial_n, trial_s, d0 = np.array([-4.221070187981062e-07]), np.array([9.520765342589138e-05]), 0.9948761913007647
    stiffness = np.array([155896422505.04425]), np.array([64956842710.435104])
    *ours, converged = compiled(trial_n, trial_s, np.array([d0]), p, *stiffness)
    reference = plastic_return(trial_n, trial_s, d0, p, stiffness=stiffness, max_halvings=0)
    assert converged[0]
    for a, b in zip(reference, ours, strict=True):
        assert b[0] == pytest.approx(a[0], rel=1e-9, abs=1e-300)


@pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled return needs numba (extra 'fast')")
def test_the_compiled_return_splits_a_failing_step_as_the_numpy_return_does():
    """Trials far beyond the strength of damaged bonds (D up to 1 − 10⁻⁴), from a start inside the surface: Newton
    fails on a quarter of them, and both returns halve those steps (depth first, each part from the state the parts
    before it left). Against the NumPy return of each bond alone (the vectorised one iterates a batch until its
    slowest bond converges, which moves the others) the compiled one gives every field to round-off (measured
    6·10⁻¹⁷ of its largest value). Nearer D = 1 (the hard case above, D up to 1 − 10⁻⁶) the two split trees can part
    at the margin of convergence and the plastic displacements then differ by up to 0.3 %, where the damage has
    saturated and the displacement that reaches the surface is nearly free; there every bond short of the failure
    damage is still returned onto its surface (|F| within 2·10⁻⁹ of the square of its end state's surface, which
    can be 10⁵ times smaller than the start state's the tolerance refers to; measured 1.1·10⁻⁹) with its damage
    between its start and 1, and every other one has broken (D ≥ D_fail)."""
    from abrakit.fatigue._return_kernel import plastic_return_bonds
    from abrakit.fatigue.bond_law import FAILURE_DAMAGE, MAX_HALVINGS, _criterion, _yield_scale

    args = (P.un, P.us, P.cohesion, P.tensile_strength, P.tan_phi, P.tan_psi, P.alpha, 1e-12, 60)

    def trials(seed, n, closest):
        rng = np.random.default_rng(seed)
        en, es = rng.uniform(-1e-4, 1e-4, n), np.abs(rng.uniform(-1e-4, 1e-4, n))
        return en, es, 1 - 10 ** rng.uniform(closest, -0.01, n), np.zeros(n), np.full(n, P.kn), np.full(n, P.ks)

    en, es, d0, start, kn, ks = trials(6, 40, -4)
    *_, unsplit = plastic_return_bonds(en, es, d0, kn, ks, *args, start, start, 0)
    *ours, converged = plastic_return_bonds(en, es, d0, kn, ks, *args, start, start, MAX_HALVINGS)
    assert (~unsplit).sum() >= 10 and converged.all()               # the splits were needed, and they worked
    alone = [plastic_return(en[[k]], es[[k]], d0[[k]], P, start=(start[[k]], start[[k]])) for k in range(40)]
    for field, ours_field in enumerate(ours):
        reference = np.array([bond[field][0] for bond in alone])
        assert np.abs(ours_field - reference).max() <= 1e-12 * np.abs(reference).max()

    en, es, d0, start, kn, ks = trials(5, 300, -6)                  # nearly broken bonds
    *ours, converged = plastic_return_bonds(en, es, d0, kn, ks, *args, start, start, MAX_HALVINGS)
    du_n, du_s, d, sn, ss = ours
    yielded = (du_n != 0) | (du_s != 0)
    assert converged.all() and yielded.sum() > 100 and np.all((d >= d0) & (d <= 1.0))
    standing = yielded & (d < FAILURE_DAMAGE)
    assert 0 < (yielded & ~standing).sum() < standing.sum()
    assert np.all(np.abs(_criterion(sn, ss, d, P))[standing] <= 2e-9 * _yield_scale(sn, d, P)[standing] ** 2)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_bond_next_to_full_damage_in_near_pure_shear_returns_or_breaks(compiled):
    """Decision "failure damage of a bond": at D = 1 − 2·10⁻⁶ with a near-pure shear trial (the state of a beam run
    at 0.86 P_max), over the bonds' range of stiffnesses and starts, every bond is returned onto its surface or
    breaks (D ≥ D_fail), without an exception and without NaN, in the NumPy and the compiled return alike."""
    from abrakit.experiments.bending import table_two
    from abrakit.fatigue._return_kernel import plastic_return_bonds
    from abrakit.fatigue.bond_law import FAILURE_DAMAGE, MAX_HALVINGS, _yield_scale

    if compiled and not HAVE_NUMBA:
        pytest.skip("the compiled return needs numba")
    p = table_two()
    rng = np.random.default_rng(0)
    n = 2000
    kn = rng.uniform(1.55e11, 1.94e11, n)
    d0 = np.full(n, 1 - 2e-6)
    tn, ts = np.full(n, -7.394e-11), rng.uniform(2.0975e-4, 2.0985e-4, n)
    start_n, start_s = tn * rng.random(n), ts * rng.random(n)
    if compiled:
        *out, converged = plastic_return_bonds(tn, ts, d0, kn, kn / 2.4, p.un, p.us, p.cohesion, p.tensile_strength,
                                               p.tan_phi, p.tan_psi, p.alpha, 1e-12, 60, start_n, start_s,
                                               MAX_HALVINGS)
        assert converged.all()
    else:
        out = plastic_return(tn, ts, d0, p, start=(start_n, start_s), stiffness=(kn, kn / 2.4))
    du_n, du_s, d, sn, ss = out
    assert np.all(np.isfinite(np.array(out))) and np.all((d >= d0) & (d <= 1.0))
    standing = d < FAILURE_DAMAGE
    assert np.all(np.abs(criterion(sn, ss, d, p))[standing] <= 1e-9 * _yield_scale(sn, d, p)[standing] ** 2)


@pytest.mark.parametrize("jump", [0.005, 0.01])
def test_the_jump_ends_at_the_failing_cycle_and_tension_equals_shear(jump):
    """0 → 60 kPa: the cycle-by-cycle run reaches D = 0.4 (the shear bond's failure damage) in cycle 311; with the
    jump both modes end there too, with the same D(N)."""
    t = cyclic_test(P, "tension", stress_min=0.0, to_failure=False, jump=jump)
    s = cyclic_test(P, "shear", stress_min=0.0, to_failure=False, jump=jump)
    assert t.cycles[-1] == s.cycles[-1] == 311
    assert np.array_equal(t.cycles, s.cycles) and np.allclose(t.cycle_damage, s.cycle_damage, rtol=1e-12)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_nearly_broken_bond_pressed_shut_by_its_dilatancy_returns_in_one_step(compiled):
    """The state a beam run at 0.86 P_max and 8000 steps per cycle stopped on (D = 1 − 1.82·10⁻⁶, a near-pure shear
    trial, a slight compression): the return slides the bond by 2.5·10⁻⁴ ū_s, dilates it by 1.6·10⁻⁵ ū_n against
    the full compressive stiffness, and friction then carries the shear on a surface 62 × the start state's. F is
    held to round-off of the end state's size (|F| < 10⁻¹² of its square) but not of the start's, which the
    tolerance used to refer to: Newton converges, without a split, in the NumPy and the compiled return alike, and
    the bond stands (D below D_fail) in compression."""
    from abrakit.experiments.bending import table_two
    from abrakit.fatigue._return_kernel import plastic_return_bonds
    from abrakit.fatigue.bond_law import FAILURE_DAMAGE, _yield_scale

    if compiled and not HAVE_NUMBA:
        pytest.skip("the compiled return needs numba")
    p = table_two()
    tn, ts, d0 = np.array([-3.24932733e-12]), np.array([2.0825e-4]), np.array([0.99999818])
    kn, ks = np.array([1.71421913e11]), np.array([7.1425797e10])
    start = _yield_scale(kn * tn, d0, p)
    if compiled:
        *out, converged = plastic_return_bonds(tn, ts, d0, kn, ks, p.un, p.us, p.cohesion, p.tensile_strength,
                                               p.tan_phi, p.tan_psi, p.alpha, 1e-12, 60, tn, ts, 0)
        assert converged.all()
    else:
        out = plastic_return(tn, ts, d0, p, stiffness=(kn, ks), max_halvings=0)
    du_n, du_s, d, sn, ss = (np.asarray(v)[0] for v in out)
    end = _yield_scale(sn, d, p)
    assert d0[0] < d < FAILURE_DAMAGE and sn < 0 and end > 50 * start[0]
    assert du_n == pytest.approx(1.64e-5 * p.un, rel=0.01) and du_s == pytest.approx(2.48e-4 * p.us, rel=0.01)
    assert abs(criterion(sn, ss, d, p)) < 1e-12 * end**2
