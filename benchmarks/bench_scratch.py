"""Benchmark of the single scratch test (Ch. 8.2): speed against error, the seed's studies, Table 8.4 from our grooves.

Parts (each run writes its force curve to ``<outdir>/scratch_runs/<name>/forces.csv`` as it goes):

1. **speed against error** — the seed's scratch (sphere R = 50 µm, d = 2 µm) on 3–4 mesh levels and 2 penalty
   factors (c_N = 1 and 10 × E/h_y): groove area A_g, degree of wear f_ab and mean normal force against the run
   time; the finest level with the stiffer penalty is the reference;
2. **the default scene** (R = 50 µm, d = 2 µm, 100 µm slide, ``"default"`` mesh): wall time, and the cost against
   the sliding distance (cumulative wall time per increment) and against the element count (part 1);
3. **depth study** (Fig. 8.8): R = 50 µm, d = 1…5 µm, normal force curves and grooves;
4. **radius study** (Fig. 8.11, 8.12): sphere-tipped 60° cones, R = 25, 50, 100 µm at d = 3 µm;
5. **the wear example** (Sec. 8.4): grains D = 100 and 200 µm (R = 50, 100 µm) scratched at the seed's normal
   force f_N = 2 N — the depth giving 2 N is interpolated from the depth study (R = 50) and scaled by
   F ∝ R d (fully plastic contact, a² ≈ 2 R d) for R = 100; a grain whose force misses 2 N by more than 5 % is
   scratched once more at the depth corrected with F ∝ d — then Table 8.4 recomputed from our own A_g and
   f_ab with :func:`abrakit.wear.astm_g65_table`, beside the version from the seed's inputs.

All studies slide the seed's 100 µm, so the mid-length section lies in the steady part of the groove (with a
shorter slide it would still feel the crater of the indentation). ``quick=True`` uses the "demo", "coarse" and
"default" meshes with 60 µm slides for part 1 (the two coarser also with the 10× penalty), the "demo" mesh for
parts 3–5, and skips part 2; the full mode adds the "fine" level to part 1 and uses the "coarse" mesh for the
studies. Part 2 alone:
``python benchmarks/bench_scratch.py --default-scene`` (writes ``scratch_default.json``, merged into
``scratch.json`` by later runs). Writes ``scratch.csv`` (one row per run), ``scratch.json`` (everything, incl.
profiles and Table 8.4), ``scratch.png`` and ``scratch_table_8_4.csv``.

    python benchmarks/bench_scratch.py [--quick] [--default-scene] [--only NAME] [--outdir DIR]

Every run is kept in ``scratch_runs/<name>/run.json`` and reused by later calls with the same scene, so an
interrupted benchmark resumes where it stopped and runs can be computed ahead in a second process with ``--only``.
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, save_figure

from abrakit.io import CurveWriter, read_curve, read_json, write_json
from abrakit.scratch import ConicalIndenter, SphericalIndenter
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import SEED_FORMULATION
from abrakit.scratch.scene import ScratchScene as _Scene
from abrakit.wear import GRAIN_100UM, GRAIN_200UM, Grain, astm_g65_table


def ScratchScene(**kwargs) -> _Scene:  # noqa: N802 - the studies of this benchmark are the seed's formulation
    """The seed's small-strain, fully integrated scene (the studies of this benchmark reproduce the seed's
    formulation; ``bench_scratch_steady.py`` studies the corrected one)."""
    return _Scene(**(SEED_FORMULATION | kwargs))

SEED_GRAINS = {100: {"A_g_um2": 88.4, "f_ab": 0.37}, 200: {"A_g_um2": 60.0, "f_ab": 0.12}}
SEED_FORCE = 2.0
"""Normal force of both worked scratches of Sec. 8.4, N."""
FORCE_TOLERANCE = 0.05
"""A grain whose sliding normal force misses SEED_FORCE by more than this fraction is scratched again, deeper or
shallower in proportion (F ~ R d)."""

COLUMNS = ("name", "part", "R_um", "d_um", "slide_um", "tip", "mesh", "penalty", "elements", "dofs", "increments",
           "newton_iterations", "cutbacks", "wall_time_s", "mean_normal_force_N", "mean_tangential_force_N",
           "A_g_loaded_um2", "A_s_loaded_um2", "f_ab_loaded", "A_g_um2", "A_s_um2", "w_um", "f_ab", "D_p",
           "regime", "removed_area_um2")


def _row(name, part, scene, summary):
    loaded, unloaded = summary["groove_loaded"] or {}, summary["groove_unloaded"] or {}
    return {
        "name": name, "part": part, "R_um": summary["R_um"], "d_um": summary["d_um"], "slide_um": summary["slide_um"],
        "tip": "cone60" if isinstance(scene.indenter, ConicalIndenter) else "sphere",
        "mesh": scene.mesh if isinstance(scene.mesh, str) else "custom", "penalty": scene.penalty,
        **{k: summary[k] for k in ("elements", "dofs", "increments", "newton_iterations", "cutbacks",
                                   "wall_time_s", "mean_normal_force_N", "mean_tangential_force_N")},
        "A_g_loaded_um2": loaded.get("A_g_um2", np.nan), "A_s_loaded_um2": loaded.get("A_s_um2", np.nan),
        "f_ab_loaded": loaded.get("f_ab", np.nan), "A_g_um2": unloaded.get("A_g_um2", np.nan),
        "A_s_um2": unloaded.get("A_s_um2", np.nan), "w_um": unloaded.get("w_um", np.nan),
        "f_ab": unloaded.get("f_ab", np.nan), "D_p": unloaded.get("D_p", np.nan),
        "regime": unloaded.get("regime", ""), "removed_area_um2": summary.get("removed_area_um2") or 0.0,
    }


class Runner:
    """Runs scenes and keeps their summaries, curves and profiles; resumable run by run.

    Every finished run is stored in ``<outdir>/scratch_runs/<name>/run.json`` together with the ``repr`` of its
    scene; a later call with the same name and scene reads it back instead of running again, so an interrupted
    benchmark loses nothing it has finished, and runs can be computed ahead in another process
    (``python benchmarks/bench_scratch.py --only NAME``).
    """

    def __init__(self, outdir: Path):
        self.outdir = outdir
        self.runs: dict[str, dict] = {}

    def __call__(self, name, part, scene, vtu_every=0):
        folder = self.outdir / "scratch_runs" / name
        stored = folder / "run.json"
        if stored.exists() and (entry := read_json(stored)).get("scene") == repr(scene):
            print(f"[scratch] {name}: stored ({entry['row']['wall_time_s']:.0f} s)", flush=True)
            self.runs[name] = entry
            return entry
        print(f"[scratch] {name}: R = {scene.indenter.radius * 1e3:g} um, d = {scene.depth * 1e3:g} um, "
              f"slide {scene.slide * 1e3:g} um, mesh {scene.mesh if isinstance(scene.mesh, str) else 'custom'}, "
              f"penalty {scene.penalty:g}", flush=True)
        result = run_scratch(scene, output=folder, vtu_every=vtu_every)
        summary = result.summary()
        row = _row(name, part, scene, summary)
        profiles = {}
        for key, p in (("loaded", result.profile_loaded), ("unloaded", result.profile_unloaded)):
            if p is not None:
                profiles[key] = {"x_um": (p.x * 1e3).tolist(), "y_um": (p.y * 1e3).tolist()}
        entry = {"scene": repr(scene), "row": row, "summary": summary, "profiles": profiles,
                 "curves": {k: result.curves[k].tolist() for k in
                            ("tau", "slide", "normal_force", "tangential_force", "wall_time")}}
        write_json(stored, entry)
        self.runs[name] = entry
        print(f"[scratch]   {row['elements']} hexes, {row['wall_time_s']:.0f} s, F_N = "
              f"{row['mean_normal_force_N']:.3f} N, A_g = {row['A_g_um2']:.1f} um2, f_ab = {row['f_ab']:.3f}",
              flush=True)
        return entry

    def write_csv(self) -> None:
        with CurveWriter(self.outdir / "scratch.csv", COLUMNS) as w:
            for entry in self.runs.values():
                w.write(**entry["row"])


def force_depth(rows, R_um):
    """Mean sliding normal force against depth for the spherical runs of radius R (sorted by depth)."""
    pts = sorted((r["d_um"], r["mean_normal_force_N"]) for r in rows if r["R_um"] == R_um)
    return np.array(pts).T


def seconds_per_um_of_slide(curve) -> float:
    """Slope of the cumulative wall time against the apex travel over the sliding increments of a force curve."""
    sliding = np.asarray(curve["phase"]) == 1
    if sliding.sum() <= 2:
        return float("nan")
    return float(np.polyfit(np.asarray(curve["slide"])[sliding] * 1e3, np.asarray(curve["wall_time"])[sliding], 1)[0])


def default_scene(outdir: Path = RESULTS) -> dict:
    """Part 2 alone: the seed's default scene, its wall time and cost per µm of slide (``scratch_default.json``)."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    print("[scratch] default scene: R = 50 um, d = 2 um, 100 um slide, 'default' mesh", flush=True)
    result = run_scratch(ScratchScene(), output=outdir / "scratch_runs" / "default_scene", vtu_every=10)
    curve = result.curves
    slope = seconds_per_um_of_slide(curve)
    out = {"date": time.strftime("%Y-%m-%d %H:%M"), "host": platform.node(), "wall_time_s": result.wall_time,
           "elements": result.n_elements, "dofs": result.n_dofs, "increments": result.increments,
           "newton_iterations": result.newton_iterations, "cutbacks": result.cutbacks,
           "seconds_per_um_of_slide": slope, "summary": result.summary(),
           "curves": {k: curve[k].tolist() for k in ("tau", "slide", "normal_force", "tangential_force",
                                                    "wall_time")}}
    write_json(outdir / "scratch_default.json", out)
    print(f"[scratch] default scene: {result.wall_time:.0f} s, {result.n_elements} hexes", flush=True)
    return out


