"""The demos of the finite element and damage chapters: fem, plasticity, localisation, Model I, Model II, their
comparison and the anisotropic damage of the second source.

Each function returns the plain-text summary ``abrakit demo <chapter>`` prints. Units: N, mm, MPa.
"""

from __future__ import annotations

import time

import numpy as np


def demo_fem() -> str:
    """Elastoplastic quarter plate with a hole (Table 7.1 plasticity, plane strain)."""
    from abrakit.fem import StepControl
    from abrakit.fem.problems import TABLE_7_1_PLASTICITY, plate_with_hole_problem
    from abrakit.materials import VonMisesPlasticity

    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY, integration="implicit")
    solver = plate_with_hole_problem(material, displacement=0.05, control=StepControl(initial=0.1, maximum=0.1))
    start = time.perf_counter()
    result = solver.run(progress=False)
    elapsed = time.perf_counter() - start
    tangent = result.response.tangent
    t0 = time.perf_counter()
    for _ in range(5):
        solver.assembler.tangent(tangent)
    rate = 5 * solver.kin.ndof / (time.perf_counter() - t0)
    plastic = np.mean(result.state["alpha_p"].max(axis=1) > 0)
    return (
        f"Quarter plate with a hole (50 x 50 mm, R = 10 mm), plane strain, von Mises (Table 7.1), "
        f"{solver.kin.nel} bilinear quads / {solver.kin.ndof} DOF: top edge pulled to "
        f"{result.curves['u_top'][-1]:.3f} mm in {len(result.load_factors) - 1} steps "
        f"({int(result.iterations.sum())} Newton iterations, {result.cutbacks} cutbacks, {elapsed:.2f} s); "
        f"reaction {result.curves['F_top'][-1]:.1f} N/mm, {100 * plastic:.0f} % of the elements plastic. "
        f"Tangent assembly {rate:.3g} DOF/s."
    )


def demo_plasticity() -> str:
    """Uniaxial tension of the Table 7.1 steel at a point: plasticity against the closed form, Model I/II peaks."""
    from abrakit.materials import (
        TABLE_7_1,
        ModelIDamage,
        ModelIIDamage,
        VonMisesPlasticity,
        ramp,
        uniaxial_hardening_modulus,
        uniaxial_strain,
        uniaxial_stress,
        uniaxial_yield_stress,
    )

    p = TABLE_7_1
    plastic = VonMisesPlasticity(p["E"], p["nu"], p["r_p"], p["K_H"], integration="implicit")
    eps = ramp(0.01, 50)
    curve = uniaxial_stress(plastic, eps)
    sigma_0, H = uniaxial_yield_stress(p["r_p"]), uniaxial_hardening_modulus(p["K_H"])
    eps_y, E_t = sigma_0 / p["E"], p["E"] * H / (p["E"] + H)
    closed = np.where(eps < eps_y, p["E"] * eps, sigma_0 + E_t * (eps - eps_y))
    error = np.max(np.abs(curve.stress_component("11")[1:] - closed))

    model_one = ModelIDamage(p["E"], 0.0, p["r_d"])
    peak_one = uniaxial_strain(model_one, ramp(2e-3, 400)).stress_component("11").max()
    model_two = ModelIIDamage(p["E"], 0.0, 0.1, n=20)
    path_two = uniaxial_strain(model_two, ramp(3e-3, 300), loading={"external_work": 1.0})
    return (
        f"von Mises (implicit), uniaxial stress to 1 %: yield {sigma_0:.2f} MPa, final stress "
        f"{curve.stress_component('11')[-1]:.2f} MPa, max error to the closed form {error:.1e} MPa\n"
        f"Model I (beta = 0, nu = 0), uniaxial strain: peak {peak_one:.2f} MPa vs sqrt(2 r_d E) = "
        f"{np.sqrt(2 * p['r_d'] * p['E']):.2f} MPa\n"
        f"Model II (n = 20, alpha dW = 0.05 per step): peak {path_two.stress_component('11').max():.2f} MPa, "
        f"final sub-domain damage {np.round(path_two.internal['d'][-1], 3).tolist()}"
    )


