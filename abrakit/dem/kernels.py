"""Optional compiled kernel (extra ``fast``: numba) for the hot loop, particle–particle contacts with the linear law.

``Simulation(kernel="numba")`` replaces the vectorised contact step of :meth:`Simulation._ball_ball` by
:func:`linear_contacts`: the same equations, Eq. (4.1)–(4.10) with contact bonds, written as one loop over the
contacts that also sums the forces onto the particles (so no temporary (3, M) arrays are made), and
:func:`linear_wall_contacts` the particle–wall step; both call one inlined law, :func:`_linear_law`. Without an
energy account and without clumps, :func:`advance` does local damping and the leap-frog update in one loop over
the particles. Results equal the NumPy path to round-off (the summation order differs); ``tests/test_dem_kernels.py``
checks it. Parallel bonds, clumps and Hertz–Mindlin stay on the NumPy path; :func:`fatigue_bond_trial` is the elastic
trial of the fatigue bonds (:meth:`~abrakit.dem.fatigue_bonds.FatigueBonds.update`).
"""

from __future__ import annotations

import math

import numpy as np

from ..compiled import HAVE_NUMBA as HAVE_NUMBA  # whether the kernels below compile (read by their callers)
from ..compiled import njit
from ..fatigue._return_kernel import elastic_stresses, surface_size, yield_function
from .contact_laws import PLANE_TOL, RETURN_TOL


@njit(cache=True, inline="always")
def _linear_law(U, n0, n1, n2, r0, r1, r2, f0, f1, f2, kn, kt, mu, beta_n, beta_t, dt, bonded, bond_gap,
                bond_normal, bond_shear):
    """The linear law with contact bonds at one contact, Eq. (4.6)–(4.10): overlap ``U``, normal n (A → B),
    relative velocity r of B's contact point, old tangential spring force f. Returns the normal spring force,
    the new spring force (3), the total force on B (3), the dashpot force (3), the *square* of the trial shear
    magnitude and the flags touching, sliding, tension failure, shear failure.

    The turn into the contact plane is :func:`~abrakit.dem.contact_laws.turn_into_plane` (a second projection
    only where the remainder is below ``RETURN_TOL`` of the length); lengths are compared squared, so a contact
    that does not slide takes one square root (its distance, in the caller) and the turn one more."""
    vn = r0 * n0 + r1 * n1 + r2 * n2
    t0, t1, t2 = r0 - vn * n0, r1 - vn * n1, r2 - vn * n2
    # normal spring, Eq. (4.6); a contact bond carries tension
    touching = U > 0.0
    fn = kn * U if touching else 0.0
    if bonded:
        fn = kn * (U + bond_gap)
        touching = True
    # tangential spring turned into the contact plane, then ΔF^t = −K^t V^t Δt, Eq. (4.7)
    before = f0 * f0 + f1 * f1 + f2 * f2
    fdn = f0 * n0 + f1 * n1 + f2 * n2
    if fdn != 0.0:                                                    # already in the plane: nothing to turn
        f0, f1, f2 = f0 - fdn * n0, f1 - fdn * n1, f2 - fdn * n2
        after = f0 * f0 + f1 * f1 + f2 * f2
        if after < RETURN_TOL * RETURN_TOL * before:
            fdn = f0 * n0 + f1 * n1 + f2 * n2
            f0, f1, f2 = f0 - fdn * n0, f1 - fdn * n1, f2 - fdn * n2
            after = f0 * f0 + f1 * f1 + f2 * f2
        scale = math.sqrt(before / after) if after > PLANE_TOL * PLANE_TOL * before else 0.0
        f0, f1, f2 = f0 * scale, f1 * scale, f2 * scale
    step = kt * dt
    f0, f1, f2 = f0 - step * t0, f1 - step * t1, f2 - step * t2
    if not touching:
        f0 = f1 = f2 = 0.0
    # Coulomb slip, Eq. (4.8), or contact-bond failure
    limit = mu * fn
    trial2 = f0 * f0 + f1 * f1 + f2 * f2
    sliding = trial2 > limit * limit and not bonded                   # not bonded: fn >= 0, so limit >= 0
    tension = bonded and -fn >= bond_normal
    shear = bonded and not tension and trial2 >= bond_shear * bond_shear
    if sliding:
        cap = limit / math.sqrt(trial2)
        f0, f1, f2 = f0 * cap, f1 * cap, f2 * cap
    if tension or shear:
        f0 = f1 = f2 = 0.0
        fn = kn * U if U > 0.0 else 0.0
    # dashpots, Eq. (4.9)/(4.10)
    dn = -beta_n * vn if touching else 0.0
    dt_on = touching and not sliding
    g0 = -beta_t * t0 if dt_on else 0.0
    g1 = -beta_t * t1 if dt_on else 0.0
    g2 = -beta_t * t2 if dt_on else 0.0
    D0, D1, D2 = dn * n0 + g0, dn * n1 + g1, dn * n2 + g2
    F0, F1, F2 = fn * n0 + f0 + D0, fn * n1 + f1 + D1, fn * n2 + f2 + D2
    return fn, f0, f1, f2, F0, F1, F2, D0, D1, D2, trial2, touching, sliding, tension, shear


