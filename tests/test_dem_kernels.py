"""The optional numba kernel gives the NumPy path's results (to round-off)."""

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


def test_numba_kernel_refuses_other_laws():
    with pytest.raises(ValueError, match="Linear law only"):
        dense_packing(8, law=HertzMindlin(), kernel="numba")


def test_numba_kernel_in_a_periodic_cell_equals_numpy():
    """The compiled contact loop takes the nearest periodic image like the NumPy path."""
    from abrakit.dem import Particles, Periodic, Simulation

    rng = np.random.default_rng(3)
    g = (np.arange(4) + 0.5) * 0.02
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3) + rng.uniform(-1e-3, 1e-3, (64, 3))
    runs = []
    for kernel in ("numpy", "numba"):
        p = Particles.spheres(x, 0.0104, kn=1e6, friction=0.3)          # overlapping by 4 %: they push apart
        sim = Simulation(p, periodic=Periodic([0.08] * 3), kernel=kernel, dt=2e-6, local_damping=0.1)
        sim.run(300, progress=False)
        runs.append(sim)
    a, b = runs
    assert a.contacts.touching.sum() > 64
    assert np.allclose(a.particles.x, b.particles.x, rtol=0, atol=1e-13)
    assert np.allclose(a.contacts.force, b.contacts.force, rtol=1e-8, atol=1e-10)
