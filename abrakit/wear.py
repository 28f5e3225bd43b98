"""From a single scratch to a wear rate: the closed-form abrasive wear model of Ch. 8.2–8.4.

The chain, in the dissertation's order:

1. a single scratch gives the groove area ``A_g`` and the shoulder area ``A_s`` of the wear scar, hence the
   degree of wear ``f_ab`` (Eq. 8.5) and the wear regime (plowing / wedging / cutting); the degree of
   penetration ``D_p`` (Eq. 8.6) characterises the relative depth of the groove;
2. particle simulations give the number of grains touching the tool per unit area, ``N_c = 0.9 D^-2``
   (Eq. 8.7) for one grain size and Eq. (8.12) for a binary mixture;
3. each touching grain removes ``f_ab A_g v_t`` per unit time (Eq. 8.13); the total rate per unit area is the
   sum over grain types (Eq. 8.14), which is scaled to the contact area of the test.

Units are SI throughout: lengths in m, areas in m², speeds in m/s, wear rates in m³/s (per unit area: m/s).
Eq. (8.7) was fitted with the diameter divided by the 1 m edge of the simulation box, so ``D`` in metres gives
``N_c`` per m²: ``contacting_particles(100e-6) = 9e7``, the seed's value.

The contact area is the one number the seed leaves unstated. Table 8.4 pins only the product ``A_c v_t``:
with the wheel speed of :func:`wheel_surface_speed` every printed rate is reproduced to its printed digits by any
``A_c`` in [114.600, 114.639] mm² (:func:`fit_scaling_area`), and by no area outside it. We take the midpoint,
:data:`G65_CONTACT_AREA` = 114.62 mm². It is half of the specimen face 18 × 12.7 mm² to 0.28 % (equivalently:
the 12.7 mm wheel width times a 9.0 mm contact length, or the full face at half the wheel speed); with exactly
half the face every row is still within 0.7 % of the table.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from abrakit.validation import broadcast_shapes, check_number_fields, check_positive, check_range

__all__ = [
    "Grain", "GRAIN_100UM", "GRAIN_200UM", "ASTM_G65", "G65_CONTACT_AREA", "TABLE_8_4", "astm_g65_table", "wear_rate",
    "mixture_wear_rate", "contacting_particles", "contacting_particles_mixture", "fit_scaling_area", "degree_of_wear",
    "degree_of_penetration", "wear_regime", "penetration_regime", "PENETRATION_BANDS", "wheel_surface_speed"
]

PLOWING_LIMIT = 0.2
"""Degree of wear below which a scratch is plowing (Sec. 8.2.2): f_ab < 0.2."""

CUTTING_LIMIT = 0.7
"""Degree of wear above which a scratch is cutting (Sec. 8.2.2): f_ab > 0.7; wedging in between, ends included."""

CONTACT_COEFFICIENT = 0.9
"""Prefactor a of N_c = a D^-2, Eq. (8.7) and (8.12)."""


def _out(x):
    """0-d results as Python floats, arrays unchanged."""
    x = np.asarray(x)
    return float(x) if x.ndim == 0 else x


# --- single scratch: Eq. (8.5), (8.6) ---------------------------------------------------------------------


def degree_of_wear(A_g, A_s):
    """Degree of wear f_ab = (A_g − A_s) / A_g, Eq. (8.5), dimensionless in [0, 1].

    ``A_g`` is the groove cross-section area (> 0), ``A_s`` the shoulder area (0 ≤ A_s ≤ A_g), same units.
    f_ab = 0 is ideal micro-plowing (all groove material pushed into the shoulders), f_ab = 1 ideal micro-cutting.
    """
    A_g = check_positive("A_g", A_g)
    A_s = check_positive("A_s", A_s, allow_zero=True)
    broadcast_shapes(A_g=A_g, A_s=A_s)
    if np.any(np.asarray(A_s) > np.asarray(A_g)):
        raise ValueError(
            f"A_s must not exceed A_g (the shoulders hold at most the groove's material), got A_s={A_s!r}, "
            f"A_g={A_g!r}"
        )
    return _out((np.asarray(A_g) - A_s) / A_g)


def degree_of_penetration(d, w):
    """Degree of penetration D_p = 2 d / w, Eq. (8.6): depth over half-width of the groove, dimensionless.

    ``d`` is the indentation depth (≥ 0), ``w`` the groove width (> 0), same units.
    """
    d = check_positive("d", d, allow_zero=True)
    w = check_positive("w", w)
    broadcast_shapes(d=d, w=w)
    return _out(2.0 * np.asarray(d) / w)


def wear_regime(f_ab):
    """Wear regime from the degree of wear (Sec. 8.2.2): ``"plowing"``, ``"wedging"`` or ``"cutting"``.

    plowing: f_ab < 0.2; wedging (the non-steady transition): 0.2 ≤ f_ab ≤ 0.7; cutting: f_ab > 0.7 ("larger than
    0.7" in the seed). Returns a ``str`` for scalar input, else an array of strings of the same shape.
    """
    f_ab = np.asarray(check_range("f_ab", f_ab, 0.0, 1.0))
    regime = np.select(
        [f_ab < PLOWING_LIMIT, f_ab <= CUTTING_LIMIT], ["plowing", "wedging"], default="cutting"
    )
    return str(regime) if regime.ndim == 0 else regime


PENETRATION_BANDS = ((0.1, 0.2), (0.2, 0.3))
"""Hokkirigawa & Kato's regime map (Tribol. Int. 21, 1988; spherical pins on brass and steels), in the degree of
penetration D_p = h/a, the seed's 2d/w of Eq. (8.6): the transition from plowing to wedge formation lies in the
first band, from wedge formation to cutting in the second; the bands' width is the spread over the materials (they
meet at 0.2, so no D_p is a wedge on every material)."""


def penetration_regime(D_p):
    """Wear regime from the degree of penetration (Eq. 8.6) on Hokkirigawa & Kato's map
    (:data:`PENETRATION_BANDS`): ``"plowing"`` below the first band, ``"plowing or wedge"`` inside it, ``"wedge"``
    between the bands, ``"wedge or cutting"`` inside the second, ``"cutting"`` above it. A second verdict beside
    :func:`wear_regime`'s, which reads the same scratch by its f_ab (Zum Gahr's measure, Sec. 8.2.2): the two agree
    when ``wear_regime`` names one of the regimes this one allows. Returns a ``str`` for scalar input, else an
    array of strings of the same shape.
    """
    D_p = np.asarray(check_positive("D_p", D_p, allow_zero=True))
    (a, b), (c, d) = PENETRATION_BANDS
    regime = np.select([D_p < a, D_p <= b, D_p < c, D_p <= d],
                       ["plowing", "plowing or wedge", "wedge", "wedge or cutting"], default="cutting")
    return str(regime) if regime.ndim == 0 else regime


# --- contacting particles: Eq. (8.7)–(8.12) ----------------------------------------------------------------


def contacting_particles(D):
    """Grains touching the tool per unit area, N_c = 0.9 D^-2, Eq. (8.7), for a single grain size.

    ``D`` is the grain diameter in m (> 0); N_c is in 1/m². ``contacting_particles(100e-6)`` = 9e7.
    """
    D = check_positive("D", D)
    return _out(CONTACT_COEFFICIENT * np.asarray(D) ** -2.0)


def contacting_particles_mixture(D_a, D_b, theta_a):
    """Grains of each type touching the tool per unit area in a binary mixture, Eq. (8.8)–(8.12), in 1/m².

    The fit is written for the coarse grain A and the fine grain B, D_A ≥ D_B (8.8), with r_AB = D_A / D_B and
    volume fractions θ_A + θ_B = 1 (8.9):

        N_c,A = 0.9 θ_A^(2 − 1/r_AB) D_A^-2,    N_c,B = 0.9 θ_B^(1/r_AB) D_B^-2        (8.12a, b)

    Here the two grains may be passed in either order: when ``D_a < D_b`` the roles are swapped explicitly
    (grain b becomes A with θ_A = 1 − ``theta_a``). The result is always returned in the caller's order,
    ``(N_c for grain a, N_c for grain b)``. Limits: θ_a = 1 or 0 give Eq. (8.7) for the grain present and zero for
    the other; r_AB = 1 gives N_c,a + N_c,b = 0.9 D^-2, the single-size result.

    ``D_a``, ``D_b`` in m (> 0), ``theta_a`` the volume fraction of grain a in [0, 1]; all broadcast together.
    """
    D_a = np.asarray(check_positive("D_a", D_a))
    D_b = np.asarray(check_positive("D_b", D_b))
    theta_a = np.asarray(check_range("theta_a", theta_a, 0.0, 1.0))
    broadcast_shapes(D_a=D_a, D_b=D_b, theta_a=theta_a)
    swap = D_a < D_b
    D_A, D_B = np.where(swap, D_b, D_a), np.where(swap, D_a, D_b)
    theta_A = np.where(swap, 1.0 - theta_a, theta_a)
    theta_B = 1.0 - theta_A                                                      # Eq. (8.9)
    r_AB = D_A / D_B                                                             # Eq. (8.8), ≥ 1
    N_A = CONTACT_COEFFICIENT * theta_A ** (2.0 - 1.0 / r_AB) * D_A**-2.0      # Eq. (8.12a)
    N_B = CONTACT_COEFFICIENT * theta_B ** (1.0 / r_AB) * D_B**-2.0            # Eq. (8.12b)
    return _out(np.where(swap, N_B, N_A)), _out(np.where(swap, N_A, N_B))


# --- wear rate: Eq. (8.13), (8.14) ------------------------------------------------------------------------


def particle_wear_rate(f_ab, A_g, v_t):
    """Volume removed per unit time by one touching grain, v̇_i = f_ab A_g,i v_t, Eq. (8.13), in m³/s.

    ``f_ab`` degree of wear in [0, 1], ``A_g`` groove area in m² (> 0), ``v_t`` grain–tool sliding speed in m/s
    (≥ 0).
    """
    f_ab = check_range("f_ab", f_ab, 0.0, 1.0)
    A_g = check_positive("A_g", A_g)
    v_t = check_positive("v_t", v_t, allow_zero=True)
    broadcast_shapes(f_ab=f_ab, A_g=A_g, v_t=v_t)
    return _out(np.asarray(f_ab) * A_g * v_t)


def wear_rate(N_c, f_ab, A_g, v_t, area=None):
    """Total wear rate v̇ = Σ_i N_c,i v̇_i, Eq. (8.14), with v̇_i from Eq. (8.13).

    Grain types run along the last axis of the broadcast inputs (scalars: one type); leading axes are batch
    axes. ``N_c`` in 1/m² (≥ 0), ``f_ab``, ``A_g``, ``v_t`` as in :func:`particle_wear_rate`.
    Without ``area`` the result is the rate per unit tool area in m³/(s m²) = m/s; with ``area`` (m², > 0, the
    contact area of the test, see :data:`G65_CONTACT_AREA`) it is the volume rate in m³/s.
    """
    N_c = check_positive("N_c", N_c, allow_zero=True)
    shape = broadcast_shapes(N_c=N_c, f_ab=f_ab, A_g=A_g, v_t=v_t)
    per_grain = np.asarray(particle_wear_rate(f_ab, A_g, v_t))                  # Eq. (8.13)
    terms = np.broadcast_to(np.asarray(N_c) * per_grain, shape)
    rate = np.atleast_1d(terms).sum(axis=-1)                                     # Eq. (8.14)
    if area is not None:
        area = check_positive("area", area)
        rate = rate * area
    return _out(rate)


@dataclass(frozen=True)
class Grain:
    """One grain type of the wear model: diameter ``D`` (m), groove area ``A_g`` (m²) of its single scratch and
    degree of wear ``f_ab``."""

    D: float
    A_g: float
    f_ab: float

    def __post_init__(self):
        check_number_fields(self)
        check_positive("D", self.D)
        check_positive("A_g", self.A_g)
        check_range("f_ab", self.f_ab, 0.0, 1.0)


GRAIN_100UM = Grain(D=100e-6, A_g=88.4e-12, f_ab=0.37)
"""Worked input of Sec. 8.4 (Fig. 8.17): D = 100 µm, A_g = 88.4 µm², f_ab = 0.37 (scratch at f_N = 2 N)."""

GRAIN_200UM = Grain(D=200e-6, A_g=60e-12, f_ab=0.12)
"""Worked input of Sec. 8.4 (Fig. 8.18): D = 200 µm, A_g = 60 µm², f_ab = 0.12 (scratch at f_N = 2 N)."""


def mixture_wear_rate(theta_a, grain_a: Grain, grain_b: Grain, v_t, area=None):
    """Wear rate of a binary mixture, Eq. (8.12) + (8.13) + (8.14); vectorised over ``theta_a``.

    ``theta_a`` is the volume fraction of ``grain_a`` in [0, 1]; ``v_t``, ``area`` and the units as in
    :func:`wear_rate`. The grains may be passed in either size order (see :func:`contacting_particles_mixture`).
    """
    N_a, N_b = contacting_particles_mixture(grain_a.D, grain_b.D, theta_a)
    N_c = np.stack(np.broadcast_arrays(N_a, N_b), axis=-1)
    f_ab = np.array([grain_a.f_ab, grain_b.f_ab])
    A_g = np.array([grain_a.A_g, grain_b.A_g])
    return wear_rate(N_c, f_ab, A_g, np.asarray(v_t)[..., None], area=area)


# --- the ASTM G65 example and Table 8.4 --------------------------------------------------------------------


def wheel_surface_speed(rpm, diameter):
    """Surface speed of a wheel, v = π D n / 60, in m/s; ``rpm`` n in 1/min (≥ 0), ``diameter`` D in m (> 0).

    The seed takes it as the grain sliding speed v_t of Eq. (8.13): 200 rpm and 228.5 mm give 2.3928 m/s.
    """
    rpm = check_positive("rpm", rpm, allow_zero=True)
    diameter = check_positive("diameter", diameter)
    broadcast_shapes(rpm=rpm, diameter=diameter)
    return _out(np.pi * np.asarray(diameter) * rpm / 60.0)


@dataclass(frozen=True)
class G65Test:
    """The dry sand / rubber wheel test (ASTM G65) as described in Sec. 8.4, SI units.

    The normal force and the grain size range are recorded for completeness; the closed-form model does not use
    them (the single scratches behind :data:`GRAIN_100UM` and :data:`GRAIN_200UM` were run at f_N = 2 N).
    """

    wheel_diameter: float = 0.2285
    rpm: float = 200.0
    specimen_length: float = 0.018
    specimen_width: float = 0.0127
    normal_force: float = 130.0
    grain_sizes: tuple[float, float] = (150e-6, 450e-6)

    def __post_init__(self):
        check_number_fields(self)
        for name in ("wheel_diameter", "rpm", "specimen_length", "specimen_width", "normal_force"):
            check_positive(name, getattr(self, name))
        sizes = check_positive("grain_sizes", self.grain_sizes)
        if np.shape(sizes) != (2,) or sizes[0] > sizes[1]:
            raise ValueError(f"grain_sizes must be (smallest, largest) in m, got {self.grain_sizes!r}")

    @property
    def wheel_speed(self) -> float:
        """Surface speed of the rubber wheel, m/s, taken as v_t."""
        return wheel_surface_speed(self.rpm, self.wheel_diameter)

    @property
    def specimen_area(self) -> float:
        """Specimen face 18 × 12.7 mm² = 2.286e-4 m²."""
        return self.specimen_length * self.specimen_width


ASTM_G65 = G65Test()

G65_CONTACT_AREA = 114.62e-6
"""Contact area (m²) that scales the per-area rate of Eq. (8.14) to the ASTM G65 specimen.