@njit(cache=True, error_model="numpy")
def linear_contacts(x, v, w, radius, i, j, kn, kt, mu, beta_n, beta_t, ft, bonded, bond_gap, bond_normal,
                    bond_shear, dt, force, torque, out_ft, out_overlap, out_normal, out_fn, out_force, out_dashpot,
                    out_trial, out_flags, box, box_inv, full):
    """Linear contact law on every contact, summed onto ``force``/``torque`` (both (N, 3), updated in place).

    ``ft`` (3, M) is the tangential spring force before the step, ``out_ft`` after it; ``out_overlap`` (M,)
    the overlap. ``out_flags`` (4, M), zeros on entry: touching, sliding, tension failure, shear failure. With
    ``full`` the kernel also writes the normal (3, M), the spring normal force, the total force on B (3, M), the
    dashpot force (3, M; pass a (3, 0) array to skip it), the trial shear force magnitude before the Coulomb cap,
    and the flags touching and sliding; without it only the spring, the overlap and the bond failures, which is
    what the next step needs (the caller rebuilds the rest from the positions when they are read, a quarter of
    the kernel's time in a dense packing). ``box`` (3, 3): the periodic cell's matrix h and ``box_inv``
    its inverse (branch vectors to the nearest image), zeros without a cell. Returns the number of bonds that failed.
    """
    keep_dashpot = out_dashpot.shape[1] > 0
    failures = 0
    periodic = box[0, 0] > 0.0
    tilted = periodic and (box[0, 1] != 0.0 or box[0, 2] != 0.0 or box[1, 0] != 0.0 or box[1, 2] != 0.0
                           or box[2, 0] != 0.0 or box[2, 1] != 0.0)
    for c in range(i.shape[0]):
        a, b = i[c], j[c]
        # geometry, Eq. (4.1)–(4.4)
        d0, d1, d2 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
        if tilted:                          # fractional coordinates s = h⁻¹ d, nearest image d − h round(s)
            s0 = np.round(box_inv[0, 0] * d0 + box_inv[0, 1] * d1 + box_inv[0, 2] * d2)
            s1 = np.round(box_inv[1, 0] * d0 + box_inv[1, 1] * d1 + box_inv[1, 2] * d2)
            s2 = np.round(box_inv[2, 0] * d0 + box_inv[2, 1] * d1 + box_inv[2, 2] * d2)
            d0 -= box[0, 0] * s0 + box[0, 1] * s1 + box[0, 2] * s2
            d1 -= box[1, 0] * s0 + box[1, 1] * s1 + box[1, 2] * s2
            d2 -= box[2, 0] * s0 + box[2, 1] * s1 + box[2, 2] * s2
        elif periodic:
            d0 -= box[0, 0] * np.round(d0 / box[0, 0])
            d1 -= box[1, 1] * np.round(d1 / box[1, 1])
            d2 -= box[2, 2] * np.round(d2 / box[2, 2])
        dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        U = (radius[a] + radius[b]) - dist
        out_overlap[c] = U
        if U <= 0.0 and not bonded[c]:     # a gap: the law gives zero forces and resets the spring
            out_ft[0, c] = out_ft[1, c] = out_ft[2, c] = 0.0
            if full:
                out_normal[0, c], out_normal[1, c], out_normal[2, c] = d0 / dist, d1 / dist, d2 / dist
                out_fn[c] = out_trial[c] = 0.0
                out_force[0, c] = out_force[1, c] = out_force[2, c] = 0.0
                if keep_dashpot:
                    out_dashpot[0, c] = out_dashpot[1, c] = out_dashpot[2, c] = 0.0
            continue
        n0, n1, n2 = d0 / dist, d1 / dist, d2 / dist
        arm_a, arm_b = radius[a] - 0.5 * U, radius[b] - 0.5 * U
        # velocity of B's contact point relative to A's: v_B − v_A − (r'_A ω_A + r'_B ω_B) × n
        s0 = arm_a * w[a, 0] + arm_b * w[b, 0]
        s1 = arm_a * w[a, 1] + arm_b * w[b, 1]
        s2 = arm_a * w[a, 2] + arm_b * w[b, 2]
        r0 = v[b, 0] - v[a, 0] - (s1 * n2 - s2 * n1)
        r1 = v[b, 1] - v[a, 1] - (s2 * n0 - s0 * n2)
        r2 = v[b, 2] - v[a, 2] - (s0 * n1 - s1 * n0)
        fn, f0, f1, f2, F0, F1, F2, D0, D1, D2, trial2, touching, sliding, tension, shear = _linear_law(
            U, n0, n1, n2, r0, r1, r2, ft[0, c], ft[1, c], ft[2, c], kn[c], kt[c], mu[c], beta_n[c], beta_t[c], dt,
            bonded[c], bond_gap[c], bond_normal[c], bond_shear[c])
        out_ft[0, c], out_ft[1, c], out_ft[2, c] = f0, f1, f2
        # Newton's third law: B gets +F, A gets −F; both get the moment −r' n × F
        force[b, 0] += F0
        force[b, 1] += F1
        force[b, 2] += F2
        force[a, 0] -= F0
        force[a, 1] -= F1
        force[a, 2] -= F2
        l0, l1, l2 = n1 * F2 - n2 * F1, n2 * F0 - n0 * F2, n0 * F1 - n1 * F0
        torque[a, 0] -= arm_a * l0
        torque[a, 1] -= arm_a * l1
        torque[a, 2] -= arm_a * l2
        torque[b, 0] -= arm_b * l0
        torque[b, 1] -= arm_b * l1
        torque[b, 2] -= arm_b * l2
        if tension or shear:
            out_flags[2, c], out_flags[3, c] = tension, shear
            failures += 1
        if full:
            out_normal[0, c], out_normal[1, c], out_normal[2, c] = n0, n1, n2
            out_fn[c] = fn
            out_trial[c] = math.sqrt(trial2)
            out_force[0, c], out_force[1, c], out_force[2, c] = F0, F1, F2
            if keep_dashpot:
                out_dashpot[0, c], out_dashpot[1, c], out_dashpot[2, c] = D0, D1, D2
            out_flags[0, c], out_flags[1, c] = touching, sliding
    return failures


