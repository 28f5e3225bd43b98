"""Path following (abrakit.fem.pathfollow): the snap-back bar against its closed form, energy, arc length against
displacement control, the constraints' linearisation, and bad input."""

import numpy as np
import pytest

from abrakit.fem import Dirichlet, meshes
from abrakit.fem.kinematics import vector_basis
from abrakit.fem.pathfollow import (
    DissipationControl,
    OpeningControl,
    PathControl,
    PathFollowingSolver,
    PathPoint,
)
from abrakit.fem.problems import TABLE_7_1_PLASTICITY, SofteningBar
from abrakit.fem.solver import Solver, StepControl, StepFailed
from abrakit.materials import LinearElastic, VonMisesPlasticity
from abrakit.materials.softening import LinearSofteningDamage


def follow(bar, load="displacement", steps=40, **options):
    solver = bar.solver(load=load, path=PathControl(dissipation=bar.fracture_energy / steps, **options))
    dissipated = []
    result = solver.run(stop_force=1e-3, progress=False,
                        on_step=lambda r: dissipated.append(float(np.sum(solver.material.dissipation(r.state)
                                                                         * solver.kin.dx))))
    return solver, result, np.array([0.0, *dissipated])


@pytest.mark.parametrize("n", [10, 50, 200])
def test_bar_is_followed_through_snap_back_on_its_closed_form(n):
    """Every computed point lies on the analytic path (elastic, softening or broken branch) to 1e-6 of the peak
    force, without a cutback; the long bars' end displacement turns back after the peak (snap-back)."""
    bar = SofteningBar(n)
    _, result, _ = follow(bar)
    v, F = result.curves["u_right"], result.curves["F_right"]
    error = np.abs(F - bar.force(v, bar.branch(v, F))) / bar.f_t
    assert np.max(error) < 1e-6
    assert result.cutbacks == 0
    assert F[-1] <= 1e-3 * bar.f_t
    assert np.max(F) == pytest.approx(bar.f_t, rel=1e-2)                 # the peak, to the step size
    softening = bar.branch(v, F) == "softening"
    assert softening.sum() >= 30                                   # the branch is resolved, not jumped
    peak = int(np.argmax(F))
    turned_back = bar.peak_displacement - v[peak:].min()
    assert bar.snaps_back == (n > 10)
    if bar.snaps_back:
        assert turned_back > 0.5 * (bar.peak_displacement - bar.softening_displacement(0.0))
    else:
        assert np.all(np.diff(v[peak:]) > -1e-12)


@pytest.mark.parametrize("n", [10, 50, 200])
def test_bar_energy_budget_closes_and_dissipates_its_fracture_energy(n):
    """External work along the path = dissipation in the material + recoverable energy ½ F v, at every point
    before the bar breaks (0.5 % of G·A), and the dissipation at the end is G·A = ½ f_t eps_f h (0.5 %)."""
    bar = SofteningBar(n)
    _, result, dissipated = follow(bar, initial=0.01, maximum=0.01)
    v, F = result.curves["u_right"], result.curves["F_right"]
    work = np.concatenate(([0.0], np.cumsum(0.5 * (F[1:] + F[:-1]) * np.diff(v))))
    intact = bar.branch(v, F) != "broken"
    budget = work - 0.5 * F * v - dissipated
    assert np.max(np.abs(budget[intact])) < 5e-3 * bar.fracture_energy
    assert dissipated[-1] == pytest.approx(bar.fracture_energy, rel=5e-3)


def test_displacement_control_fails_where_the_bar_snaps_back():
    """The same bars under displacement control: the short one (no snap-back) runs through, the long one stops at
    the peak (or would jump): what path following is for."""
    control = StepControl(initial=0.02, maximum=0.02)
    short = SofteningBar(10).solver(follow=False, control=control).run(progress=False)
    assert short.curves["F_right"][-1] < 1e-3
    with pytest.raises(StepFailed):
        SofteningBar(50).solver(follow=False, control=control).run(progress=False)


@pytest.mark.parametrize("n", [10, 200])
def test_force_loaded_bar_is_followed_past_its_limit_point(n):
    """Under an applied force the peak is a limit point in the load: the path follower passes it and follows the
    falling branch (snap-back for n = 200) on the closed form."""
    bar = SofteningBar(n)
    _, result, _ = follow(bar, load="force")
    v, F = result.curves["u_right"], result.curves["F_right"]
    assert np.max(np.abs(F - bar.force(v, bar.branch(v, F)))) < 1e-6 * bar.f_t
    assert F[-1] <= 2e-3 * bar.f_t and np.max(F) == pytest.approx(bar.f_t, rel=1e-2)


