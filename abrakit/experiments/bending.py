"""Four-point bending of a cemented DEM beam (seed 002, Sec. 5): set-up, flexural measures, the monotonic test.

The cyclic test on the same beam is :mod:`abrakit.experiments.cyclic`.

The beam is 200 × 50 mm in the plane and W = 50 mm thick (2D disks, :class:`BeamSpec`), on two supports at a 150 mm
span, loaded by two rollers 50 mm apart: third-point loading. Every particle pair closer than a bonding gap is
joined by the fatigue bond of :mod:`abrakit.fatigue` with Table 2's parameters (:func:`table_two`) and stiffnesses
from the effective modulus (deformable method, k_n = E_c/(r_A + r_B), k_s = k_n/2.4). The rollers are rigid rocker
pads of 10 mm (at least four radii) pivoting at the exact spans, one-sided and frictionless
(:mod:`abrakit.experiments.rollers`, the default ``fixture="rockers"``): the loading pads move down at a prescribed
speed (monotonic test, displacement control) or carry a prescribed haversine load (cyclic test), on the same
specimen. The earlier stand-in, ``fixture="pads"``, holds the support particles under a pad in y (which clamps the
beam's ends) and drives the loading particles themselves; the studies stored with it keep it. A rigid disk touching
one particle, as first tried, crushed the bonds under it at a tenth of the beam's strength; the paper's rollers are
walls touching several particles.

The flexural stress, strain and modulus follow from the load P and the mid-span deflection δ (Eqs. 42–44):

    FS = P S / (W H²),   ε_f = 108 H δ / (23 S²),   E_f = 23 P S³ / (108 δ W H³)

which is Euler–Bernoulli beam theory for third-point loading; :func:`flexural` evaluates the same theory for the
spec's own span and roller spacing (any four-point fixture), which reduces to these at spacing S/3. δ is the
sinking of the bottom at mid-span relative to the supports.

Particles (``grading``):

- "lattice": a hexagonal lattice of spacing 2 r̄ whose radii are drawn in [(1 − s) r̄, r̄] (``dispersion`` s), so that
  no two overlap and every lattice neighbour lies within the bonding gap 2 s r̄: the fast, reproducible stand-in.
- "fuller": a poly-disperse packing after Fuller's aggregate grading between r̄/``radius_ratio`` and r̄
  (:mod:`abrakit.experiments.disk_packing`), settled in a box at 1 kPa and bonded where the gap is at most a tenth
  of the smallest radius; disks left without a bond are removed. The paper's sample is poly-disperse (radii 1–19 mm
  after its aggregate grading, whose curve, Fig. 13, is lost in the extraction). The relaxed sample is cached in
  the compression specimens' directory (:func:`abrakit.experiments.specimen.cache_dir`), keyed on its arguments
  and on the code that made it (:func:`procedure_fingerprint`).

In both, ``radius`` r̄ is the largest radius and sets the resolution.
"""

from __future__ import annotations

import functools
import hashlib
import json
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

import abrakit.dem
import abrakit.experiments.disk_packing
from abrakit.compiled import HAVE_NUMBA
from abrakit.dem.fatigue_bonds import install_fatigue_bonds
from abrakit.dem.measure import relax
from abrakit.dem.simulation import Simulation
from abrakit.dem.state import Particles
from abrakit.experiments.disk_packing import disk_packing, fuller_radii
from abrakit.experiments.rollers import Rollers
from abrakit.experiments.specimen import cache_dir
from abrakit.fatigue.bond_law import BondParameters
from abrakit.io import RunRecord, load_state, save_state, source_fingerprint
from abrakit.validation import (
    check_integer,
    check_number_fields,
    check_option,
    check_positive,
    check_range,
    number_arguments,
)

MODULUS = 1.55e9        # E_c of Table 2 [Pa]
SEATING = 0.1           # the rockers' default load_min_ratio: the seating load one-sided supports need
STIFFNESS_RATIO = 2.4   # k_n / k_s of Table 2


