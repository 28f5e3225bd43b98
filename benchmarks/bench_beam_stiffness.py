"""How stiff the DEM beam should be: its elastic flexural modulus against beam theory and an elastic continuum.

Issue 37 asks for the beam's elastic E_f against Timoshenko within 5 % at two resolutions. At the paper's S/H = 3
Timoshenko's theory ignores how the load enters the beam, so the benchmark adds the reference that does not: the
same beam as a 2D elastic continuum loaded through the fixture's pads
(:func:`abrakit.experiments.beam_continuum.continuum_flexural_modulus`, with the E and ν that the same lattice gives
in uniaxial tension, :func:`abrakit.experiments.bending.uniaxial_modulus`).

Per lattice resolution (largest radius 5, 3.5, 2.5 mm; 5 and 2.5 with ``--quick``): E and ν of the lattice, E_f of
Timoshenko, of the continuum through the fixture's pads (Richardson's limit of h = 2.5 and 1.25 mm, first order)
and through 2 mm pads (nearly point loads), and the DEM beam's E_f from the monotonic test at δ = 2 µm with both
fixtures ("pads": support particles held both ways, loading particles driven; "rockers": rigid one-sided pads at
the spans), with the particles each rocker pad touches at the end. Then the continuum's time against error over the
element size (error to the Richardson limit).

Writes ``beam_stiffness.csv``, ``beam_stiffness.json`` and ``beam_stiffness.png``.

    python benchmarks/bench_beam_stiffness.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib.pyplot as plt
from _common import command_line, save_figure

from abrakit.experiments.beam_continuum import continuum_flexural_modulus
from abrakit.experiments.bending import (
    BeamSpec,
    beam_theory_deflection,
    flexural,
    four_point_beam,
    monotonic_bending,
    uniaxial_modulus,
)
from abrakit.io import CurveWriter, write_json

NAME = "beam_stiffness"
DEFLECTION = 2e-6          # m: elastic, no bond beyond D₀
COLUMNS = ("radius_mm", "E_GPa", "nu", "timoshenko_GPa", "continuum_GPa", "continuum_point_GPa", "pads_GPa",
           "rockers_GPa", "pads_vs_timoshenko", "rockers_vs_timoshenko", "rockers_vs_continuum",
           "rockers_vs_continuum_point", "rocker_contacts")


def dem_modulus(spec: BeamSpec, fixture: str) -> tuple[float, list[int]]:
    beam = four_point_beam(spec, fixture=fixture)
    run = monotonic_bending(beam, speed=2.5e-4, record_every=500, max_deflection=DEFLECTION)
    modulus = float(flexural(run["load"][-1], run["deflection"][-1], spec)["modulus"])
    contacts = []
    if beam.rollers is not None:
        contacts = beam.rollers.contact_counts().tolist()
    return modulus, contacts


def continuum(spec: BeamSpec, E: float, nu: float, pad: float) -> float:
    """Richardson's first-order limit from h = 2.5 and 1.25 mm."""
    coarse, fine = (continuum_flexural_modulus(spec, E, nu, pad=pad, element_size=h)["modulus"]
                    for h in (0.0025, 0.00125))
    return 2.0 * fine - coarse


