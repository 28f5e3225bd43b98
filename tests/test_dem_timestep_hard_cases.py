"""Critical time step (seed 002 Eq. 11, 12) and the hard cases: overlaps, escapes, bad input, stiffness ratios."""

import warnings

import numpy as np
import pytest

from abrakit.dem import HertzMindlin, Linear, Particles, Simulation, TimeStepError, Walls, energy_balance
from abrakit.dem.integrate import critical_time_step
from abrakit.dem.simulation import MAX_TRAVEL, ParticleEscapeError


def resting_sphere(**kw):
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1))
    p = Particles.spheres([[0, 0, 0.01]], 0.01, 2650.0, kn=1e5, kt=4e4)
    return p, Simulation(p, walls=walls, skin=0.002, **kw)


def test_critical_time_step_of_a_sphere_on_a_wall():
    """One contact: Δt_crit = min(√(m/K^n), √(I/(K^t r²))) (seed 002 Eq. 12)."""
    p, sim = resting_sphere()
    m, I = p.mass[0], p.inertia[0]
    expected = min(np.sqrt(m / 1e5), np.sqrt(I / (4e4 * 0.01**2)))
    assert sim.critical_time_step() == pytest.approx(expected)
    assert sim.dt == pytest.approx(0.8 * expected)                    # automatic: safety · Δt_crit


def test_critical_time_step_function_sums_stiffness():
    dt = critical_time_step(np.array([2.0, 8.0]), np.array([1.0, 1.0]), np.array([2.0, 2.0]), np.zeros(2))
    assert dt == pytest.approx(1.0)
    assert critical_time_step(np.ones(1), np.ones(1), np.zeros(1), np.zeros(1)) == np.inf


def test_step_above_critical_is_refused():
    _, sim = resting_sphere()
    dt_crit = sim.critical_time_step()
    with pytest.raises(TimeStepError, match="critical time step"):
        resting_sphere(dt=1.5 * dt_crit)


def test_step_above_critical_is_reduced_on_request():
    _, sim = resting_sphere()
    dt_crit = sim.critical_time_step()
    with pytest.warns(RuntimeWarning, match="reduced"):
        p, sim = resting_sphere(dt=3 * dt_crit, dt_policy="reduce", gravity=(0, 0, -9.81))
    assert sim.dt == pytest.approx(0.8 * dt_crit)
    sim.run(2000)
    assert abs(p.x[0, 2] - 0.01) < 1e-3                                  # still resting, not exploded


def test_assigning_an_unstable_step_is_refused():
    p, sim = resting_sphere()
    with pytest.raises(TimeStepError):
        sim.dt = 2.5 * np.sqrt(p.mass[0] / 1e5)
    sim.dt = 0.5 * sim.critical_time_step()                              # a stable value is accepted
    assert not sim.auto_dt


def test_divergence_is_stopped_with_a_clear_error():
    """Last line of defence: if the leap-frog diverges anyway (here the private step is forced beyond 2/ω on a
    bonded pair), the run stops at the next neighbour check — with a time-step error, or, had positions become
    non-finite first, a FloatingPointError — instead of carrying NaNs."""
    from abrakit.dem import install_contact_bonds
    from abrakit.dem.neighbours import VerletList

    p = Particles.spheres([[0, 0, 0], [0.02, 0, 0]], 0.01, 2650.0, kn=2e5, v=[[0, 0, 0], [0.01, 0, 0]])
    sim = Simulation(p, skin=0.001)
    install_contact_bonds(sim, 1e30, 1e30)
    sim.auto_dt, sim._dt = False, 3.0 * np.sqrt(p.mass[0] / 2 / 1e5)
    with pytest.raises((TimeStepError, FloatingPointError), match="critical"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            sim.run(5000)
    verlet = VerletList(0.001)
    verlet.mark_built(np.zeros((2, 3)))
    with pytest.raises(FloatingPointError, match="critical"):
        verlet.needs_rebuild(np.array([[0, 0, 0], [np.nan, 0, 0]]))


def test_automatic_step_follows_stiffening_hertz_contacts():
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1))
    p = Particles.spheres([[0, 0, 0.0099]], 0.01, 2650.0, shear_modulus=1e8, poisson=0.3)
    sim = Simulation(p, walls=walls, law=HertzMindlin(), skin=1e-4)
    dt0 = sim.dt
    p.x[0, 2] = 0.0095                                                    # 5 % overlap: much stiffer
    sim.rebuild()
    assert sim.dt < 0.7 * dt0


