"""Benchmark: small against finite strain in long scratches, the steady state, the volume budget, Table 8.4 again.

Parts (every run is kept in ``<outdir>/scratch_steady/<name>/`` — ``forces.csv`` with the per-increment volume
budget, ``summary.json``, ``u.npy`` and ``scene.txt`` — and reused by later calls with the same scene, so an
interrupted benchmark resumes, and runs can be computed ahead in another process with ``--only NAME``):

1. **small vs finite strain** on the seed's scene (sphere R = 50 µm, d = 2 µm, μ = 0.1) slid 200 µm along a
   300 µm block, "demo" mesh: runtime, forces, A_g, A_s, f_ab, the budget at the end, and how F_N and the groove
   section evolve along the slide (plateau onset, steady rates of every budget term per µm of slide);
2. **the default mesh** (the seed's block, 100 µm slide): small strain with full integration (the seed's formulation)
   against finite strain with F-bar (the scene's default);
3. **what the rise of F_N comes from**: the same scene with traction-free ends instead of the seed's fixed ones,
   with B-bar hexahedra (no volumetric locking), with perfect plasticity (H = 0, no hardening), and at finite strain
   with F-bar hexahedra (finite strain without locking);
4. **depth sweeps** at finite strain, with full integration (d/R = 0.02, 0.04) and with F-bar (d/R = 0.02, 0.04,
   0.08, 0.1; the grains below are two of its points): apparent friction F_T/F_N against the ploughing model of
   Bowden & Tabor / Goddard & Wilman for a sphere, μ_app = μ + (2/π) [(R/a)² asin(a/R) − √((R/a)² − 1)], a the
   contact radius (here √(2Rd − d²), the geometric footprint of a tip that ploughs without pile-up);
5. **grains** of Sec. 8.4 at the seed's f_N = 2 N (finite strain, F-bar, D = 100 and 200 µm; and with full
   integration for comparison): A_g and f_ab from the steady rates and from the mid-length section after
   unloading, and Table 8.4 recomputed from them beside the printed table and the seed's own inputs, with the
   removal study (f_ab if material above a plastic strain ε_c were removed).

``quick=True`` runs parts 1 and 3 on 100 µm slides of a 200 µm block (the seed's block) and skips 2, 4 and 5.
Writes ``scratch_steady.json``, ``scratch_steady.csv`` and ``scratch_steady.png``.

    python benchmarks/bench_scratch_steady.py [--quick] [--only NAME] [--partial] [--stored-only] [--outdir DIR]
"""

from __future__ import annotations

import argparse
import math
import re
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, save_figure
from bench_scratch import FORCE_TOLERANCE, SEED_FORCE, SEED_GRAINS
from bench_scratch_speed import wake_readings

from abrakit.fem import Kinematics
from abrakit.io import CurveWriter, read_curve, read_json, write_json
from abrakit.scratch import SphericalIndenter
from abrakit.scratch.budget import SteadyRates, plateau_onset, removal_by_plastic_strain, steady_rates
from abrakit.scratch.readouts import GrooveAlong, groove_along
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import SEED_FORMULATION, ScratchScene, build_specimen
from abrakit.wear import GRAIN_100UM, GRAIN_200UM, Grain, astm_g65_table

LONG = {"slide": 0.2, "size": (0.1, 0.015, 0.3)}
SEED_BLOCK = {"slide": 0.1, "size": (0.1, 0.015, 0.2)}
COLUMNS = ("name", "kinematics", "end_faces", "R_um", "d_um", "slide_um", "elements", "dofs", "wall_time_s",
           "F_N", "F_T", "apparent_friction", "F_N_plateau_from_um", "A_g_um2", "A_s_um2", "f_ab",
           "rate_groove_um2", "rate_shoulders_um2", "rate_prow_um2", "rate_volume_change_um2", "f_ab_rates",
           "D_p", "V_groove_um3", "V_shoulders_um3", "V_prow_um3", "V_sink_um3", "V_faces_um3", "V_volume_change_um3",
           "V_residual_um3", "finished", "slide_reached_um")


def ploughing_friction(mu: float, R: float, d: float) -> float:
    """Apparent friction of a sphere ploughing a plastic surface (Bowden & Tabor 1950; Goddard & Wilman 1962):
    μ + (2/π)[(R/a)² asin(a/R) − √((R/a)² − 1)], the adhesive part plus the ratio of the groove's frontal
    projected area to the load-bearing (half-circle) area, with a = √(2Rd − d²)."""
    a = math.sqrt(2 * R * d - d * d)
    k = R / a
    return mu + (2 / math.pi) * (k * k * math.asin(1 / k) - math.sqrt(k * k - 1))


