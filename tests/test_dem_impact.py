"""Normal impact against the closed forms: duration π/(ω₀√(1−ζ²)), restitution, peak overlap v₀/ω₀."""

import numpy as np
import pytest

from abrakit.dem import HertzMindlin, Particles, Simulation, Walls, two_sphere_impact
from abrakit.dem.scenes import sphere_wall_impact

SCENES = [two_sphere_impact, sphere_wall_impact]


@pytest.mark.parametrize("scene", SCENES)
def test_undamped_impact(scene):
    r = scene(0.01, 2650.0, 1e5, 0.0, 1.0)
    assert r["duration"] == pytest.approx(r["duration_analytic"], rel=1e-4)
    assert r["restitution"] == pytest.approx(1.0, abs=1e-5)
    assert r["peak_overlap"] == pytest.approx(r["peak_overlap_analytic"], rel=1e-4)
    m = 4 / 3 * np.pi * 0.01**3 * 2650 / (2 if scene is two_sphere_impact else 1)
    assert r["peak_overlap_analytic"] == pytest.approx(1.0 / np.sqrt(1e5 / m))         # v₀/ω₀


@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("zeta", [0.1, 0.5])
def test_dashpot_impact(scene, zeta):
    r = scene(0.01, 2650.0, 1e5, zeta, 0.5)
    assert r["duration"] == pytest.approx(r["duration_analytic"], rel=5e-3)
    assert r["restitution"] == pytest.approx(np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2)), rel=5e-3)
    assert r["peak_overlap"] == pytest.approx(r["peak_overlap_analytic"], rel=5e-3)
    assert abs(r["energy"]["relative_error"]) < 1e-3                    # dashpot work is booked


def test_dashpot_error_is_first_order_in_dt():
    """The dashpot sees the half-step velocity: the duration error falls like Δt, and the restitution error
    (which also depends on where in a step the contact starts) stays below 2/(steps per contact)."""
    runs = {n: two_sphere_impact(0.01, 2650.0, 1e5, 0.3, 1.0, steps_per_contact=n) for n in (100, 400, 1600)}
    dur = [abs(r["duration"] / r["duration_analytic"] - 1) for r in runs.values()]
    assert 3.5 < dur[0] / dur[1] < 4.5 and 3.5 < dur[1] / dur[2] < 4.5
    for n, r in runs.items():
        assert abs(r["restitution"] / r["restitution_analytic"] - 1) < 2.0 / n


@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("alpha", [0.3, 0.7])
def test_local_damping_impact(scene, alpha):
    r = scene(0.01, 2650.0, 1e5, 0.0, 1.0, local_damping=alpha)
    assert r["restitution"] == pytest.approx(np.sqrt((1 - alpha) / (1 + alpha)), rel=5e-3)
    # the damping force changes sign one step late at the turning point (it sees v(t − Δt/2)): the unloading
    # starts with an impulse error 2αFΔt, which delays the end of contact by at most 2α/(1 − α) steps
    assert abs(r["duration"] - r["duration_analytic"]) < 2 * alpha / (1 - alpha) * r["dt"]
    assert r["peak_overlap"] == pytest.approx(r["peak_overlap_analytic"], rel=5e-3)
    assert abs(r["energy"]["relative_error"]) < 1e-3


def test_two_sphere_impact_returns_documented_keys():
    r = two_sphere_impact(radius=0.005, density=2500.0, kn=2e5, damping_ratio=0.2, velocity=0.3)
    for key in ("duration", "restitution", "peak_overlap", "duration_analytic", "restitution_analytic", "dt"):
        assert key in r
    assert 0 < r["restitution"] < 1


def test_linear_restitution_does_not_depend_on_speed():
    e = [two_sphere_impact(0.01, 2650.0, 1e5, 0.2, v)["restitution"] for v in (0.1, 1.0, 10.0)]
    assert np.ptp(e) < 1e-6


def test_hertz_impact_duration():
    """Hertz's contact time t_c = 2.8683 (m*²/(R* E*² v₀))^{1/5}, with E* = G/(1−ν) for one material."""
    r, G, nu, v0 = 0.005, 1e8, 0.25, 0.5
    p = Particles.spheres([[-r - 1e-5, 0, 0], [r + 1e-5, 0, 0]], r, 2650.0, v=[[v0 / 2, 0, 0], [-v0 / 2, 0, 0]],
                          shear_modulus=G, poisson=nu)
    m_star, R_star, E_star = p.mass[0] / 2, r / 2, G / (1 - nu)
    t_c = 2.8683 * (m_star**2 / (R_star * E_star**2 * v0)) ** 0.2
    sim = Simulation(p, law=HertzMindlin(), dt=t_c / 400, skin=r)
    touching = 0
    for _ in range(1200):
        sim.step()
        touching += np.linalg.norm(p.x[1] - p.x[0]) < 2 * r
    assert touching * sim.dt == pytest.approx(t_c, rel=1e-2)
    assert p.v[1, 0] - p.v[0, 0] == pytest.approx(v0, rel=1e-4)          # elastic: no energy lost


def test_wall_stiffness_in_series():
    """A wall with k_w in series with the particle: K^n = k k_w/(k + k_w), Eq. (4.11)."""
    r, k = 0.01, 1e5
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1), kn=k)
    p = Particles.spheres([[0, 0, r]], r, 2650.0, v=[[0, 0, -1.0]], kn=k)
    sim = Simulation(p, walls=walls, dt=1e-6, skin=r)
    t = 0.0
    while p.x[0, 2] <= r + 1e-12 or t == 0.0:
        sim.step()
        t += sim.dt
    assert t == pytest.approx(np.pi / np.sqrt(k / 2 / p.mass[0]), rel=1e-2)
