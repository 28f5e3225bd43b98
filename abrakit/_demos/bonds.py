"""The demos of the fatigue chapters (seed 002): one cemented bond, and the beam in four-point bending.

Each function returns the plain-text summary ``abrakit demo <chapter>`` prints. Units: SI.
"""

from __future__ import annotations


def demo_fatigue() -> str:
    """The constitutive tests of seed 002 Sec. 4 against their closed forms and the paper's cycle counts."""
    from abrakit.fatigue import BondParameters, cyclic_test, monotonic_test, softening_energy

    p = BondParameters()
    lines = ["Fatigue of cemented bonds (seed 002): one bond, Table 1"]
    for mode in ("tension", "shear"):
        t = monotonic_test(p, mode)
        work = sum(0.5 * (a + b) * (v - u) for a, b, u, v in
                   zip(t.stress, t.stress[1:], t.displacement, t.displacement[1:], strict=False))
        lines.append(f"monotonic {mode}: peak {max(t.stress) / 1e3:.2f} kPa, work to failure {work:.4f} J/m² "
                     f"(closed form {softening_energy(p, mode):.4f})")
    full = cyclic_test(p, "tension", to_failure=False)
    jumped = cyclic_test(p, "tension", to_failure=False, jump=0.005)
    lines.append(f"20-60 kPa cycles, D 0.01 -> 0.4: {full.cycles[-1]} cycles; with the cycle jump 0.005: "
                 f"{jumped.simulated_cycles} simulated for {jumped.cycles[-1]}")
    for m, paper in ((0.8, 2008), (1.2, 50)):
        n = cyclic_test(p.replace(paris_exponent=m), "tension", stress_min=0.0, to_failure=False).cycles[-1]
        lines.append(f"m = {m}: {n} cycles with a 0-60 kPa range (paper: {paper})")
    return "\n".join(lines)


#: The demo's beam: disks of 5 mm radius, three across the 50 mm height (98 disks, the chapter's live beam).
BEAM_RADIUS = 5e-3


def demo_four_point_bending() -> str:
    """The chapter's coarse beam: its elastic flexural modulus (Eq. 44) against beam theory."""
    from abrakit.experiments import bending as fb

    spec = fb.BeamSpec(radius=BEAM_RADIUS)
    material = fb.uniaxial_modulus(spec)
    beam = fb.four_point_beam(spec, fixture="pads")
    elastic = fb.monotonic_bending(beam, record_every=500, max_deflection=2e-6)
    P, delta = elastic["load"][-1], elastic["deflection"][-1]
    measured = fb.flexural(P, delta, spec)["modulus"]
    theory = {shear: fb.flexural(P, fb.beam_theory_deflection(P, material["E"], material["nu"], spec, shear=shear),
                                 spec)["modulus"] for shear in (False, True)}      # beam theory through Eq. (44)
    n = len(beam.sim.particles)
    return "\n".join([
        f"Four-point bending (seed 002, Sec. 5): beam 200 x 50 x 50 mm, spans 150/50 mm, {n} bonded disks of r = "
        f"{spec.radius * 1e3:g} mm (Table 2 bonds), pads on the supports and loading points",
        f"elastic, to 2 um of deflection: flexural modulus by Eq. (44) {measured / 1e9:.3f} GPa; the same lattice "
        f"in uniaxial tension E = {material['E'] / 1e9:.3f} GPa, nu = {material['nu']:.3f}, which beam theory turns "
        f"into {theory[False] / 1e9:.3f} GPa (Euler-Bernoulli) and {theory[True] / 1e9:.3f} GPa (Timoshenko): "
        f"{100 * (measured / theory[True] - 1):+.0f} %. Eq. (44) ignores shear deformation, and three disks "
        "across the height are too few for a beam: examples/four_point_bending.py bends the 435-disk beam, "
        "which lies within 2 % of Timoshenko",
    ])