def run_or_load(outdir: Path, name: str, scene: ScratchScene, partial: bool = False,
                study: str = "scratch_steady") -> Path:
    """Run ``scene`` into ``outdir/<study>/name`` unless a finished run of the same scene is there
    (``partial``: also accept the increments an unfinished run has written so far)."""
    folder = outdir / study / name
    marker = folder / "scene.txt"
    same = marker.exists() and same_physics(marker.read_text(), scene)
    if marker.exists() and not same and (folder / "u.npy").exists():
        raise RuntimeError(f"the stored run {folder} was computed for another scene ({marker.read_text()}); "
                           "delete the folder to recompute it: a finished run is never overwritten")
    if same and (
            (folder / "u.npy").exists() or (partial and (folder / "forces.csv").exists())):
        print(f"[{study}] {name}: stored", flush=True)
        return folder
    print(f"[{study}] {name}: {scene.kinematics} strain, d = {scene.depth * 1e3:g} um, R = "
          f"{scene.indenter.radius * 1e3:g} um, slide {scene.slide * 1e3:g} um", flush=True)
    folder.mkdir(parents=True, exist_ok=True)
    marker.write_text(repr(scene))                      # first: the increments written so far belong to it
    result = run_scratch(scene, output=folder, vtu_every=0, resume=True)     # an interrupted run goes on
    np.save(folder / "u.npy", result.u)
    np.savez(folder / "state.npz", **{k: result.state[k] for k in ("alpha_p", "J", "ductile", "eroded")
                                      if k in result.state})
    print(f"[{study}]   {result.wall_time:.0f} s, F_N = {result.mean_normal_force:.3f} N", flush=True)
    return folder


def same_physics(stored: str, scene: ScratchScene) -> bool:
    """Whether a stored run's scene (its ``repr``) is ``scene`` up to the increment control of
    :data:`CONTROL_FIELDS`."""
    def physics(text: str) -> str:
        return re.sub(rf"\b({'|'.join(CONTROL_FIELDS)})=\d+, ", "", text)
    return physics(stored) == physics(repr(scene))


def analyse(name: str, scene: ScratchScene, folder: Path) -> dict:
    """Everything the tables and plots need from one stored run. An unfinished run (no ``summary.json`` yet, e.g.
    still computing or interrupted) is analysed from the increments in its ``forces.csv``: forces, budget and rates
    up to where it got, no grooves (``"finished": False``)."""
    finished = (folder / "summary.json").exists() and (folder / "u.npy").exists()
    curves = read_curve(folder / "forces.csv")
    sliding = curves["phase"] == 1
    slide_um = curves["slide"][sliding] * 1e3
    # a finished run whose force curve was cut short (its increments lost) keeps its end state; no rates then
    whole_curve = sliding.any() and slide_um.max() >= 0.99 * scene.slide * 1e3
    enough = np.count_nonzero(sliding) >= 3                 # an unfinished run may still be indenting
    rates = steady_rates(curves) if enough and (whole_curve or not finished) else SteadyRates(*[np.nan] * 7)
    if finished:
        summary = read_json(folder / "summary.json")
        z = scene.path.z_start + np.linspace(0.0, scene.slide, 41)
        along = groove_along(build_specimen(scene), np.load(folder / "u.npy"), scene, z)
        g = summary["groove_unloaded"] or {}
        budget = summary["volume_budget_um3"]
    else:
        nan = np.full(41, np.nan)
        summary = {"elements": np.nan, "dofs": np.nan, "wall_time_s": float(curves["wall_time"][-1])}
        along = GrooveAlong(scene.path.z_start + np.linspace(0.0, scene.slide, 41), nan, nan, nan)
        g = {}
        budget = {k: float(curves[f"V_{k}"][-1]) * 1e9 for k in ("groove", "shoulders", "prow", "sink", "faces",
                                                                  "volume_change", "residual")}
    F_N, F_T = curves["normal_force"][sliding], curves["tangential_force"][sliding]
    last = slide_um >= 0.5 * slide_um.max()
    mean_F_N = float(F_N[last].mean()) if whole_curve or not finished else summary["mean_normal_force_N"]
    mean_F_T = float(F_T[last].mean()) if whole_curve or not finished else summary["mean_tangential_force_N"]
    row = {
        "name": name, "kinematics": scene.kinematics, "end_faces": scene.end_faces,
        "R_um": scene.indenter.radius * 1e3, "d_um": scene.depth * 1e3, "slide_um": scene.slide * 1e3,
        "elements": summary["elements"], "dofs": summary["dofs"], "wall_time_s": summary["wall_time_s"],
        "F_N": mean_F_N, "F_T": mean_F_T, "apparent_friction": mean_F_T / mean_F_N,
        "F_N_plateau_from_um": plateau_onset(slide_um, F_N) if whole_curve else np.nan,
        "A_g_um2": g.get("A_g_um2", np.nan), "A_s_um2": g.get("A_s_um2", np.nan), "f_ab": g.get("f_ab", np.nan),
        "rate_groove_um2": rates.groove * 1e6, "rate_shoulders_um2": rates.shoulders * 1e6,
        "rate_prow_um2": rates.prow * 1e6, "rate_volume_change_um2": rates.volume_change * 1e6,
        "f_ab_rates": rates.degree_of_wear, "D_p": g.get("D_p", np.nan),
        **{f"V_{k}_um3": budget[k] for k in ("groove", "shoulders", "prow", "sink", "faces", "volume_change",
                                             "residual")},
    }
    removal = (removal_study(scene, folder, rates) if finished and whole_curve and (folder / "state.npz").exists()
               else None)
    row["finished"] = finished
    row["slide_reached_um"] = float(slide_um.max())
    return {"row": row, "removal": removal,
            "curves": {"slide_um": slide_um.tolist(), "F_N": F_N.tolist(), "F_T": F_T.tolist(),
                                   **{k: (curves[k][sliding] * 1e9).tolist() for k in
                                      ("V_groove", "V_shoulders", "V_prow", "V_sink", "V_volume_change")}},
            "along": {"z_um": ((along.z - scene.path.z_start) * 1e3).tolist(),
                      "A_g_um2": along.groove_area.tolist(), "A_s_um2": along.shoulder_area.tolist(),
                      "f_ab": along.degree_of_wear.tolist()}}


