"""The G65 loss with the wheel's 130 N shared over its grains: every grain's force, D_p and groove, saved as CSV,
with the loss bracket a single pass allows (nothing removed, every groove cut out).

    python examples/material_removal.py [outdir]
"""

import sys
from pathlib import Path

import numpy as np

from abrakit import g65
from abrakit.io import CurveWriter


def main(outdir="results/examples", D=256e-6):
    every = g65.balanced_loss(D, g65.STEEL_CONTACT_PRESSURE, np.ones_like)
    none = g65.balanced_loss(D, g65.STEEL_CONTACT_PRESSURE, np.zeros_like)
    path = Path(outdir) / "g65_grains.csv"
    with CurveWriter(path, ["force_mN", "D_p", "groove_area_um2"]) as out:
        for F, D_p, A in zip(every.forces, every.depth_ratio, every.groove_area, strict=True):
            out.write(force_mN=F * 1e3, D_p=D_p, groove_area_um2=A * 1e12)
    print(f"{every.forces.size} grains of D = {D * 1e6:.0f} um carry {every.forces.sum():.1f} N, "
          f"{every.forces.min() * 1e3:.1f}-{every.forces.max() * 1e3:.1f} mN each, D_p up to "
          f"{every.depth_ratio.max():.4f}")
    print(f"Procedure A loss: {none.loss_mm3:g} mm3 if one pass removes nothing, {every.loss_mm3:.0f} mm3 if "
          "every groove were cut out")
    print(f"written: {path}")
    return every, none


if __name__ == "__main__":
    main(*sys.argv[1:])
