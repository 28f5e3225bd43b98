"""The cohesive damage-plasticity bond of seed 002 (Nguyen et al. 2018, Sec. 3.1; after Nguyen et al. 2017b).

A bonded contact of width L carries a normal stress σ_n (tension positive) and a shear stress σ_s [Pa]. Its relative
displacement splits into elastic, plastic and fatigue parts, u = uᵉ + uᵖ + uᶠ (Eq. 14), and

    σ_n = k_n (1 − D) (u_n − u_nᵖ − u_nᶠ) − D k_n ⟨−(u_n − u_nᵖ − u_nᶠ)⟩                     (Eq. 15)
    σ_s = k_s (1 − D) (u_s − u_sᵖ − u_sᶠ)                                                      (Eq. 16)

so that a closed contact recovers its full normal stiffness. It yields on the hyperbola

    F = α² σ_s² − [c(1 − D) − σ_n tan φ]² + [(c − σ_t tan φ)(1 − D)]²,
    α = √(2 c σ_t tan φ − (σ_t tan φ)²) / c                                                     (Eq. 18)

whose apex is the tensile strength σ_t(1 − D) and which passes through the cohesion c(1 − D) at σ_n = 0. It flows
along the same hyperbola with the dilatancy angle ψ (Eq. 19, 20), and the fatigue criterion is the yield criterion
with c and σ_t scaled by the threshold a (Eq. 23).

Reconstructions (the extraction garbled Eqs. 18–22; each choice is a :mod:`abrakit.decisions` entry):

* ``α`` is read as √(2cσ_t tan φ − σ_t² tan² φ)/c: the only reading under which the criterion passes through both
  strengths the prose names (σ_t at σ_s = 0, c at σ_n = 0), pinned by
  ``test_yield_surface_passes_through_the_tensile_strength_and_the_cohesion``.
* The hyperbola has a second branch far on the tension side (σ_n tan φ > c(1 − D)) where F < 0 again. We evaluate
  F with −q|q| for −q² (q = c(1 − D) − σ_n tan φ): identical on the physical branch, positive beyond it, so a large
  tensile trial stress can never read as elastic.
* Damage (Eq. 17, 21, 22). Every irreversible displacement, plastic or fatigue, accumulates
  κ = Σ (|Δu_n| / ū_n + |Δu_s| / ū_s), and each increment raises D by ΔD = χ [1 − exp(−Δκ)] with χ = 1 − D. The
  printed χ = exp(−κ) telescopes to D = D₀ + 1 − e^{−κ}, which exceeds 1 for D₀ > 0; χ = 1 − D telescopes to
  D = 1 − (1 − D₀) e^{−κ}, the printed law when D₀ = 0, and keeps D in [D₀, 1) with the smooth cohesionless limit
  the paper describes.

All functions broadcast over bonds; stresses in Pa, displacements in m, stiffnesses per area in Pa/m.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike

from abrakit.validation import check_finite, check_number_fields, check_positive, check_range, number_arguments


@dataclass(frozen=True)
class BondParameters:
    """Parameters of the fatigue bond (seed 002, Table 1 by default; SI units).

    ``kn``, ``ks`` initial stiffness per area [Pa/m]; ``tensile_strength`` σ_t and ``cohesion`` c [Pa];
    ``un``, ``us`` softening displacements ū_n, ū_s [m]; ``friction_angle`` φ and ``dilatancy_angle`` ψ [°]
    (0 < ψ ≤ φ: at ψ = 0 the bond would not flow, hence not soften, at the tensile apex);
    ``paris_exponent`` m and ``paris_coefficient`` C [m/cycle per (Pa √m)^m] of Eq. (24); ``threshold`` a of the
    fatigue criterion (Eq. 23); ``width`` L of the contact [m]; ``initial_damage`` D₀ (the paper's 1 %).

    The threshold is not in the paper's Table 1. The prose requires a < 0.6 so that the 60 kPa cycles exceed the
    fatigue criterion in shear (c(1 − D₀) a < 60 kPa); the same cycles exceed it in tension only for
    a < 60/118.8 = 0.505, and the paper's statement that tension and shear fatigue histories coincide needs both.
    We take a = 0.5.
    """

    kn: float = 20e9
    ks: float = 10e9
    tensile_strength: float = 120e3
    cohesion: float = 100e3
    un: float = 2e-5
    us: float = 2e-5
    friction_angle: float = 10.0
    dilatancy_angle: float = 5.0
    paris_exponent: float = 1.0
    paris_coefficient: float = 1e-8
    threshold: float = 0.5
    width: float = 0.1
    initial_damage: float = 0.01

    def __post_init__(self):
        check_number_fields(self)
        for name in ("kn", "ks", "tensile_strength", "cohesion", "un", "us", "paris_exponent", "paris_coefficient",
                     "width"):
            check_positive(name, getattr(self, name))
        check_range("friction_angle", self.friction_angle, 0.0, 90.0, low_open=True, high_open=True)
        check_range("dilatancy_angle", self.dilatancy_angle, 0.0, self.friction_angle, low_open=True)
        check_range("threshold", self.threshold, 0.0, 1.0, low_open=True, high_open=True)
        check_range("initial_damage", self.initial_damage, 0.0, 1.0, low_open=True, high_open=True)
        if self.tensile_strength * self.tan_phi >= 2.0 * self.cohesion:
            raise ValueError(f"tensile_strength · tan(friction_angle) must stay below 2 · cohesion (else α² ≤ 0 in "
                             f"Eq. 18), got {self.tensile_strength * self.tan_phi:g} ≥ {2 * self.cohesion:g}")

    @property
    def tan_phi(self) -> float:
        return float(np.tan(np.radians(self.friction_angle)))

    @property
    def tan_psi(self) -> float:
        return float(np.tan(np.radians(self.dilatancy_angle)))

    @property
    def alpha(self) -> float:
        """α of Eq. (18): makes the criterion pass through the cohesion at σ_n = 0."""
        t = self.tensile_strength * self.tan_phi
        return float(np.sqrt(2.0 * self.cohesion * t - t * t) / self.cohesion)

    def replace(self, **changes) -> BondParameters:
        return BondParameters(**{**asdict(self), **changes})


def _yield(sigma_n, sigma_s, intact, p: BondParameters, level=1.0):
    """F of Eq. (18) (``level`` = 1) or F_f of Eq. (23) at the intact fraction ``intact`` = 1 − D, unchecked."""
    q = level * p.cohesion * intact - np.asarray(sigma_n, float) * p.tan_phi
    q0 = level * (p.cohesion - p.tensile_strength * p.tan_phi) * intact
    return p.alpha**2 * np.asarray(sigma_s, float) ** 2 - q * np.abs(q) + q0 * q0


def _flow(sigma_n, sigma_s, intact, p: BondParameters, level=1.0):
    """The flow direction of Eq. (19, 20) at the intact fraction ``intact`` = 1 − D, unchecked."""
    return (p.tan_psi * (level * p.cohesion * intact - np.asarray(sigma_n) * p.tan_psi), np.asarray(sigma_s, float))


def _stresses(elastic_n, elastic_s, intact, p: BondParameters, kn=None, ks=None):
    """(σ_n, σ_s) of Eq. (15, 16) at the intact fraction ``intact`` = 1 − D, unchecked."""
    kn, ks = (p.kn if kn is None else kn), (p.ks if ks is None else ks)
    elastic_n = np.asarray(elastic_n, float)
    return kn * np.where(elastic_n >= 0.0, intact, 1.0) * elastic_n, ks * intact * np.asarray(elastic_s, float)


def _criterion(sigma_n: ArrayLike, sigma_s: ArrayLike, damage: ArrayLike, p: BondParameters, level: ArrayLike = 1.0):
    """The kernel of :func:`criterion`, unchecked (the return map's Newton iterations call it)."""
    return _yield(sigma_n, sigma_s, 1.0 - np.asarray(damage, float), p, level)


def _flow_direction(sigma_n: ArrayLike, sigma_s: ArrayLike, damage: ArrayLike, p: BondParameters,
                    level: ArrayLike = 1.0):
    """The kernel of :func:`flow_direction`, unchecked (the return map's Newton iterations call it)."""
    return _flow(sigma_n, sigma_s, 1.0 - np.asarray(damage, float), p, level)


def _damage_after(damage: ArrayLike, du_n: ArrayLike, du_s: ArrayLike, p: BondParameters):
    """The kernel of :func:`damage_after`, unchecked (the return map's Newton iterations call it)."""
    damage = np.asarray(damage, float)
    return damage - (1.0 - damage) * np.expm1(-np.abs(du_n) / p.un - np.abs(du_s) / p.us)


def _bond_stresses(elastic_n: ArrayLike, elastic_s: ArrayLike, damage: ArrayLike, p: BondParameters,
                   kn: ArrayLike | None = None, ks: ArrayLike | None = None):
    """The kernel of :func:`bond_stresses`, unchecked (the return map's Newton iterations call it)."""
    return _stresses(elastic_n, elastic_s, 1.0 - np.asarray(damage, float), p, kn, ks)


# The public functions check their numbers (NaN and None refused by name); the return map's Newton iterations call
# the kernels above them, which trust their arrays.
@number_arguments
def criterion(sigma_n: ArrayLike, sigma_s: ArrayLike, damage: ArrayLike, p: BondParameters, level: ArrayLike = 1.0):
    """Yield function F (Eq. 18, ``level`` = 1) or fatigue criterion F_f (Eq. 23, ``level`` = a) [Pa²].

    ``level`` scales the cohesion and the tensile strength; F < 0 inside. Beyond the apex's far branch the
    function is continued monotonically (module docstring)."""
    return _criterion(sigma_n, sigma_s, damage, p, level)


@number_arguments
def flow_direction(sigma_n: ArrayLike, sigma_s: ArrayLike, damage: ArrayLike, p: BondParameters,
                   level: ArrayLike = 1.0):
    """Plastic flow direction (∂G/∂σ_n, ∂G/∂σ_s)/2 = (tan ψ [level·c(1 − D) − σ_n tan ψ], σ_s) (Eq. 19, 20; with
    ``level`` = a, the ratio of fatigue displacements of Eq. 37)."""
    return _flow_direction(sigma_n, sigma_s, damage, p, level)


@number_arguments
def damage_after(damage: ArrayLike, du_n: ArrayLike, du_s: ArrayLike, p: BondParameters):
    """Damage after irreversible displacement increments Δu_n, Δu_s (Eq. 21, 22 with χ = 1 − D, reconstructed):
    D' = 1 − (1 − D) exp(−|Δu_n|/ū_n − |Δu_s|/ū_s)."""
    return _damage_after(damage, du_n, du_s, p)


@number_arguments
def bond_stresses(elastic_n: ArrayLike, elastic_s: ArrayLike, damage: ArrayLike, p: BondParameters,
                  kn: ArrayLike | None = None, ks: ArrayLike | None = None):
    """(σ_n, σ_s) from the elastic displacements uᵉ = u − uᵖ − uᶠ (Eq. 15, 16): degraded stiffness in tension,
    full normal stiffness in compression. ``kn``, ``ks`` (per bond) replace ``p.kn``, ``p.ks`` if given."""
    return _bond_stresses(elastic_n, elastic_s, damage, p, kn, ks)


def _return_residual(y, trial_n, trial_s, damage, p, normal_stress, kn, ks, scale):
    """Residual of the plastic return in scaled unknowns y = (Δu_nᵖ/ū_n, Δu_sᵖ/ū_s, 2Δλ c/ū_s), shape (3, B);
    F is scaled by ``scale``² (:func:`_yield_scale`). The stresses, the flow and F take the intact fraction
    1 − D = (1 − D₀) exp(−κ) itself, not 1 minus the rounded damage: near D = 1 that difference would keep only
    the last digits of D (at 1 − D = 2·10⁻⁶, ten of sixteen), below what the tolerance and the difference
    Jacobian resolve."""
    a, b, lam = y
    kappa = np.abs(a) + np.abs(b)
    d = damage - (1.0 - damage) * np.expm1(-kappa)                # Eq. (21, 22), :func:`damage_after`
    intact = (1.0 - damage) * np.exp(-kappa)                      # 1 − D to full precision as D → 1
    if normal_stress is None:
        sigma_n, sigma_s = _stresses(trial_n - a * p.un, trial_s - b * p.us, intact, p, kn, ks)
    else:
        sigma_n = normal_stress
        sigma_s = ks * intact * (trial_s - b * p.us)
    g = lam * p.us / p.cohesion                                   # 2Δλ [m/Pa]
    flow_n, flow_s = _flow(sigma_n, sigma_s, intact, p)
    r = np.array([a - g * flow_n / p.un, b - g * flow_s / p.us, _yield(sigma_n, sigma_s, intact, p) / scale**2])
    return r, d, sigma_n, sigma_s


def _yield_scale(sigma_n, damage, p):
    """The size of the yield surface at a state [Pa]: the current cohesion c(1 − D) plus the friction that a
    compressive σ_n adds, −σ_n tan φ. F is measured against its square, so that the return's tolerance stays
    relative both as D → 1 and where a nearly broken bond carries shear by friction alone (the friction term then
    dominates by orders of magnitude and a cohesion-only scale would put the tolerance below round-off)."""
    return p.cohesion * (1.0 - damage) + p.tan_phi * np.maximum(-np.asarray(sigma_n, float), 0.0)


def _solve3(jac, rhs):
    """Solve B 3×3 systems; a singular one (a flat direction) gets the least-squares step."""
    try:
        return np.linalg.solve(jac, rhs[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:
        return np.einsum("bij,bj->bi", np.linalg.pinv(jac), rhs)


def _converged(r, sigma_n, damage, scale, p, tol):
    """Which bonds are on their surface: the flow-rule residuals and F below ``tol``, F measured against the square of
    the larger of the start state's surface (``scale``, the one the iteration uses) and the end state's. A return
    in compression can grow the surface by friction (a nearly broken bond whose dilatancy presses it shut: measured
    60 × at D = 1 − 1.8·10⁻⁶), and F, a difference of squares of the end state's size, then keeps round-off far
    above ``tol`` times the start's; the end state's size is the precision it can be held to."""
    larger = np.maximum(scale, _yield_scale(sigma_n, damage, p))
    return np.maximum(np.maximum(np.abs(r[0]), np.abs(r[1])), np.abs(r[2]) * (scale / larger) ** 2) < tol


def _newton(y, args, tol, max_iter):
    """Newton's method on :func:`_return_residual` with a forward-difference Jacobian per bond and a backtracking
    line search; returns the iterate and which bonds converged (:func:`_converged`)."""
    r, d, sn, _ = _return_residual(y, *args)
    for _ in range(max_iter):
        size = np.max(np.abs(r), axis=0)
        if np.max(size) < tol:
            break
        jac = np.empty((y.shape[1], 3, 3))
        for k in range(3):
            h = 1e-7 * np.maximum(np.abs(y[k]), 1e-6)
            shifted = y.copy()
            shifted[k] += h
            jac[:, :, k] = ((_return_residual(shifted, *args)[0] - r) / h).T
        step = _solve3(jac, -r.T).T
        t = np.ones(y.shape[1])                  # halve a bond's step until its residual decreases
        for _ in range(30):
            trial = y + t * step
            trial[0] = np.maximum(trial[0], 0.0)          # Δu_nᵖ ≥ 0 on the physical branch (ψ ≤ φ)
            trial[2] = np.maximum(trial[2], 0.0)
            r_trial, d, sn, _ = _return_residual(trial, *args)
            worse = ~(np.max(np.abs(r_trial), axis=0) < size)
            if not worse.any():
                break
            t = np.where(worse, 0.5 * t, t)
        y, r = trial, r_trial
    return y, _converged(r, sn, d, args[-1], args[3], tol)


FAILURE_DAMAGE = 1.0 - 1e-6
"""The damage D_fail at which a bond is broken: its yield and fatigue surfaces, which shrink as 1 − D and meet at
D = 1 (seed 002, Sec. 3.1, Fig. 4), have shrunk to 10⁻⁶ of their size (σ_t and c of Table 2 to 0.07 Pa); the DEM
removes the bond and logs a crack (decision "failure damage of a bond")."""

MAX_HALVINGS = 12
"""How often :func:`plastic_return` (and the compiled return of the DEM's bonds) may halve a bond's step whose Newton
iteration fails: a step split into up to 4096 parts."""


@number_arguments
def plastic_return(trial_n: ArrayLike, trial_s: ArrayLike, damage: ArrayLike, p: BondParameters, *, normal_stress=None,
                   start=None, stiffness=None, tol: float = 1e-12, max_iter: int = 60,
                   max_halvings: int | None = None):
    """Return a trial state onto the yield surface (Eqs. 15–22); vectorised over bonds.

    ``trial_n``, ``trial_s`` are the elastic displacements u − uᵖ − uᶠ at the start-of-step plastic state, ``damage``
    the damage at the start of the step. With ``normal_stress`` given, σ_n is prescribed (a free normal
    displacement, e.g. pure shear at σ_n = 0) and ``trial_n`` is ignored. ``start`` = (start_n, start_s), the
    elastic displacements at the start of the step, lets a bond whose Newton iteration fails (a trial many times
    beyond the strength) split its step in halves, up to ``max_halvings`` times (:data:`MAX_HALVINGS`).
    ``stiffness`` = (k_n, k_s) per bond replaces ``p.kn``, ``p.ks`` (bonds of different sizes in a DEM
    assembly).

    Returns ``(du_n_p, du_s_p, damage, sigma_n, sigma_s)``; bonds inside the surface return zero increments. The
    three equations (flow rule Eq. 19, 20 and F = 0 with the damage of Eq. 21 at the *end* of the step, fully
    implicit) are solved by Newton's method.

    Failure: a bond whose damage reaches :data:`FAILURE_DAMAGE` is broken. One broken at the start carries no
    stress and is returned unchanged; one that reaches it in a part of a split step ends there (the rest of the
    step's path does not matter to a broken bond); one whose iteration fails at the deepest split with its damage
    past it is broken in this step, with zero stresses. A bond short of the failure damage that cannot be returned
    raises ``RuntimeError`` rather than returning an inadmissible state.
    """
    max_halvings = MAX_HALVINGS if max_halvings is None else max_halvings
    trial_n, trial_s, damage = np.broadcast_arrays(*(np.atleast_1d(check_finite(name, v)) for name, v in
                                                      (("trial_n", trial_n), ("trial_s", trial_s), ("damage", damage))))
    kn, ks = (np.broadcast_to(np.asarray(k, float), trial_s.shape)
              for k in ((p.kn, p.ks) if stiffness is None else stiffness))
    if normal_stress is not None:
        normal_stress = np.broadcast_to(np.asarray(normal_stress, float), trial_s.shape)
        sigma_n, sigma_s = normal_stress.copy(), ks * (1.0 - damage) * trial_s
    else:
        sigma_n, sigma_s = _bond_stresses(trial_n, trial_s, damage, p, kn, ks)
    du_n, du_s, d = np.zeros_like(trial_s), np.zeros_like(trial_s), damage.copy()
    broken = damage >= FAILURE_DAMAGE                 # a broken bond carries nothing
    sigma_n, sigma_s = np.where(broken, 0.0, sigma_n), np.where(broken, 0.0, sigma_s)
    scale = _yield_scale(sigma_n, damage, p)          # the tolerance is relative to the surface's size
    active = np.flatnonzero(~broken & (_criterion(sigma_n, sigma_s, damage, p) > tol * scale**2))
    if not active.size:
        return du_n, du_s, d, sigma_n, sigma_s
    tn, ts, d0 = trial_n[active], trial_s[active], damage[active]
    fixed = None if normal_stress is None else normal_stress[active]
    # First guess: one linearised return at the trial stress, damage frozen.
    sn, ss = sigma_n[active], sigma_s[active]
    fn, fs = _flow_direction(sn, ss, d0, p)
    dfn = 2.0 * p.tan_phi * np.abs(p.cohesion * (1.0 - d0) - sn * p.tan_phi)
    dfs = 2.0 * p.alpha**2 * ss
    stiff_n = 0.0 if fixed is not None else kn[active] * (1.0 - d0)
    g0 = _criterion(sn, ss, d0, p) / (dfn * stiff_n * fn + dfs * ks[active] * (1.0 - d0) * fs)
    args = (tn, ts, d0, p, fixed, kn[active], ks[active], scale[active])
    y, converged = _newton(np.array([g0 * fn / p.un, g0 * fs / p.us, g0 * p.cohesion / p.us]), args, tol, max_iter)
    _, d_act, sn, ss = _return_residual(y, *args)
    du_n[active], du_s[active], d[active] = y[0] * p.un, y[1] * p.us, d_act
    sigma_n[active], sigma_s[active] = sn, ss
    failed = active[~converged]
    if failed.size and (start is None or max_halvings == 0):
        broke = failed[d[failed] >= FAILURE_DAMAGE]          # its surface has vanished: the bond breaks here
        sigma_n[broke], sigma_s[broke] = 0.0, 0.0
        failed = failed[d[failed] < FAILURE_DAMAGE]
        if failed.size:
            raise RuntimeError(f"plastic return did not converge for {failed.size} bond(s) in {max_iter} iterations "
                               f"(trial σ = ({trial_n[failed[0]]:.3e}, {trial_s[failed[0]]:.3e}) m elastic "
                               f"displacement at D = {damage[failed[0]]:.6f}); take smaller steps")
    elif failed.size:
        start_n, start_s = (np.broadcast_to(np.asarray(v, float), trial_s.shape)[failed] for v in start)
        mid_n, mid_s = 0.5 * (start_n + trial_n[failed]), 0.5 * (start_s + trial_s[failed])
        kw = lambda k: {"normal_stress": None if normal_stress is None else normal_stress[k],
                        "stiffness": (kn[k], ks[k]), "tol": tol, "max_iter": max_iter,
                        "max_halvings": max_halvings - 1}
        dn1, ds1, d1, sn1, ss1 = plastic_return(mid_n, mid_s, damage[failed], p, start=(start_n, start_s),
                                                **kw(failed))
        du_n[failed], du_s[failed], d[failed], sigma_n[failed], sigma_s[failed] = dn1, ds1, d1, sn1, ss1
        on = d1 < FAILURE_DAMAGE                              # a bond broken in the first half ends there
        go = failed[on]
        if go.size:
            dn2, ds2, d[go], sigma_n[go], sigma_s[go] = plastic_return(
                trial_n[go] - dn1[on], trial_s[go] - ds1[on], d1[on], p,
                start=(mid_n[on] - dn1[on], mid_s[on] - ds1[on]), **kw(go))
            du_n[go], du_s[go] = dn1[on] + dn2, ds1[on] + ds2
    return du_n, du_s, d, sigma_n, sigma_s
