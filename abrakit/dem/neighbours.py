"""Contact detection (Fig. 4.1, first box): a Verlet list of candidate pairs from ``scipy.spatial.cKDTree``.

A pair (i, j) is a candidate when its surface gap is below the *skin*: ``d < r_i + r_j + skin``. The list stays
valid while no two particles can have closed that gap, i.e. while the largest particle displacement since the
build is below ``skin/2`` (and a particle plus a wall have moved less than ``skin`` together); only then is the
tree rebuilt. Tangential springs and bond states survive a rebuild: contacts are matched by their sorted int64
keys with ``np.searchsorted`` (:func:`transfer_history`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from abrakit.dem.state import ContactSet, pair_keys
from abrakit.validation import check_finite, check_positive, number_arguments


@number_arguments
def candidate_pairs(x: ArrayLike, radius: ArrayLike, skin: float, clump=None, periodic=None, compiled=False):
    """Index pairs ``i < j`` whose surface gap is below ``skin`` [m]; pairs inside one clump are skipped.

    ``periodic`` (:class:`~abrakit.dem.periodic.Periodic`, positions inside its cell): the tree is toroidal
    (``cKDTree(boxsize=L)``, on the scaled fractional coordinates of a tilted cell with a search radius grown to
    match) and gaps are measured between nearest images. ``compiled`` (numba, no periodic
    cell): the same pairs from the cell list :func:`abrakit.dem.kernels.cell_list_pairs`, about twice as fast.
    Returned sorted by ``(i, j)``.
    """
    check_finite("x", x)                     # an inf position would reach the tree's own "data must be finite"
    check_positive("skin", skin, allow_zero=True)
    if np.shape(radius) != np.shape(x)[:1]:
        raise ValueError(f"radius must hold one entry per row of x ({len(x)}), got shape {np.shape(radius)}")
    check_positive("radius", radius, allow_zero=True)
    if len(x) < 2:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    if compiled and periodic is None:
        from abrakit.dem.kernels import cell_list_pairs

        i, j, count = cell_list_pairs(x, radius, skin, 8 * len(x))
        if count > 8 * len(x):
            i, j, count = cell_list_pairs(x, radius, skin, count)
        i, j = i[:count], j[:count]                               # sorted by (i, j) already
    else:
        stretch = 1.0
        if periodic is None:
            tree = cKDTree(x, balanced_tree=False)           # unbalanced: faster to build, as fast to query here
        else:
            points, stretch = periodic.search_coordinates(x)   # a tilted cell: its fractional coordinates
            tree = cKDTree(points, boxsize=periodic.lengths)
        pairs = tree.query_pairs(stretch * (2.0 * float(radius.max()) + skin), output_type="ndarray")
        i, j = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
        d = np.take(x, j, axis=0) - np.take(x, i, axis=0)         # np.take: twice as fast as x[j] on rows
        d = d if periodic is None else periodic.minimum_image(d)
        keep = np.einsum("ij,ij->i", d, d) < (radius[i] + radius[j] + skin) ** 2
        order = np.argsort(pair_keys(i[keep], j[keep], len(x)))   # keys are unique: no need for a stable sort
        i, j = i[keep][order], j[keep][order]
    if clump is not None:
        keep = (clump[i] < 0) | (clump[i] != clump[j])
        i, j = i[keep], j[keep]
    return i, j


def wall_candidates(x, radius, walls, skin):
    """(wall k, particle j) pairs with signed distance to the wall plane below ``r_j + skin``, sorted by key."""
    if walls is None or len(walls) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    s = x @ walls.normal.T - np.einsum("wk,wk->w", walls.point, walls.normal)   # (N, W) signed distances
    j, k = np.nonzero(s < radius[:, None] + skin)
    order = np.lexsort((j, k))
    return k[order].astype(np.int64), j[order].astype(np.int64)


def transfer_history(old: ContactSet, new: ContactSet) -> ContactSet:
    """Copy the history (:attr:`ContactSet.HISTORY`: the tangential spring, and the bond fields of intact bonds)
    of contacts present in both sets into ``new``."""
    if len(old) == 0 or len(new) == 0:
        return new
    pos = np.searchsorted(old.keys, new.keys)
    pos = np.minimum(pos, len(old) - 1)
    found = old.keys[pos] == new.keys
    src, dst = pos[found], np.flatnonzero(found)
    for row_new, row_old in zip(new.ft, old.ft, strict=True):    # by rows: much faster than new.ft[:, dst] = …
        row_new[dst] = np.take(row_old, src)
    bonded = old.bonded[src]
    if bonded.any():                     # the bond fields are read only where a bond is intact
        src, dst = src[bonded], dst[bonded]
        for name in ContactSet.HISTORY[1:]:
            getattr(new, name)[dst] = getattr(old, name)[src]
    return new


class VerletList:
    """Bookkeeping of when the candidate lists must be rebuilt.

    ``needs_rebuild`` is true when the largest particle displacement ``δp`` and the largest wall displacement
    ``δw`` since the last build satisfy ``δp + max(δp, δw) > skin`` — two particles (or a particle and a wall)
    may then have closed a gap of one skin.
    """

    def __init__(self, skin: float, compiled: bool = False):
        self.skin = float(skin)
        self.compiled = bool(compiled)      # numba: the displacement check as one compiled loop
        self.x_ref = None
        self.wall_ref = None
        self.builds = 0

    def mark_built(self, x, wall_points=None):
        self.x_ref = x.copy()
        self.wall_ref = None if wall_points is None else wall_points.copy()
        self.builds += 1

    def max_displacement(self, x) -> float:
        return _largest_distance(x, self.x_ref, self.compiled)

    def needs_rebuild(self, x, wall_points=None) -> bool:
        if self.x_ref is None or len(x) != len(self.x_ref):
            return True
        dp = self.max_displacement(x)
        if not np.isfinite(dp):
            raise FloatingPointError(
                "particle positions became non-finite: the time step is above the critical one or the input "
                "has a singular contact (check dt, stiffness ratios and initial overlaps)"
            )
        dw = 0.0
        if wall_points is not None and self.wall_ref is not None:
            dw = _largest_distance(wall_points, self.wall_ref, self.compiled)
        return dp + max(dp, dw) > self.skin


def _largest_distance(a, b, compiled: bool = False) -> float:
    """max_k |a_k − b_k| over the rows of two (K, 3) arrays (0 for K = 0); ``compiled``: the numba loop."""
    if not len(a):
        return 0.0
    if compiled:
        from abrakit.dem.kernels import largest_distance_squared

        return float(np.sqrt(largest_distance_squared(a, b)))
    d = a - b
    return float(np.sqrt(np.max(np.einsum("ij,ij->i", d, d))))
