"""The optional numba kernel gives the NumPy path's results (to round-off)."""

import copy
import pickle

import numpy as np
import pytest

from abrakit.dem import HertzMindlin, Linear, dense_packing, install_contact_bonds
from abrakit.dem.kernels import HAVE_NUMBA

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="numba (extra 'fast') not installed")


def _pair_of_runs(**kw):
    runs = []
    for kernel in ("numpy", "numba"):
        sim = dense_packing(125, seed=5, agitation=0.05, kernel=kernel, track_energy=True, dt=3e-7, **kw)
        runs.append(sim)
    return runs


@pytest.mark.parametrize("law", [Linear(), Linear(damping_normal=0.3, damping_shear=0.1)])
def test_numba_kernel_equals_numpy(law):
    a, b = _pair_of_runs(law=law, local_damping=0.1)
    for sim in (a, b):
        sim.run(200)
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)
    assert np.allclose(a.particles.v, b.particles.v, rtol=1e-8, atol=1e-12)
    assert np.allclose(a.particles.w, b.particles.w, rtol=1e-8, atol=1e-9)
    assert np.allclose(a.contacts.ft, b.contacts.ft, rtol=1e-8, atol=1e-12)
    assert len(a.wall_contacts) > 0 and a.wall_contacts.touching.any()        # the compiled wall step too
    assert np.allclose(a.wall_contacts.ft, b.wall_contacts.ft, rtol=1e-8, atol=1e-12)
    assert np.allclose(a.walls.force, b.walls.force, rtol=1e-8, atol=1e-12)
    for key in ("kinetic", "elastic", "friction", "dashpot", "local_damping", "work_walls"):
        assert getattr(a.energy, key) == pytest.approx(getattr(b.energy, key), rel=1e-8, abs=1e-15)


def test_numba_kernel_with_contact_bonds_and_cracks():
    a, b = _pair_of_runs()
    for sim in (a, b):
        install_contact_bonds(sim, 0.05, 0.05, gap=1e-5)
        sim.run(300)
    assert len(a.cracks) > 0 and len(a.cracks) == len(b.cracks)
    ca, cb = a.cracks.as_arrays(), b.cracks.as_arrays()
    assert np.array_equal(ca["i"], cb["i"]) and np.array_equal(ca["mode"], cb["mode"])
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)


@pytest.mark.parametrize("bonds", [False, True])
def test_lean_numba_kernel_results_equal_numpy(bonds):
    """Without dashpots and energy account the kernel writes only springs, overlaps and bond failures; the normals,
    normal and total forces it skips are rebuilt when read and equal the NumPy path's, bonds broken in the step
    included, at every step of the run."""
    runs = [dense_packing(125, seed=5, agitation=0.05, kernel=k, track_energy=False, dt=3e-7) for k in ("numpy",
                                                                                                      "numba")]
    for sim in runs:
        if bonds:
            install_contact_bonds(sim, 0.05, 0.05, gap=1e-5)
    a, b = runs
    broken = 0
    for _ in range(150):
        for sim in runs:
            sim.step()
        assert callable(b.contacts._results["force"])       # lean: not built yet (normals are, if a bond broke)
        for name in ("normal", "fn", "force"):
            np.testing.assert_allclose(getattr(b.contacts, name), getattr(a.contacts, name), rtol=1e-9, atol=1e-9)
        broken = len(b.cracks)
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)
    assert not bonds or (broken > 0 and broken == len(a.cracks))


def test_numba_kernel_refuses_other_laws():
    with pytest.raises(ValueError, match="Linear law only"):
        dense_packing(8, law=HertzMindlin(), kernel="numba")


