"""Fatigue of cemented bonds (seed 002, Nguyen et al. 2018): a damage-plasticity bond, Paris-law fatigue damage
updated once per load cycle, and the cycle jump.

=========================  =========================================================================
:mod:`.bond_law`           parameters, yield and fatigue criteria, stresses, damage, plastic return
:mod:`.paris`              geometric factor, stress-intensity range, Paris increment, cycle jump
:mod:`.single_bond`        the constitutive tests of Sec. 4 (pure tension / pure shear)
=========================  =========================================================================
"""

from __future__ import annotations

from abrakit.fatigue.bond_law import (
    BondParameters,
    bond_stresses,
    criterion,
    damage_after,
    flow_direction,
    plastic_return,
)
from abrakit.fatigue.paris import (
    cycle_jump,
    cycle_update,
    fatigue_displacements,
    geometric_factor,
    paris_increment,
    stress_intensity_range,
    tensile_part,
)
from abrakit.fatigue.single_bond import BondTest, cyclic_test, jump_reduction_percent, monotonic_test, softening_energy

__all__ = ["BondParameters", "BondTest", "bond_stresses", "criterion", "cycle_jump", "cycle_update", "cyclic_test",
           "damage_after", "demo", "fatigue_displacements", "flow_direction", "geometric_factor",
           "jump_reduction_percent", "monotonic_test",
           "paris_increment", "plastic_return", "softening_energy", "stress_intensity_range", "tensile_part"]


def demo() -> str:
    """The constitutive tests of seed 002 Sec. 4 against their closed forms and the paper's cycle counts."""
    p = BondParameters()
    lines = ["Fatigue of cemented bonds (seed 002): one bond, Table 1"]
    for mode in ("tension", "shear"):
        t = monotonic_test(p, mode)
        work = sum(0.5 * (a + b) * (v - u) for a, b, u, v in
                   zip(t.stress, t.stress[1:], t.displacement, t.displacement[1:], strict=False))
        lines.append(f"monotonic {mode}: peak {max(t.stress) / 1e3:.2f} kPa, work to failure {work:.4f} J/m² "
                     f"(closed form {softening_energy(p, mode):.4f})")
    full = cyclic_test(p, "tension", to_failure=False)
    jumped = cyclic_test(p, "tension", to_failure=False, jump=0.005)
    lines.append(f"20-60 kPa cycles, D 0.01 -> 0.4: {full.cycles[-1]} cycles; with the cycle jump 0.005: "
                 f"{jumped.simulated_cycles} simulated for {jumped.cycles[-1]}")
    for m, paper in ((0.8, 2008), (1.2, 50)):
        n = cyclic_test(p.replace(paris_exponent=m), "tension", stress_min=0.0, to_failure=False).cycles[-1]
        lines.append(f"m = {m}: {n} cycles with a 0-60 kPa range (paper: {paper})")
    return "\n".join(lines)
