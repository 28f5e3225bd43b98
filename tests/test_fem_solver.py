"""Newton solver and load stepping of abrakit.fem: convergence, cutback, hard cases, hooks, output."""

from dataclasses import dataclass

import meshio
import numpy as np
import pytest
import scipy.sparse as sp
import skfem

from abrakit.fem import (
    Dirichlet,
    NewtonOptions,
    Solver,
    StepControl,
    StepFailed,
    boundary_dofs,
    meshes,
    vector_basis,
)
from abrakit.fem.boundary import node_row_dofs
from abrakit.fem.output import load_checkpoint
from abrakit.fem.problems import plate_with_hole_problem, thick_cylinder_problem, thick_cylinder_solution
from abrakit.io import read_curve
from abrakit.materials import LinearElastic, MaterialResponse, VonMisesPlasticity

E, NU, R_P = 70000.0, 0.3, 200.0


def strip(nx=8, ny=4, length=4.0, height=2.0):
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, length, nx + 1), np.linspace(0, height, ny + 1))
    return mesh.with_boundaries({"left": lambda x: x[0] < 1e-9, "right": lambda x: x[0] > length - 1e-9,
                                 "bottom": lambda x: x[1] < 1e-9, "top": lambda x: x[1] > height - 1e-9})


def tension_bcs(basis, u=0.01):
    return [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
            Dirichlet.on(basis, "right", "x", u, name="right")]


# ---- stand-in materials for the hard cases ----------------------------------------------------------------------
@dataclass(frozen=True)
class FragileElastic:
    """Linear elastic, but the update 'fails' (NaN stress) when a strain increment exceeds ``max_increment``,
    like a return map that does not converge for too large a step."""

    elastic: LinearElastic
    max_increment: float

    def initial_state(self, shape):
        return self.elastic.initial_state(shape)

    def update(self, state, eps, dt=1.0, **loading):
        response = self.elastic.update(state, eps, dt)
        if np.abs(eps - state["eps"]).max() > self.max_increment:
            return MaterialResponse(np.full_like(response.stress, np.nan), response.tangent, response.state)
        return response


@dataclass(frozen=True)
class DamagedElastic:
    """Elastic with a fixed stiffness factor per element, ``factor`` (nel,); 0 means fully damaged."""

    elastic: LinearElastic
    factor: np.ndarray

    def initial_state(self, shape):
        return self.elastic.initial_state(shape)

    def update(self, state, eps, dt=1.0, scale=1.0, **loading):
        r = self.elastic.update(state, eps, dt)
        f = scale * self.factor[:, None]
        return MaterialResponse(f[..., None] * r.stress, f[..., None, None] * r.tangent, r.state)


@dataclass(frozen=True)
class ElasticTangent:
    """Wraps a material and returns the elastic stiffness as tangent (an inconsistent linearisation)."""

    material: VonMisesPlasticity

    def initial_state(self, shape):
        return self.material.initial_state(shape)

    def update(self, state, eps, dt=1.0, **loading):
        r = self.material.update(state, eps, dt)
        return MaterialResponse(r.stress, np.broadcast_to(self.material.stiffness, r.tangent.shape), r.state)


# ---- Newton ----------------------------------------------------------------------------------------------------
def convergence_orders(residuals, floor):
    """Estimated orders log(r_k+1/r_k) / log(r_k/r_k-1) over the iterates above round-off."""
    r = np.asarray([x for x in residuals if x > floor])
    return np.log(r[2:] / r[1:-1]) / np.log(r[1:-1] / r[:-2])


def test_newton_converges_quadratically_with_the_consistent_tangent():
    """Plastic steps of the thick cylinder: the consistent tangent of the implicit return map gives order 2;
    the elastic stiffness as tangent converges linearly (the test can tell them apart)."""
    material = VonMisesPlasticity(E, NU, R_P, 5000.0, integration="implicit")
    solution = thick_cylinder_solution(10.0, 20.0, E, NU, np.sqrt(1.5) * R_P)
    options = dict(pressure=solution.limit_pressure, n_radial=8, n_angular=8,
                   control=StepControl(initial=0.3, maximum=0.3, extrapolate=False))
    tight = NewtonOptions(residual_tol=1e-12, exact_tol=1e-13)
    result = thick_cylinder_problem(material, newton=tight, **options).run(end=1.2, progress=False)
    floor = 1e-9 * result.residual_histories[1][0]
    orders = [convergence_orders(h, floor) for h in result.residual_histories[3:]]  # the plastic steps
    assert all(o.size and o[-1] > 1.7 for o in orders), orders

    loose = NewtonOptions(max_iterations=200)
    fast = thick_cylinder_problem(material, newton=loose, **options).run(end=1.2, progress=False)
    slow = thick_cylinder_problem(ElasticTangent(material), newton=loose, **options).run(end=1.2, progress=False)
    assert slow.iterations[3:].min() > 2 * fast.iterations[3:].max()
    assert np.allclose(slow.u, fast.u, rtol=0, atol=1e-4 * np.abs(fast.u).max())  # same solution