def test_zero_or_negative_input_is_rejected():
    with pytest.raises(ValueError, match="radius"):
        Particles.spheres([[0, 0, 0]], 0.0)
    with pytest.raises(ValueError, match="radius"):
        Particles.spheres([[0, 0, 0], [1, 0, 0]], [0.01, -0.01])
    with pytest.raises(ValueError, match="density"):
        Particles.spheres([[0, 0, 0]], 0.01, 0.0)
    with pytest.raises(ValueError, match="x must be finite"):
        Particles.spheres([[0, np.nan, 0]], 0.01)
    with pytest.raises(ValueError, match="x must have shape"):
        Particles.spheres([[0, 0]], 0.01)
    with pytest.raises(ValueError, match="kn"):
        Particles.spheres([[0, 0, 0]], 0.01, kn=0.0)
    with pytest.raises(ValueError, match="friction"):
        Particles.spheres([[0, 0, 0]], 0.01, friction=-0.1)
    with pytest.raises(ValueError, match="poisson"):
        Particles.spheres([[0, 0, 0]], 0.01, poisson=0.5)
    with pytest.raises(ValueError, match="non-empty"):
        Simulation(Particles.spheres(np.zeros((0, 3)), 0.01))
    with pytest.raises(ValueError, match="normal"):
        Walls().add((0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="local_damping"):
        Simulation(Particles.spheres([[0, 0, 0]], 0.01), local_damping=1.0)


def test_coincident_centres_are_rejected():
    with pytest.raises(ValueError, match="coincident centres"):
        Simulation(Particles.spheres([[0, 0, 0], [0, 0, 0]], 0.01))


def test_initial_overlap_is_released_as_elastic_energy():
    """Two spheres at rest overlapping by U₀ fly apart with relative speed U₀ ω₀ (½K U₀² = ½ m* v²)."""
    r, K, U0 = 0.01, 1e5, 1e-4
    p = Particles.spheres([[0, 0, 0], [2 * r - U0, 0, 0]], r, 2650.0, kn=2 * K)
    sim = Simulation(p, skin=r, dt=0.02 * np.sqrt(p.mass[0] / K))
    sim.run(200)
    m_star = p.mass[0] / 2
    assert p.v[1, 0] - p.v[0, 0] == pytest.approx(U0 * np.sqrt(K / m_star), rel=1e-3)
    assert abs(energy_balance(sim)["relative_error"]) < 1e-3


def test_deep_initial_overlaps_stay_finite():
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 0.03, (40, 3))                                    # heavily overlapping cloud
    p = Particles.spheres(x, 0.01, 2650.0, kn=1e5)
    sim = Simulation(p, local_damping=0.7)
    sim.run(300)
    assert np.all(np.isfinite(p.x)) and np.all(np.isfinite(p.v))


def _escaping(escape, with_escapee=True):
    """A sliding contact (particles 0 and 2) far from particle 1, which flies out of the domain."""
    x = [[0.05, 0.05, 0.05], [0.2, 0.05, 0.05], [0.05, 0.05, 0.0699]]
    v = [[0, 0, 0], [5.0, 0, 0], [0.02, 0.01, 0]]
    keep = [0, 1, 2] if with_escapee else [0, 2]
    p = Particles.spheres(np.array(x)[keep], 0.01, 2650.0, v=np.array(v)[keep], kn=1e5, friction=0.5,
                          fixed=np.array([True, False, False])[keep])
    return p, Simulation(p, domain=((0, 0, 0), (0.25, 0.1, 0.1)), escape=escape, skin=0.005, dt=2e-5,
                         gravity=(0, 0, -9.81), law=Linear(damping_normal=0.5))


