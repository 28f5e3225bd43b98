"""Model I in the finite element loop (Algorithm 1): damage update, energy balance, snap-back, bad input."""

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
import skfem

from abrakit.damage import element_laplacian
from abrakit.damage.localisation import bar_mesh, cross_section
from abrakit.damage.model_one_fe import (
    ModelIResult,
    ModelISolver,
    coupled_damage_function,
    damage_update,
    element_mean,
    gradient_energy,
    solve_model_one,
)
from abrakit.fem import Dirichlet, Kinematics, NewtonOptions, StepControl, meshes, vector_basis
from abrakit.io import read_curve, read_json
from abrakit.materials import TABLE_7_1, ModelIDamage, VonMisesPlasticity
from abrakit.materials.model_one import damage_function_update

E, R_D = 200000.0, 0.05
EPS_0 = np.sqrt(2 * R_D / E)  # strain at the onset of damage in uniaxial strain with nu = 0, Psi0 = r_d


def bar_solver(n=11, length=2.0, beta=1.0, stretch=3.0, step=0.005, notch=0.0, depth=0.0, area=1.0, **options):
    """Bar of unit cross-section (square elements, nu = 0) pulled to ``stretch`` times the onset strain."""
    mesh = bar_mesh(n, length)
    basis = vector_basis(mesh)
    kin = Kinematics.from_basis(basis)
    sections = cross_section(mesh, area=area, depth=depth, notch=notch)
    kin = replace(kin, dx=kin.dx * (sections / (length / n))[:, None])
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
           Dirichlet.on(basis, "right", "x", stretch * EPS_0 * length, name="end")]
    options.setdefault("control", StepControl(initial=step, maximum=step, minimum=1e-4 * step))
    options.setdefault("damage_scheme", "coupled")
    return ModelISolver(kin, ModelIDamage(E, 0.0, R_D, beta=beta), bcs, **options)


def plate_solver(beta=1.0, step=0.01, displacement=0.1, newton=None, **material):
    """Coarse quarter plate with a hole (48 elements), Table 7.1 with plasticity, plane strain."""
    mesh = meshes.plate_with_hole(n_angular=8, n_radial=6)
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
           Dirichlet.on(basis, "top", "y", displacement, name="top")]
    params = {**TABLE_7_1, "beta": beta, "tangent": "consistent", **material}
    return ModelISolver(basis, ModelIDamage(**params), bcs, control=StepControl(initial=step, maximum=step),
                        damage_scheme="coupled", newton=newton)


# ---- the element-wise damage update ----------------------------------------------------------------------------
def test_element_mean_weights_by_volume():
    dx = np.array([[1.0, 3.0], [2.0, 2.0]])
    assert np.allclose(element_mean(np.array([[4.0, 0.0], [1.0, 3.0]]), dx), [1.0, 2.0])


def test_gradient_energy_of_a_linear_field_is_exact():
    """beta/2 |grad f|^2 V for f = 1 - 0.1 x on a uniform interior (Eq. 6.24); zero for beta = 0."""
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 10, 11), np.linspace(0, 4, 5))
    lap = element_laplacian(mesh)
    x = lap.centres[:, 0]
    f = 1.0 - 0.1 * x
    volumes = np.ones(mesh.t.shape[1])
    interior = (x > 1.5) & (x < 8.5)  # the Neumann ghosts flatten the gradient in the boundary elements
    grad = lap.gradient(f)
    assert np.allclose(grad[interior], [-0.1, 0.0])
    assert gradient_energy(f, volumes, lap, 2.0) > 0
    assert gradient_energy(f, volumes, lap, 0.0) == 0.0 and gradient_energy(f, volumes, None, 2.0) == 0.0


def _complementarity(f, f_old, psi0_bar, lap, beta, r_d):
    phi = f * (psi0_bar - beta * (lap.matrix @ f)) - r_d
    return phi, f_old - f