def test_linear_problem_converges_in_one_iteration_and_extrapolation_is_exact():
    basis = vector_basis(strip())
    result = Solver(basis, LinearElastic(E, NU), tension_bcs(basis)).run(progress=False)
    assert result.iterations[1] == 1 and result.iterations[2:].max() == 0  # later steps: linear extrapolation
    assert result.curves["F_right"] == pytest.approx(E / (1 - NU**2) * 0.01 / 4.0 * 2.0 * result.load_factors,
                                                     rel=1e-10, abs=1e-9)  # plane strain, free sides: E' eps A


@dataclass
class RecordingElastic:
    """Linear elastic; remembers the largest strain increment any update was asked to evaluate."""

    elastic: LinearElastic
    largest: float = 0.0

    def initial_state(self, shape):
        return self.elastic.initial_state(shape)

    def update(self, state, eps, dt=1.0, **loading):
        self.largest = max(self.largest, float(np.abs(eps - state["eps"]).max()))
        return self.elastic.update(state, eps, dt)


def test_the_prescribed_increment_is_lifted_through_the_linear_system():
    """One elastic step of a strip pulled by 0.01 mm over 4 mm: with lifting the first iterate is the exact,
    uniform strain 0.0025; putting the increment into the start point instead strains the last element column
    alone by 0.01 / 0.5 = 0.02, eight times more (what makes boundary points falsely plastic)."""
    basis = vector_basis(strip())
    largest = {}
    for lift in (True, False):
        material = RecordingElastic(LinearElastic(E, NU))
        control = StepControl(initial=1.0, maximum=1.0, lift=lift)
        result = Solver(basis, material, tension_bcs(basis), control=control).run(progress=False)
        assert result.iterations[1] == 1
        largest[lift] = material.largest
    assert largest[True] == pytest.approx(0.01 / 4.0, rel=1e-10)
    assert largest[False] == pytest.approx(0.01 / 0.5, rel=1e-10)


def test_a_lifted_elastic_first_step_of_the_plate_needs_one_iteration():
    from abrakit.fem.problems import TABLE_7_1_PLASTICITY, plate_with_hole_problem

    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY, integration="implicit")
    iterations = {}
    for lift in (True, False):
        solver = plate_with_hole_problem(material, n_angular=32, n_radial=24, displacement=0.05,
                                         control=StepControl(lift=lift))
        result = solver.run(progress=False)
        assert result.cutbacks == 0
        iterations[lift] = result.iterations[1]
    assert iterations[True] == 1 and iterations[False] >= 2     # unlifted: 2 (full integration), 4 (B-bar)


def test_a_chord_step_confirms_convergence_without_a_new_factorisation():
    """NewtonOptions(chord_check=True): where the residual has converged but the last correction was not yet
    small, one chord step with the kept factors replaces a tangent assembly and factorisation. The plate's
    plastic steps then need fewer factorisations, and the path agrees with full Newton's within the tolerances."""
    from abrakit.fem.problems import TABLE_7_1_PLASTICITY

    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY, integration="implicit")
    runs = {}
    for chord in (False, True):
        solver = plate_with_hole_problem(material, displacement=0.1, linear_solver="superlu",
                                         newton=NewtonOptions(chord_check=chord))
        runs[chord] = (solver.run(progress=False), solver.linear_solver)
    (full, full_ls), (chorded, chord_ls) = runs[False], runs[True]
    assert full_ls.factorisations == full_ls.solves == int(full.iterations.sum())
    assert chord_ls.solves - chord_ls.factorisations >= 5                      # chord steps taken
    assert chord_ls.factorisations < full_ls.factorisations
    np.testing.assert_allclose(chorded.curves["F_top"], full.curves["F_top"], rtol=1e-5)
    assert np.abs(chorded.u - full.u).max() <= 1e-4 * np.abs(full.u).max()