def test_escaping_particle_raises():
    p, sim = _escaping("raise")
    with pytest.raises(ParticleEscapeError, match="left the domain"):
        sim.run(2000)


def test_escaping_particle_removed_keeps_the_rest():
    """Removal re-indexes contacts without losing their history: the remaining pair moves exactly as if the
    escapee had never existed."""
    _, sim = _escaping("remove")
    sim.run(2000)
    _, alone = _escaping("remove", with_escapee=False)
    alone.run(2000)
    assert sim.removed == 1 and len(sim.particles) == 2
    assert np.abs(sim.contacts.ft).max() > 0                              # a loaded tangential spring
    assert np.allclose(sim.particles.x, alone.particles.x, rtol=0, atol=1e-12)
    assert np.allclose(sim.contacts.ft, alone.contacts.ft, rtol=1e-9, atol=1e-12)


def test_huge_stiffness_ratio_is_stable():
    """Soft (k) and stiff (10⁶ k) spheres in one box: the automatic step follows the stiffest contact."""
    rng = np.random.default_rng(4)
    x = np.stack(np.meshgrid(*(np.arange(3),) * 3, indexing="ij"), -1).reshape(-1, 3) * 0.021 + 0.0105
    kn = np.where(np.arange(27) % 2 == 0, 1e3, 1e9)
    p = Particles.spheres(x, 0.01, 2650.0, kn=kn, v=rng.normal(0, 0.1, (27, 3)), friction=0.3)
    sim = Simulation(p, walls=Walls.box((0, 0, 0), (0.063,) * 3, kn=1e12))
    assert sim.dt < 0.8 * np.sqrt(p.mass[0] / 1e9) * 1.001
    sim.run(3000)
    e = energy_balance(sim)
    assert abs(e["relative_error"]) < 1e-2 and e["kinetic"] < 2 * e["initial"]


def test_allowed_unstable_step_is_kept_with_one_warning_and_then_stopped():
    """``dt_policy="allow"`` keeps a step above the critical one (to study the instability) and warns once; the
    diverging pair leaves its domain within a few dozen steps and the run stops with a clear error."""
    from abrakit.dem import install_contact_bonds
    from abrakit.dem.simulation import ParticleEscapeError

    p = Particles.spheres([[0, 0, 0], [0.02, 0, 0]], 0.01, 2650.0, kn=2e5, v=[[0, 0, 0], [0.01, 0, 0]])
    dt = 3.0 * np.sqrt(p.mass[0] / 2 / 1e5)
    with pytest.warns(RuntimeWarning, match="allow") as record:
        sim = Simulation(p, skin=0.001, dt=dt, dt_policy="allow", domain=((-1, -1, -1), (1, 1, 1)))
        install_contact_bonds(sim, 1e30, 1e30)
        sim.rebuild()
        assert sim.dt == dt
        with pytest.raises(ParticleEscapeError, match="left the domain"):
            sim.run(200, progress=False)
    assert sum("allow" in str(w.message) for w in record) == 1


