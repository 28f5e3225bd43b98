"""The DEM calculation cycle of Fig. 4.1 in one class: :meth:`Simulation.step` is the whole time step.

    contact detection (Verlet list)  →  force–displacement law at every contact (Eq. 4.1–4.14)
        →  Newton's second law with local damping  →  leap-frog update (seed 002, Eq. 5–10)  →  walls move

Units SI. The engine is deterministic: the same input gives bit-identical results (scenes draw their random
packings from ``np.random.default_rng(seed)``).

Time step. ``dt=None`` (default) chooses Δt = ``safety`` · Δt_crit and re-evaluates it whenever the neighbour list
is rebuilt (contacts appear, Hertz contacts stiffen). A user-given ``dt`` above Δt_crit is refused with a
:class:`TimeStepError` (``dt_policy="raise"``) or replaced by ``safety`` · Δt_crit with a warning
(``dt_policy="reduce"``); it is never run silently unstable. ``dt_policy="allow"`` keeps it, with one warning: for
studying the instability itself (the exercise of the DEM chapter). Δt is also kept below the time in which the
fastest particle travels a quarter of the smallest radius (:meth:`Simulation.travel_time_step`), re-checked at every
rebuild: a 1000 m/s particle would otherwise step over a sphere without touching it.

Beside the class, in private modules: the compiled contact stage (``_compiled_step``), the sums of loads onto the
particles and the energy account (``_bookkeeping``), the contact sets across rebuilds and removals
(``_contact_sets``) and the time step's springs and policy (``_time_step``).
"""

from __future__ import annotations

import copy
import warnings
from dataclasses import dataclass

import numpy as np

from abrakit.compiled import HAVE_NUMBA
from abrakit.dem._bookkeeping import (
    _account,
    _elastic_energy,
    _gather,
    _pair_dashpot_loads,
    _place,
    _scatter,
    _scatter_pair_loads,
    _Taken,
)
from abrakit.dem._compiled_step import _ball_ball_compiled, _ball_wall_compiled, _wall_parameters
from abrakit.dem._contact_sets import _rebuilt_contacts, _renumbered
from abrakit.dem._time_step import _particle_springs, _policed_time_step, _travel_time_step
from abrakit.dem.bonds import CrackLog, ParallelBonds, _parallel_bond_update
from abrakit.dem.clumps import make_clumps
from abrakit.dem.contact_laws import ContactForces, Linear, _cross, _dot, _force_displacement, _rowdot
from abrakit.dem.fatigue_bonds import BROKEN, FatigueBonds
from abrakit.dem.integrate import _leapfrog, _local_damping, critical_time_step
from abrakit.dem.neighbours import VerletList, transfer_history, wall_candidates
from abrakit.dem.state import ContactSet, Particles
from abrakit.dem.walls import Walls
from abrakit.io import progress_bar
from abrakit.validation import check_finite, check_option, check_positive, check_range

#: Largest distance a particle may travel in one step, as a fraction of the smallest radius (automatic Δt).
MAX_TRAVEL = 0.25


class TimeStepError(ValueError):
    """The requested time step exceeds the critical one."""


class ParticleEscapeError(RuntimeError):
    """A particle left the simulation domain."""


@dataclass
class EnergyAccount:
    """Energy bookkeeping [J]. Stored parts are evaluated at the time of the last force evaluation; the
    dissipated parts and the work of walls, applied forces and prescribed motions are running sums."""

    kinetic: float = 0.0
    elastic: float = 0.0
    potential: float = 0.0
    friction: float = 0.0
    local_damping: float = 0.0
    dashpot: float = 0.0
    work_walls: float = 0.0
    work_applied: float = 0.0
    work_prescribed: float = 0.0
    initial: float | None = None

    @property
    def stored(self) -> float:
        return self.kinetic + self.elastic + self.potential

    @property
    def dissipated(self) -> float:
        return self.friction + self.local_damping + self.dashpot

    @property
    def work(self) -> float:
        return self.work_walls + self.work_applied + self.work_prescribed

    @property
    def error(self) -> float:
        """Closure: (stored + dissipated) − (initial stored + work in); zero for exact bookkeeping."""
        return self.stored + self.dissipated - (self.initial or 0.0) - self.work


