"""Paris-law fatigue damage of a bond, once per load cycle, and the cycle jump (seed 002, Eqs. 24–41).

The crack in a bond of width L is l = D L (Eq. 25), so Paris' law dl/dN = C ΔKᵐ (Eq. 24) becomes

    ΔD_f / ΔN = (C / L) ΔKᵐ,                                                                     (Eq. 27)
    ΔK = Y(D) √(π L D) √(Δσ_n² + Δσ_s²),                                                          (Eqs. 28–33)
    Y(D) = (1 − 0.025 D² + 0.06 D⁴) √sec(π D / 2)                                                 (Eq. 31, 34)

Y is Feddersen's form of the centre-cracked strip factor tabulated by Tada et al. (1973), accurate to 0.1 % for
any crack-to-width ratio; the extraction lost its square root, which we restore from that source (decision
"geometric factor, Eq. 31"). The crack is closed in compression, so the mode I range counts only the tensile part
of the cycle, Δσ_n = ⟨σ_n^max⟩ − ⟨σ_n^min⟩ (decision "mode I range").

The fatigue damage increment is converted into fatigue displacements with the damage law of
:mod:`abrakit.fatigue.bond_law`: |Δu_nᶠ|/ū_n + |Δu_sᶠ|/ū_s = −ln[(1 − D − ΔD_f)/(1 − D)] (Eq. 36 with χ = 1 − D),
split in the ratio of the fatigue flow direction Δu_nᶠ / |Δu_sᶠ| = tan ψ [a c (1 − D) − σ_n tan ψ] / |σ_s| (Eq. 37).

The cycle jump (Eqs. 40, 41) skips N_jump ≈ ΔD_jump / max ΔD_f cycles and extrapolates every bond's damage over
them with its stress range frozen: ΔD_f^j = [Y_j √D_j / (Y_1 √D_1)]ᵐ ΔD_f^1, which is Eq. (27) iterated.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from abrakit.fatigue.bond_law import BondParameters, _criterion, criterion, damage_after, flow_direction
from abrakit.validation import check_finite, check_positive, check_range, number_arguments


def geometric_factor(damage):
    """Y(D) of the centre-cracked strip, crack-to-width ratio D (Eq. 31, 34; Tada et al. 1973)."""
    d = check_range("damage", damage, 0.0, 1.0, high_open=True)
    return (1.0 - 0.025 * d**2 + 0.06 * d**4) * np.sqrt(1.0 / np.cos(0.5 * np.pi * d))


@number_arguments
def tensile_part(sigma: ArrayLike):
    """⟨σ⟩ = max(σ, 0): a closed crack sees no mode I loading."""
    return np.maximum(sigma, 0.0)


def stress_intensity_range(damage, range_n, range_s, p: BondParameters, width=None):
    """Mixed-mode ΔK = Y(D) √(π L D) √(Δσ_n² + Δσ_s²) [Pa √m] (Eqs. 28–33); ``width`` L defaults to
    ``p.width`` (one value per bond in a DEM assembly)."""
    damage = np.asarray(damage, float)
    width = p.width if width is None else check_positive("width", width)
    range_n, range_s = check_finite("range_n", range_n), check_finite("range_s", range_s)
    return geometric_factor(damage) * np.sqrt(np.pi * width * damage) * np.hypot(range_n, range_s)


def paris_increment(damage, range_n, range_s, p: BondParameters, width=None):
    """Fatigue damage of one load cycle, ΔD_f = (C/L) ΔKᵐ (Eq. 27), capped so that D + ΔD_f ≤ 1."""
    width = p.width if width is None else check_positive("width", width)
    rate = p.paris_coefficient / width * stress_intensity_range(damage, range_n, range_s, p, width) ** p.paris_exponent
    return np.minimum(rate, 1.0 - np.asarray(damage, float))


@number_arguments
def fatigue_displacements(damage: ArrayLike, increment: ArrayLike, sigma_n: ArrayLike, sigma_s: ArrayLike,
                          p: BondParameters):
    """Normal and shear fatigue displacements (Δu_nᶠ, Δu_sᶠ) [m] that raise D by ``increment`` (Eqs. 35–37).

    The shear displacement has the sign of σ_s; at σ_s = 0 (pure mode I) all of it is normal."""
    damage, increment = np.asarray(damage, float), np.asarray(increment, float)
    with np.errstate(divide="ignore"):
        kappa = -np.log1p(-increment / (1.0 - damage))            # Δκ of Eq. (36)
    ratio_n, ratio_s = flow_direction(sigma_n, sigma_s, damage, p, level=p.threshold)
    ratio_n, ratio_s = np.abs(ratio_n), np.abs(ratio_s)            # Δu_nᶠ : |Δu_sᶠ| (Eq. 37), ψ > 0
    ratio_n, ratio_s, kappa = np.broadcast_arrays(ratio_n, ratio_s, kappa)
    denominator = ratio_n / p.un + ratio_s / p.us
    scale = np.divide(kappa, denominator, out=np.zeros(np.shape(kappa)), where=denominator > 0)
    return ratio_n * scale, np.sign(sigma_s) * ratio_s * scale


@number_arguments
def peak_failure_damage(damage: ArrayLike, sigma_n: ArrayLike, sigma_s: ArrayLike, p: BondParameters):
    """The damage D* ≥ D at which the damaged yield surface (Eq. 18) shrinks onto the stress (σ_n, σ_s), held fixed:
    F(σ_n, σ_s, D*) = 0; D itself where the stress lies on or outside the surface, 1 where no damage reaches it (a
    compressed bond whose friction alone carries its shear, α|σ_s| ≤ −σ_n tan φ).

    At a fixed stress F is, on the physical branch, a downward parabola in the intact fraction I = 1 − D with
    F(I = 0) = α²σ_s² + σ_n tan φ |σ_n tan φ|: where that is positive and F(1 − D) < 0 the parabola has exactly one
    root between, found by bisection on I (to round-off). Pure tension gives 1 − σ_n/σ_t, pure shear 1 − |σ_s|/c."""
    damage = np.asarray(damage, float)
    sigma_n, sigma_s = np.broadcast_arrays(np.asarray(sigma_n, float), np.asarray(sigma_s, float))
    shape = np.broadcast_shapes(damage.shape, sigma_n.shape)
    low, high = np.zeros(shape), np.broadcast_to(1.0 - damage, shape).copy()   # F(low) > 0 > F(high)
    inside = _criterion(sigma_n, sigma_s, 1.0 - high, p) < 0.0
    reached = _criterion(sigma_n, sigma_s, np.ones(shape), p) > 0.0
    for _ in range(80):
        middle = 0.5 * (low + high)
        outside = _criterion(sigma_n, sigma_s, 1.0 - middle, p) >= 0.0
        low, high = np.where(outside, middle, low), np.where(outside, high, middle)
    return np.where(inside, np.where(reached, 1.0 - high, 1.0), np.broadcast_to(damage, shape))


@number_arguments
def cycle_jump(damage: ArrayLike, increment: ArrayLike, jump: float, *, max_cycles: float | None = None,
               exponent: float | None = None, other_rate: float = 0.0, limit: ArrayLike | None = None):
    """Cycle jump (Eqs. 40, 41): ``(n_jump, total_increment)`` for bonds whose first-cycle increments ΔD_f¹ are
    ``increment`` at damage ``damage``.

    N_jump = ΔD_jump / max ΔD_f¹ rounded to the nearest integer (at least 1, at most ``max_cycles``); rounding is
    what reproduces the paper's cycle-jump counts (decision "cycle jump count"). ``other_rate`` is the largest damage
    per cycle from other mechanisms that the caller extrapolates over the same jump (plastic ratcheting): N_jump
    then bounds the damage any bond gains from either. Every bond's damage is advanced by Eq. (41),
    ΔD_f^j = [Y(D_j) √D_j / (Y(D_1) √D_1)]ᵐ ΔD_f¹ for j = 1 … N_jump, with D_j = D_1 + Σ_{i<j} ΔD_f^i, a bond at
    D → 1 being capped there. ``exponent`` is Paris' m.

    ``limit`` (per bond, or one value): the failure damage, where the bond's peak stress reaches its damaged yield
    surface. The jump then ends before the cycle in which a bond would pass it: that cycle is left to be simulated
    (its first cycle, N_jump = 1, always is), so a jump never skips the cycle that fails a bond.
    """
    jump = check_positive("jump", jump)
    if exponent is None:
        raise TypeError("cycle_jump needs the Paris exponent (exponent=m)")
    damage = np.atleast_1d(np.asarray(damage, float))
    increment = np.atleast_1d(np.asarray(increment, float))
    largest = max(float(np.max(increment)) if increment.size else 0.0, float(other_rate))
    if largest <= 0.0:
        return 1, increment.copy()
    n_jump = max(1, round(jump / largest))
    if max_cycles is not None:
        n_jump = max(1, min(n_jump, int(max_cycles)))
    growing = increment > 0.0
    reference = np.where(growing, geometric_factor(damage) * np.sqrt(damage), 1.0)
    limit = None if limit is None else np.broadcast_to(np.asarray(limit, float), damage.shape)
    d = damage.copy()
    for j in range(n_jump):
        factor = geometric_factor(np.minimum(d, 1.0 - 1e-12)) * np.sqrt(d) / reference
        after = np.minimum(d + np.where(growing, factor**exponent * increment, 0.0), 1.0)
        if j > 0 and limit is not None and np.any(growing & (after >= limit)):
            return j, d - damage                                  # the failing cycle is simulated, not jumped
        d = after
    return n_jump, d - damage


@number_arguments
def cycle_update(damage: ArrayLike, peak, low, p: BondParameters, *, width=None, eligible=True,
                 jump: float | None = None, max_cycles: float | None = None, ratchet=None,
                 limit: ArrayLike | None = None):
    """The fatigue update of one load cycle at the onset of its unloading (Sec. 3.2, Fig. 5), for bonds whose cycle
    ran between the stresses ``low`` = (σ_n, σ_s) and ``peak`` = (σ_n, σ_s).

    A bond is fatigued if it is ``eligible`` (it did not yield in the cycle: E = 1 in Eq. 17) and its peak exceeds
    the fatigue criterion (Eq. 23); it gains ΔD_f by Paris' law (Eq. 27) with the ranges peak − low (mode I: tensile
    parts), extrapolated by the cycle jump if ``jump`` is given (Eqs. 40, 41), and the fatigue displacements of
    Eqs. (35–37).

    ``ratchet`` (2, …): the plastic displacement magnitudes (normal, shear) each bond gained in the sampled cycle.
    With a jump of N cycles they are repeated in the N − 1 skipped cycles: those bonds gain the damage of Eq. (22)
    for (N − 1) × ``ratchet`` on top of their fatigue damage, and N_jump counts that damage rate (decision
    "ratcheting in the cycle jump"). Without ``ratchet`` (the paper) a yielding bond stands still during a jump.

    ``limit``: the damage each bond's jump must not pass, passed to :func:`cycle_jump` (the jump stops before the
    cycle in which a bond would reach it), e.g. :func:`peak_failure_damage` of the peaks; None: no limit.

    Returns ``(cycles, increment, du_n, du_s, skipped)``: the cycles represented, the damage increments, the
    fatigue displacements (zero for bonds that are not fatigued) and the plastic displacements (2, …) of the
    skipped cycles (zero without ``ratchet``)."""
    (peak_n, peak_s), (low_n, low_s) = peak, low
    damage = np.asarray(damage, float)
    fatigued = np.asarray(eligible) & (criterion(peak_n, peak_s, damage, p, level=p.threshold) >= 0.0)
    range_n = tensile_part(peak_n) - tensile_part(low_n)
    increment = np.where(fatigued, paris_increment(damage, range_n, np.abs(np.subtract(peak_s, low_s)), p, width),
                         0.0)
    ratchet_rate = 0.0
    if ratchet is not None:
        ratchet = np.abs(np.asarray(ratchet, float))
        if ratchet.shape != (2,) + damage.shape:
            raise ValueError(f"ratchet must have shape {(2,) + damage.shape}, got {ratchet.shape}")
        ratchet_rate = float(np.max(damage_after(damage, ratchet[0], ratchet[1], p) - damage, initial=0.0))
    cycles = 1
    if jump is not None and (np.any(fatigued) or ratchet_rate > 0.0):
        cycles, increment = cycle_jump(damage, increment, jump, max_cycles=max_cycles, exponent=p.paris_exponent,
                                       other_rate=ratchet_rate, limit=limit)
        increment = increment.reshape(np.shape(damage))
    du_n, du_s = fatigue_displacements(damage, increment, peak_n, peak_s, p)
    skipped = np.zeros((2,) + damage.shape)
    if ratchet is not None and cycles > 1:
        skipped = (cycles - 1) * ratchet
        increment = damage_after(damage + increment, skipped[0], skipped[1], p) - damage
    return cycles, increment, np.where(fatigued, du_n, 0.0), np.where(fatigued, du_s, 0.0), skipped
