"""Example scenes with analytic answers: the verification cases of the chapter, each a function returning a dict.

Every scene builds a small :class:`~abrakit.dem.simulation.Simulation`, runs it and returns what it measured next
to the closed-form value. Units SI. Random scenes take an explicit ``seed`` (``np.random.default_rng(seed)``).

- :func:`two_sphere_impact` and :func:`sphere_wall_impact`: contact duration π/(ω₀√(1−ζ²)), restitution
  e = exp(−ζπ/√(1−ζ²)) with dashpots, e = √((1−α)/(1+α)) with local damping, peak overlap v₀/ω₀;
- :func:`rolling_sphere`: a sphere thrown on a frictional plane rolls from t* = 2v₀/(7μg) on, at v = 5v₀/7;
- :func:`bonded_pair`: contact/parallel bond broken in tension, shear or bending at its strength;
- :func:`bonded_chain_wave`: a pulse runs along a bonded chain at c = ℓ√(k/m);
- :func:`settling`: spheres rain into a box under gravity with local damping;
- :func:`dense_packing`: a jittered, polydisperse FCC packing in a wall box (the benchmark's specimen).
"""

from __future__ import annotations

import warnings

import numpy as np

from abrakit.dem.bonds import install_contact_bonds, install_parallel_bonds
from abrakit.dem.contact_laws import Linear
from abrakit.dem.measure import coordination_number, energy_balance, kinetic_energy, porosity
from abrakit.dem.simulation import Simulation
from abrakit.dem.state import Particles, sphere_mass
from abrakit.dem.walls import Walls
from abrakit.validation import (
    check_finite,
    check_integer,
    check_option,
    check_positive,
    check_range,
    number_arguments,
)


def impact_analytic(kn, mass, velocity, damping_ratio=0.0, local_damping=0.0) -> dict:
    """Closed-form normal impact of a linear spring–dashpot contact with effective mass ``mass`` [kg].

    Dashpots (ratio ζ, Eq. 4.10): ω₀ = √(K^n/m), duration π/(ω₀√(1−ζ²)), e = exp(−ζπ/√(1−ζ²)), peak overlap
    (v₀/ω₀) exp(−ζφ/√(1−ζ²)) with φ = atan2(√(1−ζ²), ζ). Local damping α instead: loading runs at ω₀√(1+α),
    unloading at ω₀√(1−α), so e = √((1−α)/(1+α)) and the peak overlap is v₀/(ω₀√(1+α)).
    """
    zeta = check_range("damping_ratio", damping_ratio, 0.0, 1.0, high_open=True)
    alpha = check_range("local_damping", local_damping, 0.0, 1.0, high_open=True)
    kn, mass, velocity = check_positive("kn", kn), check_positive("mass", mass), check_finite("velocity", velocity)
    w0 = np.sqrt(kn / mass)
    if alpha:
        up, down = w0 * np.sqrt(1 + alpha), w0 * np.sqrt(1 - alpha)
        return {"omega0": w0, "duration": 0.5 * np.pi * (1 / up + 1 / down),
                "restitution": np.sqrt((1 - alpha) / (1 + alpha)), "peak_overlap": velocity / up}
    root = np.sqrt(1.0 - zeta**2)
    phi = np.arctan2(root, zeta)
    return {"omega0": w0, "duration": np.pi / (w0 * root), "restitution": np.exp(-zeta * np.pi / root),
            "peak_overlap": velocity / w0 * np.exp(-zeta * phi / root)}


def _crossings(t, u):
    """Times where ``u`` changes sign, linearly interpolated."""
    s = np.flatnonzero(np.sign(u[:-1]) != np.sign(u[1:]))
    return t[s] - u[s] * (t[s + 1] - t[s]) / (u[s + 1] - u[s])


