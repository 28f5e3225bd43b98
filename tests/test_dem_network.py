"""The exact linear response of a contact network (abrakit.dem.network) and the elastic probe held against it."""

import numpy as np
import pytest

from abrakit.dem import Particles, Periodic, Simulation, elastic_probe, relax
from abrakit.dem.measure import love_weber_stress
from abrakit.dem.network import affine_network_stiffness, network_stiffness
from abrakit.dem.periodic import VOIGT, ElasticConstants, voigt_strain

R, KN = 0.01, 1e6


@pytest.fixture(scope="module")
def packing():
    """A jammed periodic packing of 100 spheres (the identification specimen's genesis, frictionless, 1 MPa)."""
    from abrakit.experiments.periodic_cell import periodic_genesis
    from abrakit.experiments.specimen import SpecimenSpec

    sim = periodic_genesis(SpecimenSpec(n_particles=100, seed=1))
    return sim.snapshot(), sim


def with_springs(packing, ratio: float, friction: float = 10.0, settle: bool = True):
    """The packing with K^t = K^n/``ratio`` (0: none) and a friction large enough that nothing slides, relaxed
    (``settle``; without tangential springs the packing is not a stable solid and would collapse)."""
    snapshot, sim = packing
    sim.restore(snapshot)
    p = sim.particles
    p.kt[:] = p.kn / ratio if ratio else 0.0
    p.friction[:] = friction
    sim.refresh()
    if settle:
        relax(sim, tolerance=1e-7, min_steps=0, max_steps=40_000, check_every=100)
    else:
        sim.step()
    return sim


@pytest.mark.parametrize("ratio", [1.0, 4.0])
def test_the_probe_equals_the_exact_network_response(packing, ratio):
    """Kn/Kt = 1 and 4: the dynamic probe (six strains of the cell, relaxed) and C = (A − Bᵀ H⁻¹ B)/V agree
    within 1 % in E and 0.01 in ν, and column by column within 3 % of C11."""
    sim = with_springs(packing, ratio)
    exact = network_stiffness(sim)
    probe = elastic_probe(sim, tol=1e-7)
    assert probe.E == pytest.approx(exact.E, rel=0.01)
    assert probe.nu == pytest.approx(exact.nu, abs=0.01)
    np.testing.assert_allclose(probe.C, exact.C, atol=0.03 * exact.C11)
    affine = ElasticConstants.from_stiffness(affine_network_stiffness(sim))
    assert exact.E < affine.E                                   # relaxation softens the affine bound


def test_without_the_spring_shift_the_probe_misses_the_tangential_springs(packing):
    """The trap the probe used to fall into: positions jumped, incremental springs untouched, so ν came out near
    the 1/4 of a normal-spring network and E a third too low (Kn/Kt = 1). The test above would fail."""
    sim = with_springs(packing, 1.0)
    exact = network_stiffness(sim)
    missed = elastic_probe(sim, tol=1e-7, shift_springs=False)
    assert missed.E < 0.8 * exact.E and missed.nu > exact.nu + 0.05


def closed_form_affine(sim) -> np.ndarray:
    """Σ_c l² [k_n n n n n + k_t (sym(δ_ik n_j n_l) − n n n n)] / V over the touching contacts, in Voigt form,
    written independently of the network module (a branch vector along the normal for spheres)."""
    c = sim.contacts
    t = c.touching
    branch = sim.branch(c.i[t], c.j[t])
    l = np.linalg.norm(branch, axis=1)
    n = branch / l[:, None]
    kn, kt = c.prm["kn"][t], c.prm["kt"][t]
    nnnn = np.einsum("ci,cj,ck,cl->cijkl", n, n, n, n)
    dnn = np.einsum("ik,cj,cl->cijkl", np.eye(3), n, n)
    sym = 0.25 * (dnn + dnn.transpose(0, 2, 1, 3, 4) + dnn.transpose(0, 1, 2, 4, 3)
                  + dnn.transpose(0, 2, 1, 4, 3))
    C4 = np.einsum("c,cijkl->ijkl", l**2, kn[:, None, None, None, None] * nnnn
                   + kt[:, None, None, None, None] * (sym - nnnn)) / sim.periodic.volume
    return np.array([[C4[a, b, c_, d] for c_, d in VOIGT] for a, b in VOIGT])


def stress_in_place(sim) -> np.ndarray:
    """The cell's stress of the present positions: one step from rest (no relative motion, the springs as they
    are), its positions put back."""
    p = sim.particles
    x = p.x.copy()
    p.v[:], p.w[:] = 0.0, 0.0
    sim.step()
    p.x[:] = x
    return love_weber_stress(sim, sim.periodic.volume)


@pytest.mark.parametrize("ratio", [0.0, 2.5])
def test_the_stress_right_after_the_jump_is_the_affine_closed_form(packing, ratio):
    """Without tangential springs (kt = 0) and with them: the stress change of the cell right after an affine
    strain, before any relaxation, equals the closed-form affine stiffness (to the pre-stress, 10⁻³ here), and
    so does the network module's A/V (to round-off). Equilibrium is not needed: the packing is not relaxed."""
    sim = with_springs(packing, ratio, settle=False)
    expected = closed_form_affine(sim)
    np.testing.assert_allclose(affine_network_stiffness(sim), expected, rtol=1e-9, atol=1e-9 * expected[0, 0])
    strain = 1e-10                  # 1e-6 opens five of 278 contacts of this unrelaxed packing, 1 % of C11
    C = np.zeros((6, 6))
    rows = tuple(zip(*VOIGT, strict=True))
    for k in range(6):
        snapshot = sim.snapshot()
        sigma0 = stress_in_place(sim)
        sim.strain_cell(voigt_strain(k, strain))
        C[:, k] = (stress_in_place(sim) - sigma0)[rows] / strain
        sim.restore(snapshot)
    np.testing.assert_allclose(C, expected, atol=3e-3 * expected[0, 0])