def plate(material, **options):
    mesh = meshes.plate_with_hole(50.0, 50.0, 10.0, 6, 4, 4.0)
    basis = vector_basis(mesh)
    conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
                  Dirichlet.on(basis, "top", "y", 0.1, name="top")]
    return basis, conditions


def test_arc_length_reproduces_the_displacement_controlled_path():
    """Elastic plate: every arc-length point on the displacement-controlled line to round-off; plastic plate:
    on the displacement-controlled curve (fine steps) to 0.2 %."""
    for material, tol in ((LinearElastic(200000.0, 0.3), 1e-10), (VonMisesPlasticity(**TABLE_7_1_PLASTICITY), 2e-3)):
        basis, conditions = plate(material)
        reference = Solver(basis, material, conditions, bbar=True,
                           control=StepControl(initial=0.01, maximum=0.01)).run(progress=False)
        arc = PathFollowingSolver(basis, material, conditions, bbar=True, method="arc-length",
                                  path=PathControl(initial=0.05, arc_length=0.01)).run(progress=False)
        u, F = arc.curves["u_top"], arc.curves["F_top"]
        assert len(u) > 8 and np.all(np.diff(u) > 0)
        u, F = u[u <= 0.1], F[u <= 0.1]                                # the last step may pass the end
        expected = np.interp(u, reference.curves["u_top"], reference.curves["F_top"])
        assert np.max(np.abs(F - expected)) <= tol * np.max(np.abs(F))
        assert set(arc.curves["constraint"][2:]) == {2.0}              # arc length after the first step


def test_constraint_linearisations_match_finite_differences():
    """a·δu_I + b δλ of the dissipation and opening constraints against a finite difference of g along a
    random direction, at a softening state of the bar (so K is the consistent, indefinite tangent)."""
    bar = SofteningBar(20)
    solver = bar.solver()
    solver.run(stop_force=0.5, progress=False)                     # stop half-way down the softening branch
    rng = np.random.default_rng(0)
    free = solver.constraints.free
    result = solver.run(stop_force=0.5, progress=False)
    u0, lam0 = result.u, float(result.load_factors[-1])
    state = result.state

    def pair(u, lam):
        from abrakit.fem.solver import StepContext
        ctx = StepContext(1, lam, 0.0, lam, 0.0, 1, u, u0, state, result.f_int)
        response, _, f_int, _, extra = solver.evaluate(u, state, ctx)
        return solver.load_pair(u, lam, f_int), response, extra

    (v0, P0), response, extra = pair(u0, lam0)
    K, _ = solver.tangent(response, extra, u0)
    du = np.zeros_like(u0)
    du[free] = rng.normal(size=free.size) * 1e-3 * np.max(np.abs(u0))
    dlam = 1e-3 * lam0
    for constraint in (DissipationControl(0.0), OpeningControl(0.0, solver.opening)):
        base = PathPoint(u0, lam0, v0, P0, u0, lam0, v0, P0, K, solver.u_hat, solver.f_hat, free)
        a, b = constraint.gradient(base)
        h = 1e-4
        u1 = solver._at(u0[free] + h * du[free], lam0 + h * dlam, u0)
        (v1, P1), _, _ = pair(u1, lam0 + h * dlam)
        moved = PathPoint(u0, lam0, v0, P0, u1, lam0 + h * dlam, v1, P1, K, solver.u_hat, solver.f_hat, free)
        finite = (constraint.residual(moved) - constraint.residual(base)) / h
        assert finite == pytest.approx(a @ du[free] + b * dlam, rel=1e-4)


def test_path_following_refuses_bad_input():
    bar = SofteningBar(10)
    with pytest.raises(ValueError, match="method"):
        bar.solver(method="riks")
    with pytest.raises(ValueError, match="load"):
        bar.solver(load="pressure")
    basis, conditions = plate(LinearElastic(1000.0, 0.3))
    with pytest.raises(ValueError, match="opening"):
        PathFollowingSolver(basis, LinearElastic(1000.0, 0.3), conditions, method="opening")
    squared = [*conditions[:2], Dirichlet(conditions[2].dofs, lambda lam: 0.1 * lam**2)]
    with pytest.raises(ValueError, match="linear in the load factor"):
        PathFollowingSolver(basis, LinearElastic(1000.0, 0.3), squared)
    with pytest.raises(ValueError, match="one load"):
        PathFollowingSolver(basis, LinearElastic(1000.0, 0.3), conditions,
                            external_force=lambda lam: lam * np.ones(basis.N))
    with pytest.raises(ValueError, match="stop_force"):
        bar.solver().run(stop_force=1.5, progress=False)
    with pytest.raises(ValueError, match="eps_f"):
        LinearSofteningDamage(1000.0, 0.0, 1e-3, 5e-4)
    with pytest.raises(ValueError, match="switch"):
        PathControl(switch=-1.0)