BLOCK = (0.1, 0.015, 0.2)
"""The seed's block: full width, thickness, length (mm)."""
STUDY_SLIDE = 0.1
"""The seed's slide (mm): the mid-length section lies in the steady part of the groove."""
PENALTIES = (1.0, 10.0)


def convergence_levels(quick: bool) -> list[tuple[str, float]]:
    """(mesh level, penalty factor) pairs of part 1: every level with c_N = E/h_y, the coarser ones also with 10×."""
    levels = ["demo", "coarse", "default"] if quick else ["demo", "coarse", "default", "fine"]
    return [(level, PENALTIES[0]) for level in levels] + [(level, PENALTIES[1]) for level in levels[:2]]


def planned_runs(quick: bool) -> list[tuple[str, str, ScratchScene]]:
    """(name, part, scene) of parts 1, 3 and 4 (part 5 depends on the depth study's forces)."""
    convergence_slide = 0.06 if quick else 0.1
    study_mesh = "demo" if quick else "coarse"
    plan = [(f"level_{level}_penalty_{penalty:g}", "convergence",
             ScratchScene(slide=convergence_slide, mesh=level, penalty=penalty, size=BLOCK))
            for level, penalty in convergence_levels(quick)]
    plan += [(f"depth_{d * 1e3:g}um", "depth", ScratchScene(depth=d, slide=STUDY_SLIDE, mesh=study_mesh, size=BLOCK))
             for d in (0.001, 0.002, 0.003, 0.004, 0.005)]
    plan += [(f"radius_{R * 1e3:g}um", "radius",
              ScratchScene(indenter=ConicalIndenter.from_included_angle(R, 60.0), depth=0.003, slide=STUDY_SLIDE,
                           mesh=study_mesh, size=BLOCK))
             for R in (0.025, 0.05, 0.1)]
    return plan


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    run = Runner(outdir)
    study_mesh = "demo" if quick else "coarse"
    convergence_slide = 0.06 if quick else 0.1
    plan = planned_runs(quick)

    # 1. speed against error; 3. depth study (Fig. 8.8); 4. radius study (Fig. 8.10-8.12, 60 deg cones, d = 3 um)
    for name, part, scene in plan:
        run(name, part, scene)
    finest = [level for level, penalty in convergence_levels(quick) if penalty == PENALTIES[0]][-1]
    reference = run.runs[f"level_{finest}_penalty_{PENALTIES[0]:g}"]["row"]
    convergence = []
    for name, entry in run.runs.items():
        row = entry["row"]
        if row["part"] != "convergence":
            continue
        convergence.append({
            "name": name, "mesh": row["mesh"], "penalty": row["penalty"], "elements": row["elements"],
            "wall_time_s": row["wall_time_s"],
            **{f"{k}_error": abs(row[k] / reference[k] - 1.0) if name != reference["name"] else 0.0
               for k in ("A_g_um2", "f_ab", "mean_normal_force_N", "A_g_loaded_um2")},
        })

    # 2. the default scene (full mode; or an earlier ``--default-scene`` run) -----------------------------------
    if not quick:
        default_scene(outdir)
    default = read_json(outdir / "scratch_default.json") if (outdir / "scratch_default.json").exists() else None

    # 5. the wear example: both grains at f_N = 2 N ---------------------------------------------------------------
    depth_rows = [e["row"] for e in run.runs.values() if e["row"]["part"] == "depth"]
    d_um, F = force_depth(depth_rows, 50.0)
    d50 = float(np.interp(SEED_FORCE, F, d_um)) if F.max() >= SEED_FORCE else float(d_um[-1] * SEED_FORCE / F[-1])
    d100 = 0.5 * d50                                          # F ~ H pi R d: the same force at half the depth
    grains = {}
    for D, R, d in ((100, 0.05, d50), (200, 0.1, d100)):
        scene = ScratchScene(indenter=SphericalIndenter(R), depth=round(d, 4) * 1e-3, slide=STUDY_SLIDE,
                             mesh=study_mesh, size=BLOCK)
        summary = run(f"grain_{D}um", "grain", scene)["summary"]
        first_guess = {"d_um": scene.depth * 1e3, "F_N": summary["mean_normal_force_N"]}
        if abs(summary["mean_normal_force_N"] / SEED_FORCE - 1.0) > FORCE_TOLERANCE:
            # one secant correction with F ~ R d (plastic contact at constant hardness)
            d = scene.depth * 1e3 * SEED_FORCE / summary["mean_normal_force_N"]
            scene = scene.with_(depth=round(d, 4) * 1e-3)
            summary = run(f"grain_{D}um_corrected", "grain", scene)["summary"]
        loaded = summary["groove_loaded"] or {}
        g = summary["groove_unloaded"] or loaded
        grains[D] = {"R_um": R * 1e3, "d_um": scene.depth * 1e3, "F_N": summary["mean_normal_force_N"],
                     "first_guess": first_guess,
                     "A_g_um2": g["A_g_um2"], "f_ab": g["f_ab"], "A_g_loaded_um2": loaded.get("A_g_um2"),
                     "f_ab_loaded": loaded.get("f_ab"), "seed": SEED_GRAINS[D]}
    ours = astm_g65_table(fine=Grain(100e-6, grains[100]["A_g_um2"] * 1e-12, grains[100]["f_ab"]),
                          coarse=Grain(200e-6, grains[200]["A_g_um2"] * 1e-12, grains[200]["f_ab"]))
    seed_inputs = astm_g65_table(fine=GRAIN_100UM, coarse=GRAIN_200UM)
    table = {"label": ours["label"], "theta_200um": ours["theta_coarse"].tolist(),
             "seed_printed": seed_inputs["seed"].tolist(), "from_seed_inputs": seed_inputs["ours"].tolist(),
             "from_our_scratches": ours["ours"].tolist()}
    with CurveWriter(outdir / "scratch_table_8_4.csv",
                     ["theta_200um", "seed_printed", "from_seed_inputs", "from_our_scratches"]) as w:
        for i in range(len(table["label"])):
            w.write(**{k: table[k][i] for k in ("theta_200um", "seed_printed", "from_seed_inputs",
                                                 "from_our_scratches")})

    # cost against sliding distance: the finest convergence run (the default scene is in scratch_default.json)
    cost_run = reference["name"]
    slope = seconds_per_um_of_slide(read_curve(outdir / "scratch_runs" / cost_run / "forces.csv"))
    elements = np.array([c["elements"] for c in convergence], dtype=float)
    times = np.array([c["wall_time_s"] for c in convergence])
    exponent = float(np.polyfit(np.log(elements), np.log(times), 1)[0]) if np.unique(elements).size > 1 else None

    results = {
        "mode": "quick" if quick else "full",
        "date": time.strftime("%Y-%m-%d %H:%M"),
        "host": platform.node(),
        "wall_time_s": time.perf_counter() - t0,
        "study_mesh": study_mesh, "study_slide_um": STUDY_SLIDE * 1e3,
        "convergence_slide_um": convergence_slide * 1e3,
        "convergence": convergence, "reference_run": reference["name"],
        "default_scene": default,
        "cost": {"run": cost_run, "seconds_per_um_of_slide": slope, "time_vs_elements_exponent": exponent},
        "grains": grains, "depth_for_2N_um": {"R50": d50, "R100": d100},
        "table_8_4": table,
        "runs": run.runs,
    }
    run.write_csv()
    write_json(outdir / "scratch.json", results)
    plot(results, outdir / "scratch.png")
    return results


