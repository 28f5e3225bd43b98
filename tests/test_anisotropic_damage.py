"""Anisotropic softening damage of seed 001 at a material point (abrakit.materials.anisotropic_damage): strength,
toughness per crack area, secant unloading, the four traction failure surfaces, crack normals, the consistent
tangent, compression, residual strain, the softening laws, the Mandel rotation, hard cases and bad input."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.spatial.transform import Rotation

from abrakit import tensors as T
from abrakit.materials import (
    AnisotropicSofteningDamage,
    finite_difference_tangent,
    pure_shear,
    ramp,
    uniaxial_strain,
    uniaxial_stress,
)
from abrakit.materials.anisotropic_damage import SURFACES, ProjectedBandWidth
from abrakit.materials.softening_laws import max_band_width, softening_law

E, NU, SIGMA_C, TAU_C, G_I, G_II = 1000.0, 0.25, 30.0, 20.0, 0.5, 0.8
LAWS = ("linear", "exponential")


def material(surface="ovoid", law="linear", h=0.3, **options):
    return AnisotropicSofteningDamage(E, options.pop("nu", NU), SIGMA_C, TAU_C, G_I, G_II, band_width=h,
                                      softening_I=law, softening_II=law, surface=surface, **options)


def work(result, component):
    return np.trapezoid(result.stress_component(component), result.strain_component(component))


def drive_points(m, strains, state=None):
    """Apply Mandel strains one after another to one point; return the responses."""
    state = m.initial_state(()) if state is None else state
    responses = []
    for eps in strains:
        response = m.update(state, np.asarray(eps, dtype=float))
        state = response.state
        responses.append(response)
    return responses


# ---- mode I and mode II: strength and toughness -------------------------------------------------------------------
@pytest.mark.parametrize("surface", SURFACES)
@pytest.mark.parametrize("law", LAWS)
def test_uniaxial_strain_peaks_at_the_strength_and_dissipates_the_toughness(surface, law):
    """Uniaxial strain to separation: the stress peaks at sigma_c, and the work per volume, the dissipation and the
    law's own energy all equal G_Ic/h (1 %) for every surface (mode I only, so the couplings play no part)."""
    h = 0.3
    m = material(surface, law, h)
    end = SIGMA_C / m.C11 + (2.0 if law == "linear" else 12.0) * G_I / SIGMA_C / h
    result = uniaxial_strain(m, ramp(end, 1500))
    stress = result.stress_component("11")
    assert stress.max() == pytest.approx(SIGMA_C, rel=1e-2)                # to the strain step
    assert stress.max() <= SIGMA_C * (1.0 + 1e-12)
    assert work(result, "11") * h == pytest.approx(G_I, rel=1e-2)
    assert result.internal["dissipation_I"][-1] * h == pytest.approx(G_I, rel=1e-2)
    assert result.internal["dissipation_II"][-1] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(result.internal["axes"][-1][0], [1.0, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("surface", SURFACES)
def test_pure_shear_peaks_at_the_shear_strength_and_dissipates_the_mode_II_toughness(surface):
    """Pure shear (tau_c < sigma_c): the crack starts in shear on a plane of largest shear, the shear stress peaks
    at tau_c, and the dissipation per volume is G_IIc/h (1 %) with no mode I part."""
    h = 0.3
    m = material(surface, "linear", h)
    end = 2.0 * (TAU_C / m.mu + 2.0 * G_II / TAU_C / h)        # gamma = 2 eps_12
    result = pure_shear(m, ramp(end / 2.0, 1500))
    tau = result.stress_component("12")
    assert tau.max() == pytest.approx(TAU_C, rel=1e-2)
    assert tau.max() <= TAU_C * (1.0 + 1e-12)
    assert result.internal["dissipation_II"][-1] * h == pytest.approx(G_II, rel=1e-2)
    assert result.internal["dissipation_I"][-1] == pytest.approx(0.0, abs=1e-12)
    normal = result.internal["axes"][-1][0]
    assert abs(normal[0]) == pytest.approx(1.0) or abs(normal[1]) == pytest.approx(1.0)


def test_unloading_is_secant_back_to_the_origin():
    """Damage, not plasticity: unloading from the softening branch is linear through the origin with the
    damaged stiffness, and reloading retraces it until the envelope."""
    m = material("ovoid")
    peak = SIGMA_C / m.C11
    up = np.linspace(0.0, 1.5 * peak, 60)
    down = np.linspace(1.5 * peak, 0.0, 30)[1:]
    responses = drive_points(m, [[e, 0, 0, 0, 0, 0] for e in np.concatenate([up, down])])
    stress = np.array([r.stress[0] for r in responses])
    d = responses[len(up) - 1].state["d"][0]
    assert 0.05 < d < 0.95
    secant = (1.0 - d) * m.C11
    np.testing.assert_allclose(stress[len(up):], secant * down, rtol=1e-12, atol=1e-12)
    assert responses[-1].stress[0] == 0.0
    assert responses[-1].state["d"][0] == d                          # no damage while unloading


# ---- the traction failure surfaces ----------------------------------------------------------------------------------
def cracked_in_tension(m, factor=1.3):
    """A point pulled along x into its softening branch and unloaded: crack normal x, 0 < d_n < 1."""
    peak = SIGMA_C / m.C11
    path = [[e, 0, 0, 0, 0, 0] for e in np.concatenate([np.linspace(0, factor * peak, 40), [0.0]])]
    return drive_points(m, path)[-1].state


@pytest.mark.parametrize("surface", SURFACES)
def test_a_tension_crack_leaves_the_stiffness_along_the_crack_plane_untouched(surface):
    """After a crack with normal x: uniaxial stress along y and z gives E, the in-plane shear yz keeps 2 mu, and the
    normal stiffness is (1 - d_n) C_11 (every surface)."""
    m = material(surface)
    state = cracked_in_tension(m)
    d_n = state["d"][0]
    assert 0.05 < d_n < 0.95
    tangent = m.update(state, np.array([1e-6, 0, 0, 0, 0, 0])).tangent
    assert tangent[0, 0] == pytest.approx((1.0 - d_n) * m.C11, rel=1e-12)
    assert tangent[3, 3] == pytest.approx(2.0 * m.mu, rel=1e-12)
    for k in (1, 2):
        compliance = np.linalg.inv(tangent[:3, :3])
        assert 1.0 / compliance[k, k] == pytest.approx(E, rel=1e-9)


@pytest.mark.parametrize("surface, shear_damaged", [("cuboid", False), ("elliptical_cylinder", False),
                                                     ("ovoid", True), ("coupled_cuboid", True)])
def test_tension_then_shear_follows_the_coupling_of_each_surface(surface, shear_damaged):
    """The seed's description of the surfaces: after tension damage, the cuboid and the elliptical cylinder are
    virgin in shear (shear modulus mu, shear peak tau_c); the ovoid and the coupled cuboid have d_n = d_xy = d_xz,
    so shear is softer by (1 - d) and fails below tau_c."""
    m = material(surface)
    state = cracked_in_tension(m)
    d_n = state["d"][0]
    tangent = m.update(state, np.zeros(6)).tangent
    expected = 2.0 * m.mu * ((1.0 - d_n) if shear_damaged else 1.0)
    assert tangent[5, 5] == pytest.approx(expected, rel=1e-12)
    assert tangent[4, 4] == pytest.approx(expected, rel=1e-12)
    gammas = np.linspace(0.0, 3.0 * TAU_C / m.mu, 400)
    responses = drive_points(m, [[0, 0, 0, 0, 0, g / np.sqrt(2.0)] for g in gammas], state)   # eps_12 = gamma/2
    tau = np.array([r.stress[5] for r in responses]) / np.sqrt(2.0)
    if shear_damaged:
        assert tau.max() < 0.95 * TAU_C
        np.testing.assert_allclose(responses[-1].state["d"], responses[-1].state["d"][0], rtol=0, atol=0)
    else:
        assert tau.max() == pytest.approx(TAU_C, rel=1e-2)
        assert responses[-1].state["d"][0] == d_n                        # the shear leaves d_n alone
    if surface == "cuboid":       # one shear direction damages, the other stays virgin (which one is local y or z
        assert min(responses[-1].state["d"][1:]) == 0.0               # depends on the axes chosen in the crack plane)
        assert max(responses[-1].state["d"][1:]) > 0.0
    if surface == "elliptical_cylinder":
        assert responses[-1].state["d"][1] == responses[-1].state["d"][2] > 0.0


@pytest.mark.parametrize("surface", SURFACES)
def test_a_closed_crack_carries_compression_and_never_fails_in_the_normal_direction(surface):
    """Compression across a damaged crack: the full C_11 (the crack closes) and no damage growth, however far."""
    m = material(surface)
    state = cracked_in_tension(m)
    d = state["d"].copy()
    responses = drive_points(m, [[-e, 0, 0, 0, 0, 0] for e in np.linspace(0, 0.5, 50)], state)
    stress = np.array([r.stress[0] for r in responses])
    np.testing.assert_allclose(stress, -m.C11 * np.linspace(0, 0.5, 50), rtol=1e-12)
    np.testing.assert_array_equal(responses[-1].state["d"], d)


def test_surface_numbers_are_the_seeds():
    assert [material(k).surface for k in range(4)] == list(SURFACES)


# ---- crack normals -----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("angle", np.linspace(0.0, np.pi, 7))
def test_plane_crack_normal_is_the_principal_direction_of_a_rotated_tension(angle):
    """2D (plane=True): uniaxial tension along (cos a, sin a) cracks with exactly that normal (up to sign)."""
    m = material(plane=True)
    n = np.array([np.cos(angle), np.sin(angle), 0.0])
    stress_dir = T.to_mandel(np.outer(n, n))
    strain = np.linalg.solve(m.stiffness, stress_dir) * 1.2 * SIGMA_C           # sigma = 1.2 sigma_c n (x) n
    state = m.update(m.initial_state(()), strain).state
    assert state["initiated"]
    assert abs(state["axes"][0] @ n) == pytest.approx(1.0, abs=1e-12)
    assert state["axes"][2] @ [0.0, 0.0, 1.0] == pytest.approx(1.0)          # t2 out of the plane


@pytest.mark.parametrize("seed", range(5))
def test_crack_normal_is_the_principal_direction_in_3d(seed):
    """3D: tension 1.2 sigma_c along a random direction with smaller lateral stresses cracks along it; the axes are
    orthonormal."""
    m = material()
    Q = Rotation.random(random_state=seed).as_matrix()
    principal = np.diag([1.2 * SIGMA_C, 0.3 * SIGMA_C, -0.2 * SIGMA_C])
    stress = T.to_mandel(Q @ principal @ Q.T)
    state = m.update(m.initial_state(()), np.linalg.solve(m.stiffness, stress)).state
    axes = state["axes"]
    np.testing.assert_allclose(axes @ axes.T, np.eye(3), atol=1e-12)
    assert abs(axes[0] @ Q[:, 0]) == pytest.approx(1.0, abs=1e-10)


def test_shear_initiation_takes_the_plane_of_largest_shear():
    """sigma_1 = -sigma_3 = 1.1 tau_c (< sigma_c): a shear crack, normal halfway between v_1 and v_3."""
    m = material()
    stress = T.to_mandel(np.diag([1.1 * TAU_C, 0.0, -1.1 * TAU_C]))
    state = m.update(m.initial_state(()), np.linalg.solve(m.stiffness, stress)).state
    assert abs(state["axes"][0] @ np.array([1.0, 0.0, 1.0]) / np.sqrt(2.0)) == pytest.approx(1.0)


# ---- the tangent ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("surface", SURFACES)
@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("plane", [False, True])
def test_tangent_is_consistent_on_the_softening_branch(surface, law, plane):
    """Mixed strain, mid-softening: the returned tangent equals centred finite differences of the stress (1e-5)."""
    m = material(surface, law, 0.4, plane=plane)
    direction = np.array([1.0, 0.1, 0.0 if plane else -0.05, 0.0 if plane else 0.2, 0.0 if plane else 0.3, 0.4])
    state = m.initial_state((1,))
    for t in np.linspace(0.0, 0.032, 40):
        state = m.update(state, t * direction[None]).state
    eps = 0.0322 * direction[None] + 1e-4 * np.array([0.3, -0.2, 0.0, 0.0, 0.1 * (not plane), 0.5])
    response = m.update(state, eps)
    assert 0.05 < response.state["d"][0, 0] < 0.95
    fd = finite_difference_tangent(m, state, eps, h=1e-9)
    assert np.max(np.abs(response.tangent - fd)) < 1e-5 * np.max(np.abs(fd))


def test_elastic_tangent_is_the_stiffness_before_initiation():
    m = material()
    response = m.update(m.initial_state((3,)), np.full((3, 6), 1e-4))
    np.testing.assert_array_equal(response.tangent, np.broadcast_to(m.stiffness, (3, 6, 6)))


# ---- energy, residual strain ------------------------------------------------------------------------------------
def test_energy_budget_closes_on_a_mixed_path_with_unloading():
    """Work = stored + dissipated at every step of tension, unloading, shear with tension (ovoid), to 0.5 % of
    G_Ic/h: the dissipation is the integral of Y dd."""
    h = 0.3
    m = material("ovoid", h=h)
    peak = SIGMA_C / m.C11
    path = np.concatenate([np.outer(np.linspace(0, 1.3 * peak, 200), [1, 0, 0, 0, 0, 0]),
                           np.outer(np.linspace(1.3 * peak, 0.2 * peak, 100), [1, 0, 0, 0, 0, 0]),
                           [[0.2 * peak, 0, 0, 0, 0, s] for s in np.linspace(0, 0.06, 300)]])
    responses = drive_points(m, path)
    stress = np.array([r.stress for r in responses])
    eps = np.vstack([np.zeros(6), path])
    sig = np.vstack([np.zeros(6), stress])
    work_done = np.concatenate([[0.0], np.cumsum(np.sum(0.5 * (sig[1:] + sig[:-1]) * np.diff(eps, axis=0), axis=1))])
    stored = 0.5 * np.sum(sig * eps, axis=1)
    dissipated = np.array([0.0] + [float(m.dissipation(r.state)) for r in responses])
    assert np.max(np.abs(work_done - stored - dissipated)) < 5e-3 * G_I / h
    assert dissipated[-1] > 0.2 * G_I / h


def test_residual_strain_is_stress_free():
    """eps = eps_res gives zero stress; uniaxial strain (lateral strains held at zero, so the thermal residual strain
    compresses laterally by lambda 2 eps_res) cracks at eps_11 = eps_res + (sigma_c + 2 lambda eps_res)/C_11."""
    residual = np.array([1e-3, 1e-3, 1e-3, 0.0, 0.0, 0.0])
    m = material(residual_strain=residual)
    assert np.allclose(m.update(m.initial_state(()), residual).stress, 0.0, atol=1e-12)
    result = uniaxial_strain(m, residual[0] + ramp(2.0 * SIGMA_C / m.C11, 200))
    first = np.flatnonzero(result.internal["initiated"])[0]
    onset = residual[0] + (SIGMA_C + 2.0 * m.lam * residual[0]) / m.C11
    assert result.strain_component("11")[first] >= onset - 1e-12
    assert result.strain_component("11")[first - 1] < onset


def test_stored_energy_is_half_stress_times_strain():
    m = material()
    state = cracked_in_tension(m)
    state = m.update(state, np.array([2e-3, 1e-3, 0, 0, 0, 1e-3])).state
    assert m.stored_energy(state) == pytest.approx(0.5 * m.update(state, state["eps"]).stress @ state["eps"])


# ---- the softening laws and the rotation ----------------------------------------------------------------------------
@pytest.mark.parametrize("law", LAWS)
def test_softening_law_area_is_the_toughness_and_its_band_limit_its_steepest_slope(law):
    f = softening_law(law)
    strength, toughness = 3.0, 0.2
    area, _ = quad(lambda x: f.traction(x, strength, toughness), 0.0, np.inf if law == "exponential" else 1.0)
    assert area == pytest.approx(toughness, rel=1e-9)
    for delta in (0.01, 0.05, 0.1):
        part, _ = quad(lambda x: f.traction(x, strength, toughness), 0.0, delta)
        assert f.energy(delta, strength, toughness) == pytest.approx(part, rel=1e-9)
    assert f.traction(0.0, strength, toughness) == strength
    delta = np.array([0.0, 0.01, 0.05, 0.1])
    np.testing.assert_allclose(f.opening(f.traction(delta, strength, toughness), strength, toughness), delta,
                               atol=1e-12)
    slope = (f.traction(1e-9, strength, toughness) - strength) / 1e-9
    assert max_band_width(f, 100.0, strength, toughness) == pytest.approx(100.0 / -slope, rel=1e-6)


def test_mandel_rotation_is_orthogonal_and_rotates_tensors():
    rng = np.random.default_rng(3)
    Q = Rotation.random(4, random_state=1).as_matrix()
    A = rng.normal(size=(4, 3, 3))
    A = A + np.swapaxes(A, -1, -2)
    R = T.mandel_rotation(Q)
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(6), (4, 6, 6)), atol=1e-12)
    expected = T.to_mandel(Q @ A @ np.swapaxes(Q, -1, -2))
    np.testing.assert_allclose(np.einsum("mij,mj->mi", R, T.to_mandel(A)), expected, atol=1e-12)