def _run_impact(sim, overlap_of, relative_velocity_of, v0, analytic, steps_per_contact):
    t_list, u_list = [sim.time], [overlap_of(sim)]
    steps = int(2.5 * steps_per_contact)
    for _ in range(steps):
        sim.step()
        t_list.append(sim.time)
        u_list.append(overlap_of(sim))
    t, u = np.array(t_list), np.array(u_list)
    cross = _crossings(t, u)
    if len(cross) < 2:
        raise RuntimeError("the impact did not finish within the simulated time")
    peak = int(np.argmax(u))
    a, b, c = u[peak - 1], u[peak], u[peak + 1]            # parabola through the three samples at the peak
    peak_overlap = b + (a - c) ** 2 / (8 * (2 * b - a - c))
    return {
        "duration": float(cross[1] - cross[0]),
        "restitution": float(relative_velocity_of(sim) / v0),
        "peak_overlap": float(peak_overlap),
        "duration_analytic": float(analytic["duration"]),
        "restitution_analytic": float(analytic["restitution"]),
        "peak_overlap_analytic": float(analytic["peak_overlap"]),
        "dt": sim.dt, "time": t, "overlap": u,
        "energy": energy_balance(sim),
    }


@number_arguments
def two_sphere_impact(radius: float = 0.01, density: float = 2650.0, kn: float = 1e5, damping_ratio: float = 0.0,
                      velocity: float = 1.0, *, local_damping: float = 0.0, steps_per_contact: int = 200) -> dict:
    """Head-on impact of two equal spheres; returns measured and analytic duration, restitution, peak overlap.

    ``kn`` is the *contact* normal stiffness K^n [N/m] (each sphere gets k_n = 2K^n, so Eq. 4.11 returns K^n);
    ``velocity`` is the approach speed v₀ [m/s] (each sphere moves at v₀/2 in the centre-of-mass frame);
    ``damping_ratio`` is the dashpot ratio d_n of Eq. (4.10), ``local_damping`` the α of seed 002 Eq. (5).
    The time step is the contact duration / ``steps_per_contact``. Keys: ``duration`` [s], ``restitution``,
    ``peak_overlap`` [m], their ``*_analytic`` values, ``dt``, the sampled ``time``/``overlap`` and ``energy``.
    """
    radius, density, kn = (check_positive(n, v) for n, v in (("radius", radius), ("density", density),
                                                               ("kn", kn)))
    velocity = check_positive("velocity", velocity)
    mass = float(sphere_mass(radius, density))
    analytic = impact_analytic(kn, mass / 2, velocity, damping_ratio, local_damping)
    gap = 0.02 * velocity / analytic["omega0"]
    x = [[-radius - gap / 2, 0, 0], [radius + gap / 2, 0, 0]]
    p = Particles.spheres(x, radius, density, v=[[velocity / 2, 0, 0], [-velocity / 2, 0, 0]], kn=2 * kn)
    dt = analytic["duration"] / steps_per_contact
    sim = Simulation(p, law=Linear(damping_normal=damping_ratio), dt=dt, local_damping=local_damping,
                     skin=0.5 * radius)
    # start the clock at touch-down: the spheres first close the small gap
    sim.run(int(gap / velocity / dt) - 3, progress=False)

    def overlap(s):
        return 2 * radius - np.linalg.norm(s.particles.x[1] - s.particles.x[0])

    def separation_speed(s):
        return s.particles.v[1, 0] - s.particles.v[0, 0]

    return _run_impact(sim, overlap, separation_speed, velocity, analytic, steps_per_contact)


