"""The periodic DEM cell and the elastic probe (abrakit.dem.periodic)."""

import numpy as np
import pytest

from abrakit.dem import Particles, Periodic, Simulation, elastic_probe
from abrakit.dem.bonds import install_parallel_bonds
from abrakit.dem.measure import love_weber_stress

R, KN = 0.01, 1e6


def two_spheres(centre_x: float, periodic: Periodic | None):
    """Two spheres overlapping by 0.1 R along x, their midpoint at ``centre_x``."""
    gap = 2 * R - 0.1 * R
    x = np.array([[centre_x - gap / 2, 0.05, 0.05], [centre_x + gap / 2, 0.05, 0.05]])
    sim = Simulation(Particles.spheres(x, R, kn=KN), periodic=periodic, dt=1e-6)
    sim.step()
    return sim


def test_a_contact_across_the_boundary_acts_as_one_inside():
    """The same pair in the middle of the cell and straddling its x faces: equal overlap, normal and force, and
    the particle that left the cell is wrapped back in at the next rebuild."""
    cell = (0.1, 0.1, 0.1)
    inside, across = two_spheres(0.05, Periodic(cell)), two_spheres(0.0, Periodic(cell))
    assert across.particles.x[0, 0] > 0.09                      # wrapped into [0, L)
    for sim in (inside, across):
        assert len(sim.contacts) == 1 and sim.contacts.touching.all()
    np.testing.assert_allclose(across.contacts.overlap, inside.contacts.overlap, rtol=1e-12)
    np.testing.assert_allclose(across.contacts.normal, inside.contacts.normal, atol=1e-12)
    np.testing.assert_allclose(across.contacts.force, inside.contacts.force, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(across.particles.v, inside.particles.v, rtol=1e-12, atol=1e-15)
    assert abs(inside.contacts.fn[0] - 0.5 * KN * 0.1 * R) < 1e-9 * KN * R      # kn in series: kn/2
    without = two_spheres(0.0, None)                             # no cell: the same pair still touches
    assert len(without.contacts) == 1


def simple_cubic(n: int = 4, strain: float = -1e-3):
    """n³ spheres on a simple cubic lattice of spacing 2R in a periodic cell, pre-compressed by ``strain``."""
    g = (np.arange(n) + 0.5) * 2 * R
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    sim = Simulation(Particles.spheres(x, R, kn=KN, friction=0.5), periodic=Periodic([2 * R * n] * 3),
                     local_damping=0.7)
    sim.strain_cell(strain)
    sim.step()
    return sim


def test_affine_strain_of_a_simple_cubic_lattice_gives_its_analytic_stiffness():
    """Simple cubic, contact stiffness k = kn/2 along the lattice axes: σ_xx = −k (2R − ℓ_x)/(ℓ_y ℓ_z), so
    C11 = k ℓ_x/(ℓ_y ℓ_z) ≈ k/(2R) and C12 = f/(ℓ_x ℓ_z) (the lateral pre-stress, zero without one); C44 from
    the tangential springs and the pre-stress; the probe reads all three and leaves the packing as it found it."""
    sim = simple_cubic()
    ell = sim.periodic.lengths / 4
    k = 0.5 * KN
    f = k * (2 * R - ell[0])
    sigma = love_weber_stress(sim, sim.periodic.volume)
    np.testing.assert_allclose(np.diag(sigma), -f / (ell[1] * ell[2]), rtol=1e-9)
    x_before = sim.particles.x.copy()
    probe = elastic_probe(sim, strain=1e-6, max_steps=200)
    np.testing.assert_allclose(probe.C11_axes, k * ell[0] / (ell[1] * ell[2]), rtol=1e-5)
    np.testing.assert_allclose(probe.C12_axes, f / (ell[0] * ell[2]), rtol=1e-3)
    # shear: the tangential springs (kt = kn, in series k_t = kn/2) and the pre-stress turning with the normals,
    # C44 = k_t/(2ℓ) − f/ℓ²; before the springs were shifted with the strain the probe read only −f/ℓ²
    kt = 0.5 * KN
    np.testing.assert_allclose(np.diag(probe.C)[3:], kt / (2 * ell[0]) - f / ell[0] ** 2, rtol=1e-4)
    np.testing.assert_allclose(probe.C[:3, 3:], 0.0, atol=1e-6 * probe.C11)      # cubic: no normal–shear coupling
    # Zener ratio 2 C44/(C11 − C12) = k_t/k_n = 1 up to the pre-stress: this lattice is isotropic, ν ≈ 0
    assert probe.anisotropy < 1e-2 and abs(probe.nu) < 1e-2
    np.testing.assert_array_equal(sim.particles.x, x_before)


def test_periodic_cell_refuses_what_it_cannot_do():
    with pytest.raises(ValueError, match="3 entries"):
        Periodic([1.0, 1.0])
    with pytest.raises(ValueError, match="positive"):
        Periodic([1.0, -1.0, 1.0])
    x = np.array([[0.01, 0.01, 0.01], [0.03, 0.01, 0.01]])
    with pytest.raises(ValueError, match="twice the largest interaction"):
        Simulation(Particles.spheres(x, R), periodic=Periodic([0.04, 0.1, 0.1]))
    clumped = Particles.spheres(x, R)
    clumped.clump = np.array([0, 0])
    with pytest.raises(ValueError, match="clumps"):
        Simulation(clumped, periodic=Periodic([0.1] * 3))
    sim = Simulation(Particles.spheres(x, R), periodic=Periodic([0.1] * 3))
    with pytest.raises(ValueError, match="parallel bonds"):
        install_parallel_bonds(sim, kn=1e9, ks=1e9, tensile_strength=1e6, shear_strength=1e6)
    with pytest.raises(ValueError, match="above -1"):
        sim.strain_cell([-1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="periodic"):
        elastic_probe(Simulation(Particles.spheres(x, R)))
    with pytest.raises(ValueError, match="periodic"):
        Simulation(Particles.spheres(x, R)).strain_cell(0.01)


def test_periodic_specimen_reaches_its_stress_and_gives_isotropic_elastic_constants():
    """A small identification specimen made in a periodic cell: consolidated to σ₀ within 2 %, denser than the
    walled vessel (no loose wall layers), the probe nearly isotropic (C11 along x, y, z within 15 % at 150 spheres;
    80 spheres spread by up to 23 %), 0 < ν < 0.5, E and ν close to the exact network response; Eq. (5.20)
    evaluated with the whole cell's contact density."""
    from abrakit.experiments.periodic_cell import periodic_elastic_case

    out = periodic_elastic_case({"n_particles": 150, "seed": 1})
    assert out["pressure"] == pytest.approx(1e6, rel=0.02)
    assert out["porosity"] < 0.40 and out["coordination"] > 4.0
    assert out["C11_spread"] < 0.15 and out["anisotropy"] < 0.15
    assert 0.0 < out["nu"] < 0.5 and out["E"] > 0.0
    # the material's friction (0.5): a few contacts slide under the probe, so probe and exact network response
    # (tangential springs of contacts at the Coulomb limit left out) agree less closely than with μ = 10
    assert out["E"] == pytest.approx(out["E_exact"], rel=0.05)
    assert out["nu"] == pytest.approx(out["nu_exact"], abs=0.02)
    assert out["rho_c"] == pytest.approx(out["rho_c_vessel"])


def test_a_sheared_cell_takes_the_nearest_image_through_its_tilted_faces():
    """A cell sheared by γ_xy = 0.2: the image across the y faces is shifted by γ L_y along x (Lees–Edwards).
    Branch vectors in both array layouts agree, positions wrap into the parallelepiped, and the neighbour search
    finds the pair across the tilted face as the same contact it is inside the cell."""
    cell = Periodic([0.1, 0.1, 0.1])
    x = np.zeros((1, 3))
    eps = np.zeros((3, 3))
    eps[0, 1] = eps[1, 0] = 0.1
    cell.strain(x, eps)
    assert cell.tilted and cell.tilt[0, 1] == pytest.approx(0.01) and cell.tilt[1, 0] == pytest.approx(0.01)
    assert cell.volume == pytest.approx(0.1**3 * np.linalg.det(np.eye(3) + eps))
    d = np.array([[0.0, 0.105, 0.0], [0.05, 0.0, 0.04]])
    np.testing.assert_allclose(cell.minimum_image(d), cell.minimum_image(d.T, axis=0).T, atol=1e-15)
    np.testing.assert_allclose(cell.minimum_image(d)[0], d[0] - cell.matrix[:, 1], atol=1e-15)
    rng = np.random.default_rng(0)
    pts = rng.uniform(-0.3, 0.3, (50, 3))
    wrapped = pts.copy()
    cell.wrap(wrapped)
    s = cell.fractional(wrapped)
    assert np.all((s >= 0.0) & (s < 1.0))
    np.testing.assert_allclose(cell.minimum_image(wrapped - pts), 0.0, atol=1e-15)
    # one pair straddling the tilted y faces, one inside: the same overlap
    from abrakit.dem.neighbours import candidate_pairs

    centre = cell.lower + cell.matrix @ np.array([0.5, 0.0, 0.5])
    across = np.array([centre - 0.0095 * cell.matrix[:, 1] / np.linalg.norm(cell.matrix[:, 1]),
                       centre + 0.0095 * cell.matrix[:, 1] / np.linalg.norm(cell.matrix[:, 1])])
    cell.wrap(across)
    i, j = candidate_pairs(across, np.full(2, R), 0.001, periodic=cell)
    assert len(i) == 1
    assert np.linalg.norm(cell.minimum_image(across[1] - across[0])) == pytest.approx(0.019)
    with pytest.raises(ValueError, match="tilt"):
        Periodic([0.1] * 3, tilt=np.eye(3))
    with pytest.raises(ValueError, match="symmetric"):
        cell.strain(x, np.array([[0.0, 0.1, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
