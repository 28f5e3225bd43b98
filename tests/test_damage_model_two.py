"""Model II in the finite element loop (abrakit.damage.model_two_fe): Algorithm 2 with the rate limit (6.96-6.98).

The regression reference ``tests/data/double_notch_model2_reference.csv`` was produced by :func:`reference_run`;
regenerate it (only after a deliberate change of the model) with

    python -c "import tests.test_damage_model_two as t; t.write_reference()"
"""

from pathlib import Path

import numpy as np
import pytest

from abrakit.damage import metrics as M
from abrakit.damage.model_two_fe import (
    default_material,
    f_bar_of,
    rate_limit_work,
    run_model_two,
)
from abrakit.damage.specimens import double_notched, sharp_notch
from abrakit.fem import NewtonOptions, StepControl
from abrakit.fem.output import load_checkpoint
from abrakit.io import CurveWriter, read_curve
from abrakit.materials import TABLE_7_2

REFERENCE = Path(__file__).parent / "data" / "double_notch_model2_reference.csv"
REFERENCE_COLUMNS = ("u", "F", "external_work", "dissipated_energy", "max_d")


def reference_run(alpha=0.005):
    """Double-notched strip, ~300 elements, Table 7.2 with alpha = 0.005, 75 steps to u = 0.3 mm, stop at 10 %."""
    return run_model_two(double_notched(300), alpha, steps=75, stop_fraction=0.1)


def write_reference():  # pragma: no cover - run by hand
    res = reference_run()
    with CurveWriter(REFERENCE, REFERENCE_COLUMNS) as writer:
        for i in range(len(res.curves["u"])):
            writer.write(**{k: float(res.curves[k][i]) for k in REFERENCE_COLUMNS})


@pytest.fixture(scope="module")
def reference():
    return reference_run()


def test_rate_limit_work_is_applied_displacement_times_old_reaction():
    u_old = np.array([0.0, 0.1, 0.0, 0.2])
    u = np.array([0.5, 0.15, 7.0, 0.3])
    f_old = np.array([3.0, 10.0, 99.0, -4.0])
    prescribed = np.array([1, 3])
    # 3 mm * (0.05 * 10 + 0.1 * -4) = 0.3
    assert rate_limit_work(u, u_old, f_old, prescribed, 3.0) == pytest.approx(0.3)


def test_reference_curve_is_reproduced(reference):
    """Regression: peak, curve and energies of the stored run. A 10 % change of alpha breaks these bounds."""
    ref = read_curve(REFERENCE)
    c = reference.curves
    assert reference.status == "fractured"
    F_max = ref["F"].max()
    assert M.curve_distance(c["u"], c["F"], ref["u"], ref["F"]) < 2e-3
    assert abs(c["F"].max() - F_max) < 2e-3 * F_max
    assert c["u"][-1] == pytest.approx(ref["u"][-1], abs=0.0121)  # within three steps of the stop
    W = M.work(ref["u"], ref["F"])
    assert M.work(c["u"], c["F"], upto=min(c["u"][-1], ref["u"][-1])) == pytest.approx(
        M.work(ref["u"], ref["F"], upto=min(c["u"][-1], ref["u"][-1])), rel=5e-3)
    assert W == pytest.approx(ref["external_work"][-1], rel=1e-3)


def test_reference_bound_detects_a_real_change():
    changed = reference_run(alpha=0.0055)
    ref = read_curve(REFERENCE)
    assert M.curve_distance(changed.curves["u"], changed.curves["F"], ref["u"], ref["F"]) > 2e-3 * 3