def test_coupled_damage_solves_the_complementarity_problem():
    """min(f_old - f, -Phi_d) = 0 for all elements of a 2D field with a hot spot (Eq. 6.64/6.76)."""
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 6, 13), np.linspace(0, 4, 9))
    lap = element_laplacian(mesh)
    x, y = lap.centres.T
    psi0_bar = 0.04 + 0.2 * np.exp(-((x - 3) ** 2 + (y - 2) ** 2))
    f_old = np.full(x.size, 0.9)
    for beta in (0.0, 0.1, 1.0):
        f, iterations = coupled_damage_function(f_old, psi0_bar, lap, beta, R_D, 1e-6)
        phi, gap = _complementarity(f, f_old, psi0_bar, lap, beta, R_D)
        assert np.all(gap >= 0) and np.all(f > 0)
        assert np.max(np.abs(np.minimum(gap, -phi))) < 1e-8
        assert np.any(gap > 0.1)
        assert np.any(gap == 0.0) == (beta < 1.0)  # beta = 1: the band (~ 2 sqrt(beta / r_d)) fills the plate
        assert iterations < 30
    # beta = 0: the local root f = r_d / Psibar0 where the hot spot is above threshold
    f0, _ = coupled_damage_function(f_old, psi0_bar, lap, 0.0, R_D, 1e-6)
    hot = psi0_bar * f_old > R_D
    assert np.allclose(f0[hot], R_D / psi0_bar[hot])


def test_coupled_equals_the_seed_update_for_a_single_active_element():
    """With one element above threshold its neighbours stay put, so both schemes agree (Eq. 6.77)."""
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 5, 6), np.linspace(0, 5, 6))
    lap = element_laplacian(mesh)
    psi0_bar = np.full(25, 0.01)
    psi0_bar[12] = 0.08
    f_old = np.ones(25)
    f_coupled, _ = coupled_damage_function(f_old, psi0_bar, lap, 0.01, R_D, 1e-6)
    f_seed = damage_function_update(f_old, psi0_bar, lap(f_old), lap.diagonal, 0.01, R_D, 1e-6)
    assert np.count_nonzero(f_coupled < 1) == 1
    assert np.allclose(f_coupled, f_seed, atol=1e-12)


def test_damage_update_keeps_d_constant_per_element_and_never_heals():
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 4, 5), np.linspace(0, 1, 2))
    basis = vector_basis(mesh)
    kin = Kinematics.from_basis(basis)
    material = ModelIDamage(E, 0.0, R_D, beta=0.5)
    state = material.initial_state((kin.nel, kin.nqp))
    state["psi0"] = np.linspace(0.0, 0.3, kin.nel * kin.nqp).reshape(kin.nel, kin.nqp)
    lap = element_laplacian(mesh)
    for scheme in ("seed", "coupled"):
        new = damage_update(material, state, kin.dx, lap, scheme)
        assert np.all(new["d"] == new["d"][:, :1]) and np.all(new["d"] >= state["d"])
        assert np.allclose(new["f"], np.exp(-new["d"]))
        unloaded = {**new, "psi0": np.zeros_like(new["psi0"])}
        assert np.all(damage_update(material, unloaded, kin.dx, lap, scheme)["d"] >= new["d"])  # no healing
        # without load only the gradient term can drive damage (-beta f Lambda_f > r_d at a band's edge)
        local = replace(material, beta=0.0)
        assert np.array_equal(damage_update(local, unloaded, kin.dx, None, scheme)["d"], new["d"])
    with pytest.raises(ValueError, match="scheme"):
        damage_update(material, state, kin.dx, lap, "implicit")


# ---- runs --------------------------------------------------------------------------------------------------------
def test_uniform_bar_follows_the_closed_form_and_keeps_f_in_range():
    """Short bar (shorter than the band): uniform damage f = r_d / Psi0 with Psi0 = E eps^2 / 2; f in (0, 1],
    monotone in every element at every step."""
    history = []
    result = bar_solver(beta=1.0, stretch=3.0).run(on_step=lambda r: history.append(r.f.copy()))
    assert result.completed and result.jumps == 0
    strain = result.curves["u_end"][-1] / 2.0
    assert np.allclose(result.f, R_D / (0.5 * E * strain**2), rtol=1e-6)
    f = np.array(history)
    assert np.all((f > 0) & (f <= 1)) and np.all(np.diff(f, axis=0) <= 0)
    assert isinstance(result, ModelIResult) and result.d.shape == result.f.shape


