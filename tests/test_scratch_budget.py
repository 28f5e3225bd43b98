"""The volume audit of a scratch: exact closure, an analytic field, and the physics it must show.

- any displacement field: shoulders + prow + faces − groove − sink = ∫(J − 1) dV_0 to round-off;
- a uniform settlement of the top by δ: groove + sink = δ A_top = −∫(J − 1) dV_0, nothing else moves;
- a finite-strain plastic scratch: the volume change is purely elastic, ∫(J − 1) = ∫(exp(tr τ / 3K) − 1),
  so plastic flow loses no volume; a small-strain one loses some (its J is not conserved), which the audit shows.
"""

import numpy as np
import pytest

from abrakit.fem import Kinematics
from abrakit.scratch.budget import BoundaryFaces, steady_rates, volume_budget
from abrakit.scratch.readouts import groove_along
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import (
    SEED_FORMULATION,
    ST52,
    ScratchScene,
    SpecimenMesh,
    build_specimen,
)

TINY_BLOCK = (0.06, 0.015, 0.08)
TINY_MESH = SpecimenMesh(h=0.003, h_z=0.004, h_y=0.001, growth=1.6, width=1.6)
SCENE = ScratchScene(depth=0.0008, slide=0.02, mesh=TINY_MESH, size=TINY_BLOCK, indent_steps=4, unload_steps=2,
                     **SEED_FORMULATION)


@pytest.fixture(scope="module")
def specimen():
    spec = build_specimen(SCENE)
    return spec, Kinematics.from_basis(spec.basis), BoundaryFaces(spec.mesh)


def test_the_budget_closes_to_round_off_for_any_displacement(specimen):
    spec, kin, faces = specimen
    u = 1e-3 * np.random.default_rng(1).standard_normal(spec.basis.N)        # every face moves
    b = volume_budget(faces, kin, spec.mesh.p, u, z_tip=0.04)
    assert abs(b.faces) > 0 and min(b.groove, b.shoulders, b.prow, b.sink) > 0
    assert abs(b.residual) <= 1e-12 * max(b.groove, b.shoulders, abs(b.volume_change))


def test_removed_elements_close_the_budget_and_move_volume_from_the_shoulders_to_the_debris(specimen):
    """Elements counted as removed (eroded, or Model II at its cap): the budget still closes to round-off,
    ``removed`` is their undeformed volume ∫ dV_0 (the material that left), their current volume ∫ J dV_0
    (computed here from det F independently) leaves the shoulders and the prow where it sits above y = 0 and
    deepens groove and sink where it sits below, and the volume change is the remaining body's; no element, no
    change."""
    spec, kin, faces = specimen
    rng = np.random.default_rng(2)
    u = 1e-3 * rng.standard_normal(spec.basis.N)
    mask = rng.random(kin.nel) < 0.2
    plain = volume_budget(faces, kin, spec.mesh.p, u, z_tip=0.04)
    b = volume_budget(faces, kin, spec.mesh.p, u, z_tip=0.04, removed=mask)
    assert abs(b.residual) <= 1e-12 * max(b.groove, b.shoulders, abs(b.volume_change))
    J = np.linalg.det(np.eye(3) + kin.displacement_gradient(u))
    assert b.removed == pytest.approx(2 * np.sum(kin.dx[mask]), rel=1e-12)
    moved = (plain.shoulders - b.shoulders) + (plain.prow - b.prow) + (b.groove - plain.groove) \
        + (b.sink - plain.sink)
    assert moved == pytest.approx(2 * np.sum(J[mask] * kin.dx[mask]), rel=1e-12)
    assert b.volume_change == pytest.approx(2 * np.sum((J[~mask] - 1) * kin.dx[~mask]), rel=1e-10)
    assert b.shoulders < plain.shoulders and b.groove > plain.groove
    none = volume_budget(faces, kin, spec.mesh.p, u, z_tip=0.04, removed=np.zeros(kin.nel, bool))
    assert none == plain and none.removed == 0.0
    with pytest.raises(ValueError, match="one flag per element"):
        volume_budget(faces, kin, spec.mesh.p, u, z_tip=0.04, removed=np.ones(3, bool))


def test_a_uniform_settlement_of_the_top_is_all_groove_and_volume_change(specimen):
    spec, kin, faces = specimen
    thickness, strain = TINY_BLOCK[1], -0.01
    y = kin.basis.doflocs[1]
    u = np.zeros(spec.basis.N)
    u[spec.basis.nodal_dofs[1]] = strain * (spec.mesh.p[1] + thickness)        # u_y = eps (y + t), bottom fixed
    assert np.isclose(y.min(), -thickness)
    b = volume_budget(faces, kin, spec.mesh.p, u, z_tip=0.04)
    area = 2 * 0.5 * TINY_BLOCK[0] * TINY_BLOCK[2]                               # whole grain: twice the half top
    assert b.groove + b.sink == pytest.approx(-strain * thickness * area, rel=1e-12)
    assert b.volume_change == pytest.approx(strain * thickness * area, rel=1e-12)
    assert b.shoulders == b.prow == 0.0 and b.faces == pytest.approx(0.0, abs=1e-18)
    assert b.sink / (b.groove + b.sink) == pytest.approx((TINY_BLOCK[2] - 0.04) / TINY_BLOCK[2], rel=1e-12)


@pytest.fixture(scope="module")
def scratches():
    """The small-strain scene with the seed's friction, and a frictionless finite-strain F-bar one."""
    return {"small": run_scratch(SCENE, vtu_every=0),
            "finite": run_scratch(SCENE.with_(kinematics="finite", bbar=True, mu=0.0), vtu_every=0)}