@number_arguments
def sphere_wall_impact(radius: float = 0.01, density: float = 2650.0, kn: float = 1e5, damping_ratio: float = 0.0,
                       velocity: float = 1.0, *, local_damping: float = 0.0, steps_per_contact: int = 200) -> dict:
    """A sphere hits a rigid wall at ``velocity``; K^n = ``kn`` (rigid wall, Eq. 4.11), effective mass m.

    Returns the same keys as :func:`two_sphere_impact`.
    """
    radius, density, kn = (check_positive(n, v) for n, v in (("radius", radius), ("density", density),
                                                               ("kn", kn)))
    velocity = check_positive("velocity", velocity)
    mass = float(sphere_mass(radius, density))
    analytic = impact_analytic(kn, mass, velocity, damping_ratio, local_damping)
    gap = 0.02 * velocity / analytic["omega0"]
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1), name="floor")
    p = Particles.spheres([[0, 0, radius + gap]], radius, density, v=[[0, 0, -velocity]], kn=kn)
    dt = analytic["duration"] / steps_per_contact
    sim = Simulation(p, walls=walls, law=Linear(damping_normal=damping_ratio), dt=dt,
                     local_damping=local_damping, skin=0.5 * radius)
    sim.run(int(gap / velocity / dt) - 3, progress=False)
    return _run_impact(sim, lambda s: radius - s.particles.x[0, 2], lambda s: s.particles.v[0, 2],
                       velocity, analytic, steps_per_contact)


def rolling_sphere(radius=0.01, density=2650.0, friction=0.3, velocity=1.0, *, gravity=9.81, kn=1e6,
                   steps=None) -> dict:
    """A sphere thrown (no spin) along a frictional floor: slides, then rolls from t* = 2v₀/(7μg) at 5v₀/7.

    Returns ``t_star``/``v_star`` (when the contact point's slip velocity v − ωr first vanishes) with their
    analytic values, and the sampled ``time``, ``velocity``, ``spin_speed`` (ωr). ``steps`` (default: to 2 t*)
    must take the run past 1.5 t*, where the final velocity is read.
    """
    radius, friction, velocity = (check_positive(n, v) for n, v in (("radius", radius), ("friction", friction),
                                                                     ("velocity", velocity)))
    mass = float(sphere_mass(radius, density))
    walls = Walls()
    walls.add((0, 0, 0), (0, 0, 1), friction=friction, name="floor")
    overlap = mass * gravity / kn                                  # resting overlap: no bouncing
    p = Particles.spheres([[0, 0, radius - overlap]], radius, density, v=[[velocity, 0, 0]], kn=kn,
                          friction=friction)
    law = Linear(damping_normal=0.5, damping_shear=0.5)
    sim = Simulation(p, walls=walls, law=law, gravity=(0, 0, -gravity), skin=radius)
    t_star = 2 * velocity / (7 * friction * gravity)
    shortest = int(np.ceil(1.5 * t_star / sim.dt)) + 1              # past 1.5 t*, where v_final is read
    steps = int(np.ceil(2.0 * t_star / sim.dt)) if steps is None else int(check_range("steps", steps, shortest))
    t, v, spin = np.empty(steps), np.empty(steps), np.empty(steps)
    for s in range(steps):
        sim.step()
        t[s] = sim.time - 0.5 * sim.dt                             # velocities live at half steps
        v[s], spin[s] = p.v[0, 0], p.w[0, 1] * radius
    slip = v - spin
    crossing = _crossings(t, slip)
    t_meas = float(crossing[0]) if len(crossing) else np.nan
    v_meas = float(np.interp(t_meas, t, v))
    return {"t_star": t_meas, "v_star": v_meas, "t_star_analytic": t_star, "v_star_analytic": 5 * velocity / 7,
            "v_final": float(np.mean(v[t > 1.5 * t_star])), "time": t, "velocity": v, "spin_speed": spin,
            "dt": sim.dt}