def test_passed_work_is_exactly_the_documented_one(reference):
    """rate_limit_work of step m+1 = (u^{m+1} - u^m) F^m (uniform top edge); increment = alpha * that."""
    c = reference.curves
    expected = np.diff(c["u"]) * c["F"][:-1]
    np.testing.assert_allclose(c["rate_limit_work"][1:], expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(c["damage_increment"], 0.005 * np.maximum(c["rate_limit_work"], 0.0))
    assert c["rate_limit_work"][1] == 0.0  # no reaction before the first step: no damage can start there


def test_damage_capped_and_irreversible_at_every_step():
    seen = []

    def check(partial):
        d = partial.state["d"]
        seen.append(d)
        assert d.max() <= TABLE_7_2.get("d_max", 0.999) + 1e-15
        assert np.all(d <= 0.999)
        f_bar = f_bar_of(partial.state)
        assert np.all((f_bar > 0) & (f_bar <= 1.0 + 1e-12))

    res = run_model_two(double_notched(300), 0.05, steps=60, stop_fraction=0.1, on_step=check)
    assert len(seen) == res.steps
    for old, new in zip(seen[:-1], seen[1:], strict=True):
        assert np.all(new >= old)
    assert res.curves["max_d"].max() == pytest.approx(0.999)  # damage reached the cap ...
    assert np.all(res.curves["max_d"] <= 0.999)  # ... and never passed it
    assert res.f_bar.min() > 0.0


def test_energy_balance_and_its_first_order_error():
    """W_ext = stored + plastic + damage dissipation, up to the splitting error, which halves with the step."""
    errors = []
    for steps in (75, 150):
        res = run_model_two(double_notched(300), 0.005, steps=steps, end=0.5)  # to u = 0.15 mm, past the peak
        c = res.curves
        W = c["external_work"][-1]
        assert W == pytest.approx(M.work(c["u"], c["F"]), rel=1e-9)
        assert c["damage_dissipation"][-1] > 0.2 * W and c["plastic_dissipation"][-1] > 0.2 * W
        # r_d/n sum dd_i is only a lower bound of the released energy (the rate limit, not r_d, stops growth)
        assert c["threshold_dissipation"][-1] < c["damage_dissipation"][-1]
        errors.append(abs(c["energy_error"][-1]) / W)
    assert errors[1] < 0.02
    assert errors[1] < 0.7 * errors[0]


def test_strong_regularisation_is_mesh_independent_on_two_small_meshes():
    """alpha = 0.005: peak spread < 1 %, curve distance < 6 %, energy spread < 4 % (about 300 vs 700 elements)."""
    curves = {}
    for n in (300, 700):
        res = run_model_two(double_notched(n), 0.005, steps=75, stop_fraction=0.1)
        curves[n] = (res.curves["u"], res.curves["F"])
    study = M.mesh_study(curves)
    assert study["peak_spread"] < 0.01
    assert study["max_curve_distance"] < 0.06
    assert study["work_spread"] < 0.04


def test_weak_regularisation_drops_steeper_than_strong(reference):
    weak = run_model_two(double_notched(300), 0.05, steps=75, stop_fraction=0.1)
    u_s, F_s = reference.curves["u"], reference.curves["F"]
    u_w, F_w = weak.curves["u"], weak.curves["F"]
    assert M.peak(u_w, F_w)[0] < 0.8 * M.peak(u_s, F_s)[0]  # damage sets in at lower force
    assert M.softening_displacement(u_w, F_w) < M.softening_displacement(u_s, F_s)
    assert weak.dissipated_energy < reference.dissipated_energy


def test_sudden_drop_is_cut_back_or_stopped_with_the_last_state_saved(tmp_path):
    # 20 big steps: the band snapping through after the peak needs cutbacks, and the run still ends
    res = run_model_two(sharp_notch(300, displacement=0.1), 0.05, steps=20)
    assert res.cutbacks > 0 and res.status == "end"
    assert res.steps > 20 and np.all(np.diff(res.curves["u"]) > 0)
    # a small Newton budget and a floor on the cutbacks: the run stops at the peak with a message
    control = StepControl(initial=0.05, maximum=0.05, minimum=0.05 / 16)
    with pytest.warns(RuntimeWarning, match="stopped at load factor"):
        failed = run_model_two(sharp_notch(300, displacement=0.1), 0.05, control=control,
                               newton=NewtonOptions(max_iterations=6), output=tmp_path / "run")
    assert failed.status == "failed" and not failed.completed
    assert failed.steps >= 3 and failed.curves["F"][-1] > 0.5 * res.peak()[0]
    assert "last converged state" in failed.message
    saved = load_checkpoint(failed.checkpoint)
    assert saved["load_factor"] == pytest.approx(failed.curves["load_factor"][-1])
    np.testing.assert_allclose(saved["state"]["d"], failed.state["d"])
    assert np.all(saved["state"]["d"] <= 0.999)
    rows = read_curve(tmp_path / "run" / "force_displacement.csv")
    np.testing.assert_allclose(rows["F"], failed.curves["F"])
    assert (tmp_path / "run" / "fields" / "damage.pvd").exists()


def test_outputs_written_as_the_run_goes(tmp_path):
    import meshio

    res = run_model_two(double_notched(300), 0.005, steps=30, end=0.4, output=tmp_path, vtu_every=10)
    rows = read_curve(tmp_path / "force_displacement.csv")
    assert len(rows["u"]) == res.steps + 1
    vtus = sorted((tmp_path / "fields").glob("damage_*.vtu"))
    expected = res.steps // 10 + (1 if res.steps % 10 else 0)  # every 10th step, and the last one once
    assert len(vtus) == expected
    mesh = meshio.read(vtus[-1])
    f_bar = mesh.cell_data["f_bar"][0]
    np.testing.assert_allclose(f_bar, res.f_bar)
    for name in ("stiffness_loss", "d_mean", "d_max", "alpha_p", "von_mises"):
        assert name in mesh.cell_data
    assert (tmp_path / "summary.json").exists()


def test_hard_inputs_are_refused():
    sp = double_notched(300)
    with pytest.raises(ValueError, match="alpha"):
        run_model_two(sp, -1.0)
    with pytest.raises(ValueError, match="stop_fraction"):
        run_model_two(sp, 0.05, stop_fraction=1.5)
    with pytest.raises(ValueError, match="steps"):
        run_model_two(sp, 0.05, steps=0)


def test_default_material_is_table_7_2():
    m = default_material(0.005)
    assert (m.E, m.nu, m.r_d, m.n, m.r_p, m.K_H, m.alpha, m.d_max) == (200000.0, 0.33, 0.1, 20, 60.0, 8000.0,
                                                                        0.005, 0.999)
    assert m.integration == "implicit" and m.damage_energy == "full"
    state = m.initial_state((2, 3))
    assert np.all(f_bar_of(state) == 1.0)


def test_arc_length_follows_model_two_to_fracture_like_displacement_control(reference):
    """Model II under Crisfield's arc length (the rate limit on |work|): the same peak as the displacement-
    controlled reference to 1 %, fracture without a cutback, and the energy budget closes at least as well."""
    from abrakit.fem import PathControl

    res = run_model_two(double_notched(300), 0.005, stop_fraction=0.1, method="arc-length",
                        path=PathControl(initial=0.01, maximum=0.01, target_iterations=8, max_steps=400))
    assert res.status == "fractured" and res.cutbacks == 0
    assert res.peak()[0] == pytest.approx(reference.peak()[0], rel=1e-2)
    assert res.dissipated_energy == pytest.approx(reference.dissipated_energy, rel=0.1)
    assert abs(res.curves["energy_error"][-1]) <= abs(reference.curves["energy_error"][-1])


def test_dissipation_control_unloads_an_elastoplastic_specimen_instead_of_damaging_it():
    """The hard case the path follower documents: with plastic (not secant) unloading, the released energy
    G = ½ (P0 Δv − v0 ΔP) is positive on elastic unloading, so dissipation control may follow unloading: the load
    falls, the displacement goes back, and almost nothing is dissipated by damage."""
    from abrakit.fem import PathControl

    res = run_model_two(double_notched(300), 0.005, stop_fraction=0.05, method="dissipation",
                        path=PathControl(initial=0.01, maximum=0.01, target_iterations=8, max_steps=200))
    u = res.curves["u"]
    assert u[-1] < u.max() and res.curves["damage_dissipation"][-1] < 0.01 * res.curves["external_work"].max()


@pytest.mark.slow
def test_sharp_notch_corner_damage_comes_from_the_grip():
    """(slow: a study of benchmarks/bench_sharp_notch_edge.py, which stores it.) The top-right corner of the sharp
    notch is damaged under the non-rotating grip (uniform top displacement) and stays intact when the same edge
    is pulled by a traction."""
    import importlib.util
    import sys

    bench_dir = Path(__file__).resolve().parent.parent / "benchmarks"
    sys.path.insert(0, str(bench_dir))
    spec = importlib.util.spec_from_file_location("bench_sharp_notch_edge", bench_dir / "bench_sharp_notch_edge.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    sp = sharp_notch("coarse")
    centres = sp.mesh.p[:, sp.mesh.t].mean(axis=1)
    corner = bench.ZONES["corner"](*centres)
    area = M.element_areas(sp.mesh)
    held = bench.grip(sp)
    pulled = bench.traction(sp, 1.5 * held["peak_N"] / sp.force_scale / 50.0)
    assert area[corner & (held["loss"] > 0.5)].sum() > 15.0                  # mm² of a 25 mm² zone
    assert pulled["status"] == "fractured" and pulled["loss"][corner].max() < 0.01


def test_a_killed_run_resumes_from_its_checkpoint_with_the_uninterrupted_curve(tmp_path):
    """Checkpoints every 4 steps; killed after step 10, the rerun goes back to step 8 and ends with the steps,
    curve, energy account, fields and state of a run never stopped, to round-off (the resumed solver analyses its
    first matrix afresh: 4e-15 relative); each step is on disk once, and a finished run's rerun returns at once. A
    checkpoint of another run is refused by name."""
    def run(directory, **options):
        return run_model_two(double_notched(300), 0.005, steps=40, end=0.5, output=tmp_path / directory,
                             vtu_every=3, checkpoint_every=4, linear_solver="superlu", **options)

    def kill(result):
        if result.steps == 10:
            raise KeyboardInterrupt

    full = run("full")
    with pytest.raises(KeyboardInterrupt):
        run("cut", on_step=kill)
    assert load_checkpoint(tmp_path / "cut" / "last_converged.npz")["meta"]["account"]["rows"][-1]["step"] == 8
    resumed = run("cut", resume=True)
    assert resumed.steps == full.steps and resumed.cutbacks == full.cutbacks and resumed.status == full.status
    for name, values in full.curves.items():
        if name != "seconds":
            np.testing.assert_allclose(resumed.curves[name], values, rtol=1e-12, atol=1e-12, err_msg=name)
    np.testing.assert_allclose(resumed.u, full.u, rtol=0, atol=1e-14)
    np.testing.assert_allclose(resumed.f_bar, full.f_bar, rtol=0, atol=1e-12)
    on_disk = read_curve(tmp_path / "cut" / "force_displacement.csv")
    np.testing.assert_array_equal(on_disk["step"], np.arange(full.steps + 1))
    np.testing.assert_allclose(on_disk["F"], full.curves["F"], rtol=1e-12)
    assert sorted(p.name for p in (tmp_path / "cut" / "fields").glob("*.vtu")) == \
        sorted(p.name for p in (tmp_path / "full" / "fields").glob("*.vtu"))
    again = run("cut", resume=True)
    np.testing.assert_array_equal(again.curves["F"], resumed.curves["F"])
    assert again.status == full.status and again.wall_time < 0.5 * full.wall_time
    with pytest.raises(ValueError, match="another Model II run"):
        run_model_two(double_notched(300), 0.05, steps=40, end=0.5, output=tmp_path / "cut", resume=True)


def test_model_two_does_not_snap_back_its_largest_drop_halves_with_the_step():
    """Eq. (6.96)-(6.98): a sub-domain's damage grows in a step by at most alpha times the step's external work
    s sum du_D f*_D, so under displacement control the force is Lipschitz in u: halving the step halves the largest
    force drop of a step (8.3 % -> 4.0 % on the weak double notch) and leaves the steepest secant slope of a step
    (83 -> 80 peaks per mm). A snap-back or a vertical drop keeps the drop and steepens the slope, as the bar shows
    without an effective rate limit (alpha = 100: 99.9 % per step, slope doubling) and with local Model I (50 %)."""
    from abrakit.damage.localisation import bar_models, run_bar
    from abrakit.damage.runs import run_specimen
    from abrakit.damage.specimens import specimen

    def refined(runs):
        runs = list(runs)
        drop, slope = ([f(r.u, r.F) for r in runs] for f in (M.largest_drop, M.steepest_softening))
        return drop[1] / drop[0], slope[1] / slope[0], min(drop)

    def bar(material):
        return refined(run_bar(material, 41, length=200.0, end_displacement=0.2, step=step) for step in (1e-3, 5e-4))

    sp = specimen("double_notched", 250)
    for drop, slope, _ in (refined(run_specimen(sp, "II", 0.05, step=step, stop_fraction=0.1) for step in (1e-3, 5e-4)),
                           bar(bar_models(alpha=0.01)["model_two"])):
        assert 0.4 < drop < 0.6 and 0.85 < slope < 1.15
    for material in (bar_models(alpha=100.0)["model_two"], bar_models()["local"]):
        drop, slope, smallest = bar(material)
        assert smallest > 0.3 and drop > 0.8 and slope > 1.4


def test_arc_length_creeps_at_the_plate_peak_because_the_rate_limit_follows_the_load_factor():
    """Diagnostic of the stall: under arc length the rate limit's work, and with it the damage of the step, moves
    with the load factor during the Newton iterations, which the tangent does not carry. With the live rate limit
    the plate creeps at its peak; frozen at the step's predictor it passes the peak within a few steps (and then
    stops where the arc-length equation has no real root, so freezing is a diagnostic, not a method)."""
    from abrakit.damage.specimens import specimen
    from abrakit.fem import PathControl

    sp = specimen("plate_with_hole", 250)
    h = 0.002 / sp.displacement
    ends = {}
    for rate_limit in ("iterate", "predictor"):
        with pytest.warns(RuntimeWarning):
            run = run_model_two(sp, 0.05, stop_fraction=0.1, method="arc-length", rate_limit=rate_limit,
                                path=PathControl(initial=2 * h, maximum=2 * h, target_iterations=8, max_steps=60))
        ends[rate_limit] = run.curves["F"][-1] / run.curves["F"].max()
    assert ends["iterate"] > 0.99 and ends["predictor"] < 0.95
    with pytest.raises(ValueError, match="rate_limit"):
        run_model_two(sp, 0.05, rate_limit="frozen")
