"""Tests of abrakit.scratch.indenters and abrakit.scratch.hertz: analytic tips, the tip path and Hertz's numbers."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.scratch import ConicalIndenter, SphericalIndenter, hertz_sphere
from abrakit.scratch.hertz import effective_modulus, hertz_depth
from abrakit.scratch.indenters import FineZone, ScratchPath, check_path

R = 0.05
TIP = np.array([0.01, -0.002, 0.03])
INDENTERS = [SphericalIndenter(R), ConicalIndenter(R, 30.0), ConicalIndenter(R, 60.0)]


def surface_points(indenter, tip, rho, phi):
    """Points on the surface of revolution at radial distance rho and azimuth phi (rho, phi arrays)."""
    h = indenter.height(rho)
    return tip + np.stack([rho * np.cos(phi), h, rho * np.sin(phi)], axis=-1)


def random_points(seed, n=200, spread=0.03):
    rng = np.random.default_rng(seed)
    return TIP + rng.uniform(-spread, spread, (n, 3)) * [1, 0.3, 1] + [0, 0.004, 0]


@pytest.mark.parametrize("indenter", INDENTERS, ids=["sphere", "cone30", "cone60"])
def test_points_on_the_surface_have_zero_gap_and_are_their_own_closest_point(indenter):
    rng = np.random.default_rng(0)
    rho = rng.uniform(0.0, 0.045, 300)
    phi = rng.uniform(0.0, 2 * np.pi, 300)
    x = surface_points(indenter, TIP, rho, phi)
    sg = indenter.gap(x, TIP)
    np.testing.assert_allclose(sg.gap, 0.0, atol=1e-14)
    np.testing.assert_allclose(sg.closest, x, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(sg.normal, axis=1), 1.0, atol=1e-14)


@pytest.mark.parametrize("indenter", INDENTERS, ids=["sphere", "cone30", "cone60"])
def test_gap_decomposition_and_closest_point_on_surface(indenter):
    x = random_points(1)
    sg = indenter.gap(x, TIP)
    np.testing.assert_allclose(sg.closest + sg.gap[:, None] * sg.normal, x, atol=1e-14)
    # the closest point lies on the surface: its height above the apex is the profile height at its radius
    rel = sg.closest - TIP
    rho = np.hypot(rel[:, 0], rel[:, 2])
    np.testing.assert_allclose(rel[:, 1], indenter.height(rho), atol=1e-13)
    assert np.any(sg.gap < 0) and np.any(sg.gap > 0)


@pytest.mark.parametrize("indenter", INDENTERS, ids=["sphere", "cone30", "cone60"])
def test_gap_is_the_distance_to_a_dense_sampling_of_the_surface(indenter):
    """Independent check: the distance of outside points to ~10^5 surface samples."""
    rng = np.random.default_rng(2)
    x = TIP + rng.uniform(-0.02, 0.02, (40, 3)) * [1, 0.5, 1] + [0, 0.0, 0]
    sg = indenter.gap(x, TIP)
    x, gap = x[sg.gap > 1e-4], sg.gap[sg.gap > 1e-4]
    rho, phi = np.meshgrid(np.linspace(0, 0.045, 400), np.linspace(0, 2 * np.pi, 400, endpoint=False))
    cloud = surface_points(indenter, TIP, rho.ravel(), phi.ravel())
    brute = np.min(np.linalg.norm(x[:, None, :] - cloud[None], axis=-1), axis=1)
    np.testing.assert_allclose(gap, brute, atol=2e-4 * 0.045)
    assert np.all(brute >= gap - 1e-12)


@pytest.mark.parametrize("indenter", INDENTERS, ids=["sphere", "cone30", "cone60"])
def test_normal_is_the_gap_gradient_and_normal_gradient_is_its_derivative(indenter):
    x = random_points(3, n=60)
    sg = indenter.gap(x, TIP)
    h = 1e-7
    for j in range(3):
        dx = np.zeros(3)
        dx[j] = h
        up, down = indenter.gap(x + dx, TIP), indenter.gap(x - dx, TIP)
        np.testing.assert_allclose((up.gap - down.gap) / (2 * h), sg.normal[:, j], atol=1e-7)
        np.testing.assert_allclose((up.normal - down.normal) / (2 * h), sg.normal_gradient[:, :, j],
                                   rtol=1e-5, atol=1e-4)
    np.testing.assert_allclose(sg.normal_gradient, np.swapaxes(sg.normal_gradient, 1, 2), atol=1e-12)


def test_sphere_values_are_analytic():
    sg = SphericalIndenter(R).gap([[0.0, 0.0, 0.0], [0.0, 0.1, 0.08]], [0.0, -0.002, 0.0])
    np.testing.assert_allclose(sg.gap, [-0.002, math.hypot(0.052, 0.08) - R])
    np.testing.assert_allclose(sg.normal[0], [0, -1, 0])
    np.testing.assert_allclose(sg.normal_gradient[0], np.diag([1, 0, 1]) / 0.048)


def test_cone_is_continuous_across_the_tangency_circle_and_matches_the_generator_far_out():
    cone = ConicalIndenter(R, 30.0)
    a = math.radians(30.0)
    rho_t = R * math.cos(a)
    assert cone.cap_height == pytest.approx(R * (1 - math.sin(a)))
    assert cone.height(rho_t) == pytest.approx(cone.cap_height)
    # points straddling the normal line through the tangency circle: gap and normal vary continuously
    t = np.array([rho_t, cone.cap_height, 0.0])
    m = np.array([math.cos(a), -math.sin(a), 0.0])
    gen = np.array([math.sin(a), math.cos(a), 0.0])
    x = t + 0.003 * m + np.outer([-1e-9, 1e-9], gen)
    sg = cone.gap(x, np.zeros(3))
    np.testing.assert_allclose(sg.gap, 0.003, atol=1e-12)
    np.testing.assert_allclose(sg.normal, [m, m], atol=1e-9)
    # far up the flank: the gap is the distance to the generator line
    p = t + 0.02 * gen + 0.001 * m
    assert cone.gap(p[None], np.zeros(3)).gap[0] == pytest.approx(0.001)
    # slope of the flank: 1/tan(alpha) per unit radius
    assert cone.height(rho_t + 0.01) - cone.height(rho_t) == pytest.approx(0.01 / math.tan(a))


def test_cone_from_included_angle_and_footprints():
    cone = ConicalIndenter.from_included_angle(0.025)
    assert cone.half_angle == 30.0
    sphere = SphericalIndenter(0.025)
    # at the seed's d = 3 um only the cap touches, for every radius of Fig. 8.10
    for radius in (0.025, 0.05, 0.1):
        tip = ConicalIndenter.from_included_angle(radius)
        assert tip.cap_height > 0.003
        assert tip.footprint_radius(0.003) == pytest.approx(SphericalIndenter(radius).footprint_radius(0.003))
    assert sphere.footprint_radius(0.002) == pytest.approx(math.sqrt(2 * 0.025 * 0.002 - 0.002**2))
    blunt = ConicalIndenter(0.025, 60.0)                 # cap up to R(1 - sin 60) = 3.35 um
    d = 0.006
    assert blunt.footprint_radius(d) == pytest.approx(0.025 * 0.5 + (d - blunt.cap_height) * math.tan(math.pi / 3))
    assert blunt.height(blunt.footprint_radius(d)) == pytest.approx(d)


@pytest.mark.parametrize("bad", [
    lambda: SphericalIndenter(0.0),
    lambda: ConicalIndenter(0.05, 90.0),
    lambda: ConicalIndenter.from_included_angle(0.05, 180.0),
    lambda: SphericalIndenter(R).gap(np.zeros((2, 2)), np.zeros(3)),
    lambda: SphericalIndenter(R).gap([[0.0, 0.05, 0.0]], [0.0, 0.0, 0.0]),     # at the centre
    lambda: ConicalIndenter(R, 30.0).gap([[0.0, 0.2, 0.0]], [0.0, 0.0, 0.0]),  # on the axis, deep inside
    lambda: SphericalIndenter(R).gap([[np.nan, 0.0, 0.0]], [0.0, 0.0, 0.0]),
])
def test_bad_input_is_refused(bad):
    with pytest.raises(ValueError):
        bad()


def test_path_indents_slides_and_unloads():
    path = ScratchPath(depth=0.002, slide=0.1, z_start=0.05, clearance=0.001)
    np.testing.assert_allclose(path.position(0.0), [0, 0.001, 0.05])
    np.testing.assert_allclose(path.position(0.5), [0, -0.0005, 0.05])
    np.testing.assert_allclose(path.position(1.0), [0, -0.002, 0.05])
    np.testing.assert_allclose(path.position(1.5), [0, -0.002, 0.1])
    np.testing.assert_allclose(path.position(2.0), [0, -0.002, 0.15])
    np.testing.assert_allclose(path.position(3.0), [0, 0.001, 0.15])
    assert path.position(np.linspace(0, 3, 7)).shape == (7, 3)
    assert list(path.phase(np.array([0.3, 1.3, 2.3]))) == ["indentation", "scratching", "unloading"]
    assert path.phase(1.0) == "indentation" and path.end == 3.0 and path.z_end == pytest.approx(0.15)
    assert ScratchPath(0.002, 0.1, unload=False).end == 2.0
    with pytest.raises(ValueError, match="tau"):
        ScratchPath(0.002, 0.1, unload=False).position(2.5)


def test_an_indenter_starting_inside_the_block_is_refused():
    with pytest.raises(ValueError, match="starts inside the block"):
        ScratchPath(depth=0.002, slide=0.1, clearance=-1e-4)
    with pytest.raises(ValueError, match="depth"):
        ScratchPath(depth=0.0, slide=0.1)


def test_sliding_past_the_fine_zone_is_refused():
    tip = SphericalIndenter(R)
    path = ScratchPath(depth=0.002, slide=0.1, z_start=0.05)
    a = tip.footprint_radius(0.002)
    assert check_path(path, (0.0, 0.15)) is path                  # apex only
    assert check_path(path, FineZone(0.05 - a, 0.15 + a, x_max=a), tip) is path
    with pytest.raises(ValueError, match="slides past the end of the fine zone"):
        check_path(path, (0.0, 0.149))
    with pytest.raises(ValueError, match="slides past the end of the fine zone"):
        check_path(path, (0.0, 0.15 + 0.99 * a), tip)
    with pytest.raises(ValueError, match="starts before the fine zone"):
        check_path(path, (0.05 - 0.99 * a, 0.2), tip)
    with pytest.raises(ValueError, match="wider"):
        check_path(path, FineZone(0.0, 0.2, x_max=0.9 * a), tip)
    with pytest.raises(ValueError, match="depth"):
        check_path(path, FineZone(0.0, 0.2, depth=0.001))


# --- Hertz --------------------------------------------------------------------------------------------------


def test_hertz_numbers_by_hand():
    """Steel (E = 210 GPa, nu = 0.3) under a rigid sphere R = 50 um at d = 1 um, computed by hand."""
    h = hertz_sphere(210000.0, 0.3, 0.05, 0.001)
    E_star = 210000.0 / 0.91                                   # 230769.23 MPa
    assert h.effective_modulus == pytest.approx(E_star)
    assert h.force == pytest.approx(4 / 3 * E_star * math.sqrt(0.05) * 0.001**1.5)
    assert h.force == pytest.approx(2.17571, rel=1e-5)         # N
    assert h.contact_radius == pytest.approx(math.sqrt(0.05e-3))   # 7.0711 um
    assert h.max_pressure == pytest.approx(2 * E_star / math.pi * math.sqrt(0.02), rel=1e-12)
    assert h.max_pressure == pytest.approx(20776.5, rel=1e-5)      # MPa


@given(st.floats(1e3, 1e6), st.floats(-0.9, 0.49), st.floats(1e-3, 1.0), st.floats(1e-5, 1e-2))
@settings(max_examples=60, deadline=None)
def test_hertz_identities(E, nu, radius, d):
    h = hertz_sphere(E, nu, radius, d)
    # p0 = 3F / (2 pi a^2), a^2 = R d, and the contact stiffness dF/dd = 2 E* a (Sneddon)
    assert h.max_pressure == pytest.approx(3 * h.force / (2 * math.pi * h.contact_radius**2), rel=1e-10)
    assert h.contact_radius**2 == pytest.approx(radius * d, rel=1e-12)
    eps = 1e-6 * d
    stiffness = (hertz_sphere(E, nu, radius, d + eps).force - hertz_sphere(E, nu, radius, d - eps).force) / (2 * eps)
    assert stiffness == pytest.approx(2 * h.effective_modulus * h.contact_radius, rel=1e-6)
    assert hertz_depth(h.force, E, nu, radius) == pytest.approx(d, rel=1e-10)


def test_hertz_with_a_quartz_grain_and_arrays():
    E_star = effective_modulus(210000.0, 0.33, 73000.0, 0.17)
    assert E_star == pytest.approx(1 / ((1 - 0.33**2) / 210000 + (1 - 0.17**2) / 73000))
    assert E_star < effective_modulus(210000.0, 0.33) < 210000.0 / (1 - 0.33**2) + 1e-9
    d = np.array([0.0, 0.001, 0.002])
    h = hertz_sphere(210000.0, 0.33, 0.05, d, E_indenter=73000.0)
    assert h.force.shape == (3,) and h.force[0] == 0.0
    assert h.force[2] / h.force[1] == pytest.approx(2**1.5)
    with pytest.raises(ValueError, match="nu"):
        hertz_sphere(210000.0, 0.5, 0.05, 0.001)
    with pytest.raises(ValueError, match="d"):
        hertz_sphere(210000.0, 0.3, 0.05, -0.001)
