"""How many grains touch the tool (Ch. 8.3): a bed of spheres pressed by a plate, and the grains on its floor.

The seed fills a box with grains, lets them settle under gravity, presses a plate on top and counts the grains
touching the bottom face per unit area, N_c. One grain size gives N_c = 0.9 D⁻² (Eq. 8.7); a binary mixture of
coarse grains A and fine grains B (r_AB = D_A/D_B ≥ 1, volume fractions θ_A + θ_B = 1, Eq. 8.8, 8.9) gives
N_c,i = a θ_i^α D_i^β (8.10) with β = −2 and α_A = 2 − 1/r_AB, α_B = 1/r_AB (8.11, 8.12).

Normalisation. The seed's box had unit edge, and the diameter on the axis of its Fig. 8.13 is "divided by the
length of the contacting surface": N_c counts grains per box face, D is D/L. Either way the invariant is the
dimensionless areal density N_c D² (grains per unit area times the diameter squared), and Eq. (8.7) says
N_c D² = 0.9. In SI, :func:`abrakit.wear.contacting_particles` reads D in m and returns N_c in 1/m².

Protocol (:func:`pressed_bed`), all lengths in units of the coarse diameter D:

1. grains are placed at random, without overlap, in a column of the box at 25 % solid fraction (random
   sequential addition, :func:`loose_column`); the box is square, L × L, with frictionless walls;
2. they settle under gravity with dashpots (d_n = 0.3) and local damping α = 0.3 until the unbalanced-force
   ratio (:func:`unbalanced_force_ratio`) is below 0.05; with ``shake`` the two x walls first move together
   back and forth (square-wave velocity, ``shake`` D per half period of 200 steps, ``shake_cycles`` periods, the
   seed's "small velocity applied to the side walls") and return to their places;
3. the top wall is lowered onto the bed and held at the pressure ``p`` by a servo; the dashpots are removed (a
   servo fights a velocity-dependent force) and the local damping raised to α = 0.7, until the unbalanced-force
   ratio is below ``balance`` (10⁻³; going on to 10⁻⁵ changes no count in the benchmark) and the plate
   stress within 0.1 % of ``p``.

Dimensionless groups, held fixed when D or L change: the box in diameters L/D; the bed height in diameters
(``layers``, the height at 62 % solid fraction); the overlap scale ε (linear contacts, particle stiffness
k_i = 2 p D_i/ε, so a contact between two equal grains carrying the force p D² overlaps by ε D; floor contacts,
which carry plate and weight, overlap by ≈ 0.75 ε D); the weight of the bed over the plate force
(``gravity_ratio`` = W/(p L²), which sets g); friction.
With all of them fixed the experiment is exactly similar: doubling D and L doubles every length and gives the
same count (a test checks it to the bit). So N_c D² can only depend on D through L/D — the seed's fixed box — and
on the wall zones, which :func:`contact_census` excludes. It does depend on ε and on friction: stiffer grains and
frictional grains touch the floor less often (``benchmarks/bench_experiments_contacting.py`` extrapolates to
rigid grains).

Contact criterion (:func:`count_touching`): a grain touches the face when the gap between its surface and the
plane, s − r, is at most ``tol`` (s the distance of its centre from the plane, r its radius); overlapping grains
have a negative gap. The census uses tol = 10⁻³ D: far above round-off, far below the gap of any grain that is not
in contact (in a pressed bed the gaps are bimodal, and the counts at tol = 0, 10⁻³ D and 10⁻² D agree, see the
benchmark). A grain is counted where its contact point (its centre projected on the face) lies in the window:
the face minus a band of width ``wall_zone`` along each lateral wall.

Units SI: m, kg, s, N, Pa.
"""

from __future__ import annotations

import time

import numpy as np
from scipy import optimize, stats
from scipy.spatial import cKDTree

from abrakit.dem import Linear, Particles, Simulation, Walls
from abrakit.dem.kernels import HAVE_NUMBA
from abrakit.dem.measure import unbalanced_force_ratio
from abrakit.validation import check_finite, check_option, check_positive, check_range, check_shape

SEED_COEFFICIENT = 0.9
"""a in N_c = a D⁻², Eq. (8.7)."""

