"""Fatigue bonds in the DEM engine: a bonded pair against the constitutive driver, the cycle update, a specimen."""

import numpy as np
import pytest

from abrakit.dem import Simulation
from abrakit.dem.fatigue_bonds import install_fatigue_bonds
from abrakit.dem.fatigue_specimen import bonded_bar, cyclic_bar, history_deviation
from abrakit.dem.kernels import HAVE_NUMBA
from abrakit.dem.periodic import Periodic
from abrakit.dem.state import Particles
from abrakit.fatigue import BondParameters, monotonic_test
from abrakit.fatigue.bond_law import bond_stresses, damage_after
from abrakit.fatigue.paris import fatigue_displacements, paris_increment

P = BondParameters()
R = 0.05                      # Ø 0.1 m particles: the bond width 2R is the paper's 0.1 m contact


def bonded_pair(params=P):
    """Two touching disks, both moved kinematically, joined by one fatigue bond of width 0.1 m."""
    p = Particles.disks([[0, 0], [2 * R, 0]], R, 2650.0, fixed=True)
    sim = Simulation(p, planar=True, dt=1e-5, skin=0.1 * R)
    assert install_fatigue_bonds(sim, params) == 1
    return sim


def test_bonded_pair_pulled_apart_follows_the_constitutive_driver_and_breaks_in_tension():
    """Same displacement increments (2·10⁻⁷ m per step) through the engine's kinematics and through
    :func:`monotonic_test`: identical stress paths; at D → 1 the bond is removed and logged as a tension crack."""
    sim = bonded_pair()
    assert sim.fatigue_bonds.width[0] == pytest.approx(0.1)
    sim.particles.v[1] = (0.02, 0.0, 0.0)
    stresses = []
    while not len(sim.cracks) and len(stresses) < 5000:
        sim.step()
        if len(sim.fatigue_bonds):
            stresses.append(sim.fatigue_bonds.sigma[0, 0])
    reference = monotonic_test(P, "tension", increment=2e-7).stress[1:]
    n = min(len(stresses), len(reference))
    assert n > 1000
    assert np.max(np.abs(np.array(stresses[:n]) - reference[:n])) < 1e-6 * P.tensile_strength
    cracks = sim.cracks.as_arrays()
    assert list(cracks["mode"]) == ["tension"] and list(cracks["kind"]) == ["fatigue"]
    assert len(sim.fatigue_bonds) == 0


def opened_pair(stress: float):
    """The bonded pair opened in 100 steps to the normal stress ``stress`` [Pa] of its undamaged bond, then held."""
    sim = bonded_pair()
    opening = stress / (P.kn * (1 - P.initial_damage))
    sim.particles.v[1] = (opening / (100 * sim.dt), 0.0, 0.0)
    sim.run(100)
    sim.particles.v[1] = 0.0
    return sim


def test_onset_of_unloading_applies_paris_law_and_the_stress_update_of_eq_38():
    """Open the pair to 80 kPa (above the fatigue criterion, below yield), call the cycle update: D grows by
    Eq. (27) with the range 80 − 0 kPa, the opening loses the fatigue displacement of Eq. (36), and the stress after
    the update is Eq. (38)'s σ (1 − Dⁿ)/(1 − Dⁿ⁻¹) − Δu_nᶠ (1 − Dⁿ) k_n."""
    sim = opened_pair(80e3)
    b = sim.fatigue_bonds
    before = b.sigma[0, 0]
    assert before == pytest.approx(80e3, rel=1e-9) and not b.yielded[0]
    assert sim.fatigue_bonds.onset_of_unloading() == 1
    increment = paris_increment(P.initial_damage, 80e3, 0.0, P)
    du_n, _ = fatigue_displacements(P.initial_damage, increment, 80e3, 0.0, P)
    d_new = P.initial_damage + increment
    assert b.damage[0] == pytest.approx(d_new, rel=1e-12)
    assert b.fatigue[0, 0] == pytest.approx(du_n, rel=1e-12)
    sim.step()
    expected = before * (1 - d_new) / (1 - P.initial_damage) - du_n * (1 - d_new) * P.kn
    assert sim.fatigue_bonds.sigma[0, 0] == pytest.approx(expected, rel=1e-9)
    assert sim.fatigue_bonds.sigma[0, 0] == pytest.approx(bond_stresses(b.elastic_n, 0.0, d_new, P)[0][0], rel=1e-9)


