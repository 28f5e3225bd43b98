"""Comparing the models (Ch. 7): Model I and Model II on the same double-notched strip, weak and strong.

    python examples/comparison.py [outdir]

Runs both models with the book's two regularisations on about 250 elements (plane strain times 3 mm) until the
force falls to 10 % of its peak, writes ``comparison.csv`` (peak, work, steps and time per run) and
``comparison_<model>_<strength>.csv`` (the force-displacement curves).
"""

import sys
from pathlib import Path

from abrakit import damage
from abrakit.damage import REGULARISATION, run_specimen, specimen
from abrakit.io import CurveWriter


def main(outdir="results/examples", elements=250):
    sp = specimen("double_notched", elements)
    rows = []
    for model in ("I", "II"):
        for strength, parameter in REGULARISATION[model].items():
            run = run_specimen(sp, model, parameter, step=0.002, stop_fraction=0.1)
            with CurveWriter(Path(outdir) / f"comparison_{model}_{strength}.csv", ["u_mm", "F_N"]) as out:
                for u, F in zip(run.u, run.F, strict=True):
                    out.write(u_mm=u, F_N=F)
            rows.append({"model": model, "strength": strength, "parameter": parameter, "peak_N": float(run.F.max()),
                         "work_Nmm": damage.path_work(run.u, run.F), "status": run.status, "steps": run.steps,
                         "seconds": run.seconds})
            print(f"Model {model:2s} {strength:6s} ({parameter:g}): peak {run.F.max():6.0f} N, work "
                  f"{rows[-1]['work_Nmm']:6.1f} N mm, {run.status} after {run.steps} steps, {run.seconds:.1f} s")
    path = Path(outdir) / "comparison.csv"
    with CurveWriter(path, list(rows[0])) as out:
        for row in rows:
            out.write(**row)
    print(f"written: {path}")
    return rows


if __name__ == "__main__":
    main(*sys.argv[1:])