# ---- hard cases and bad input --------------------------------------------------------------------------------------
@pytest.mark.parametrize("surface", SURFACES)
def test_damage_close_to_one_stays_finite(surface):
    """Pulled and sheared far past separation: damage at d_max, stress and tangent finite, the open crack carries
    (almost) nothing."""
    m = material(surface)
    path = [[e, 0.2 * e, 0, 0.1 * e, 0.1 * e, 0.3 * e] for e in np.linspace(0, 2.0, 100)]
    response = drive_points(m, path)[-1]
    assert np.all(np.isfinite(response.stress)) and np.all(np.isfinite(response.tangent))
    assert response.state["d"][0] == pytest.approx(m.d_max)
    local = T.mandel_rotation(response.state["axes"]) @ response.stress
    assert abs(local[0]) < 1e-6 * m.C11 * 2.0


def test_too_wide_a_band_is_refused_with_its_limit():
    h_max = 2.0 * E * G_I / SIGMA_C**2
    with pytest.raises(ValueError, match=r"band_width .* below 1\.111 mm .* mode I"):
        material(h=1.2 * h_max)
    material(h=0.99 * h_max)
    with pytest.raises(ValueError, match="band_width"):                # a less tough point narrows the limit
        material(h=0.9 * h_max, relative_toughness=0.8)
    material(h=1.1 * h_max, relative_strength=0.9)                     # a weaker one widens it (G/sigma^2)


