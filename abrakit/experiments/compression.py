"""Strain-controlled compression tests on DEM specimens (Ch. 5.3): E, ν, peak strength, crack initiation.

The platens ``zmin``/``zmax`` move towards each other at v_p = ½ ε̇ L₀ each (Ch. 5.3.1); the lateral walls are
servo-controlled at the confining stress σ_c (confined test) or absent (unconfined test). Stress and strain are
measured by the three schemes of Fig. 5.2, all recorded during the same test:

``"wall"``      platen force over the vessel's cross-section, strain from platen and lateral wall positions;
``"specimen"``  the specimen's outer dimensions, from the particles that form its six faces at the start of
                loading (their mean centre ± radius, moved by the median displacement of the face; rattlers left
                out), and the Love–Weber stress of all contacts (walls included) over the volume they span;
``"sphere"``    three measurement spheres on the axis (lower, middle, upper part): the Love–Weber stress of the
                contacts whose contact point lies inside each sphere over its volume, and the strain from the
                best-fit (least-squares) displacement gradient of the particles whose centres lie inside (rattlers,
                with fewer than two force-carrying contacts, left out: they drift); the three are averaged.

From the curves: Young's modulus E = Δσ_a/Δε_a, Eq. (5.27), and Poisson's ratio ν = −Δε_x/Δε_a, Eq. (5.28), as
least-squares slopes over a small-strain window (compression positive); the peak strength σ_f (largest axial
stress); for bonded material the crack-initiation stress σ_ci, the axial stress when 1 % of the cracks present at
the peak have formed. Eq. (5.28)'s second form 1 − Δε_v/Δε_a uses the 2D volumetric strain ε_x + ε_a; in 3D
(ε_v = ε_a + 2ε_x) it reads ν = (1 − Δε_v/Δε_a)/2.

Rates. The elastic window and the loading rate are set from the specimen itself: the window is a fraction of the
mean contact "strain" ū/(2r̄) (ū = |F^n|/K^n, the mean normal spring displacement), because a granular specimen
stays elastic only while contact displacements are small against the overlaps; the platens traverse the window in
``crossings`` elastic wave transits t_w = L₀/c with c = 2r̄ √(K̄^n/m̄). :func:`elastic_test` with half the rate
checks that E does not depend on it (quasi-static loading).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from abrakit.dem.contact_laws import _rowdot
from abrakit.dem.measure import contact_counts, love_weber_stress
from abrakit.experiments.specimen import DemMaterial, DemSpecimen
from abrakit.io import progress_bar
from abrakit.validation import check_finite, check_option, check_positive, check_range, check_shape, number_arguments

SCHEMES = ("wall", "specimen", "sphere")


# ---------------------------------------------------------------------------------------------- measurement
def platen_gap(walls) -> float:
    """Distance between the platens ``zmin`` and ``zmax`` [m]."""
    a, b = walls.index("zmin"), walls.index("zmax")
    return float(np.dot(walls.point[b] - walls.point[a], walls.normal[a]))


def _touching_contacts(sim):
    """Force-carrying particle–particle contacts: (force on B (3, K), branch A→B (3, K), contact point (3, K))."""
    p, c = sim.particles, sim.contacts
    if c.force is None or not len(c):
        return np.zeros((3, 0)), np.zeros((3, 0)), np.zeros((3, 0))
    t = c.touching
    i, j = c.i[t], c.j[t]
    branch = (p.x[j] - p.x[i]).T
    point = p.x[i].T + (p.radius[i] - 0.5 * c.overlap[t]) * c.normal[:, t]
    return c.force[:, t], branch, point


def force_carrying_contacts(sim) -> np.ndarray:
    """Number of force-carrying contacts (particles and walls) of each particle; fewer than 2 marks a rattler."""
    n = len(sim.particles)
    w = sim.wall_contacts
    walls = np.bincount(w.j[w.touching], minlength=n) if len(w) and w.overlap is not None else np.zeros(n, int)
    return contact_counts(sim) + walls


def sphere_stress(sim, centre, radius: float) -> np.ndarray:
    """Love–Weber stress of the contacts whose contact point lies in the sphere (``centre``, ``radius``), over the
    sphere's volume, compression positive, (3, 3) [Pa] (a PFC measurement sphere, contact-point rule)."""
    check_shape("centre", check_finite("centre", centre), (3,))
    check_positive("radius", radius)
    force, branch, point = _touching_contacts(sim)
    d = point - np.asarray(centre, float)[:, None]
    inside = np.einsum("ik,ik->k", d, d) <= radius**2
    sigma = force[:, inside] @ branch[:, inside].T
    return 0.5 * (sigma + sigma.T) / (4.0 / 3.0 * np.pi * radius**3)


