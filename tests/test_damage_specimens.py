"""The Ch. 7 boundary value problems (abrakit.damage.specimens): meshes, conditions, refinement, elastic response."""

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

from abrakit.damage import runs as R
from abrakit.damage import specimens as S
from abrakit.damage.metrics import element_areas
from abrakit.fem import Solver, meshes
from abrakit.materials import LinearElastic

NAMES = tuple(S.SPECIMENS)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("level", ["coarse", "medium", "fine"])
def test_element_counts_match_the_seed_levels(name, level):
    sp = S.specimen(name, level)
    assert abs(sp.elements - S.LEVELS[level]) <= 0.05 * S.LEVELS[level]
    q = meshes.check_quality(sp.mesh, max_aspect_ratio=25.0)
    assert q.worst_jacobian_ratio > 0.8  # no distorted elements


@pytest.mark.parametrize("name", NAMES)
def test_conditions_and_loaded_edge(name):
    sp = S.specimen(name, 300, displacement=0.05)
    assert sp.level == f"{300} elements" and 250 <= sp.elements <= 350
    top = sp.loaded_dofs
    loaded = next(c for c in sp.dirichlet if c.name == "top")
    np.testing.assert_allclose(loaded(1.0), 0.05)
    np.testing.assert_allclose(loaded(0.4), 0.02)
    y = sp.basis.doflocs[1, top]
    assert np.all(top % 2 == 1) and np.allclose(y, y.max())  # the y DOFs of the top edge
    assert sp.force_scale == 3.0 and sp.thickness == 3.0


def test_symmetry_lines_hold_the_right_nodes():
    sp = S.sharp_notch(300)
    held_y = np.concatenate([c.dofs for c in sp.dirichlet if c.name == ""])
    xy = sp.basis.doflocs[:, held_y]
    ligament = held_y[(held_y % 2 == 1)]
    x = sp.basis.doflocs[0, ligament]
    assert np.all(sp.basis.doflocs[1, ligament] == 0.0) and x.min() >= 25.0 - 1e-9  # notch faces are free
    x_held = held_y[held_y % 2 == 0]
    assert x_held.size == 1 and np.allclose(sp.basis.doflocs[:, x_held].ravel(), [50.0, 0.0])
    assert np.all(np.isfinite(xy))
    plate = S.plate_with_hole_specimen(300)
    dofs = {c.dofs.size for c in plate.dirichlet}
    assert len(plate.dirichlet) == 3 and min(dofs) > 5


def test_meshes_are_refined_where_the_band_goes():
    area = {}
    # plate: elements touching the ligament y = 0 are smaller than those touching the top edge
    sp = S.plate_with_hole_specimen("coarse")
    a, c = element_areas(sp.plane_mesh), sp.plane_mesh.p[:, sp.plane_mesh.t].mean(axis=1)
    area["plate"] = a[c[1] < 1.0].mean() / a[c[1] > 40.0].mean()
    # sharp notch: elements on the ligament vs near the grip
    sp = S.sharp_notch("coarse")
    a, c = element_areas(sp.plane_mesh), sp.plane_mesh.p[:, sp.plane_mesh.t].mean(axis=1)
    area["sharp"] = a[(c[1] < 1.0) & (c[0] > 25)].mean() / a[c[1] > 15.0].mean()
    # double notch: elements between the notches vs near the clamped ends
    sp = S.double_notched("coarse")
    a, c = element_areas(sp.plane_mesh), sp.plane_mesh.p[:, sp.plane_mesh.t].mean(axis=1)
    area["double"] = a[np.abs(c[1] - 50.0) < 10.0].mean() / a[c[1] < 10.0].mean()
    assert all(ratio < 0.3 for ratio in area.values()), area


def test_double_notch_geometry():
    sp = S.double_notched("coarse")
    mesh = sp.plane_mesh
    assert mesh.p[0].min() == 0.0 and mesh.p[0].max() == 50.0 and mesh.p[1].max() == 100.0
    total = element_areas(mesh).sum()
    assert total == pytest.approx(50.0 * 100.0 - 2 * 10.0 * 2.0)  # two notches of 10 x 2 mm removed
    c = mesh.p[:, mesh.t].mean(axis=1)
    in_upper_notch = (c[0] < 10.0) & (np.abs(c[1] - 60.0) < 1.0)
    in_lower_notch = (c[0] > 40.0) & (np.abs(c[1] - 40.0) < 1.0)
    assert not np.any(in_upper_notch | in_lower_notch)


