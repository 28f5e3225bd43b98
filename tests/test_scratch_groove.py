"""Tests of abrakit.scratch.groove: groove metrics (Eq. 8.5, 8.6) on profiles with known areas, sections of a
deformed mesh, removed material."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.scratch import groove_metrics
from abrakit.scratch.groove import profile_from_surface_nodes, removed_material


def v_groove(depth=2.0, half_width=10.0, pile=1.0, pile_width=5.0, far=30.0):
    """Full V groove |x| < a with triangular pile-ups on a < |x| < a + b; breakpoints are samples."""
    a, b = half_width, pile_width
    x = np.array([-far, -a - b, -a - b / 2, -a, 0.0, a, a + b / 2, a + b, far])
    y = np.array([0.0, 0.0, pile, 0.0, -depth, 0.0, pile, 0.0, 0.0])
    return x, y


def test_v_groove_with_triangular_pile_ups_is_exact():
    m = groove_metrics(*v_groove(), half=False)
    assert m.groove_area == pytest.approx(2.0 * 10.0)            # triangle: base 20, height 2
    assert m.shoulder_area == pytest.approx(2 * 0.5 * 5.0 * 1.0)  # two triangles: base 5, height 1
    assert m.width == pytest.approx(20.0)
    assert m.depth == pytest.approx(2.0)
    assert m.degree_of_wear == pytest.approx((20.0 - 5.0) / 20.0)   # Eq. (8.5)
    assert m.degree_of_penetration == pytest.approx(2 * 2.0 / 20.0)  # Eq. (8.6)
    assert m.regime == "cutting"
    assert m.crest_width == pytest.approx(25.0) and m.shoulder_height == pytest.approx(1.0)


def test_crossings_between_samples_are_found_exactly():
    """A coarse linear profile whose zero crossings fall inside segments: areas are the exact triangles."""
    x = np.array([-20.0, -10.0, 0.0, 10.0, 20.0])
    y = np.array([1.0, 1.0, -4.0, 1.0, 1.0])
    m = groove_metrics(x, y, half=False)
    # the profile crosses y = 0 at x = +-8: groove triangle 16 x 4 / 2; each shoulder a 2 x 1 triangle plus a
    # 10 x 1 rectangle up to the end of the profile
    assert m.width == pytest.approx(16.0)
    assert m.groove_area == pytest.approx(32.0)
    assert m.shoulder_area == pytest.approx(2 * (1.0 + 10.0))
    assert m.degree_of_wear == pytest.approx(10.0 / 32.0)
    assert m.crest_width == pytest.approx(20.0)         # ties go to the sample nearest the groove: x = +-10


def test_parabolic_groove_matches_the_trapezoid_error_exactly():
    """y = k x^2 - c with crossings on samples: the piecewise-linear area is the exact one minus a h^2 k / 3."""
    k, c = 0.02, 2.0
    a = np.sqrt(c / k)                                  # 10
    for n in (10, 40, 160):
        h = 2 * a / n
        x = np.concatenate([[-a - 5.0], np.linspace(-a, a, n + 1), [a + 5.0]])
        y = np.where(np.abs(x) <= a, k * x**2 - c, 0.0)
        m = groove_metrics(x, y, half=False)
        exact = 4.0 / 3.0 * c * a
        assert m.groove_area == pytest.approx(exact - a * h**2 * k / 3.0, rel=1e-12)
        assert m.width == pytest.approx(2 * a)
        assert m.shoulder_area == 0.0 and m.degree_of_wear == pytest.approx(1.0) and m.crest_width is None


def test_sphere_shaped_groove_area_converges_to_the_circular_segment():
    """The groove cut by a sphere R to depth d: the circular segment area, second order in the sampling."""
    R, d = 50.0, 2.0
    a = np.sqrt(2 * R * d - d**2)
    exact = R**2 * np.arccos((R - d) / R) - (R - d) * a
    errors = []
    for n in (50, 100, 200):
        x = np.concatenate([[-a - 5], np.linspace(-a, a, n + 1), [a + 5]])
        y = np.minimum(R - d - np.sqrt(R**2 - np.minimum(x**2, R**2)), 0.0)
        errors.append(abs(groove_metrics(x, y, half=False).groove_area - exact) / exact)
    assert errors[-1] < 1e-3
    np.testing.assert_allclose(np.array(errors[:-1]) / errors[1:], 4.0, rtol=0.05)


def test_half_profile_gives_the_full_metrics():
    x, y = v_groove()
    keep = x >= 0
    full = groove_metrics(x, y, half=False)
    half = groove_metrics(x[keep], y[keep], half=True)
    for name in ("groove_area", "shoulder_area", "width", "depth", "degree_of_wear", "degree_of_penetration",
                 "crest_width", "shoulder_height"):
        assert getattr(half, name) == pytest.approx(getattr(full, name)), name
    assert half.regime == full.regime


@given(st.lists(st.floats(0.05, 3.0), min_size=2, max_size=12), st.lists(st.floats(0.0, 1.0), min_size=1,
       max_size=8), st.integers(0, 2**31))
@settings(max_examples=80, deadline=None)
def test_net_area_equals_the_integral_of_the_profile(groove_depths, pile_heights, seed):
    """Independent check: for a groove with one shoulder each side returning to 0, A_s - A_g = trapz(y)."""
    rng = np.random.default_rng(seed)
    left_pile = np.array(pile_heights)
    right_pile = np.array(pile_heights[::-1]) * 0.7
    y = np.concatenate([[0.0], left_pile + 1e-3, [0.0], -np.array(groove_depths), [0.0], right_pile + 1e-3, [0.0]])
    x = np.cumsum(rng.uniform(0.1, 2.0, y.size))
    areas_ok = True
    try:
        m = groove_metrics(x, y, half=False)
    except ValueError as err:                          # shoulders larger than the groove: f_ab undefined
        assert "A_s" in str(err)
        areas_ok = False
    if areas_ok:
        assert m.shoulder_area - m.groove_area == pytest.approx(np.trapezoid(y, x), abs=1e-9)
        assert m.groove_area == pytest.approx(-np.trapezoid(np.minimum(y, 0), x), rel=1e-12)
        assert 0.0 <= m.degree_of_wear <= 1.0


def test_far_field_undulations_and_noise_floor():
    x, y = v_groove()
    # a bump far out, separated from the shoulder by a return to y = 0, is not a shoulder
    x2 = np.append(x, [40.0, 45.0, 50.0])
    y2 = np.append(y, [0.5, 0.0, 0.0])
    assert groove_metrics(x2, y2, half=False).shoulder_area == pytest.approx(5.0)
    # noise of 1e-6 around the original surface is cleared by tol
    noisy = y + np.where(y == 0.0, 1e-6 * np.sin(np.arange(y.size)), 0.0)
    m = groove_metrics(x, noisy, half=False, tol=1e-5)
    assert m.shoulder_area == pytest.approx(5.0) and m.groove_area == pytest.approx(20.0)


def test_depth_override_and_regimes():
    x, y = v_groove(pile=3.0)                       # A_s = 15, A_g = 20: f_ab = 0.25
    m = groove_metrics(x, y, half=False, depth=1.0)
    assert m.degree_of_wear == pytest.approx(0.25) and m.regime == "wedging"
    assert m.degree_of_penetration == pytest.approx(2 * 1.0 / 20.0)
    m = groove_metrics(*v_groove(pile=3.8), half=False)       # A_s = 19: f_ab = 0.05
    assert m.regime == "plowing"


@pytest.mark.parametrize("x, y, half, match", [
    ([0, 1, 2, 3], [0, 0.1, 0.2, 0], False, "no groove"),
    ([0, 1, 2, 3], [0, -1, -1, -0.5], False, "does not close on the right"),
    ([0, 1, 2, 3], [-1, -1, 0.5, 0], False, "does not close on the left"),
    ([0, 1, 2, 3], [0.5, -1, 0.5, 0], True, "touch the symmetry plane"),
    ([1, 2, 3, 4], [-1, 0, 0.5, 0], True, "symmetry plane x = 0"),
    ([0, 2, 1, 3], [0, -1, 0, 0], False, "strictly increasing"),
    ([-4, -1, 0, 1, 4], [0, 3, -1, 3, 0], False, "A_s"),
    ([0, 1], [-1, 0], True, "at least 3"),
])
def test_bad_profiles_are_refused(x, y, half, match):
    with pytest.raises(ValueError, match=match):
        groove_metrics(x, y, half=half)


# --- sections of a deformed tensor-product mesh --------------------------------------------------------------


def tensor_surface_mesh():
    """Nodes of a graded tensor grid on the half block x >= 0 (top y = 0), with a groove-like displacement."""
    xs = np.array([0.0, 0.001, 0.002, 0.004, 0.008, 0.012, 0.02])
    ys = np.array([-0.015, -0.005, -0.002, 0.0])
    zs = np.array([0.0, 0.01, 0.02, 0.035, 0.05])
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    points = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    # u_y = -d (1 - (x/a)^2) for x < a, bilinear in x, z, plus u_z = s z (a stretch) and u_x = 0
    a, d = 0.008, 0.002
    u = np.zeros_like(points)
    u[:, 1] = np.where(points[:, 0] < a, -d * (1 - (points[:, 0] / a) ** 2), 0.0) * (1 + 2 * points[:, 2])
    u[:, 2] = 0.1 * points[:, 2]
    return points, u, xs


def test_material_section_interpolates_linearly_between_layers():
    points, u, xs = tensor_surface_mesh()
    rng = np.random.default_rng(7)
    order = rng.permutation(points.shape[0])            # node numbering must not matter
    prof = profile_from_surface_nodes(points[order], u[order], 0.03, section="material")
    np.testing.assert_allclose(prof.x, xs)
    # between layers z = 0.02 and 0.035 the nodal y values are linear in z: exact at z = 0.03
    y_expected = np.where(xs < 0.008, -0.002 * (1 - (xs / 0.008) ** 2), 0.0) * (1 + 2 * 0.03)
    np.testing.assert_allclose(prof.y, y_expected, atol=1e-15)
    np.testing.assert_allclose(prof.z, 0.03 * 1.1)


def test_spatial_section_follows_the_deformed_layers():
    points, u, xs = tensor_surface_mesh()
    prof = profile_from_surface_nodes(points, u, 0.033)   # spatial z = 1.1 Z: reference Z = 0.03
    np.testing.assert_allclose(prof.z, 0.033)
    y_expected = np.where(xs < 0.008, -0.002 * (1 - (xs / 0.008) ** 2), 0.0) * (1 + 2 * 0.03)
    np.testing.assert_allclose(prof.y, y_expected, atol=1e-15)
    m = groove_metrics(prof.x, prof.y, half=True)
    assert m.width == pytest.approx(2 * 0.008) and m.depth == pytest.approx(0.002 * 1.06)


def test_section_refusals():
    points, u, _ = tensor_surface_mesh()
    with pytest.raises(ValueError, match="outside"):
        profile_from_surface_nodes(points, u, 0.06)
    with pytest.raises(ValueError, match="outside"):
        profile_from_surface_nodes(points, u, 0.06, section="material")
    keep = np.arange(points.shape[0]) != np.flatnonzero(points[:, 1] == 0.0)[5]     # drop one surface node
    with pytest.raises(ValueError, match="tensor grid"):
        profile_from_surface_nodes(points[keep], u[keep], 0.03)
    folded = u.copy()
    folded[:, 2] = -2.0 * points[:, 2]
    with pytest.raises(ValueError, match="folds"):
        profile_from_surface_nodes(points, folded, 0.0)
    with pytest.raises(ValueError, match="section"):
        profile_from_surface_nodes(points, u, 0.03, section="both")
    with pytest.raises(ValueError, match="top surface"):
        profile_from_surface_nodes(points, u, 0.03, top=0.5)


def test_removed_material():
    volumes = np.array([1.0, 2.0, 3.0, 4.0]) * 1e-9
    damage = np.array([0.99, 0.5, 0.99 * (1 - 1e-12), 0.98])
    centres = np.array([[0, 0, 0.01], [0, 0, 0.02], [0, 0, 0.03], [0, 0, 0.09]])
    r = removed_material(volumes, damage, 0.99, half=False)
    assert r.count == 2 and r.volume == pytest.approx(4e-9) and r.area is None
    np.testing.assert_array_equal(r.mask, [True, False, True, False])
    r = removed_material(volumes, damage, 0.99, half=True, centres=centres, z_range=(0.0, 0.025))
    assert r.count == 1 and r.volume == pytest.approx(2e-9) and r.area == pytest.approx(2e-9 / 0.025)
    with pytest.raises(ValueError, match="cap"):
        removed_material(volumes, damage, 1.5, half=False)
    with pytest.raises(ValueError, match="centres"):
        removed_material(volumes, damage, 0.99, half=False, z_range=(0, 1))
    with pytest.raises(ValueError, match="damage"):
        removed_material(volumes, damage[:2], 0.99, half=False)
