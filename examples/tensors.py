"""Tensor notation (Ch. 2): one strain energy in three notations, Eq. (5.18) by quadrature, the tension split.

    python examples/tensors.py [outdir]

Prints the largest disagreement of each check, every one round-off, and writes them with the three energies to
``tensors.json``.
"""

import sys
from pathlib import Path

import numpy as np

from abrakit import tensors as T
from abrakit.io import write_json


def main(outdir="results/examples"):
    C = T.isotropic_stiffness(210000.0, 0.3)                          # MPa, the 3x3x3x3 tensor
    eps = np.array([[1.0, 0.4, 0.0], [0.4, -0.5, 0.2], [0.0, 0.2, 0.3]]) * 1e-3
    energy = {
        "tensor": 0.5 * T.ddot(eps, np.einsum("ijkl,kl->ij", C, eps)),
        "Voigt, Eq. (2.17)": 0.5 * T.to_voigt(eps, "strain") @ T.to_voigt4(C) @ T.to_voigt(eps, "strain"),
        "Mandel": 0.5 * T.to_mandel(eps) @ T.to_mandel4(C) @ T.to_mandel(eps),
    }
    for name, value in energy.items():
        print(f"strain energy density, {name:18s}: {value:.9f} MPa")
    spread = max(energy.values()) - min(energy.values())

    sigma = np.array([[3.0, 1.0, 0.0], [1.0, -2.0, 0.5], [0.0, 0.5, 1.0]])
    quadrature = T.sphere_average(lambda n: np.einsum("mi,mj,mk,ml,kl->mij", n, n, n, n, sigma), degree=4)
    moment = np.abs(quadrature - T.fourth_moment_contraction(sigma)).max()
    print(f"Eq. (5.18), the sphere average of (n x n x n x n) : sigma, quadrature against the closed form: "
          f"{moment:.1e}")

    split = np.abs(T.positive_part(eps) + T.negative_part(eps) - eps).max()
    print(f"eps+ + eps- - eps (Eq. 6.57): {split:.1e}")
    checks = {"energy_spread": spread / energy["tensor"], "fourth_moment": moment, "split": split}
    path = write_json(Path(outdir) / "tensors.json", {"strain_energy_MPa": energy, "checks": checks})
    print(f"written: {path}")
    return checks


if __name__ == "__main__":
    main(*sys.argv[1:])
