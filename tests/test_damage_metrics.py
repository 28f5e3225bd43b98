"""Mesh-independence metrics (abrakit.damage.metrics): exact on synthetic curves and fields."""

import numpy as np
import pytest
import skfem
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.damage import metrics as M


# ---- curves ----------------------------------------------------------------------------------------------------
def test_peak_and_relative_spread():
    u = np.array([0.0, 1.0, 2.0, 3.0])
    F = np.array([0.0, 5.0, 7.0, 1.0])
    assert M.peak(u, F) == (7.0, 2.0)
    assert M.relative_spread([9.0, 10.0, 11.0]) == pytest.approx(0.2)
    assert M.relative_spread([4.0, 4.0]) == 0.0


def test_curve_distance_of_shifted_curve_is_exact():
    # F = 1 + u and F_ref = u on [0, 2]: difference 1 everywhere, max |F_ref| = 2 -> 0.5
    u = np.linspace(0.0, 2.0, 7)
    assert M.curve_distance(u, 1.0 + u, u, u) == pytest.approx(0.5, rel=1e-14)


def test_curve_distance_on_different_nodes_is_exact():
    # F = u^2 sampled at 0, 1, 2 (piecewise linear: u on [0,1], 3u - 2 on [1,2]); reference F_ref = 2u on a fine
    # grid. Difference g = -u on [0,1], u - 2 on [1,2]: int g^2 = 1/3 + 1/3; RMS = sqrt(2/3 / 2); max|F_ref| = 4
    u = np.array([0.0, 1.0, 2.0])
    u_ref = np.linspace(0.0, 2.0, 11)
    expected = np.sqrt((2.0 / 3.0) / 2.0) / 4.0
    assert M.curve_distance(u, u**2, u_ref, 2 * u_ref) == pytest.approx(expected, rel=1e-13)


def test_curve_distance_uses_common_range_only():
    u_ref = np.linspace(0.0, 1.0, 5)
    u = np.linspace(0.0, 3.0, 13)
    F = np.where(u <= 1.0, u, 100.0)  # agrees on [0, 1], wildly different beyond
    assert M.curve_distance(u, F, u_ref, u_ref) == pytest.approx(0.0, abs=1e-15)
    with pytest.raises(ValueError, match="share no displacement range"):
        M.curve_distance([2.0, 3.0], [1.0, 1.0], [0.0, 1.0], [1.0, 1.0])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-5, 5), min_size=3, max_size=8), st.floats(0.1, 3.0))
def test_curve_distance_matches_dense_quadrature(values, length):
    u = np.linspace(0.0, length, len(values))
    F = np.asarray(values)
    u_ref = np.linspace(0.0, length, 4)
    F_ref = 2.0 + u_ref
    dense = np.linspace(0.0, length, 200001)
    g = np.interp(dense, u, F) - np.interp(dense, u_ref, F_ref)
    rms = np.sqrt(np.trapezoid(g**2, dense) / length) / np.max(np.abs(F_ref))
    assert M.curve_distance(u, F, u_ref, F_ref) == pytest.approx(rms, rel=1e-6, abs=1e-9)


def test_work_and_partial_work_are_exact():
    u = np.array([0.0, 1.0, 3.0])
    F = np.array([0.0, 2.0, 0.0])  # triangle: area 3
    assert M.work(u, F) == pytest.approx(3.0)
    assert M.work(u, F, upto=2.0) == pytest.approx(1.0 + 1.5)  # 1 + (2 + 1)/2


def test_softening_displacement():
    u = np.array([0.0, 1.0, 2.0, 4.0])
    F = np.array([0.0, 10.0, 8.0, 0.0])
    # falls to 5 between u = 2 (F = 8) and u = 4 (F = 0): at u = 2 + 2 * 3/8 = 2.75 -> 1.75 past the peak
    assert M.softening_displacement(u, F, 0.5) == pytest.approx(1.75)
    assert M.softening_displacement(u, F, 0.8) == pytest.approx(1.0)
    assert M.softening_displacement(u[:3], F[:3], 0.5) == np.inf


def test_largest_drop_is_the_largest_fall_of_one_step_after_the_peak():
    u = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    assert M.largest_drop(u, np.array([0.0, 10.0, 8.0, 3.0, 2.5, 2.0])) == pytest.approx(0.5)
    assert M.largest_drop(u, np.array([0.0, 2.0, 4.0, 6.0, 8.0, 10.0])) == 0.0          # never falls
    assert M.largest_drop(u, np.array([0.0, 10.0, 1.0, 9.0, 0.0, 0.0])) == pytest.approx(0.9)


