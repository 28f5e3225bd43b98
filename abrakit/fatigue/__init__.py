"""Fatigue of cemented bonds (seed 002, Nguyen et al. 2018): a damage-plasticity bond, Paris-law fatigue damage
updated once per load cycle, and the cycle jump.

=========================  =========================================================================
:mod:`.bond_law`           parameters, yield and fatigue criteria, stresses, damage, plastic return
:mod:`.paris`              geometric factor, stress-intensity range, Paris increment, cycle jump
:mod:`.single_bond`        the constitutive tests of Sec. 4 (pure tension / pure shear)
=========================  =========================================================================
"""

from __future__ import annotations

from abrakit.fatigue.bond_law import BondParameters, criterion
from abrakit.fatigue.paris import geometric_factor
from abrakit.fatigue.single_bond import BondTest, cyclic_test, monotonic_test, softening_energy

__all__ = [
    "BondParameters", "criterion", "geometric_factor",
    "monotonic_test", "cyclic_test", "BondTest", "softening_energy",
]
