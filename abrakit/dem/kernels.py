"""Optional compiled kernel (extra ``fast``: numba) for the hot loop, particle–particle contacts with the linear law.

``Simulation(kernel="numba")`` replaces the vectorised contact step of :meth:`Simulation._ball_ball` by
:func:`linear_contacts`: the same equations, Eq. (4.1)–(4.10) with contact bonds, written as one loop over the
contacts that also sums the forces onto the particles (so no temporary (3, M) arrays are made). Results equal the
NumPy path to round-off (the summation order differs); ``tests/test_dem_kernels.py`` checks it. Everything else
(walls, bonds, clumps, Hertz–Mindlin) stays on the NumPy path.
"""

from __future__ import annotations

import math

from ..compiled import HAVE_NUMBA, njit

__all__ = ["HAVE_NUMBA", "linear_contacts"]


@njit(cache=True, error_model="numpy")
def linear_contacts(x, v, w, radius_sum, radius_i, radius_j, i, j, kn, kt, mu, beta_n, beta_t, ft, bonded,
                    bond_gap, bond_normal, bond_shear, dt, force, torque, out_overlap, out_normal, out_fn,
                    out_force, out_dashpot, out_trial, out_flags):
    """Linear contact law on every contact, summed onto ``force``/``torque`` (both (N, 3), updated in place).

    ``ft`` (3, M) is updated in place (the new tangential spring force). Per contact outputs: overlap, normal
    (3, M), spring normal force, total force on B (3, M), dashpot force (3, M), trial shear force magnitude
    before the Coulomb cap, and ``out_flags`` (4, M): touching, sliding, tension failure, shear failure.
    """
    for c in range(i.shape[0]):
        a, b = i[c], j[c]
        # geometry, Eq. (4.1)–(4.4)
        d0, d1, d2 = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1], x[b, 2] - x[a, 2]
        dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        n0, n1, n2 = d0 / dist, d1 / dist, d2 / dist
        U = radius_sum[c] - dist
        arm_a, arm_b = radius_i[c] - 0.5 * U, radius_j[c] - 0.5 * U
        # velocity of B's contact point relative to A's: v_B − v_A − (r'_A ω_A + r'_B ω_B) × n
        s0 = arm_a * w[a, 0] + arm_b * w[b, 0]
        s1 = arm_a * w[a, 1] + arm_b * w[b, 1]
        s2 = arm_a * w[a, 2] + arm_b * w[b, 2]
        r0 = v[b, 0] - v[a, 0] - (s1 * n2 - s2 * n1)
        r1 = v[b, 1] - v[a, 1] - (s2 * n0 - s0 * n2)
        r2 = v[b, 2] - v[a, 2] - (s0 * n1 - s1 * n0)
        vn = r0 * n0 + r1 * n1 + r2 * n2
        t0, t1, t2 = r0 - vn * n0, r1 - vn * n1, r2 - vn * n2
        # normal spring, Eq. (4.6); a contact bond carries tension
        touching = U > 0.0
        fn = kn[c] * U if touching else 0.0
        if bonded[c]:
            fn = kn[c] * (U + bond_gap[c])
            touching = True
        # tangential spring turned into the contact plane, then ΔF^t = −K^t V^t Δt, Eq. (4.7)
        f0, f1, f2 = ft[0, c], ft[1, c], ft[2, c]
        before = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
        fdn = f0 * n0 + f1 * n1 + f2 * n2
        f0, f1, f2 = f0 - fdn * n0, f1 - fdn * n1, f2 - fdn * n2
        after = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
        scale = before / after if after > 0.0 else 0.0
        f0, f1, f2 = f0 * scale - kt[c] * dt * t0, f1 * scale - kt[c] * dt * t1, f2 * scale - kt[c] * dt * t2
        if not touching:
            f0 = f1 = f2 = 0.0
        # Coulomb slip, Eq. (4.8), or contact-bond failure
        limit = mu[c] * fn
        magnitude = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
        sliding = magnitude > limit and not bonded[c]
        tension = bonded[c] and -fn >= bond_normal[c]
        shear = bonded[c] and not tension and magnitude >= bond_shear[c]
        if sliding:
            f0, f1, f2 = f0 * (limit / magnitude), f1 * (limit / magnitude), f2 * (limit / magnitude)
        if tension or shear:
            f0 = f1 = f2 = 0.0
            fn = kn[c] * U if U > 0.0 else 0.0
        ft[0, c], ft[1, c], ft[2, c] = f0, f1, f2
        # dashpots, Eq. (4.9)/(4.10)
        dn = -beta_n[c] * vn if touching else 0.0
        dt_on = touching and not sliding
        g0 = -beta_t[c] * t0 if dt_on else 0.0
        g1 = -beta_t[c] * t1 if dt_on else 0.0
        g2 = -beta_t[c] * t2 if dt_on else 0.0
        F0 = fn * n0 + f0 + dn * n0 + g0
        F1 = fn * n1 + f1 + dn * n1 + g1
        F2 = fn * n2 + f2 + dn * n2 + g2
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
        out_overlap[c] = U
        out_normal[0, c], out_normal[1, c], out_normal[2, c] = n0, n1, n2
        out_fn[c] = fn
        out_trial[c] = magnitude
        out_force[0, c], out_force[1, c], out_force[2, c] = F0, F1, F2
        out_dashpot[0, c] = dn * n0 + g0
        out_dashpot[1, c] = dn * n1 + g1
        out_dashpot[2, c] = dn * n2 + g2
        out_flags[0, c], out_flags[1, c], out_flags[2, c], out_flags[3, c] = touching, sliding, tension, shear