REMOVAL_THRESHOLDS = (0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0)


def removal_study(scene: ScratchScene, folder: Path, rates) -> dict:
    """f_ab if shoulder material with accumulated plastic strain above ε_c were removed (a study, not a model):
    1 − (shoulders − removed)/groove with the steady rates, the removed volume per unit length taken over the
    steady half of the wake (up to two footprint radii before the end)."""
    state = np.load(folder / "state.npz")
    kin = Kinematics.from_basis(build_specimen(scene).basis)
    z_lo = scene.path.z_start + 0.5 * scene.slide
    z_hi = scene.path.z_end - 2.0 * scene.footprint
    J = state["J"] if scene.kinematics == "finite" else None
    r = removal_by_plastic_strain(kin, np.load(folder / "u.npy"), state["alpha_p"], J, REMOVAL_THRESHOLDS,
                                  (z_lo, z_hi))
    f_ab = 1.0 - (rates.shoulders - r.removed) / rates.groove
    return {"eps_c": r.thresholds.tolist(), "removed_um2": (r.removed * 1e6).tolist(), "f_ab": f_ab.tolist()}


def critical_strain_for(removal: dict, f_ab: float) -> float:
    """The ε_c at which the removal study reaches ``f_ab`` (f_ab falls as ε_c grows); NaN outside its range."""
    eps, f = np.array(removal["eps_c"]), np.array(removal["f_ab"])
    if not f.min() <= f_ab <= f.max():
        return float("nan")
    return float(np.interp(f_ab, f[::-1], eps[::-1]))


def planned(quick: bool) -> dict[str, ScratchScene]:
    """The formulation study (parts 1 and 2) and, unless ``quick``, the depth sweeps and grains (parts 3 and 4)."""
    geometry = SEED_BLOCK if quick else LONG
    base = ScratchScene(mesh="demo", **SEED_FORMULATION, **geometry)
    plan = {"small": base, "finite": base.with_(kinematics="finite"),
            "small_free_ends": base.with_(end_faces="free"), "small_bbar": base.with_(bbar=True),
            "small_perfect_plastic": base.with_(hardening=0.0),
            "finite_fbar": base.with_(kinematics="finite", bbar=True)}
    if quick:
        return plan
    full, fbar = base.with_(kinematics="finite"), base.with_(kinematics="finite", bbar=True)
    plan["finite_d1um"] = full.with_(depth=0.001)                    # d/R = 0.02, full integration
    plan.update({name: fbar.with_(indenter=SphericalIndenter(R), depth=d) for name, (R, d) in GRAINS.items()})
    plan["fbar_d3.25um"] = fbar.with_(depth=0.00325)                # brackets 2 N with grain_100um (R = 50 µm)
    plan["fbar_R100_d1.75um"] = fbar.with_(indenter=SphericalIndenter(0.1), depth=0.00175)   # and with grain_200um
    plan["fbar_d5um"] = fbar.with_(depth=0.005, **SEED_BLOCK)        # d/R = 0.1, the seed's 100 um slide (time)
    seed_scene = ScratchScene(mesh="default", **SEED_FORMULATION, **SEED_BLOCK)   # the seed's scene and mesh
    plan["default_small"] = seed_scene
    plan["default_fbar"] = seed_scene.with_(kinematics="finite", bbar=True)
    plan["grain_200um_fullint"] = full.with_(indenter=SphericalIndenter(0.1), depth=0.001)
    plan.update({f"{name}_damage": plan[name].with_(damage=True) for name in DAMAGE_RUNS})
    plan.update({f"{name}_{level}": plan[name].with_(mesh=level) for name in DAMAGE_RUNS for level in GRAIN_LEVELS})
    plan.update({name: plan[base].with_(slide=slide, size=(0.1, 0.015, slide + 0.1))
                 for name, (base, slide) in SLIDE_STUDY.items()})
    plan.update({name: plan[source].with_(**changes) for name, (source, changes) in STEADY_VARIANTS.items()})
    return plan


