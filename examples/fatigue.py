"""Fatigue of one cemented bond (seed 002, Sec. 4): monotonic work against the closed form, cycles to a damage.

    python examples/fatigue.py [outdir]

Writes ``bond_tension.csv`` (the monotonic tension test: opening and stress) and prints the work to failure in
tension and shear against the area under the softening law, and the cycles of a 20-60 kPa tension loading to
D = 0.4, computed cycle by cycle and with the cycle jump.
"""

import sys
from pathlib import Path

from abrakit.damage import path_work
from abrakit.fatigue import BondParameters, cyclic_test, monotonic_test, softening_energy
from abrakit.io import CurveWriter


def main(outdir="results/examples"):
    p = BondParameters()                                                      # Table 1 of seed 002
    errors = {}
    for mode in ("tension", "shear"):
        test = monotonic_test(p, mode)
        work = path_work(test.displacement, test.stress)
        errors[mode] = work / softening_energy(p, mode) - 1.0
        print(f"monotonic {mode}: peak {max(test.stress) / 1e3:.2f} kPa, work to failure {work:.4f} J/m2 "
              f"(closed form {softening_energy(p, mode):.4f}, {100 * errors[mode]:+.2f} %)")
        if mode == "tension":
            path = Path(outdir) / "bond_tension.csv"
            with CurveWriter(path, ["opening_m", "stress_Pa"]) as out:
                for u, s in zip(test.displacement, test.stress, strict=True):
                    out.write(opening_m=u, stress_Pa=s)
    full = cyclic_test(p, "tension", to_failure=False)
    jumped = cyclic_test(p, "tension", to_failure=False, jump=0.005)
    print(f"20-60 kPa tension cycles to D = 0.4: {full.cycles[-1]} cycle by cycle, {jumped.cycles[-1]} with the "
          f"cycle jump ({jumped.simulated_cycles} simulated)")
    print(f"written: {path}")
    return {"work_error": errors, "cycles": full.cycles[-1], "jumped_cycles": jumped.cycles[-1]}


if __name__ == "__main__":
    main(*sys.argv[1:])
