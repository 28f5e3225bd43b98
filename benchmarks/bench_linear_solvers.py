"""Benchmark: the direct-solver back-ends against problem size, analysis once and numerical factorisations after.

Elastic stiffness matrices of bilinear quadrilaterals (2D plane strain) and trilinear hexahedra (3D), clamped on
one side, from about 1 000 to 400 000 free DOFs in 2D and to 90 000 in 3D (larger 3D factorisations need more
memory and time than a two-core machine shared with other runs gives). For every back-end of
:class:`abrakit.fem.DirectSolver` (SuperLU in its own order; PARDISO if pypardiso is installed, in double precision
and with single-precision factors refined in double, ``pardiso-single``, ``DirectSolver("pardiso",
precision="single")``; the banded LU in a reverse Cuthill–McKee order while its band fits in
:data:`BANDED_MAX_MB`; dense LU up to :data:`DENSE_MAX` unknowns) and for the AMG-preconditioned CG of
:class:`abrakit.fem.AMGSolver`: the time of the symbolic analysis, of a numerical factorisation (the cost of
every further Newton iteration; the fastest of repeated ones) and of its solve, of the whole ``solve`` call
(``total_s``, what ``DirectSolver("auto")`` is judged by), the factor size (non-zeros of L + U, PARDISO's peak
memory) and the relative residual. SuperLU stops at 60 000 DOFs in 3D (minutes per factorisation beyond). The
smallest 2D sizes (about 100 and 400 DOFs, a coarse plate's) show where the banded LU beats the sparse solvers:
the crossover that ``DirectSolver("auto")`` models (:func:`abrakit.fem.linsolve.banded_wins`).
Writes ``linear_solvers.csv``, ``linear_solvers.json`` and ``linear_solvers.png``.

    python benchmarks/bench_linear_solvers.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import skfem
from _common import RESULTS, command_line, save_figure

from abrakit.fem import Assembler, DirectSolver, Dirichlet, Kinematics
from abrakit.fem.linsolve import AMGSolver, pardiso_available, rigid_body_modes
from abrakit.io import CurveWriter, write_json
from abrakit.materials import LinearElastic

SIZES = {2: (5, 10, 20, 40, 80, 160, 320), 3: (6, 10, 16, 24)}
QUICK_SIZES = {2: (5, 10, 20, 40), 3: (6, 10)}
SUPERLU_MAX_3D = 60_000
DENSE_MAX = 3_000            # dense LU beyond this: seconds per factorisation
BANDED_MAX_MB = 300          # the banded LU's band storage (2 kl + ku + 1) x n doubles
COLUMNS = ("dim", "n", "dofs", "backend", "analyse_s", "factorise_s", "solve_s", "total_s", "factor_nnz", "memory_mb",
           "residual")


def elastic_system(dim: int, n: int):
    """Clamped elastic block with n elements per side (3D: n x n x 2n), its free stiffness and a load."""
    if dim == 2:
        mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 1, n + 1), np.linspace(0, 2, 2 * n + 1))
    else:
        mesh = skfem.MeshHex.init_tensor(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1),
                                         np.linspace(0, 2, 2 * n + 1))
    mesh = mesh.with_boundaries({"clamped": lambda x: x[dim - 1] < 1e-9})
    kin = Kinematics.from_mesh(mesh)
    material = LinearElastic(200000.0, 0.3)
    tangent = material.update(material.initial_state((kin.nel, kin.nqp)), np.zeros((kin.nel, kin.nqp, 6))).tangent
    K = Assembler(kin).tangent(tangent)
    free = np.setdiff1d(np.arange(kin.ndof), Dirichlet.on(kin.basis, "clamped").dofs)
    K = sp.csr_matrix(K[free][:, free])
    component = np.zeros(kin.ndof, dtype=int)
    component[kin.element_dofs] = np.arange(kin.nbf) % dim
    modes = rigid_body_modes(kin.basis.doflocs[:, free], component[free])
    return K, np.random.default_rng(0).standard_normal(K.shape[0]), modes


def measure_direct(backend: str, K, rhs, budget: float = 0.3) -> dict:
    """Analysis and first factorisation, then numerical refactorisations of the same pattern (each Newton
    iteration's cost) repeated for about ``budget`` seconds: the fastest one and its solve are reported (a single
    sub-millisecond factorisation is at the mercy of the host)."""
    solver = DirectSolver("pardiso", precision="single") if backend == "pardiso-single" else DirectSolver(backend)
    solver.solve(K, rhs)                                   # analysis + first factorisation
    analyse = solver.times["analyse"] / solver.analyses
    factorise, solve, total, spent, repeat = np.inf, np.inf, np.inf, 0.0, 0
    while repeat < 3 or (spent < budget and repeat < 200):
        before = dict(solver.times)
        t0 = time.perf_counter()
        x = solver.solve(K * (1.0 + 1e-4 * (repeat + 1)), rhs)     # same pattern: numerical factorisation only
        elapsed = time.perf_counter() - t0
        spent += elapsed
        repeat += 1
        if elapsed < total:
            total = elapsed
            factorise = solver.times["factorise"] - before["factorise"]
            solve = solver.times["solve"] - before["solve"]
    b = solver.backend
    nnz = memory = np.nan
    extra = {}
    if backend == "superlu":
        lu = b._lu[0]
        nnz = lu.L.nnz + lu.U.nnz
    elif backend == "banded":
        extra["bandwidth"] = b.bandwidth
        nnz = float(np.prod(b._shape))
        memory = 8 * nnz / 2**20
    elif backend == "dense":
        nnz = float(K.shape[0]) ** 2
        memory = 8 * nnz / 2**20
    else:
        iparm = b._solver.iparm
        nnz = float(iparm[17])                             # iparm(18): non-zeros in the factors
        memory = max(iparm[14], iparm[15] + iparm[16]) / 1024.0   # iparm(15)-(17): peak memory, KB
    scaled = K * (1.0 + 1e-4 * repeat)
    return {"analyse_s": analyse, "factorise_s": factorise, "solve_s": solve, "factor_nnz": nnz, "memory_mb": memory,
            "residual": float(np.linalg.norm(scaled @ x - rhs) / np.linalg.norm(rhs)), "total_s": total, **extra}


def band_megabytes(K) -> float:
    """The banded LU's storage for K in its analysis order [MB]."""
    from abrakit.fem.linsolve import _BandedBackend

    band = _BandedBackend()
    band.analyse(K)
    return 8 * float(np.prod(band._shape)) / 2**20