def test_energy_balance_of_a_softening_bar_is_first_order_in_the_step():
    """External work = stored + dissipated (Eq. 6.23-6.25) up to the error of the explicit split, O(step)."""
    errors = []
    for step in (0.005, 0.0025):
        c = bar_solver(beta=1.0, stretch=3.0, step=step).run().curves
        errors.append(np.max(np.abs(c["energy_error"])) / c["external_work"][-1])
    assert errors[0] < 0.015
    assert 1.7 < errors[0] / errors[1] < 2.3


def test_energy_balance_with_plasticity_before_the_first_drop():
    """Plate with a hole, Table 7.1 (plasticity + damage, beta = 1): balance within 1 % of the work until the first
    snap-back; damage and plastic dissipation both positive."""
    result = plate_solver(step=0.01).run()
    c = result.curves
    first = np.flatnonzero(c["jump"])[0] if result.jumps else len(c["step"])
    assert first > 10
    assert np.max(np.abs(c["energy_error"][:first])) < 0.01 * c["external_work"][first - 1]
    assert c["damage_dissipation"][-1] > 0 and c["plastic_dissipation"][-1] > 0
    assert np.allclose(c["stored_energy"] + c["dissipated_energy"] + c["energy_error"], c["external_work"])


def test_local_run_completes_and_localises_in_one_element():
    """beta = 0 (local, mesh-dependent by design) runs through the snap-back without crashing."""
    result = bar_solver(n=21, length=20.0, beta=0.0, stretch=2.0, step=0.005, notch=0.02, area=100.0).run()
    assert result.completed and result.jumps >= 1
    assert np.count_nonzero(result.f < 0.5) == 1 and result.laplacian is None
    F = result.curves["F_end"]
    assert F[-1] < 0.05 * F.max()


def test_snap_back_passed_or_stopped_with_the_last_state_saved(tmp_path):
    kwargs = {"n": 21, "length": 20.0, "beta": 1.0, "stretch": 2.5, "step": 0.01, "notch": 0.02, "depth": 0.05}
    passed = bar_solver(**kwargs).run()
    assert passed.completed and passed.jumps >= 1 and passed.cutbacks >= 1
    F = passed.curves["F_end"]
    drop = np.argmin(np.diff(F))
    assert F[drop] - F[drop + 1] > 0.1 * F.max()                                  # a sudden force drop ...
    assert passed.curves["u_end"][drop + 1] - passed.curves["u_end"][drop] < 0.002 * passed.curves["u_end"][-1]
    with pytest.warns(RuntimeWarning, match="snap-back"):
        stopped = bar_solver(**kwargs, snap_back="stop").run(output=tmp_path)
    assert not stopped.completed and "snap-back" in stopped.message
    assert stopped.curves["F_end"].max() == pytest.approx(F.max(), rel=1e-6)    # converged steps kept
    assert (tmp_path / "last_converged.npz").exists()
    assert read_json(tmp_path / "summary.json")["completed"] is False


def test_output_files(tmp_path):
    result = bar_solver(step=0.05).run(output=tmp_path, vtu_every=5)
    curve = read_curve(tmp_path / "model_one.csv")
    assert len(curve["step"]) == len(result.curves["step"])
    assert np.allclose(curve["dissipated_energy"], result.curves["dissipated_energy"])
    summary = read_json(tmp_path / "summary.json")
    assert summary["completed"] and summary["peak_F_end"] == pytest.approx(result.peak("end")[0])
    assert (tmp_path / "curves.csv").exists() and (tmp_path / "fields" / "step.pvd").exists()
    import meshio

    vtu = sorted((tmp_path / "fields").glob("*.vtu"))[-1]
    fields = meshio.read(vtu).cell_data
    assert {"d", "f", "alpha_p", "laplacian"} <= set(fields)