GRAINS = {"grain_100um": (0.05, 0.004), "grain_200um": (0.1, 0.002)}
"""First guesses for the grains of Sec. 8.4 (finite strain, F-bar): (R, d) in mm. The seed does not state its
depths, only f_N = 2 N. The d = 2 µm, R = 50 µm F-bar run carries F_N = 1.03 N; a fully plastic contact carries
F = p_m π a²/2 with a² ≈ 2 R d, so 2 N needs R d ≈ 200 µm², d = 4 µm for R = 50 µm and d = 2 µm for R = 100 µm."""

DAMAGE_RUNS = {"grain_100um": 100, "fbar_R100_d1.75um": 200}
"""The grains' F-bar runs nearest 2 N (R = 50 µm, d = 4 µm, F_N 2.5 N; R = 100 µm, d = 1.75 µm, F_N 1.9 N) run
again with Model II on top (Table 8.2, ``damage_rate="work"``): removal in the scene's own physics, with and
without, on the same scene (run name + "_damage"), keyed by the grain size D in µm."""

GRAIN_LEVELS = ("coarse",)
"""Mesh levels on which the grains of :data:`DAMAGE_RUNS` are scratched again (run name + "_" + level) beside their
"demo" runs: the spread of F_N, A_g and f_ab (rates and sections) over the mesh levels (:func:`mesh_spread`)."""

SLIDE_STUDY = {"fbar_R100_d1.75um_coarse_400um": ("fbar_R100_d1.75um_coarse", 0.4),
               "grain_100um_coarse_400um": ("grain_100um_coarse", 0.4),
               "finite_fbar_400um": ("finite_fbar", 0.4),
               "fbar_R100_d1.75um_400um": ("fbar_R100_d1.75um", 0.4),
               "grain_100um_400um": ("grain_100um", 0.4)}
"""Both grains' runs (coarse and demo meshes) and the seed's scene (R = 50 µm, d = 2 µm, demo mesh) again with a
400 µm slide on a 500 µm block: does their degree of wear settle (:func:`slide_windows`)?"""

STEADY_VARIANTS = {"finite_fbar_coarse_400um": ("finite_fbar_400um", {"mesh": "coarse"}),
                   "fbar_R100_d1.85um_coarse_400um": ("fbar_R100_d1.75um_coarse_400um", {"depth": 0.00185})}
"""400 µm slides that vary one of :data:`SLIDE_STUDY`'s: the seed's scene on the coarse mesh (so that both of the
R = 50 µm grain's depths are read on one level), and the R = 100 µm grain 0.1 µm deeper, F_N ∝ d giving 2.05 N
(so that a pair of runs brackets 2 N)."""

STEADY_SERIES = {"grain_100um": ("finite_fbar_coarse_400um", "grain_100um_coarse_400um"),
                 "grain_200um": ("fbar_R100_d1.75um_coarse_400um", "fbar_R100_d1.85um_coarse_400um")}
"""The grains' steady state: the coarse mesh's 400 µm slides of :data:`SLIDE_STUDY` and :data:`STEADY_VARIANTS`
read over the second half of their slide (200–400 µm: :func:`slide_windows` shows the d ≈ 2 µm runs levelled from
about 250 µm on, the d = 4 µm run still falling slowly there, so its reading is an upper estimate), interpolated
to 2 N as in :data:`GRAIN_SERIES` (:func:`at_two_newtons`): the R = 50 µm grain between d = 2 µm (1.1 N) and
d = 4 µm (2.6 N), the R = 100 µm grain between d = 1.75 and 1.85 µm. :data:`STEADY_LEVEL_PAIRS` gives the mesh
part of their uncertainty."""

STEADY_LEVEL_PAIRS = {"R50_d2um": ("finite_fbar_400um", "finite_fbar_coarse_400um"),
                      "R50_d4um": ("grain_100um_400um", "grain_100um_coarse_400um"),
                      "R100_d1.75um": ("fbar_R100_d1.75um_400um", "fbar_R100_d1.75um_coarse_400um")}
"""One scene's 400 µm slide on the demo and the coarse mesh: the spread of its steady readings over the two levels
(:func:`steady_spread`)."""