@njit(cache=True, error_model="numpy")
def linear_wall_contacts(x, v, w, radius, k, j, normal, point, velocity, kn, kt, mu, beta_n, beta_t, ft, dt,
                         force, torque, wall_force, wall_stiffness, out_ft, out_overlap, out_fn, out_force,
                         out_dashpot, out_trial, out_flags):
    """The linear law on particle–wall contacts (wall ``k`` is body A, its normal the contact normal), summed
    onto ``force``/``torque`` of the particles, ``wall_force`` (W, 3) and the touching contacts' K^n onto
    ``wall_stiffness`` (W,) of the walls (a servo's gain); ``radius`` of the particles; outputs as
    :func:`linear_contacts` (flags: touching, sliding)."""
    keep_dashpot = out_dashpot.shape[1] > 0
    for c in range(k.shape[0]):
        a, b = k[c], j[c]
        n0, n1, n2 = normal[a, 0], normal[a, 1], normal[a, 2]
        U = radius[b] - ((x[b, 0] - point[a, 0]) * n0 + (x[b, 1] - point[a, 1]) * n1 + (x[b, 2] - point[a, 2]) * n2)
        arm = radius[b] - 0.5 * U
        s0, s1, s2 = arm * w[b, 0], arm * w[b, 1], arm * w[b, 2]
        r0 = v[b, 0] - velocity[a, 0] - (s1 * n2 - s2 * n1)
        r1 = v[b, 1] - velocity[a, 1] - (s2 * n0 - s0 * n2)
        r2 = v[b, 2] - velocity[a, 2] - (s0 * n1 - s1 * n0)
        fn, f0, f1, f2, F0, F1, F2, D0, D1, D2, trial2, touching, sliding, _, _ = _linear_law(
            U, n0, n1, n2, r0, r1, r2, ft[0, c], ft[1, c], ft[2, c], kn[c], kt[c], mu[c], beta_n[c], beta_t[c], dt,
            False, 0.0, 0.0, 0.0)
        out_ft[0, c], out_ft[1, c], out_ft[2, c] = f0, f1, f2
        force[b, 0] += F0
        force[b, 1] += F1
        force[b, 2] += F2
        wall_force[a, 0] -= F0
        wall_force[a, 1] -= F1
        wall_force[a, 2] -= F2
        if touching:
            wall_stiffness[a] += kn[c]
        l0, l1, l2 = n1 * F2 - n2 * F1, n2 * F0 - n0 * F2, n0 * F1 - n1 * F0
        torque[b, 0] -= arm * l0
        torque[b, 1] -= arm * l1
        torque[b, 2] -= arm * l2
        out_overlap[c] = U
        out_fn[c] = fn
        out_trial[c] = math.sqrt(trial2)
        out_force[0, c], out_force[1, c], out_force[2, c] = F0, F1, F2
        if keep_dashpot:
            out_dashpot[0, c], out_dashpot[1, c], out_dashpot[2, c] = D0, D1, D2
        out_flags[0, c], out_flags[1, c] = touching, sliding