def test_chord_check_must_be_a_bool():
    with pytest.raises(TypeError, match="chord_check"):
        NewtonOptions(chord_check="yes")


# ---- load stepping: cutback, growth, failure ---------------------------------------------------------------------
def test_failed_step_is_cut_back_and_recovers():
    basis = vector_basis(strip())
    # the lifted first iterate is the elastic solution, a uniform strain of 0.01 * dlambda / 4: steps above 0.28 of
    # the load fail
    material = FragileElastic(LinearElastic(E, NU), max_increment=0.0007)
    solver = Solver(basis, material, tension_bcs(basis),
                    control=StepControl(initial=1.0, maximum=1.0, extrapolate=False))
    result = solver.run(progress=False)
    assert result.cutbacks >= 1 and result.load_factors[-1] == pytest.approx(1.0)
    assert np.diff(result.load_factors)[0] == pytest.approx(0.25)   # 1 -> 0.25 (Abaqus cut-back factor)
    assert np.diff(result.load_factors).max() <= 0.3                # every accepted step was a feasible one
    reference = Solver(basis, LinearElastic(E, NU), tension_bcs(basis)).run(progress=False)
    assert np.allclose(result.u, reference.u, atol=1e-14)
    assert np.all(np.isfinite(result.curves["F_right"]))


def test_step_growth_after_easy_steps():
    basis = vector_basis(strip())
    control = StepControl(initial=0.01, maximum=0.5, extrapolate=False)
    result = Solver(basis, LinearElastic(E, NU), tension_bcs(basis), control=control).run(progress=False)
    steps = np.diff(result.load_factors)
    assert steps[0] == pytest.approx(0.01) and steps.max() > 0.1
    assert np.all(steps[1:-1] / steps[:-2] <= 1.5 + 1e-9)


def test_minimum_step_raises_with_last_good_state_saved(tmp_path):
    """Beyond the limit load of a perfectly plastic cylinder no step converges: a clear error, state saved."""
    material = VonMisesPlasticity(E, NU, R_P, 0.0, integration="implicit")
    solution = thick_cylinder_solution(10.0, 20.0, E, NU, np.sqrt(1.5) * R_P)
    solver = thick_cylinder_problem(material, pressure=solution.limit_pressure, n_radial=6, n_angular=6,
                                    control=StepControl(initial=0.1, maximum=0.1, minimum=1e-3))
    with pytest.raises(StepFailed, match=r"failed: .*minimum.*Last converged state: λ=") as info:
        solver.run(end=1.5, output=tmp_path, progress=False, vtu_every=0)
    failure = info.value
    assert 1.0 <= failure.load_factor <= 1.01  # the collapse load (upper bound on a coarse mesh)
    saved = load_checkpoint(failure.checkpoint)
    assert failure.checkpoint == tmp_path / "last_converged.npz"
    assert saved["load_factor"] == failure.load_factor and np.array_equal(saved["u"], failure.u)
    assert np.array_equal(saved["state"]["alpha_p"], failure.state["alpha_p"])
    assert np.all(np.isfinite(failure.u))
    curve = read_curve(tmp_path / "curves.csv")
    assert curve["load_factor"][-1] == pytest.approx(failure.load_factor)  # rows were written as the run went


def test_restart_from_a_saved_state_continues_the_path():
    material = VonMisesPlasticity(200000.0, 0.33, 60.0, 8000.0, integration="implicit")
    control = StepControl(initial=0.1, maximum=0.1, extrapolate=False)
    solver = plate_with_hole_problem(material, n_angular=6, n_radial=4, control=control)
    full = solver.run(progress=False)
    half = solver.run(end=0.5, progress=False)
    rest = solver.run(start=0.5, u0=half.u, state0=half.state, progress=False)
    assert rest.load_factors[0] == 0.5 and rest.curves["F_top"][0] == pytest.approx(half.curves["F_top"][-1])
    assert np.allclose(rest.u, full.u, rtol=0, atol=1e-12)
    assert np.allclose(rest.state["alpha_p"], full.state["alpha_p"], rtol=0, atol=1e-14)