def demo_localisation() -> str:
    """Local against regularised softening bar on three meshes: the energy dissipated to break it."""
    from abrakit.damage.localisation import localisation_study

    study = localisation_study(LOCALISATION_MESHES, step=0.004)
    lines = ["Bar 20 mm x 100 mm^2 with a weak spot, pulled to 0.04 mm; energy dissipated to break it (N mm):"]
    for name in study.runs:
        e = ", ".join(f"{v:.3g}" for v in study.energies(name))
        lines.append(f"  {name:10s} n = {study.n_elements}: {e}  (finest/coarsest {study.energy_ratio(name):.2f}, "
                     f"F-u distance {100 * study.curve_distance(name):.1f} %)")
    return "\n".join(lines)


#: Element numbers of the localisation demo's bars.
LOCALISATION_MESHES = (21, 41, 81)


def _laplacian_summary() -> str:
    """Laplacian of a quadratic and of cos(pi x) cos(pi y) on perturbed quadrilateral meshes."""
    from abrakit.damage.laplacian import element_laplacian, face_neighbours, unit_cube_mesh

    lines = []
    for n in (8, 16, 32):
        mesh = unit_cube_mesh("quad", n, perturb=0.25)
        lap = element_laplacian(mesh)
        x, y = lap.centres.T
        quadratic = lap(1.0 + x - 2.0 * y + 2.0 * x**2 + x * y - 0.5 * y**2)   # exact Laplacian 4 - 1 = 3
        cosine = lap(np.cos(np.pi * x) * np.cos(np.pi * y))                # exact -2 pi^2 cos cos
        error = cosine + 2.0 * np.pi**2 * np.cos(np.pi * x) * np.cos(np.pi * y)
        interior = np.all(face_neighbours(mesh) >= 0, axis=1)
        lines.append(f"h = 1/{n:<3d} {mesh.t.shape[1]:5d} quads: quadratic |Lf - 3| = "
                     f"{np.abs(quadratic[interior] - 3.0).max():.1e} (interior), cos field rms error "
                     f"{np.sqrt(np.mean(error**2)):.3f} of |Lf| <= {2 * np.pi**2:.1f}, fallbacks {lap.n_fallback}")
    return ("Model I element Laplacian (4 faces + 1 diagonal, mirrored ghosts) on quads perturbed by 25 % of h:\n"
            + "\n".join(lines))


def demo_model_one() -> str:
    """The element Laplacian, then Model I (Table 7.1, beta = 1 MPa mm^2) on a coarse quarter plate with a hole."""
    from abrakit.damage.model_one_fe import ModelISolver
    from abrakit.fem import Dirichlet, StepControl, meshes, vector_basis
    from abrakit.materials import TABLE_7_1, ModelIDamage

    mesh = meshes.plate_with_hole(n_angular=8, n_radial=6)
    basis = vector_basis(mesh)
    conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
                  Dirichlet.on(basis, "top", "y", 0.1, name="top")]
    material = ModelIDamage(**{**TABLE_7_1, "beta": 1.0}, tangent="consistent")
    solver = ModelISolver(basis, material, conditions, control=StepControl(initial=0.01, maximum=0.01))
    result = solver.run()
    c = result.curves
    peak, u_peak = result.peak("top")
    return _laplacian_summary() + "\n" + (
        f"Model I (Table 7.1, beta = 1 MPa mm^2, coupled damage update) on a quarter plate with a hole, "
        f"{solver.kin.nel} quads, plane strain, top edge pulled to {c['u_top'][-1]:.2f} mm in "
        f"{len(c['step']) - 1} steps ({result.cutbacks} cutbacks, {result.jumps} sudden drops passed, "
        f"{result.wall_time:.1f} s): peak {peak:.0f} N/mm at u = {u_peak:.3f} mm, final force "
        f"{c['F_top'][-1]:.0f} N/mm; {int(np.sum(result.f < 0.5))} elements below half stiffness, "
        f"max alpha_p {result.alpha_p.max():.4f}. Energy (N mm/mm): external {c['external_work'][-1]:.1f} = stored "
        f"{c['stored_energy'][-1]:.1f} + dissipated {c['dissipated_energy'][-1]:.1f} (damage "
        f"{c['damage_dissipation'][-1]:.1f}, plastic {c['plastic_dissipation'][-1]:.1f}) + released in drops "
        f"{c['energy_error'][-1]:.1f}."
    )


