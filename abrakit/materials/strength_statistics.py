"""White-noise strength and toughness statistics (seed 001, "White Noise Statistical Variations").

Every point gets a relative value ``r`` drawn once at the start: a probability ``p`` uniform in [0.001, 0.999] is
mapped through the inverse of one of two distributions,

- normal, coefficient of variation ``C_v``:  p = 1/2 [1 + erf((r - 1) / (C_v sqrt 2))],
  so r = 1 + C_v Phi^-1(p);
- two-parameter Weibull, reference volume ``V_0`` and shape ``alpha``, for a point of volume ``V_p``:
  p = 1 - exp(-(V_p/V_0) (r Gamma(1 + 1/alpha))^alpha),  so  r = [-(V_0/V_p) ln(1 - p)]^(1/alpha) / Gamma(1 + 1/alpha),
  with mean <r> = (V_0/V_p)^(1/alpha) and C_v = sqrt(Gamma(1 + 2/alpha) / Gamma(1 + 1/alpha)^2 - 1) (a size effect:
  larger points are weaker on average).

``mode`` says what ``r`` scales, and with it the critical crack opening ``delta_c ∝ G_c / sigma_c``:

- 1: strength only (``delta_c`` grows as 1/r, the toughness is kept);
- 2: toughness only (``delta_c`` shrinks as r, the strength is kept);
- 3: both (``delta_c`` is kept).

The truncation of ``p`` to [0.001, 0.999] keeps ``r`` away from the tails: the drawn values follow the
distribution's CDF renormalised to that interval (:func:`truncated_cdf`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import special

from ..validation import check_callable, check_finite, check_number_fields, check_option, check_positive, check_range

P_RANGE = (0.001, 0.999)
DISTRIBUTIONS = ("normal", "weibull")
MODES = (1, 2, 3)
#: A normal r must stay positive down to p = 0.001: C_v < 1 / Phi^-1(0.999).
MAX_NORMAL_CV = float(1.0 / special.ndtri(P_RANGE[1]))


def normal_cdf(r, cv):
    """``p(r) = 1/2 [1 + erf((r - 1)/(C_v sqrt 2))]`` of the normal relative value (``cv`` > 0)."""
    r, cv = check_finite("r", r), check_positive("cv", cv)
    return 0.5 * (1.0 + special.erf((np.asarray(r) - 1.0) / (cv * np.sqrt(2.0))))


def weibull_cdf(r, shape, V0=1.0, Vp=1.0):
    """``p(r) = 1 - exp(-(V_p/V_0) (r Gamma(1 + 1/alpha))^alpha)`` of the Weibull relative value (r >= 0)."""
    r = check_range("r", r, 0.0, None)
    shape, V0, Vp = check_positive("shape", shape), check_positive("V0", V0), check_positive("Vp", Vp)
    return -np.expm1(-(Vp / V0) * (np.asarray(r) * special.gamma(1.0 + 1.0 / shape)) ** shape)


def weibull_mean(shape, V0=1.0, Vp=1.0):
    """``<r> = (V_0/V_p)^(1/alpha)``."""
    shape, V0, Vp = check_positive("shape", shape), check_positive("V0", V0), check_positive("Vp", Vp)
    return (V0 / Vp) ** (1.0 / shape)


def weibull_cv(shape):
    """``C_v = sqrt(Gamma(1 + 2/alpha)/Gamma(1 + 1/alpha)^2 - 1)``."""
    shape = check_positive("shape", shape)
    return np.sqrt(special.gamma(1.0 + 2.0 / shape) / special.gamma(1.0 + 1.0 / shape) ** 2 - 1.0)


def truncated_cdf(cdf, r):
    """The CDF of the drawn values: ``(cdf(r) - 0.001) / 0.998`` clipped to [0, 1]."""
    cdf, r = check_callable("cdf", cdf), check_finite("r", r)
    lo, hi = P_RANGE
    return np.clip((cdf(r) - lo) / (hi - lo), 0.0, 1.0)


@dataclass(frozen=True)
class StrengthStatistics:
    """Relative strength and toughness per point (seed 001).

    ``distribution``: ``"normal"`` (needs ``cv`` in (0, 0.3236)) or ``"weibull"`` (needs ``shape`` > 0 and the
    reference volume ``V0`` > 0 in the units of the point volumes). ``mode``: 1 strength, 2 toughness, 3 both.
    ``seed`` makes the field reproducible. In a finite element model the point volumes are the quadrature
    weights times the Jacobians, ``solver.kin.dx`` (shape (elements, points)), and the two arrays of
    :meth:`sample` go to the material's ``relative_strength`` and ``relative_toughness``.
    """

    distribution: str = "normal"
    cv: float | None = None
    shape: float | None = None
    V0: float | None = None
    mode: int = 1
    seed: int | None = None

    def __post_init__(self):
        check_number_fields(self)
        check_option("distribution", self.distribution, DISTRIBUTIONS)
        check_option("mode", self.mode, MODES)
        if self.distribution == "normal":
            if self.cv is None:
                raise ValueError("cv (coefficient of variation) is required by the normal distribution")
            check_range("cv", self.cv, 0.0, MAX_NORMAL_CV, high_open=True)
        else:
            if self.shape is None or self.V0 is None:
                raise ValueError("shape and V0 are required by the Weibull distribution")
            check_positive("shape", self.shape)
            check_positive("V0", self.V0)

    def relative_values(self, volumes) -> np.ndarray:
        """One relative value ``r`` per point; ``volumes`` (any shape, > 0) are the point volumes ``V_p`` (the
        normal distribution uses only their shape)."""
        volumes = np.asarray(check_positive("volumes", volumes), dtype=float)
        p = np.random.default_rng(self.seed).uniform(*P_RANGE, size=volumes.shape)
        if self.distribution == "normal":
            return 1.0 + self.cv * special.ndtri(p)
        return (-(self.V0 / volumes) * np.log1p(-p)) ** (1.0 / self.shape) / special.gamma(1.0 + 1.0 / self.shape)

    def sample(self, volumes) -> tuple[np.ndarray, np.ndarray]:
        """``(relative_strength, relative_toughness)`` per point, after ``mode``."""
        r = self.relative_values(volumes)
        ones = np.ones_like(r)
        return {1: (r, ones), 2: (ones, r), 3: (r, r)}[self.mode]