def main(outdir: Path, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    radii = (5e-3, 2.5e-3) if quick else (5e-3, 3.5e-3, 2.5e-3)
    rows = []
    writer = CurveWriter(outdir / f"{NAME}.csv", COLUMNS)
    try:
        for radius in radii:
            spec = BeamSpec(radius=radius)
            material = uniaxial_modulus(spec)
            E, nu = float(material["E"]), float(material["nu"])
            pad = max(0.01, 4.0 * radius)                     # four_point_beam's default pad
            timoshenko = float(flexural(1.0, beam_theory_deflection(1.0, E, nu, spec), spec)["modulus"])
            through_pads, point = continuum(spec, E, nu, pad), continuum(spec, E, nu, 0.002)
            pads, _ = dem_modulus(spec, "pads")
            rockers, contacts = dem_modulus(spec, "rockers")
            row = {"radius_mm": 1e3 * radius, "E_GPa": E / 1e9, "nu": nu, "timoshenko_GPa": timoshenko / 1e9,
                   "continuum_GPa": through_pads / 1e9, "continuum_point_GPa": point / 1e9, "pads_GPa": pads / 1e9,
                   "rockers_GPa": rockers / 1e9, "pads_vs_timoshenko": pads / timoshenko - 1,
                   "rockers_vs_timoshenko": rockers / timoshenko - 1,
                   "rockers_vs_continuum": rockers / through_pads - 1,
                   "rockers_vs_continuum_point": rockers / point - 1,
                   "rocker_contacts": " ".join(map(str, contacts))}
            writer.write(**row)
            rows.append(row)
    finally:
        writer.close()
    spec, E, nu = BeamSpec(), 1.9e9, 0.2
    sizes = (0.01, 0.005, 0.0025, 0.00125) if quick else (0.01, 0.005, 0.0025, 0.00125, 0.000625)
    convergence = []
    for h in sizes:
        tic = time.perf_counter()
        r = continuum_flexural_modulus(spec, E, nu, element_size=h)
        convergence.append({"element_size_mm": 1e3 * h, "dofs": r["dofs"], "modulus": r["modulus"],
                            "seconds": time.perf_counter() - tic})
    limit = 2.0 * convergence[-1]["modulus"] - convergence[-2]["modulus"]
    for c in convergence:
        c["error"] = abs(c["modulus"] / limit - 1.0)
    result = {"rows": rows, "continuum_convergence": convergence, "continuum_limit": limit,
              "deflection_m": DEFLECTION, "quick": quick}
    write_json(outdir / f"{NAME}.json", result)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    r_mm = [r["radius_mm"] for r in rows]
    for key, label, style in (("timoshenko_GPa", "Timoshenko", "k--"), ("continuum_GPa", "continuum, fixture pads",
                                                                        "k-"),
                              ("continuum_point_GPa", "continuum, 2 mm pads", "k:"), ("pads_GPa", "DEM, pads", "o-"),
                              ("rockers_GPa", "DEM, rockers", "s-")):
        ax[0].plot(r_mm, [r[key] for r in rows], style, label=label)
    ax[0].set(xlabel="largest radius [mm]", ylabel="E_f [GPa]", title="elastic flexural modulus (δ = 2 µm)")
    ax[0].invert_xaxis()
    ax[0].legend(fontsize=7)
    ax[1].loglog([c["seconds"] for c in convergence], [c["error"] for c in convergence], "o-")
    for c in convergence:
        ax[1].annotate(f"h = {c['element_size_mm']:g} mm", (c["seconds"], c["error"]), fontsize=7)
    ax[1].set(xlabel="wall time [s]", ylabel="relative error of E_f", title="continuum beam: time against error")
    save_figure(fig, outdir / f"{NAME}.png")
    result["summary"] = "\n".join(
        [f"{r['radius_mm']:.1f} mm: E {r['E_GPa']:.2f} GPa, nu {r['nu']:.2f}; E_f Timoshenko {r['timoshenko_GPa']:.2f},"
         f" continuum {r['continuum_GPa']:.2f} (2 mm pads {r['continuum_point_GPa']:.2f}), DEM pads "
         f"{r['pads_GPa']:.2f} ({r['pads_vs_timoshenko']:+.1%}), rockers {r['rockers_GPa']:.2f} "
         f"({r['rockers_vs_timoshenko']:+.1%} Timoshenko, {r['rockers_vs_continuum']:+.1%} continuum; contacts "
         f"{r['rocker_contacts']})" for r in rows]
        + [f"continuum h = {c['element_size_mm']:g} mm: {c['dofs']} DOF, {c['seconds']:.2f} s, error {c['error']:.2%}"
           for c in convergence])
    return result


if __name__ == "__main__":
    command_line(main, __doc__)
