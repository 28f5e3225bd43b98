"""The ASTM G65 dry sand / rubber wheel test in numbers, and the physical bounds the wear chain of Ch. 8.4 must meet.

Table 8.4 of the seed turns single scratches into wear rates of the G65 test: 8.07 × 10⁻⁷ m³/s for 100 µm quartz.
This module holds the test's own numbers and the checks a reader can make against them:

- **the standard** (:data:`ASTM_G65_STANDARD`): wheel 228.6 mm (9 in) × 12.7 mm, chlorobutyl rubber of
  58–62 Shore A, 200 rpm; AFS 50/70 quartz sand of 212–300 µm fed at 300–400 g/min; coupons 25.4 × 76.2 mm,
  6.4–19.1 mm thick; procedures A–E (:data:`PROCEDURES`); results as volume loss in mm³, Procedure B asked for
  where Procedure A exceeds 100 mm³; measured losses of steels are of the order of 10–10³ mm³ per Procedure A.
  Source: ASTM G65-16, *Standard Test Method for Measuring Abrasion Using the Dry Sand/Rubber Wheel Apparatus*,
  as summarised in the project's reference notes (the standard itself is not open). The seed's wheel, 228.5 mm,
  is 0.04 % smaller.
- **the contact zone**: the rubber's Young's modulus from its Shore A hardness by Gent's relation
  (:func:`shore_a_modulus`, A. N. Gent, Trans. IRI 34 (1958) 46), the contact length from Hertz's line contact
  of the wheel on the rigid steel face (:func:`line_contact_half_width`, K. L. Johnson, *Contact Mechanics*
  (1985) Eq. 4.43). Assumptions: a homogeneous rubber half-space (the real rim is a 12.7 mm layer on a steel hub,
  which shortens the contact) and no sand layer between them.
- **grain counts** (:func:`grains_in_contact`): the seed's N_c A_c (Eq. 8.7, every grain on the face); a full
  hexagonal monolayer; the sand feed (every grain fed passes the contact at the wheel speed); and the load
  (each grain carries the single scratch's 2 N, and together they carry the test's 130 N).
- **the groove at another load** (:func:`plastic_groove_area`): a rigid-plastic sphere sliding on a flat carries
  its load on the front half of its contact circle, F = H π a²/2, and leaves a groove of area
  A_g = (2/3) a³/R ∝ F^{3/2} (Bowden and Tabor). Fitted to the seed's groove at 2 N, it scales A_g to the load a
  grain carries when the 130 N are shared.

:func:`g65_bounds` assembles all of it for one wear rate and one grain: the volume loss per procedure in mm³, the
surface recession speed, the removed volume against the sand's own volume flow, the coupon's volume, and the
bracket that the two load assumptions put around the measured losses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from abrakit.validation import check_number_fields, check_option, check_positive, check_range, number_arguments
from abrakit.wear import contacting_particles, wheel_surface_speed

__all__ = ["G65Standard", "contact_zone", "sand_volume_flow", "g65_bounds", "grain_forces", "balanced_loss",
           "STEEL_CONTACT_PRESSURE"]

MM3 = 1e-9
"""One cubic millimetre in m³."""


@dataclass(frozen=True)
class Procedure:
    """One procedure of ASTM G65: normal force [N] and wheel revolutions."""

    force: float
    revolutions: float


PROCEDURES = {
    "A": Procedure(130.0, 6000.0),   # metals of medium to extreme abrasion resistance
    "B": Procedure(130.0, 2000.0),   # the short variant of A, for volume losses above 100 mm³
    "C": Procedure(130.0, 100.0),    # thin coatings
    "D": Procedure(45.0, 6000.0),    # a lighter load, for low abrasion resistance
    "E": Procedure(130.0, 1000.0),   # medium to low abrasion resistance
}
"""ASTM G65's procedures A–E."""


