"""Mesh generators of abrakit.fem.meshes: geometry, grading, boundary tags, element quality."""

import numpy as np
import pytest
import skfem
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.fem import Kinematics, meshes


def measure(mesh):
    return Kinematics.from_mesh(mesh).volume


def all_boundary_tagged(mesh):
    tagged = np.concatenate(list(mesh.boundaries.values()))
    return np.array_equal(np.unique(tagged), np.sort(mesh.boundary_facets()))


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 40), st.floats(0.1, 20.0))
def test_graded_points(n, ratio):
    x = meshes.graded(n, ratio)
    h = np.diff(x)
    assert x[0] == 0.0 and x[-1] == pytest.approx(1.0) and np.all(h > 0)
    if n > 1:
        assert h[-1] / h[0] == pytest.approx(ratio, rel=1e-9)


def test_graded_towards_has_the_fine_point_as_node():
    x = meshes.graded_towards(0.0, 50.0, 40, 25.0, 6.0)
    h = np.diff(x)
    assert 25.0 in x and x[0] == 0.0 and x[-1] == pytest.approx(50.0)
    assert h.argmin() in (np.searchsorted(x, 25.0) - 1, np.searchsorted(x, 25.0))
    assert h.max() / h.min() == pytest.approx(6.0, rel=1e-9)


@pytest.mark.parametrize("triangles", [False, True])
@pytest.mark.parametrize("width, height, radius", [(50.0, 50.0, 10.0), (40.0, 80.0, 5.0)])
def test_plate_with_hole_geometry(width, height, radius, triangles):
    mesh = meshes.plate_with_hole(width, height, radius, n_angular=32, n_radial=10, triangles=triangles)
    hole_nodes = np.unique(mesh.facets[:, mesh.boundaries["hole"]])
    angles = np.sort(np.arctan2(mesh.p[1, hole_nodes], mesh.p[0, hole_nodes]))
    polygonal_hole = np.sum(0.5 * radius**2 * np.sin(np.diff(angles)))  # the hole is bounded by chords
    assert angles[0] == 0.0 and angles[-1] == pytest.approx(np.pi / 2)
    assert measure(mesh) == pytest.approx(width * height - polygonal_hole, rel=1e-12)
    assert np.allclose(np.hypot(*mesh.p[:, hole_nodes]), radius)
    assert hole_nodes.size == 33 and all_boundary_tagged(mesh)
    assert np.any(np.all(np.isclose(mesh.p.T, [width, height]), axis=1))  # the corner is a node
    quality = meshes.check_quality(mesh)
    assert quality.worst_jacobian_ratio > 0.3


def test_plate_with_hole_is_graded_towards_the_hole():
    mesh = meshes.plate_with_hole(n_angular=8, n_radial=10, grading=5.0)
    on_axis = np.sort(mesh.p[0, np.isclose(mesh.p[1], 0.0)])
    h = np.diff(on_axis)
    assert on_axis[0] == pytest.approx(10.0) and h[-1] / h[0] == pytest.approx(5.0, rel=1e-9)


def test_ring_sector():
    mesh = meshes.ring_sector(10.0, 20.0, n_radial=8, n_angular=48)
    assert measure(mesh) == pytest.approx(np.pi * (20**2 - 10**2) / 4, rel=2e-3)
    assert np.allclose(np.hypot(*mesh.p[:, np.unique(mesh.facets[:, mesh.boundaries["inner"]])]), 10.0)
    assert np.allclose(np.hypot(*mesh.p[:, np.unique(mesh.facets[:, mesh.boundaries["outer"]])]), 20.0)
    assert all_boundary_tagged(mesh)


def test_double_notched_specimen():
    mesh = meshes.double_notched_specimen()
    assert measure(mesh) == pytest.approx(50 * 100 - 2 * 10 * 2, rel=1e-12)
    assert all_boundary_tagged(mesh)
    notch = mesh.p[:, np.unique(mesh.facets[:, mesh.boundaries["notches"]])]
    left = (notch[0] <= 10 + 1e-9) & (np.abs(notch[1] - 60) <= 1 + 1e-9)
    right = (notch[0] >= 40 - 1e-9) & (np.abs(notch[1] - 40) <= 1 + 1e-9)
    assert np.all(left | right) and left.sum() == right.sum() == 2 * 11 + 1  # faces: 10 + 10 + 2 mm, h = 1
    centre = mesh.p[:, mesh.t].mean(axis=1)
    band = (centre[1] > 40) & (centre[1] < 60)
    area = np.abs(np.asarray(mesh._mapping().detDF(np.array([[0.5], [0.5]]))))[:, 0]
    assert area[band].max() <= 1.0 + 1e-9 < area.max()  # finest between the notches
    meshes.check_quality(mesh)


