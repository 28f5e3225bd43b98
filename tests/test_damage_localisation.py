"""Localisation demo (Ch. 6.2): a local softening bar depends on the mesh, the regularised models do not."""

import numpy as np
import pytest

from abrakit.damage.localisation import (
    BarRun,
    bar_mesh,
    bar_models,
    cross_section,
    curve_distance,
    localisation_study,
    run_bar,
)
from abrakit.materials import LinearElastic


@pytest.fixture(scope="module")
def study():
    """Three meshes (21, 41, 81 elements), load step 0.4 % of the path: ~7 s."""
    return localisation_study((21, 41, 81), step=0.004)


def test_local_model_dissipates_less_on_finer_meshes(study):
    """Local softening: the strain localises in one element, the dissipated energy falls with h (seed Ch. 6.2)."""
    energies = study.energies("local")
    assert np.all(np.diff(energies) < 0)
    assert study.energy_ratio("local") < 0.5
    assert all(r.damaged_width == pytest.approx(r.h) for r in study.runs["local"])  # one element broken


def test_model_one_is_mesh_independent(study):
    """Model I (beta = 1 MPa mm^2): dissipated energy within 2 %, peak within 0.5 %, drop at the same displacement
    (one load step), band ~ 6-7 mm wide on every mesh."""
    assert study.energy_spread("model_one") < 0.02
    assert study.peak_spread("model_one") < 0.005
    drops = [r.drop_displacement for r in study.runs["model_one"]]
    assert np.ptp(drops) <= 0.004 * 0.04 + 1e-12
    widths = [r.damaged_width for r in study.runs["model_one"]]
    assert min(widths) > 5.0 and np.ptp(widths) < 1.0


def test_model_two_spreads_over_the_weak_zone(study):
    """Model II (alpha = 0.01 1/(N mm)): the rate limit lets the whole weak zone damage; energy within 20 %."""
    assert study.energy_spread("model_two") < 0.2
    assert all(r.damaged_width > 2.0 for r in study.runs["model_two"])


def test_table_and_curve_distance(study):
    rows = study.table()
    assert len(rows) == 9 and {"model", "elements", "peak_N", "dissipated_Nmm", "u_drop_mm"} <= set(rows[0])
    for name in study.runs:
        assert 0.0 <= study.curve_distance(name) < 0.3
    run = study.runs["local"][0]
    assert curve_distance(run, run) == 0.0


def test_elastic_branch_is_the_series_stiffness():
    """Before damage the bar is springs in series: F = E u / sum(h / A_e) (independent check of the set-up)."""
    run = run_bar(LinearElastic(2.0e5, 0.0), 21, end_displacement=0.005, step=0.5)
    mesh = bar_mesh(21)
    stiffness = 2.0e5 / np.sum((20.0 / 21) / cross_section(mesh))
    assert np.allclose(run.F[1:], stiffness * run.u[1:], rtol=1e-10)


def test_local_peak_is_the_onset_in_the_weakest_element():
    """Peak force of the local model -> sqrt(2 r_d E) A_min (damage onset, Psi0 = r_d): the explicit split
    overshoots by O(load step); the dissipated energy does not depend on the step."""
    exact = np.sqrt(2 * 0.05 * 2.0e5) * cross_section(bar_mesh(21)).min()
    runs = [run_bar(bar_models()["local"], 21, step=s) for s in (0.004, 0.002)]
    errors = [r.peak / exact - 1.0 for r in runs]
    assert 0.0 < errors[1] < 0.02 and 1.6 < errors[0] / errors[1] < 2.2
    assert runs[0].dissipated == pytest.approx(runs[1].dissipated, rel=1e-3)
    assert runs[1].completed and runs[1].F[-1] < 0.05 * runs[1].peak and isinstance(runs[1], BarRun)


def test_cross_section_shape():
    mesh = bar_mesh(41)
    a = cross_section(mesh, area=1.0, depth=0.05, width=1.0, notch=0.02)
    x = mesh.p[0, mesh.t].mean(axis=0)
    assert np.argmin(a) == np.argmin(np.abs(x - 10.0))
    h = 20.0 / 41
    # integral of the reduction: depth sqrt(2 pi) width (Gaussian, exact element means) + notch h
    assert np.sum((1 - a) * h) == pytest.approx(0.05 * np.sqrt(2 * np.pi) + 0.02 * h, rel=1e-6)


def test_invalid_input():
    for n in (4, 1, 2.5):
        with pytest.raises(ValueError, match="n_elements"):
            bar_mesh(n)
    with pytest.raises(TypeError, match="n_elements must be an integer, got True"):
        bar_mesh(True)
    with pytest.raises(ValueError, match="length"):
        bar_mesh(5, -1.0)
    with pytest.raises(ValueError, match="depth"):
        cross_section(bar_mesh(5), depth=1.0)
    with pytest.raises(ValueError, match="end_displacement"):
        run_bar(LinearElastic(1.0, 0.0), 5, end_displacement=0.0)
    with pytest.raises(ValueError, match="n_elements"):
        localisation_study((21,))


@pytest.mark.slow
def test_refinement_to_161_elements():
    """Full study of the book: 21 ... 161 elements, step 0.2 %."""
    s = localisation_study((21, 41, 81, 161), step=0.002)
    assert s.energy_ratio("local") < 0.25
    assert s.energy_spread("model_one") < 0.02
