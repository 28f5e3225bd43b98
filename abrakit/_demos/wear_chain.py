"""The demos of the wear chapters: how many grains touch the tool, the wear-rate model, the single scratch, where
its groove goes, and from the scratch to a wear rate.

The three scratch demos share one small scene, :data:`SCRATCH_SCENE`, run once per process
(:func:`scratch_run`). Each function returns the plain-text summary ``abrakit demo <chapter>`` prints.
"""

from __future__ import annotations

import functools

import numpy as np


def demo_contacting() -> str:
    """A small pressed bed: the count of grains on its floor against Eq. (8.7)."""
    from abrakit.experiments.contacting import SEED_COEFFICIENT, contact_census, pressed_bed

    D, L = 1e-3, CONTACTING_BOX * 1e-3
    sim, bed = pressed_bed(D, box=L, layers=CONTACTING_LAYERS, seed=0)
    census = contact_census(sim, wall_zone=D, tol=1e-3 * D)["all"]
    return (f"How many grains touch the tool (Ch. 8.3): {bed['coarse_grains']} frictionless grains of D = 1 mm "
            f"settled and pressed at 10 kPa in a {L / D:.0f} x {L / D:.0f} D box ({bed['steps']} steps, "
            f"{bed['seconds']:.1f} s)\n"
            f"{census['count']} grains touch the {(L - 2 * D) / D:.0f} x {(L - 2 * D) / D:.0f} D^2 floor window "
            f"without the wall zones: N_c D^2 = {census['N_c_D2']:.3f} (Eq. 8.7: {SEED_COEFFICIENT}; one bed this "
            "small scatters by about +-0.04 from the mean of many)")


#: The contacting demo's bed: box edge and height in grain diameters.
CONTACTING_BOX, CONTACTING_LAYERS = 6, 3


def demo_wear() -> str:
    """Table 8.4 recomputed, with the derived contact area."""
    from abrakit.wear import (
        ASTM_G65,
        G65_CONTACT_AREA,
        astm_g65_table,
        contacting_particles,
        contacting_particles_mixture,
        fit_scaling_area,
        wear_regime,
    )

    table = astm_g65_table()
    fit = fit_scaling_area(table["per_area"], table["seed"])
    N_a, N_b = contacting_particles_mixture(200e-6, 100e-6, 0.7)
    lines = [
        "Wear-rate model (Ch. 8.4), ASTM G65: wheel 228.5 mm at 200 rpm -> "
        f"v_t = {ASTM_G65.wheel_speed:.4f} m/s",
        f"N_c(100 um) = {contacting_particles(100e-6):.3g} /m2; 70/30 mixture of 200/100 um: "
        f"N_A = {N_a:.3g}, N_B = {N_b:.3g} /m2",
        f"contact area derived from Table 8.4: {G65_CONTACT_AREA * 1e6:.2f} mm2 (consistent interval "
        f"{fit.low * 1e6:.3f}-{fit.high * 1e6:.3f} mm2; half specimen face {ASTM_G65.specimen_area / 2 * 1e6:.1f})",
        f"{'material':32s} {'seed':>6s} {'ours':>7s} {'dev %':>6s}   [1e-7 m3/s]",
    ]
    for label, s, o, d in zip(table["label"], table["seed"], table["ours"], table["deviation"], strict=True):
        lines.append(f"{label:32s} {s * 1e7:6.2f} {o * 1e7:7.3f} {100 * d:+6.2f}")
    lines.append(f"regimes: f_ab = 0.37 -> {wear_regime(0.37)}, f_ab = 0.12 -> {wear_regime(0.12)}")
    return "\n".join(lines)


def _scratch_scene():
    from abrakit.scratch.scene import DEMO_SCENE, SpecimenMesh

    return DEMO_SCENE.with_(slide=0.016, size=(0.06, 0.015, 0.08),
                            mesh=SpecimenMesh(h=0.005, h_z=0.008, h_y=0.0015, growth=1.8, width=1.6))