def test_steepest_softening_is_the_steepest_secant_after_the_peak():
    u = np.array([0.0, 1.0, 1.5, 3.5, 4.0])
    F = np.array([0.0, 10.0, 6.0, 2.0, 1.0])                   # slopes after the peak: 8, 2, 2 N/mm
    assert M.steepest_softening(u, F) == pytest.approx(0.8)
    assert M.steepest_softening(u, u) == 0.0
    with pytest.raises(ValueError, match="grows in every step"):
        M.steepest_softening([0.0, 1.0, 1.0], [0.0, 2.0, 1.0])


def test_curve_input_is_validated():
    with pytest.raises(ValueError, match="must not decrease"):
        M.peak([0.0, 2.0, 1.0], [0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="finite"):
        M.work([0.0, 1.0], [0.0, np.nan])


# ---- fields ----------------------------------------------------------------------------------------------------
def grid(nx=20, ny=10, lx=20.0, ly=10.0):
    return skfem.MeshQuad.init_tensor(np.linspace(0, lx, nx + 1), np.linspace(0, ly, ny + 1))


def centres(mesh):
    return mesh.p[:, mesh.t].mean(axis=1)


def test_band_width_of_straight_band_is_exact():
    mesh = grid()  # 1 mm squares
    c = centres(mesh)
    band = (np.abs(c[1] - 5.0) < 1.01).astype(float)  # rows with centres 4.5, 5.5: width 2, length 20
    result = M.band_width(mesh, band, 0.5)
    assert result.width == pytest.approx(2.0)
    assert result.length == pytest.approx(20.0)
    assert result.area == pytest.approx(40.0)
    assert result.angle == pytest.approx(0.0, abs=1e-9) or result.angle == pytest.approx(180.0)
    assert M.band_width(mesh, band, 0.5, mirror=2).width == pytest.approx(4.0)
    assert M.band_width(mesh, band, 0.5, length=10.0).width == pytest.approx(4.0)
    assert M.band_width(mesh, np.zeros_like(band), 0.5).width == 0.0


def test_band_angle_of_diagonal_band():
    mesh = grid(40, 40, 40.0, 40.0)
    c = centres(mesh)
    band = (np.abs(c[1] - c[0]) < 1.5).astype(float)
    result = M.band_width(mesh, band, 0.5)
    assert result.angle == pytest.approx(45.0, abs=1e-6)
    vertical = (np.abs(c[0] - 20.0) < 1.0).astype(float)
    assert M.band_width(mesh, vertical, 0.5).angle == pytest.approx(90.0, abs=1e-6)
    assert M.band_width(mesh, vertical, 0.5, within=(0, 40, 0, 10)).length == pytest.approx(10.0)


def test_cut_width_is_exact_on_structured_and_distorted_meshes():
    mesh = grid()
    c = centres(mesh)
    band = (np.abs(c[1] - 5.0) < 1.01).astype(float)
    assert M.cut_width(mesh, band, 0.5, (7.3, 0.0), (0.0, 1.0)) == pytest.approx(2.0, rel=1e-12)
    # a 45-degree cut crosses the 2 mm band over 2 sqrt(2) mm
    assert M.cut_width(mesh, band, 0.5, (0.0, 0.0), (1.0, 1.0)) == pytest.approx(2 * np.sqrt(2), rel=1e-12)
    # shear the mesh (x += 0.3 y): the elements are parallelograms, the band is still 2 mm high
    sheared = skfem.MeshQuad(np.vstack((mesh.p[0] + 0.3 * mesh.p[1], mesh.p[1])), mesh.t)
    assert M.cut_width(sheared, band, 0.5, (10.0, 0.0), (0.0, 1.0), mirror=2) == pytest.approx(4.0, rel=1e-12)
    # a line outside the mesh crosses nothing
    assert M.cut_width(mesh, band, 0.5, (50.0, 0.0), (0.0, 1.0)) == 0.0


def test_transition_ratio_tells_smooth_from_sharp():
    mesh = grid(20, 40, 20.0, 40.0)
    y = centres(mesh)[1]
    sharp = (np.abs(y - 20.0) < 2.0).astype(float)
    smooth = np.exp(-(((y - 20.0) / 4.0) ** 2))
    assert M.transition_ratio(mesh, sharp) == pytest.approx(1.0)
    # smooth: width at 0.1 is 2*4*sqrt(ln 10) ~ 12.1, at 0.9 2*4*sqrt(ln(1/0.9)) ~ 2.6 -> ratio about 4 to 6
    assert M.transition_ratio(mesh, smooth) > 3.0


def test_damaged_components_counts_separate_cracks():
    mesh = grid(20, 20, 20.0, 20.0)
    c = centres(mesh)
    two = ((np.abs(c[1] - 5.0) < 1.0) | (np.abs(c[1] - 15.0) < 1.0)).astype(float)
    assert M.damaged_components(mesh, two) == 2
    linked = two + ((np.abs(c[0] - 10.0) < 1.0) & (c[1] > 5.0) & (c[1] < 15.0))
    assert M.damaged_components(mesh, linked) == 1
    diagonal_touch = ((np.abs(c[0] - 5.5) < 0.6) & (np.abs(c[1] - 5.5) < 0.6)) | (
        (np.abs(c[0] - 6.5) < 0.6) & (np.abs(c[1] - 6.5) < 0.6))
    assert M.damaged_components(mesh, diagonal_touch.astype(float)) == 1  # a staircase touching at corners
    assert M.damaged_components(mesh, np.zeros(mesh.t.shape[1])) == 0
    spot = linked.copy()
    spot[np.argmin(np.hypot(c[0] - 19.5, c[1] - 0.5))] = 1.0  # one isolated element in a corner
    assert M.damaged_components(mesh, spot) == 2
    assert M.damaged_components(mesh, spot, min_fraction=0.05) == 1
    bigger = two + (np.abs(c[1] - 16.0) < 1.0)  # the upper crack is now three rows thick
    count, labels = M.damaged_components(mesh, bigger, labels=True)
    upper = (c[1] > 14.0) & (bigger >= 0.9)
    assert count == 2 and np.all(labels[upper] == 0) and np.all(labels[np.abs(c[1] - 5.0) < 1.0] == 1)
    assert np.all(labels[bigger < 0.9] == -1)


def test_field_input_is_validated():
    mesh = grid()
    with pytest.raises(ValueError, match="one entry per element"):
        M.band_width(mesh, np.zeros(3))
    with pytest.raises(ValueError, match="non-zero 2-vector"):
        M.cut_width(mesh, np.ones(mesh.t.shape[1]), 0.5, (0, 0), (0, 0))


def test_mesh_study_summary():
    u = np.linspace(0.0, 1.0, 11)
    curves = {"coarse": (u, 1.1 * np.sin(np.pi * u)), "fine": (u, np.sin(np.pi * u))}
    mesh = grid()
    band = (np.abs(centres(mesh)[1] - 5.0) < 1.01).astype(float)
    study = M.mesh_study(curves, {"coarse": (mesh, band), "fine": (mesh, band)})
    assert study["reference"] == "fine"
    assert study["runs"]["coarse"]["peak_error"] == pytest.approx(0.1)
    assert study["peak_spread"] == pytest.approx(0.1 / 1.05)
    assert study["runs"]["fine"]["curve_distance"] == 0.0
    assert study["max_curve_distance"] > 0.0
    assert study["band_width_spread"] == 0.0


def test_specimen_metrics_on_a_synthetic_ligament_band():
    from abrakit.damage.specimens import sharp_notch

    sp = sharp_notch(1000)
    mesh = sp.plane_mesh
    c = centres(mesh)
    on_band = (c[0] > 25.0) & (c[1] < 1.0)
    loss = np.where(on_band, 1.0, 0.0)
    u = np.array([0.0, 1.0, 2.0, 3.0])
    F = np.array([0.0, 10.0, 6.0, 0.0])
    m = M.specimen_metrics(sp, u, F, loss)
    area = M.element_areas(mesh)[on_band].sum()
    assert m["band_width_mm"] == pytest.approx(2 * area / 25.0)  # half model: the band is mirrored
    assert m["damaged_pieces"] == 1 and m["band_angle_deg"] % 180 == pytest.approx(0.0, abs=1e-6)
    assert m["transition_ratio"] == pytest.approx(1.0)
    assert m["peak_force_N"] == 10.0 and m["softening_mm"] == pytest.approx(7 / 6)  # F = 5 at u = 2 + 1/6
    assert m["softening_relative"] == pytest.approx(7 / 6) and m["work_Nmm"] == pytest.approx(5.0 + 8.0 + 3.0)


def test_path_work_follows_a_path_that_turns_back():
    """Up to (1, 2), back to (0.5, 0): the trapezoids 1 and -0.5 sum to 0.5 N mm (``work`` refuses such a path);
    on a curve in u both give the same."""
    assert M.path_work([0.0, 1.0, 0.5], [0.0, 2.0, 0.0]) == pytest.approx(0.5)
    assert M.path_work([0.0, 1.0, 2.0], [0.0, 2.0, 2.0]) == M.work([0.0, 1.0, 2.0], [0.0, 2.0, 2.0]) == 3.0