def table_two() -> BondParameters:
    """Table 2 of seed 002 (the flexural tests): σ_t = c = 74 kPa, ū = 2·10⁻⁵ m, φ = 20°, ψ = 10°, m = 1.2,
    C = 1.8·10⁻¹¹, a = 0.84, D₀ = 0.01. k_n, k_s here are placeholders: the beam's bonds take theirs from E_c."""
    return BondParameters(kn=MODULUS / 5e-3, ks=MODULUS / 5e-3 / STIFFNESS_RATIO, tensile_strength=74e3,
                          cohesion=74e3, un=2e-5, us=2e-5, friction_angle=20.0, dilatancy_angle=10.0,
                          paris_exponent=1.2, paris_coefficient=1.8e-11, threshold=0.84, initial_damage=0.01)


def scaled_strengths(params: BondParameters, factor: float) -> BondParameters:
    """The bond law with its strengths σ_t, c and its softening displacements ū_n, ū_s multiplied by ``factor``:
    the calibration route of the beam's strength (decision "calibrating the beam's strength by similarity").

    The particles' contacts, the bonds' stiffnesses, the rollers' penalty and the damping are linear, and Eqs. (15–22)
    are homogeneous of degree one in (σ_t, c, ū, u): scaling the strengths, the softening displacements and the
    loading speed scales every force and displacement of the monotonic test by ``factor``, up to the geometric
    non-linearity (the bonds turn with the particles; of the order of the displacement over the radius, 10⁻³) and
    the settling forces of a graded packing (1 kPa). So FS_max and the strain at the peak scale by ``factor`` and E_f
    is unchanged (measured within 10⁻³ on the coarse beam at factor 1/2:
    ``test_scaling_the_strengths_scales_the_monotonic_curve_by_the_same_factor``), which makes the calibration to a
    target strength one run: factor = FS_target / FS_max. The Paris law (m, C) and the threshold a are left as they
    are: the fatigue of a calibrated beam is not similar to the uncalibrated one's."""
    if not isinstance(params, BondParameters):
        raise TypeError(f"params must be a BondParameters, got {type(params).__name__}")
    check_positive("factor", factor)
    return params.replace(tensile_strength=params.tensile_strength * factor, cohesion=params.cohesion * factor,
                          un=params.un * factor, us=params.us * factor)


@dataclass(frozen=True)
class BeamSpec:
    """Geometry [m] and particles of the beam. ``width`` W is the out-of-plane thickness of the 2D disks."""

    length: float = 0.2
    height: float = 0.05
    width: float = 0.05
    span: float = 0.15
    roller_spacing: float = 0.05
    radius: float = 2.5e-3
    dispersion: float = 0.2
    density: float = 2400.0
    seed: int = 0
    grading: str = "lattice"
    radius_ratio: float = 3.0

    def __post_init__(self):
        check_number_fields(self)
        for name in ("length", "height", "width", "span", "roller_spacing", "radius", "density"):
            check_positive(name, getattr(self, name))
        check_range("dispersion", self.dispersion, 0.0, 0.5, high_open=True)
        check_option("grading", self.grading, ("lattice", "fuller"))
        if not self.radius_ratio > 1.0:
            raise ValueError(f"radius_ratio must exceed 1, got {self.radius_ratio}")
        if not self.roller_spacing < self.span < self.length:
            raise ValueError(f"need roller_spacing < span < length, got {self.roller_spacing}, {self.span}, "
                             f"{self.length}")
        if 4 * self.radius > self.height:
            raise ValueError(f"radius must be at most height/4 = {self.height / 4:g} m, got {self.radius:g}")


