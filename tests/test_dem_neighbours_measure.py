"""Verlet lists (history across rebuilds), walls and servo, and the measurements (stress, fabric, strain)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.dem import Linear, Particles, Simulation, Walls, coordination_number, dense_packing, porosity
from abrakit.dem.measure import box_strain, contact_counts, love_weber_stress, wall_stress
from abrakit.dem.neighbours import candidate_pairs, transfer_history
from abrakit.dem.state import ContactSet
from abrakit.identification import measured_contact_density


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 60), st.integers(0, 10_000), st.floats(0.0, 0.01))
def test_candidate_pairs_match_brute_force(n, seed, skin):
    rng = np.random.default_rng(seed)
    x = rng.uniform(0, 0.1, (n, 3))
    r = rng.uniform(0.005, 0.015, n)
    i, j = candidate_pairs(x, r, skin)
    d = np.linalg.norm(x[:, None] - x[None], axis=-1)
    bi, bj = np.nonzero(np.triu(d < r[:, None] + r[None] + skin, 1))
    assert set(zip(i.tolist(), j.tolist(), strict=True)) == set(zip(bi.tolist(), bj.tolist(), strict=True))
    assert np.all(np.diff(i * n + j) > 0)                                 # sorted keys


def test_transfer_history_matches_keys():
    old = ContactSet.empty_history([0, 0, 1], [1, 2, 2], 3)
    old.ft[:] = [[1, 2, 3], [0, 0, 0], [0, 0, 0]]
    old.bonded[:] = [False, True, False]
    new = transfer_history(old, ContactSet.empty_history([0, 1], [2, 2], 3))
    assert new.ft[0].tolist() == [2, 3] and new.bonded.tolist() == [True, False]


def test_results_do_not_depend_on_the_skin():
    """The skin only decides how often the list is rebuilt, never the physics (history is carried over)."""
    runs = []
    for skin in (2e-5, 5e-4):
        sim = dense_packing(64, seed=3, radius=0.001, agitation=0.05, skin=skin, local_damping=0.2, dt=3e-7)
        sim.run(300)
        runs.append(sim)
    assert runs[0].neighbours.builds > 3 * runs[1].neighbours.builds
    assert np.allclose(runs[0].particles.x, runs[1].particles.x, rtol=0, atol=1e-12)
    assert np.allclose(runs[0].particles.w, runs[1].particles.w, rtol=1e-8, atol=1e-9)


def test_tangential_history_survives_rebuild():
    p = Particles.spheres([[0, 0, 0], [0.0199, 0, 0]], 0.01, kn=1e5, v=[[0, 0, 0], [0, 0.001, 0]], fixed=True)
    sim = Simulation(p, dt=1e-5, skin=1e-3)
    sim.run(10)
    ft = sim.contacts.ft.copy()
    sim.rebuild()
    assert np.array_equal(sim.contacts.ft, ft) and np.abs(ft).max() > 0


def simple_cubic(m=3, squeeze=0.01, r=0.01, kn=1e5):
    """m³ spheres on a simple cubic lattice squeezed uniformly between fixed walls: every contact (internal,
    K = k/2 with overlap 2rs; wall, K = k with overlap rs) carries f = k r s, so the packing is in equilibrium."""
    a = 2 * r * (1 - squeeze)
    x = np.stack(np.meshgrid(*(np.arange(m),) * 3, indexing="ij"), -1).reshape(-1, 3) * a + r
    p = Particles.spheres(x, r, 2650.0, kn=kn, friction=0.5)
    walls = Walls.box(x.min(0) - r * (1 - squeeze), x.max(0) + r * (1 - squeeze))
    sim = Simulation(p, walls=walls, dt=1e-6)
    sim.step()
    return sim, kn * r * squeeze / a**2


def test_love_weber_equals_wall_stress_on_a_lattice():
    sim, stress = simple_cubic()
    V = sim.walls.box_volume()
    sigma = love_weber_stress(sim, V)
    assert np.allclose(sigma, -stress * np.eye(3), rtol=1e-6, atol=1e-6 * stress)   # tension positive
    assert np.allclose(love_weber_stress(sim, V, compression_positive=True), stress * np.eye(3), rtol=1e-6)
    assert wall_stress(sim, "zmax") == pytest.approx(stress, rel=1e-6)
    assert np.allclose(sim.walls.box_stress(), stress, rtol=1e-6)


def test_fabric_of_a_lattice():
    sim, _ = simple_cubic(m=4)
    assert coordination_number(sim) == pytest.approx(6 * 3 / 4)          # Z = 2C/N, C = 3 m² (m − 1)
    assert coordination_number(sim, mechanical=True) == pytest.approx(4.5)
    V = sim.walls.box_volume()
    assert measured_contact_density(contact_counts(sim).sum() / 2, V) == pytest.approx(3 * 16 * 3 / V)  # (5.29)
    assert porosity(sim, V) == pytest.approx(1 - 64 * 4 / 3 * np.pi * 0.01**3 / V)


def test_love_weber_matches_walls_in_a_relaxed_random_packing():
    sim = dense_packing(500, seed=1, spread=0.1, overlap=0.003, agitation=0.0, local_damping=0.7)
    sim.run(1500)
    V = sim.walls.box_volume()
    lw = np.diag(love_weber_stress(sim, V, compression_positive=True))
    assert np.allclose(lw, sim.walls.box_stress(), rtol=0.03)


def test_servo_converges_on_a_single_sphere():
    """A sphere pressed between a floor and a servo wall: F = σ_target A exactly once settled."""
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1), name="floor")
    top = walls.add((0, 0, 0.0205), (0, 0, -1), name="top")
    walls.add_servo(top, 1e5, 1e-4, max_speed=0.1)
    p = Particles.spheres([[0, 0, 0.01]], 0.01, 2650.0, kn=1e6)
    sim = Simulation(p, walls=walls, local_damping=0.7)
    sim.run(3000)
    assert float(walls.normal_force(top)) / 1e-4 == pytest.approx(1e5, rel=1e-6)
    assert float(walls.normal_force(0)) == pytest.approx(10.0, rel=1e-6)


def test_servo_holds_the_target_stress_on_a_packing():
    sim = dense_packing(216, seed=2, overlap=0.0, agitation=0.0, local_damping=0.7)
    for name, axis in (("xmax", "x"), ("ymax", "y"), ("zmax", "z")):
        sim.walls.add_servo(name, 5e5, lambda w, a=axis: w.box_area(a), max_speed=0.2)
    history = []
    sim.run(4000, callback=lambda s: history.append([wall_stress(s, k) for k in ("xmax", "ymax", "zmax")]))
    late = np.array(history[-500:])
    assert np.allclose(late.mean(axis=0), 5e5, rtol=0.05)
    assert np.all(late.std(axis=0) < 0.02 * 5e5)


def test_prescribed_wall_velocity_and_box_strain():
    sim, _ = simple_cubic()
    L0 = sim.walls.box_lengths()
    sim.walls.velocity[sim.walls.index("zmax")] = (0, 0, -0.01)
    sim.run(100)
    eps = box_strain(sim.walls, L0)
    assert eps[2] == pytest.approx(-0.01 * 100 * sim.dt / L0[2]) and eps[0] == 0.0
    with pytest.raises(ValueError, match="box"):
        w = Walls()
        w.add((0, 0, 0), (0, 0, 1))
        wall_stress(Simulation(Particles.spheres([[0, 0, 0.02]], 0.01), walls=w), 0)


def test_frictional_wall_holds_a_sphere_on_a_slope():
    """Gravity tilted by 20° on a wall with μ = 0.5 > tan 20°: the sphere sticks (rolls only if free to
    rotate: here the slope test is of the Coulomb limit, so the sphere is given a huge inertia)."""
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1), friction=0.5)
    g = 9.81 * np.array([np.sin(np.radians(20)), 0, -np.cos(np.radians(20))])
    p = Particles.spheres([[0, 0, 0.01]], 0.01, 2650.0, kn=1e5, friction=0.5)
    p.inertia[:] *= 1e9
    sim = Simulation(p, walls=walls, gravity=g, law=Linear(damping_normal=0.5, damping_shear=0.5))
    sim.run(3000)
    assert abs(p.v[0, 0]) < 1e-4
    p.friction[:] = walls.friction[:] = 0.3                            # μ < tan 20° = 0.364: slides
    sim.rebuild()
    sim.run(3000)
    assert p.v[0, 0] == pytest.approx(9.81 * (np.sin(np.radians(20)) - 0.3 * np.cos(np.radians(20)))
                                      * 3000 * sim.dt, rel=0.02)


def test_radius_expansion_builds_stress():
    """Growing the radii by 2 % in a closed box (radius expansion, Ch. 5.3) creates contact stress; masses
    follow at constant density."""
    sim = dense_packing(125, seed=6, spread=0.0, overlap=-0.02, agitation=0.0, local_damping=0.7)
    m0 = sim.particles.mass.copy()
    sim.run(10)
    assert np.allclose(sim.walls.box_stress(), 0.0)
    sim.scale_radii(1.04)
    sim.run(500)
    assert np.all(sim.walls.box_stress() > 0)
    assert np.allclose(sim.particles.mass, m0 * 1.04**3)
    with pytest.raises(ValueError, match="factor"):
        sim.scale_radii(0.0)
