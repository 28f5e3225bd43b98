"""A single scratch (Ch. 8.2): the seed's sphere (R = 50 um) drawn 2 um deep through St-52, on the demo mesh.

    python examples/scratch.py [outdir]

Writes the run to ``<outdir>/scratch/`` (``forces.csv``, one row per converged increment; VTU fields every 10
increments; a checkpoint from which a killed run resumes) and prints the forces while sliding and the groove after
unloading: its area A_g, shoulders A_s, width w and degree of wear f_ab = (A_g - A_s)/A_g, Eq. (8.5).
"""

import sys
from pathlib import Path

from abrakit.scratch import DEMO_SCENE, run_scratch


def main(outdir="results/examples"):
    result = run_scratch(DEMO_SCENE, output=Path(outdir) / "scratch", resume=True)
    print(f"{result.n_elements} hexahedra, {result.increments} increments, {result.wall_time:.1f} s; while sliding "
          f"F_N = {result.mean_normal_force:.3f} N, F_T = {result.mean_tangential_force:.3f} N")
    groove = result.groove_unloaded
    print(f"groove after unloading: A_g = {groove.groove_area * 1e6:.1f} um2, A_s = {groove.shoulder_area * 1e6:.1f} "
          f"um2, w = {groove.width * 1e3:.1f} um, f_ab = {groove.degree_of_wear:.2f} ({groove.regime})")
    print(f"written: {Path(outdir) / 'scratch'}")
    return result


if __name__ == "__main__":
    main(*sys.argv[1:])