def plot(results: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    runs = results["runs"]
    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))

    a = ax[0, 0]
    conv = results["convergence"]
    for penalty, marker in ((1.0, "o"), (10.0, "s")):
        pts = sorted((c["wall_time_s"], c) for c in conv if c["penalty"] == penalty)
        t = [p[0] for p in pts]
        for key, colour in (("A_g_um2_error", "C0"), ("f_ab_error", "C1"), ("mean_normal_force_N_error", "C2")):
            err = [max(p[1][key], 1e-4) for p in pts]
            a.loglog(t, err, marker=marker, color=colour, ls="-" if penalty == 1.0 else "--",
                     label=f"{key.removesuffix('_error').replace('_um2', '').replace('_N', '')}, c_N = {penalty:g} E/h")
    a.set(xlabel="wall time [s]", ylabel="|relative difference| to the reference",
          title=f"speed against error (reference: {results['reference_run']})")
    a.legend(fontsize=7)

    a = ax[0, 1]
    for entry in runs.values():
        if entry["row"]["part"] == "depth":
            c = entry["curves"]
            a.plot(np.array(c["tau"]), c["normal_force"], label=f"d = {entry['row']['d_um']:g} um")
    a.set(xlabel="pseudo-time tau (0-1 indentation, 1-2 sliding, 2-3 unloading)", ylabel="normal force F_N [N]",
          title="Fig. 8.8: normal force, R = 50 um")
    a.legend(fontsize=8)

    a = ax[0, 2]
    for entry in runs.values():
        if entry["row"]["part"] == "radius":
            c = entry["curves"]
            s = np.array(c["slide"]) * 1e3
            sliding = (np.array(c["tau"]) > 1) & (np.array(c["tau"]) <= 2)
            a.plot(s[sliding], np.array(c["normal_force"])[sliding], label=f"R = {entry['row']['R_um']:g} um")
    a.set(xlabel="sliding distance [um]", ylabel="normal force F_N [N]", title="Fig. 8.11: 60 deg cones, d = 3 um")
    a.legend(fontsize=8)

    a = ax[1, 0]
    for name, entry in runs.items():
        if entry["row"]["part"] in ("radius", "grain") and "unloaded" in entry["profiles"]:
            p = entry["profiles"]["unloaded"]
            x, y = np.array(p["x_um"]), np.array(p["y_um"])
            a.plot(np.r_[-x[::-1], x], np.r_[y[::-1], y], label=f"{name} (f_ab = {entry['row']['f_ab']:.2f})")
    a.axhline(0.0, color="k", lw=0.5)
    a.set(xlabel="x [um]", ylabel="y [um]", title="Fig. 8.12/8.17/8.18: grooves after unloading (mid-length)")
    a.legend(fontsize=7)

    a = ax[1, 1]
    name = results["cost"]["run"]
    c = runs[name]["curves"]
    a.plot(np.array(c["slide"]) * 1e3, c["wall_time"], label=name)
    if results.get("default_scene"):
        c = results["default_scene"]["curves"]
        a.plot(np.array(c["slide"]) * 1e3, c["wall_time"], label="default scene")
    a.set(xlabel="apex travel along z [um]", ylabel="cumulative wall time [s]",
          title=f"cost: {results['cost']['seconds_per_um_of_slide']:.2f} s per um of slide")
    inset = a.inset_axes([0.58, 0.12, 0.38, 0.35])
    inset.loglog([x["elements"] for x in conv], [x["wall_time_s"] for x in conv], "o")
    inset.set_xlabel("elements", fontsize=7)
    inset.set_ylabel("wall time [s]", fontsize=7)
    inset.tick_params(labelsize=6)
    a.legend(fontsize=7, loc="upper left")

    a = ax[1, 2]
    t = results["table_8_4"]
    theta = np.array(t["theta_200um"])
    a.plot(theta, np.array(t["seed_printed"]) * 1e7, "ko", label="Table 8.4 (printed)")
    a.plot(theta, np.array(t["from_seed_inputs"]) * 1e7, "C0-", label="from the seed's A_g, f_ab")
    a.plot(theta, np.array(t["from_our_scratches"]) * 1e7, "C3s--", label="from our scratches")
    a.set(xlabel="volume fraction of 200 um grains", ylabel="wear rate [1e-7 m3/s]", title="Table 8.4")
    a.legend(fontsize=8)

    fig.suptitle(f"abrakit single scratch benchmark ({results['mode']} mode, {results['date']})")
    save_figure(fig, path, dpi=110)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse meshes, no default scene")
    parser.add_argument("--default-scene", action="store_true", help="run only the seed's default scene")
    parser.add_argument("--only", metavar="NAME", help="compute one planned run ahead (e.g. in a second process)")
    parser.add_argument("--outdir", type=Path, default=RESULTS)
    args = parser.parse_args()
    if args.default_scene:
        default_scene(args.outdir)
    elif args.only:
        plan = {name: (part, scene) for name, part, scene in planned_runs(args.quick)}
        if args.only not in plan:
            parser.error(f"--only must be one of {sorted(plan)}")
        Runner(args.outdir)(args.only, *plan[args.only])
    else:
        out = main(args.outdir, quick=args.quick)
        print(f"done in {out['wall_time_s']:.0f} s")
