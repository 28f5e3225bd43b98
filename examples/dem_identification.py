"""DEM identification (Ch. 5.3): make a specimen as PFC does, test it in compression, compare with Eq. (5.20).

    python examples/dem_identification.py [outdir]

The demo's 150-sphere specimen (radius expansion, isotropic consolidation to 1 MPa; cached on disk after the first run)
is compressed granular and fully bonded. Writes ``moduli.csv`` (E from the walls, the specimen and measurement
spheres, Poisson's ratio from the walls) beside Eq. (5.20)'s E in its published and its consistent form, computed
from the specimen's own contact density.
"""

import sys
from pathlib import Path

from abrakit.experiments import DEMO_SPEC, contact_statistics, elastic_predictions, elastic_test, genesis
from abrakit.io import CurveWriter


def main(outdir="results/examples"):
    spec = DEMO_SPEC
    specimen = genesis(spec)
    print(f"{len(specimen)} spheres, interior porosity {specimen.info['porosity_interior']:.3f}")
    path = Path(outdir) / "moduli.csv"
    columns = ["material", "E_wall_GPa", "E_specimen_GPa", "E_sphere_GPa", "nu_wall", "E_eq_5_20_published_GPa",
               "E_eq_5_20_consistent_GPa"]
    rows = {}
    with CurveWriter(path, columns) as out:
        for label, material in (("granular", spec.material()), ("bonded", spec.material().with_bonds(1e30, 1e30))):
            result = elastic_test(specimen, material)
            predicted = elastic_predictions(contact_statistics(result["sim"], margin=1.0))
            m = result["moduli"]
            rows[label] = {"E_wall": m["wall"]["E"], "nu_wall": m["wall"]["nu"],
                           "published": predicted["published"]["E"], "consistent": predicted["consistent"]["E"]}
            out.write(material=label, E_wall_GPa=m["wall"]["E"] / 1e9, E_specimen_GPa=m["specimen"]["E"] / 1e9,
                      E_sphere_GPa=m["sphere"]["E"] / 1e9, nu_wall=m["wall"]["nu"],
                      E_eq_5_20_published_GPa=predicted["published"]["E"] / 1e9,
                      E_eq_5_20_consistent_GPa=predicted["consistent"]["E"] / 1e9)
            print(f"{label:8s}: E = {m['wall']['E'] / 1e9:.1f} GPa, nu = {m['wall']['nu']:.3f} (walls); Eq. (5.20): "
                  f"{predicted['published']['E'] / 1e9:.1f} GPa as published, {predicted['consistent']['E'] / 1e9:.1f}"
                  " GPa in its consistent form (the book's decisions page explains both)")
    print(f"written: {path}")
    return rows


if __name__ == "__main__":
    main(*sys.argv[1:])
