"""Recompute Table 8.4 of the seed (ASTM G65, quartz 100/200 um mixtures) and save it as CSV.

    python examples/wear.py [outdir]
"""

import sys
from pathlib import Path

from abrakit import wear
from abrakit.io import CurveWriter


def main(outdir="results/examples"):
    table = wear.astm_g65_table()
    path = Path(outdir) / "table_8_4.csv"
    with CurveWriter(path, ["theta_200um", "seed_e7_m3_per_s", "ours_e7_m3_per_s", "deviation_percent"]) as out:
        for theta, seed, ours, dev in zip(table["theta_coarse"], table["seed"], table["ours"], table["deviation"],
                                          strict=True):
            out.write(theta_200um=theta, seed_e7_m3_per_s=seed * 1e7, ours_e7_m3_per_s=ours * 1e7,
                      deviation_percent=100 * dev)
    print(f"{'material':32s} {'seed':>6s} {'ours':>7s} {'dev %':>6s}   [1e-7 m3/s]")
    for label, seed, ours, dev in zip(table["label"], table["seed"], table["ours"], table["deviation"], strict=True):
        print(f"{label:32s} {seed * 1e7:6.2f} {ours * 1e7:7.3f} {100 * dev:+6.2f}")
    print(f"written: {path}")
    return table


if __name__ == "__main__":
    main(*sys.argv[1:])