def simple_cubic(n: int = 4, strain: float = -1e-3, kt: float = KN):
    g = (np.arange(n) + 0.5) * 2 * R
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    sim = Simulation(Particles.spheres(x, R, kn=KN, kt=kt, friction=0.5), periodic=Periodic([2 * R * n] * 3))
    sim.strain_cell(strain)
    sim.step()
    return sim


def test_simple_cubic_lattice_has_its_analytic_network_stiffness():
    """Simple cubic, contact springs k_n = KN/2, k_t = KT/2 (two particles in series): C11 = k_n/ℓ, C12 = 0,
    C44 = k_t/(2ℓ), nothing else; the lattice needs no fluctuations (A = C)."""
    for kt in (KN, 0.25 * KN):
        sim = simple_cubic(kt=kt)
        ell = sim.periodic.lengths[0] / 4
        expected = np.diag([KN / 2 / ell] * 3 + [kt / 2 / (2 * ell)] * 3)
        exact = network_stiffness(sim)
        np.testing.assert_allclose(exact.C, expected, atol=1e-9 * expected[0, 0])
        np.testing.assert_allclose(affine_network_stiffness(sim), expected, atol=1e-9 * expected[0, 0])


def test_elastic_constants_of_an_isotropic_stiffness_are_exact():
    E, nu = 30e9, 0.2
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[np.arange(3), np.arange(3)] += 2 * mu
    C[np.arange(3, 6), np.arange(3, 6)] = mu
    out = ElasticConstants.from_stiffness(C)
    assert out.E == pytest.approx(E) and out.nu == pytest.approx(nu) and out.anisotropy < 1e-14
    assert out.bulk == pytest.approx(lam + 2 * mu / 3) and out.shear == pytest.approx(mu)
    assert out.C11 == pytest.approx(lam + 2 * mu) and out.C12 == pytest.approx(lam)
    with pytest.raises(ValueError, match="6, 6"):
        ElasticConstants.from_stiffness(np.eye(3))
    with pytest.raises(ValueError, match="finite"):
        ElasticConstants.from_stiffness(np.full((6, 6), np.nan))
    with pytest.raises(ValueError, match="non-zero"):
        ElasticConstants.from_stiffness(np.zeros((6, 6)))           # no NaN from finite input


def test_velocity_driven_motion_loads_the_springs_as_the_jump_does(packing):
    """A walled test strains its packing through velocities: the incremental springs integrate V^t Δt over the
    steps. Driving every particle with the affine velocity ε̇ x (fixed particles keep it) for 200 steps shifts the
    springs of the contacts inside the cell (not across its faces, whose images do not move) by what
    ``strain_cell`` adds at once."""
    sim = with_springs(packing, 2.5)
    eps = 2e-7 * np.array([[1.0, 0.5, 0.0], [0.5, -0.3, 0.2], [0.0, 0.2, 0.4]])
    c = sim.contacts
    inside = c.touching & (np.linalg.norm(sim.particles.x[c.j] - sim.particles.x[c.i], axis=1)
                           < 0.5 * sim.periodic.lengths.min())
    jump = sim.snapshot()
    ft0 = c.ft.copy()
    sim.strain_cell(eps)
    shifted = sim.contacts.ft - ft0
    sim.restore(jump)
    p = sim.particles
    steps = 200
    sim.dt = sim.dt                                             # kept: fixed particles have no time step of their own
    p.fixed[:] = True
    p.v[:] = (p.x - p.x.mean(axis=0)) @ eps.T / (steps * sim.dt)
    p.w[:] = 0.0
    sim.refresh()
    keys = sim.contacts.keys.copy()
    for _ in range(steps):
        sim.step()
    assert np.array_equal(sim.contacts.keys, keys)              # the same contact list: compare them one by one
    driven = sim.contacts.ft - ft0
    scale = np.abs(shifted[:, inside]).max()
    assert scale > 0
    np.testing.assert_allclose(driven[:, inside], shifted[:, inside], atol=2e-3 * scale)


def test_network_stiffness_refuses_what_it_cannot_compute():
    x = np.array([[0.01, 0.01, 0.01], [0.0299, 0.01, 0.01]])
    sim = Simulation(Particles.spheres(x, R), periodic=Periodic([0.1] * 3), dt=1e-6)
    if sim.contacts.force is None:
        with pytest.raises(ValueError, match="run at least one step"):
            network_stiffness(sim)
    walled = Simulation(Particles.spheres(x, R), dt=1e-6)
    walled.step()
    with pytest.raises(ValueError, match="periodic"):
        network_stiffness(walled)
    with pytest.raises(ValueError, match="periodic"):
        affine_network_stiffness(walled)


def test_the_probe_converges_to_the_exact_response_as_its_strain_shrinks(packing):
    """μ = 0.5, K^n = K^t: at a strain of 10⁻⁵ contacts open and slide and E reads more than 5 % low; at the
    default 10⁻⁸ the probe measures the tangent stiffness, the exact response to 10⁻³."""
    sim = with_springs(packing, 1.0, friction=0.5)
    exact = network_stiffness(sim)
    large = elastic_probe(sim, strain=1e-5, tol=1e-7)
    small = elastic_probe(sim, tol=1e-7)
    assert large.E < 0.95 * exact.E
    assert small.E == pytest.approx(exact.E, rel=1e-3) and small.nu == pytest.approx(exact.nu, abs=1e-3)