PACKED_FRACTION = 0.62
"""Solid fraction used to size a bed from its height (a frictionless random packing is ≈ 0.62–0.64)."""

LOOSE_FRACTION = 0.25
"""Solid fraction of the random column the grains start from (random sequential addition jams at ≈ 0.38)."""


def seed_exponents(ratio):
    """The seed's exponents of θ_i in Eq. (8.10): α_A = 2 − 1/r_AB (8.11a), α_B = 1/r_AB (8.11b)."""
    ratio = check_range("ratio", ratio, 1.0, None)
    return 2.0 - 1.0 / ratio, 1.0 / ratio


# --- the count ---------------------------------------------------------------------------------------------


def _plane(plane):
    try:
        point, normal = plane
    except (TypeError, ValueError) as exc:
        raise TypeError("plane must be (point, normal), two 3-vectors; the normal points into the bed") from exc
    point = np.asarray(check_finite("plane point", point), float).reshape(3)
    normal = np.asarray(check_finite("plane normal", normal), float).reshape(3)
    length = np.linalg.norm(normal)
    if length == 0.0:
        raise ValueError("plane normal must be a non-zero vector")
    return point, normal / length


def touching_mask(positions, radii, plane, tol, window=None) -> np.ndarray:
    """Which spheres touch the plane: gap s − r ≤ ``tol``, with s = (x − x₀)·n the centre's distance [m].

    ``positions`` (N, 3) [m]; ``radii`` (N,) or scalar [m]; ``plane`` = (point x₀, normal n), n pointing into the
    bed; ``tol`` ≥ 0 [m]. ``window`` = (lower, upper), two 3-vectors [m] (±inf for no bound): only spheres whose
    contact point x − s n (the centre projected on the plane) lies in that box, ends included, are counted;
    ``None`` counts the whole plane. Spheres behind the plane (s < 0) are an error: they are not in the bed.
    """
    x = np.array(check_finite("positions", positions), float, ndmin=2)
    check_shape("positions", x, (None, 3))
    r = np.broadcast_to(check_positive("radii", radii), (len(x),))
    tol = check_positive("tol", tol, allow_zero=True)
    point, normal = _plane(plane)
    s = (x - point) @ normal
    if np.any(s < 0.0):
        raise ValueError(f"{int(np.sum(s < 0))} sphere centre(s) lie behind the plane: flip its normal or the "
                         "plane point")
    mask = s - r <= tol
    if window is not None:
        lower, upper = (np.asarray(w, float).reshape(3) for w in window)
        if np.any(np.isnan(lower) | np.isnan(upper)) or np.any(upper < lower):
            raise ValueError(f"window must be (lower, upper) with upper >= lower, got {lower}, {upper}")
        contact = x - s[:, None] * normal
        mask &= np.all((contact >= lower) & (contact <= upper), axis=1)
    return mask


def count_touching(positions, radii, plane, tol, window=None) -> int:
    """Number of spheres touching the plane within ``tol`` whose contact point lies in ``window``.

    See :func:`touching_mask` for the arguments. Exact: a sphere counts iff its gap is ≤ ``tol``; the window
    test is on the contact point, so a lattice's count per window area is its areal density exactly.
    """
    return int(np.count_nonzero(touching_mask(positions, radii, plane, tol, window)))


# --- the bed ----------------------------------------------------------------------------------------------