def test_sharp_notch_specimen():
    mesh = meshes.sharp_notch_specimen(n_x=40, n_y=16)
    assert measure(mesh) == pytest.approx(50.0 * 20.0)
    notch = mesh.p[:, np.unique(mesh.facets[:, mesh.boundaries["notch"]])]
    ligament = mesh.p[:, np.unique(mesh.facets[:, mesh.boundaries["ligament"]])]
    assert notch[0].max() == pytest.approx(25.0) == ligament[0].min()  # the tip is the shared node
    assert np.allclose(notch[1], 0.0) and np.allclose(ligament[1], 0.0)
    tip = np.argmin(np.hypot(mesh.p[0] - 25.0, mesh.p[1]))
    sizes = np.abs(np.asarray(mesh._mapping().detDF(np.array([[0.5], [0.5]]))))[:, 0]
    assert sizes[np.any(mesh.t == tip, axis=0)].max() == pytest.approx(sizes.min())  # finest at the tip


def test_graded_block_and_extrusion():
    block = meshes.graded_block(size=(200.0, 100.0, 15.0), divisions=(20, 10, 6), fine_at=(0.0, 100.0, None),
                                grading=(4.0, 3.0, 1.0))
    assert measure(block) == pytest.approx(200 * 100 * 15)
    assert all_boundary_tagged(block)
    x = np.unique(block.p[0])
    assert np.diff(x)[-1] / np.diff(x)[0] == pytest.approx(4.0)
    plate = meshes.plate_with_hole(n_angular=8, n_radial=4)
    solid = meshes.extrude(plate, thickness=3.0, layers=2)
    assert isinstance(solid, skfem.MeshHex1) and solid.t.shape[1] == 2 * plate.t.shape[1]
    assert measure(solid) == pytest.approx(3.0 * measure(plate))
    assert len(solid.boundaries["hole"]) == 2 * len(plate.boundaries["hole"])
    assert len(solid.boundaries["front"]) == plate.t.shape[1] and all_boundary_tagged(solid)
    assert meshes.check_quality(solid).worst_jacobian_ratio > 0.3


def test_quality_check_rejects_inverted_and_warns_on_slender_elements():
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3))
    p = mesh.p.copy()
    centre = np.argmin(np.hypot(p[0] - 0.5, p[1] - 0.5))
    p[:, centre] = [1.4, 1.4]  # the middle node pulled outside: elements fold over
    with pytest.raises(ValueError, match="inverted"):
        meshes.check_quality(skfem.MeshQuad(p, mesh.t))
    slender = skfem.MeshQuad.init_tensor(np.linspace(0, 100, 3), np.linspace(0, 1, 3))
    with pytest.warns(UserWarning, match="aspect ratio"):
        q = meshes.check_quality(slender)
    assert q.worst_aspect_ratio == pytest.approx(100.0)
    assert "aspect ratio max 100.00" in q.summary()


def test_invalid_dimensions_raise():
    with pytest.raises(ValueError, match="radius"):
        meshes.plate_with_hole(width=10.0, radius=12.0)
    with pytest.raises(ValueError, match="notch"):
        meshes.sharp_notch_specimen(notch=60.0)
    with pytest.raises(ValueError, match="outer"):
        meshes.ring_sector(10.0, 5.0)
    with pytest.raises(ValueError, match="ratio"):
        meshes.graded(4, -1.0)


def test_quadratic_plate_with_hole_has_a_curved_hole_and_the_exact_area():
    """order=2: every node of the hole's edges (vertices and mid-sides) lies on the circle, the vertices are those of
    the bilinear mesh, and the biquadratic geometry's area is exact to O(h⁴) where the straight-sided mesh misses the
    circle segments."""
    linear = meshes.plate_with_hole(n_angular=8, n_radial=4)
    curved = meshes.plate_with_hole(n_angular=8, n_radial=4, order=2)
    assert isinstance(curved, skfem.MeshQuad2)
    np.testing.assert_array_equal(curved.doflocs[:, : linear.p.shape[1]], linear.p)
    hole_vertices = np.unique(curved.facets[:, curved.boundaries["hole"]])
    basis = skfem.FacetBasis(curved, skfem.ElementQuad2(), facets=curved.boundaries["hole"])
    r = np.hypot(*basis.doflocs[:, basis.get_dofs(facets="hole").flatten()])
    np.testing.assert_allclose(r, 10.0, rtol=1e-13)
    assert hole_vertices.size == 9 and r.size == 2 * 8 + 1                       # 9 vertices and 8 mid-sides
    exact = 50.0 * 50.0 - np.pi * 10.0**2 / 4

    def area(mesh, element):
        return skfem.Functional(lambda w: 1.0).assemble(skfem.CellBasis(mesh, element, intorder=6))

    assert abs(area(curved, skfem.ElementQuad2()) / exact - 1) < 1e-6
    assert abs(area(linear, skfem.ElementQuad1()) / exact - 1) > 1e-4
    with pytest.raises(ValueError, match="order"):
        meshes.plate_with_hole(order=3)
