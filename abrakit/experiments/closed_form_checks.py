"""Do the closed forms of Ch. 5.2 predict what a DEM specimen does? (Ch. 5.4.1–5.4.2, Table 5.2–5.4, Fig. 5.3–5.8)

- **Elastic constants**: E and ν measured in a small-strain compression test (:func:`elastic_case`) beside
  Eq. (5.20) evaluated with the specimen's own mean K^n, K^t, mean radius r and measured contact density
  ρ_c = n_c/V (Eq. 5.29), counted in an interior window (a margin of 1.5 mean diameters from the walls, where
  the packing is layered and loose) without rattlers; in the three variants of
  :func:`abrakit.identification.elastic_constants` ("published", "consistent", "affine"). Ratios
  measured/predicted are averaged over random specimens with a Student-t confidence interval
  (:func:`mean_interval`).
- **Bond strength** (Table 5.3): three unconfined tests with f^{n,c} = f^{t,c}, f^{n,c} = 100 f^{t,c} and
  100 f^{n,c} = f^{t,c}; the peak stress beside σ_y^Rankine = ρ_c r f^{n,c} and σ_y^Tresca = ρ_c r f^{t,c}
  (Eq. 5.26), and the share of tensile and shear cracks.
- **Strength envelope** (Fig. 5.3, 5.4): triaxial peak stresses at several confinements, a Mohr–Coulomb line
  σ₁ = N_φ σ₃ + 2c√N_φ fitted by least squares, friction angle φ and cohesion c.
- **Grain shape** (Table 5.4): the same tests on a mixture of 50 % peanuts, 25 % dyads and 25 % spheres.

Each study is a plain function ``case(params: dict) -> dict`` of JSON-able numbers, so a sweep runner can
distribute and cache it (specimens come from the genesis cache).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats

from abrakit import identification
from abrakit.experiments.compression import elastic_test, force_carrying_contacts, strength_test
from abrakit.experiments.specimen import DemMaterial, SpecimenSpec, genesis
from abrakit.validation import check_positive, check_range, number_arguments

#: Table 5.3: (f^{n,c}, f^{t,c}) as multiples of the base strength f
BOND_CASES = {1: (1.0, 1.0), 2: (100.0, 1.0), 3: (1.0, 100.0)}

#: Table 5.4 / Ch. 5.4.2: fractions of spheres, dyads and peanuts (by number of grains)
MIXTURE = (0.25, 0.25, 0.5)


# ---------------------------------------------------------------------------------------------- Eq. (5.29)
def _box_of(sim) -> tuple[np.ndarray, np.ndarray]:
    """The vessel (lower, upper): box walls where present, the particles' extent otherwise."""
    walls, p = sim.walls, sim.particles
    lo = (p.x - p.radius[:, None]).min(axis=0)
    hi = (p.x + p.radius[:, None]).max(axis=0)
    for a, axis in enumerate("xyz"):
        if f"{axis}min" in walls.names:
            lo[a] = walls.point[walls.index(f"{axis}min"), a]
            hi[a] = walls.point[walls.index(f"{axis}max"), a]
    return lo, hi