@dataclass(frozen=True)
class G65Standard:
    """The numbers of ASTM G65 (SI units): wheel, rubber, sand, coupon and the reported losses."""

    wheel_diameter: float = 0.2286
    wheel_width: float = 0.0127
    rubber_shore_a: tuple[float, float] = (58.0, 62.0)
    rubber_poisson: float = 0.5
    rpm: float = 200.0
    sand_sizes: tuple[float, float] = (212e-6, 300e-6)
    sand_flow: tuple[float, float] = (300e-3 / 60.0, 400e-3 / 60.0)     # kg/s (300–400 g/min)
    sand_density: float = 2650.0                                        # quartz, kg/m³
    coupon: tuple[float, float, float] = (0.0254, 0.0762, 0.0127)       # mid thickness of 6.4–19.1 mm
    procedure_b_threshold: float = 100.0 * MM3                          # Procedure B where A loses more
    measured_losses: tuple[float, float] = (10.0 * MM3, 1000.0 * MM3)   # steels, Procedure A, order of magnitude

    def __post_init__(self):
        check_number_fields(self)
        for name in ("wheel_diameter", "wheel_width", "rpm", "sand_density", "procedure_b_threshold"):
            check_positive(name, getattr(self, name))
        check_range("rubber_poisson", self.rubber_poisson, 0.0, 0.5)
        for name, low, high in (("rubber_shore_a", 0.0, 100.0), ("sand_sizes", 0.0, None), ("sand_flow", 0.0, None),
                                ("coupon", 0.0, None), ("measured_losses", 0.0, None)):
            check_range(name, getattr(self, name), low, high, low_open=True, high_open=high is not None)

    @property
    def wheel_speed(self) -> float:
        """Surface speed of the wheel, π D n / 60 [m/s]."""
        return float(wheel_surface_speed(self.rpm, self.wheel_diameter))

    @property
    def coupon_volume(self) -> float:
        return float(np.prod(self.coupon))


ASTM_G65_STANDARD = G65Standard()


@number_arguments
def shore_a_modulus(shore_a):
    """Young's modulus of a rubber from its Shore A hardness S [Pa], Gent's relation (Trans. IRI 34 (1958) 46):

        E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 − 2.54 S)) MPa,   0 < S < 100.

    60 Shore A gives 3.6 MPa.
    """
    S = check_range("shore_a", shore_a, 0.0, 100.0, low_open=True, high_open=True)
    return 1e6 * 0.0981 * (56.0 + 7.62336 * S) / (0.137505 * (254.0 - 2.54 * S))


@number_arguments
def line_contact_half_width(force, radius, width, modulus, poisson=0.5):
    """Half-width b of the Hertzian line contact of an elastic cylinder on a rigid flat [m] (Johnson 1985, 4.43):

        b = √(4 P R / (π w E*)),   E* = E / (1 − ν²),

    for a load ``force`` P [N] over the cylinder's ``width`` w [m], its ``radius`` R [m], ``modulus`` E [Pa] and
    ``poisson`` ν. The pressure is p(x) = p₀ √(1 − x²/b²) with p₀ = 2P/(π b w).
    """
    P = check_positive("force", force)
    R, w, E = check_positive("radius", radius), check_positive("width", width), check_positive("modulus", modulus)
    nu = check_range("poisson", poisson, 0.0, 0.5)
    return np.sqrt(4.0 * P * R / (np.pi * w * E / (1.0 - nu**2)))


def contact_zone(force: float = 130.0, standard: G65Standard = ASTM_G65_STANDARD, shore_a: float | None = None) -> dict:
    """The wheel's contact on the coupon under ``force`` [N]: ``length`` 2b [m], ``width`` (the wheel's) [m],
    ``area`` [m²], ``mean_pressure`` [Pa], ``modulus`` of the rubber [Pa] (``shore_a`` default: the middle of the
    standard's range), all by :func:`line_contact_half_width` with :func:`shore_a_modulus`."""
    S = float(np.mean(standard.rubber_shore_a)) if shore_a is None else shore_a
    E = float(shore_a_modulus(S))
    b = float(line_contact_half_width(force, 0.5 * standard.wheel_diameter, standard.wheel_width, E,
                                      standard.rubber_poisson))
    area = 2.0 * b * standard.wheel_width
    return {"shore_a": S, "modulus": E, "length": 2.0 * b, "width": standard.wheel_width, "area": area,
            "mean_pressure": force / area}


def sand_volume_flow(standard: G65Standard = ASTM_G65_STANDARD) -> tuple[float, float]:
    """The sand's volume flow through the nip, (low, high) [m³/s]: the feed rate over the quartz density."""
    low, high = standard.sand_flow
    return low / standard.sand_density, high / standard.sand_density


def procedure_duration(procedure: str, standard: G65Standard = ASTM_G65_STANDARD) -> float:
    """Duration of a procedure at the standard's speed [s] (Procedure A: 6000 revolutions at 200 rpm, 1800 s)."""
    check_option("procedure", procedure, tuple(PROCEDURES))
    return PROCEDURES[procedure].revolutions / standard.rpm * 60.0


@number_arguments
def plastic_groove_area(force, radius, hardness):
    """Groove cross-section of a rigid-plastic sphere sliding under ``force`` [N] [m²] (Bowden and Tabor):
    the front half of the contact circle carries the load, F = H π a²/2, and the groove is a circular segment of
    half-width a and depth d = a²/(2R), area ≈ (4/3) a d = (2/3) a³/R; so A_g ∝ F^{3/2}."""
    F, R, H = check_positive("force", force), check_positive("radius", radius), check_positive("hardness", hardness)
    a = np.sqrt(2.0 * F / (np.pi * H))
    return 2.0 / 3.0 * a**3 / R