SLIDE_WINDOW = 0.05
"""Width of the slide windows of :func:`slide_windows`, mm."""

CONTROL_FIELDS = ("indent_steps", "unload_steps")
"""Fields of a scene that set only the increment control of its indentation and unloading, not its physics: a
stored run that differs from the planned scene in these alone is reused (the runs before issue 39 indented in 20
increments, today's scenes in 5; ``test_the_faster_increment_control_changes_no_groove_beyond_its_tolerances``
pins the grooves of both within 2 %)."""

GRAIN_SERIES = {"grain_100um": ("finite_fbar", "fbar_d3.25um", "grain_100um"),
                "grain_200um": ("fbar_R100_d1.75um", "grain_200um")}
"""F-bar runs of each grain's radius at several depths: the grain at 2 N is interpolated between the two that
bracket it (:func:`at_two_newtons`)."""

SWEEPS = {"finite strain, full integration": ("finite_d1um", "finite"),
          "finite strain, F-bar": ("grain_200um", "fbar_R100_d1.75um", "finite_fbar", "fbar_d3.25um", "grain_100um",
                                   "fbar_d5um")}
"""The d/R sweeps of the apparent friction (runs named in the plan, with their depths and radii)."""

FULLINT_GRAINS = {"grain_100um_fullint": "finite", "grain_200um_fullint": "grain_200um_fullint"}
"""The grains with full integration (computed before F-bar existed: they lock into a growing prow)."""


def corrected_grain(scene: ScratchScene, force: float) -> ScratchScene:
    """The grain scratched again at the depth that scales its force to 2 N (F ∝ d at a fixed radius), rounded to
    0.25 µm."""
    return scene.with_(depth=0.25 * round(4 * scene.depth * 1e3 * SEED_FORCE / force) * 1e-3)


def at_seed_force(outdir: Path, name: str, scene: ScratchScene, entry: dict, partial: bool,
                  stored_only: bool = False) -> dict:
    """The grain's analysis at 2 N: its own run, or one secant step (F ∝ d) when its force misses 2 N
    (``stored_only``: only if that run is already stored; otherwise the grain is kept at its own force)."""
    force = entry["row"]["F_N"]
    if abs(force / SEED_FORCE - 1.0) <= FORCE_TOLERANCE or not entry["row"]["finished"]:
        return entry
    corrected = corrected_grain(scene, force)
    folder = outdir / "scratch_steady" / f"{name}_corrected"
    if stored_only and not (folder / "u.npy").exists():
        print(f"[steady] {name}: F_N = {force:.2f} N misses 2 N; the corrected run (d = {corrected.depth * 1e3:g} "
              "um) is not stored, the grain is kept at its own force", flush=True)
        return entry
    return analyse(name, corrected, run_or_load(outdir, f"{name}_corrected", corrected, partial))


GRAIN_KEYS = ("d_um", "A_g_um2", "A_s_um2", "f_ab", "rate_groove_um2", "f_ab_rates", "D_p")


def slid_half(row: dict) -> bool:
    """Whether a run (finished or not) has covered at least half of its slide: enough for a steady mean."""
    return row["slide_reached_um"] >= 0.5 * row["slide_um"]


def at_two_newtons(entries: dict[str, dict]) -> dict:
    """A grain at F_N = 2 N from finished runs of one radius at several depths: every quantity of
    :data:`GRAIN_KEYS` interpolated linearly in F_N between the two runs that bracket 2 N (the run nearest to 2 N
    when none bracket it). Returns the row and the removal study of the run nearest 2 N."""
    done = sorted((e for e in entries.values() if e["row"]["finished"]), key=lambda e: e["row"]["F_N"])
    if not done:
        return {"row": {"F_N": np.nan, **{k: np.nan for k in GRAIN_KEYS}, "runs": []}, "removal": None}
    forces = np.array([e["row"]["F_N"] for e in done])
    nearest = done[int(np.argmin(np.abs(forces - SEED_FORCE)))]
    k = int(np.searchsorted(forces, SEED_FORCE))
    if 0 < k < len(done):
        lo, hi = done[k - 1], done[k]
        w = (SEED_FORCE - lo["row"]["F_N"]) / (hi["row"]["F_N"] - lo["row"]["F_N"])
        row = {q: (1 - w) * lo["row"][q] + w * hi["row"][q] for q in GRAIN_KEYS}
        row.update(F_N=SEED_FORCE, runs=[lo["row"]["name"], hi["row"]["name"]], weight=w)
    else:
        row = {q: nearest["row"][q] for q in GRAIN_KEYS}
        row.update(F_N=nearest["row"]["F_N"], runs=[nearest["row"]["name"]], weight=0.0)
    return {"row": row, "removal": nearest["removal"], "removal_run": nearest["row"]["name"]}