@number_arguments
def bonded_pair(mode="tension", kind="contact", *, radius: float = 0.01, density: float = 2650.0, kn: float = 1e6,
                strength: float | None = None, steps_to_failure: int = 2000) -> dict:
    """Two touching spheres, bonded, driven apart (``tension``), sideways (``shear``) or, for parallel bonds,
    turned (``bending``) at constant rate until the bond breaks.

    Contact bonds use strengths f^{n,c} = f^{t,c} = ``strength`` [N] (default 1 N); parallel bonds
    σ̄_c = τ̄_c = ``strength`` [Pa] (default 1 MPa), k̄^n = k̄^s = k_n/(π r²), λ̄ = 1. Returns the largest force
    (or moment) carried before failure, its analytic value, and the recorded crack.
    """
    mode = check_option("mode", mode, ("tension", "shear", "bending"))
    kind = check_option("kind", kind, ("contact", "parallel"))
    if mode == "bending" and kind == "contact":
        raise ValueError("contact bonds carry no moment: bending needs kind='parallel'")
    check_positive("radius", radius)
    p = Particles.spheres([[0, 0, 0], [2 * radius, 0, 0]], radius, density, kn=2 * kn, friction=0.5,
                          fixed=True)
    # both spheres move kinematically, so the step is set from the bond stiffness: 0.1 √(m/k)
    sim = Simulation(p, skin=0.5 * radius, dt=0.1 * np.sqrt(p.mass[0] / kn))
    area = np.pi * radius**2
    if kind == "contact":
        strength = 1.0 if strength is None else strength
        install_contact_bonds(sim, strength, strength)
        limit = strength                                    # [N]
    else:
        strength = 1e6 if strength is None else strength
        install_parallel_bonds(sim, kn=kn / area, ks=kn / area, tensile_strength=strength,
                               shear_strength=strength)
        b = sim.parallel_bonds
        limit = {"tension": strength * area, "shear": strength * area,
                 "bending": strength * b.inertia[0] / radius}[mode]
    stiffness = kn      # the contact (at zero overlap) carries nothing in tension or at first in shear
    if mode == "bending":
        rate = limit / (kn / area * sim.parallel_bonds.inertia[0]) / (steps_to_failure * sim.dt)
        p.w[0], p.w[1] = (0.0, -rate / 2, 0.0), (0.0, rate / 2, 0.0)   # opposite spins: bending, no shear
    else:
        speed = limit / stiffness / (steps_to_failure * sim.dt)
        p.v[1] = (speed, 0.0, 0.0) if mode == "tension" else (0.0, speed, 0.0)
    carried = []
    while len(sim.cracks) == 0 and len(carried) < 3 * steps_to_failure:
        sim.step()
        if kind == "contact":
            c = sim.contacts
            value = {"tension": -c.fn[0], "shear": float(np.linalg.norm(c.ft[:, 0]))}[mode] if len(c) else 0.0
        else:
            b = sim.parallel_bonds
            value = 0.0 if not len(b) else {"tension": -b.fn[0], "shear": float(np.linalg.norm(b.fs[:, 0])),
                                            "bending": float(np.linalg.norm(b.ms[:, 0]))}[mode]
        carried.append(float(value))
    cracks = sim.cracks.as_arrays()
    return {"peak": max(carried), "analytic": float(limit), "steps": len(carried),
            "crack_mode": str(cracks["mode"][0]) if len(cracks["mode"]) else None,
            "crack_kind": str(cracks["kind"][0]) if len(cracks["kind"]) else None,
            "crack_position": cracks["position"][0] if len(cracks["mode"]) else None,
            "increment": float(np.max(np.abs(np.diff(carried[:10])))) if len(carried) > 10 else np.nan}


