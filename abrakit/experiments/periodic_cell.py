"""The identification specimens in a periodic cell: genesis without walls and the elastic probe (Ch. 5.3–5.4).

Walled specimens of a few hundred spheres are loose next to their walls (more than half of a 300-sphere vessel lies
within a diameter of a wall), so the walls bias the E and ν they give. The same specimen made in a periodic cell
has no boundary at all:

1. the radii of :func:`~abrakit.experiments.specimen.grains` (same seed, same distribution), a cubic cell sized so
   that they fill it at the target porosity;
2. random placement at half size, radius expansion in ``expansion_steps`` steps with frictionless settling, as in
   the walled genesis;
3. isotropic consolidation to σ₀ by straining the *cell* (not walls): every ``check_every`` steps the cell strain
   changes by ``gain`` × (p − σ₀)/K, bounded by ``max_rate`` mean radii per step (the walled servo's speed);
4. the material's friction assigned, re-equilibrated, :func:`~abrakit.dem.periodic.elastic_probe` run and the
   exact network response (:func:`~abrakit.dem.network.network_stiffness`) computed beside it.

Eq. (5.20) is evaluated with the contact density of the whole cell (every force-carrying contact between
non-rattlers), which needs no interior window. Spheres only (a clump's members would be wrapped one by one).
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from abrakit.dem import (
    Particles,
    Periodic,
    Simulation,
    coordination_number,
    elastic_probe,
    relax,
    unbalanced_force_ratio,
)
from abrakit.dem.measure import love_weber_stress
from abrakit.dem.network import network_stiffness
from abrakit.experiments.closed_form_checks import contact_statistics, elastic_predictions
from abrakit.experiments.specimen import SpecimenSpec, grains, random_placement
from abrakit.validation import check_positive


def mean_pressure(sim) -> float:
    """Mean compressive stress p = −tr σ/3 of the cell (Love–Weber) [Pa]."""
    return -float(np.trace(love_weber_stress(sim, sim.periodic.volume))) / 3.0


def consolidate_cell(sim, stress: float, *, modulus: float, gain: float = 0.5, max_rate: float = 1e-4,
                     tolerance: float = 0.02, check_every: int = 100, max_steps: int = 40_000) -> dict:
    """Strain the periodic cell isotropically until the mean pressure is within ``tolerance`` of ``stress`` [Pa]
    and the unbalanced-force ratio below ``tolerance``; ``modulus`` [Pa] scales the strain increments."""
    check_positive("stress", stress)
    check_positive("modulus", modulus)
    r_mean = float(np.mean(sim.particles.radius))
    steps = 0
    while steps < max_steps:
        sim.run(check_every, progress=False)
        steps += check_every
        p = mean_pressure(sim)
        ratio = unbalanced_force_ratio(sim)
        if abs(p / stress - 1.0) < tolerance and ratio < tolerance:
            return {"steps": steps, "pressure": p, "ratio": ratio, "converged": True}
        limit = max_rate * r_mean * check_every / float(np.min(sim.periodic.lengths))
        sim.strain_cell(float(np.clip(gain * (p - stress) / modulus, -limit, limit)))
    return {"steps": steps, "pressure": mean_pressure(sim), "ratio": unbalanced_force_ratio(sim),
            "converged": False}


def periodic_genesis(spec: SpecimenSpec, *, max_steps: int = 40_000) -> Simulation:
    """A frictionless specimen of ``spec`` consolidated to σ₀ in a periodic cube (module doc, steps 1–3)."""
    if spec.shapes[0] != 1.0:
        raise ValueError("periodic_genesis makes sphere specimens only (shapes=(1, 0, 0))")
    rng = np.random.default_rng(spec.seed)
    radius, _ = grains(rng, spec)
    solid = float(np.sum(4.0 / 3.0 * np.pi * radius**3))
    side = (solid / (1.0 - spec.porosity)) ** (1.0 / 3.0)
    x = random_placement(rng, 0.5 * radius, np.full(3, side))
    kn = 4.0 * radius * spec.youngs_modulus
    p = Particles.spheres(x, 0.5 * radius, spec.density, kn=kn, kt=kn / spec.stiffness_ratio, friction=0.0)
    sim = Simulation(p, periodic=Periodic([side] * 3), local_damping=0.7, track_energy=False)
    factor = 2.0 ** (1.0 / spec.expansion_steps)
    for _ in range(spec.expansion_steps):
        sim.scale_radii(factor)
        relax(sim, min_steps=1000, max_steps=max_steps // 4)
    result = consolidate_cell(sim, spec.stress, modulus=spec.youngs_modulus / 3.0, max_steps=max_steps)
    if not result["converged"]:
        warnings.warn(f"periodic consolidation did not converge in {result['steps']} steps: p = "
                      f"{result['pressure']:.4g} Pa for {spec.stress:.4g} Pa, unbalanced-force ratio "
                      f"{result['ratio']:.2g}", RuntimeWarning, stacklevel=2)
    return sim


def periodic_elastic_case(params: dict) -> dict:
    """One specimen in a periodic cell: E, ν by the elastic probe (isotropic projection of its 6 × 6 stiffness),
    by the exact network response (:func:`~abrakit.dem.network.network_stiffness`) and by Eq. (5.20) from the
    cell's contacts.

    ``params``: :class:`SpecimenSpec` fields (``n_particles``, ``seed``, ``stiffness_ratio``, …), ``strain``
    (probe, default 1e-8), ``tolerance`` (relaxation, default 1e-6), ``friction`` (default the material's 0.5),
    ``positions_only`` (also run the probe without the spring shift: ``E_positions_only``, ``nu_positions_only``).
    Returns JSON-able numbers.
    """
    return periodic_elastic_cases(params)[0]


def periodic_elastic_cases(params: dict, ratios=None) -> list[dict]:
    """:func:`periodic_elastic_case` for several K^n/K^t ``ratios`` on one packing (made once, at the spec's
    ratio: the frictionless genesis does not depend on it); default the spec's ratio alone."""
    start = time.perf_counter()
    spec = SpecimenSpec(**{k: v for k, v in params.items() if k in SpecimenSpec.__dataclass_fields__})
    sim = periodic_genesis(spec)
    genesis = sim.snapshot()
    tolerance = params.get("tolerance", 1e-6)
    friction = params.get("friction", spec.material().friction)
    rows = []
    for ratio in (spec.stiffness_ratio,) if ratios is None else ratios:
        sim.restore(genesis)
        p = sim.particles
        p.kt[:] = p.kn / check_positive("ratio", ratio)
        p.friction[:] = friction
        sim.refresh()
        relax(sim, tolerance=tolerance, min_steps=0, max_steps=40_000, check_every=100)
        tic = time.perf_counter()
        probe = elastic_probe(sim, strain=params.get("strain", 1e-8), tol=tolerance)
        probe_seconds = time.perf_counter() - tic
        tic = time.perf_counter()
        exact = network_stiffness(sim)
        exact_seconds = time.perf_counter() - tic
        out = {"n_particles": spec.n_particles, "seed": spec.seed, "stiffness_ratio": float(ratio),
               "friction": float(friction), "E": probe.E, "nu": probe.nu, "C11": probe.C11, "C12": probe.C12,
               "C44": float(np.mean(np.diag(probe.C)[3:])), "anisotropy": probe.anisotropy,
               "C11_spread": float(np.ptp(probe.C11_axes) / probe.C11), "E_exact": exact.E, "nu_exact": exact.nu,
               "anisotropy_exact": exact.anisotropy, "pressure": mean_pressure(sim),
               "porosity": 1.0 - float(np.sum(4 / 3 * np.pi * p.radius**3)) / sim.periodic.volume,
               "coordination": coordination_number(sim), **contact_statistics(sim),
               "probe_seconds": probe_seconds, "exact_seconds": exact_seconds}
        if params.get("positions_only", False):       # the probe without the spring shift, for comparison
            legacy = elastic_probe(sim, strain=params.get("strain", 1e-8), tol=tolerance, shift_springs=False)
            out["E_positions_only"], out["nu_positions_only"] = legacy.E, legacy.nu
        for variant, pred in elastic_predictions(out).items():
            out[f"E_pred_{variant}"], out[f"nu_pred_{variant}"] = pred["E"], pred["nu"]
            out[f"ratio_E_{variant}"], out[f"diff_nu_{variant}"] = probe.E / pred["E"], probe.nu - pred["nu"]
        out["seconds"] = time.perf_counter() - start
        rows.append(out)
    return rows
