"""Benchmark: material removal by ductile erosion in the scratch, its mesh convergence and the wear-mode map.

Every scene erodes the St-52 block by Johnson and Cook's 4340 damage with the cut-off η ≤ −1/3 and the nonlocal
length ℓ = :data:`LENGTH` (:mod:`abrakit.scratch.erosion`), at finite strain with F-bar, d = 2 µm, on a 100 × 15 ×
100 µm block slid :data:`SLIDE` along its middle. Its readings: the removal fraction f_ab = (rate of removed
volume)/(rate of groove volume) over the second half of the slide, by chords (:func:`chord`; the f_ab the wear
chain takes), Eq. (8.5) on the
mid-length section with the tip in contact (the seed's reading, which counts the compaction of the wake as wear),
the degree of penetration D_p = d/a (a the tip's footprint radius at d) and the attack angle at the footprint's
rim (:func:`attack_angle`), the eroded elements and the slide positions where they went, the energy their
erosion released, the budget's worst closure and the run time.

Parts (every run kept in ``<outdir>/scratch_removal/<name>/``, reused by later calls with the same scene, so an
interrupted benchmark resumes; ``--only NAME`` computes one run, e.g. in another process):

1. **mesh convergence** of the removed volume per unit slide at one cutting scene (cone of 120° included angle,
   attack angle 30°, tip radius 5 µm, μ = 0.5) on the mesh levels :data:`MESH_STUDY`;
2. **ductility**: the cutting scene with a steel of half and a quarter of 4340's fracture strain
   (:data:`DUCTILITY`), how removal depends on the ductility;
3. **the wear-mode map**: D_p from 0.1 to 0.5, by spheres whose radius puts d = 2 µm at that D_p
   (:func:`sphere_for`, :data:`MAP_PENETRATIONS`) and by sphere-tipped cones (an angular quartz corner: tip
   radius 5 µm, attack angle 20° and 30°), at μ = 0.1 and 0.5, on the mesh the convergence study picks
   (:data:`MAP_MESH`).

Writes ``scratch_removal.json``, ``scratch_removal.csv`` and ``scratch_removal.png``.

    python benchmarks/bench_scratch_removal.py [--quick] [--only NAME] [--stored-only] [--outdir DIR]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from _common import RESULTS, save_figure
from bench_scratch_steady import run_or_load

from abrakit.io import CurveWriter, read_curve, read_json, write_json
from abrakit.materials import JohnsonCookFailure
from abrakit.scratch.budget import steady_rates
from abrakit.scratch.erosion import Erosion
from abrakit.scratch.indenters import ConicalIndenter, SphericalIndenter
from abrakit.scratch.scene import ScratchScene
from abrakit.wear import PENETRATION_BANDS

STUDY = "scratch_removal"
LENGTH = 0.001
"""The nonlocal length ℓ of the erosion, mm (1 µm: half the scratch's depth, so that a 2 µm groove can shed a
layer, and at least the top element layer of the meshes compared)."""
DEPTH, SLIDE, BLOCK = 0.002, 0.03, (0.1, 0.015, 0.1)
TIP_RADIUS = 0.005
"""Tip radius of the sphere-tipped cones (mm): a rounded quartz corner."""
MESH_STUDY = ("default", "fine")
"""The mesh levels of the convergence study ("finer", 7020 elements, is left out: with ten indentation increments,
after its contact chattered at five, its indentation alone had not finished after 20 minutes on two cores)."""
MAP_MESH = "fine"
DUCTILITY = (0.5, 0.25)
"""Factors on Johnson and Cook's ε_f (D₁ and D₂ scaled) of the ductility study: a steel of half and a quarter of
4340's fracture strain at every triaxiality, at the cutting scene of the mesh study."""
FRICTIONS = (0.1, 0.5)
MAP_PENETRATIONS = {0.1: (0.1, 0.2, 0.3, 0.45), 0.5: (0.2, 0.3, 0.45)}
"""The spheres' D_p at each friction (D_p = 0.1 at μ = 0.5 left out: the μ = 0.1 point there removes nothing, and
friction adds shear only where the tip already plows deep)."""
MAP_ATTACK_ANGLES = (20.0, 30.0)
CONTROL = {"sphere_Dp0.3_mu0.5": {"slide_step": 0.0005},
           **{f"cone30_mu0.5_fine_ductility{f:g}": {"indent_steps": 10} for f in (0.5, 0.25)}}