def test_fully_damaged_region_gives_no_nans():
    """A band of zero-stiffness elements cuts the strip: finite displacements, zero reaction, no NaN."""
    mesh = strip(nx=10, ny=4, length=5.0)
    centre = mesh.p[:, mesh.t].mean(axis=1)[0]
    factor = np.where((centre > 2.0) & (centre < 3.0), 0.0, 1.0)  # two element columns, interior nodes inside
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "left", "xy"), Dirichlet.on(basis, "right", "y"),
           Dirichlet.on(basis, "right", "x", 0.01, name="right")]
    result = Solver(basis, DamagedElastic(LinearElastic(E, NU), factor), bcs).run(progress=False)
    assert np.all(np.isfinite(result.u)) and np.all(np.isfinite(result.response.stress))
    assert np.abs(result.curves["F_right"]).max() <= 1e-9
    assert np.abs(result.u).max() <= 0.01 + 1e-12


def test_everything_damaged_stays_finite():
    basis = vector_basis(strip(nx=4, ny=2))
    material = DamagedElastic(LinearElastic(E, NU), np.zeros(8))
    result = Solver(basis, material, tension_bcs(basis)).run(progress=False)
    assert np.all(np.isfinite(result.u)) and result.curves["F_right"][-1] == 0.0


# ---- hooks ----------------------------------------------------------------------------------------------------
def test_loading_kwargs_reach_the_material():
    basis = vector_basis(strip())
    material = DamagedElastic(LinearElastic(E, NU), np.ones(32))
    seen = []

    def loading(ctx):
        seen.append((ctx.step, ctx.iteration, ctx.dt))
        return {"scale": 2.0}

    result = Solver(basis, material, tension_bcs(basis), loading=loading, duration=10.0).run(progress=False)
    reference = Solver(basis, LinearElastic(E, NU), tension_bcs(basis)).run(progress=False)
    assert result.curves["F_right"][-1] == pytest.approx(2.0 * reference.curves["F_right"][-1], rel=1e-12)
    assert seen[-1][0] == len(result.load_factors) - 1 and seen[-1][2] == pytest.approx(1.0)  # dt = 0.1 * 10 s


def test_extra_terms_add_residual_and_tangent():
    """A penalty spring k (u - lambda*g) on the right edge (like penalty contact) approaches the Dirichlet
    solution as k grows; an extra residual -lambda*f equals the same external force."""
    basis = vector_basis(strip())
    right = boundary_dofs(basis, "right", "x")
    target = 0.01
    k = 1e12

    def spring(u, ctx):
        r = np.zeros_like(u)
        r[right] = k * (u[right] - ctx.load_factor * target)
        K = sp.csr_matrix((np.full(right.size, k), (right, right)), shape=(u.size, u.size))
        return r, K

    fixed = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y")]
    penalty = Solver(basis, LinearElastic(E, NU), fixed, extra_terms=[spring], monitors={"right": right})
    result = penalty.run(progress=False)
    reference = Solver(basis, LinearElastic(E, NU), tension_bcs(basis)).run(progress=False)
    assert result.curves["F_right"][-1] == pytest.approx(reference.curves["F_right"][-1], rel=1e-5)

    f = np.zeros(basis.N)
    f[right] = 1.0
    as_term = Solver(basis, LinearElastic(E, NU), fixed, extra_terms=[lambda u, ctx: (-ctx.load_factor * f, None)])
    as_load = Solver(basis, LinearElastic(E, NU), fixed, external_force=lambda lam: lam * f)
    assert np.allclose(as_term.run(progress=False).u, as_load.run(progress=False).u, rtol=1e-12)


# ---- output -----------------------------------------------------------------------------------------------------
def test_results_are_written_as_the_run_goes(tmp_path):
    material = VonMisesPlasticity(200000.0, 0.33, 60.0, 8000.0, integration="implicit")
    solver = plate_with_hole_problem(material, n_angular=6, n_radial=4, displacement=0.05)
    rows = []
    result = solver.run(output=tmp_path, vtu_every=2, progress=False,
                        on_step=lambda r: rows.append(len(read_curve(tmp_path / "curves.csv")["step"])))
    assert rows == list(range(2, len(result.load_factors) + 1))  # each step flushed before the callback
    curve = read_curve(tmp_path / "curves.csv")
    assert np.allclose(curve["F_top"], result.curves["F_top"]) and curve["u_top"][-1] == pytest.approx(0.05)
    pvd = (tmp_path / "fields" / "step.pvd").read_text()
    files = sorted((tmp_path / "fields").glob("*.vtu"))
    assert len(files) == (len(result.load_factors) + 1) // 2 and pvd.count("<DataSet") == len(files)
    last = meshio.read(files[-1])
    assert {"stress_yy", "von_mises", "alpha_p"} <= set(last.cell_data)
    assert last.point_data["displacement"].shape == (solver.kin.basis.mesh.p.shape[1], 3)