@functools.lru_cache(maxsize=2)
def scratch_run(formulation: str = "scene"):
    """The demos' scratch: the small scene in its own physics (``"scene"``: finite strain, F-bar) or in the
    seed's formulation (``"seed"``: small strain, full integration); run once per process."""
    from abrakit.scratch.run import run_scratch
    from abrakit.scratch.scene import SEED_FORMULATION

    scene = _scratch_scene()
    return run_scratch(scene.with_(**SEED_FORMULATION) if formulation == "seed" else scene, vtu_every=0)


TRANSIENT = ("f_ab here is a transient reading: the section at mid-length of a {slide:g} um slide on this coarse "
             "mesh still lies in the indentation's transient, not in steady removal; the steady degree of wear of "
             "long scratches is far lower (chapter 'From our scratches to a wear rate')")
"""The caveat the book draws on the degree of wear of short scratches."""


def _building_blocks() -> str:
    """The scratch building blocks on the seed's default tip (R = 50 µm, d = 2 µm), without the FE solver."""
    from abrakit.scratch import SphericalIndenter, contact_response, groove_metrics, hertz_sphere, initial_state
    from abrakit.scratch.contact import penalty_from_stiffness
    from abrakit.scratch.indenters import FineZone, ScratchPath, check_path
    from abrakit.scratch.scene import ST52

    R, d = 0.05, 0.002
    tip = SphericalIndenter(R)
    path = check_path(ScratchPath(depth=d, slide=0.1, z_start=0.05), FineZone(0.02, 0.18, x_max=0.03), tip)
    hertz = hertz_sphere(ST52["E"], ST52["nu"], R, d)

    # A surface point 10 nm inside the tip's apex at the end of the indentation, then dragged in 0.3 nm steps:
    # it sticks until the elastic slip reaches mu p / c_T = 1 nm, then slips at |t_T| = mu p.
    c_N = penalty_from_stiffness(ST52["E"], 0.001)
    x = path.position(1.0)[None] + [0.0, 1e-5, 0.0]
    state, lines = initial_state(1), []
    for step in range(6):
        old, new = path.position(1.0 + step * 3e-6), path.position(1.0 + (step + 1) * 3e-6)
        gap = tip.gap(x, new)
        response = contact_response(gap.gap, gap.normal, -(new - old)[None], state, c_N=c_N, mu=0.1,
                                    normal_gradient=gap.normal_gradient)
        state = response.state
        t_T = response.traction - np.sum(response.traction * gap.normal, axis=1)[:, None] * gap.normal
        ratio = np.linalg.norm(t_T) / response.pressure[0]
        lines.append(f"    step {step + 1}: p = {response.pressure[0]:7.1f} MPa, |t_T|/p = {ratio:.4f}, "
                     f"{['open', 'stick', 'slip'][state['status'][0]]}")

    # A groove shaped by the tip (parabola of depth d) with triangular pile-ups of 1.7 µm.
    a = np.sqrt(2 * R * d)
    xs = np.linspace(0.0, 2 * a, 401)
    ys = np.where(xs <= a, xs**2 / (2 * R) - d, np.maximum(0.0017 * (1 - abs(xs - 1.5 * a) / (0.5 * a)), 0.0))
    groove = groove_metrics(xs, ys, half=True)
    return "\n".join([
        f"Single scratch building blocks: sphere R = {R * 1e3:g} um, depth d = {d * 1e3:g} um, slide "
        f"{path.slide * 1e3:g} um, footprint radius {tip.footprint_radius(d) * 1e3:.2f} um",
        f"Hertz (elastic St-52, rigid tip): F = {hertz.force:.3f} N (half model {hertz.force / 2:.3f} N), "
        f"a = {hertz.contact_radius * 1e3:.2f} um, p0 = {hertz.max_pressure / 1e3:.1f} GPa",
        f"penalty c_N = E/h at h = 1 um: {c_N:.3g} N/mm3; a point under the sliding tip (mu = 0.1):",
        *lines,
        f"synthetic groove: A_g = {groove.groove_area * 1e6:.1f} um2, A_s = {groove.shoulder_area * 1e6:.1f} um2, "
        f"w = {groove.width * 1e3:.2f} um, f_ab = {groove.degree_of_wear:.3f} ({groove.regime}), "
        f"D_p = {groove.degree_of_penetration:.3f}",
    ])