@dataclass
class Beam:
    """A built beam: the simulation, the spec and what stands for the rollers.

    ``supports``: bottom-row particles within ``pad``/2 of each support; ``loading``: top-row particles within
    ``pad``/2 of each loading roller; ``mid_bottom``: bottom-row particles at mid-span. With ``rollers`` None (the
    "pads" fixture) the support particles are held in y and free in x, and the loading particles are kinematic
    (displacement control) or carry the load in equal shares (force control). With :class:`Rollers` (the "rockers"
    fixture) four rigid rocker pads act on the beam instead (supports fixed, loading pads prescribed or
    force-driven): one-sided, frictionless, their resultants at the exact spans."""

    sim: Simulation
    spec: BeamSpec
    supports: np.ndarray
    loading: np.ndarray
    mid_bottom: np.ndarray
    control: str
    rollers: Rollers | None = None

    def __post_init__(self):
        self._y0 = self.sim.particles.x[:, 1].copy()
        self.speed = 0.0            # of the loading particles (or pads) under displacement control [m/s]
        self._travel = 0.0
        self.pull = 0.0             # the largest tension a roller exerted on the beam so far [N] (rockers: none)
        x = self.sim.particles.x[self.mid_bottom, 0]
        self._anchor = self.mid_bottom[np.argmin(np.abs(x - 0.5 * self.spec.length))]
        self._x_anchor = float(self.sim.particles.x[self._anchor, 0])

    def load(self) -> float:
        """Total load P [N] on the beam, positive downward: under displacement control the force the loading
        rollers exert (the rocker pads' contact forces, or the guide's force on the kinematic loading particles:
        minus the bonds' pull on them), under force control the applied force."""
        if self.rollers is not None:
            if self.control == "force":
                return float(-self.rollers.force[2:].sum())
            return float(self.rollers.contact_total()[2:].sum())
        if self.control == "force":
            return float(-self.sim.applied_force[self.loading, 1].sum())
        return float(self.sim.particle_force[self.loading, 1].sum())

    def set_load(self, load: float) -> None:
        """Under force control: the total load P [N] (downward), shared equally by the two loading rollers (or,
        with the "pads" fixture, by the loading particles)."""
        if self.rollers is not None:
            self.rollers.force[2:] = -0.5 * load
        else:
            self.sim.applied_force[self.loading, 1] = -load / len(self.loading)

    def deflection(self) -> float:
        """Mid-span deflection δ [m], positive downward, relative to the supports (with rocker pads: to the beam's
        particles on the support pads, weighted by their contact forces, so the contact's own compliance is not
        counted)."""
        sink = self._y0 - self.sim.particles.x[:, 1]
        if self.rollers is None:
            return float(np.mean(sink[self.mid_bottom]) - np.mean(sink[self.supports]))
        support = self.rollers.contact_mean(sink, (0, 1))
        if np.isnan(support):
            support = np.mean(sink[self.supports])
        return float(np.mean(sink[self.mid_bottom]) - support)

    def step(self, steps: int = 1) -> None:
        """Advance ``steps`` steps. "pads": the rollers guide in y only (free in x, frictionless): the supports are
        held, the loading particles under displacement control sink at :attr:`speed`. "rockers": the pads push the
        particles they touch, then move under the reactions (:class:`~abrakit.experiments.rollers.Rollers`)."""
        p = self.sim.particles
        for _ in range(int(steps)):
            if self.rollers is not None:
                self.rollers.speed = self.speed
                on_particles, reaction, moment = self.rollers.contact_forces(p.x, p.radius)
                self.sim.applied_force[:, :2] = on_particles
                self.sim.step()
                self.rollers.advance(reaction, moment, self.sim.dt)
                p.v[self._anchor, 0] = 0.0                    # mid-span: u_x = 0 by symmetry (no rigid drift)
                p.x[self._anchor, 0] = self._x_anchor
                continue
            self.sim.step()
            self.pull = max(self.pull, float(np.max(-self.sim.particle_force[self.supports, 1], initial=0.0)))
            p.v[self.supports, 1] = 0.0
            p.x[self.supports, 1] = self._y0[self.supports]
            if self.control == "displacement":
                self._travel += self.speed * self.sim.dt
                p.v[self.loading, 1] = -self.speed
                p.x[self.loading, 1] = self._y0[self.loading] - self._travel


