"""The compiled contact step of the rocker pads (:meth:`~abrakit.experiments.rollers.Rollers.contact_forces`): the
same equations as the NumPy version, one loop over the pads and the particles, in the same order (pad by pad,
particles ascending), so both give the same sums to the last bit. A beam of a few hundred disks spent a third of
its time step in the NumPy version's temporaries (``tests/test_rollers.py`` compares the two)."""

from __future__ import annotations

import math

import numpy as np

from ..compiled import njit


@njit(cache=True)
def pad_contacts(x, radius, x0, y, theta, side, pad, k):  # pragma: no cover - compiled where numba is installed
    """Per pad k (pivot (x0, y), angle θ, ``side``) and particle (centre x, ``radius``): along = (c − p)·t,
    height = (c − p)·n, overlap δ = r − height; a contact where |along| ≤ pad/2, δ > 0 and height > −r, of force
    k δ n on the particle. Returns ``(on_particles (N, 2), reaction (K, 2), moment (K,), pad_index, particle,
    along, f)``, the contacts pad by pad."""
    K, N = x0.shape[0], x.shape[0]
    on_particles = np.zeros((N, 2))
    reaction = np.zeros((K, 2))
    moment = np.zeros(K)
    pad_index = np.empty(K * N, np.int64)
    particle = np.empty(K * N, np.int64)
    along_of = np.empty(K * N)
    f_of = np.empty(K * N)
    m = 0
    for q in range(K):
        c, s = math.cos(theta[q]), math.sin(theta[q])
        n0, n1 = -side[q] * s, side[q] * c
        turning = 0.0
        for p in range(N):
            r0, r1 = x[p, 0] - x0[q], x[p, 1] - y[q]
            along = r0 * c + r1 * s
            height = r0 * n0 + r1 * n1
            overlap = radius[p] - height
            if abs(along) <= 0.5 * pad and overlap > 0.0 and height > -radius[p]:
                f = k * overlap
                on_particles[p, 0] += f * n0
                on_particles[p, 1] += f * n1
                reaction[q, 0] += -f * n0
                reaction[q, 1] += -f * n1
                turning += along * f
                pad_index[m], particle[m], along_of[m], f_of[m] = q, p, along, f
                m += 1
        moment[q] = -side[q] * turning
    return on_particles, reaction, moment, pad_index[:m], particle[:m], along_of[:m], f_of[:m]
