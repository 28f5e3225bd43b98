"""Energy: O(Δt²) oscillation and no drift without damping; bookkeeping closes with damping, friction, walls."""

import numpy as np
import pytest

from abrakit.dem import Linear, Particles, Simulation, Walls, energy_balance, settling


def compressed_lattice(dt_factor, *, m=4, squeeze=0.01, seed=0, law=None):
    """m³ spheres on a simple cubic lattice squeezed by 1 % between fixed walls, with small random velocities:
    every contact stays closed, so the energy surface is smooth and leap-frog is symplectic on it."""
    rng = np.random.default_rng(seed)
    r, kn = 0.01, 1e5
    a = 2 * r * (1 - squeeze)
    x = np.stack(np.meshgrid(*(np.arange(m),) * 3, indexing="ij"), -1).reshape(-1, 3) * a + r
    p = Particles.spheres(x, r, 2650.0, kn=kn, friction=0.0)
    p.v[:] = rng.normal(0, 0.001 * r * np.sqrt(kn / p.mass[0]), x.shape)
    walls = Walls.box(x.min(0) - r * (1 - squeeze), x.max(0) + r * (1 - squeeze))
    return Simulation(p, walls=walls, law=law or Linear(), dt=dt_factor * np.sqrt(p.mass[0] / kn))


def energy_history(sim, steps):
    E = np.empty(steps)
    for s in range(steps):
        sim.step()
        E[s] = sim.energy.stored
    return E


def test_energy_error_is_second_order_in_dt():
    """Same physical time at Δt, Δt/2, Δt/4: the largest deviation falls by 4 each time."""
    dev = []
    for f in (0.2, 0.1, 0.05):
        E = energy_history(compressed_lattice(f, m=3), int(200 / f))
        dev.append(np.max(np.abs(E - E[0])) / E[0])
    assert 3.5 < dev[0] / dev[1] < 4.5 and 3.5 < dev[1] / dev[2] < 4.5
    assert dev[0] < 1e-4


def test_no_energy_drift_over_ten_thousand_steps():
    sim = compressed_lattice(0.2, m=3)
    E = energy_history(sim, 10_000)
    dev = (E - E[0]) / E[0]
    drift = np.polyfit(np.arange(len(E)), dev, 1)[0] * len(E)
    assert np.max(np.abs(dev)) < 1e-4
    assert abs(drift) < 0.02 * np.max(np.abs(dev))
    assert (sim.contacts.overlap > 0).all()                       # the premise: no contact opened


def test_colliding_gas_keeps_its_energy():
    """Contacts open and close (a kink in the linear law): each collision leaves an O(Δt²) residual of random
    sign, so over 10⁴ steps the energy wanders but does not drift away."""
    rng = np.random.default_rng(3)
    r = 0.01
    x = np.stack(np.meshgrid(*(np.arange(3),) * 3, indexing="ij"), -1).reshape(-1, 3) * 2.5 * r + 1.25 * r
    p = Particles.spheres(x, r, 2650.0, v=rng.normal(0, 0.5, x.shape), kn=1e5, friction=0.0)
    sim = Simulation(p, walls=Walls.box((0, 0, 0), (7.5 * r,) * 3), dt=0.05 * np.sqrt(p.mass[0] / 1e5))
    E = energy_history(sim, 10_000)
    assert np.max(np.abs(E - E[0])) / E[0] < 2e-3


def test_bookkeeping_closes_when_settling_with_damping_and_friction():
    sim, summary = settling(60, seed=2, steps=4000)
    e = summary["energy"]
    released = e["initial"] - e["potential"]
    assert e["local_damping"] > 0 and e["dashpot"] > 0 and e["friction"] > 0     # every mechanism worked
    assert e["dissipated"] > 0.5 * released
    assert abs(e["error"]) < 2e-3 * released


def test_bookkeeping_closes_with_moving_wall_and_dashpots():
    """Input = work of a moving wall: work = Δ(stored) + dissipated (dashpots, slip, local damping)."""
    rng = np.random.default_rng(1)
    r = 0.005
    x = np.stack(np.meshgrid(*(np.arange(4),) * 3, indexing="ij"), -1).reshape(-1, 3) * 2.05 * r + 1.1 * r
    x += rng.normal(0, 0.02 * r, x.shape)
    p = Particles.spheres(x, r, 2650.0, kn=1e5, friction=0.3)
    walls = Walls.box((0, 0, 0), (8.4 * r,) * 3, friction=0.3)
    walls.velocity[walls.index("zmax")] = (0, 0, -0.05)
    sim = Simulation(p, walls=walls, law=Linear(damping_normal=0.2, damping_shear=0.2), local_damping=0.1)
    sim.run(3000)
    e = energy_balance(sim)
    assert e["work_walls"] > 0 and e["dashpot"] > 0 and e["friction"] > 0 and e["elastic"] > 0
    assert abs(e["error"]) < 5e-3 * e["work_walls"]


def test_energy_balance_needs_a_step():
    sim = Simulation(Particles.spheres([[0, 0, 0]], 0.01))
    with pytest.raises(ValueError, match="no step"):
        energy_balance(sim)