def measure_amg(K, rhs, modes) -> dict:
    solver = AMGSolver(modes)
    t0 = time.perf_counter()
    solver._build(K)
    build = time.perf_counter() - t0
    t0 = time.perf_counter()
    x = solver.solve(K, rhs, new_step=False)
    solve = time.perf_counter() - t0
    return {"analyse_s": 0.0, "factorise_s": build, "solve_s": solve, "total_s": build + solve, "factor_nnz": np.nan,
            "memory_mb": np.nan,
            "residual": float(np.linalg.norm(K @ x - rhs) / np.linalg.norm(rhs))}


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    backends = ["superlu"] + (["pardiso", "pardiso-single"] if pardiso_available() else []) + ["banded", "dense"]
    rows, choice = [], {}
    for dim, sizes in (QUICK_SIZES if quick else SIZES).items():
        for n in sizes:
            K, rhs, modes = elastic_system(dim, n)
            auto = DirectSolver()
            auto.solve(K, rhs)
            choice[(dim, K.shape[0])] = auto.name.removeprefix("direct-")
            for backend in backends + ["amg"]:
                if backend == "superlu" and dim == 3 and K.shape[0] > SUPERLU_MAX_3D:
                    continue
                if backend == "dense" and K.shape[0] > DENSE_MAX:
                    continue
                if backend == "banded" and band_megabytes(K) > BANDED_MAX_MB:
                    continue
                m = measure_amg(K, rhs, modes) if backend == "amg" else measure_direct(backend, K, rhs)
                rows.append({"dim": dim, "n": n, "dofs": K.shape[0], "backend": backend, **m})
                print(f"[linear solvers] {dim}D {K.shape[0]:7d} DOFs {backend:14s} analyse {m['analyse_s']:7.3f} s "
                      f"factorise {m['factorise_s']:7.3f} s solve {m['solve_s']:7.4f} s", flush=True)
    with CurveWriter(outdir / "linear_solvers.csv", COLUMNS) as w:
        for r in rows:
            w.write(**{k: r[k] for k in COLUMNS})
    speedup, single = {}, {}
    for dim in (2, 3):
        pairs = {(r["dofs"], r["backend"]): r for r in rows if r["dim"] == dim}
        speedup[dim] = {d: pairs[(d, "superlu")]["factorise_s"] / pairs[(d, "pardiso")]["factorise_s"]
                        for (d, b) in pairs if b == "superlu" and (d, "pardiso") in pairs}
        single |= {f"{dim}D {d}": pairs[(d, "pardiso")]["total_s"] / pairs[(d, b)]["total_s"]
                   for (d, b) in pairs if b == "pardiso-single"}
    fastest = {}
    for (dim, dofs), chosen in choice.items():
        cost = {r["backend"]: r["total_s"] for r in rows
                if r["dim"] == dim and r["dofs"] == dofs and r["backend"] != "amg"}
        fastest[f"{dim}D {dofs}"] = {"auto": chosen, "fastest": min(cost, key=cost.get),
                                     "auto_over_fastest": cost.get(chosen, np.nan) / min(cost.values())}
    results = {"mode": "quick" if quick else "full", "date": time.strftime("%Y-%m-%d %H:%M"), "rows": rows,
               "pardiso_over_superlu_factorisation_speedup": speedup, "auto_choice": fastest,
               "pardiso_single_over_double_speedup": single}
    write_json(outdir / "linear_solvers.json", results)
    plot(rows, outdir / "linear_solvers.png")
    lines = [f"{dim}D, {d} DOFs: PARDISO factorises {s:.1f}x faster than SuperLU" for dim in speedup
             for d, s in sorted(speedup[dim].items())]
    lines += [f"{k}: PARDISO with single factors refined in double, {v:.2f}x faster per solve call"
              for k, v in single.items()]
    lines += [f"{k}: auto chooses {v['auto']}, fastest measured {v['fastest']} ({v['auto_over_fastest']:.2f}x its time)"
              for k, v in fastest.items()]
    results["summary"] = "\n".join(lines)
    return results


def plot(rows, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for a, dim in zip(ax, (2, 3), strict=True):
        for backend, colour in (("superlu", "C0"), ("pardiso", "C3"), ("pardiso-single", "C5"), ("amg", "C2"),
                                ("banded", "C1"), ("dense", "C4")):
            sel = sorted((r for r in rows if r["dim"] == dim and r["backend"] == backend), key=lambda r: r["dofs"])
            if not sel:
                continue
            dofs = [r["dofs"] for r in sel]
            label = "AMG set-up" if backend == "amg" else f"{backend} factorisation"
            a.loglog(dofs, [r["factorise_s"] for r in sel], "o-", color=colour, label=label)
            a.loglog(dofs, [r["solve_s"] for r in sel], "s--", color=colour, label=f"{backend} solve")
            if backend != "amg":
                a.loglog(dofs, [r["analyse_s"] for r in sel], "^:", color=colour, label=f"{backend} analysis")
        a.set(xlabel="free DOFs", ylabel="seconds", title=f"{dim}D elasticity")
        a.legend(fontsize=7)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__)
