"""The DEM engine (Ch. 4.1) against closed forms: two spheres colliding with a dashpot, a sphere rolling off.

    python examples/dem.py [outdir]

Writes ``impact.csv`` (damping ratio, contact duration and restitution, computed and analytic) and prints the
rolling sphere's time and speed at which it stops slipping against 2 v0/(7 mu g) and 5 v0/7.
"""

import sys
from pathlib import Path

from abrakit.dem import rolling_sphere, two_sphere_impact
from abrakit.io import CurveWriter


def main(outdir="results/examples"):
    path = Path(outdir) / "impact.csv"
    errors = []
    columns = ["damping_ratio", "duration_ms", "duration_analytic_ms", "restitution", "restitution_analytic"]
    with CurveWriter(path, columns) as out:
        for zeta in (0.0, 0.1, 0.2, 0.4):
            r = two_sphere_impact(radius=0.01, density=2650.0, kn=1e5, damping_ratio=zeta, velocity=1.0)
            out.write(damping_ratio=zeta, duration_ms=r["duration"] * 1e3,
                      duration_analytic_ms=r["duration_analytic"] * 1e3, restitution=r["restitution"],
                      restitution_analytic=r["restitution_analytic"])
            errors.append(abs(r["restitution"] - r["restitution_analytic"]))
            print(f"zeta = {zeta}: restitution {r['restitution']:.4f} (analytic {r['restitution_analytic']:.4f}), "
                  f"contact {r['duration'] * 1e3:.4f} ms (analytic {r['duration_analytic'] * 1e3:.4f})")
    roll = rolling_sphere(friction=0.3, velocity=1.0)
    print(f"rolling sphere: slipping stops at t = {roll['t_star'] * 1e3:.2f} ms (analytic "
          f"{roll['t_star_analytic'] * 1e3:.2f}) with v = {roll['v_star']:.4f} m/s (analytic "
          f"{roll['v_star_analytic']:.4f})")
    print(f"written: {path}")
    return {"restitution_error": max(errors), "roll_speed_error": abs(roll["v_star"] / roll["v_star_analytic"] - 1)}


if __name__ == "__main__":
    main(*sys.argv[1:])