def loose_column(radii, lower, upper, rng, *, oversample: int = 4, max_rounds: int = 500) -> np.ndarray:
    """Random non-overlapping positions (N, 3) for spheres of ``radii`` inside the box ``lower``–``upper``.

    Random sequential addition in vectorised rounds, size class by size class from the largest (classes 5 % wide
    in radius: a coarse grain finds no hole among fines already placed). Each round draws ``oversample``
    candidates per unplaced grain of the class, drops those overlapping a placed grain or an earlier candidate,
    and keeps the first survivor of each grain. Fails with ``ValueError`` if the box is too full (beyond ≈ 35 %
    solid).
    """
    radii = np.asarray(check_positive("radii", radii), float).reshape(-1)
    lower = np.asarray(check_finite("lower", lower), float).reshape(3)
    upper = np.asarray(check_finite("upper", upper), float).reshape(3)
    if np.any(upper - lower <= 2 * radii.max()):
        raise ValueError("the box must be wider than the largest grain on every axis")
    x = np.zeros((len(radii), 3))
    placed = np.zeros(0, np.int64)
    size_class = np.floor(np.log(radii.max() / radii) / np.log(1.05)).astype(np.int64)
    for group in np.unique(size_class):
        pending = np.flatnonzero(size_class == group)
        for _ in range(max_rounds):
            if not len(pending):
                break
            who = np.resize(pending, max(oversample * len(pending), 64))
            r = radii[who]
            candidate = rng.uniform(lower + r[:, None], upper - r[:, None])
            ok = np.ones(len(who), bool)
            tree = cKDTree(candidate)
            reach = r.max() + (radii[placed].max() if len(placed) else r.max())
            if len(placed):
                near = tree.sparse_distance_matrix(cKDTree(x[placed]), reach, output_type="coo_matrix")
                ok[near.row[near.data < r[near.row] + radii[placed][near.col]]] = False
            pairs = tree.query_pairs(2 * r.max(), output_type="ndarray")
            if len(pairs):
                a, b = pairs[:, 0], pairs[:, 1]
                clash = np.linalg.norm(candidate[a] - candidate[b], axis=1) < r[a] + r[b]
                ok[np.maximum(a, b)[clash]] = False          # the later candidate of a clashing pair gives way
            good = np.flatnonzero(ok)
            grains, first = np.unique(who[good], return_index=True)
            x[grains] = candidate[good[first]]
            placed = np.concatenate([placed, grains])
            pending = pending[~np.isin(pending, grains)]
        if len(pending):
            raise ValueError(f"could not place {len(pending)} of {len(radii)} grains: the column is too full; "
                             "make it taller")
    return x


def _grain_counts(diameter, fine_diameter, theta_coarse, box, layers):
    """Numbers of coarse and fine grains for a bed ``layers`` coarse diameters high at 62 % solid fraction."""
    solid = PACKED_FRACTION * box * box * layers * diameter
    n_coarse = int(round(theta_coarse * solid / (np.pi / 6 * diameter**3)))
    n_fine = 0 if fine_diameter is None else int(round((1 - theta_coarse) * solid / (np.pi / 6 * fine_diameter**3)))
    return n_coarse, n_fine


SETTLED = 0.05
"""Unbalanced-force ratio that ends the settling stage."""

CHECK_EVERY = 200
"""Steps between two checks of equilibrium."""


def _settle(sim: Simulation, max_steps: int, shake: float = 0.0, cycles: int = 0) -> None:
    """Stage 2: shake the x walls by ``shake`` [m] for ``cycles`` periods (if ``shake``), then run under gravity
    until the unbalanced-force ratio is below :data:`SETTLED`."""
    walls = sim.walls
    sides = [walls.index("xmin"), walls.index("xmax")]
    home = walls.point[sides, 0].copy()
    chunk = CHECK_EVERY // 10
    for half in range(2 * cycles if shake else 0):     # out by ``shake`` and back, one half period each
        target = home + (shake if half % 2 == 0 else 0.0)
        for left in range(10, 0, -1):                  # the speed that arrives on time (Δt follows the contacts)
            walls.velocity[sides, 0] = (target - walls.point[sides, 0]) / (left * chunk * sim.dt)
            sim.run(chunk, progress=False)
    walls.velocity[sides, 0] = 0.0
    walls.point[sides, 0] = home                       # the last chunk's round-off undone
    while sim.step_count < max_steps:
        sim.run(CHECK_EVERY, progress=False)
        if unbalanced_force_ratio(sim) < SETTLED:
            return