def test_projected_band_width_is_the_element_extent_along_the_normal_and_is_checked_at_initiation():
    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 0.5], [0.0, 0.5]])[None]          # 2 mm along x, 0.5 along y
    wide = AnisotropicSofteningDamage(E, NU, SIGMA_C, TAU_C, G_I, G_II, band_width=ProjectedBandWidth(square),
                                      plane=True)
    pulled_y = np.linalg.solve(wide.stiffness, T.to_mandel(np.diag([0.0, 1.2 * SIGMA_C, 0.0])))[None]
    assert wide.update(wide.initial_state((1,)), pulled_y).state["band_width"][0] == pytest.approx(0.5)
    pulled_x = np.linalg.solve(wide.stiffness, T.to_mandel(np.diag([1.2 * SIGMA_C, 0.0, 0.0])))[None]
    with pytest.raises(ValueError, match="band_width"):                         # 2 mm > h_max = 1.11 mm
        wide.update(wide.initial_state((1,)), pulled_x)


@pytest.mark.parametrize("changes, match", [
    ({"nu": 0.5}, "nu"), ({"sigma_c": -1.0}, "sigma_c"), ({"G_IIc": 0.0}, "G_IIc"), ({"surface": "sphere"}, "surface"),
    ({"surface": 4}, "surface"), ({"softening_I": "cubic"}, "softening law"), ({"d_max": 1.0}, "d_max"),
    ({"relative_strength": -0.5}, "relative_strength"), ({"residual_strain": np.zeros(5)}, "residual_strain"),
    ({"band_width": -1.0}, "band_width"),
])
def test_bad_input_is_refused_by_name(changes, match):
    arguments = {"E": E, "nu": NU, "sigma_c": SIGMA_C, "tau_c": TAU_C, "G_Ic": G_I, "G_IIc": G_II, "band_width": 0.3}
    arguments.update(changes)
    with pytest.raises(ValueError, match=match):
        AnisotropicSofteningDamage(**arguments)