@pytest.mark.parametrize("jump", [0.2, 0.5])
def test_the_jump_stops_before_the_cycle_in_which_a_bond_would_yield(jump):
    """A pair held at 110 kPa (below the 120 kPa strength of D₀, above its fatigue criterion): its surface shrinks
    onto the peak at D* = 1 − 110/120 (``peak_failure_damage``). A jump of ΔD_jump far beyond D* − D stops
    before the cycle that would reach D*, at D < D* and with fewer cycles than the unlimited jump takes; the same
    jump given directly to :func:`cycle_update` without a limit passes D*."""
    from abrakit.fatigue.paris import cycle_update, peak_failure_damage

    sim = opened_pair(110e3)
    b = sim.fatigue_bonds
    assert not b.yielded[0]
    failure = peak_failure_damage(b.damage, b.peak[0], b.peak[1], P)[0]
    unlimited, increment, *_ = cycle_update(b.damage, b.peak, b.low, P, width=b.width, jump=jump)
    assert b.damage[0] + increment[0] > failure                   # the paper's jump would pass it
    count = b.onset_of_unloading(jump=jump)
    assert 1 <= count < unlimited and b.damage[0] < failure


def test_a_bond_that_yields_in_a_cycle_gets_no_fatigue_damage():
    """E = 0 in Eq. (17): a cycle that reaches the yield surface lumps its fatigue into the plastic damage."""
    sim = bonded_pair()
    sim.particles.v[1] = (0.02, 0.0, 0.0)
    while sim.fatigue_bonds.damage[0] < 0.05:
        sim.step()
    d = sim.fatigue_bonds.damage[0]
    assert sim.fatigue_bonds.yielded[0]
    sim.fatigue_bonds.onset_of_unloading()
    assert sim.fatigue_bonds.damage[0] == d and sim.fatigue_bonds.fatigue[0, 0] == 0.0


def test_the_jump_proceeds_past_a_yielding_bond_unless_held():
    """Two bonds: one fatigued below yield, one that yielded in the sampled cycle. The paper's jump proceeds (and
    gives the yielding bond nothing); ``hold_while_yielding`` takes a single cycle instead."""
    p = Particles.disks([[0, 0], [2 * R, 0], [4 * R, 0]], R, 2650.0, fixed=True)
    counts = {}
    for hold in (False, True):
        sim = Simulation(p.take(np.arange(3)), planar=True, dt=1e-5, skin=0.1 * R)
        assert install_fatigue_bonds(sim, P) == 2
        b = sim.fatigue_bonds
        b.peak[:] = [[80e3, 80e3], [0.0, 0.0]]
        b.low[:] = 0.0
        b.ratchet[:] = [[0.0, 0.0], [0.0, 1e-9]]            # the second bond yielded in the sampled cycle
        counts[hold] = b.onset_of_unloading(jump=0.01, hold_while_yielding=hold)
        assert b.damage[1] == P.initial_damage and b.damage[0] > P.initial_damage
    assert counts[True] == 1 < counts[False]