def contact_statistics(sim, margin: float = 1.5) -> dict:
    """Contact density ρ_c = n_c/V (Eq. 5.29) in the interior window and the contact means that enter Eq. (5.20).

    The window is the vessel shrunk by ``margin`` mean diameters on every side; a contact counts when it carries
    force, neither of its particles is a rattler (fewer than two force-carrying contacts) and its contact point lies
    in the window. Returns ``rho_c`` [1/m³], ``n_c``, ``volume`` [m³], the means ``kn``, ``kt`` [N/m] and ``radius``
    [m] (half the mean branch length r_A + r_B) over the counted contacts, and ``rho_c_vessel`` (all contacts over
    the whole vessel) for comparison. In a periodic cell every such contact counts, over the cell's volume.
    """
    check_positive("margin", margin, allow_zero=True)
    p, c = sim.particles, sim.contacts
    t = c.touching
    held = force_carrying_contacts(sim) >= 2
    i, j = c.i[t], c.j[t]
    if getattr(sim, "periodic", None) is not None:          # no boundary: the whole cell is interior
        lo, hi = sim.periodic.lower, sim.periodic.lower + sim.periodic.lengths
        inside = held[i] & held[j]
        volume = sim.periodic.volume
    else:
        lo, hi = _box_of(sim)
        shift = 2.0 * margin * float(np.mean(p.radius))
        window_lo, window_hi = lo + shift, hi - shift
        if np.any(window_hi <= window_lo):
            raise ValueError(f"a margin of {margin} diameters leaves no interior window in this specimen")
        point = p.x[i] + (p.radius[i] - 0.5 * c.overlap[t])[:, None] * c.normal[:, t].T
        inside = np.all((point >= window_lo) & (point <= window_hi), axis=1) & held[i] & held[j]
        volume = float(np.prod(window_hi - window_lo))
    n_c = int(inside.sum())
    if n_c == 0:
        raise ValueError("no force-carrying contact in the interior window")
    return {
        "rho_c": identification.measured_contact_density(n_c, volume),
        "n_c": n_c,
        "volume": volume,
        "kn": float(np.mean(c.prm["kn"][t][inside])),
        "kt": float(np.mean(c.prm["kt"][t][inside])),
        "radius": float(np.mean(0.5 * (p.radius[i] + p.radius[j])[inside])),
        "rho_c_vessel": float(t.sum() / np.prod(hi - lo)),
    }


def elastic_predictions(stats_: dict) -> dict:
    """Eq. (5.20) in the three variants for the measured contact statistics: ``{variant: {"E", "nu"}}``."""
    out = {}
    for variant in identification.VARIANTS:
        E, nu = identification.elastic_constants(stats_["kn"], stats_["kt"], stats_["rho_c"], stats_["radius"],
                                                 variant)
        out[variant] = {"E": float(E), "nu": float(nu)}
    return out


def mean_interval(values, confidence: float = 0.95) -> dict:
    """Mean, sample standard deviation and the Student-t confidence half-width of the mean over ``values``.

    Non-finite values (a case that failed) are left out and counted in ``"dropped"``; the half-width is NaN for
    fewer than two values."""
    check_range("confidence", confidence, 0.0, 1.0, low_open=True, high_open=True)
    v = np.asarray(values, float)
    finite = np.isfinite(v)
    dropped = int(np.size(v) - np.count_nonzero(finite))
    v = v[finite]
    n = len(v)
    if n == 0:
        return {"mean": float("nan"), "std": float("nan"), "half_width": float("nan"), "n": 0, "dropped": dropped}
    mean = float(v.mean())
    if n < 2:
        return {"mean": mean, "std": float("nan"), "half_width": float("nan"), "n": 1, "dropped": dropped}
    std = float(v.std(ddof=1))
    half = float(stats.t.ppf(0.5 + confidence / 2, n - 1) * std / np.sqrt(n))
    return {"mean": mean, "std": std, "half_width": half, "n": n, "dropped": dropped}


def _spec(params: dict) -> SpecimenSpec:
    names = set(SpecimenSpec.__dataclass_fields__)
    return SpecimenSpec(**{k: v for k, v in params.items() if k in names})


