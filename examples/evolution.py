"""A 1D damage point under cyclic strain, rate-independent and rate-dependent (Ch. 2.6), saved as CSV.

    python examples/evolution.py [outdir]
"""

import sys
from pathlib import Path

import numpy as np

from abrakit import evolution as ev
from abrakit.io import CurveWriter


def main(outdir="results/examples"):
    model = ev.Damage1D(E=200e3, damage_function="exp")                  # MPa
    t = np.linspace(0.0, 4.0, 401)
    strain = 1e-3 * np.abs(np.sin(np.pi * t / 2)) * (1 + t / 2)
    results = {}
    for label, dissipation in (("rate-independent", ev.rate_independent(0.05)),
                               ("rate-dependent", ev.elasto_viscoplastic(0.05, 0.5))):
        run = ev.simulate(model, strain, t, dissipation, scheme="implicit")
        results[label] = run
        path = Path(outdir) / f"damage_1d_{label}.csv"
        with CurveWriter(path, ["time", "strain", "stress", "d"]) as out:
            for row in zip(run["time"], run["strain"], run["stress"], run["d"], strict=True):
                out.write(**dict(zip(("time", "strain", "stress", "d"), row, strict=True)))
        print(f"{label:17s}: final d = {run['d'][-1]:.3f}, peak stress = {run['stress'].max():.2f} MPa -> {path}")
    return results


if __name__ == "__main__":
    main(*sys.argv[1:])