def test_a_nan_strain_is_refused():
    with pytest.raises(ValueError, match="eps"):
        material().update(material().initial_state(()), np.full(6, np.nan))


def test_uniaxial_stress_with_poisson_contraction_dissipates_the_toughness():
    """Uniaxial stress (nu = 0.25): lateral contraction does not change the mode I energy (1 %)."""
    h = 0.3
    m = material(h=h)
    result = uniaxial_stress(m, ramp(SIGMA_C / E + 2.0 * G_I / SIGMA_C / h, 1500))
    assert work(result, "11") * h == pytest.approx(G_I, rel=1e-2)
    assert result.stress_component("11").max() == pytest.approx(SIGMA_C, rel=1e-2)


# ---- a prescribed crack plane, the secant tangent -----------------------------------------------------------------
def test_prescribed_crack_plane_cracks_when_its_traction_reaches_the_strength():
    """crack_normal = y: uniaxial strain along x never cracks that plane (no traction on it in tension along x;
    the Poisson stresses stay below sigma_c); along y it cracks at sigma_yy = sigma_c with normal y."""
    m = material(crack_normal=(0.0, 2.0, 0.0))                        # normalised on construction
    np.testing.assert_allclose(m.crack_normal, [0.0, 1.0, 0.0])
    along_x = uniaxial_strain(m, ramp(0.9 * SIGMA_C / m.lam, 50))     # sigma_yy = lambda eps < 0.9 sigma_c
    assert not along_x.internal["initiated"].any()
    state = m.initial_state(())
    for eps in np.linspace(0.0, 1.2 * SIGMA_C / m.C11, 60):
        response = m.update(state, np.array([0.0, eps, 0.0, 0.0, 0.0, 0.0]))
        if response.state["initiated"] and not state["initiated"]:
            assert response.stress[1] <= SIGMA_C * (1.0 + 1e-12)
            assert eps * m.C11 >= SIGMA_C
            np.testing.assert_allclose(response.state["axes"][0], [0.0, 1.0, 0.0])
        state = response.state
    assert state["initiated"]