def grains_in_contact(D: float, contact_area: float, force: float = 130.0, grain_force: float = 2.0,
                      standard: G65Standard = ASTM_G65_STANDARD) -> dict:
    """Upper bounds on the number of grains of diameter ``D`` [m] scratching at once in ``contact_area`` [m²].

    - ``seed``: N_c A_c with N_c = 0.9 D⁻² (Eq. 8.7): every grain on the face;
    - ``monolayer``: a hexagonal monolayer of spheres, 0.9069 A/(π D²/4) (the densest the face can hold);
    - ``sand_flow``: every grain fed at the standard's high feed passes the contact at the wheel speed,
      (Q/V_grain) × L/v with L the contact length of :func:`contact_zone`;
    - ``load``: each grain carries ``grain_force`` (the single scratch's 2 N) and all of them the test's
      ``force``.
    """
    D, area = check_positive("D", D), check_positive("contact_area", contact_area)
    force, grain_force = check_positive("force", force), check_positive("grain_force", grain_force)
    volume = np.pi / 6.0 * D**3
    transit = contact_zone(force, standard)["length"] / standard.wheel_speed
    return {"seed": float(contacting_particles(D)) * area, "monolayer": 0.9069 * area / (np.pi * D**2 / 4.0),
            "sand_flow": sand_volume_flow(standard)[1] / volume * transit, "load": force / grain_force}


def g65_bounds(rate: float, grain, contact_area: float, grain_force: float = 2.0, procedure: str = "A",
               standard: G65Standard = ASTM_G65_STANDARD) -> dict:
    """The wear ``rate`` [m³/s] of Eq. (8.14) for one grain type (``grain``: :class:`abrakit.wear.Grain`, its
    single scratch run at ``grain_force``) held against the real test. Returns (SI units, volumes also in mm³):

    - ``loss``: the volume the rate removes in ``procedure``; ``loss_mm3``; ``over_threshold`` and
      ``over_measured``: its ratio to Procedure B's 100 mm³ threshold and to the top of the measured range;
      ``coupons``: the number of whole coupons it amounts to;
    - ``recession``: the surface recession speed over ``contact_area`` [m/s];
    - ``sand_share``: the removed volume over the sand's volume flow (low and high feed);
    - ``grains``: :func:`grains_in_contact`; ``grain_load``: the force per grain if the seed's count shared
      the test's force;
    - ``load_limited``: the loss in mm³ with only as many grains as the load allows, each at ``grain_force``
      (an upper estimate); ``load_shared``: the loss in mm³ with the seed's count sharing the force, each groove
      scaled by :func:`plastic_groove_area` from the seed's groove at ``grain_force`` (a lower estimate; f_ab
      kept, although so shallow a groove would plow);
    - ``hardness``: the hardness that makes :func:`plastic_groove_area` give the seed's groove at ``grain_force``.
    """
    rate = check_positive("rate", rate)
    force = PROCEDURES[check_option("procedure", procedure, tuple(PROCEDURES))].force
    duration = procedure_duration(procedure, standard)
    loss = rate * duration
    grains = grains_in_contact(grain.D, contact_area, force, grain_force, standard)
    per_grain = rate / grains["seed"]                                    # f_ab A_g v_t of Eq. (8.13)
    radius = 0.5 * grain.D
    hardness = 2.0 * grain_force / np.pi * (2.0 / 3.0 / (grain.A_g * radius)) ** (2.0 / 3.0)
    grain_load = force / grains["seed"]
    shared_groove = float(plastic_groove_area(grain_load, radius, hardness))
    flow = sand_volume_flow(standard)
    return {"procedure": procedure, "duration": duration, "loss": loss, "loss_mm3": loss / MM3,
            "over_threshold": loss / standard.procedure_b_threshold,
            "over_measured": loss / standard.measured_losses[1], "coupons": loss / standard.coupon_volume,
            "recession": rate / contact_area, "sand_share": (rate / flow[1], rate / flow[0]),
            "grains": grains, "grain_load": grain_load, "hardness": hardness, "shared_groove": shared_groove,
            "load_limited": grains["load"] * per_grain * duration / MM3,
            "load_shared": grains["seed"] * per_grain * shared_groove / grain.A_g * duration / MM3}


# ---- the load balanced over the grains ---------------------------------------------------------------------------