def elastic_case(params: dict) -> dict:
    """One specimen, one small-strain test: E, ν per scheme, Eq. (5.20) per variant and their ratios.

    ``params``: any :class:`SpecimenSpec` field (``n_particles``, ``seed``, …), ``bonded`` (bool, contact bonds
    strong enough never to break), ``confinement`` [Pa], ``crossings``, ``window_fraction``, ``tolerance``,
    ``margin``, ``bond_gap`` (mean radii), ``cache`` (genesis cache: True, a directory, or False).
    Returns JSON-able numbers: ``E_<scheme>``, ``nu_<scheme>``, ``E_pred_<variant>``, ``nu_pred_<variant>``,
    ``ratio_E_<scheme>_<variant>``, ``ratio_nu_<scheme>_<variant>``, contact statistics, rate, runtime.
    """
    import time

    start = time.perf_counter()
    spec = _spec(params)
    specimen = genesis(spec, cache=params.get("cache", True))
    material = spec.material()
    if params.get("bonded", False):
        material = material.with_bonds(1e30, 1e30, gap=params.get("bond_gap", DemMaterial.bond_gap))
    result = elastic_test(specimen, material, params.get("confinement"),
                          window_fraction=params.get("window_fraction", 0.1),
                          crossings=params.get("crossings", 40.0), tolerance=params.get("tolerance", 1e-6))
    contacts = contact_statistics(result["sim"], params.get("margin", 1.5))
    predictions = elastic_predictions(contacts)
    out = {"n_particles": spec.n_particles, "seed": spec.seed, "bonded": bool(params.get("bonded", False)),
           "strain_rate": result["strain_rate"], "window_strain": result["window_strain"],
           "sliding": result["sliding"], "bonds": result["prepare"].get("bonds", 0),
           "coordination": result["prepare"]["coordination"],
           "porosity": specimen.info["porosity"], "porosity_interior": specimen.info["porosity_interior"],
           **{k: v for k, v in contacts.items()}}
    for scheme, m in result["moduli"].items():
        out[f"E_{scheme}"], out[f"nu_{scheme}"] = m["E"], m["nu"]
        for variant, pred in predictions.items():
            out[f"ratio_E_{scheme}_{variant}"] = m["E"] / pred["E"]
            out[f"ratio_nu_{scheme}_{variant}"] = m["nu"] / pred["nu"]
    for variant, pred in predictions.items():
        out[f"E_pred_{variant}"], out[f"nu_pred_{variant}"] = pred["E"], pred["nu"]
    out["seconds"] = time.perf_counter() - start
    return out


# ---------------------------------------------------------------------------------------------- Eq. (5.26)
def bond_strength_case(params: dict) -> dict:
    """One Table 5.3 test: an unconfined (or ``confinement``) test to failure of a contact-bonded specimen.

    ``params``: :class:`SpecimenSpec` fields, ``case`` (1, 2 or 3), ``target_stress`` [Pa] — the base strength f is
    chosen so that Eq. (5.26) (published) predicts this failure stress, f = σ/(ρ_c r) with ρ_c measured before
    loading — ``confinement`` (default 0, unconfined), ``bond_gap``, ``inertial_number``, ``margin``, ``cache``.
    Returns the peak stress per scheme, σ_ci, σ_y^Rankine and σ_y^Tresca per variant, and the crack modes.
    """
    import time

    start = time.perf_counter()
    spec = _spec(params)
    case = int(params.get("case", 1))
    if case not in BOND_CASES:
        raise ValueError(f"case must be one of {list(BOND_CASES)} (Table 5.3), got {case}")
    specimen = genesis(spec, cache=params.get("cache", True))
    probe, _ = specimen.prepare(spec.material())           # contact statistics of the consolidated specimen
    contacts = contact_statistics(probe, params.get("margin", 1.5))
    target = check_positive("target_stress", params.get("target_stress", 100e6))
    f = target / (contacts["rho_c"] * contacts["radius"])
    fn, ft = (m * f for m in BOND_CASES[case])
    material = spec.material().with_bonds(fn, ft, gap=params.get("bond_gap", DemMaterial.bond_gap))
    result = strength_test(specimen, material, params.get("confinement", 0.0), max_strain=0.05,
                           inertial_number=params.get("inertial_number", 1e-3))
    curve = result["curve"]
    cracks = result["sim"].cracks.as_arrays()
    out = {"case": case, "n_particles": spec.n_particles, "seed": spec.seed, "f_n": fn, "f_t": ft,
           "base_strength": f, "target_stress": target, "rho_c": contacts["rho_c"], "radius": contacts["radius"],
           "sigma_ci": result["crack_initiation"], "cracks": len(cracks["mode"]),
           "tension_share": float(np.mean(cracks["mode"] == "tension")) if len(cracks["mode"]) else float("nan"),
           "strain_rate": result["strain_rate"], "bonds": result["prepare"].get("bonds", 0)}
    for scheme in ("wall", "specimen", "sphere"):
        c = curve[scheme]
        out[f"sigma_f_{scheme}"] = float(np.max(c["sigma_axial"] - c["sigma_lateral"]))
    for variant in ("published", "consistent"):
        rankine, tresca = identification.failure_stresses(fn, ft, contacts["rho_c"], contacts["radius"], variant)
        out[f"rankine_{variant}"], out[f"tresca_{variant}"] = float(rankine), float(tresca)
    out["seconds"] = time.perf_counter() - start
    return out