def _lattice(spec: BeamSpec):
    """Centres, radii and bonding gap of the "lattice" grading."""
    rng = np.random.default_rng(spec.seed)
    r = spec.radius
    dy = np.sqrt(3.0) * r
    rows = int(np.floor((spec.height - 2 * r) / dy)) + 1
    columns = int(np.floor((spec.length - 2 * r) / (2 * r))) + 1
    row, col = np.divmod(np.arange(rows * columns), columns)
    x = r + 2 * r * col + r * (row % 2)
    keep = x <= spec.length - r + 1e-12
    xy = np.column_stack([x[keep], (r + dy * row)[keep]])
    radii = r * (1.0 - spec.dispersion * rng.random(len(xy)))
    return xy, radii, 2.0 * spec.dispersion * r * (1 + 1e-9)


BEAM_KERNEL = "numba" if HAVE_NUMBA else "numpy"
"""The beam's particle–particle contacts and leap-frog update: compiled where numba is installed (the same
equations, :mod:`abrakit.dem.kernels`). With the other compiled pieces (the bond update, the pair loads' sums, the
rocker pads' contacts) a step of the 223-disk graded beam on rockers takes 0.23 ms instead of 1.04 ms on the NumPy
paths, about 0.75 ms with only the bond update compiled (``benchmarks/bench_fatigue_bond_kernel.py``). The two paths
differ by round-off, which the local damping's sign(v) turns into differences of 10⁻⁸ m over a cycle (the kernels'
tests compare single steps and pieces, bit for bit where the summation order allows)."""

SETTLING_STRESS = 1e3   # confining stress at which the "fuller" packing is bonded [Pa]
FILL = 0.85             # solid fraction whose disks the grading draws (the packing then settles near 0.82)


def _fuller(spec: BeamSpec, modulus: float):
    """Centres, radii and bonding gap of the "fuller" grading."""
    rng = np.random.default_rng(spec.seed)
    radii = fuller_radii(rng, spec.radius / spec.radius_ratio, spec.radius, FILL * spec.length * spec.height)
    packing = disk_packing((spec.length, spec.height), radii, rng, modulus=modulus, thickness=spec.width,
                           stress=SETTLING_STRESS, density=spec.density)
    return packing["xy"], packing["radius"], 0.1 * float(packing["radius"].min())


@functools.cache
def procedure_fingerprint() -> str:
    """A hash of the source that makes a graded sample: the packing (:mod:`abrakit.experiments.disk_packing`), the
    whole DEM (:mod:`abrakit.dem`: contacts, bonds, relaxation) and the two functions of this module that call them.
    Part of the cached sample's key, so an edit of any of them never serves a sample of the older code. (A fixed
    version number that was never raised served a cached 6 mm seed-0 sample with 415 bonds, FS_max = 70.1 kPa on
    rockers, where the committed code makes 424 bonds and 88.5 kPa; ``test_the_cached_sample_is_keyed_on_the_code_that_
    made_it``.)"""
    return source_fingerprint(abrakit.dem, abrakit.experiments.disk_packing, _fuller, _bonded_sample)


def _sample_cache_path(spec: BeamSpec, params, modulus, stiffness_ratio, local_damping, safety) -> Path:
    """Where the relaxed graded sample of these arguments is cached: keyed on them and on
    :func:`procedure_fingerprint`."""
    key = json.dumps({"code": procedure_fingerprint(), "spec": asdict(spec), "params": asdict(params),
                      "modulus": modulus, "stiffness_ratio": stiffness_ratio, "local_damping": local_damping,
                      "safety": safety}, sort_keys=True)
    return cache_dir() / f"beam_{hashlib.sha1(key.encode()).hexdigest()[:16]}.pkl"