def main(outdir: Path = RESULTS, quick: bool = False, only: str | None = None, partial: bool = False,
         stored_only: bool = False) -> dict:
    outdir = Path(outdir)
    t0 = time.perf_counter()
    plan = planned(quick)
    if only is not None:
        if only not in plan:
            raise ValueError(f"--only: unknown run {only!r}; planned runs: {', '.join(plan)}")
        run_or_load(outdir, only, plan[only])
        return {}
    if stored_only:                 # a run still being computed (no u.npy yet) is left to its own process
        stored = "forces.csv" if partial else "u.npy"
        plan = {n: sc for n, sc in plan.items() if (outdir / "scratch_steady" / n / stored).exists()}
    runs = {name: analyse(name, scene, run_or_load(outdir, name, scene, partial)) for name, scene in plan.items()}
    results = {"mode": "quick" if quick else "full", "date": time.strftime("%Y-%m-%d %H:%M"), "runs": runs}
    if not quick:
        results["ploughing"] = {
            label: [{"name": n, "d_over_R": runs[n]["row"]["d_um"] / runs[n]["row"]["R_um"],
                     "measured": runs[n]["row"]["apparent_friction"],
                     "model": ploughing_friction(0.1, runs[n]["row"]["R_um"], runs[n]["row"]["d_um"])}
                    for n in names if n in runs and slid_half(runs[n]["row"])]
            for label, names in SWEEPS.items()}
        grains = {name: at_two_newtons({n: runs[n] for n in series if n in runs})
                  for name, series in GRAIN_SERIES.items()}
        fullint = {name: at_seed_force(outdir, name, plan[source], runs[source], partial, stored_only)
                   for name, source in FULLINT_GRAINS.items() if source in runs}
        runs.update({f"{n}_at_2N": e for n, e in fullint.items() if e is not runs.get(n)})
        results["grains_at_2N"] = {n: e["row"] for n, e in grains.items()}
        steady = {name: at_two_newtons({n: runs[n] for n in series if n in runs})
                  for name, series in STEADY_SERIES.items()}
        results["grains_steady"] = {n: e["row"] for n, e in steady.items()}
        for key, pair in (("table_8_4", grains), ("table_8_4_fullint", fullint), ("table_8_4_steady", steady)):
            if len(pair) == 2:
                results[key] = table_8_4(*(entry["row"] for entry in pair.values()))
        results["removal"] = {
            D: {"seed_f_ab": SEED_GRAINS[D]["f_ab"], "study": grains[name]["removal"],
                "eps_c_for_seed_f_ab": critical_strain_for(grains[name]["removal"], SEED_GRAINS[D]["f_ab"])
                if grains[name]["removal"] else None}
            for D, name in ((100, "grain_100um"), (200, "grain_200um")) if name in grains}
        results["removal_model"] = removal_model(outdir, runs)
        results["mesh_spread"] = mesh_spread(outdir, plan, runs)
        results["slide_windows"] = slide_windows(outdir, plan, runs)
        results["steady_spread"] = steady_spread(results["slide_windows"])
    results["wall_time_s"] = time.perf_counter() - t0
    with CurveWriter(outdir / "scratch_steady.csv", COLUMNS) as w:
        for entry in runs.values():
            w.write(**entry["row"])
    write_json(outdir / "scratch_steady.json", results)
    plot(results, outdir / "scratch_steady.png")
    return results


REMOVAL_KEYS = ("F_N", "A_g_um2", "A_s_um2", "f_ab", "f_ab_rates", "wall_time_s")


def removal_model(outdir: Path, runs: dict) -> dict:
    """Per grain (D in µm), the run with Model II on top beside the same scene without it: forces, groove, f_ab
    (section and steady rates), the removed volume (elements at the damage cap) and the removed elements."""
    out = {}
    for name, D in DAMAGE_RUNS.items():
        damaged = f"{name}_damage"
        if damaged not in runs or name not in runs or not runs[damaged]["row"]["finished"]:
            continue
        summary = read_json(outdir / "scratch_steady" / damaged / "summary.json")
        out[str(D)] = {"runs": [name, damaged],
                       "without": {k: runs[name]["row"][k] for k in REMOVAL_KEYS},
                       "with": {k: runs[damaged]["row"][k] for k in REMOVAL_KEYS},
                       "removed_um3": summary["volume_budget_um3"]["removed"],
                       "removed_elements": summary["removed_elements"]}
    return out


SPREAD_KEYS = ("dofs", "wall_time_s", "F_N", "A_g_um2", "f_ab", "f_ab_rates")