# ---------------------------------------------------------------------------------------------- envelopes
@number_arguments
def mohr_coulomb_fit(sigma3: ArrayLike, sigma1: ArrayLike, *, cohesionless: bool = False) -> dict:
    """Least-squares line σ₁ = N_φ σ₃ + 2c√N_φ through peak states (compression positive) [Pa]:
    friction angle φ = asin((N_φ − 1)/(N_φ + 1)) [deg] and cohesion c [Pa] (Fig. 5.3, 5.4).

    ``cohesionless`` fits a line through the origin (c = 0, granular material; one state suffices)."""
    sigma3, sigma1 = np.asarray(sigma3, float), np.asarray(sigma1, float)
    if cohesionless:
        if not np.any(sigma3 > 0):
            raise ValueError("a cohesionless fit needs a peak state with positive confinement")
        slope, intercept = float(sigma3 @ sigma1 / (sigma3 @ sigma3)), 0.0
    elif len(sigma3) < 2 or np.ptp(sigma3) == 0:
        raise ValueError("a Mohr–Coulomb fit needs peak states at two or more different confinements")
    else:
        slope, intercept = np.polyfit(sigma3, sigma1, 1)
    if slope <= 1.0:
        raise ValueError(f"peak stresses do not grow faster than the confinement (slope {slope:.3f} ≤ 1)")
    phi = np.degrees(np.arcsin((slope - 1.0) / (slope + 1.0)))
    return {"friction_angle": float(phi), "cohesion": float(intercept / (2.0 * np.sqrt(slope))),
            "slope": float(slope), "intercept": float(intercept)}


def envelope_case(params: dict) -> dict:
    """One triaxial test to the peak: ``confinement`` [Pa], ``bonded`` (with ``bond_strength`` f [N] for both
    f^{n,c} and f^{t,c}, or ``target_stress`` for f from Eq. 5.26), ``shapes`` (sphere/dyad/peanut fractions),
    ``max_strain`` (granular: 0.01, as Fig. 5.10), plus :class:`SpecimenSpec` fields.
    Returns σ₃, the peak σ₁ (wall-based), the strain at peak and the number of cracks."""
    import time

    start = time.perf_counter()
    spec = _spec(params)
    specimen = genesis(spec, cache=params.get("cache", True))
    material = spec.material()
    if params.get("bonded", False):
        f = params.get("bond_strength")
        if f is None:
            probe, _ = specimen.prepare(material)
            contacts = contact_statistics(probe, params.get("margin", 1.5))
            f = params.get("target_stress", 100e6) / (contacts["rho_c"] * contacts["radius"])
        material = material.with_bonds(f, f, gap=params.get("bond_gap", DemMaterial.bond_gap))
    confinement = float(params.get("confinement", spec.stress))
    result = strength_test(specimen, material, confinement, max_strain=params.get("max_strain", 0.01),
                           inertial_number=params.get("inertial_number", 1e-3))
    peak = result["peak"]
    return {"n_particles": spec.n_particles, "seed": spec.seed, "shapes": list(spec.shapes),
            "bonded": bool(params.get("bonded", False)), "sigma3": confinement, "sigma1": peak["sigma_f"],
            "eps_peak": peak["eps_axial"], "cracks": int(result["curve"].cracks[-1]),
            "seconds": time.perf_counter() - start}


#: the demo's specimen: 150 spheres whose consolidation is accepted (walls within 9 % of σ0; seed 0 ends 20 % off
#: and would be made anew at every call), so it is cached after the first call
DEMO_SPEC = SpecimenSpec(n_particles=150, seed=5, aspect=1.5)