Derived from Table 8.4 (the seed does not state it): the midpoint of the interval [114.600, 114.639] mm² of
areas that reproduce all seven printed rates to their printed digits (:func:`fit_scaling_area`). Physically it
is half the specimen face, 0.5014 × 18 × 12.7 mm², or 12.7 mm (the wheel width) × 9.0 mm.
"""

TABLE_8_4 = (
    ("Homogeneous with D=100 µm", 0.0, 8.07e-7),
    ("90 % D=100 µm + 10 % D=200 µm", 0.1, 7.67e-7),
    ("70 % D=100 µm + 30 % D=200 µm", 0.3, 6.83e-7),
    ("50 % D=100 µm + 50 % D=200 µm", 0.5, 5.87e-7),
    ("30 % D=100 µm + 70 % D=200 µm", 0.7, 4.68e-7),
    ("10 % D=100 µm + 90 % D=200 µm", 0.9, 2.93e-7),
    ("Homogeneous with D=200 µm", 1.0, 0.44e-7),
)
"""Table 8.4 of the seed: (material, volume fraction of the 200 µm grain, wear rate in m³/s)."""

TABLE_8_4_RESOLUTION = 0.01e-7
"""Last printed digit of Table 8.4 in m³/s (rates are printed as x.xx × 10^-7)."""


class ScalingAreaFit(NamedTuple):
    """Areas (m²) that scale per-area rates to printed rates; see :func:`fit_scaling_area`."""

    least_squares: float
    low: float
    high: float

    @property
    def consistent(self) -> bool:
        """True when one area reproduces every printed value to its printed digits (low ≤ high)."""
        return self.low <= self.high

    @property
    def midpoint(self) -> float:
        return 0.5 * (self.low + self.high)


def fit_scaling_area(per_area_rate, printed_rate, resolution=TABLE_8_4_RESOLUTION) -> ScalingAreaFit:
    """Derive the area A that turns per-area rates q_i (m/s) into printed rates p_i (m³/s): p_i ≈ A q_i.

    Returns the relative least-squares area, argmin Σ (A q_i / p_i − 1)², and the interval [low, high] of areas
    for which every A q_i rounds to p_i, i.e. |A q_i − p_i| ≤ resolution / 2 (empty when low > high: then no
    single area explains the printed values and at least one row carries another input or a misprint).
    """
    q = np.asarray(check_positive("per_area_rate", per_area_rate), dtype=float).ravel()
    p = np.asarray(check_positive("printed_rate", printed_rate), dtype=float).ravel()
    resolution = check_positive("resolution", resolution)
    broadcast_shapes(per_area_rate=q, printed_rate=p)
    x = q / p
    least_squares = x.sum() / (x @ x)
    low = np.max((p - 0.5 * resolution) / q)
    high = np.min((p + 0.5 * resolution) / q)
    return ScalingAreaFit(float(least_squares), float(low), float(high))


def astm_g65_table(area=G65_CONTACT_AREA, test: G65Test = ASTM_G65, fine: Grain = GRAIN_100UM,
                   coarse: Grain = GRAIN_200UM) -> dict:
    """Recompute Table 8.4: wear rates of 100/200 µm quartz mixtures in the ASTM G65 test, Eq. (8.12)–(8.14).

    Returns a dict of equal-length entries: ``label``, ``theta_coarse`` (volume fraction of the 200 µm grain),
    ``per_area`` (m/s), ``seed`` and ``ours`` (m³/s) and ``deviation`` = ours / seed − 1.
    """
    labels, theta, seed = (list(column) for column in zip(*TABLE_8_4, strict=True))
    theta, seed = np.array(theta), np.array(seed)
    per_area = mixture_wear_rate(theta, coarse, fine, test.wheel_speed)
    ours = per_area * check_positive("area", area)
    return {"label": labels, "theta_coarse": theta, "per_area": per_area, "seed": seed, "ours": ours,
            "deviation": ours / seed - 1.0}
