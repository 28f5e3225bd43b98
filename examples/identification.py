"""Micro-macro identification: contact stiffnesses for a target E and nu (Eq. 5.9, 5.21), and back (Eq. 5.20).

    python examples/identification.py [outdir]

Writes the contact density, the stiffnesses of both variants and the constants they give back to
``identification.json``.
"""

import sys
from pathlib import Path

from abrakit import identification as ident
from abrakit.io import write_json


def main(outdir="results/examples", E=30e9, nu=0.26, radius=1e-3, porosity=0.35, coordination=6.0):
    rho_c = ident.contact_density(coordination, porosity, radius)              # Eq. (5.9), 1/m^3
    variants = {}
    for variant in ("published", "consistent"):
        kn, kt = ident.contact_stiffnesses(E, nu, rho_c, radius, variant)       # Eq. (5.21), N/m
        E_back, nu_back = ident.elastic_constants(kn, kt, rho_c, radius, variant)  # Eq. (5.20)
        variants[variant] = {"kn_N_per_m": kn, "kt_N_per_m": kt, "E_back_Pa": E_back, "nu_back": nu_back}
        print(f"{variant:10s}: kn = {kn:.4g} N/m, kt = {kt:.4g} N/m -> E = {E_back:.4g} Pa, nu = {nu_back:.3f}")
    path = write_json(Path(outdir) / "identification.json",
                      {"target": {"E_Pa": E, "nu": nu}, "radius_m": radius, "porosity": porosity,
                       "coordination": coordination, "rho_c_per_m3": rho_c, "variants": variants})
    print(f"written: {path}")
    return rho_c


if __name__ == "__main__":
    main(*sys.argv[1:])