def _press(sim: Simulation, pressure, d_min, balance, max_steps, history):
    """Stage 3: lower the top wall onto the bed and hold ``pressure`` with a servo until equilibrium.

    Dashpots are switched off (the servo would fight a velocity-dependent force) and the local damping raised to
    0.7. Returns (converged, unbalanced-force ratio, plate stress [Pa], history rows).
    """
    walls, grains = sim.walls, sim.particles
    sim.law = Linear()
    sim.local_damping = 0.7
    plate, floor = walls.index("zmax"), walls.index("zmin")
    area = walls.box_area("z")
    walls.point[plate, 2] = np.max(grains.x[:, 2] + grains.radius) + 0.01 * d_min
    sim.rebuild()
    walls.add_servo(plate, pressure, area, relaxation=0.2, max_speed=1e-3 * d_min / sim.dt)
    ratio, stress, trace = np.inf, 0.0, []
    while sim.step_count < max_steps:
        sim.run(CHECK_EVERY, progress=False)
        ratio = unbalanced_force_ratio(sim)
        stress = float(walls.normal_force(plate)) / area
        if history:
            trace.append({"step": sim.step_count, "unbalanced": ratio, "plate_stress_ratio": stress / pressure,
                          "floor_count": count_touching(grains.x, grains.radius,
                                                        (walls.point[floor], walls.normal[floor]), 1e-3 * d_min)})
        if ratio < balance and abs(stress / pressure - 1.0) < 1e-3:
            return True, ratio, stress, trace
    return False, ratio, stress, trace


def pressed_bed(diameter, *, box, fine_diameter=None, theta_coarse=1.0, layers=4.0, pressure=1e4, overlap=1e-2,
                gravity_ratio=0.5, friction=0.0, density=2200.0, seed=0, balance=1e-3, max_steps=80_000,
                kernel="auto", history=False, shake: float = 0.0, shake_cycles: int = 10) -> tuple[Simulation, dict]:
    """Grains settled under gravity in a square box and pressed by a servo plate (protocol: module doc).

    ``diameter`` D (coarse grains A) [m]; ``box`` lateral edge L [m]; ``fine_diameter`` D_B ≤ D [m] and
    ``theta_coarse`` θ_A (volume fraction of A) for a binary mixture; ``layers`` bed height in D; ``pressure`` p
    on the plate [Pa]; ``overlap`` ε (contact stiffness k_i = 2 p D_i/ε); ``gravity_ratio`` weight of the bed over
    p L²; ``friction`` μ of grain contacts (walls are frictionless); ``density`` [kg/m³] (quartz, Table 8.3:
    2200); ``seed`` of ``np.random.default_rng``; ``balance`` the final unbalanced-force ratio; ``kernel``
    "numpy", "numba" or "auto" (numba if installed); ``history`` records, every 200 steps of the pressing stage,
    the unbalanced-force ratio, the plate stress over p and the number of grains on the whole floor. ``shake``
    (in D, ≥ 0) and ``shake_cycles`` shake the side walls before the settling (protocol step 2).

    Returns the simulation and a summary: grain numbers, steps of each stage, whether equilibrium was reached
    within ``max_steps`` (``converged``), final unbalanced-force ratio, plate stress over p, solid fraction,
    mean floor overlap over D, and run time [s].
    """
    D = check_positive("diameter", diameter)
    L = check_positive("box", box)
    if L < 3 * D:
        raise ValueError(f"box must be at least 3 diameters wide, got L/D = {L / D:.3g}")
    mixture = fine_diameter is not None
    D_B = check_range("fine_diameter", fine_diameter, 0.0, D, low_open=True) if mixture else None
    theta = check_range("theta_coarse", theta_coarse, 0.0, 1.0)
    if not mixture and theta != 1.0:
        raise ValueError("theta_coarse < 1 needs fine_diameter (a binary mixture)")
    layers = check_range("layers", layers, 1.0, None)
    p = check_positive("pressure", pressure)
    eps = check_range("overlap", overlap, 0.0, 0.1, low_open=True)
    gamma = check_positive("gravity_ratio", gravity_ratio)
    mu = check_positive("friction", friction, allow_zero=True)
    shake = check_positive("shake", shake, allow_zero=True)
    shake_cycles = int(check_range("shake_cycles", shake_cycles, 0, None))
    check_range("balance", balance, 0.0, 1.0, low_open=True, high_open=True)  # NaN or <= 0: never balanced
    max_steps = int(check_range("max_steps", max_steps, 1, None))
    kernel = check_option("kernel", kernel, ("auto", "numpy", "numba"))
    kernel = ("numba" if HAVE_NUMBA else "numpy") if kernel == "auto" else kernel
    rng = np.random.default_rng(seed)
    start = time.perf_counter()

    n_coarse, n_fine = _grain_counts(D, D_B, theta, L, layers)
    if n_coarse + n_fine == 0:
        raise ValueError("the bed holds no grain: increase box or layers")
    diameters = np.concatenate([np.full(n_coarse, D), np.full(n_fine, D_B if mixture else D)])
    radii = diameters / 2
    solid = np.sum(np.pi / 6 * diameters**3)
    column = solid / (LOOSE_FRACTION * L * L)
    x = loose_column(radii, (0.0, 0.0, 0.0), (L, L, column), rng)
    walls = Walls.box((0.0, 0.0, 0.0), (L, L, column + D))
    grains = Particles.spheres(x, radii, density, kn=2 * p * diameters / eps, friction=mu)
    g = gamma * p * L * L / grains.mass.sum()
    sim = Simulation(grains, law=Linear(damping_normal=0.3), walls=walls, gravity=(0.0, 0.0, -g),
                     local_damping=0.3, track_energy=False, kernel=kernel)

    _settle(sim, max_steps, shake * D, shake_cycles)                     # stage 2
    settle_steps = sim.step_count
    converged, ratio, stress, trace = _press(sim, p, diameters.min(), balance, max_steps, history)   # stage 3

    plate = walls.index("zmax")
    top = float(walls.point[plate, 2])
    floor = sim.wall_contacts
    on_floor = (floor.i == walls.index("zmin")) & floor.touching
    summary = {
        "coarse_grains": n_coarse, "fine_grains": n_fine,
        "theta_coarse_actual": float(n_coarse * D**3 / (n_coarse * D**3 + n_fine * (D_B or D) ** 3)),
        "settle_steps": settle_steps, "press_steps": sim.step_count - settle_steps, "steps": sim.step_count,
        "converged": converged, "unbalanced": ratio, "plate_stress_ratio": stress / p,
        "solid_fraction": float(solid / (L * L * top)), "bed_height": top / D,
        "floor_overlap": float(np.mean(floor.overlap[on_floor] / (2 * grains.radius[floor.j[on_floor]])))
        if on_floor.any() else 0.0,
        "gravity": g, "dt": sim.dt, "kernel": kernel, "seconds": time.perf_counter() - start,
    }
    if history:
        summary["history"] = trace
    return sim, summary