def test_bar_at_the_snap_back_limit_drops_vertically_through_a_singular_tangent():
    """n = 20 is the borderline bar: the softening branch is vertical (the force falls at constant end
    displacement), K_II is singular along it, and the augmented system [[K_II, −q], [a, b]] carries the steps."""
    bar = SofteningBar(20)
    assert bar.h * (bar.eps_f - bar.eps_0) / bar.f_t == pytest.approx((bar.length - bar.h) / bar.E)
    _, result, dissipated = follow(bar)
    v, F = result.curves["u_right"], result.curves["F_right"]
    falling = bar.branch(v, F) == "softening"
    assert falling.sum() >= 30 and np.allclose(v[falling], bar.peak_displacement, rtol=1e-9)
    assert F[-1] <= 1e-3 * bar.f_t and dissipated[-1] == pytest.approx(bar.fracture_energy, rel=5e-3)


def test_path_following_warns_when_it_runs_out_of_steps():
    bar = SofteningBar(50)
    with pytest.warns(RuntimeWarning, match="max_steps"):
        bar.solver(path=PathControl(max_steps=5)).run(stop_force=1e-3, progress=False)


@pytest.mark.parametrize("method, stop_after", [("dissipation", 23), ("arc-length", 7)])
def test_an_interrupted_path_following_run_resumes_with_the_uninterrupted_curve(tmp_path, interrupt_after, method,
                                                                                stop_after):
    """Killed after a step past the switch to dissipation control (or under arc length) with checkpoints every
    5 steps: the rerun continues with the checkpoint's constraint, targets and counters and ends on the curve of
    a run never stopped; a finished run's rerun returns at once."""
    if method == "dissipation":
        bar = SofteningBar(50)

        def make():
            return bar.solver(load="displacement", path=PathControl(dissipation=bar.fracture_energy / 40))
        options = {"stop_force": 1e-3}
    else:
        material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY)
        basis, conditions = plate(material)

        def make():
            return PathFollowingSolver(basis, material, conditions, bbar=True, method="arc-length",
                                       path=PathControl(initial=0.05, arc_length=0.01))
        options = {}

    def run(output, **kw):
        return make().run(output=output, vtu_every=0, progress=False, checkpoint_every=5, **options, **kw)

    whole = run(tmp_path / "whole")
    with pytest.raises(interrupt_after.error):
        run(tmp_path / "cut", on_step=interrupt_after(stop_after))
    resumed = run(tmp_path / "cut", resume=True)
    assert len(resumed.load_factors) == len(whole.load_factors)
    for name in ("load_factor", "constraint", "P", "v", "iterations"):
        assert np.allclose(resumed.curves[name], whole.curves[name], rtol=1e-9, atol=1e-12), name
    if method == "dissipation":
        assert 1.0 in set(whole.curves["constraint"][:stop_after])        # the kill came after the switch
    again = run(tmp_path / "cut", resume=True)
    assert np.array_equal(again.load_factors, whole.load_factors)


def test_arc_length_at_a_kinked_peak_stops_naming_the_methods_that_pass_it():
    """Issue 38's hard case: on the snap-back bar of 37 elements the weak element's loading flag alternates at the
    peak, the arc-length equation has no real root however short the arc, and the run stops there; the message
    names dissipation and opening control, and dissipation control follows the same bar to fracture."""
    bar = SofteningBar(37)
    with pytest.raises(StepFailed, match="method='dissipation'.*method='opening'"):
        bar.solver(method="arc-length").run(progress=False, stop_force=0.01)
    result = bar.solver(method="dissipation").run(progress=False, stop_force=0.01)
    assert result.curves["F_right"][-1] <= 0.01 * bar.f_t * 1.0001


def test_arc_length_on_a_long_brittle_bar_stops_at_the_peak_naming_the_methods_that_pass_it():
    """Issue 38's second bar: 500 elements with f_t/E = 1e-4. Arc length stops at F = f_t (Newton diverges at a
    round-off residual however short the arc) and names dissipation and opening control; both pass the peak to
    complete separation."""
    bar = SofteningBar(500, eps_0=1e-4, eps_f=2e-3)
    with pytest.raises(StepFailed, match="method='dissipation'.*method='opening'") as stop:
        bar.solver(method="arc-length").run(progress=False, stop_force=0.01)
    assert stop.value.result.curves["F_right"][-1] == pytest.approx(bar.f_t, rel=1e-4)
    for method in ("dissipation", "opening"):
        result = bar.solver(method=method).run(progress=False, stop_force=0.01)
        assert result.curves["F_right"][-1] <= 0.01 * bar.f_t * 1.0001