@number_arguments
def bonded_chain_wave(n: int = 200, *, radius: float = 0.005, density: float = 2650.0, k: float = 1e5,
                      width: float = 8.0, amplitude: float | None = None) -> dict:
    """A right-running Gaussian pulse (width ``width`` spacings) along a chain of ``n`` contact-bonded spheres.

    The spacing is ℓ = 2r, the bond stiffness K^n = ``k``; the pulse peak is tracked and a line fitted to its
    position over time gives the wave speed, compared with c = ℓ√(k/m) (long waves of the discrete chain).
    """
    n = int(check_positive("n", n))
    check_positive("radius", radius)
    width = check_positive("width", width)
    if amplitude is not None:
        amplitude = check_finite("amplitude", amplitude)
    spacing = 2 * radius
    X = np.column_stack([np.arange(n) * spacing, np.zeros(n), np.zeros(n)])
    p = Particles.spheres(X, radius, density, kn=2 * k, friction=0.0)
    sim = Simulation(p, skin=0.5 * radius)
    install_contact_bonds(sim, 1e30, 1e30)
    mass = p.mass[0]
    c = spacing * np.sqrt(k / mass)
    W = width * spacing
    A = 0.01 * radius if amplitude is None else amplitude
    x0 = 0.25 * n * spacing
    u = A * np.exp(-(((X[:, 0] - x0) / W) ** 2))
    p.x[:, 0] = X[:, 0] + u
    p.v[:, 0] = -c * u * (-2 * (X[:, 0] - x0) / W**2)          # v = −c f'(x): runs towards +x
    t_end = 0.5 * n * spacing / c
    steps = int(np.ceil(t_end / sim.dt))
    times, peaks = [], []
    for s in range(steps):
        sim.step()
        if s % 10 == 0:
            disp = p.x[:, 0] - X[:, 0]
            k_max = int(np.clip(np.argmax(disp), 1, n - 2))
            a, b, cc = disp[k_max - 1: k_max + 2]
            shift = 0.5 * (a - cc) / (a - 2 * b + cc)         # parabolic peak refinement
            times.append(sim.time)
            peaks.append((k_max + shift) * spacing)
    slope = np.polyfit(times, peaks, 1)[0]
    return {"speed": float(slope), "speed_analytic": float(c), "steps": steps, "dt": sim.dt,
            "time": np.array(times), "peak_position": np.array(peaks)}


@number_arguments
def settling(n: int = 300, *, seed: int = 0, radius: float = 0.005, spread: float = 0.2, density: float = 2650.0,
             kn: float = 1e5, friction: float = 0.4, wall_friction: float = 0.0, local_damping: float = 0.3, box=None,
             steps: int | None = None, max_steps: int = 20_000, law=None, progress=False) -> tuple[Simulation, dict]:
    """``n`` polydisperse spheres (radii r(1 ± spread)) dropped from a loose grid into a box, settling under
    gravity.

    Damping: normal dashpots with d_n = 0.3 (restitution 0.37) and local damping α = 0.3 by default — the
    quasi-static α = 0.7 would also slow the free fall to 0.3 g. The box is about √(n/6) mean diameters wide,
    so the settled bed is a few layers deep, and its walls are frictionless by default (frictional walls in a
    narrow box hold arches that creep for a long time).
    ``steps=None`` runs until the kinetic energy is below 10⁻⁴ of the potential energy released (at most
    ``max_steps``). Spheres without rolling resistance keep rolling on a flat bed (local damping acts on the
    unbalanced force, which vanishes for pure rolling), so the last rearrangements die out slowly.
    Returns the simulation and a summary (porosity of the bed, coordination, kinetic energy, energy closure).
    Reproducible: positions and radii come from ``np.random.default_rng(seed)``.
    """
    rng = np.random.default_rng(seed)
    n = int(check_positive("n", n))
    check_positive("radius", radius)
    check_range("spread", spread, 0.0, 1.0, high_open=True)
    check_positive("density", density)
    check_positive("kn", kn)
    check_range("wall_friction", wall_friction, 0.0, None)
    max_steps = int(check_range("max_steps", max_steps, 1, None))       # the settling loop's bound
    if steps is not None:
        steps = int(check_range("steps", steps, 1, None))               # the summary's energy needs a step
    side = 2 * radius * max(np.sqrt(n / 6.0), 3.0) if box is None else box
    per_layer = max(int(side / (2.1 * radius * (1 + spread))) ** 2, 1)
    m = int(np.sqrt(per_layer))
    layers = int(np.ceil(n / per_layer))
    pitch = side / m
    gx, gy, gz = np.meshgrid(np.arange(m), np.arange(m), np.arange(layers), indexing="ij")
    x = np.column_stack([(gx.ravel() + 0.5) * pitch, (gy.ravel() + 0.5) * pitch, (gz.ravel() + 0.5) * pitch
                         + radius])[:n]
    # random offsets within each grid cell, so that no sphere starts exactly on top of another (a stacked
    # column is an unstable equilibrium that would topple slowly)
    x[:, :2] += rng.uniform(-1, 1, (n, 2)) * max(0.5 * pitch - radius * (1 + spread), 0.0)
    radii = radius * rng.uniform(1 - spread, 1 + spread, n)
    height = (layers + 1) * pitch + 2 * radius
    walls = Walls.box((0, 0, 0), (side, side, height), friction=wall_friction)
    p = Particles.spheres(x, radii, density, kn=kn, friction=friction)
    law = Linear(damping_normal=0.3) if law is None else law
    sim = Simulation(p, walls=walls, law=law, gravity=(0, 0, -9.81), local_damping=local_damping,
                     domain=((-side, -side, -side), (2 * side, 2 * side, 3 * height)))
    if steps is None:
        z0 = p.x[:, 2].copy()
        while sim.step_count < max_steps:
            sim.run(500, progress=False)
            released = float(np.sum(p.mass * 9.81 * (z0 - p.x[:, 2])))
            if sim.step_count > 3000 and kinetic_energy(sim) < 1e-4 * released:
                break
    else:
        sim.run(steps, progress=progress, desc="settling")
    top = np.max(p.x[:, 2] + p.radius)
    summary = {"particles": n, "steps": sim.step_count, "time": sim.time, "dt": sim.dt,
               "porosity": porosity(sim, side * side * top), "coordination": coordination_number(sim),
               "kinetic_energy": kinetic_energy(sim), "energy": energy_balance(sim)}
    return sim, summary