def mesh_spread(outdir: Path, plan: dict[str, ScratchScene], runs: dict) -> dict:
    """Per grain of :data:`DAMAGE_RUNS` (D in µm), its finished runs on the "demo" mesh and on
    :data:`GRAIN_LEVELS`: forces, groove area, f_ab of the mid-length section and of the steady rates (second half
    of the slide, and last quarter: has the slide reached the steady state?), the mean and range of nine wake
    sections beyond mid-slide (:func:`bench_scratch_speed.wake_sections`), and the spread over the levels (largest
    minus smallest; relative for F_N and A_g)."""
    out = {}
    for name, D in DAMAGE_RUNS.items():
        levels = {}
        for level, run in (("demo", name), *((lv, f"{name}_{lv}") for lv in GRAIN_LEVELS)):
            if run not in runs or not runs[run]["row"]["finished"]:
                continue
            folder = outdir / "scratch_steady" / run
            scene = plan[run]
            levels[level] = {"run": run, **{k: runs[run]["row"][k] for k in SPREAD_KEYS},
                             "f_ab_rates_last_quarter":
                                 steady_rates(read_curve(folder / "forces.csv"), 0.75 * scene.slide).degree_of_wear,
                             **wake_readings(scene, folder)}
        if not levels:
            continue
        values = {k: np.array([lv[k] for lv in levels.values()], dtype=float)
                  for k in ("F_N", "A_g_um2", "f_ab_rates", "f_ab_sections")}
        out[str(D)] = {"levels": levels,
                       "spread": {"F_N_relative": float(np.ptp(values["F_N"]) / np.mean(values["F_N"])),
                                  "A_g_relative": float(np.ptp(values["A_g_um2"]) / np.mean(values["A_g_um2"])),
                                  "f_ab_rates": float(np.ptp(values["f_ab_rates"])),
                                  "f_ab_sections": float(np.ptp(values["f_ab_sections"]))}}
    return out


def slide_windows(outdir: Path, plan: dict[str, ScratchScene], runs: dict) -> dict:
    """For the runs of :data:`SLIDE_STUDY`, the runs they extend and :data:`STEADY_VARIANTS`: f_ab from the
    budget's rates over consecutive windows of :data:`SLIDE_WINDOW` along the slide (the first from one window
    after the start: the indentation's transient), and the mean and range of nine wake sections beyond mid-slide:
    the slide a degree of wear needs to settle."""
    out = {}
    extended = [run for name, (base, _) in SLIDE_STUDY.items() for run in (base, name)]
    for run in dict.fromkeys(extended + list(STEADY_VARIANTS)):
        if run not in runs or not runs[run]["row"]["finished"]:
            continue
        folder = outdir / "scratch_steady" / run
        curves, scene = read_curve(folder / "forces.csv"), plan[run]
        starts = np.arange(SLIDE_WINDOW, scene.slide - 0.5 * SLIDE_WINDOW, SLIDE_WINDOW)
        out[run] = {"slide_um": scene.slide * 1e3,
                    "windows_um": [[a * 1e3, (a + SLIDE_WINDOW) * 1e3] for a in starts],
                    "f_ab_rates": [steady_rates(curves, a, a + SLIDE_WINDOW).degree_of_wear for a in starts],
                    "f_ab_rates_second_half": runs[run]["row"]["f_ab_rates"],
                    **wake_readings(scene, folder)}
    return out


def steady_spread(windows: dict) -> dict:
    """Per scene of :data:`STEADY_LEVEL_PAIRS` slid 400 µm on both levels: its steady readings (f_ab from the rates
    of the second half, the wake sections' mean) on the demo and the coarse mesh and their difference."""
    out = {}
    for scene, runs in STEADY_LEVEL_PAIRS.items():
        if not all(run in windows for run in runs):
            continue
        levels = {level: {"run": run, "f_ab_rates": windows[run]["f_ab_rates_second_half"],
                          "f_ab_sections": windows[run]["f_ab_sections"]}
                  for level, run in zip(("demo", "coarse"), runs, strict=True)}
        out[scene] = {"levels": levels,
                      "spread": {key: abs(levels["coarse"][key] - levels["demo"][key])
                                 for key in ("f_ab_rates", "f_ab_sections")}}
    return out