COMPILED_SCATTER = HAVE_NUMBA
"""Whether the pair loads of contacts and bonds are summed onto the particles by a compiled loop (where numba is
installed; the same sums as np.bincount's, bit for bit), read at every step."""


class Simulation:
    """A DEM run: particles, a contact law, walls, bonds, clumps and the time step.

    Parameters
    ----------
    particles : Particles
    law : contact law (:class:`~abrakit.dem.contact_laws.Linear` by default)
    walls : Walls, optional
    gravity : (3,) [m/s²]
    dt : time step [s]; ``None`` chooses it (see module doc)
    safety : C_s in Δt = C_s Δt_crit (seed 002 Eq. 11)
    local_damping : α of seed 002 Eq. (5)/(6), 0 ≤ α < 1 (0.7 for quasi-static runs)
    skin : Verlet skin [m] (default 0.2 · mean radius)
    domain : ``(lower, upper)`` box; a particle outside it is an escape, handled by ``escape``
    escape : "raise" (:class:`ParticleEscapeError`) or "remove" (the particle is deleted and counted)
    planar : 2D mode, motion in the x–y plane only (use :meth:`Particles.disks`)
    track_energy : keep :attr:`energy` (costs a few percent)
    kernel : "numpy" (default) or "numba" (compiled particle–particle loop for the linear law, extra ``fast``)
    periodic : :class:`~abrakit.dem.periodic.Periodic` cell, optional: minimum-image contacts across its faces,
        positions wrapped at every Verlet rebuild, homogeneous strains (normal and shear) by :meth:`strain_cell`
        (no parallel bonds, no clumps)
    """

    def __init__(self, particles: Particles, *, law=None, walls: Walls | None = None, gravity=(0.0, 0.0, 0.0),
                 dt: float | None = None, safety: float = 0.8, dt_policy: str = "raise",
                 local_damping: float = 0.0, skin: float | None = None, domain=None, escape: str = "raise",
                 planar: bool = False, track_energy: bool = True, kernel: str = "numpy", periodic=None):
        if not isinstance(particles, Particles) or len(particles) == 0:
            raise ValueError("particles must be a non-empty Particles set (see Particles.spheres)")
        self.particles = particles
        self.law = Linear() if law is None else law
        self.neighbours = VerletList(0.0)
        self.kernel = kernel
        self.periodic = periodic
        self.walls = Walls() if walls is None else walls
        self.gravity = np.asarray(check_finite("gravity", gravity), float).reshape(3)
        self.safety = check_range("safety", safety, 0.0, 1.0, low_open=True)
        self.dt_policy = check_option("dt_policy", dt_policy, ("raise", "reduce", "allow"))
        self._warned_unstable = False
        self.local_damping = check_range("local_damping", local_damping, 0.0, 1.0, high_open=True)
        self.skin = 0.2 * float(np.mean(particles.radius)) if skin is None else check_positive("skin", skin)
        if domain is not None:
            domain = np.asarray(check_finite("domain", domain), float)
            if domain.shape != (2, 3) or np.any(domain[1] <= domain[0]):
                raise ValueError(f"domain must be ((xmin, ymin, zmin), (xmax, ymax, zmax)) with max > min, "
                                 f"got {domain.tolist()}")
        self.domain = domain
        self.escape = check_option("escape", escape, ("raise", "remove"))
        self.planar = bool(planar)
        self.track_energy = bool(track_energy)
        self.auto_dt = dt is None
        self._dt = np.inf if dt is None else check_positive("dt", dt)
        self.time = 0.0
        self.step_count = 0
        self.removed = 0
        self.applied_force: np.ndarray | None = None     # (N, 3) external forces [N], optional
        self.particle_force = np.zeros((len(particles), 3))   # last step's total force per particle [N]
        self.parallel_bonds = ParallelBonds.empty()
        self.fatigue_bonds = FatigueBonds.empty()
        self.cracks = CrackLog()
        self.energy = EnergyAccount()
        self.neighbours.skin = self.skin
        self.contacts = ContactSet.empty_history([], [], len(particles))
        self.wall_contacts = ContactSet.empty_history([], [], len(particles))
        self.clumps = make_clumps(particles)
        if periodic is not None and self.clumps is not None:
            raise ValueError("clumps are not supported in a periodic cell (their members would be wrapped one by one)")
        if self.planar:
            particles.x[:, 2] = particles.v[:, 2] = 0.0
            particles.w[:, :2] = 0.0
        if periodic is not None:
            periodic.check_range(2.0 * float(particles.radius.max()) + self.skin)
        self.refresh()
        self._warn_initial_overlaps()

    def _warn_initial_overlaps(self, limit: float = 0.05) -> None:
        """Warn when the start has pairs overlapping by more than ``limit`` of the smaller radius: each spring then
        releases ½ K U² in the first steps and sends its pair apart at U √(K/m*) (m* the pair's reduced mass)."""
        c, p = self.contacts, self.particles
        if not len(c):
            return
        d = self.branch(c.i, c.j)
        overlap = p.radius[c.i] + p.radius[c.j] - np.sqrt(_rowdot(d, d))
        ratio = overlap / np.minimum(p.radius[c.i], p.radius[c.j])
        deep = ratio > limit
        if not deep.any():
            return
        prm = {k: v[deep] if np.ndim(v) else v for k, v in c.prm.items()}
        stiffness = np.broadcast_to(self.law.normal_force(overlap[deep], prm)[1], overlap[deep].shape)
        speed = float(np.max(overlap[deep] * np.sqrt(stiffness / prm["mass"])))     # prm["mass"]: the pair's m*
        warnings.warn(f"{int(deep.sum())} particle pair(s) start overlapping by up to {100 * ratio.max():.0f} % of the "
                      f"smaller radius: released, they fly apart at up to {speed:.3g} m/s. Separate them, or let the "
                      "packing settle first with local damping (Simulation(local_damping=0.7) and dem.relax)",
                      RuntimeWarning, stacklevel=3)

    @property
    def kernel(self) -> str:
        """"numpy" or "numba" (the compiled contact loops, extra ``fast``); may be switched between steps."""
        return self._kernel

    @kernel.setter
    def kernel(self, value: str) -> None:
        check_option("kernel", value, ("numpy", "numba"))
        if value == "numba":
            from abrakit.dem.kernels import HAVE_NUMBA
            if not HAVE_NUMBA:
                raise ImportError("kernel='numba' needs numba: pip install abrakit[fast]")
            if type(self.law) is not Linear:
                raise ValueError("kernel='numba' implements the Linear law only; use kernel='numpy'")
        self._kernel = value
        self.neighbours.compiled = value == "numba"

    @property
    def dt(self) -> float:
        """The time step [s]. Assigning a value fixes it (no longer automatic) and applies ``dt_policy``."""
        return self._dt

    @dt.setter
    def dt(self, value: float) -> None:
        self._dt = check_positive("dt", value)
        self.auto_dt = False
        self.update_time_step()

    # ------------------------------------------------------------------ the calculation cycle (Fig. 4.1)
    def step(self) -> None:
        """One time step: contacts → forces → Newton + damping → leap-frog → walls."""
        if self.neighbours.needs_rebuild(self.particles.x, self.walls.point):
            self.rebuild()
        p, dt = self.particles, self.dt
        force = p.mass[:, None] * self.gravity + (0.0 if self.applied_force is None else self.applied_force)
        torque = np.zeros_like(force)
        if self.track_energy and (self.law.damping_normal or self.law.damping_shear):
            self._dashpot, self._dashpot_wall = np.zeros((2, len(p), 3)), 0.0   # dashpot force/moment sums
        stored = self._ball_ball(force, torque)                  # Eq. (4.1)–(4.14), contact bonds
        stored += self._ball_wall(force, torque)
        stored += self._parallel_bonds(force, torque)
        stored += self._fatigue_bonds(force, torque)
        self.particle_force = force                              # this step's force on each particle (reactions)
        kick = 0.5 * dt if self.step_count == 0 else dt             # v given at t = 0: start with a half kick
        if self.kernel == "numba" and not self.track_energy and self.clumps is None:
            from abrakit.dem.kernels import advance
            advance(p.x, p.v, p.w, force, torque, self.inv_mass, self.inv_inertia, self.local_damping, self.planar,
                    dt, kick)                                     # :meth:`_update` in one compiled loop
            self._move_walls(dt)
        else:
            self._update(force, torque, stored, kick)
        self.time += dt
        self.step_count += 1

    def _update(self, force, torque, stored, kick) -> None:
        """Newton's second law with local damping, the leap-frog update, clumps, walls, and the energy account."""
        p, dt = self.particles, self.dt
        v_old, w_old = (p.v.copy(), p.w.copy()) if self.track_energy else (None, None)
        force_total, torque_total = force, torque
        if self.local_damping:                                    # seed 002 Eq. (5), (6)
            force_total = force + _local_damping(force, p.v, self.local_damping)
            torque_total = torque + _local_damping(torque, p.w, self.local_damping)
        if self.planar:                                           # 2D: motion in the x–y plane only
            force_total[:, 2] = 0.0
            torque_total[:, :2] = 0.0
        _leapfrog(p.x, p.v, p.w, force_total, torque_total, self.inv_mass, self.inv_inertia, dt, kick)  # Eq. 7–9
        clump_damping = 0.0
        if self.clumps is not None:
            clump_damping = self.clumps.step(p, force, torque, dt, self.local_damping, kick)
        wall_velocity_old = self.walls.velocity.copy()
        self._move_walls(dt)
        if self.track_energy:
            _account(self, stored, force, force_total - force, torque_total - torque, v_old, w_old,
                     wall_velocity_old, clump_damping)

    def _move_walls(self, dt) -> None:
        """Servos set their walls' velocities from this step's wall forces; then every wall moves."""
        for servo in self.walls.servos:
            servo.update(self.walls, self._wall_stiffness[servo.wall], dt)
        self.walls.move(dt)

    def _ball_ball(self, force, torque) -> float:
        """Particle–particle contacts: geometry (Eq. 4.1–4.4), force–displacement law, sums onto particles.

        The NumPy path runs the law on the *live* contacts only, those that overlap or hold a bond: a gap in the
        Verlet list carries no force and forgets its spring (about half of the list in a dense packing).
        """
        p, c = self.particles, self.contacts
        if not len(c):
            return self._no_contacts(c)
        if self.kernel == "numba":                                    # the kernel updates the contact set
            r, overlap, n, failed = _ball_ball_compiled(self, force, torque)
            live, prm = slice(None), c.prm
        else:
            d, dist = self._branches(p.x)                             # Eq. (4.2)
            overlap = self._radius_sum - dist                         # Eq. (4.3)
            live = np.flatnonzero((overlap > 0.0) | c.bonded)
            n = np.take(d, live, axis=1) / dist[live]                 # Eq. (4.1), on the live contacts
            prm = _Taken(c.prm, live)
            r = self._live_contact_forces(live, prm, overlap, n, force, torque)
            failed = r.tension_failure.any() or r.shear_failure.any()
            c.ft = _place(r.ft, live, len(c))
            m = len(c)
            c.defer(normal=lambda: d / dist, fn=lambda: _place(r.fn, live, m), force=lambda: _place(r.force, live, m))
        c.overlap = overlap
        i, j, overlap = c.i[live], c.j[live], overlap[live]           # n: the live contacts' normals
        if failed:
            self._record_contact_cracks(r, i, j, np.arange(len(c))[live],
                                        _gather(p.x, i) + (p.radius[i] - 0.5 * overlap) * n)
        if not self.track_energy:
            return 0.0
        self.energy.friction += r.slip_dissipation
        if r.dashpot_force is not None:
            _pair_dashpot_loads(self._dashpot, r.dashpot_force, n, i, j, p.radius[i] - 0.5 * overlap,
                                p.radius[j] - 0.5 * overlap)
        return _elastic_energy(self.law, prm, overlap, c.bonded[live], c.bond_gap[live], r)

    def _live_contact_forces(self, live, prm, overlap, n, force, torque) -> ContactForces:
        """The law on the contacts ``live`` (indices; their parameters ``prm`` and normals ``n``; Eq. 4.4–4.10),
        their forces and moments summed onto the particles."""
        p, c = self.particles, self.contacts
        i, j, U = c.i[live], c.j[live], overlap[live]
        arm_i = p.radius[i] - 0.5 * U                                 # Eq. (4.4): centre to contact point
        arm_j = p.radius[j] - 0.5 * U
        v_rel = _gather(p.v, j) - _gather(p.v, i) - _cross(arm_i * _gather(p.w, i) + arm_j * _gather(p.w, j), n)
        bonds = (c.bonded[live], c.bond_gap[live], c.bond_normal_strength[live], c.bond_shear_strength[live]) \
            if c.bonded.any() else ()
        r = _force_displacement(self.law, prm, U, n, v_rel, np.take(c.ft, live, axis=1), self.dt, *bonds,
                               energy=self.track_energy)
        moment = _cross(r.force, n)                                    # −n × F per unit arm: torque = r' F × n
        _scatter_pair_loads(force, torque, i, j, r.force, arm_i * moment, arm_j * moment,   # B: +F, A: −F
                            compiled=COMPILED_SCATTER)
        return r

    def _branches(self, x):
        """Branch vectors d = x_B − x_A (3, M) of the candidate contacts (nearest images) and their lengths."""
        c = self.contacts
        d = _gather(x, c.j) - _gather(x, c.i)
        if self.periodic is not None:
            d = self.periodic.minimum_image(d, axis=0)
        return d, np.sqrt(_dot(d, d))

    def _ball_wall(self, force, torque) -> float:
        """Particle–wall contacts: the wall is body A, its normal the contact normal."""
        p, c, walls = self.particles, self.wall_contacts, self.walls
        walls.force[:] = 0.0
        self._wall_stiffness = np.zeros(len(walls))
        if not len(c):
            return self._no_contacts(c)
        k, j = c.i, c.j
        n = self._wall_normal
        if self.kernel == "numba":
            r, overlap = _ball_wall_compiled(self, force, torque)
            c.ft, c.overlap, c.normal, c.fn, c.force = r.ft, overlap, n, r.fn, r.force
            if not self.track_energy:
                return 0.0
            arm = self._radius_wall - 0.5 * overlap
        else:
            overlap = self._radius_wall - _dot(_gather(p.x, j) - _gather(walls.point, k), n)
            arm = self._radius_wall - 0.5 * overlap
            v_rel = _gather(p.v, j) - _gather(walls.velocity, k) - _cross(arm * _gather(p.w, j), n)
            r = _force_displacement(self.law, c.prm, overlap, n, v_rel, c.ft, self.dt, energy=self.track_energy)
            _scatter(force, j, r.force)
            _scatter(torque, j, arm * _cross(n, r.force), -1.0)
            _scatter(walls.force, k, r.force, -1.0)
            self._wall_stiffness = np.bincount(k, r.kn * r.touching, len(walls))
            c.ft, c.overlap, c.normal, c.fn, c.force = r.ft, overlap, n, r.fn, r.force
        if not self.track_energy:
            return 0.0
        self.energy.friction += r.slip_dissipation
        if r.dashpot_force is not None:      # the wall's share of dashpot power is −F_d · v_wall
            f = r.dashpot_force
            _scatter(self._dashpot[0], j, f)
            _scatter(self._dashpot[1], j, arm * _cross(n, f), -1.0)
            self._dashpot_wall += float(np.sum(f * _gather(walls.velocity, k)))
        return _elastic_energy(self.law, c.prm, overlap, c.bonded, c.bond_gap, r)

    @staticmethod
    def _no_contacts(c) -> float:
        c.overlap, c.fn = np.zeros(0), np.zeros(0)
        c.normal, c.force = np.zeros((3, 0)), np.zeros((3, 0))
        return 0.0

    def _parallel_bonds(self, force, torque) -> float:
        b = self.parallel_bonds
        if not len(b):
            return 0.0
        p = self.particles
        new, f, t_i, t_j, tension, shear, point = _parallel_bond_update(b, p.x, p.v, p.w, p.radius, self.dt)
        _scatter_pair_loads(force, torque, new.i, new.j, f, t_i, t_j, compiled=COMPILED_SCATTER)
        broken = tension | shear
        if broken.any():
            for mode, mask in (("tension", tension), ("shear", shear)):
                self.cracks.record(self.time, point[:, mask].T, new.i[mask], new.j[mask], mode, "parallel")
            new = new.take(~broken)
        self.parallel_bonds = new
        return new.energy() if self.track_energy else 0.0

    def _fatigue_bonds(self, force, torque) -> float:
        b = self.fatigue_bonds
        if not len(b):
            return 0.0
        p = self.particles
        new, f, t_i, t_j, point = b.update(p.x, p.v, p.w, p.radius, self.dt)
        _scatter_pair_loads(force, torque, new.i, new.j, f, t_i, t_j, compiled=COMPILED_SCATTER)
        broken = new.damage >= BROKEN
        if broken.any():
            tension = broken & (new.plastic[0] + new.fatigue[0] >= new.plastic[1] + new.fatigue[1])
            for mode, mask in (("tension", tension), ("shear", broken & ~tension)):
                self.cracks.record(self.time, point[:, mask].T, new.i[mask], new.j[mask], mode, "fatigue")
            new = new.take(~broken)
        self.fatigue_bonds = new
        return new.energy() if self.track_energy else 0.0

    def _record_contact_cracks(self, r, i, j, index, point):
        """Log the bonds that broke in ``r`` (results of the contacts ``index``, pairs ``i``–``j``, contact points
        ``point``) and unbond them."""
        for mode, mask in (("tension", r.tension_failure), ("shear", r.shear_failure)):
            self.cracks.record(self.time, point[:, mask].T, i[mask], j[mask], mode, "contact")
        self.contacts.bonded[index[r.tension_failure | r.shear_failure]] = False

    # ------------------------------------------------------------------ neighbour lists and time step
    def rebuild(self, extra_pairs=None, skin: float | None = None) -> None:
        """Rebuild the Verlet lists (keeping contact history and intact bonds) and re-check the time step."""
        if skin is not None and skin > self.skin:
            self.skin = self.neighbours.skin = float(skin)
        self._check_domain()
        p = self.particles
        if self.periodic is not None:
            self.periodic.wrap(p.x)
        self.contacts = c = _rebuilt_contacts(self, extra_pairs)
        self._radius_sum = p.radius[c.i] + p.radius[c.j]
        k, jw = wall_candidates(p.x, p.radius, self.walls, self.skin)
        wall_new = transfer_history(self.wall_contacts, ContactSet.empty_history(k, jw, len(p)))
        wall_new.prm = self.law.wall_parameters(p, self.walls, k, jw)
        self.wall_contacts = wall_new
        self._radius_wall = p.radius[jw]
        self._wall_normal = _gather(self.walls.normal, k)            # walls translate only: fixed until the next build
        if type(self.law) is Linear:                 # per contact, for the compiled wall loop
            self._wall_prm = _wall_parameters(wall_new.prm, len(jw))
        self._wall_stiffness = np.zeros(len(self.walls))
        self.neighbours.mark_built(p.x, self.walls.point)
        self.update_time_step()

    def refresh(self) -> None:
        """Re-derive everything cached from particle properties (call after changing radii, masses, stiffness)."""
        p = self.particles
        movable = ~p.fixed & (p.clump < 0)
        self.inv_mass = np.where(movable, 1.0 / p.mass, 0.0)
        self.inv_inertia = np.where(movable, 1.0 / p.inertia, 0.0)
        self.rebuild()

    def scale_radii(self, factor, *, keep_mass: bool = False) -> None:
        """Radius expansion: multiply the radii by ``factor`` (scalar or per particle), in place.

        Masses and inertias follow at constant density (m ∝ r³, I ∝ r⁵) unless ``keep_mass``; contact history and
        bonds are kept; the contact parameters and the time step are re-derived (:meth:`refresh`).
        """
        if self.clumps is not None:
            raise ValueError("scale_radii does not rescale clumps (their member offsets are rigid)")
        p = self.particles
        factor = np.broadcast_to(check_positive("factor", factor), p.radius.shape)
        p.radius *= factor
        if not keep_mass:
            p.mass *= factor**3
            p.inertia *= factor**5
        self.refresh()

    def critical_time_step(self) -> float:
        """Δt_crit = min √(m/Σk), √(I/Σk_rot) over the current candidate contacts (seed 002 Eq. 12) [s].

        Every particle counts at least one contact with a particle like itself, at 1 % overlap for Hertz, so
        the estimate is finite (and safe for a first impact) even in a loose gas.
        """
        p = self.particles
        k_t, k_r = _particle_springs(self)
        return critical_time_step(p.mass, p.inertia, k_t, k_r, movable=~p.fixed)

    def travel_time_step(self) -> float:
        """Δt at which the fastest particle moves :data:`MAX_TRAVEL` of the smallest radius (surface speed of its
        spin included) [s], ``inf`` at rest: a contact is then seen before the pair overlaps by more than that, so a
        fast particle cannot step over another one without touching it (tunnelling)."""
        return _travel_time_step(self.particles, MAX_TRAVEL)

    def update_time_step(self) -> float:
        """Apply the time-step policy after the contact set changed; returns Δt_crit. The step is also kept below
        :meth:`travel_time_step` (a fast particle would otherwise cross a contact zone in one step)."""
        dt_crit = self.critical_time_step()
        self._dt, refusal, self._warned_unstable = _policed_time_step(
            self._dt, dt_crit, self.travel_time_step(), auto=self.auto_dt, safety=self.safety, policy=self.dt_policy,
            warned=self._warned_unstable, max_travel=MAX_TRAVEL)
        if refusal is not None:
            raise TimeStepError(refusal)
        return dt_crit

    # ------------------------------------------------------------------ periodic cell, snapshots
    def branch(self, i, j) -> np.ndarray:
        """Branch vectors x_j − x_i ``(K, 3)`` (nearest periodic images in a periodic cell)."""
        x = self.particles.x
        d = np.take(x, j, axis=0) - np.take(x, i, axis=0)          # np.take: twice as fast as x[j] on rows
        return d if self.periodic is None else self.periodic.minimum_image(d)

    def _cell_matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """The periodic cell's matrix h and its inverse for the compiled kernel (zeros without a cell)."""
        if self.periodic is None:
            return np.zeros((3, 3)), np.zeros((3, 3))
        return self.periodic.matrix, self.periodic.inverse

    def strain_cell(self, strain, *, shift_springs: bool = True) -> None:
        """Strain the periodic cell homogeneously by ε (``(ε_xx, ε_yy, ε_zz)`` or a symmetric (3, 3) tensor), the
        positions affinely with it, and every touching contact's tangential spring by the increment of its affine
        relative displacement, ΔF^t = −K^t (ε l)_t (Eq. 4.7 integrated over the jump; :mod:`abrakit.dem.periodic`
        explains why the springs need it). ``shift_springs=False`` moves the positions only: the classic mistake,
        kept so that it can be shown (the incremental springs then never see the strain)."""
        if self.periodic is None:
            raise ValueError("strain_cell needs a periodic simulation (periodic=Periodic(...))")
        c = self.contacts
        shift = shift_springs and len(c) and c.force is not None
        branch = self.branch(c.i, c.j).T if shift else None           # (3, M), before the strain
        eps = self.periodic.strain(self.particles.x, strain)
        if branch is not None:
            self._shift_tangential_springs(eps @ branch)
        self.periodic.check_range(2.0 * float(self.particles.radius.max()) + self.skin)
        self.neighbours.x_ref = None                       # the images moved: rebuild at the next step

    def _shift_tangential_springs(self, displacement) -> None:
        """Add −K^t u_t to the tangential springs of the touching contacts for relative displacements
        ``displacement`` (3, M) of B's contact point with respect to A's (Eq. 4.7 with V^t Δt = u_t)."""
        c = self.contacts
        touching = c.touching
        n = c.normal
        u_t = (displacement - _dot(displacement, n) * n) * touching
        kt = self.law.shear_stiffness(c.fn, c.prm)
        c.ft = c.ft - kt * u_t

    def snapshot(self) -> dict:
        """A deep copy of the state (particles, contacts, bonds, walls, cell, clock) for :meth:`restore`."""
        return copy.deepcopy({k: v for k, v in self.__dict__.items()})

    def restore(self, snapshot: dict) -> None:
        """Return to a :meth:`snapshot` (the snapshot stays usable)."""
        self.__dict__.update(copy.deepcopy(snapshot))

    # ------------------------------------------------------------------ domain, running
    def _check_domain(self) -> None:
        if self.domain is None:
            return
        p = self.particles
        outside = np.any((p.x < self.domain[0]) | (p.x > self.domain[1]), axis=1)
        if not outside.any():
            return
        idx = np.flatnonzero(outside)
        if self.escape == "raise":
            raise ParticleEscapeError(
                f"{len(idx)} particle(s) left the domain {self.domain.tolist()} at t = {self.time:.6g} s, "
                f"first: index {idx[0]} at {p.x[idx[0]].tolist()}; use escape='remove' to delete escapees")
        self.remove_particles(outside, rebuild=False)

    def remove_particles(self, mask, *, rebuild: bool = True) -> None:
        """Delete particles (boolean ``mask``), keeping the history of the remaining contacts and bonds."""
        p = self.particles
        mask = np.asarray(mask, bool)
        if np.any(p.clump[mask] >= 0):
            raise ValueError("clump members cannot be removed one by one")
        keep = np.flatnonzero(~mask)
        self.contacts, self.wall_contacts, self.parallel_bonds, self.fatigue_bonds = _renumbered(
            keep, len(p), self.contacts, self.wall_contacts, self.parallel_bonds, self.fatigue_bonds)
        if self.applied_force is not None:
            self.applied_force = self.applied_force[keep]
        self.particle_force = self.particle_force[keep]
        self.particles = p.take(keep)
        self.removed += int(mask.sum())
        movable = ~self.particles.fixed & (self.particles.clump < 0)
        self.inv_mass = np.where(movable, 1.0 / self.particles.mass, 0.0)
        self.inv_inertia = np.where(movable, 1.0 / self.particles.inertia, 0.0)
        self.neighbours.x_ref = None
        if rebuild:
            self.rebuild()

    def run(self, steps: int, *, callback=None, every: int = 1, progress: bool | None = None,
            desc: str = "DEM") -> Simulation:
        """Take ``steps`` steps, calling ``callback(sim)`` every ``every`` steps (and after the last).

        ``progress``: a tqdm bar; ``None`` shows it for runs of at least 20 000 steps on a terminal.
        """
        steps = int(steps)
        disable = (steps < 20_000 or None) if progress is None else not progress
        for s in progress_bar(range(steps), desc=desc, disable=disable, mininterval=1.0):
            self.step()
            if callback is not None and ((s + 1) % every == 0 or s == steps - 1):
                callback(self)
        return self