def demo_model_two() -> str:
    """Double-notched strip, ~300 elements, Model II with alpha = 0.005 (Table 7.2)."""
    from abrakit.damage.model_two_fe import run_model_two
    from abrakit.damage.specimens import double_notched

    specimen = double_notched(300)
    res = run_model_two(specimen, alpha=0.005, steps=100, stop_fraction=0.05)
    F_max, u_peak = res.peak()
    s = res.summary()
    return (
        f"Model II (ERVE, n = 20, alpha = 0.005 1/(N mm), Table 7.2) on the double-notched strip 50 x 100 mm, "
        f"{res.elements} elements, plane strain x 3 mm: peak force {F_max:.0f} N at u = {u_peak:.4f} mm; "
        f"{res.status} after {res.steps} steps ({res.newton_iterations} Newton iterations, {res.cutbacks} "
        f"cutbacks, {res.wall_time:.1f} s); dissipated {res.dissipated_energy:.1f} N mm of "
        f"{s['external_work_Nmm']:.1f} N mm external work (balance error {s['energy_error_Nmm']:.2f} N mm); "
        f"max sub-domain damage {s['max_d']:.3f} (cap 0.999); "
        f"fully damaged area {res.curves['damaged_area'][-1]:.1f} mm^2."
    )


#: Elements of the comparison demo's double-notched strip (the chapter's live strip has about 500).
COMPARISON_ELEMENTS = 120


def demo_comparison() -> str:
    """Model I and Model II, weak and strong regularisation (Tables 7.1/7.2), on one coarse double-notched strip."""
    from abrakit.damage import metrics
    from abrakit.damage.runs import REGULARISATION, run_specimen
    from abrakit.damage.specimens import specimen

    sp = specimen("double_notched", COMPARISON_ELEMENTS)
    lines = [f"Model I and Model II (Ch. 7.3) on the double-notched strip 50 x 100 mm, {sp.elements} elements, "
             "plane strain x 3 mm, steps of 0.004 mm until the force falls below 10 % of its peak:"]
    peaks = {}
    for model in ("I", "II"):
        name = "beta" if model == "I" else "alpha"
        unit = "MPa mm^2" if model == "I" else "1/(N mm)"
        for strength, parameter in REGULARISATION[model].items():
            run = run_specimen(sp, model, parameter, step=0.004, stop_fraction=0.1)
            peaks[model, strength] = run.F.max()
            lines.append(f"  Model {model:2s} {strength:6s} ({name} = {parameter:g} {unit}): peak {run.F.max():6.0f} N,"
                         f" work {metrics.path_work(run.u, run.F):6.1f} N mm, {run.status} after {run.steps} steps,"
                         f" {run.seconds:.1f} s")
    ratios = ", ".join(f"Model {m} {peaks[m, 'strong'] / peaks[m, 'weak']:.2f}" for m in ("I", "II"))
    lines.append(f"the strong regularisation carries more than the weak one (peak strong/weak: {ratios}; "
                 "claim 5 of the chapter)")
    return "\n".join(lines)


def demo_anisotropic_damage() -> str:
    """A crack-band bar on 1 and 64 elements: the energy per crack area is G_Ic on both."""
    from abrakit.damage import metrics
    from abrakit.damage.crack_band import CrackBandBar
    from abrakit.fem import StepControl

    lines = []
    for n in (1, 64):
        bar = CrackBandBar(n)
        solver = bar.solver(follow=False, control=StepControl(initial=0.01, maximum=0.01))
        result = solver.run(progress=False)
        v, F = result.curves["u_right"], result.curves["F_right"]
        work = metrics.work(v, F)
        lines.append(f"{n} element(s): peak {F.max():.4f} N (weak element's strength {bar.strength:g} N), "
                     f"work to separation {work:.5f} N mm against G_Ic A = {bar.fracture_energy:g} N mm "
                     f"({100 * (work / bar.fracture_energy - 1):+.3f} %)")
    return ("Seed 001's anisotropic softening damage, crack band in a 100 mm bar (E = 1000 MPa, sigma_c = 1 MPa, "
            "G_Ic = 0.1 N/mm, linear softening): " + "; ".join(lines) + ". The energy does not depend on the mesh.")