def test_every_increment_of_a_scratch_closes_its_budget(scratches):
    for r in scratches.values():
        c = r.curves
        scale = np.maximum(c["V_groove"], 1e-12)
        assert np.all(np.abs(c["V_residual"]) <= 1e-10 * scale)
        assert np.all(c["V_removed"] == 0.0)                     # no damage, nothing removed
        assert r.summary()["volume_budget_um3"]["groove"] == pytest.approx(c["V_groove"][-1] * 1e9)


def test_finite_strain_plastic_flow_changes_volume_only_elastically(scratches):
    """Frictionless plastic scratch at finite strain: groove + sink − shoulders − prow − faces = −∫(J − 1) dV_0,
    and that bound is the elastic volume change ∫(exp(tr τ / 3K) − 1) dV_0 exactly (plastic flow is isochoric)."""
    r = scratches["finite"]
    K = ST52["E"] / (3 * (1 - 2 * ST52["nu"]))
    st = r.state
    kin = Kinematics.from_basis(r.specimen.basis)
    kirchhoff_mean = st["J"] * st["cauchy"][..., :3].sum(axis=-1) / 3
    elastic = 2 * np.sum((np.exp(kirchhoff_mean / K) - 1) * kin.dx)
    assert np.any(st["alpha_p"] > 0.05)                                         # well into the plastic range
    assert r.budget.volume_change == pytest.approx(elastic, rel=1e-9)
    b = r.budget
    assert abs(b.groove + b.sink - b.shoulders - b.prow - b.faces + elastic) <= 1e-8 * b.groove


def test_small_strain_kinematics_lose_volume_beyond_the_elastic_change(scratches):
    """Small strain conserves tr(eps) in plastic flow, not J: its int(J - 1) dV exceeds its own elastic part
    int tr(eps_e) dV = int tr(sigma)/3K dV by the second-order terms of det(I + grad u); finite strain has no
    such excess (test above), so its volume change is the smaller one."""
    r = scratches["small"]
    kin = Kinematics.from_basis(r.specimen.basis)
    eps_e = r.state["eps"] - r.state["eps_p"]                            # Mandel; eps_p is deviatoric
    elastic = 2 * np.sum(eps_e[..., :3].sum(axis=-1) * kin.dx)
    kinematic_loss = r.budget.volume_change - elastic
    assert kinematic_loss < -0.05 * r.budget.groove
    assert abs(r.budget.volume_change) > abs(scratches["finite"].budget.volume_change)


@pytest.mark.slow
def test_plastic_only_finite_strain_scratch_is_plowing_at_steady_state():
    """The plowing limit (about 30 min on one core): sphere R = 50 µm, d = 2 µm, μ = 0.1, 200 µm along a 300 µm
    block, finite strain with F-bar, no damage. The budget closes to round-off; the sections of the steady half of
    the wake have f_ab < 0.2 (plowing), and what is missing from the shoulders is bounded by the elastic volume
    change and the prow: groove − shoulders − sink ≤ prow + |∫(J−1) dV| + faces."""
    scene = ScratchScene(mesh="demo", kinematics="finite", bbar=True, slide=0.2, size=(0.1, 0.015, 0.3))
    r = run_scratch(scene, vtu_every=0)
    b = r.budget
    assert abs(b.residual) < 1e-8 * b.groove
    assert b.groove - b.shoulders - b.sink <= b.prow + abs(b.volume_change) + abs(b.faces) + 1e-8 * b.groove
    z = scene.path.z_start + np.linspace(0.5 * scene.slide, scene.slide - 2 * scene.footprint, 5)
    along = groove_along(r.specimen, r.u, scene, z)
    assert np.all(along.degree_of_wear < 0.2)


def _budget_curves(slide, groove, shoulders):
    """forces.csv-like curves: two indentation increments, then sliding ones with the given volumes."""
    n = len(slide)
    zeros = np.zeros(n + 2)
    curves = {"phase": np.r_[0, 0, np.ones(n)], "slide": np.r_[0.0, 0.0, slide],
              "V_groove": np.r_[0.0, 0.0, groove], "V_shoulders": np.r_[0.0, 0.0, shoulders]}
    curves.update({f"V_{k}": zeros for k in ("prow", "sink", "faces", "volume_change", "removed")})
    return curves


def test_steady_rates_are_the_slopes_over_the_window_and_give_eq_8_5_in_rates():
    """Volumes linear in the slide within a window: the rates are their slopes exactly, f_ab = 1 − shoulders/groove
    (Eq. 8.5 in rates); a window before a kink does not see the slope after it."""
    s = np.linspace(0.0, 0.2, 41)
    groove = 3e-5 * s + 1e-7
    shoulders = np.where(s <= 0.1, 2e-5 * s, 2e-6 + 2.7e-5 * (s - 0.1))     # the shoulders grow faster after 0.1
    curves = _budget_curves(s, groove, shoulders)
    late = steady_rates(curves)                                             # default: the second half
    assert late.from_slide == pytest.approx(0.1)
    assert late.groove == pytest.approx(3e-5) and late.shoulders == pytest.approx(2.7e-5)
    assert late.degree_of_wear == pytest.approx(0.1)
    early = steady_rates(curves, 0.0, 0.1)
    assert early.shoulders == pytest.approx(2e-5) and early.degree_of_wear == pytest.approx(1.0 / 3.0)
    with pytest.raises(ValueError, match="to_slide"):
        steady_rates(curves, 0.05, 0.055)                                   # one increment in the window