STEEL_CONTACT_PRESSURE = 3.23e9
"""The St-52 block's mean contact pressure under a sliding sphere, Pa: F_N / (π a²/2) with a = √(2Rd − d²), the
front half of the footprint carrying the load; 0.994 N on the seed's scene (R = 50 µm, d = 2 µm, finite strain,
F-bar, default mesh, the stored run ``scratch_steady/default_fbar``). The hardness of :func:`balanced_loss`: the
scene's own number, nothing fitted to a wear test (Tabor's 3 σ at 8 % strain would give 1.3 GPa)."""


@dataclass(frozen=True)
class BalancedLoss:
    """The G65 loss with the wheel's force shared over the grains in its contact (:func:`balanced_loss`); SI units.

    forces: every grain's force [N] (they sum to the procedure's force); depth_ratio: each grain's degree of
    penetration D_p = a/(2R) of its plastic contact; groove_area: A_g of each [m²]; removal: f_ab of each (the
    removal map at its D_p); rate: Σ f_ab A_g v_t [m³/s]; loss: over the procedure [m³] and ``loss_mm3``."""

    forces: np.ndarray
    depth_ratio: np.ndarray
    groove_area: np.ndarray
    removal: np.ndarray
    rate: float
    loss: float
    procedure: str

    @property
    def loss_mm3(self) -> float:
        return self.loss / MM3


def grain_forces(D: float, force: float = 130.0, standard: G65Standard = ASTM_G65_STANDARD) -> np.ndarray:
    """The force on every grain of diameter ``D`` [m] in the wheel's contact under ``force`` [N], [N].

    The grains sit on the seed's square share of the face, N_c = 0.9 D⁻² (Eq. 8.7), one per cell of side
    s = D/√0.9 over the contact zone of :func:`contact_zone` (length 2b along the wheel's travel, the wheel's width
    across); each carries the Hertz pressure p(x) = p₀ √(1 − x²/b²) of its cell's centre over the cell, rescaled by
    one factor so that the forces sum to ``force`` exactly (the discrete cells miss the ends of the ellipse)."""
    D, force = check_positive("D", D), check_positive("force", force)
    zone = contact_zone(force, standard)
    b, width = 0.5 * zone["length"], zone["width"]
    cell = D / np.sqrt(float(contacting_particles(1.0)))           # N_c = 0.9 D^-2: one grain per s^2
    n_x, n_y = max(1, int(np.floor(2.0 * b / cell))), max(1, int(np.floor(width / cell)))
    x = (np.arange(n_x) + 0.5) * (2.0 * b / n_x) - b
    pressure = np.sqrt(np.clip(1.0 - (x / b) ** 2, 0.0, None))
    per_row = force * pressure / (n_y * pressure.sum())
    return np.repeat(per_row, n_y)


def balanced_loss(D: float, hardness: float, removal, procedure: str = "A",
                  standard: G65Standard = ASTM_G65_STANDARD) -> BalancedLoss:
    """The G65 volume loss of grains of diameter ``D`` [m] with the load balanced (:func:`grain_forces`).

    Each grain, a rounded quartz grain of tip radius R = D/2, sits in the steel at the plastic contact of its own
    force F: F = H π a²/2 (the front half of the contact carries it, Bowden and Tabor), so a = √(2F/(πH)),
    D_p = d/a = a/(2R) and A_g = :func:`plastic_groove_area`; ``hardness`` H [Pa] is the steel's contact pressure.
    ``removal(D_p) -> f_ab`` is the removal map (the share of the groove that leaves as debris, from the eroding
    scratch); every grain slides at the wheel's speed, so the rate is Σ f_ab A_g v_t (Eq. 8.13–8.14 summed over the
    grains in the contact, not scaled from one). Nothing in it is fitted to a wear measurement."""
    H = check_positive("hardness", hardness)
    if not callable(removal):
        raise TypeError(f"removal must be a callable D_p -> f_ab (the removal map), got {type(removal).__name__}")
    force = PROCEDURES[check_option("procedure", procedure, tuple(PROCEDURES))].force
    forces = grain_forces(D, force, standard)
    radius = 0.5 * D
    a = np.sqrt(2.0 * forces / (np.pi * H))
    depth_ratio = a / (2.0 * radius)
    groove = np.asarray(plastic_groove_area(forces, radius, H), dtype=float)
    f_ab = np.asarray(removal(depth_ratio), dtype=float)
    if f_ab.shape != depth_ratio.shape or not np.all(np.isfinite(f_ab)) or np.any((f_ab < 0) | (f_ab > 1)):
        raise ValueError("removal(D_p) must give one f_ab in [0, 1] per grain")
    rate = float(np.sum(f_ab * groove) * standard.wheel_speed)
    return BalancedLoss(forces, depth_ratio, groove, f_ab, rate, rate * procedure_duration(procedure, standard),
                        procedure)