@number_arguments
def best_fit_gradient(x0: ArrayLike, x: ArrayLike):
    """Least-squares displacement gradient G of u = x − x₀ ≈ G (x₀ − x̄₀) + t over the given points, (3, 3)."""
    u = x - x0
    y = x0 - x0.mean(axis=0)
    return np.linalg.solve(y.T @ y, y.T @ (u - u.mean(axis=0))).T


class Gauges:
    """The three measurement schemes of Fig. 5.2, fixed at the start of loading (see module doc).

    ``sphere_radius`` (default 0.4 × the specimen width) and three centres on the axis, at mid-height and as far
    up and down as the same clearance to the platens allows.
    """

    def __init__(self, sim, *, sphere_radius: float | None = None, layer: float = 1.0):
        p, walls = sim.particles, sim.walls
        self.lateral = all(f"{a}{s}" in walls.names for a in "xy" for s in ("min", "max"))
        self.platens = (walls.index("zmin"), walls.index("zmax"))
        self.platen_gap0 = platen_gap(walls)
        self.lateral0 = self._lateral_lengths(walls) if self.lateral else None
        r_mean = float(np.mean(p.radius))
        held = force_carrying_contacts(sim) >= 2                    # rattlers carry no load and drift
        lo_surface, hi_surface = p.x - p.radius[:, None], p.x + p.radius[:, None]
        lo, hi = lo_surface.min(axis=0), hi_surface.max(axis=0)
        self.faces = [(np.flatnonzero((lo_surface[:, a] <= lo[a] + layer * r_mean) & held),
                       np.flatnonzero((hi_surface[:, a] >= hi[a] - layer * r_mean) & held)) for a in range(3)]
        self.face_x0 = p.x.copy()
        self.outer0 = np.array([np.mean(p.x[hi, a] + p.radius[hi]) - np.mean(p.x[lo, a] - p.radius[lo])
                                for a, (lo, hi) in enumerate(self.faces)])
        self.area0 = float(self.outer0[0] * self.outer0[1])
        width = float(min(self.outer0[:2]))
        self.sphere_radius = 0.4 * width if sphere_radius is None else check_positive("sphere_radius",
                                                                                        sphere_radius)
        mid = 0.5 * (lo + hi)
        clearance = 0.5 * width - self.sphere_radius
        offset = max(0.5 * self.outer0[2] - self.sphere_radius - clearance, 0.0)
        self.centres = mid + np.array([[0.0, 0.0, -offset], [0.0, 0.0, 0.0], [0.0, 0.0, offset]])
        self.members = []
        for c in self.centres:
            d = p.x - c
            inside = np.flatnonzero((_rowdot(d, d) <= self.sphere_radius**2) & held)
            if len(inside) < 4:
                raise ValueError("a measurement sphere holds fewer than 4 particles: the specimen is too small")
            self.members.append((inside, p.x[inside].copy()))

    @staticmethod
    def _lateral_lengths(walls) -> np.ndarray:
        return np.array([np.dot(walls.point[walls.index(f"{a}max")] - walls.point[walls.index(f"{a}min")],
                                walls.normal[walls.index(f"{a}min")]) for a in "xy"])

    def _outer(self, p) -> np.ndarray:
        """Outer dimensions: initial ones plus the *median* displacement of each face's particles (a particle
        that loses its contacts and drifts must not move the face)."""
        u = p.x - self.face_x0
        return self.outer0 + np.array([np.median(u[hi, a]) - np.median(u[lo, a])
                                       for a, (lo, hi) in enumerate(self.faces)])

    def read(self, sim) -> dict:
        """Axial and lateral stress and strain of each scheme, compression positive:
        ``{scheme: (sigma_axial, sigma_lateral, eps_axial, eps_lateral)}`` [Pa, Pa, -, -]."""
        p, walls = sim.particles, sim.walls
        force = 0.5 * (walls.normal_force(self.platens[0]) + walls.normal_force(self.platens[1]))
        eps_axial = 1.0 - platen_gap(walls) / self.platen_gap0
        if self.lateral:
            lengths = self._lateral_lengths(walls)
            area = float(np.prod(lengths))
            height = platen_gap(walls)
            sig_lat = np.mean([0.5 * (walls.normal_force(walls.index(f"{a}min"))
                                      + walls.normal_force(walls.index(f"{a}max"))) / (lengths[1 - k] * height)
                               for k, a in enumerate("xy")])
            eps_lat = float(np.mean(1.0 - lengths / self.lateral0))
        else:
            area, sig_lat, eps_lat = self.area0, 0.0, np.nan
        out = {"wall": (float(force) / area, float(sig_lat), eps_axial, eps_lat)}

        outer = self._outer(p)
        strain = 1.0 - outer / self.outer0
        sigma = love_weber_stress(sim, float(np.prod(outer)), include_walls=True, compression_positive=True)
        out["specimen"] = (sigma[2, 2], 0.5 * (sigma[0, 0] + sigma[1, 1]), strain[2], 0.5 * (strain[0] + strain[1]))

        stresses, strains = [], []
        for c, (members, x0) in zip(self.centres, self.members, strict=True):
            stresses.append(sphere_stress(sim, c, self.sphere_radius))
            strains.append(-best_fit_gradient(x0, p.x[members]))
        sigma, eps = np.mean(stresses, axis=0), np.mean(strains, axis=0)
        eps = 0.5 * (eps + eps.T)
        out["sphere"] = (sigma[2, 2], 0.5 * (sigma[0, 0] + sigma[1, 1]), eps[2, 2], 0.5 * (eps[0, 0] + eps[1, 1]))
        return out