def test_deep_initial_overlap_is_announced_with_the_speed_it_releases():
    """Two spheres starting 30 % into each other: a warning says so and predicts the separation speed
    U √(K/m*), which the undamped linear spring then delivers (energy conservation)."""
    r = 0.01
    p = Particles.spheres([[0, 0, 0], [2 * r - 0.3 * r, 0, 0]], r, 2650.0, kn=2e5)
    with pytest.warns(RuntimeWarning, match=r"overlapping by up to 30 %") as record:
        sim = Simulation(p, safety=0.05)                             # fine steps: the release is resolved
    predicted = float(str(record[0].message).split("up to ")[2].split(" m/s")[0])
    sim.run(2000, progress=False)
    separation = np.linalg.norm(p.v[1] - p.v[0])
    assert separation == pytest.approx(predicted, rel=2e-2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        from abrakit.dem import dense_packing

        dense_packing(64)                                               # 0.5 % overlaps: no warning


def _head_on(speed, overlap_fraction=0.3, dt=None, **options):
    """Sphere 1 flies at ``speed`` onto sphere 0 (both free, r = 1 cm); the spring is stiff enough to stop the pair
    at an overlap of ``overlap_fraction`` r (½ m* v² = ½ K U²)."""
    r = 0.01
    p = Particles.spheres([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]], r, 2650.0, v=[[0, 0, 0], [-speed, 0, 0]])
    m_star = p.mass[0] / 2
    K = m_star * speed**2 / (overlap_fraction * r) ** 2
    p = Particles.spheres(p.x, r, 2650.0, v=p.v, kn=2 * K)
    return p, Simulation(p, skin=r, dt=dt, domain=((-5, -1, -1), (5, 1, 1)), track_energy=False, **options)


@pytest.mark.parametrize("speed", [100.0, 1000.0])
def test_a_fast_particle_neither_tunnels_nor_gains_energy(speed):
    """The automatic step keeps the fastest particle below a quarter of the smallest radius per step, so the
    contact is seen and resolved: the pair rebounds (sphere 1 comes back, it never passes sphere 0) and the overlap
    never exceeds half a radius. The relative speed after the elastic impact equals the one before to 2 %: with
    Δt = 0.8 Δt_crit a linear contact lasts about four steps, and the leap-frog's error at its start and end does
    not depend on the speed (ω Δt is the same), so a fast impact gains no more than a slow one."""
    p, sim = _head_on(speed)
    largest = 0.0
    for _ in range(4000):
        sim.step()
        largest = max(largest, 0.02 - abs(p.x[1, 0] - p.x[0, 0]))
        if p.v[1, 0] - p.v[0, 0] > 0 and p.x[1, 0] - p.x[0, 0] > 0.03:
            break
    assert sim.dt <= MAX_TRAVEL * 0.01 / speed * (1 + 1e-9)
    assert p.x[1, 0] > p.x[0, 0]                                           # on its own side: no tunnelling
    assert p.v[1, 0] - p.v[0, 0] == pytest.approx(speed, rel=2e-2)         # rebound, within the step's error
    assert largest < 0.5 * 0.01


def test_a_fixed_step_too_long_for_the_fastest_particle_is_refused():
    """A fixed step in which a 1000 m/s sphere would travel a whole radius: refused by name, or reduced to the
    travel limit with a warning (dt_policy="reduce")."""
    with pytest.raises(TimeStepError, match="fastest particle"):
        _head_on(1000.0, dt=1e-5)
    with pytest.warns(RuntimeWarning, match="fastest particle"):
        _, sim = _head_on(1000.0, dt=1e-5, dt_policy="reduce")
    assert sim.dt <= MAX_TRAVEL * 0.01 / 1000.0 * (1 + 1e-9)
    with pytest.warns(RuntimeWarning, match="exceeds the critical time step .* is kept"):   # 'allow' keeps it,
        _, sim = _head_on(1000.0, dt=1e-5, dt_policy="allow")                          # warning as before
    assert sim.dt == 1e-5


def test_hertz_impact_at_high_speed_keeps_the_travel_limit():
    """Hertz contacts stiffen with the overlap, and before the impact Δt_crit is estimated at 1 % overlap: at
    3000 m/s the travel limit, not Δt_crit, sets the first step (a quarter radius, not more)."""
    r = 0.01
    p = Particles.spheres([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]], r, 2650.0, v=[[0, 0, 0], [-3000.0, 0, 0]])
    sim = Simulation(p, law=HertzMindlin(), skin=r, domain=((-5, -1, -1), (5, 1, 1)), track_energy=False)
    sim.step()
    assert sim.dt == pytest.approx(MAX_TRAVEL * r / 3000.0, rel=1e-9)
    assert sim.dt < sim.safety * sim.critical_time_step()
