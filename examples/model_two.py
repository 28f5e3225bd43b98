"""Model II (Ch. 6.3): the double-notched strip on about 300 elements, with the rate limit alpha = 0.005.

    python examples/model_two.py [outdir]

Writes the run to ``<outdir>/model_two/`` (``force_displacement.csv``, one row per converged step; ``summary.json``; a
checkpoint from which a killed run resumes) and prints the peak and the energy balance: the external work equals
the stored plus the dissipated energy up to the balance error.
"""

import sys
from pathlib import Path

from abrakit import damage
from abrakit.damage import run_model_two


def main(outdir="results/examples"):
    specimen = damage.specimen("double_notched", 300)
    result = run_model_two(specimen, alpha=0.005, steps=100, stop_fraction=0.05, output=Path(outdir) / "model_two",
                           resume=True)
    peak, u_peak = result.peak()
    summary = result.summary()
    print(f"{result.elements} elements: peak {peak:.0f} N at u = {u_peak:.4f} mm, {result.status} after "
          f"{result.steps} steps; external work {summary['external_work_Nmm']:.1f} N mm, dissipated "
          f"{result.dissipated_energy:.1f} N mm, balance error {summary['energy_error_Nmm']:.2f} N mm")
    print(f"written: {Path(outdir) / 'model_two'}")
    return {"peak": peak, "work": summary["external_work_Nmm"], "balance_error": summary["energy_error_Nmm"]}


if __name__ == "__main__":
    main(*sys.argv[1:])