def _groove_line(label, g, notes) -> str:
    if g is None:
        return f"groove {label}: not defined ({'; '.join(notes)})"
    return (f"groove {label}: A_g = {g.groove_area * 1e6:.1f} um2, A_s = {g.shoulder_area * 1e6:.1f} um2, "
            f"w = {g.width * 1e3:.1f} um, f_ab = {g.degree_of_wear:.2f} ({g.regime} by Eq. 8.5's thresholds), "
            f"D_p = {g.degree_of_penetration:.3f}")


def _budget_line(name, r) -> str:
    b = r.budget.as_dict(scale=1e9)                                                         # mm3 -> um3
    return (f"{name}: groove {b['groove']:.0f} + sink {b['sink']:.0f} = shoulders {b['shoulders']:.0f} + prow "
            f"{b['prow']:.0f} + faces {b['faces']:.0f} - int(J-1)dV {b['volume_change']:+.0f} um3 "
            f"(closure {b['residual']:.1e})")


def demo_scratch() -> str:
    """The building blocks, then one small scratch in the scene's physics (finite strain, F-bar)."""
    from abrakit.scratch.scene import ST52

    r = scratch_run("scene")
    scene = r.scene
    lines = [
        _building_blocks(),
        f"Single scratch, half model: sphere R = {scene.indenter.radius * 1e3:g} um, d = {scene.depth * 1e3:g} um, "
        f"slide {scene.slide * 1e3:g} um on a {scene.size[2] * 1e3:g} um block, St-52 (sigma_0 = "
        f"{ST52['yield_stress']:g} MPa, H = {ST52['hardening']:g} MPa), mu = {scene.mu}; finite strain with F-bar "
        f"(the scene's physics); {r.n_elements} hexes / {r.n_dofs} DOF, {r.increments} increments, "
        f"{r.newton_iterations} Newton iterations, {r.cutbacks} cutbacks, {r.wall_time:.1f} s",
        f"forces while sliding (whole grain): F_N = {r.mean_normal_force:.3f} N, F_T = {r.mean_tangential_force:.3f}"
        f" N (F_T/F_N = {r.mean_tangential_force / r.mean_normal_force:.3f}); peak F_N "
        f"{np.max(r.curves['normal_force']):.3f} N at the end of the indentation",
        _groove_line("tip in contact", r.groove_loaded, r.notes),
        _groove_line("after unloading", r.groove_unloaded, r.notes),
        TRANSIENT.format(slide=scene.slide * 1e3),
    ]
    b = r.budget.as_dict(scale=1e9)
    lines.append(f"volume audit (um3): groove {b['groove']:.0f} + sink {b['sink']:.0f} = shoulders {b['shoulders']:.0f}"
                 f" + prow {b['prow']:.0f} - int(J-1)dV {b['volume_change']:+.0f} (closure {b['residual']:.1e}); "
                 "finite strain keeps only the elastic volume change, small strain loses volume at second order "
                 "(chapter 'Where the groove goes')")
    return "\n".join(lines)


def demo_scratch_volume() -> str:
    """The volume audit of the small scratch in the scene's physics and in the seed's small-strain formulation."""
    scene, seed = scratch_run("scene"), scratch_run("seed")
    return "\n".join([
        "Where the groove goes (Ch. 8.2, volume audit, whole grain, after unloading): groove + sink = shoulders + "
        "prow + faces - int(J-1)dV closes to round-off in both kinematics",
        _budget_line("finite strain, F-bar (the scene)   ", scene),
        _budget_line("small strain, full integration (seed)", seed),
        f"small strain loses {-seed.budget.volume_change * 1e9:.0f} um3 to int(J-1)dV, finite strain "
        f"{-scene.budget.volume_change * 1e9:.0f} um3 (its elastic volume change only): plastic flow conserves "
        "tr(eps) in small strain, det F at finite strain",
    ])