def _box_edge(sim) -> float:
    walls = sim.walls
    lengths = walls.box_lengths()
    if not np.isclose(lengths[0], lengths[1]):
        raise ValueError("contact_census expects a square box (L × L floor)")
    return float(lengths[0])


def contact_census(sim: Simulation, *, wall_zone, tol) -> dict:
    """Grains touching the floor of a :func:`pressed_bed` box, per grain type, in the window without wall zones.

    ``wall_zone`` [m]: width of the band along each lateral wall whose grains are not counted (0 counts the whole
    floor); ``tol`` [m]: contact tolerance of :func:`count_touching`. For a mixture, grains are typed by radius
    (coarse: above the mean of the two radii). Returns ``area`` [m²] of the window and, for ``coarse``/``fine``/
    ``all``: ``count``, ``N_c`` [1/m²] and ``N_c_D2`` (N_c times that type's diameter squared; for ``all`` the
    coarse diameter).
    """
    p, walls = sim.particles, sim.walls
    L = _box_edge(sim)
    w = check_range("wall_zone", wall_zone, 0.0, L / 2, high_open=True)
    floor = walls.index("zmin")
    origin = walls.point[floor]
    lower = origin + np.array([w, w, -np.inf])
    upper = origin + np.array([L - w, L - w, np.inf])
    mask = touching_mask(p.x, p.radius, (origin, walls.normal[floor]), tol, (lower, upper))
    area = (L - 2 * w) ** 2
    r_max, r_min = p.radius.max(), p.radius.min()
    coarse = p.radius > 0.5 * (r_max + r_min) if r_max > r_min * (1 + 1e-9) else np.ones(len(p), bool)
    out = {"area": area, "wall_zone": w, "tol": tol}
    for name, kind, d in (("coarse", coarse, 2 * r_max), ("fine", ~coarse, 2 * r_min), ("all", None, 2 * r_max)):
        count = int(np.count_nonzero(mask if kind is None else mask & kind))
        out[name] = {"count": count, "N_c": count / area, "N_c_D2": count / area * d * d, "diameter": d}
    return out


