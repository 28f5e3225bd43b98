"""Speed against error of the finite element core ``abrakit.fem`` (seed Ch. 4.2, Eq. 4.37/4.40).

Three studies:

- ``assembly``: throughput (DOF/s) of the tangent of Eq. (4.40) and the internal force of Eq. (4.37) with the
  vectorised einsum assembly against scikit-fem's generic ``BilinearForm``/``LinearForm`` on the same mesh and the
  same quadrature-point tangent/stress (bilinear quads in plane strain, trilinear hexes in 3D); the error column is
  the largest entry difference relative to the largest entry (the two must agree to round-off).
- ``plate``: the full elastoplastic load path of the quarter plate with a hole (50 x 50 mm, R = 10 mm, plane
  strain, Table 7.1 plasticity, implicit return map, top edge pulled 0.05 mm in 20 equal steps) on four meshes of
  about 225, 900, 4000 and 8000 elements (the seed used 900/4038/8014); runtime against the largest deviation of
  the force–displacement curve from the finest mesh, relative to its peak force.
- ``linear``: one Newton correction on a 3D hex block, SuperLU against pyamg-preconditioned CG; the error is the
  relative difference of the two solutions.

    python benchmarks/bench_fem.py [--quick] [--outdir DIR]

writes ``fem.csv`` (one row per case, flushed as it goes), ``fem.json`` (summary) and ``fem.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import skfem
from _common import command_line, save_figure

from abrakit.fem import Assembler, Dirichlet, Kinematics, Solver, StepControl, meshes, vector_basis
from abrakit.fem.assembly import skfem_internal_force, skfem_tangent
from abrakit.fem.problems import TABLE_7_1_PLASTICITY, plate_with_hole_problem
from abrakit.io import CurveWriter, write_json
from abrakit.materials import LinearElastic, VonMisesPlasticity

NAME = "fem"
COLUMNS = ["study", "case", "elements", "dofs", "seconds", "dofs_per_second", "error"]


def best_time(fn, repeats=3):
    best, out = np.inf, None
    for _ in range(repeats):
        tic = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - tic)
    return best, out


def assembly_study(writer, quick):
    sizes = {"quad": (16, 32, 64) if quick else (16, 32, 64, 128, 256),
             "hex": (4, 8) if quick else (4, 8, 12, 16, 24)}
    generic_limit = {"quad": 128, "hex": 16}
    rng = np.random.default_rng(0)
    rows = []
    for kind, ns in sizes.items():
        for n in ns:
            axis = np.linspace(0.0, 1.0, n + 1)
            mesh = skfem.MeshQuad.init_tensor(axis, axis) if kind == "quad" else skfem.MeshHex.init_tensor(*[axis] * 3)
            kin = Kinematics.from_basis(vector_basis(mesh))
            setup, asm = best_time(lambda kin=kin: Assembler(kin), repeats=1)
            C = rng.standard_normal((kin.nel, kin.nqp, 6, 6))
            S = rng.standard_normal((kin.nel, kin.nqp, 6))
            t_K, K = best_time(lambda asm=asm, C=C: asm.tangent(C))
            t_f, f = best_time(lambda asm=asm, S=S: asm.internal_force(S))
            record = {"kind": kind, "n": n, "elements": kin.nel, "dofs": kin.ndof, "setup": setup,
                      "tangent": t_K, "force": t_f}
            if n <= generic_limit[kind]:
                reps = 1 if kin.ndof > 5000 else 3
                g_K, K_ref = best_time(lambda kin=kin, C=C: skfem_tangent(kin.basis, C), reps)
                g_f, f_ref = best_time(lambda kin=kin, S=S: skfem_internal_force(kin.basis, S), reps)
                record.update(generic_tangent=g_K, generic_force=g_f,
                              error_K=float(abs(K - K_ref).max() / abs(K_ref).max()),
                              error_f=float(np.abs(f - f_ref).max() / np.abs(f_ref).max()))
            rows.append(record)
            for label, seconds, err in (("einsum tangent", t_K, record.get("error_K", np.nan)),
                                        ("einsum force", t_f, record.get("error_f", np.nan)),
                                        ("generic tangent", record.get("generic_tangent", np.nan), 0.0),
                                        ("generic force", record.get("generic_force", np.nan), 0.0)):
                if np.isfinite(seconds):
                    writer.write(study="assembly", case=f"{kind} {label}", elements=kin.nel, dofs=kin.ndof,
                                 seconds=seconds, dofs_per_second=kin.ndof / seconds, error=err)
    return rows


def plate_study(writer, quick):
    sizes = ((8, 7), (16, 14), (30, 30)) if quick else ((16, 14), (30, 30), (64, 63), (90, 89))
    material = VonMisesPlasticity(**TABLE_7_1_PLASTICITY, integration="implicit")
    runs = []
    for n_angular, n_radial in sizes:
        solver = plate_with_hole_problem(material, n_angular=n_angular, n_radial=n_radial, displacement=0.05,
                                         control=StepControl(initial=0.05, maximum=0.05))
        tic = time.perf_counter()
        result = solver.run(progress=False)
        runs.append({"elements": solver.kin.nel, "dofs": solver.kin.ndof, "seconds": time.perf_counter() - tic,
                     "iterations": int(result.iterations.sum()), "cutbacks": result.cutbacks,
                     "u": result.curves["u_top"], "F": result.curves["F_top"]})
    ref = runs[-1]
    for run in runs:
        F_on_ref = np.interp(ref["u"], run["u"], run["F"])
        run["error"] = float(np.abs(F_on_ref - ref["F"]).max() / np.abs(ref["F"]).max()) if run is not ref else 0.0
        writer.write(study="plate", case=f"{run['elements']} quads", elements=run["elements"], dofs=run["dofs"],
                     seconds=run["seconds"], dofs_per_second=run["dofs"] * run["iterations"] / run["seconds"],
                     error=run["error"])
    return runs


def linear_study(writer, quick):
    sizes = (6, 10) if quick else (6, 10, 14, 18)
    material = LinearElastic(200000.0, 0.3)
    rows = []
    for n in sizes:
        mesh = meshes.graded_block(size=(2.0, 1.0, 1.0), divisions=(2 * n, n, n))
        basis = vector_basis(mesh)
        bcs = [Dirichlet.on(basis, "xmin", "xyz"), Dirichlet.on(basis, "xmax", "z", -0.01)]
        out = {}
        for kind in ("direct", "amg"):
            solver = Solver(basis, material, bcs, linear_solver=kind, control=StepControl(initial=1.0, maximum=1.0))
            tic = time.perf_counter()
            out[kind] = (solver.run(progress=False).u, time.perf_counter() - tic)
        u_ref = out["direct"][0]
        for kind, (u, seconds) in out.items():
            err = float(np.abs(u - u_ref).max() / np.abs(u_ref).max())
            rows.append({"kind": kind, "n": n, "elements": mesh.t.shape[1], "dofs": basis.N, "seconds": seconds,
                         "error": err})
            writer.write(study="linear", case=f"hex {kind}", elements=mesh.t.shape[1], dofs=basis.N,
                         seconds=seconds, dofs_per_second=basis.N / seconds, error=err)
    return rows


def plot(path, assembly, plate, linear):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    fig, ax = plt.subplots(1, 4, figsize=(19, 4.5))
    for kind, marker in (("quad", "o"), ("hex", "s")):
        rows = [r for r in assembly if r["kind"] == kind]
        dofs = np.array([r["dofs"] for r in rows])
        ax[0].loglog(dofs, dofs / np.array([r["tangent"] for r in rows]), marker + "-", label=f"{kind}: einsum")
        gen = [r for r in rows if "generic_tangent" in r]
        ax[0].loglog([r["dofs"] for r in gen], [r["dofs"] / r["generic_tangent"] for r in gen], marker + "--",
                     label=f"{kind}: scikit-fem BilinearForm")
    ax[0].set(xlabel="DOFs", ylabel="tangent assembly [DOF/s]", title="Assembly throughput (Eq. 4.40)")
    for run in plate:
        ax[1].plot(run["u"], run["F"], label=f"{run['elements']} elements")
    ax[1].set(xlabel="top displacement [mm]", ylabel="reaction [N/mm]", title="Plate with hole, plane strain")
    coarse = plate[:-1]
    ax[2].loglog([r["seconds"] for r in coarse], [r["error"] for r in coarse], "o-", label="plate: F–u error")
    for r in coarse:
        ax[2].annotate(f"{r['elements']}", (r["seconds"], r["error"]), fontsize=8)
    ax[2].set(xlabel="runtime [s]", ylabel="max |F - F_finest| / F_max", title="Load path: error vs runtime")
    for kind, marker in (("direct", "o-"), ("amg", "s-")):
        rows = [r for r in linear if r["kind"] == kind]
        ax[3].loglog([r["dofs"] for r in rows], [r["seconds"] for r in rows], marker,
                     label="SuperLU" if kind == "direct" else "AMG-preconditioned CG")
    ax[3].set(xlabel="DOFs", ylabel="runtime of one elastic solve [s]", title="3D hex block: linear solver")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
        a.xaxis.set_minor_formatter(NullFormatter())
    save_figure(fig, path)


def main(outdir: Path = Path(__file__).parent / "results", quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    tic = time.perf_counter()
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        assembly = assembly_study(writer, quick)
        plate = plate_study(writer, quick)
        linear = linear_study(writer, quick)
    plot(outdir / f"{NAME}.png", assembly, plate, linear)
    speedups = {f"{r['kind']} {r['dofs']} DOF": r["generic_tangent"] / r["tangent"]
                for r in assembly if "generic_tangent" in r}
    largest = {kind: max((r for r in assembly if r["kind"] == kind), key=lambda r: r["dofs"])
               for kind in ("quad", "hex")}
    summary_lines = [
        *(f"tangent assembly, {k}: {v['dofs']} DOF in {v['tangent'] * 1e3:.1f} ms = "
          f"{v['dofs'] / v['tangent']:.3g} DOF/s" for k, v in largest.items()),
        "speed-up over scikit-fem BilinearForm: " + ", ".join(f"{k}: {v:.0f}x" for k, v in speedups.items()),
        "max difference to the generic forms: "
        f"{max(max(r.get('error_K', 0), r.get('error_f', 0)) for r in assembly):.1e} (relative)",
        *(f"plate {r['elements']:5d} elements: {r['seconds']:6.2f} s, {r['iterations']} Newton iterations, "
          f"F–u error vs finest {r['error']:.2e}" for r in plate),
        *(f"3D block {r['dofs']} DOF, {r['kind']}: {r['seconds']:.2f} s (difference {r['error']:.1e})" for r in linear),
    ]
    summary = "\n".join(summary_lines)
    data = {"assembly": assembly,
            "plate": [{k: v for k, v in r.items() if k not in ("u", "F")} for r in plate],
            "plate_curves": [{"elements": r["elements"], "u": r["u"], "F": r["F"]} for r in plate],
            "linear": linear, "speedups": speedups, "quick": quick,
            "wall_time": time.perf_counter() - tic, "summary": summary}
    write_json(outdir / f"{NAME}.json", data)
    return data


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="small meshes only (seconds instead of minutes)")