def test_tangent_choice_changes_iterations_not_the_answer():
    """Eq. (6.63) f^m E and the consistent tangent converge to the same equilibrium (the constant tangent
    converges only linearly while plastic flow is active: it needs more iterations)."""
    split = plate_solver(step=0.02, displacement=0.04, tangent="operator_split",
                         newton=NewtonOptions(max_iterations=60)).run()
    consistent = plate_solver(step=0.02, displacement=0.04).run()
    F_split, F_cons = split.curves["F_top"], consistent.curves["F_top"]
    assert len(F_split) == len(F_cons)
    assert np.allclose(F_split, F_cons, rtol=2e-4, atol=1e-6 * F_cons.max())
    assert split.curves["iterations"].sum() > consistent.curves["iterations"].sum()


def test_seed_scheme_lags_and_converges_to_the_coupled_one_with_the_step():
    """Algorithm 1 as printed takes Lambda_f from f^m: on a fine bar its damage lags behind the load (peak too
    high); the lag shrinks with the load step, towards the coupled update."""
    kwargs = {"n": 41, "length": 20.0, "beta": 1.0, "stretch": 1.4, "notch": 0.02, "depth": 0.05}
    coupled = [bar_solver(**kwargs, step=s).run().peak("end")[0] for s in (0.01, 0.0025)]
    seed = [bar_solver(**kwargs, step=s, damage_scheme="seed").run().peak("end")[0] for s in (0.01, 0.0025)]
    assert abs(coupled[0] - coupled[1]) < 0.02 * coupled[1]          # the coupled update hardly feels the step
    assert seed[0] > 1.2 * coupled[1]
    assert abs(seed[1] - coupled[1]) < 0.5 * abs(seed[0] - coupled[1])


def test_runs_on_an_extruded_hex_mesh():
    mesh = meshes.extrude(skfem.MeshQuad.init_tensor(np.linspace(0, 4, 5), np.linspace(0, 2, 3)).with_boundaries(
        {"left": lambda x: x[0] < 1e-9, "right": lambda x: x[0] > 4 - 1e-9}), 1.0, 1)
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "left", "xyz"), Dirichlet.on(basis, "right", "x", 4 * 3 * EPS_0, name="end")]
    result = solve_model_one(basis, ModelIDamage(E, 0.0, R_D, beta=0.5), bcs, damage_scheme="coupled",
                             control=StepControl(initial=0.05, maximum=0.05))
    assert result.completed and result.f.min() < 0.5 and result.f.shape == (mesh.t.shape[1],)


# ---- bad input ---------------------------------------------------------------------------------------------------
def test_invalid_input_is_rejected():
    mesh = bar_mesh(5, 2.0)
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "left", "x")]
    material = ModelIDamage(E, 0.0, R_D, beta=1.0)
    with pytest.raises(TypeError, match="Model I material"):
        ModelISolver(basis, VonMisesPlasticity(E, 0.3, 60.0), bcs)
    with pytest.raises(ValueError, match="max_dd"):
        ModelISolver(basis, material, bcs, max_dd=0.0)
    with pytest.raises(ValueError, match="snap_back"):
        ModelISolver(basis, material, bcs, snap_back="ignore")
    with pytest.raises(ValueError, match="damage_scheme"):
        ModelISolver(basis, material, bcs, damage_scheme="implicit")
    with pytest.raises(ValueError, match="jump_step"):
        ModelISolver(basis, material, bcs, jump_step=1e-12)
    with pytest.raises(ValueError, match="laplacian"):
        ModelISolver(basis, material, bcs, laplacian=element_laplacian(bar_mesh(7, 2.0)))


def test_coupled_damage_reports_non_convergence():
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 6, 13), np.linspace(0, 4, 9))
    lap = element_laplacian(mesh)
    psi0_bar = 0.04 + 0.2 * np.exp(-((lap.centres[:, 0] - 3) ** 2))
    with pytest.raises(RuntimeError, match="did not converge"):
        coupled_damage_function(np.full(psi0_bar.size, 0.9), psi0_bar, lap, 1.0, R_D, 1e-6, max_iterations=1)
    assert sp.issparse(lap.matrix)