def floor_profile(sim: Simulation, *, bin_width, tol, reach=None) -> dict:
    """Areal density of floor contacts against the distance from the nearest lateral wall (the wall zones).

    Bins of ``bin_width`` [m] up to ``reach`` (default L/2); each bin's area is the band of the floor between its
    two distances. Returns ``distance`` (bin centres) [m], ``count`` and ``N_c`` [1/m²] per bin.
    """
    p, walls = sim.particles, sim.walls
    L = _box_edge(sim)
    width = check_positive("bin_width", bin_width)
    reach = L / 2 if reach is None else check_range("reach", reach, 0.0, L / 2, low_open=True)
    floor = walls.index("zmin")
    origin = walls.point[floor]
    mask = touching_mask(p.x, p.radius, (origin, walls.normal[floor]), tol)
    xy = p.x[mask, :2] - origin[:2]
    distance = np.min(np.concatenate([xy, L - xy], axis=1), axis=1)
    edges = np.arange(0.0, reach + 0.5 * width, width)
    edges = edges[edges <= reach + 1e-12 * L]
    count = np.histogram(distance, edges)[0]
    band = (L - 2 * edges[:-1]) ** 2 - (L - 2 * edges[1:]) ** 2
    return {"distance": 0.5 * (edges[:-1] + edges[1:]), "count": count, "N_c": count / band}


# --- a sweep case and the fits ------------------------------------------------------------------------------

BED_KEYS = ("diameter", "box", "fine_diameter", "theta_coarse", "layers", "pressure", "overlap", "gravity_ratio",
            "friction", "density", "seed", "balance", "max_steps", "kernel", "shake", "shake_cycles")
TOLERANCES = (0.0, 1e-3, 1e-2, 5e-2)
"""Contact tolerances of a case's census, in diameters of the finest grain."""

BOOKKEEPING = {"name", "version", "study", "variant"}
"""Case parameters that only label a case (they change its sweep key, not the bed)."""

WALL_ZONES = (0.0, 0.5, 1.0, 1.5, 2.0)
"""Wall-zone widths of a case's census, in coarse diameters."""


def contacting_case(params: dict) -> dict:
    """One sweep case (for :func:`abrakit.experiments.run_sweep`): a :func:`pressed_bed` and its census.

    ``params`` holds :func:`pressed_bed` arguments (``diameter`` and ``box`` required) plus optional
    ``wall_zone`` (in coarse diameters, default 1) and ``tol`` (in fine diameters, default 10⁻³) for the main
    census, and labels (:data:`BOOKKEEPING`) that are ignored. Returns the bed summary, the main census
    (``census``), the census for every tolerance in :data:`TOLERANCES` and wall zone in :data:`WALL_ZONES`, and
    the floor profile (bins of D/4).
    """
    bed = {k: params[k] for k in BED_KEYS if k in params}
    unknown = set(params) - set(BED_KEYS) - {"wall_zone", "tol"} - BOOKKEEPING
    if unknown:
        raise ValueError(f"unknown case parameter(s) {sorted(unknown)}; allowed: {BED_KEYS + ('wall_zone', 'tol')}")
    sim, summary = pressed_bed(**bed)
    D = float(params["diameter"])
    d_min = 2 * float(sim.particles.radius.min())
    zone, tol = float(params.get("wall_zone", 1.0)), float(params.get("tol", 1e-3))
    census = contact_census(sim, wall_zone=zone * D, tol=tol * d_min)
    by_tol = {f"{t:g}": contact_census(sim, wall_zone=zone * D, tol=t * d_min) for t in TOLERANCES}
    by_zone = {f"{z:g}": contact_census(sim, wall_zone=z * D, tol=tol * d_min) for z in WALL_ZONES
               if z * D < float(params["box"]) / 2}
    profile = floor_profile(sim, bin_width=D / 4, tol=tol * d_min)
    return {"bed": summary, "census": census, "by_tol": by_tol, "by_zone": by_zone,
            "profile": {k: np.asarray(v).tolist() for k, v in profile.items()}}


