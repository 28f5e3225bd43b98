"""The constitutive tests of seed 002, Sec. 4: one bond in pure tension or pure shear (Figs. 6–11).

*Monotonic*: the displacement of the loaded direction grows in small steps; the other stress is zero (in pure
shear the normal displacement is free, so the dilatant plastic flow opens the contact without normal stress).
*Cyclic*: the stress of the loaded direction cycles between ``stress_min`` and ``stress_max`` (20–60 kPa in the
paper). Below the yield surface a cycle is elastic with the stiffness k(1 − D), so its path is known in closed form;
at the onset of unloading the fatigue criterion (Eq. 23) is checked at the cycle's peak stress and, if exceeded,
Paris' law (Eq. 27) raises D and the fatigue displacements grow (Eqs. 35–37). The stress stays at its peak while the
displacement moves (stress control); under displacement control the same update is Eq. (38, 39), see
:func:`abrakit.fatigue.bond_law.bond_stresses`. Cycling stops once D reaches ``target_damage`` (0.4 in the paper);
the bond is then loaded monotonically to failure.

With ``jump`` = ΔD_jump > 0 every simulated cycle stands for N_jump cycles (Eqs. 40, 41).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from abrakit.fatigue.bond_law import FAILURE_DAMAGE, BondParameters, criterion, plastic_return
from abrakit.fatigue.paris import cycle_update
from abrakit.validation import (
    check_integer,
    check_number_fields,
    check_option,
    check_positive,
    check_range,
    number_arguments,
)

MODES = ("tension", "shear")


@dataclass
class BondTest:
    """State and records of one bond under pure tension or pure shear.

    ``u``, ``up``, ``uf``: total, plastic and fatigue displacements (normal, shear) [m]; ``damage`` D. The records
    hold the loaded direction's displacement and stress along the path (``displacement``, ``stress``), and per
    simulated cycle the cycle count N, the damage after the cycle and the fatigue displacement (``cycles``,
    ``cycle_damage``, ``cycle_fatigue``)."""

    p: BondParameters
    mode: str
    u: np.ndarray = field(default_factory=lambda: np.zeros(2))
    up: np.ndarray = field(default_factory=lambda: np.zeros(2))
    uf: np.ndarray = field(default_factory=lambda: np.zeros(2))
    damage: float = 0.0
    displacement: list = field(default_factory=list)
    stress: list = field(default_factory=list)
    cycles: list = field(default_factory=list)
    cycle_damage: list = field(default_factory=list)
    cycle_fatigue: list = field(default_factory=list)

    def __post_init__(self):
        if not isinstance(self.p, BondParameters):
            raise TypeError(f"p must be a BondParameters, got {self.p!r}")
        check_number_fields(self)
        check_option("mode", self.mode, MODES)
        self.damage = self.p.initial_damage
        self._record(0.0)

    @property
    def axis(self) -> int:
        return 0 if self.mode == "tension" else 1

    @property
    def stiffness(self) -> float:
        return self.p.kn if self.mode == "tension" else self.p.ks

    @property
    def intact_strength(self) -> float:
        """The undamaged yield surface on the loaded axis, Eq. (18) with the other stress zero: σ_t in tension, c
        in shear [Pa]."""
        return self.p.tensile_strength if self.mode == "tension" else self.p.cohesion

    @property
    def strength(self) -> float:
        """The damaged yield surface on the loaded axis, (1 − D) times :attr:`intact_strength` [Pa]."""
        return (1.0 - self.damage) * self.intact_strength

    def failure_damage(self, stress: float) -> float:
        """The damage at which a peak ``stress`` on the loaded axis reaches the yield surface, 1 − σ/σ_t in tension
        and 1 − σ/c in shear (where :attr:`strength` equals ``stress``)."""
        return 1.0 - stress / self.intact_strength

    @property
    def simulated_cycles(self) -> int:
        """Cycles actually simulated (each one stands for a whole jump when the cycle jump is on)."""
        return len(self.cycles)

    def _record(self, stress):
        self.displacement.append(float(self.u[self.axis]))
        self.stress.append(float(stress))

    def _set_stress(self, stress):
        """Move the loaded displacement elastically to ``stress`` (the normal one follows its irreversible part in
        pure shear)."""
        k = self.axis
        self.u[k] = self.up[k] + self.uf[k] + stress / (self.stiffness * (1.0 - self.damage))
        if self.mode == "shear":
            self.u[0] = self.up[0] + self.uf[0]
        self._record(stress)

    def load(self, increment: float):
        """One displacement-controlled step of the loaded direction, with the plastic return (Eqs. 15–22)."""
        k = self.axis
        self.u[k] += increment
        elastic = self.u - self.up - self.uf
        if self.mode == "tension":
            dn, ds, d, sn, ss = plastic_return(elastic[0], 0.0, self.damage, self.p)
            stress = sn[0]
        else:
            dn, ds, d, sn, ss = plastic_return(0.0, elastic[1], self.damage, self.p, normal_stress=0.0)
            stress = ss[0]
        self.up += (dn[0], ds[0])
        if self.mode == "shear":
            self.u[0] = self.up[0] + self.uf[0]
        self.damage = float(d[0])
        self._record(stress)
        return stress

    def cycle(self, stress_min: float, stress_max: float, jump: float | None = None, max_cycles=None,
              limit: float | None = None) -> bool:
        """One load cycle (or one cycle jump); returns False, doing nothing, if its peak reaches the yield surface.

        A jump ends before the cycle in which the damage would reach ``limit``, by default (and at most) the failure
        damage of the peak (the cycle that fails the bond is simulated, not jumped over). The stress recorded at the
        peak after the damage update is held on the damaged yield surface if the update took the surface below the
        peak (the bond fails in that cycle)."""
        peak = (stress_max, 0.0) if self.mode == "tension" else (0.0, stress_max)
        if criterion(*peak, self.damage, self.p) >= 0.0:
            return False
        self._set_stress(stress_min)
        self._set_stress(stress_max)
        low = (stress_min, 0.0) if self.mode == "tension" else (0.0, stress_min)
        n, increment, dn, ds, _ = cycle_update(self.damage, peak, low, self.p, jump=jump, max_cycles=max_cycles,
                                               limit=min(self.failure_damage(stress_max), 1.0 if limit is None
                                                         else float(limit)))
        if increment > 0.0:                                 # at the onset of unloading (Sec. 3.2)
            self.uf += (float(dn), float(ds))
            self.damage += float(increment)
            self._set_stress(min(stress_max, self.strength))
        self._set_stress(stress_min)
        self.cycles.append((self.cycles[-1] if self.cycles else 0) + n)
        self.cycle_damage.append(self.damage)
        self.cycle_fatigue.append(float(self.uf[self.axis]))
        return True


def monotonic_test(p: BondParameters, mode: str, *, increment=2e-7, until_damage=FAILURE_DAMAGE, max_steps=100_000,
                   test: BondTest | None = None) -> BondTest:
    """Monotonic pure tension or pure shear under displacement control until D ≥ ``until_damage`` (by default the
    failure damage, :data:`~abrakit.fatigue.bond_law.FAILURE_DAMAGE`: the bond is broken)."""
    check_positive("increment", increment)
    check_range("until_damage", until_damage, 0.0, 1.0, low_open=True, high_open=True)
    test = BondTest(p, mode) if test is None else test
    for _ in range(max_steps):
        if test.damage >= until_damage:
            return test
        test.load(increment)
    raise RuntimeError(f"monotonic {mode} test reached max_steps={max_steps} at D = {test.damage:.4f}; "
                       f"raise increment or max_steps")


@number_arguments
def cyclic_test(p: BondParameters, mode: str, *, stress_min: float = 20e3, stress_max: float = 60e3,
                target_damage: float = 0.4, jump: float | None = None, to_failure=True, increment: float = 2e-7,
                max_cycles: int = 1_000_000) -> BondTest:
    """Cyclic stress between ``stress_min`` and ``stress_max`` until D ≥ ``target_damage``, then (``to_failure``)
    monotonic displacement control to failure. ``jump`` = ΔD_jump switches the cycle jump on (Eqs. 40, 41).

    No jump passes the cycle that ends the cyclic phase: it stops before the cycle in which D would reach the
    target or the peak's failure damage, whichever is lower, and that cycle is simulated. The programme then ends in
    the same cycle with and without the jump, and in tension and shear alike (their damage histories coincide,
    Sec. 4.2, while their failure damages differ: 1 − σ/σ_t and 1 − σ/c)."""
    check_positive("stress_max", stress_max)
    check_range("stress_min", stress_min, 0.0, stress_max, high_open=True)
    check_positive("increment", increment)
    check_integer("max_cycles", max_cycles, 1)
    check_range("target_damage", target_damage, p.initial_damage, 1.0, low_open=True, high_open=True)
    if jump is not None:
        check_positive("jump", jump)
    test = BondTest(p, mode)
    while test.damage < target_damage:
        done = test.cycles[-1] if test.cycles else 0
        if done >= max_cycles or not test.cycle(stress_min, stress_max, jump, max_cycles - done,
                                                limit=target_damage):
            break
        if test.cycle_damage[-1] <= (test.cycle_damage[-2] if len(test.cycle_damage) > 1 else p.initial_damage):
            break                                                     # below the fatigue threshold: no growth
    if to_failure:
        monotonic_test(p, mode, increment=increment, test=test)
    return test


def softening_energy(p: BondParameters, mode: str) -> float:
    """Closed-form energy per area [J/m²] dissipated by a monotonic test to failure.

    Tension: σ_t(1 − D₀)(ū_n + σ_t / 2k_n). Shear at σ_n = 0: on the yield surface σ_s = c(1 − D) and the flow
    rule gives Δu_nᵖ = tan ψ Δu_sᵖ, so D = 1 − (1 − D₀) exp[−u_sᵖ (1/ū_s + tan ψ/ū_n)] and the energy is
    c(1 − D₀)[1/(1/ū_s + tan ψ/ū_n) + c / 2k_s]. In both the elastic displacement stays at strength/k while the
    stress softens, and the elastic energy at the peak is released too (all of it is dissipated at D = 1)."""
    check_option("mode", mode, MODES)
    intact = 1.0 - p.initial_damage
    if mode == "tension":
        return intact * p.tensile_strength * (p.un + p.tensile_strength / (2.0 * p.kn))
    return intact * p.cohesion * (1.0 / (1.0 / p.us + p.tan_psi / p.un) + p.cohesion / (2.0 * p.ks))


@number_arguments
def jump_reduction_percent(p: BondParameters, jump: float, *, mode: str = "tension",
                           stress_max: float = 60e3) -> float:
    """The paper's measure of the cycle jump's saving (Sec. 4.1: the jumps 0.005 and 0.01 "reduce the simulated
    cycles by 388.8 % and 797.4 %"): 100 × simulated cycles without the jump / simulated cycles with it, on the
    0 → ``stress_max`` cycle up to D = 0.4 (decisions "cycle counts of Fig. 11" and "cycle jump count")."""
    check_positive("jump", jump)
    runs = [cyclic_test(p, mode, stress_min=0.0, stress_max=stress_max, to_failure=False, jump=j)
            for j in (None, jump)]
    return 100.0 * runs[0].simulated_cycles / runs[1].simulated_cycles
