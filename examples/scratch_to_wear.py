"""From one scratch to a wear rate (Ch. 8.4): the demo groove as a grain of Eq. (8.13), the seed's grain beside it.

    python examples/scratch_to_wear.py [outdir]

The groove after unloading gives the grain's A_g and f_ab; N_c = 0.9 / D^2 grains touch the tool per unit area
(Eq. 8.7) and slide at the rubber wheel's speed of the ASTM G65 test. Prints the wear rate of Eq. (8.14) on the
test's contact area (G65_CONTACT_AREA, reconstructed from Table 8.4) in m3/s, as Table 8.4, for the demo groove
and for the seed's 100 um grain (A_g = 88.4 um2, f_ab = 0.37), whose rate is Table 8.4's first row. Writes both
grains and rates to ``scratch_to_wear.csv``.
"""

import sys
from pathlib import Path

from abrakit import wear
from abrakit.io import CurveWriter
from abrakit.scratch import DEMO_SCENE, run_scratch


def main(outdir="results/examples"):
    groove = run_scratch(DEMO_SCENE, vtu_every=0).groove_unloaded
    D = 2.0 * DEMO_SCENE.indenter.radius * 1e-3                                     # mm -> m: 100 um
    ours = wear.Grain(D=D, A_g=groove.groove_area * 1e-6, f_ab=groove.degree_of_wear)  # mm2 -> m2
    v_t = wear.ASTM_G65.wheel_speed
    rates = {}
    path = Path(outdir) / "scratch_to_wear.csv"
    with CurveWriter(path, ["grain", "D_m", "A_g_m2", "f_ab", "wear_rate_m3_per_s"]) as out:
        for name, grain in (("demo groove", ours), ("seed's grain", wear.GRAIN_100UM)):
            rates[name] = wear.wear_rate(wear.contacting_particles(grain.D), grain.f_ab, grain.A_g, v_t,
                                         area=wear.G65_CONTACT_AREA)
            out.write(grain=name, D_m=grain.D, A_g_m2=grain.A_g, f_ab=grain.f_ab, wear_rate_m3_per_s=rates[name])
            print(f"{name:12s}: A_g = {grain.A_g * 1e12:5.1f} um2, f_ab = {grain.f_ab:.2f} -> wear rate "
                  f"{rates[name] * 1e7:.2f} x 1e-7 m3/s (v_t = {v_t:.2f} m/s)")
    ratio = rates["demo groove"] / rates["seed's grain"]
    print(f"ratio demo / seed: {ratio:.2f} (the demo groove is 2 um deep and 30 um long on a coarse mesh, and its "
          "f_ab is a transient reading of that short slide, not steady removal; the seed's grain comes from its "
          "single scratch at f_N = 2 N)")
    print(f"written: {path}")
    return rates


if __name__ == "__main__":
    main(*sys.argv[1:])