@njit(cache=True, error_model="numpy")
def advance(x, v, w, force, torque, inv_mass, inv_inertia, alpha, planar, dt, kick):
    """Local damping F_d = −α |F| sign(v) (seed 002 Eq. 5, 6), the planar constraint (no z force, no x/y moment)
    and the leap-frog update (Eq. 7–9) in one loop over the particles, in place: what
    :func:`~abrakit.dem.integrate.local_damping` and :func:`~abrakit.dem.integrate.leapfrog` do in NumPy, with the
    same operations in the same order."""
    for p in range(x.shape[0]):
        for k in range(3):
            f, t = force[p, k], torque[p, k]
            if alpha > 0.0:
                f += -alpha * abs(f) * np.sign(v[p, k])
                t += -alpha * abs(t) * np.sign(w[p, k])
            if planar:
                if k == 2:
                    f = 0.0
                else:
                    t = 0.0
            v[p, k] += f * (inv_mass[p] * kick)
            w[p, k] += t * (inv_inertia[p] * kick)
            x[p, k] += v[p, k] * dt


@njit(cache=True)
def cell_list_pairs(x, radius, skin, capacity):
    """Candidate pairs ``i < j`` with surface gap below ``skin``, sorted by ``(i, j)``, from a cell list (cells of
    edge 2 r_max + skin, each particle checks the 27 cells around its own): the compiled counterpart of the
    ``cKDTree`` search in :func:`abrakit.dem.neighbours.candidate_pairs`, without a periodic cell.

    Returns ``(i, j, count)``; ``count > capacity`` means the arrays were too short (call again with ``count``).
    """
    n = x.shape[0]
    cutoff = 2.0 * radius.max() + skin
    lower = np.empty(3)
    dims = np.empty(3, np.int64)
    for k in range(3):
        lower[k] = x[:, k].min()
        dims[k] = max(1, int((x[:, k].max() - lower[k]) / cutoff) + 1)
    cell = np.empty(n, np.int64)
    for p in range(n):
        cx = min(int((x[p, 0] - lower[0]) / cutoff), dims[0] - 1)
        cy = min(int((x[p, 1] - lower[1]) / cutoff), dims[1] - 1)
        cz = min(int((x[p, 2] - lower[2]) / cutoff), dims[2] - 1)
        cell[p] = (cx * dims[1] + cy) * dims[2] + cz
    # particles grouped by cell (counting sort), ascending index within a cell
    start = np.zeros(dims[0] * dims[1] * dims[2] + 1, np.int64)
    for p in range(n):
        start[cell[p] + 1] += 1
    for q in range(len(start) - 1):
        start[q + 1] += start[q]
    fill = start[:-1].copy()
    members = np.empty(n, np.int64)
    for p in range(n):
        members[fill[cell[p]]] = p
        fill[cell[p]] += 1
    out_i = np.empty(capacity, np.int64)
    out_j = np.empty(capacity, np.int64)
    count = 0
    found = np.empty(n, np.int64)
    for a in range(n):
        cz = cell[a] % dims[2]
        cy = (cell[a] // dims[2]) % dims[1]
        cx = cell[a] // (dims[1] * dims[2])
        m = 0
        for ix in range(max(cx - 1, 0), min(cx + 2, dims[0])):
            for iy in range(max(cy - 1, 0), min(cy + 2, dims[1])):
                for iz in range(max(cz - 1, 0), min(cz + 2, dims[2])):
                    q = (ix * dims[1] + iy) * dims[2] + iz
                    for s in range(start[q], start[q + 1]):
                        b = members[s]
                        if b <= a:
                            continue
                        d0, d1, d2 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
                        reach = radius[a] + radius[b] + skin
                        if d0 * d0 + d1 * d1 + d2 * d2 < reach * reach:
                            s = m                  # insertion sort: the few neighbours of a in ascending order
                            while s > 0 and found[s - 1] > b:
                                found[s] = found[s - 1]
                                s -= 1
                            found[s] = b
                            m += 1
        for s in range(m):
            if count < capacity:
                out_i[count], out_j[count] = a, found[s]
            count += 1
    return out_i, out_j, count


@njit(cache=True)
def largest_distance_squared(a, b):
    """max_k |a_k − b_k|² over the rows of two (K, 3) arrays: the Verlet list's displacement check."""
    largest = 0.0
    for k in range(a.shape[0]):
        d0, d1, d2 = a[k, 0] - b[k, 0], a[k, 1] - b[k, 1], a[k, 2] - b[k, 2]
        squared = d0 * d0 + d1 * d1 + d2 * d2
        if squared > largest or squared != squared:     # a NaN stays (the caller reports it)
            largest = squared
    return largest


@njit(cache=True)
def fatigue_bond_trial(i, j, x, v, w, radius, elastic_n, elastic_s, damage, kn, ks, dt, cohesion, tensile_strength,
                       tan_phi, alpha, tol):  # pragma: no cover - compiled where numba is installed
    """The elastic part of :meth:`~abrakit.dem.fatigue_bonds.FatigueBonds.update` in one loop over the bonds: the
    pair kinematics of :func:`~abrakit.dem.bonds._bond_kinematics`, the shear displacement turned into the
    contact plane as :func:`~abrakit.dem.contact_laws._turn_into_plane` does, the trial displacements, the
    elastic stresses of Eq. (15, 16) and the yield test of Eq. (18) with the tolerance of
    :func:`~abrakit.fatigue.bond_law.plastic_return` (F > tol · scale²). Returns ``(n, arm_i, arm_j, point,
    start_size, trial_n, trial_s, size_s, sigma_n, sigma_s, active)``; the caller returns the active bonds
    (:mod:`abrakit.fatigue._return_kernel`, whose Eq. 15, 16 and 18 helpers this loop shares, or
    :func:`~abrakit.fatigue.bond_law.plastic_return`)."""
    B = i.shape[0]
    n = np.empty((3, B))
    point = np.empty((3, B))
    trial_s = np.empty((3, B))
    arm_i, arm_j = np.empty(B), np.empty(B)
    start_size, trial_n, size_s = np.empty(B), np.empty(B), np.empty(B)
    sigma_n, sigma_s = np.empty(B), np.empty(B)
    active = np.zeros(B, dtype=np.bool_)
    alpha2, q0_unit = alpha * alpha, cohesion - tensile_strength * tan_phi
    for b in range(B):
        a, c = i[b], j[b]
        d0, d1, d2 = x[c, 0] - x[a, 0], x[c, 1] - x[a, 1], x[c, 2] - x[a, 2]
        dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        n0, n1, n2 = d0 / dist, d1 / dist, d2 / dist
        overlap = radius[a] + radius[c] - dist
        ai, aj = radius[a] - 0.5 * overlap, radius[c] - 0.5 * overlap
        s0 = ai * w[a, 0] + aj * w[c, 0]
        s1 = ai * w[a, 1] + aj * w[c, 1]
        s2 = ai * w[a, 2] + aj * w[c, 2]
        r0 = v[c, 0] - v[a, 0] - (s1 * n2 - s2 * n1)
        r1 = v[c, 1] - v[a, 1] - (s2 * n0 - s0 * n2)
        r2 = v[c, 2] - v[a, 2] - (s0 * n1 - s1 * n0)
        vn = r0 * n0 + r1 * n1 + r2 * n2
        # the shear displacement turned into the contact plane (_turn_into_plane)
        e0, e1, e2 = elastic_s[0, b], elastic_s[1, b], elastic_s[2, b]
        before = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        en = e0 * n0 + e1 * n1 + e2 * n2
        e0, e1, e2 = e0 - en * n0, e1 - en * n1, e2 - en * n2
        after = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        if after < RETURN_TOL * before:
            en = e0 * n0 + e1 * n1 + e2 * n2
            e0, e1, e2 = e0 - en * n0, e1 - en * n1, e2 - en * n2
            after = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        scale = before / after if after > PLANE_TOL * before else 0.0
        e0, e1, e2 = e0 * scale, e1 * scale, e2 * scale
        start_size[b] = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        # trial displacements and elastic stresses (Eq. 15, 16)
        tn = elastic_n[b] + vn * dt
        t0, t1, t2 = e0 + (r0 - vn * n0) * dt, e1 + (r1 - vn * n1) * dt, e2 + (r2 - vn * n2) * dt
        size = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        intact = 1.0 - damage[b]
        sn, ss = elastic_stresses(tn, size, intact, kn[b], ks[b])
        # the yield test of Eq. (18), relative to the surface's size (bond_law._yield_scale)
        f = yield_function(sn, ss, intact, cohesion, q0_unit, tan_phi, alpha2)
        surface = surface_size(sn, intact, cohesion, tan_phi)
        active[b] = f > tol * surface * surface
        n[0, b], n[1, b], n[2, b] = n0, n1, n2
        point[0, b] = x[a, 0] + ai * n0
        point[1, b] = x[a, 1] + ai * n1
        point[2, b] = x[a, 2] + ai * n2
        trial_s[0, b], trial_s[1, b], trial_s[2, b] = t0, t1, t2
        arm_i[b], arm_j[b] = ai, aj
        trial_n[b], size_s[b], sigma_n[b], sigma_s[b] = tn, size, sn, ss
    return n, arm_i, arm_j, point, start_size, trial_n, trial_s, size_s, sigma_n, sigma_s, active


@njit(cache=True)
def scatter_pair_loads(force, torque, i, j, force_on_j, torque_on_i, torque_on_j):  # pragma: no cover - compiled
    """:func:`~abrakit.dem._bookkeeping._scatter_pair_loads` as one loop over the pairs: each particle's four sums
    (force on it as j and as i, torque as i and as j) are built in pair order, as ``np.bincount`` builds them,
    and combined as the NumPy version combines them, so both give the same sums to the last bit."""
    N, M = force.shape[0], i.shape[0]
    as_j, as_i = np.zeros((N, 3)), np.zeros((N, 3))
    t_i, t_j = np.zeros((N, 3)), np.zeros((N, 3))
    for b in range(M):
        a, c = i[b], j[b]
        for k in range(3):
            as_j[c, k] += force_on_j[k, b]
            as_i[a, k] += force_on_j[k, b]
            t_i[a, k] += torque_on_i[k, b]
            t_j[c, k] += torque_on_j[k, b]
    for p in range(N):
        for k in range(3):
            force[p, k] += as_j[p, k] - as_i[p, k]
            torque[p, k] += t_i[p, k] + t_j[p, k]


@njit(cache=True)
def _larger(a, b):  # pragma: no cover - compiled where numba is installed
    """np.maximum of two numbers (NaN wins)."""
    return a if (a >= b or a != a) else b


@njit(cache=True)
def _smaller(a, b):  # pragma: no cover - compiled where numba is installed
    """np.minimum of two numbers (NaN wins)."""
    return a if (a <= b or a != a) else b


@njit(cache=True)
def fatigue_bond_finish(trial_n, trial_s, size_s, du_n, du_s, damage, sigma_n, sigma_s, n, arm_i, arm_j, area, ks,
                        plastic, peak, low, ratchet):  # pragma: no cover - compiled where numba is installed
    """The rest of :meth:`~abrakit.dem.fatigue_bonds.FatigueBonds.update` after the return, in one loop over the
    bonds and with the NumPy version's operations in its order (the same numbers to the last bit): the shear
    displacement shortened by its plastic part, the new state (e_n, e_s, σ, accumulated |Δuᵖ|, the cycle's stress
    extremes and plastic flow) and the bond's force on j, −A (σ_n n + k_s (1 − D) e_s), with its torques on i and
    j. Returns ``(elastic_n, elastic_s, sigma, plastic, peak, low, ratchet, force, torque_i, torque_j)``."""
    B = trial_n.shape[0]
    elastic_n, elastic_s = np.empty(B), np.empty((3, B))
    sigma, new_plastic = np.empty((2, B)), np.empty((2, B))
    new_peak, new_low, new_ratchet = np.empty((2, B)), np.empty((2, B)), np.empty((2, B))
    force, torque_i, torque_j = np.empty((3, B)), np.empty((3, B)), np.empty((3, B))
    for b in range(B):
        shrink = (size_s[b] - du_s[b]) / size_s[b] if size_s[b] > 0 else 1.0
        e0, e1, e2 = trial_s[0, b] * shrink, trial_s[1, b] * shrink, trial_s[2, b] * shrink
        elastic_s[0, b], elastic_s[1, b], elastic_s[2, b] = e0, e1, e2
        elastic_n[b] = trial_n[b] - du_n[b]
        sigma[0, b], sigma[1, b] = sigma_n[b], sigma_s[b]
        flow_n, flow_s = abs(du_n[b]), abs(du_s[b])
        new_plastic[0, b], new_plastic[1, b] = plastic[0, b] + flow_n, plastic[1, b] + flow_s
        new_ratchet[0, b], new_ratchet[1, b] = ratchet[0, b] + flow_n, ratchet[1, b] + flow_s
        new_peak[0, b], new_peak[1, b] = _larger(peak[0, b], sigma_n[b]), _larger(peak[1, b], sigma_s[b])
        new_low[0, b], new_low[1, b] = _smaller(low[0, b], sigma_n[b]), _smaller(low[1, b], sigma_s[b])
        shear = ks[b] * (1.0 - damage[b])
        n0, n1, n2 = n[0, b], n[1, b], n[2, b]
        f0 = -area[b] * (sigma_n[b] * n0 + shear * e0)
        f1 = -area[b] * (sigma_n[b] * n1 + shear * e1)
        f2 = -area[b] * (sigma_n[b] * n2 + shear * e2)
        force[0, b], force[1, b], force[2, b] = f0, f1, f2
        l0, l1, l2 = n1 * f2 - n2 * f1, n2 * f0 - n0 * f2, n0 * f1 - n1 * f0
        torque_i[0, b], torque_i[1, b], torque_i[2, b] = -arm_i[b] * l0, -arm_i[b] * l1, -arm_i[b] * l2
        torque_j[0, b], torque_j[1, b], torque_j[2, b] = -arm_j[b] * l0, -arm_j[b] * l1, -arm_j[b] * l2
    return elastic_n, elastic_s, sigma, new_plastic, new_peak, new_low, new_ratchet, force, torque_i, torque_j