def test_an_interrupted_run_resumes_from_its_checkpoint_with_the_uninterrupted_curve(tmp_path, interrupt_after):
    """Killed after step 8 with checkpoints every 3 steps: the rerun goes back to step 6, recomputes 7 and 8
    (replacing their rows and VTU files), and ends with the curve, fields and state of a run never stopped."""
    material = VonMisesPlasticity(200000.0, 0.33, 60.0, 8000.0, integration="implicit")
    control = StepControl(initial=0.05, maximum=0.1)

    def run(output, **kw):
        solver = plate_with_hole_problem(material, n_angular=6, n_radial=4, control=control)
        return solver.run(output=output, vtu_every=2, progress=False, checkpoint_every=3, **kw)

    whole = run(tmp_path / "whole")
    with pytest.raises(interrupt_after.error):
        run(tmp_path / "cut", on_step=interrupt_after(8))
    assert len(read_curve(tmp_path / "cut" / "curves.csv")["step"]) == 9          # steps 0..8 were on disk
    assert load_checkpoint(tmp_path / "cut" / "last_converged.npz")["meta"]["control"]["step"] == 6
    resumed = run(tmp_path / "cut", resume=True)

    assert np.array_equal(resumed.load_factors, whole.load_factors)
    for name in ("F_top", "u_top", "iterations"):
        assert np.allclose(resumed.curves[name], whole.curves[name], rtol=1e-12, atol=0), name
    assert np.allclose(resumed.u, whole.u, rtol=0, atol=1e-12)
    assert np.allclose(resumed.state["alpha_p"], whole.state["alpha_p"], rtol=0, atol=1e-14)
    assert len(resumed.residual_histories) == len(whole.residual_histories)
    on_disk = read_curve(tmp_path / "cut" / "curves.csv")
    assert np.array_equal(on_disk["step"], np.arange(len(whole.load_factors)))        # each step exactly once
    assert np.allclose(on_disk["F_top"], whole.curves["F_top"], rtol=1e-12, atol=0)
    names = sorted(p.name for p in (tmp_path / "cut" / "fields").glob("*.vtu"))
    assert names == sorted(p.name for p in (tmp_path / "whole" / "fields").glob("*.vtu"))
    assert (tmp_path / "cut" / "fields" / "step.pvd").read_text().count("<DataSet") == len(names)
    again = run(tmp_path / "cut", resume=True)              # a finished run's rerun returns its result at once
    assert np.array_equal(again.load_factors, whole.load_factors) and again.iterations[-1] == whole.iterations[-1]


def test_a_run_continued_from_a_partial_results_continuation_takes_the_same_steps():
    """``SolveResult.continuation`` of step 5 (kept by a caller's own checkpoint, as the scratch scene does) makes
    ``run(continuation=...)`` take steps 6… with the step sizes, growth counter and state of the run never stopped."""
    material = VonMisesPlasticity(200000.0, 0.33, 60.0, 8000.0, integration="implicit")
    control = StepControl(initial=0.05, maximum=0.1)
    kept = {}

    def keep(result):
        kept.setdefault(len(result.load_factors) - 1, result.continuation)

    whole = plate_with_hole_problem(material, n_angular=6, n_radial=4, control=control).run(progress=False,
                                                                                              on_step=keep)
    assert kept[5]["control"]["delta"] != control.initial                  # the step has grown by step 5
    rest = plate_with_hole_problem(material, n_angular=6, n_radial=4, control=control).run(
        progress=False, continuation=kept[5])
    np.testing.assert_array_equal(rest.load_factors, whole.load_factors[5:])
    np.testing.assert_allclose(rest.curves["F_top"], whole.curves["F_top"][5:], rtol=1e-12)
    np.testing.assert_allclose(rest.u, whole.u, rtol=0, atol=1e-12)


