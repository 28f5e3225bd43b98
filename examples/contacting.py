"""How many grains touch the tool (Ch. 8.3): a pressed bed of frictionless grains, counted on its floor.

    python examples/contacting.py [outdir]

Grains of D = 1 mm settle and are pressed at 10 kPa in a box of 6 x 6 diameters (3 layers). The grains touching
the floor window (the box without a wall zone of one diameter) give N_c D^2, against Eq. (8.7)'s 0.9. One bed this
small scatters by about +-0.04 from the mean of many; the chapter's benchmark averages larger beds. Writes
``contacting.json``.
"""

import sys
from pathlib import Path

from abrakit.experiments import SEED_COEFFICIENT, contact_census, pressed_bed
from abrakit.io import write_json


def main(outdir="results/examples", seed=0):
    D, L = 1e-3, 6e-3
    sim, bed = pressed_bed(D, box=L, layers=3, seed=seed)
    census = contact_census(sim, wall_zone=D, tol=1e-3 * D)["all"]
    result = {"grains": bed["coarse_grains"], "touching": census["count"], "N_c_D2": census["N_c_D2"],
              "eq_8_7": SEED_COEFFICIENT, "steps": bed["steps"]}
    print(f"{bed['coarse_grains']} grains, {census['count']} touch the floor window: N_c D^2 = "
          f"{census['N_c_D2']:.3f} (Eq. 8.7: {SEED_COEFFICIENT})")
    path = Path(outdir) / "contacting.json"
    write_json(path, result)
    print(f"written: {path}")
    return result


if __name__ == "__main__":
    main(*sys.argv[1:])