def fit_contact_coefficient(diameter, N_c) -> dict:
    """Fit N_c = a D^β (Eq. 8.7 form): ``a`` with β = −2 fixed (geometric mean of N_c D², the least-squares fit
    in log space) and the free pair (``a_free``, ``beta``) by least squares on log N_c = log a + β log D.

    ``diameter`` and ``N_c`` are matching 1-D arrays (any consistent units: D in m with N_c in 1/m², or D/L with
    N_c per face). Returns ``a``, ``a_spread`` (sample std of N_c D²), ``a_free``, ``beta``, ``beta_stderr``.
    """
    D = np.asarray(check_positive("diameter", diameter), float).ravel()
    N = np.asarray(check_positive("N_c", N_c), float).ravel()
    if D.shape != N.shape or len(D) < 2:
        raise ValueError("diameter and N_c must be matching arrays with at least two entries")
    invariant = N * D**2
    a = float(np.exp(np.mean(np.log(invariant))))
    out = {"a": a, "a_spread": float(invariant.std(ddof=1)), "a_free": np.nan, "beta": np.nan,
           "beta_stderr": np.nan}
    if np.ptp(np.log(D)) > 0:
        fit = stats.linregress(np.log(D), np.log(N))
        out.update(a_free=float(np.exp(fit.intercept)), beta=float(fit.slope), beta_stderr=float(fit.stderr))
    return out


def fit_mixture_exponent(theta, count, area, diameter, *, a=None) -> dict:
    """Exponent α of N_c,i = a θ_i^α D_i⁻² (Eq. 8.10 with β = −2) by Poisson maximum likelihood on the counts.

    Each case k contributes ``count[k]`` grains of type i touching a window of ``area[k]`` [m²], expected
    μ_k = a θ_k^α area_k / D_k² (``diameter[k]`` D_i [m], ``theta[k]`` θ_i in (0, 1]). With ``a`` given the
    coefficient is held (e.g. the homogeneous value); else it is fitted too. Zero counts are valid data.
    Returns ``alpha``, ``alpha_stderr`` and ``a``, ``a_stderr`` from the Fisher information (Poisson counts;
    the spread over seeds is the check on that assumption).
    """
    theta = np.asarray(check_range("theta", theta, 0.0, 1.0, low_open=True), float).ravel()
    c = np.asarray(check_positive("count", count, allow_zero=True), float).ravel()
    exposure = (np.asarray(check_positive("area", area), float) / np.asarray(check_positive("diameter", diameter),
                                                                               float) ** 2).ravel()
    exposure = np.broadcast_to(exposure, theta.shape)
    if c.shape != theta.shape:
        raise ValueError("theta and count must have the same length")
    if c.sum() == 0:
        raise ValueError("all counts are zero: nothing to fit")
    log_t = np.log(theta)
    if np.ptp(log_t) == 0:
        raise ValueError("theta must take at least two different values to fit an exponent")

    def coefficient(alpha):
        return a if a is not None else c.sum() / np.sum(theta**alpha * exposure)

    def score(alpha):                               # ∂ log-likelihood / ∂α = Σ (c − μ) log θ
        mu = coefficient(alpha) * theta**alpha * exposure
        return float(np.sum((c - mu) * log_t))

    lo, hi = -1.0, 1.0
    while score(lo) * score(hi) > 0 and hi < 64:
        lo, hi = lo - 2.0, hi * 2.0 + 1.0
    alpha = optimize.brentq(score, lo, hi, xtol=1e-12)
    a_hat = coefficient(alpha)
    mu = a_hat * theta**alpha * exposure
    if a is not None:
        return {"alpha": float(alpha), "alpha_stderr": float(1.0 / np.sqrt(np.sum(mu * log_t**2))), "a": float(a),
                "a_stderr": 0.0}
    fisher = np.array([[np.sum(mu), np.sum(mu * log_t)], [np.sum(mu * log_t), np.sum(mu * log_t**2)]])
    cov = np.linalg.inv(fisher)                     # parameters (log a, α)
    return {"alpha": float(alpha), "alpha_stderr": float(np.sqrt(cov[1, 1])), "a": float(a_hat),
            "a_stderr": float(a_hat * np.sqrt(cov[0, 0]))}
