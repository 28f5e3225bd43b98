"""Clumps (rigid multi-sphere grains), 2D disks, reproducibility, VTU/CSV output."""

import numpy as np
import pytest

from abrakit.dem import Linear, Particles, Simulation, Walls, dense_packing, settling
from abrakit.dem.clumps import clump_particles, dyad, make_clumps, peanut
from abrakit.dem.output import HistoryWriter, VtuWriter, callbacks
from abrakit.dem.state import sphere_mass
from abrakit.io import read_curve


def test_dyad_mass_properties():
    r, s = 0.01, 0.012
    p = clump_particles([[0, 0, 0]], dyad(r, s), 2650.0)
    c = make_clumps(p)
    m = float(sphere_mass(r, 2650.0))
    assert c.mass[0] == pytest.approx(2 * m)
    own = 0.4 * m * r**2
    assert np.sort(c.inertia[0]) == pytest.approx(sorted([2 * own, 2 * own + 2 * m * (s / 2) ** 2,
                                                           2 * own + 2 * m * (s / 2) ** 2]))


def test_internal_contacts_are_skipped():
    """Members overlap by half a radius; a free clump at rest stays exactly at rest."""
    p = clump_particles([[0, 0, 0], [0.05, 0, 0]], peanut(0.01), 2650.0, rng=np.random.default_rng(0))
    x0 = p.x.copy()
    sim = Simulation(p)
    sim.run(200)
    assert len(sim.contacts) == 0
    assert np.allclose(sim.particles.x, x0, rtol=0, atol=1e-15)
    assert np.abs(sim.particles.v).max() < 1e-15


def test_torque_free_clump_keeps_angular_momentum_and_energy():
    p = clump_particles([[0, 0, 0]], peanut(0.01, 0.012), 2650.0, rng=np.random.default_rng(1))
    p.w[:] = (3.0, 20.0, -7.0)                                    # not about a principal axis: it tumbles
    sim = Simulation(p, dt=5e-5)
    c = sim.clumps
    L0 = c.L.copy()
    E0 = c.kinetic_energy()
    gaps = np.linalg.norm(p.x[1:] - p.x[:-1], axis=1)
    sim.run(6000)
    assert np.allclose(c.L, L0, rtol=1e-12, atol=0)
    assert c.kinetic_energy() == pytest.approx(E0, rel=1e-3)
    assert np.allclose(np.linalg.norm(p.x[1:] - p.x[:-1], axis=1), gaps, rtol=1e-10)   # rigid
    assert np.allclose(c.R[0] @ c.R[0].T, np.eye(3), atol=1e-12)


def test_clump_lies_down_on_the_floor():
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1), friction=0.5)
    p = clump_particles([[0, 0, 0.03]], dyad(0.01, 0.015), 2650.0, kn=1e5, friction=0.5)
    p.x[:] = [[0, 0, 0.025], [0.0106, 0, 0.0356]]                # tilted 45°
    p.clump[:] = 0
    sim = Simulation(p, walls=walls, gravity=(0, 0, -9.81), local_damping=0.7)
    sim.run(6000)
    assert p.x[:, 2] == pytest.approx([0.01, 0.01], abs=2e-4)     # both lobes on the floor
    assert np.abs(sim.clumps.v).max() < 1e-3


def test_clump_sphere_collision_conserves_momentum():
    p1 = clump_particles([[0, 0, 0]], dyad(0.01), 2650.0, kn=1e5, friction=0.4)
    p2 = Particles.spheres([[0.004, 0.03, 0.002]], 0.01, 2650.0, v=[[0, -1.0, 0]], kn=1e5, friction=0.4)
    p = Particles.concatenate(p1, p2)
    sim = Simulation(p, law=Linear(damping_normal=0.1))
    momentum = lambda: sim.clumps.mass @ sim.clumps.v + p.mass[2] * p.v[2]
    P0 = momentum()
    sim.run(1500)
    assert np.allclose(momentum(), P0, atol=1e-12)
    assert np.linalg.norm(sim.clumps.v[0]) > 0.1                    # it was hit


def test_two_dimensional_disks():
    """Disks in the x–y plane: duration π/ω₀ with the disk mass ρπr²t, and no motion out of the plane."""
    r, t, K = 0.01, 0.005, 1e5
    p = Particles.disks([[-0.0101, 0], [0.0101, 0.002]], r, 2650.0, thickness=t, kn=2 * K,
                        v=[[0.5, 0, 0.3], [-0.5, 0, 0]], friction=0.3)
    sim = Simulation(p, planar=True, dt=1e-6, skin=r)
    m = 2650.0 * np.pi * r**2 * t
    assert p.mass[0] == pytest.approx(m) and p.inertia[0] == pytest.approx(0.5 * m * r**2)
    sim.run(3000)
    assert np.all(p.x[:, 2] == 0.0) and np.all(p.v[:, 2] == 0.0) and np.all(p.w[:, :2] == 0.0)
    assert np.abs(p.w[:, 2]).max() > 0                             # friction spun them about z


def test_runs_are_reproducible_from_the_seed():
    a = settling(40, seed=7, steps=300)[0].particles.x
    b = settling(40, seed=7, steps=300)[0].particles.x
    c = settling(40, seed=8, steps=300)[0].particles.x
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def test_vtu_and_history_output(tmp_path):
    import meshio

    sim, _ = settling(30, seed=0, steps=200)
    vtu = VtuWriter(tmp_path / "vtu")
    history = HistoryWriter(tmp_path / "history.csv")
    sim.run(100, callback=callbacks(vtu, history), every=50)
    files = sorted((tmp_path / "vtu").glob("*.vtu"))
    assert len(files) == 2 and (tmp_path / "vtu" / "particles.pvd").exists()
    mesh = meshio.read(files[-1])
    assert np.allclose(mesh.points, sim.particles.x)
    assert np.allclose(mesh.point_data["radius"], sim.particles.radius)
    curve = read_curve(tmp_path / "history.csv")
    assert curve["step"].tolist() == [250.0, 300.0]
    assert np.all(curve["kinetic"] >= 0)


def test_history_without_energy_tracking_leaves_the_energy_out_or_refuses(tmp_path):
    """A run without ``track_energy`` has no energies: the writer leaves those columns out (energy=False) or
    refuses at the first row, never writing zeros."""
    sim = dense_packing(27, dt=3e-7)
    assert not sim.track_energy
    history = HistoryWriter(tmp_path / "plain.csv", energy=False)
    sim.run(20, callback=history, every=10)
    curve = read_curve(tmp_path / "plain.csv")
    assert "kinetic" not in curve and curve["step"].tolist() == [10.0, 20.0]
    with pytest.raises(ValueError, match="track_energy"):
        sim.run(10, callback=HistoryWriter(tmp_path / "energy.csv"), every=10)