@pytest.mark.parametrize("shear", [0.0, 0.05])
def test_numba_kernel_in_a_periodic_cell_equals_numpy(shear):
    """The compiled contact loop takes the nearest periodic image like the NumPy path, in an orthogonal and in a
    sheared (tilted) cell."""
    from abrakit.dem import Particles, Periodic, Simulation

    rng = np.random.default_rng(3)
    g = (np.arange(4) + 0.5) * 0.02
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3) + rng.uniform(-1e-3, 1e-3, (64, 3))
    runs = []
    for kernel in ("numpy", "numba"):
        p = Particles.spheres(x, 0.0104, kn=1e6, friction=0.3)          # overlapping by 4 %: they push apart
        sim = Simulation(p, periodic=Periodic([0.08] * 3), kernel=kernel, dt=2e-6, local_damping=0.1)
        sim.strain_cell(np.array([[0.0, shear, 0.0], [shear, 0.0, 0.0], [0.0, 0.0, 0.0]]))
        sim.run(300, progress=False)
        runs.append(sim)
    a, b = runs
    assert a.contacts.touching.sum() > 64
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)
    assert np.allclose(a.contacts.force, b.contacts.force, rtol=1e-8, atol=1e-10)


def test_compiled_step_without_energy_account_equals_numpy():
    """Without an energy account the numba path damps and integrates in one compiled loop (``advance``); with a
    servo wall, damping, a fixed particle and contact bonds that break, it still follows the NumPy path."""
    runs = []
    for kernel in ("numpy", "numba"):
        sim = dense_packing(125, seed=7, agitation=0.05, kernel=kernel, dt=3e-7, local_damping=0.3,
                            law=Linear(damping_normal=0.2))
        sim.particles.fixed[0] = True
        sim.refresh()
        sim.walls.add_servo("zmax", 2e3, lambda w: w.box_area("z"), max_speed=0.05)
        install_contact_bonds(sim, 0.05, 0.05, gap=1e-5)
        sim.run(300, progress=False)
        runs.append(sim)
    a, b = runs
    assert not a.track_energy and len(a.cracks) > 0 and len(a.cracks) == len(b.cracks)
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)
    assert np.allclose(a.particles.w, b.particles.w, rtol=1e-8, atol=1e-9)
    assert np.allclose(a.walls.point, b.walls.point, rtol=0, atol=1e-13)       # the servo saw the same K^n
    assert np.array_equal(a.particles.v[0], b.particles.v[0])                 # the fixed particle kept its v


def test_compiled_planar_step_equals_numpy():
    from abrakit.dem import Particles, Simulation

    rng = np.random.default_rng(2)
    g = (np.arange(6) + 0.5) * 0.0198
    x = np.stack(np.meshgrid(g, g, [0.0], indexing="ij"), -1).reshape(-1, 3) + rng.uniform(-5e-4, 5e-4, (36, 3))
    runs = []
    for kernel in ("numpy", "numba"):
        sim = Simulation(Particles.disks(x[:, :2], 0.01, kn=1e6, friction=0.4), planar=True, kernel=kernel,
                         dt=2e-6, local_damping=0.2, track_energy=False)
        sim.run(300, progress=False)
        runs.append(sim)
    a, b = runs
    assert np.all(a.particles.x[:, 2] == 0.0) and np.all(a.particles.w[:, :2] == 0.0)
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)


@pytest.mark.parametrize("capacity", [None, 5])
def test_cell_list_gives_the_kdtree_pairs(capacity):
    """The compiled cell list finds exactly the cKDTree's candidate pairs, in the same (i, j) order; too short an
    output array is detected and the search repeated."""
    from abrakit.dem.kernels import cell_list_pairs
    from abrakit.dem.neighbours import candidate_pairs

    rng = np.random.default_rng(0)
    x = rng.uniform(0, 0.05, (400, 3)) * [1.0, 0.3, 2.0]             # flat and elongated box
    radius = rng.uniform(0.001, 0.003, 400)
    i0, j0 = candidate_pairs(x, radius, 5e-4)
    if capacity is None:
        i1, j1 = candidate_pairs(x, radius, 5e-4, compiled=True)
    else:
        i1, j1, count = cell_list_pairs(x, radius, 5e-4, capacity)
        assert count == len(i0) > capacity
        i1, j1, count = cell_list_pairs(x, radius, 5e-4, count)
    assert len(i0) > 100
    assert np.array_equal(i0, i1) and np.array_equal(j0, j1)


def test_compiled_displacement_check_reports_non_finite_positions():
    sim = dense_packing(27, kernel="numba", dt=3e-7)
    sim.particles.x[3, 1] = np.nan
    with pytest.raises(FloatingPointError, match="non-finite"):
        sim.step()