def _bonded_sample(spec: BeamSpec, params, modulus, stiffness_ratio, local_damping=0.7, safety=0.8) -> Simulation:
    """The particles of :class:`BeamSpec` as a planar simulation, every pair within the bonding gap bonded. A
    "fuller" sample is relaxed after bonding (its packing's contacts still press) and cached: genesis and
    relaxation take about a minute."""
    path = None
    if spec.grading == "fuller":
        path = _sample_cache_path(spec, params, modulus, stiffness_ratio, local_damping, safety)
        cached = load_state(path)
        if cached is not None:
            return cached
    xy, radii, gap = _lattice(spec) if spec.grading == "lattice" else _fuller(spec, modulus)
    particles = Particles.disks(xy, radii, spec.density, thickness=spec.width, kn=modulus * spec.width,
                                friction=0.0)
    sim = Simulation(particles, planar=True, local_damping=local_damping, safety=safety, skin=0.5 * spec.radius,
                     track_energy=False)
    install_fatigue_bonds(sim, params, thickness=spec.width, gap=gap, modulus=modulus,
                          stiffness_ratio=stiffness_ratio)
    b = sim.fatigue_bonds
    lonely = np.bincount(np.concatenate([b.i, b.j]), minlength=len(particles)) == 0
    if lonely.any():
        sim.remove_particles(lonely)
    if path is not None:
        relax(sim, tolerance=1e-4, min_steps=1000, max_steps=50_000)
        sim.fatigue_bonds.restart_cycle()
        path.parent.mkdir(parents=True, exist_ok=True)
        save_state(path, sim)
    return sim


@number_arguments
def four_point_beam(spec: BeamSpec | None = None, params: BondParameters | None = None, *,
                    control: str = "displacement", modulus: float = MODULUS, stiffness_ratio: float = STIFFNESS_RATIO,
                    pad: float | None = None, local_damping: float = 0.7, safety: float = 0.8,
                    fixture: str = "rockers") -> Beam:
    """Build the beam and its bonds; each roller acts on the particles within ``pad``/2 of it [m] (default: 10 mm,
    at least four radii).

    ``control``: "displacement" (the loading rollers move at a prescribed speed) or "force" (they carry a
    prescribed load, :meth:`Beam.set_load`). ``fixture``: "rockers" (the paper's test and the default: rigid rocker
    pads of length ``pad`` pivoting at the exact spans, one-sided and frictionless, the same for both controls:
    :mod:`abrakit.experiments.rollers`) or "pads" (support particles held in y, which clamps the beam's ends, and
    loading particles kinematic or sharing the load: the earlier stand-in, kept for the studies stored with it)."""
    spec = BeamSpec() if spec is None else spec
    params = table_two() if params is None else params
    check_option("control", control, ("displacement", "force"))
    check_option("fixture", fixture, ("pads", "rockers"))
    pad = max(0.01, 4.0 * spec.radius) if pad is None else check_positive("pad", pad)
    check_positive("modulus", modulus)
    check_positive("stiffness_ratio", stiffness_ratio)
    check_range("local_damping", local_damping, 0.0, 1.0, high_open=True)
    check_range("safety", safety, 0.0, 1.0, low_open=True)
    sim = _bonded_sample(spec, params, modulus, stiffness_ratio, local_damping, safety)
    sim.kernel = BEAM_KERNEL
    xy, r = sim.particles.x[:, :2], sim.particles.radius
    centre, half_span, half_spacing = 0.5 * spec.length, 0.5 * spec.span, 0.5 * spec.roller_spacing
    bottom, top = _faces(xy[:, 1], r)
    under = lambda row, *x0: np.flatnonzero(row & np.any([np.abs(xy[:, 0] - x) <= 0.5 * pad for x in x0], axis=0))
    supports = under(bottom, centre - half_span, centre + half_span)
    loading = under(top, centre - half_spacing, centre + half_spacing)
    mid = under(bottom, centre)
    if min(len(supports), len(loading)) < 2 or len(mid) < 1:
        raise ValueError(f"pad = {pad:g} m covers too few particles at radius {spec.radius:g} m; widen it")
    if control == "force" or fixture == "rockers":
        sim.applied_force = np.zeros((len(sim.particles), 3))
    rollers = None
    if fixture == "rockers":
        x0 = np.array([centre - half_span, centre + half_span, centre - half_spacing, centre + half_spacing])
        mode = ("fixed", "fixed") + (("prescribed",) * 2 if control == "displacement" else ("force",) * 2)
        mass = np.full(4, sim.particles.mass[np.concatenate([supports, loading])].sum() / 4)
        rollers = Rollers(x0, np.zeros(4), np.array([1.0, 1.0, -1.0, -1.0]), mode, pad, modulus * spec.width, mass,
                          local_damping)
        rollers.seat(xy, r, np.array([bottom, bottom, top, top]))
        rollers.contact_forces(xy, r)
    return Beam(sim, spec, supports, loading, mid, control, rollers)