def test_bonds_record_their_plastic_flow_per_cycle_and_extrapolate_it_on_request():
    """``ratchet`` sums |Δuᵖ| since the last cycle update; "extrapolated" repeats it over the jump (Eq. 22's damage,
    elastic opening lowered by the same displacement) while "frozen", the paper, leaves the yielded bond alone."""
    results = {}
    for plasticity in ("frozen", "extrapolated"):
        p = Particles.disks([[0, 0], [2 * R, 0], [4 * R, 0]], R, 2650.0, fixed=True)
        sim = Simulation(p, planar=True, dt=1e-5, skin=0.1 * R)
        install_fatigue_bonds(sim, P)
        sim.particles.v[2] = (2e-4, 0.0, 0.0)                   # the second bond is pulled slowly to yield
        while not sim.fatigue_bonds.yielded[1]:
            sim.step()
        b = sim.fatigue_bonds
        assert b.yielded[1] and b.plastic[0, 1] > 0
        assert np.array_equal(b.ratchet, b.plastic)              # no cycle update yet: all flow is this cycle's
        b.peak[:, 0], b.low[:, 0] = (80e3, 80e3), 0.0              # the first bond saw a fatigue cycle
        d, e_n, flow = b.damage.copy(), b.elastic_n.copy(), b.ratchet.copy()
        n = b.onset_of_unloading(jump=0.01, plasticity=plasticity)
        results[plasticity] = n
        if plasticity == "frozen":
            assert b.damage[1] == d[1] and b.elastic_n[1] == e_n[1]
        else:
            assert b.damage[1] == pytest.approx(damage_after(d[1], (n - 1) * flow[0, 1], (n - 1) * flow[1, 1], P),
                                                rel=1e-12)
            assert b.elastic_n[1] == pytest.approx(e_n[1] - (n - 1) * flow[0, 1], rel=1e-12)
            assert n > 1 and b.damage[1] > d[1]
        assert np.all(b.ratchet == 0.0) and not b.yielded.any()
    assert results["extrapolated"] <= results["frozen"]
    with pytest.raises(ValueError, match="plasticity"):
        sim.fatigue_bonds.onset_of_unloading(plasticity="ignored")


def test_cycle_jump_on_a_bonded_specimen_keeps_the_largest_damage_close_and_saves_cycles():
    """17 bonds, 25–75 kPa, C = 3·10⁻⁸ to a largest D of 0.3: ΔD_jump = 0.01 simulates a third of the cycles and
    keeps the largest damage within 2.5 % of the cycle-by-cycle run at the same cycle (measured 2.0 %). The mean
    damage deviates more (about 9 %): bonds whose peak stress sits near their fatigue threshold switch fatigue on
    and off from cycle to cycle as their neighbours soften, and a jump freezes that switch for N_jump cycles."""
    params = BondParameters(paris_coefficient=3e-8)
    runs = {}
    for jump in (None, 0.01):
        sim, _, loaded = bonded_bar(params)
        runs[jump] = cyclic_bar(sim, loaded, 25e3, 75e3, ramp_steps=100, jump=jump, target_damage=0.3)
    full, jumped = runs[None], runs[0.01]
    assert full["stopped"] == jumped["stopped"] == "target"
    assert jumped["simulated_cycles"] * 3 <= full["simulated_cycles"]
    assert history_deviation(jumped, full, "max_damage", start=params.initial_damage) < 0.025


def test_history_deviation_interpolates_the_reference():
    reference = {"cycles": [1, 2, 3, 4], "d": [0.02, 0.03, 0.04, 0.05]}
    assert history_deviation({"cycles": [2, 4], "d": [0.03, 0.05]}, reference, "d", start=0.01) == 0.0
    assert history_deviation({"cycles": [0.5], "d": [0.0165]}, reference, "d", start=0.01) == pytest.approx(0.1)
    assert np.isnan(history_deviation({"cycles": [9], "d": [0.1]}, reference, "d"))


def test_time_step_sees_the_bond_stiffness_and_removal_renumbers_bonds():
    p = Particles.disks([[0, 0], [2 * R, 0], [4 * R, 0]], R, 2650.0)
    sim = Simulation(p, planar=True, skin=0.1 * R)
    loose = sim.critical_time_step()
    assert install_fatigue_bonds(sim, P) == 2
    assert sim.critical_time_step() < loose
    sim.remove_particles(np.array([True, False, False]))
    b = sim.fatigue_bonds
    assert len(b) == 1 and (b.i[0], b.j[0]) == (0, 1)