def test_plate_and_sharp_notch_areas():
    plate = S.plate_with_hole_specimen("coarse")
    # straight chords along the hole cut off a little: area within 0.1 % of 50^2 - pi 10^2 / 4
    assert element_areas(plate.plane_mesh).sum() == pytest.approx(2500 - np.pi * 25, rel=1e-3)
    assert element_areas(S.sharp_notch("coarse").plane_mesh).sum() == pytest.approx(50.0 * 20.0)


def elastic_stiffness(sp):
    material = LinearElastic(200000.0, 0.33)
    result = Solver(sp.basis, material, sp.dirichlet).run(progress=False)
    return sp.force_scale * result.curves["F_top"][-1] / sp.displacement


@pytest.mark.parametrize("name", NAMES)
def test_elastic_stiffness_converges_with_the_mesh(name):
    k_coarse = elastic_stiffness(S.specimen(name, 500))
    k_fine = elastic_stiffness(S.specimen(name, 2000))
    assert k_fine > 0
    assert abs(k_coarse - k_fine) / k_fine < 0.02  # displacement FE: the stiffness falls towards the limit
    assert k_coarse >= k_fine * (1 - 1e-6)


def test_plate_plane_strain_stiffer_than_the_extruded_plate():
    """The seed's 3D plate (one hex layer, free faces) behaves as plane stress: about 1/(1 - nu^2) softer."""
    k_strain = elastic_stiffness(S.plate_with_hole_specimen(300))
    k_3d = elastic_stiffness(S.plate_with_hole_specimen(300, formulation="extruded"))
    ratio = k_strain / k_3d
    assert 1.03 < ratio < 1.0 / (1 - 0.33**2) + 0.01


def test_bad_levels_and_options():
    with pytest.raises(ValueError, match="level"):
        S.plate_with_hole_specimen("huge")
    with pytest.raises(TypeError, match="level"):
        S.plate_with_hole_specimen(1000.0)
    with pytest.raises(ValueError, match="level"):
        S.double_notched(10)
    with pytest.raises(ValueError, match="formulation"):
        S.sharp_notch(300, formulation="plane_stress")
    with pytest.raises(ValueError, match="displacement"):
        S.sharp_notch(300, displacement=-1.0)
    with pytest.raises(ValueError, match="name"):
        S.specimen("dogbone")


def test_plot_field_mirrors_the_model():
    import matplotlib.pyplot as plt

    sp = S.plate_with_hole_specimen(300)
    fig, ax = plt.subplots()
    S.plot_field(sp, np.linspace(0, 1, sp.elements), ax, colorbar=False)
    assert len(ax.collections) == 4  # quarter model shown whole
    x0, x1 = ax.get_xlim()
    assert x0 <= -50 and x1 >= 50
    with pytest.raises(ValueError, match="one entry per element"):
        S.plot_field(sp, np.zeros(3), ax)
    plt.close(fig)


def test_run_specimen_gives_the_same_record_for_both_models():
    sp = S.double_notched(250)
    runs = {m: R.run_specimen(sp, m, R.REGULARISATION[m]["strong"], step=0.004) for m in ("I", "II")}
    for model, run in runs.items():
        assert run.model == model and run.status in ("fractured", "end")
        assert run.stiffness_loss.shape == run.alpha_p.shape == (sp.elements,)
        assert np.all((run.stiffness_loss >= 0.0) & (run.stiffness_loss <= 1.0))
        assert run.stiffness_loss.max() > 0.99  # a band has formed
        assert run.F.max() > 5e3 and run.F[-1] < 0.1 * run.F.max()  # stopped after the force fell below 10 %
        assert run.steps == len(run.u) - 1 and run.iterations >= run.steps and run.seconds > 0
    with pytest.raises(ValueError, match="model"):
        R.run_specimen(sp, "III", 1.0)