def table_8_4(fine: dict, coarse: dict) -> dict:
    """Table 8.4 from the grains' steady rates (A_g = groove rate, f_ab from rates) and from their sections."""
    def grains(key_A, key_f):
        return (Grain(100e-6, fine[key_A] * 1e-12, max(fine[key_f], 0.0)),
                Grain(200e-6, coarse[key_A] * 1e-12, max(coarse[key_f], 0.0)))

    seed = astm_g65_table(fine=GRAIN_100UM, coarse=GRAIN_200UM)
    rates = astm_g65_table(*(), **dict(zip(("fine", "coarse"), grains("rate_groove_um2", "f_ab_rates"),
                                           strict=True)))
    section = astm_g65_table(**dict(zip(("fine", "coarse"), grains("A_g_um2", "f_ab"), strict=True)))
    return {"label": seed["label"], "theta_200um": seed["theta_coarse"].tolist(),
            "seed_printed": seed["seed"].tolist(), "from_seed_inputs": seed["ours"].tolist(),
            "from_steady_rates": rates["ours"].tolist(), "from_sections": section["ours"].tolist(),
            "grains": {"100um": {k: fine[k] for k in ("F_N", "runs", *GRAIN_KEYS) if k in fine},
                       "200um": {k: coarse[k] for k in ("F_N", "runs", *GRAIN_KEYS) if k in coarse},
                       "seed": SEED_GRAINS}}


def plot(results: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    runs = results["runs"]
    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))
    for name, colour in (("small", "C0"), ("finite", "C3"), ("small_free_ends", "C2"), ("small_bbar", "C4"),
                         ("finite_fbar", "k")):
        if name not in runs:
            continue
        c, a = runs[name]["curves"], runs[name]["along"]
        ax[0, 0].plot(c["slide_um"], c["F_N"], color=colour, label=f"{name}: F_N")
        ax[0, 0].plot(c["slide_um"], c["F_T"], color=colour, ls="--", label=f"{name}: F_T")
        ax[0, 1].plot(a["z_um"], a["f_ab"], color=colour, label=f"{name}: f_ab")
        ax[0, 1].plot(a["z_um"], np.array(a["A_s_um2"]) / np.array(a["A_g_um2"]), color=colour, ls=":",
                      label=f"{name}: A_s/A_g")
    ax[0, 0].set(xlabel="slide [um]", ylabel="force [N]", title="forces along the slide (plateau?)")
    ax[0, 1].set(xlabel="position of the section behind the start [um]", ylabel="[-]",
                 title="groove section along the wake (after unloading)")
    for a in ax[0, :2]:
        a.legend(fontsize=7)
    for k, name in enumerate(("small", "finite_fbar")):
        if name not in runs:
            continue
        c, a = runs[name]["curves"], ax[1, k]
        s = np.array(c["slide_um"])
        parts = [np.array(c["V_shoulders"]), np.array(c["V_prow"]), -np.array(c["V_volume_change"])]
        a.stackplot(s, *parts, labels=["shoulders", "prow", "volume lost (−∫(J−1)dV)"], alpha=0.7)
        a.plot(s, np.array(c["V_groove"]) + np.array(c["V_sink"]), "k-", lw=2, label="groove + sink")
        a.set(xlabel="slide [um]", ylabel="volume [um³]", title=f"volume budget, {name}")
        a.legend(fontsize=7, loc="upper left")
    a = ax[0, 2]
    if "ploughing" in results:
        for (label, points), style in zip(results["ploughing"].items(), ("C3o-", "ks-"), strict=False):
            p = sorted(points, key=lambda x: x["d_over_R"])
            a.plot([q["d_over_R"] for q in p], [q["measured"] for q in p], style, label=f"FE, {label}")
        x = np.linspace(0.01, 0.11, 50)
        a.plot(x, [ploughing_friction(0.1, 1.0, r) for r in x], "C0--", label="Bowden-Tabor / Goddard-Wilman")
        a.set(xlabel="d/R", ylabel="apparent friction F_T/F_N", title="apparent friction, sphere, mu = 0.1")
        a.legend(fontsize=8)
    a = ax[1, 2]
    if "table_8_4" in results:
        t = results["table_8_4"]
        th = np.array(t["theta_200um"])
        for key, style in (("seed_printed", "ko"), ("from_seed_inputs", "C0-"), ("from_steady_rates", "C3s--"),
                           ("from_sections", "C1^:")):
            a.plot(th, np.array(t[key]) * 1e7, style, label=key.replace("_", " "))
        a.set(xlabel="volume fraction of 200 um grains", ylabel="wear rate [1e-7 m3/s]", title="Table 8.4")
        a.legend(fontsize=8)
    fig.suptitle(f"abrakit scratch: small vs finite strain, steady state ({results['mode']}, {results['date']})")
    save_figure(fig, path, dpi=110)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the seed's 100 um slides; parts 1-2 only")
    parser.add_argument("--only", metavar="NAME", help="compute one planned run ahead (e.g. in a second process)")
    parser.add_argument("--partial", action="store_true",
                        help="analyse unfinished runs from the increments they have written so far")
    parser.add_argument("--stored-only", action="store_true",
                        help="analyse the stored runs only: start no computation (a missing run is left out)")
    parser.add_argument("--outdir", type=Path, default=RESULTS)
    args = parser.parse_args()
    main(args.outdir, quick=args.quick, only=args.only, partial=args.partial, stored_only=args.stored_only)