"""Increment control of the runs whose contact chattered at the default one (the less ductile steels in their
indentation, the sphere at D_p = 0.3 and μ = 0.5 after 7.6 µm of slide): more indentation increments, a slide
step of h_z/8."""
COLUMNS = ("name", "tip", "mesh", "mu", "R_um", "attack_deg", "D_p", "D_p_section", "elements", "wall_time_s",
           "eroded", "erosion_energy_uJ", "rate_groove_um2", "rate_removed_um2", "removed_per_slide_um2",
           "removal_f_ab", "seed_f_ab",
           "rate_f_ab", "max_damage", "worst_residual_rel", "finished")


def sphere_for(penetration: float, depth: float = DEPTH) -> float:
    """The sphere radius (mm) whose footprint a = √(2Rd − d²) at ``depth`` gives D_p = d/a = ``penetration``."""
    return 0.5 * depth * (1.0 / penetration**2 + 1.0)


def scene(indenter, mu: float, mesh: str = MAP_MESH, ductility: float = 1.0) -> ScratchScene:
    steel = JohnsonCookFailure()
    criterion = replace(steel, D1=steel.D1 * ductility, D2=steel.D2 * ductility)
    return ScratchScene(indenter=indenter, depth=DEPTH, slide=SLIDE, size=BLOCK, mu=mu, mesh=mesh,
                        erosion=Erosion(criterion, length=LENGTH))


def cone(attack_angle: float) -> ConicalIndenter:
    return ConicalIndenter(TIP_RADIUS, 90.0 - attack_angle)


def planned() -> dict[str, ScratchScene]:
    plan = {f"cone30_mu0.5_{mesh}": scene(cone(30.0), 0.5, mesh) for mesh in MESH_STUDY}
    for mu in FRICTIONS:
        for D_p in MAP_PENETRATIONS[mu]:
            plan[f"sphere_Dp{D_p:g}_mu{mu:g}"] = scene(SphericalIndenter(sphere_for(D_p)), mu)
        for angle in MAP_ATTACK_ANGLES:
            plan.setdefault(f"cone{angle:g}_mu{mu:g}_{MAP_MESH}", scene(cone(angle), mu))
    for factor in DUCTILITY:
        plan[f"cone30_mu0.5_{MAP_MESH}_ductility{factor:g}"] = scene(cone(30.0), 0.5, ductility=factor)
    return {name: sc.with_(**CONTROL.get(name, {})) for name, sc in plan.items()}


def analyse(name: str, sc: ScratchScene, folder: Path) -> dict:
    """The row of one stored run (unfinished runs: from the increments written so far, no section)."""
    curves = read_curve(folder / "forces.csv")
    finished = (folder / "summary.json").exists() and (folder / "u.npy").exists()
    summary = read_json(folder / "summary.json") if finished else {}
    sliding = curves["phase"] == 1
    rates = steady_rates(curves) if np.count_nonzero(sliding) >= 6 else None
    removed_rate = chord(curves, "V_removed")
    loaded = summary.get("groove_loaded") or {}
    erosion = summary.get("erosion") or {}
    tip = "sphere" if isinstance(sc.indenter, SphericalIndenter) else "cone"
    residual = np.max(np.abs(curves["V_residual"])) / max(np.max(curves["V_groove"]), 1e-300)
    return {"name": name, "tip": tip, "mesh": sc.mesh, "mu": sc.mu, "R_um": sc.indenter.radius * 1e3,
            "attack_deg": attack_angle(sc),
            "D_p": sc.depth / sc.footprint, "D_p_section": loaded.get("D_p", np.nan),
            "elements": summary.get("elements", np.nan),
            "wall_time_s": summary.get("wall_time_s", float(curves["wall_time"][-1])),
            "eroded": erosion.get("eroded_elements", np.nan),
            "erosion_energy_uJ": erosion.get("erosion_energy", np.nan) * 1e3,
            "rate_groove_um2": rates.groove * 1e6 if rates else np.nan,
            "rate_removed_um2": removed_rate * 1e6,
            "removed_per_slide_um2": slide_mean_removal(curves) * 1e6,
            "removal_events_um": removal_events(curves),
            "removal_f_ab": removed_rate / chord(curves, "V_groove"),
            "seed_f_ab": loaded.get("f_ab", np.nan), "rate_f_ab": rates.degree_of_wear if rates else np.nan,
            "max_damage": erosion.get("max_ductile_damage", np.nan), "worst_residual_rel": float(residual),
            "finished": finished, "slide_reached_um": float(curves["slide"][sliding].max() * 1e3)
            if sliding.any() else 0.0}