def test_prescribed_crack_plane_must_lie_in_the_plane_for_2d():
    with pytest.raises(ValueError, match="crack_normal"):
        material(plane=True, crack_normal=(0.0, 0.6, 0.8))
    with pytest.raises(ValueError, match="crack_normal"):
        material(crack_normal=(0.0, 0.0, 0.0))


def test_secant_tangent_is_the_symmetric_damaged_stiffness():
    m = material(tangent="secant")
    state = cracked_in_tension(m)
    eps = np.array([1.4 * SIGMA_C / m.C11, 0.0, 0.0, 0.0, 0.0, 0.0])
    response = m.update(state, eps)
    np.testing.assert_allclose(response.tangent, response.tangent.T, atol=1e-9)
    np.testing.assert_allclose(response.tangent @ eps, response.stress, rtol=1e-12)
    with pytest.raises(ValueError, match="tangent"):
        material(tangent="numerical")


def test_shear_initiation_does_not_depend_on_pressure():
    """The seed's optional pressure-dependent shear strength is not built (decisions page): a hydrostatic pressure
    added to a shear state moves neither the shear initiation nor its plane."""
    m = material()
    for pressure in (0.0, -50.0, -200.0):
        stress = T.to_mandel(np.diag([1.01 * TAU_C, 0.0, -1.01 * TAU_C]) + pressure * np.eye(3))
        state = m.update(m.initial_state(()), np.linalg.solve(m.stiffness, stress)).state
        assert state["initiated"]
        assert abs(state["axes"][0] @ np.array([1.0, 0.0, 1.0]) / np.sqrt(2.0)) == pytest.approx(1.0)
        below = T.to_mandel(np.diag([0.99 * TAU_C, 0.0, -0.99 * TAU_C]) + pressure * np.eye(3))
        assert not m.update(m.initial_state(()), np.linalg.solve(m.stiffness, below)).state["initiated"]


