"""The contact sets of a DEM run across Verlet rebuilds and particle removals (:mod:`abrakit.dem.simulation`).

A contact is identified by its pair key i N + j (:func:`~abrakit.dem.state.pair_keys`), so the tangential spring and
the bond state of a pair that stays a candidate survive a rebuild (:func:`~abrakit.dem.neighbours.transfer_history`);
bonded pairs stay candidates however far apart they are.
"""

from __future__ import annotations

import numpy as np

from abrakit.dem.contact_laws import _rowdot
from abrakit.dem.neighbours import candidate_pairs, transfer_history
from abrakit.dem.state import ContactSet, pair_keys


def _rebuilt_contacts(sim, extra_pairs=None) -> ContactSet:
    """The particle–particle contacts of ``sim`` after a Verlet rebuild: the pairs within the skin, the bonded ones
    and ``extra_pairs`` ((K, 2), optional), with the old contacts' history and the law's pair parameters. Refuses
    coincident centres (the normal of Eq. 4.1 would be undefined)."""
    p = sim.particles
    n = len(p)
    i, j = candidate_pairs(p.x, p.radius, sim.skin, p.clump if sim.clumps is not None else None,
                           sim.periodic, compiled=sim.kernel == "numba")
    keys = pair_keys(i, j, n)
    old = sim.contacts
    forced = [old.keys[old.bonded]] if len(old) else []
    if extra_pairs is not None and len(extra_pairs):
        forced.append(pair_keys(extra_pairs[:, 0], extra_pairs[:, 1], n))
    forced = [f for f in forced if len(f)]
    if forced:
        keys = np.union1d(keys, np.concatenate(forced))
        i, j = keys // n, keys % n
    new = transfer_history(old, ContactSet.empty_history(i, j, n))
    new.prm = sim.law.pair_parameters(p, i, j)
    d = sim.branch(i, j)
    coincident = _rowdot(d, d) <= (1e-12 * (p.radius[i] + p.radius[j])) ** 2
    if coincident.any():
        a = int(np.argmax(coincident))
        raise ValueError(f"particles {i[a]} and {j[a]} have coincident centres: the contact normal "
                         "(Eq. 4.1) is undefined; separate them")
    return new


def _renumbered(keep, n, contacts, wall_contacts, parallel_bonds, fatigue_bonds) -> tuple:
    """``(contacts, wall_contacts, parallel_bonds, fatigue_bonds)`` of the particles ``keep`` (indices into the ``n``
    particles) only, renumbered 0 … len(keep) − 1, with their history (walls keep their numbers)."""
    new_index = np.full(n, -1, np.int64)
    new_index[keep] = np.arange(len(keep))
    n_new = len(keep)
    kept = []
    for c, between_particles in ((contacts, True), (wall_contacts, False)):
        ok = (new_index[c.j] >= 0) & ((new_index[c.i] >= 0) if between_particles else True)
        i = new_index[c.i[ok]] if between_particles else c.i[ok]
        j = new_index[c.j[ok]]
        fresh = ContactSet.empty_history(i, j, n_new)
        for h in ContactSet.HISTORY:
            getattr(fresh, h)[:] = getattr(c, h)[..., ok]
        kept.append(fresh)
    for b in (parallel_bonds, fatigue_bonds):
        b = b.take((new_index[b.i] >= 0) & (new_index[b.j] >= 0))
        b.i, b.j = new_index[b.i], new_index[b.j]
        kept.append(b)
    return tuple(kept)