def test_fatigue_bonds_refuse_a_periodic_cell_mixed_parameters_and_bad_input():
    p = Particles.spheres([[0.5, 0.5, 0.5], [0.5 + 2 * R, 0.5, 0.5]], R)
    sim = Simulation(p, periodic=Periodic([1.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match="periodic"):
        install_fatigue_bonds(sim, P)
    sim = bonded_pair()
    with pytest.raises(ValueError, match="share one BondParameters"):
        install_fatigue_bonds(sim, P.replace(cohesion=90e3), pairs=[[0, 1]], gap=0.0)
    with pytest.raises(ValueError, match="thickness"):
        install_fatigue_bonds(sim, P, thickness=0.0)
    with pytest.raises(TypeError, match="BondParameters"):
        install_fatigue_bonds(sim, {"kn": 1.0})
    sim, _, loaded = bonded_bar(P)
    with pytest.raises(ValueError, match="jump"):
        cyclic_bar(sim, loaded, 20e3, 60e3, jump=-0.01)
    with pytest.raises(ValueError, match="stress_min"):
        cyclic_bar(sim, loaded, 70e3, 60e3)
    with pytest.raises(ValueError, match="columns"):
        bonded_bar(P, columns=1)


@pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled bond update needs numba (extra 'fast')")
@pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled finish needs numba")
def test_the_compiled_finish_of_the_bond_update_is_the_numpy_one_to_the_last_bit():
    """After the return, the compiled loop (new e_n, e_s, σ, plastic flow, stress extremes, force and torques)
    repeats the NumPy lines' operations in their order: every array equal bit for bit, on the coarse beam under a
    sudden 200 N load where bonds yield and some e_s are zero."""
    from abrakit.experiments.bending import BeamSpec, four_point_beam

    beam = four_point_beam(BeamSpec(radius=5e-3), control="force", fixture="pads")
    beam.set_load(200.0)
    beam.step(300)
    b, p = beam.sim.fatigue_bonds, beam.sim.particles
    trial = b._compiled_trial(p.x, p.v, p.w, p.radius, beam.sim.dt)
    du_n, du_s, damage, sigma_n, sigma_s, trial_n, trial_s, size_s, n, arm_i, arm_j, _ = trial
    assert np.count_nonzero(du_n) + np.count_nonzero(du_s) > 0              # some bonds flow in this step
    args = (trial_n, trial_s, size_s, du_n, du_s, damage, sigma_n, sigma_s, n, arm_i, arm_j)
    (new_a, *loads_a), (new_b, *loads_b) = (b._finish(*args, compiled=c) for c in (False, True))
    for name in ("elastic_n", "elastic_s", "damage", "sigma", "plastic", "peak", "low", "ratchet"):
        assert np.array_equal(getattr(new_a, name), getattr(new_b, name)), name
    for a, c in zip(loads_a, loads_b, strict=True):
        assert np.array_equal(a, c)


def test_the_compiled_bond_update_gives_the_numpy_update_through_yielding(monkeypatch):
    """Issue 37: the compiled update (kinematics, turn into the contact plane, trial stresses and yield test in one
    loop, the yielding bonds' return in another: :mod:`abrakit.fatigue._return_kernel`) against the NumPy update on
    the coarse beam under a sudden 200 N load, where bonds yield and damage: the same particles to round-off and the
    same bonds to the return's tolerance, and the same answer from one call on the same state. The compiled return
    stops each bond at its own tolerance (10⁻¹² of the scaled residual), the vectorised one iterates every bond
    until the slowest has converged; measured after 600 steps: the bonds' fields within 1·10⁻¹⁰ of their largest
    value (bit for bit while only the elastic trial was compiled), the positions within 2·10⁻¹⁶ m."""
    from abrakit.dem import fatigue_bonds
    from abrakit.experiments.bending import BeamSpec, four_point_beam

    runs = []
    for compiled in (False, True):
        monkeypatch.setattr(fatigue_bonds, "COMPILED_UPDATE", compiled)   # update()'s default
        beam = four_point_beam(BeamSpec(radius=5e-3), control="force", fixture="pads")
        beam.set_load(200.0)
        beam.step(600)
        runs.append((beam.sim.particles.x.copy(), beam.sim.fatigue_bonds))
    (x0, b0), (x1, b1) = runs
    assert b0.yielded.sum() > 5 and b0.damage.max() > 0.05              # the plastic return was exercised
    assert np.allclose(x1, x0, rtol=0, atol=1e-15)
    for name in ("damage", "plastic", "elastic_n", "elastic_s", "sigma"):
        a, b = getattr(b0, name), getattr(b1, name)
        assert np.abs(b - a).max() <= 1e-9 * np.abs(a).max(), name
    p = beam.sim.particles
    one = [b1.update(p.x, p.v, p.w, p.radius, beam.sim.dt, compiled=c) for c in (False, True)]
    for a, b in zip(one[0][1:], one[1][1:], strict=True):
        assert np.abs(b - a).max() <= 1e-9 * np.abs(a).max()