@pytest.mark.parametrize("surface, expected", [("cuboid", (0.8, 0.8, 0.9, 0.8)),
                                               ("elliptical_cylinder", (0.8, 0.8, np.hypot(0.9, 0.9), 0.8)),
                                               ("ovoid", (np.hypot(0.8, 0.8), 0.8, np.hypot(0.9, 0.9), 0.8)),
                                               ("coupled_cuboid", (0.8, 0.8, 0.9, 0.8))])
def test_traction_failure_surfaces_have_the_seeds_shapes(surface, expected):
    """f at (T_n, T_1, T_2) = (0.8 sigma_c, 0.8 tau_c, 0), (-5 sigma_c, 0.8 tau_c, 0) (compression: the shear limit
    alone), (0, 0.9 tau_c, 0.9 tau_c) and (0.8 sigma_c, 0, 0): rectangles, a circle in shear for the elliptical
    cylinder and the ovoid, an ellipse in tension for the ovoid."""
    m = material(surface)
    points = np.array([[0.8 * SIGMA_C, 0.8 * TAU_C, 0.0], [-5 * SIGMA_C, 0.8 * TAU_C, 0.0],
                       [0.0, 0.9 * TAU_C, 0.9 * TAU_C], [0.8 * SIGMA_C, 0.0, 0.0]])
    np.testing.assert_allclose(m.traction_ratio(*points.T), expected, rtol=1e-12)