def test_resume_refuses_the_checkpoint_of_another_problem(tmp_path):
    material = VonMisesPlasticity(200000.0, 0.33, 60.0, 8000.0, integration="implicit")
    plate_with_hole_problem(material, n_angular=6, n_radial=4).run(output=tmp_path, vtu_every=0, progress=False,
                                                                   end=0.2)
    finer = plate_with_hole_problem(material, n_angular=8, n_radial=4)
    with pytest.raises(ValueError, match="another problem.*delete it"):
        finer.run(output=tmp_path, vtu_every=0, progress=False, resume=True)
    with pytest.raises(ValueError, match="checkpoint_every"):
        finer.run(checkpoint_every=-1, progress=False)


def test_3d_amg_solver_matches_direct():
    mesh = meshes.graded_block(size=(4.0, 2.0, 2.0), divisions=(6, 3, 3), fine_at=(0.0, None, None),
                               grading=(2.0, 1.0, 1.0))
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "xmin", "xyz"), Dirichlet.on(basis, "xmax", "z", -0.05, name="tip")]
    material = VonMisesPlasticity(E, NU, R_P, 5000.0, integration="implicit")
    options = dict(control=StepControl(initial=0.5, maximum=0.5))
    direct = Solver(basis, material, bcs, linear_solver="direct", **options).run(progress=False)
    amg = Solver(basis, material, bcs, linear_solver="amg", **options).run(progress=False)
    assert amg.u == pytest.approx(direct.u, abs=1e-8 * np.abs(direct.u).max())
    assert np.abs(amg.iterations - direct.iterations).max() <= 1  # inexact linear solves: at most one more


@dataclass(frozen=True)
class SkewElastic:
    """Linear material with a non-symmetric tangent C + W (W skew): AMG must switch from CG to GMRES."""

    elastic: LinearElastic

    @property
    def tangent(self):
        W = np.zeros((6, 6))
        W[0, 1], W[1, 0] = 0.2 * self.elastic.E, -0.2 * self.elastic.E
        return self.elastic.stiffness + W

    def initial_state(self, shape):
        return self.elastic.initial_state(shape)

    def update(self, state, eps, dt=1.0, **loading):
        C = self.tangent
        return MaterialResponse(eps @ C.T, np.broadcast_to(C, eps.shape + (6,)).copy(), {"eps": eps})


def test_amg_handles_a_non_symmetric_tangent():
    mesh = meshes.graded_block(size=(4.0, 2.0, 2.0), divisions=(6, 3, 3))
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "xmin", "xyz"), Dirichlet.on(basis, "xmax", "xz", 0.01, name="tip")]
    material = SkewElastic(LinearElastic(E, NU))
    control = StepControl(initial=1.0, maximum=1.0)
    direct = Solver(basis, material, bcs, linear_solver="direct", control=control).run(progress=False)
    amg_solver = Solver(basis, material, bcs, linear_solver="amg", control=control)
    amg = amg_solver.run(progress=False)
    assert amg_solver.linear_solver._method.__name__ == "gmres"
    assert amg.u == pytest.approx(direct.u, abs=1e-8 * np.abs(direct.u).max())


# ---- invalid input -----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, match", [
    (dict(cutback=1.5), "cutback"), (dict(minimum=0.0), "minimum"), (dict(initial=2.0, maximum=1.0), "initial"),
    (dict(growth=0.5), "growth"),
])
def test_invalid_step_control_raises(kwargs, match):
    with pytest.raises(ValueError, match=match):
        StepControl(**kwargs)


def test_invalid_inputs_raise():
    basis = vector_basis(strip())
    with pytest.raises(ValueError, match="max_iterations"):
        NewtonOptions(max_iterations=0)
    with pytest.raises(ValueError, match="boundary"):
        Dirichlet.on(basis, "nowhere", "x")
    with pytest.raises(ValueError, match="components"):
        Dirichlet.on(basis, "left", "z")
    with pytest.raises(ValueError, match="one entry per DOF"):
        Dirichlet(np.arange(3), [1.0, 2.0])
    with pytest.raises(ValueError, match="linear_solver"):
        Solver(basis, LinearElastic(E, NU), tension_bcs(basis), linear_solver="magic")
    with pytest.raises(ValueError, match="end"):
        Solver(basis, LinearElastic(E, NU), tension_bcs(basis)).run(end=0.0, progress=False)