def demo_scratch_to_wear() -> str:
    """The small scratch's groove as a grain of Eq. (8.13), beside the seed's 100 µm grain (Table 8.4, row 1)."""
    from abrakit import wear

    r = scratch_run("scene")
    groove = r.groove_unloaded
    v_t = wear.ASTM_G65.wheel_speed
    lines = ["From one scratch to a wear rate (Ch. 8.4): N_c = 0.9/D^2 grains (Eq. 8.7) at the wheel speed "
             f"v_t = {v_t:.2f} m/s on the ASTM G65 contact area {wear.G65_CONTACT_AREA * 1e6:.2f} mm2, Eq. (8.14)"]
    if groove is None:
        return "\n".join([*lines, f"the small scratch left no readable groove ({'; '.join(r.notes)})"])
    D = 2.0 * r.scene.indenter.radius * 1e-3                                              # mm -> m
    ours = wear.Grain(D=D, A_g=groove.groove_area * 1e-6, f_ab=groove.degree_of_wear)     # mm2 -> m2
    rates = {}
    for name, grain in (("demo groove ", ours), ("seed's grain", wear.GRAIN_100UM)):
        rates[name] = wear.wear_rate(wear.contacting_particles(grain.D), grain.f_ab, grain.A_g, v_t,
                                     area=wear.G65_CONTACT_AREA)
        lines.append(f"{name}: D = {grain.D * 1e6:.0f} um, A_g = {grain.A_g * 1e12:5.1f} um2, f_ab = "
                     f"{grain.f_ab:.2f} -> wear rate {rates[name] * 1e7:.2f} x 1e-7 m3/s")
    lines.append(f"Table 8.4, homogeneous D = 100 um: {wear.TABLE_8_4[0][2] * 1e7:.2f} x 1e-7 m3/s; "
                 + TRANSIENT.format(slide=r.scene.slide * 1e3))
    return "\n".join(lines)


def demo_material_removal() -> str:
    """The removal model at a material point, and the G65 loss with the wheel's force shared over its grains."""
    from abrakit import g65
    from abrakit.materials.ductile_failure import JohnsonCookFailure

    criterion = JohnsonCookFailure()
    eps = criterion.fracture_strain(np.array([1.0 / 3.0, 0.0, -0.4]))
    D = criterion.update(0.0, np.full(3, 0.5), np.array([np.diag([300.0, 0.0, 0.0]),
                                                          [[0.0, 200.0, 0.0], [200.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
                                                          np.diag([-500.0, -100.0, -100.0])]))
    lines = ["Material removal (Ch. 8, beyond the seed): Johnson-Cook 4340 steel, D = sum d(eps_p)/eps_f(eta), "
             "no damage for eta <= -1/3",
             f"eps_f = {eps[0]:.3f} (uniaxial tension), {eps[1]:.3f} (shear), {eps[2]:g} (eta = -0.4); "
             f"D after eps_p = 0.5: {D[0]:.3f}, {D[1]:.3f}, {D[2]:g}"]
    grain, hardness = 256e-6, g65.STEEL_CONTACT_PRESSURE
    forces = g65.grain_forces(grain)
    none = g65.balanced_loss(grain, hardness, np.zeros_like)
    every = g65.balanced_loss(grain, hardness, np.ones_like)
    lines += [f"G65, {forces.size} grains of D = {grain * 1e6:.0f} um share the wheel's 130 N: {forces.sum():.1f} N, "
              f"{forces.min() * 1e3:.1f}-{forces.max() * 1e3:.1f} mN each, D_p = "
              f"{every.depth_ratio.min():.4f}-{every.depth_ratio.max():.4f} (plowing)",
              f"Procedure A loss: {none.loss_mm3:g} mm3 if single passes remove nothing, {every.loss_mm3:.0f} mm3 if "
              "every groove were cut out (measured on steels: 10-1000 mm3)"]
    return "\n".join(lines)
