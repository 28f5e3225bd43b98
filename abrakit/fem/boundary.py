"""Boundary conditions: prescribed displacements, their condensation, reaction forces and surface loads.

A :class:`Dirichlet` condition prescribes displacement components on a set of DOFs as a function of the load
factor lambda. :class:`Constraints` collects them, splits the DOFs into free (I) and prescribed (D) ones and
condenses the tangent to K_II with index arrays computed once, so each Newton iteration solves

    K_II du_I = -R_I                                   (Eq. 4.39 restricted to the free DOFs)

Reaction forces are the internal forces on prescribed DOFs, summed per boundary (N, or N/mm in plane strain).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem

from ..validation import check_finite

COMPONENT = {"x": 0, "y": 1, "z": 2}


def _components(components, dim: int) -> list[int]:
    if isinstance(components, str):
        bad = [c for c in components if c not in COMPONENT or COMPONENT[c] >= dim]
        if bad:
            raise ValueError(f"components must be letters from {'xyz'[:dim]!r}, got {components!r}")
        return [COMPONENT[c] for c in components]
    comps = [int(c) for c in np.atleast_1d(components)]
    if any(c < 0 or c >= dim for c in comps):
        raise ValueError(f"components must lie in [0, {dim - 1}], got {components!r}")
    return comps


def boundary_dofs(basis: skfem.CellBasis, boundary, components="xyz") -> np.ndarray:
    """Global DOFs of the given displacement components on a tagged boundary (name) or facet index array."""
    dim = basis.mesh.dim()
    comps = _components(components[:dim] if components == "xyz" else components, dim)
    if isinstance(boundary, str):
        if basis.mesh.boundaries is None or boundary not in basis.mesh.boundaries:
            known = sorted(basis.mesh.boundaries or {})
            raise ValueError(f"boundary must be one of the mesh's tagged boundaries {known}, got {boundary!r}")
    view = basis.get_dofs(boundary)
    names = [f"u^{c + 1}" for c in comps]
    return np.sort(np.concatenate([view.nodal[n] for n in names] + [view.facet.get(n, []) for n in names]
                                  ).astype(np.int64))


def node_row_dofs(basis: skfem.CellBasis, axis: str, coordinate: float, component: str) -> np.ndarray:
    """DOFs of displacement ``component`` at the nodes whose ``axis`` coordinate is the one nearest to
    ``coordinate``: a row of nodes of a structured mesh (a plane in 3D), e.g. one end of a gauge."""
    (axis_index,), (comp,) = (_components(c, basis.mesh.dim()) for c in (axis, component))
    x = basis.mesh.p[axis_index]
    nearest = x[np.argmin(np.abs(x - coordinate))]
    return np.asarray(basis.nodal_dofs)[comp, np.abs(x - nearest) <= 1e-9 * max(1.0, abs(nearest))]


@dataclass(frozen=True, eq=False)
class Dirichlet:
    """Prescribed displacement on ``dofs``.

    ``value`` is either the displacement at load factor 1 (number or one value per DOF, mm) applied
    proportionally, u = lambda * value, or a callable ``value(load_factor) -> number | array``.
    A non-empty ``name`` makes the solver record the reaction force and displacement of this condition.
    """

    dofs: np.ndarray
    value: float | np.ndarray | Callable[[float], float | np.ndarray] = 0.0
    name: str = ""

    def __post_init__(self):
        object.__setattr__(self, "dofs", np.asarray(self.dofs, dtype=np.int64).ravel())
        if not callable(self.value):
            v = np.asarray(check_finite("value", self.value), dtype=float)
            if v.ndim and v.shape != self.dofs.shape:
                raise ValueError(f"value must be a number or have one entry per DOF ({self.dofs.size}), "
                                 f"got shape {v.shape}")

    @classmethod
    def on(cls, basis, boundary, components="xyz", value=0.0, name: str = "") -> Dirichlet:
        """Condition on the components (e.g. ``"x"``, ``"xy"``, ``[2]``) of a tagged boundary."""
        return cls(boundary_dofs(basis, boundary, components), value, name)

    def __call__(self, load_factor: float) -> np.ndarray:
        if callable(self.value):
            v = np.asarray(self.value(load_factor), dtype=float)
        else:
            v = load_factor * np.asarray(self.value, dtype=float)
        return np.broadcast_to(v, self.dofs.shape)


class Constraints:
    """All Dirichlet conditions of a problem, with the condensation K -> K_II precomputed for a CSR pattern.

    Where conditions share a DOF (e.g. a corner node on two edges), the later condition in the list wins.
    """

    def __init__(self, conditions: Sequence[Dirichlet], ndof: int):
        if isinstance(ndof, bool) or not isinstance(ndof, int | np.integer) or ndof < 0:
            raise TypeError(f"ndof must be a non-negative integer (the number of DOFs), got {ndof!r}")
        self.conditions = list(conditions)
        self.ndof = int(ndof)
        dofs = np.concatenate([c.dofs for c in self.conditions]) if self.conditions else np.zeros(0, int)
        unique = np.unique(dofs)
        if unique.size and (unique[0] < 0 or unique[-1] >= ndof):
            raise ValueError(f"Dirichlet DOFs must lie in [0, {ndof - 1}]")
        self.prescribed = unique
        mask = np.ones(ndof, dtype=bool)
        mask[unique] = False
        self.free = np.flatnonzero(mask)
        self.is_free = mask
        self._pattern = None

    def apply(self, u: np.ndarray, load_factor: float) -> np.ndarray:
        """Copy of ``u`` with the prescribed values at ``load_factor``."""
        u = np.array(u, dtype=float)
        for c in self.conditions:
            u[c.dofs] = c(load_factor)
        return u

    # ---- condensation -----------------------------------------------------------------------------------------
    def condense_pattern(self, indptr: np.ndarray, indices: np.ndarray) -> None:
        """Precompute which CSR entries survive in K_II and where its diagonal is."""
        row = np.repeat(np.arange(self.ndof), np.diff(indptr))
        keep = self.is_free[row] & self.is_free[indices]
        new_index = np.full(self.ndof, -1, dtype=np.int64)
        new_index[self.free] = np.arange(self.free.size)
        kept_rows = new_index[row[keep]]
        c_indices = new_index[indices[keep]].astype(np.int32)
        c_indptr = np.concatenate(([0], np.cumsum(np.bincount(kept_rows, minlength=self.free.size))))
        diag = np.flatnonzero(kept_rows == c_indices)
        if diag.size != self.free.size:
            raise ValueError("the sparsity pattern must contain every diagonal entry")
        self._pattern = (keep, c_indices, c_indptr.astype(np.int32), diag)

    @property
    def diagonal_positions(self) -> np.ndarray:
        return self._pattern[3]

    def condense(self, K: sp.csr_matrix, same_pattern: bool = True) -> sp.csr_matrix:
        """K_II. With ``same_pattern`` the precomputed index arrays are used (no sparse slicing)."""
        if same_pattern and self._pattern is not None:
            return self.condense_values(K.data)
        K = sp.csr_matrix(K)
        return K[self.free][:, self.free].tocsr()

    def condense_values(self, data: np.ndarray) -> sp.csr_matrix:
        """K_II from the values ``data`` of a matrix in the pattern given to :meth:`condense_pattern` (the global
        matrix itself need not be built)."""
        keep, indices, indptr, _ = self._pattern
        n = self.free.size
        return sp.csr_matrix((data[keep], indices, indptr), shape=(n, n), copy=False)

    # ---- reactions --------------------------------------------------------------------------------------------
    @staticmethod
    def reaction(f_int: np.ndarray, dofs: np.ndarray) -> float:
        """Reaction force on a set of prescribed DOFs: the sum of their internal forces (N)."""
        return float(np.sum(f_int[dofs]))


def surface_load(basis: skfem.CellBasis, boundary, traction=None, pressure=None, intorder=None) -> np.ndarray:
    """Consistent nodal forces of a surface load on a tagged boundary, the last term of Eq. (4.37).

    ``traction`` is a constant vector t (MPa); ``pressure`` p (MPa) acts against the outward normal, t = -p n.
    Returns the external force vector at load factor 1 (N, or N/mm in plane strain).
    """
    if (traction is None) == (pressure is None):
        raise ValueError("give exactly one of traction or pressure")
    facets = basis.mesh.boundaries[boundary] if isinstance(boundary, str) else boundary
    order = intorder if intorder is not None else 2 * basis.elem.maxdeg
    fbasis = skfem.FacetBasis(basis.mesh, basis.elem, facets=facets, intorder=order)
    dim = basis.mesh.dim()
    if pressure is not None:
        p = check_finite("pressure", pressure)

        @skfem.LinearForm
        def load(v, w):
            return -p * sum(w.n[i] * v[i] for i in range(dim))
    else:
        t = np.asarray(check_finite("traction", traction), dtype=float)
        if t.shape != (dim,):
            raise ValueError(f"traction must have {dim} components, got shape {t.shape}")

        @skfem.LinearForm
        def load(v, w):
            return sum(t[i] * v[i] for i in range(dim))

    return load.assemble(fbasis)