def attack_angle(sc: ScratchScene) -> float:
    """The tip's attack angle at the rim of its footprint, degrees: 90° − half-angle on a cone's flank, arcsin(a/R)
    on a sphere (Challen and Oxley's angle of the wedge that meets the surface)."""
    if isinstance(sc.indenter, SphericalIndenter):
        return float(np.degrees(np.arcsin(min(sc.footprint / sc.indenter.radius, 1.0))))
    return 90.0 - sc.indenter.half_angle


def chord(curves: dict, column: str) -> float:
    """(V(end) − V(mid))/(s(end) − s(mid)) of a budget column over the second half of the slide, mm²: the mean
    rate, which a removal in discrete element-sized events needs (a least-squares slope weighs an event by where in
    the window it falls); NaN before the slide's second half is reached."""
    sliding = np.flatnonzero(curves["phase"] == 1)
    if sliding.size < 6:
        return float("nan")
    s, v = curves["slide"][sliding], curves[column][sliding]
    mid = int(np.searchsorted(s, 0.5 * s[-1]))
    return float((v[-1] - v[mid]) / (s[-1] - s[mid])) if s[-1] > s[mid] else float("nan")


def slide_mean_removal(curves: dict) -> float:
    """The volume removed while sliding over the slide length, mm² (transient included): the measure of the mesh
    study, robust where the removal is a few element-sized events."""
    sliding = np.flatnonzero(curves["phase"] == 1)
    if sliding.size < 2:
        return float("nan")
    s, v = curves["slide"][sliding], curves["V_removed"]
    start = v[sliding[0] - 1] if sliding[0] > 0 else 0.0
    return float((v[sliding[-1]] - start) / s[-1]) if s[-1] > 0 else float("nan")


def removal_events(curves: dict) -> list[float]:
    """The slide positions (µm; negative: during the indentation, 0) of the increments that removed material."""
    grew = np.flatnonzero(np.diff(curves["V_removed"], prepend=0.0) > 0.0)
    return [float(curves["slide"][i] * 1e3) if curves["phase"][i] >= 1 else 0.0 for i in grew]


def crossing(D_p: np.ndarray, f_ab: np.ndarray, level: float = 0.1) -> float:
    """The D_p at which f_ab first reaches ``level`` (linear between the bracketing points), NaN if it does not."""
    order = np.argsort(D_p)
    D_p, f_ab = np.asarray(D_p)[order], np.asarray(f_ab)[order]
    above = np.flatnonzero(f_ab >= level)
    if above.size == 0:
        return float("nan")
    k = above[0]
    if k == 0:
        return float(D_p[0])
    return float(np.interp(level, f_ab[k - 1:k + 1], D_p[k - 1:k + 1]))