# ---------------------------------------------------------------------------------------------- the test
@dataclass
class CompressionCurve:
    """Recorded test: per scheme arrays ``sigma_axial``, ``sigma_lateral``, ``eps_axial``, ``eps_lateral``
    (compression positive) plus ``time``, ``cracks`` (broken bonds so far) and ``sliding`` (fraction of
    sliding contacts)."""

    schemes: dict
    time: np.ndarray
    cracks: np.ndarray
    sliding: np.ndarray
    strain_rate: float
    confinement: float
    info: dict = field(default_factory=dict)

    def __getitem__(self, scheme: str) -> dict:
        return self.schemes[check_option("scheme", scheme, SCHEMES)]

    @property
    def deviator(self) -> np.ndarray:
        """σ_d = σ_a − σ_c from the wall-based measurement [Pa]."""
        return self["wall"]["sigma_axial"] - self.confinement


def _sliding_fraction(sim) -> float:
    c = sim.contacts
    if c.fn is None or not len(c):
        return 0.0
    t = c.touching & ~c.bonded
    if not t.any():
        return 0.0
    limit = c.prm["mu"][t] * c.fn[t]
    return float(np.mean(np.sqrt(_rowdot(c.ft[:, t].T, c.ft[:, t].T)) >= 0.999 * limit))