def test_kernel_can_be_switched_between_steps():
    a = dense_packing(64, seed=1, agitation=0.05, dt=3e-7)
    b = dense_packing(64, seed=1, agitation=0.05, dt=3e-7)
    a.run(50, progress=False)
    b.run(25, progress=False)
    b.kernel = "numba"
    b.run(25, progress=False)
    assert b.neighbours.compiled
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)
    with pytest.raises(ValueError, match="kernel"):
        b.kernel = "fortran"


@pytest.mark.parametrize("kernel", ["numpy", "numba"])
def test_gaps_in_the_verlet_list_carry_nothing(kernel):
    """Both paths skip the law on candidate pairs with a gap: those hold zero force, spring and normal force,
    while every overlapping pair is computed."""
    sim = dense_packing(216, seed=4, agitation=0.05, kernel=kernel, dt=3e-7)
    sim.run(100, progress=False)
    c = sim.contacts
    gap = (c.overlap <= 0.0) & ~c.bonded
    assert 0.2 < gap.mean() < 0.8
    assert np.all(c.fn[gap] == 0.0) and np.all(c.ft[:, gap] == 0.0) and np.all(c.force[:, gap] == 0.0)
    assert np.all(c.fn[~gap] > 0.0)


def test_numpy_results_are_built_when_read_and_survive_pickling_and_copies():
    """The NumPy path defers spreading its live-contact results over the candidate list (``ContactSet.defer``):
    reading them gives the full arrays (a unit normal for every candidate), and a pickle or a deep copy holds the
    arrays themselves, equal to the originals."""
    sim = dense_packing(216, seed=4, agitation=0.05, dt=3e-7)
    sim.run(20, progress=False)
    twin = pickle.loads(pickle.dumps(sim))
    copied = copy.deepcopy(sim)
    c = sim.contacts
    assert c.normal.shape == (3, len(c)) and np.allclose(np.sum(c.normal**2, axis=0), 1.0, rtol=1e-14)
    for other in (twin.contacts, copied.contacts):
        assert not any(callable(v) for v in other._results.values())
        for name in ("normal", "fn", "force"):
            np.testing.assert_array_equal(getattr(other, name), getattr(c, name))


def test_a_contact_set_pickled_before_the_results_were_deferred_still_loads():
    """Snapshots and cached beams written by earlier versions hold ``normal``, ``fn`` and ``force`` as fields."""
    from abrakit.dem.state import ContactSet

    c = ContactSet.empty_history([0], [1], 2)
    old = {k: v for k, v in c.__dict__.items() if k != "_results"}
    old |= {"normal": np.array([[1.0], [0.0], [0.0]]), "fn": np.array([2.0]), "force": np.array([[2.0], [0.0], [0.0]])}
    loaded = ContactSet.__new__(ContactSet)
    loaded.__setstate__(old)
    assert loaded.fn[0] == 2.0 and loaded.force[0, 0] == 2.0 and loaded.normal[0, 0] == 1.0
    assert "fn" not in loaded.__dict__ and len(loaded) == 1


def test_the_compiled_pair_scatter_gives_the_bincount_sums_to_the_last_bit():
    """Pairs that share particles, in any order: the compiled loop's force and torque sums are the NumPy
    version's (np.bincount), bit for bit, so the fatigue bonds' and contacts' loads do not change with numba."""
    from abrakit.dem._bookkeeping import _scatter_pair_loads

    rng = np.random.default_rng(3)
    n, m = 40, 300
    i, j = rng.integers(0, n, m), rng.integers(0, n, m)
    loads = rng.standard_normal((3, 3, m)) * 10.0 ** rng.uniform(-6, 3, (3, 3, m))
    start = rng.standard_normal((2, n, 3))
    sums = []
    for compiled in (False, True):
        force, torque = start[0].copy(), start[1].copy()
        _scatter_pair_loads(force, torque, i, j, *loads, compiled=compiled)
        sums.append((force, torque))
    assert np.array_equal(sums[0][0], sums[1][0]) and np.array_equal(sums[0][1], sums[1][1])