def main(outdir: Path = RESULTS, quick: bool = False, only: str | None = None, stored_only: bool = False) -> dict:
    """The study (``quick``: one cutting scene on the demo mesh with local erosion, a minute, for a check of the
    machinery and the book's fallback)."""
    outdir = Path(outdir)
    t0 = time.perf_counter()
    plan = planned()
    if quick:
        plan = {"cone30_mu0.5_demo": replace(scene(cone(30.0), 0.5, "demo"), erosion=Erosion(length=0.0))}
    if only is not None:
        if only not in plan:
            raise ValueError(f"--only: unknown run {only!r}; planned runs: {', '.join(plan)}")
        run_or_load(outdir, only, plan[only], study=STUDY)
        return {}
    if stored_only:
        plan = {n: sc for n, sc in plan.items() if (outdir / STUDY / n / "forces.csv").exists()}
    rows = {name: analyse(name, sc, run_or_load(outdir, name, sc, partial=stored_only, study=STUDY))
            for name, sc in plan.items()}
    mesh = [rows[f"cone30_mu0.5_{m}"] for m in MESH_STUDY if f"cone30_mu0.5_{m}" in rows]
    mesh = [r for r in mesh if r["finished"]]
    finest = mesh[-1]["removed_per_slide_um2"] if mesh else np.nan
    convergence = [{"mesh": r["mesh"], "elements": r["elements"], "wall_time_s": r["wall_time_s"],
                    "removed_per_slide_um2": r["removed_per_slide_um2"], "eroded": r["eroded"],
                    "removal_events_um": r["removal_events_um"],
                    "deviation_from_finest": r["removed_per_slide_um2"] / finest - 1.0 if finest else np.nan}
                   for r in mesh]
    transitions = {}
    for mu in FRICTIONS:
        points = [r for r in rows.values() if r["mu"] == mu and r["mesh"] == MAP_MESH and r["finished"]]
        if points:
            transitions[f"mu{mu:g}"] = crossing(np.array([r["D_p"] for r in points]),
                                                np.array([r["removal_f_ab"] for r in points]))
    results = {"date": time.strftime("%Y-%m-%d %H:%M"), "length_mm": LENGTH, "map_mesh": MAP_MESH,
               "runs": rows, "mesh_convergence": convergence, "transition_D_p": transitions,
               "hokkirigawa_kato_bands": PENETRATION_BANDS, "wall_time_s": time.perf_counter() - t0}
    stem = f"{STUDY}_quick" if quick else STUDY                   # a quick check never overwrites the study
    with CurveWriter(outdir / f"{stem}.csv", COLUMNS) as w:
        for row in rows.values():
            w.write(**{k: row[k] for k in COLUMNS})
    write_json(outdir / f"{stem}.json", results)
    plot(results, outdir / f"{stem}.png")
    return results


def plot(results: dict, path: Path) -> None:
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    for (lo, hi), label in zip(results["hokkirigawa_kato_bands"], ("wedge", "cutting"), strict=True):
        ax.axvspan(lo, hi, color="0.9" if label == "wedge" else "0.8", zorder=0)
        ax.text(0.5 * (lo + hi), 0.98, label, ha="center", va="top", transform=ax.get_xaxis_transform())
    for tip, marker in (("sphere", "o"), ("cone", "^")):
        for mu, color in zip(FRICTIONS, ("C0", "C3"), strict=True):
            pts = sorted((r["D_p"], r["removal_f_ab"]) for r in results["runs"].values()
                         if r["tip"] == tip and r["mu"] == mu and r["mesh"] == results["map_mesh"])
            if pts:
                ax.plot(*zip(*pts, strict=True), marker=marker, color=color, label=f"{tip}, μ = {mu:g}")
    ax.set(xlabel="degree of penetration D_p = d/a", ylabel="removal f_ab = removed/groove (rates)",
           title="Wear-mode map (Hokkirigawa–Kato bands shaded)")
    ax.legend(fontsize=8)
    conv = results["mesh_convergence"]
    if conv:
        bx.plot([c["elements"] for c in conv], [c["removed_per_slide_um2"] for c in conv], "o-")
        for c in conv:
            bx.annotate(f"{c['mesh']}, {c['wall_time_s']:.0f} s", (c["elements"], c["removed_per_slide_um2"]),
                        fontsize=8)
        bx.set(xscale="log", xlabel="elements", ylabel="removed volume per µm of slide, µm²",
               title="Mesh convergence (cone 30°, μ = 0.5)")
    save_figure(fig, path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one cutting scene on the demo mesh")
    parser.add_argument("--only", help="compute one planned run")
    parser.add_argument("--stored-only", action="store_true", help="analyse the runs stored so far")
    parser.add_argument("--outdir", type=Path, default=RESULTS)
    args = parser.parse_args()
    out = main(args.outdir, args.quick, args.only, args.stored_only)
    if out:
        print({k: out[k] for k in ("mesh_convergence", "transition_D_p")})