def compression_test(sim, confinement: float, *, strain_rate: float, max_strain: float, records: int = 200,
                     stop_drop: float | None = None, gauges: Gauges | None = None,
                     progress: bool = False) -> CompressionCurve:
    """Move the platens of a prepared specimen (:meth:`DemSpecimen.prepare`) at ε̇ = ``strain_rate`` [1/s] until the
    axial strain reaches ``max_strain`` or, with ``stop_drop`` = α, the deviatoric stress has fallen below
    α·max|σ_d| after its peak (the seed's termination for bonded material). ``records`` readings are taken."""
    check_positive("strain_rate", strain_rate)
    check_range("max_strain", max_strain, 0.0, 0.5, low_open=True)
    walls = sim.walls
    gauges = Gauges(sim) if gauges is None else gauges
    bottom, top = gauges.platens
    speed = 0.5 * strain_rate * gauges.platen_gap0                     # v_p = ½ ε̇ L₀ (Ch. 5.3.1)
    walls.velocity[bottom] = speed * walls.normal[bottom]
    walls.velocity[top] = speed * walls.normal[top]
    steps = int(np.ceil(max_strain / (strain_rate * sim.dt)))
    every = max(steps // records, 1)
    rows, times, cracks, sliding = [], [], [], []
    peak = 0.0
    bar = progress_bar(total=steps, desc="compression", unit="step", disable=not progress)   # one bar per test
    for _ in range(0, steps, every):
        sim.run(every, progress=False)
        bar.update(every)
        reading = gauges.read(sim)
        rows.append(reading)
        times.append(sim.time)
        cracks.append(len(sim.cracks))
        sliding.append(_sliding_fraction(sim))
        deviator = reading["wall"][0] - confinement
        peak = max(peak, abs(deviator))
        if stop_drop is not None and peak > 0 and abs(deviator) < stop_drop * peak and len(rows) > 5:
            break
    bar.close()
    walls.velocity[[bottom, top]] = 0.0
    names = ("sigma_axial", "sigma_lateral", "eps_axial", "eps_lateral")
    schemes = {s: {n: np.array([r[s][k] for r in rows]) for k, n in enumerate(names)} for s in SCHEMES}
    return CompressionCurve(schemes, np.array(times), np.array(cracks), np.array(sliding), strain_rate,
                            confinement, {"steps_per_record": every, "dt": sim.dt})


# ---------------------------------------------------------------------------------------------- analysis
def elastic_moduli(curve: CompressionCurve, window=(0.25, 1.0), *, max_strain: float | None = None) -> dict:
    """E (Eq. 5.27) and ν (Eq. 5.28) of each scheme as least-squares slopes of σ_a and ε_lat against ε_a over the
    records whose wall-based axial strain lies in ``window`` × ``max_strain`` (default: the largest strain reached).
    Returns ``{scheme: {"E": Pa, "nu": -}}`` (ν is NaN for the wall scheme of an unconfined test)."""
    wall_strain = curve["wall"]["eps_axial"]
    top = float(wall_strain.max()) if max_strain is None else max_strain
    sel = (wall_strain >= window[0] * top) & (wall_strain <= window[1] * top)
    if sel.sum() < 3:
        raise ValueError("fewer than 3 records in the strain window: record more often or widen the window")
    out = {}
    for s in SCHEMES:
        c = curve[s]
        eps = c["eps_axial"][sel]
        E = np.polyfit(eps, c["sigma_axial"][sel], 1)[0]
        lat = c["eps_lateral"][sel]
        nu = -np.polyfit(eps, lat, 1)[0] if np.all(np.isfinite(lat)) else np.nan
        out[s] = {"E": float(E), "nu": float(nu)}
    return out


def peak_strength(curve: CompressionCurve, scheme: str = "wall") -> dict:
    """Peak axial stress σ_f [Pa], the deviator at peak and the axial strain at peak."""
    c = curve[scheme]
    k = int(np.argmax(c["sigma_axial"]))
    return {"sigma_f": float(c["sigma_axial"][k]), "deviator": float(c["sigma_axial"][k] - curve.confinement),
            "eps_axial": float(c["eps_axial"][k])}


@number_arguments
def crack_initiation_stress(curve: CompressionCurve, fraction: float = 0.01, scheme: str = "wall") -> float:
    """σ_ci: the axial stress when ``fraction`` (0.01) of the cracks present at the peak have formed [Pa];
    NaN if no bond broke before the peak."""
    c = curve[scheme]
    k = int(np.argmax(c["sigma_axial"]))
    at_peak = curve.cracks[k]
    if at_peak == 0:
        return float("nan")
    first = int(np.argmax(curve.cracks >= max(fraction * at_peak, 1)))
    return float(c["sigma_axial"][first])


def mean_contact_strain(sim) -> float:
    """ū/(2r̄): the mean normal spring displacement |F^n|/K^n of the force-carrying particle contacts over the mean
    diameter — the strain scale below which a granular packing responds elastically."""
    c = sim.contacts
    t = c.touching
    if not t.any():
        raise ValueError("no contact carries force: the specimen is not consolidated")
    u = np.abs(c.fn[t]) / c.prm["kn"][t]
    return float(u.mean() / (2.0 * np.mean(sim.particles.radius)))


def loading_rate(sim, window_strain: float, crossings: float = 40.0) -> float:
    """Strain rate [1/s] at which the platens traverse ``window_strain`` in ``crossings`` wave transits
    t_w = L₀/c, c = 2r̄ √(K̄^n/m̄)."""
    p, c = sim.particles, sim.contacts
    t = c.touching
    kn = float(np.mean(c.prm["kn"][t])) if t.any() else float(np.mean(p.kn) / 2)
    speed = 2.0 * float(np.mean(p.radius)) * np.sqrt(kn / float(np.mean(p.mass)))
    return window_strain / (crossings * platen_gap(sim.walls) / speed)


def elastic_test(specimen: DemSpecimen, material: DemMaterial | None = None, confinement: float | None = None, *,
                 window_fraction: float = 0.1, crossings: float = 40.0, strain_rate: float | None = None,
                 records: int = 60, tolerance: float = 1e-6, kernel: str | None = None) -> dict:
    """A small-strain compression test for E and ν by the three schemes (Fig. 5.2, Eq. 5.27, 5.28).

    The window is ``window_fraction`` × ū/(2r̄) (:func:`mean_contact_strain`), the rate from ``crossings`` wave
    transits over the window (:func:`loading_rate`) unless ``strain_rate`` is given. The specimen is first relaxed
    to an unbalanced force ratio of ``tolerance`` (10⁻⁶): the strains read are ~10⁻⁶, and creep left over from a
    looser equilibrium (10⁻⁴) shifts ν by up to 0.03 at slow rates, while from 10⁻⁶ on E and ν agree to 0.1 %
    between 40 and 160 wave transits. Returns ``{"moduli":
    {scheme: {"E", "nu"}}, "curve", "window_strain", "strain_rate", "sliding", "sim", "prepare"}``; ``sim`` is
    left at the end of the window, so :mod:`~abrakit.experiments.closed_form_checks` can count its contacts.
    """
    material = material or specimen.spec.material()
    sim, prep = specimen.prepare(material, confinement, kernel=kernel, tolerance=tolerance)
    window = window_fraction * mean_contact_strain(sim)
    rate = loading_rate(sim, window, crossings) if strain_rate is None else strain_rate
    confinement = prep["confinement"]
    curve = compression_test(sim, confinement, strain_rate=rate, max_strain=window, records=records)
    return {"moduli": elastic_moduli(curve), "curve": curve, "window_strain": window, "strain_rate": rate,
            "sliding": float(curve.sliding[-1]), "sim": sim, "prepare": prep}


def strength_test(specimen: DemSpecimen, material: DemMaterial | None = None, confinement: float | None = None, *,
                  max_strain: float = 0.01, strain_rate: float | None = None, inertial_number: float = 1e-3,
                  stop_drop: float | None = None, records: int = 200, kernel: str | None = None) -> dict:
    """A compression test to failure: peak strength σ_f, crack-initiation stress σ_ci (bonded) and the curve.

    Default rate: inertial number I = ε̇ d̄ √(ρ/p) = ``inertial_number`` with p = max(σ_c, σ₀) (I ≤ 10⁻³ is the
    usual quasi-static limit). Bonded material stops after the deviator drops to ``stop_drop`` (default 0.7) of
    its peak, granular material at ``max_strain``.
    """
    material = material or specimen.spec.material()
    sim, prep = specimen.prepare(material, confinement, kernel=kernel)
    confinement = prep["confinement"]
    if strain_rate is None:
        pressure = max(confinement, specimen.spec.stress)
        strain_rate = inertial_number / (2 * float(np.mean(specimen.radius)) * np.sqrt(material.density / pressure))
    if stop_drop is None and material.bonded:
        stop_drop = 0.7
    curve = compression_test(sim, confinement, strain_rate=strain_rate, max_strain=max_strain, records=records,
                             stop_drop=stop_drop)
    return {"peak": peak_strength(curve), "crack_initiation": crack_initiation_stress(curve), "curve": curve,
            "strain_rate": strain_rate, "sim": sim, "prepare": prep}