def _faces(y, radius):
    """Boolean masks of the particles that form the bottom and the top face: those whose edge lies within half the
    smallest radius of the lowest bottom edge (highest top edge)."""
    tolerance = 0.5 * float(radius.min())
    return (y - radius < np.min(y - radius) + tolerance), (y + radius > np.max(y + radius) - tolerance)


def _shear_span(spec: BeamSpec) -> float:
    """The shear span a = (S − s)/2: the distance from a support to the nearer loading roller [m]."""
    return 0.5 * (spec.span - spec.roller_spacing)


@number_arguments
def flexural(load: ArrayLike, deflection: ArrayLike, spec: BeamSpec) -> dict:
    """Flexural stress, strain and modulus from the load P [N] and the mid-span deflection δ [m] of four-point
    bending with the spec's span S and roller spacing s, shear span a = (S − s)/2 (Euler–Bernoulli):

        FS = 3 P a / (W H²),   ε_f = 12 H δ / (3 S² − 4 a²),   E_f = P a (3 S² − 4 a²) / (4 δ W H³)

    For third-point loading (s = S/3, the paper's fixture) they are seed 002 Eqs. 42–44: FS = P S/(W H²),
    ε_f = 108 H δ/(23 S²), E_f = 23 P S³/(108 δ W H³)."""
    P, d = np.asarray(load, float), np.asarray(deflection, float)
    S, W, H, a = spec.span, spec.width, spec.height, _shear_span(spec)
    shape = 3.0 * S**2 - 4.0 * a**2
    with np.errstate(divide="ignore", invalid="ignore"):
        modulus = P * a * shape / (4.0 * d * W * H**3)
    return {"stress": 3.0 * P * a / (W * H**2), "strain": 12.0 * H * d / shape, "modulus": modulus}


@number_arguments
def beam_theory_deflection(load: ArrayLike, modulus: float, poisson: float, spec: BeamSpec, *, shear: bool = True
                           ) -> float:
    """Mid-span deflection of four-point bending [m]: Euler–Bernoulli P a (3 S² − 4 a²)/(4 E W H³) with the shear
    span a = (S − s)/2 (the inverse of :func:`flexural`'s modulus; 23 P S³/(108 E W H³) for third-point loading)
    plus, with ``shear``, Timoshenko's shear part P a/(2 κ G W H) with κ = 5/6 and G = E/(2(1 + ν)) (2D plane
    stress). For S/H = 3 the shear part adds about a quarter."""
    check_positive("modulus", modulus)
    check_range("poisson", poisson, -1.0, 0.5, low_open=True, high_open=True)
    S, W, H, a = spec.span, spec.width, spec.height, _shear_span(spec)
    bending = load * a * (3.0 * S**2 - 4.0 * a**2) / (4.0 * modulus * W * H**3)
    if not shear:
        return bending
    G = modulus / (2.0 * (1.0 + poisson))
    return bending + load * a / (2.0 * 5.0 / 6.0 * G * W * H)