def dense_packing(n=1000, *, seed=0, radius=0.001, spread=0.1, overlap=0.005, density=2650.0, kn=1e6,
                  friction=0.5, wall_friction=0.0, agitation=0.01, law=None, walls=True, track_energy=False,
                  **sim_kwargs):
    """A dense specimen: ≈ ``n`` spheres on a jittered FCC lattice with radii r(1 ± spread), lattice neighbours of
    the nominal radius overlapping by about ``overlap``·r, in a box of (frictionless by default) walls, with random
    velocities (``agitation`` · √(k/m) r).

    This is the packing the benchmarks time (mean coordination ≈ 6–8, like a consolidated specimen). It starts
    stressed, not relaxed: neighbours drawn large overlap by up to about 2·``spread``·r, and the first steps
    release those springs (the Simulation's warning about deep initial overlaps is expected here and silenced).
    """
    rng = np.random.default_rng(None if seed is None else check_integer("seed", seed, 0))
    n = int(check_positive("n", n))
    check_positive("radius", radius)
    check_range("spread", spread, 0.0, 1.0, high_open=True)
    check_range("wall_friction", wall_friction, 0.0, None)
    check_range("overlap", overlap, -1.0, 1.0, low_open=True, high_open=True)
    check_positive("agitation", agitation, allow_zero=True)
    m = max(int(round((n / 4) ** (1 / 3))), 1)                 # m × m cells per layer, layers filled upwards
    layers = int(np.ceil(n / (4 * m * m)))
    a = 2 * np.sqrt(2) * radius * (1 - overlap)                # FCC cube edge from the neighbour distance
    cell = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.stack(np.meshgrid(np.arange(m), np.arange(m), np.arange(layers), indexing="ij"), -1).reshape(-1, 1, 3)
    x = ((g + cell) * a).reshape(-1, 3)
    x = x[np.lexsort((x[:, 0], x[:, 1], x[:, 2]))][:n] + radius
    x += rng.normal(0, 0.01 * radius, x.shape)
    radii = radius * rng.uniform(1 - spread, 1 + spread, len(x))
    p = Particles.spheres(x, radii, density, kn=kn, friction=friction)
    speed = agitation * np.sqrt(kn / p.mass.mean()) * radius
    p.v[:] = rng.normal(0, speed, x.shape)
    box = None
    if walls:
        lo = x.min(axis=0) - radii.max() * (1 - overlap)
        hi = x.max(axis=0) + radii.max() * (1 - overlap)
        box = Walls.box(lo, hi, friction=wall_friction)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*start overlapping", category=RuntimeWarning)
        return Simulation(p, law=law or Linear(), walls=box, track_energy=track_energy, **sim_kwargs)

