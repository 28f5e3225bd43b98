"""Friction (rolling onset), contact and parallel bonds (strength, stiffness, moment), the bonded chain wave."""

import numpy as np
import pytest

from abrakit.dem import Particles, Simulation, bonded_chain_wave, bonded_pair, install_contact_bonds, rolling_sphere
from abrakit.dem.bonds import install_parallel_bonds


@pytest.mark.parametrize("mu, v0", [(0.3, 1.0), (0.1, 0.5)])
def test_rolling_onset(mu, v0):
    """Slides, then rolls from t* = 2v₀/(7μg) on at v = 5v₀/7."""
    r = rolling_sphere(friction=mu, velocity=v0)
    assert r["t_star"] == pytest.approx(2 * v0 / (7 * mu * 9.81), rel=2e-3)
    assert r["v_star"] == pytest.approx(5 * v0 / 7, rel=1e-3)
    assert r["v_final"] == pytest.approx(5 * v0 / 7, rel=2e-3)          # and keeps rolling


@pytest.mark.parametrize("mode", ["tension", "shear"])
def test_contact_bond_breaks_at_its_strength(mode):
    r = bonded_pair(mode, "contact", strength=2.0, steps_to_failure=400)
    assert r["analytic"] == 2.0
    # the largest force carried is within one load increment below f^{n,c} (f^{t,c})
    assert r["analytic"] - r["increment"] * 1.01 <= r["peak"] <= r["analytic"]
    assert r["crack_mode"] == mode and r["crack_kind"] == "contact"
    assert r["crack_position"] == pytest.approx([0.01, 0, 0], abs=1e-5)       # the contact point


@pytest.mark.parametrize("mode", ["tension", "shear", "bending"])
def test_parallel_bond_breaks_at_its_strength(mode):
    r = bonded_pair(mode, "parallel", strength=5e5, steps_to_failure=400)
    area, inertia = np.pi * 0.01**2, np.pi * 0.01**4 / 4
    expected = {"tension": 5e5 * area, "shear": 5e5 * area, "bending": 5e5 * inertia / 0.01}[mode]
    assert r["analytic"] == pytest.approx(expected)
    assert r["analytic"] - r["increment"] * 1.01 <= r["peak"] <= r["analytic"] * (1 + 1e-9)
    assert r["crack_mode"] == ("tension" if mode == "bending" else mode)   # bending fails on the tensile side
    assert r["crack_kind"] == "parallel"


def test_bending_needs_a_parallel_bond():
    with pytest.raises(ValueError, match="moment"):
        bonded_pair("bending", "contact")


def _pair(skin=0.005):
    p = Particles.spheres([[0, 0, 0], [0.02, 0, 0]], 0.01, kn=2e6, fixed=True)
    return p, Simulation(p, dt=1e-6, skin=skin)


def test_parallel_bond_stiffness_and_moment_transfer():
    """F̄^n = k̄^n A δ for a stretch δ, M̄^s = −k̄^n I θ for a relative rotation θ, M̄^n = −k̄^s J θ_n."""
    p, sim = _pair()
    install_parallel_bonds(sim, kn=1e10, ks=5e9, tensile_strength=1e12, shear_strength=1e12)
    b = sim.parallel_bonds
    A, I, J = b.area[0], b.inertia[0], b.polar[0]
    p.v[1] = (1e-3, 0, 0)
    p.w[1] = (0.5, 0.2, 0)
    sim.run(100)
    delta, theta_n, theta_s = 1e-3 * 100 * sim.dt, 0.5 * 100 * sim.dt, 0.2 * 100 * sim.dt
    b = sim.parallel_bonds
    assert -b.fn[0] == pytest.approx(1e10 * A * delta, rel=1e-9)
    assert b.mn[0] == pytest.approx(-5e9 * J * theta_n, rel=1e-9)
    assert b.ms[:, 0] == pytest.approx([0, -1e10 * I * theta_s, 0], rel=1e-6)
    assert b.energy() > 0


def test_bonds_survive_neighbour_list_rebuilds():
    """A bonded pair pulled far beyond the Verlet skin stays in the contact list and keeps its tension."""
    p, sim = _pair(skin=1e-5)
    install_contact_bonds(sim, 1e9, 1e9)
    p.v[1] = (0.5, 0, 0)
    builds = sim.neighbours.builds
    sim.run(100)                                     # 50 µm apart: five skins
    assert sim.neighbours.builds > builds
    c = sim.contacts
    assert c.bonded.sum() == 1
    gap = np.linalg.norm(p.x[1] - p.x[0]) - 0.02 - 0.5 * sim.dt       # forces are from the step's start
    assert -c.fn[c.bonded][0] == pytest.approx(1e6 * gap, rel=1e-6)


def test_bond_strength_arrays_and_crack_log():
    x = np.array([[0, 0, 0], [0.02, 0, 0], [0.04, 0, 0]], float)
    p = Particles.spheres(x, 0.01, kn=2e6, fixed=True)
    sim = Simulation(p, dt=1e-6, skin=0.005)
    assert install_contact_bonds(sim, [1.0, 3.0], 10.0) == 2
    p.v[2] = (0.1, 0, 0)                             # only the second bond is stretched
    p.v[1] = (0.0, 0, 0)
    sim.run(40)                                      # stretch 4 µm: 4 N > 3 N
    cracks = sim.cracks.as_arrays()
    assert len(sim.cracks) == 1 and cracks["i"][0] == 1 and cracks["j"][0] == 2
    assert cracks["mode"][0] == "tension" and cracks["time"][0] > 0


def test_chain_wave_speed():
    """c = ℓ√(k/m) for long waves along a chain of bonded spheres."""
    r = bonded_chain_wave(160, width=12.0)
    assert r["speed"] == pytest.approx(r["speed_analytic"], rel=3e-3)