def monotonic_bending(beam: Beam, *, speed: float = 5e-4, max_deflection: float | None = None,
                      record_every: int = 50, drop: float = 0.5, csv=None, max_steps: int = 400_000) -> dict:
    """Displacement-controlled test: the loading particles move down at ``speed`` [m/s] until, once a bond has
    yielded, the load averaged over ``record_every`` steps has fallen to ``drop`` × its peak (or δ reaches
    ``max_deflection``). Returns arrays
    ``load``, ``deflection``, ``stress``, ``strain``, ``broken`` (broken bonds so far), the peak flexural stress
    ``FS_max``, ``steps`` and ``seconds``; with ``csv`` every record is written as it is taken."""
    check_positive("speed", speed)
    if max_deflection is not None:
        check_positive("max_deflection", max_deflection)
    record_every = check_integer("record_every", record_every, 1)
    max_steps = check_integer("max_steps", max_steps, 1)
    check_range("drop", drop, 0.0, 1.0, low_open=True, high_open=True)
    sim = beam.sim
    if beam.control != "displacement":
        raise ValueError("monotonic_bending needs a beam built with control='displacement'")
    beam.speed = speed
    record = RunRecord(("load", "deflection", "stress", "strain", "broken"), csv)
    clock, peak, steps = time.perf_counter(), 0.0, 0
    while steps < max_steps:
        load = 0.0
        for _ in range(record_every):
            beam.step()
            load += beam.load() / record_every
        steps += record_every
        d = beam.deflection()
        f = flexural(load, d, beam.spec)
        record.add(load=load, deflection=d, stress=float(f["stress"]), strain=float(f["strain"]),
                   broken=len(sim.cracks))
        peak = max(peak, load)
        softening = load < drop * peak and np.any(sim.fatigue_bonds.plastic > 0)  # not a start-up transient
        if softening or (max_deflection is not None and d >= max_deflection):
            break
    record.close()
    out = record.arrays()
    out.update(FS_max=float(out["stress"].max(initial=0.0)), steps=steps, seconds=time.perf_counter() - clock)
    return out


def uniaxial_modulus(spec: BeamSpec | None = None, params: BondParameters | None = None, *, stress: float = 5e3,
                     modulus: float = MODULUS, stiffness_ratio: float = STIFFNESS_RATIO, steps: int = 20_000,
                     tolerance: float = 1e-4) -> dict:
    """Young's modulus and Poisson's ratio of the beam's material from a uniaxial tension test on the same lattice
    (a block of the beam's height and spec): the left column is held in x, the right column pulled by ``stress``
    [Pa] over the height × W, small enough to stay elastic; the run stops when the extension changes by less than
    ``tolerance`` (relative) over 1000 steps. Returns ``E`` [Pa], ``nu`` and the strains."""
    spec = BeamSpec() if spec is None else spec
    params = table_two() if params is None else params
    sim = _bonded_sample(spec, params, modulus, stiffness_ratio)
    xy, r = sim.particles.x[:, :2].copy(), sim.particles.radius
    left, right = map(np.flatnonzero, _faces(xy[:, 0], r))
    bottom, top = map(np.flatnonzero, _faces(xy[:, 1], r))
    height = xy[top, 1].mean() - xy[bottom, 1].mean()
    sim.applied_force = np.zeros((len(xy), 3))
    sim.applied_force[right, 0] = stress * spec.height * spec.width / len(right)
    anchor = left[np.argmin(np.abs(xy[left, 1] - xy[:, 1].mean()))]
    p, x0 = sim.particles, xy.copy()
    previous, extension = np.inf, 0.0
    for step in range(1, steps + 1):
        sim.step()
        p.v[left, 0], p.x[left, 0] = 0.0, x0[left, 0]          # held in x, free in y
        p.v[anchor, 1], p.x[anchor, 1] = 0.0, x0[anchor, 1]    # no rigid drift
        if step % 1000 == 0:
            extension = p.x[right, 0].mean() - x0[right, 0].mean()
            if abs(extension - previous) <= tolerance * abs(extension):
                break
            previous = extension
    strain_x = extension / (x0[right, 0].mean() - x0[left, 0].mean())
    strain_y = ((p.x[top, 1].mean() - p.x[bottom, 1].mean()) - height) / height
    return {"E": stress / strain_x, "nu": -strain_y / strain_x, "strain_x": strain_x, "strain_y": strain_y,
            "steps": step}