def test_vtu_fields_write_mandel_state_as_true_tensors(tmp_path):
    """Strain state variables reach the VTU file as 3 × 3 tensors with the true shears (read back with meshio),
    not as Mandel 6-vectors that ParaView would mislabel."""
    import meshio

    from abrakit.fem import Dirichlet, Solver, StepControl, meshes, vector_basis
    from abrakit.materials import LinearElastic

    mesh = meshes.plate_with_hole(50.0, 50.0, 10.0, 4, 3, 4.0)
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
           Dirichlet.on(basis, "top", "y", 0.05, name="top")]
    result = Solver(basis, LinearElastic(200000.0, 0.3), bcs, control=StepControl(initial=1.0, maximum=1.0)).run(
        output=tmp_path, progress=False)
    last = sorted((tmp_path / "fields").glob("*.vtu"))[-1]
    eps = meshio.read(last).cell_data["eps"][0]
    mandel = result.state["eps"].mean(axis=1)
    assert eps.shape == (mesh.nelements, 9)
    assert np.allclose(eps[:, 0], mandel[:, 0]) and np.allclose(eps[:, 4], mandel[:, 1])
    assert np.allclose(eps[:, 1], mandel[:, 5] / np.sqrt(2)) and np.allclose(eps[:, 1], eps[:, 3])


def test_node_row_dofs_picks_the_nearest_row_of_one_component():
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0.0, 4.0, 5), np.linspace(0.0, 2.0, 3))
    basis = vector_basis(mesh)
    dofs = node_row_dofs(basis, "x", 2.4, "y")                    # nearest column x = 2, its y-DOFs
    nodes = np.flatnonzero(np.isclose(mesh.p[0], 2.0))
    assert np.array_equal(np.sort(dofs), np.sort(np.asarray(basis.nodal_dofs)[1, nodes]))
    with pytest.raises(ValueError, match="components"):
        node_row_dofs(basis, "z", 1.0, "x")


def test_line_search_halves_a_correction_that_does_not_lower_the_residual():
    """R(x) = atan(x) from x = 2: the Newton correction overshoots to |R| = 1.30 > atan(2); the search halves it
    once (Armijo: |R(u + s du)| <= (1 - 1e-4 s) |R(u)|) and returns the evaluation at the accepted point."""
    from abrakit.fem.solver import LineSearch

    calls = []

    def evaluate(x):
        calls.append(x.copy())
        return None, np.arctan(x)

    u, free = np.array([2.0]), np.array([0])
    residual = np.arctan(u)
    du = -residual * (1.0 + u**2)                                       # Newton: -R / R'
    s, trial, evaluation = LineSearch()(evaluate, u, du, free, residual)
    assert s == 0.5 and trial[0] == u[0] + 0.5 * du[0] and len(calls) == 2
    assert abs(evaluation[1][0]) <= (1 - 0.5e-4) * abs(residual[0])
    s, trial, _ = LineSearch(max_backtracks=0)(evaluate, u, du, free, residual)
    assert s == 1.0                                                      # no halving allowed: the full step
    with pytest.raises(ValueError, match="max_backtracks"):
        LineSearch(max_backtracks=-1)
    with pytest.raises(TypeError, match="line_search"):
        Solver(vector_basis(meshes.plate_with_hole()), LinearElastic(1.0, 0.3), line_search="backtracking")


def test_a_failed_newton_step_carries_the_diagnosis_of_its_last_iterate():
    """``diagnose(reason, iterate)`` is called once per failed step with the step's last evaluated iterate; its
    answer is appended to the failure's reason, and hence to StepFailed's message."""
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3)).with_boundaries(
        {"bottom": lambda x: x[1] < 1e-9, "top": lambda x: x[1] > 1 - 1e-9})
    basis = vector_basis(mesh)
    seen = []

    def diagnose(reason, iterate):
        seen.append(iterate)
        return "named"

    bcs = [Dirichlet.on(basis, "bottom"), Dirichlet.on(basis, "top", "y", 0.5, name="top")]
    solver = Solver(basis, VonMisesPlasticity(210000.0, 0.3, 100.0, 0.0), bcs, diagnose=diagnose,
                    newton=NewtonOptions(max_iterations=1), control=StepControl(initial=1.0, maximum=1.0,
                                                                                minimum=0.5))
    with pytest.raises(StepFailed, match=r"\[named\]"):
        solver.run(progress=False)
    assert seen and all(it is not None and it.residual.shape == (basis.N,) for it in seen)
