"""A thick cylinder under internal pressure up to collapse, against Hill's closed form (verification of the solver).

    python examples/fem.py [outdir]

Quarter of a plane-strain cylinder (inner radius 10 mm, outer 20 mm), von Mises plasticity without hardening,
B-bar quadrilaterals, loaded to 95 % of the limit pressure p_L = (2/sqrt 3) sigma_0 ln(b/a). Prints the radial
displacement of the outer surface against Hill's solution at a few pressures, and writes every load step
(pressure, outer displacement, Hill's) to ``thick_cylinder.csv``.
"""

import sys
from pathlib import Path

import numpy as np

from abrakit.fem import StepControl, thick_cylinder_problem, thick_cylinder_solution
from abrakit.io import CurveWriter
from abrakit.materials import VonMisesPlasticity

E, NU, SIGMA_0 = 200000.0, 0.49, 240.0          # MPa; nu near 1/2, where Hill's solution is exact


def main(outdir="results/examples", n=12, fraction=0.95):
    exact = thick_cylinder_solution(10.0, 20.0, E, NU, SIGMA_0)
    pressure = fraction * exact.limit_pressure
    material = VonMisesPlasticity(E, NU, SIGMA_0 / np.sqrt(1.5), 0.0)
    solver = thick_cylinder_problem(material, pressure=pressure, n_radial=n, n_angular=n,
                                    control=StepControl(initial=0.05, maximum=0.05))
    result = solver.run(progress=False)
    p = result.curves["load_factor"] * pressure
    u = result.curves["u_outer"]
    errors = []
    for k in np.linspace(0, len(p) - 1, 6).astype(int)[1:]:
        reference = exact.outer_displacement(p[k])
        errors.append(abs(u[k] / reference - 1))
        print(f"p = {p[k]:7.2f} MPa ({p[k] / exact.limit_pressure:.2f} p_L): u_outer = {1e3 * u[k]:.4f} um, "
              f"Hill {1e3 * reference:.4f} um, error {100 * errors[-1]:.2f} %")
    path = Path(outdir) / "thick_cylinder.csv"
    with CurveWriter(path, ["pressure_MPa", "p_over_p_L", "u_outer_mm", "u_hill_mm"]) as out:
        for p_k, u_k in zip(p, u, strict=True):
            out.write(pressure_MPa=p_k, p_over_p_L=p_k / exact.limit_pressure, u_outer_mm=u_k,
                      u_hill_mm=exact.outer_displacement(p_k))
    print(f"written: {path}")
    return max(errors)


if __name__ == "__main__":
    main(*sys.argv[1:])
