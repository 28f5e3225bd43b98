"""Internal force and tangent stiffness, Eq. (4.37) and (4.40), by vectorised numpy over all elements.

    f_int = sum_e int_e B^T sigma dV                        (4.37, first term)
    K     = sum_e int_e B^T (d sigma / d eps) B dV           (4.40)

The element matrices are batched matrix products over precomputed shape-function gradients
(:class:`~abrakit.fem.kinematics.Kinematics`); they are summed into a CSR matrix whose sparsity pattern is
computed once, so every Newton iteration only refills ``K.data`` with one ``np.bincount``.

:func:`skfem_tangent` and :func:`skfem_internal_force` are the same operators written as scikit-fem's generic
``BilinearForm``/``LinearForm``: the reference the tests compare against, and the baseline of the benchmark.
Units: stress and tangent in MPa, forces in N (3D) or N per mm of thickness (plane strain).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import skfem

from ..validation import check_finite, check_shape
from .kinematics import (
    ACTIVE_COMPONENTS,
    MANDEL_GRADIENT_TABLE_2D,
    MANDEL_GRADIENT_TABLE_3D,
    FBarKinematics,
    Kinematics,
)

# Element matrices are built in chunks of at most this many entries (bounds the temporary memory).
_CHUNK_ENTRIES = 4_000_000
# B-matrices of all elements are kept (and element matrices collected for one scatter) below this size:
# rebuilding B costs about as much as the products B^T C B themselves.
CACHE_BYTES = 256 * 2**20


class Assembler:
    """Residual and tangent assembly on a fixed mesh; the CSR pattern is built once and reused.

    Example::

        asm = Assembler(Kinematics.from_mesh(mesh))
        f_int = asm.internal_force(stress)          # stress (nel, nqp, 6) Mandel, MPa
        K = asm.tangent(tangent)                    # tangent (nel, nqp, 6, 6) Mandel, MPa
    """

    def __init__(self, kinematics: Kinematics):
        self.kin = kinematics
        n, nbf, dofs = kinematics.ndof, kinematics.nbf, kinematics.element_dofs.astype(np.int64)
        # pattern of K = pattern of E^T E, E the element-DOF incidence (a sparse product, no sort of all entries)
        E = sp.csr_matrix((np.ones(dofs.size), dofs.ravel(), np.arange(0, dofs.size + 1, nbf)),
                          shape=(kinematics.nel, n))
        pattern = (E.T @ E).tocsr()
        pattern.sort_indices()
        self.indices = pattern.indices.astype(np.int32)
        self.indptr = pattern.indptr.astype(np.int32)
        self.nnz = self.indices.size
        keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(self.indptr)) * n + self.indices
        entry_keys = np.repeat(dofs, nbf, axis=1) * n + np.tile(dofs, (1, nbf))
        self.slot = np.searchsorted(keys, entry_keys).astype(np.int32)  # CSR position of each element entry
        self._keys = keys                                                 # row * n + column, sorted
        self._comps = np.asarray(kinematics.components)
        self._chunk = max(1, _CHUNK_ENTRIES // (kinematics.nqp * nbf * nbf))
        b_bytes = 8 * kinematics.nel * kinematics.nqp * len(self._comps) * nbf
        self._B = kinematics.B() if b_bytes <= CACHE_BYTES and not isinstance(kinematics, FBarKinematics) else None
        self._one_scatter = 8 * kinematics.nel * nbf * nbf <= CACHE_BYTES
        # small strain with B cached: strain and internal force are one product with B each (a few numpy calls
        # instead of a sum over the gradient table; what a small mesh's Newton iteration costs), with a transposed
        # copy of B and B as one sparse matrix (its values B's own, its column indices half B's bytes) while all
        # fit in the cache budget
        self._small_strain_B = (self._B is not None and type(kinematics) is Kinematics
                                and 2.5 * b_bytes <= CACHE_BYTES)
        if self._small_strain_B:
            nel, nqp, rows = kinematics.nel, kinematics.nqp, self._B[..., 0].size
            self._Bt = np.ascontiguousarray(self._B.reshape(nel, nqp * len(self._comps), nbf).transpose(0, 2, 1))
            columns = np.broadcast_to(kinematics.element_dofs[:, None, :], (nel, nqp * len(self._comps), nbf))
            self._B_global = sp.csr_matrix((self._B.reshape(-1), columns.reshape(-1).astype(np.int32),
                                            np.arange(0, rows * nbf + 1, nbf)), shape=(rows, n), copy=False)

    @property
    def ndof(self) -> int:
        return self.kin.ndof

    def _check(self, name, array, tail):
        return check_shape(name, array, (self.kin.nel, self.kin.nqp) + tail)

    # ---- Eq. (4.29) and (4.37) ---------------------------------------------------------------------------------
    def strain(self, u: np.ndarray) -> np.ndarray:
        """The kinematics' strain measure at every quadrature point (:meth:`Kinematics.strain`); small strain
        eps = B u_e (Eq. 4.29) as one sparse product with the cached B of all elements."""
        if not self._small_strain_B:
            return self.kin.strain(u)
        eps = np.zeros((self.kin.nel, self.kin.nqp, 6))
        eps[..., self._comps] = (self._B_global @ np.asarray(u, dtype=float)).reshape(eps.shape[:2] + (-1,))
        return eps

    def element_forces(self, stress: np.ndarray, u: np.ndarray | None = None) -> np.ndarray:
        """Element internal forces int_e B^T sigma dV, ``(nel, nbf)`` (``u``: for kinematics whose B depends on
        the displacement, F-bar)."""
        stress = self._check("stress", stress, (self.kin.measure_size,))
        if self._small_strain_B:
            weighted = (stress[..., self._comps] * self.kin.dx[..., None]).reshape(self.kin.nel, -1, 1)
            return np.matmul(self._Bt, weighted)[..., 0]
        if isinstance(self.kin, FBarKinematics):
            return self.kin.element_forces(stress, u)
        return self.kin.element_forces(stress)

    def internal_force(self, stress: np.ndarray, u: np.ndarray | None = None) -> np.ndarray:
        """Global internal force vector of Eq. (4.37), ``(ndof,)``."""
        fe = self.element_forces(stress, u)
        return np.bincount(self.kin.element_dofs.ravel(), weights=fe.ravel(), minlength=self.ndof)

    # ---- Eq. (4.40) --------------------------------------------------------------------------------------------
    def element_matrices(self, tangent: np.ndarray, elements=slice(None)) -> np.ndarray:
        """Element tangents int_e B^T C B dV for the selected elements, ``(n, nbf, nbf)``."""
        kin = self.kin
        B = kin.B(elements) if self._B is None else self._B[elements]  # (n, q, m, nbf)
        n, nqp, m, nbf = B.shape
        C = tangent[elements][:, :, self._comps[:, None], self._comps[None, :]]
        CB = np.matmul(C * kin.dx[elements][..., None, None], B)
        Bt = self._Bt[elements] if self._small_strain_B else B.transpose(0, 3, 1, 2).reshape(n, nbf, nqp * m)
        return np.matmul(Bt, CB.reshape(n, nqp * m, nbf))

    def tangent_data(self, tangent: np.ndarray, u: np.ndarray | None = None,
                     stress: np.ndarray | None = None) -> np.ndarray:
        """Values of the global tangent in the fixed CSR pattern (``K.data``); F-bar kinematics also need the
        displacement ``u`` and the ``stress`` (geometric terms)."""
        tangent = self._check("tangent", tangent, (self.kin.measure_size,) * 2)
        if isinstance(self.kin, FBarKinematics):
            if u is None or stress is None:
                raise ValueError("F-bar tangents need the displacement u and the stress")
            Ke = self.kin.element_tangents(tangent, stress, u)
            return np.bincount(self.slot.ravel(), weights=Ke.ravel(), minlength=self.nnz)
        nel = self.kin.nel
        chunks = [slice(start, min(start + self._chunk, nel)) for start in range(0, nel, self._chunk)]
        if self._one_scatter:
            Ke = np.empty((nel, self.kin.nbf, self.kin.nbf))
            for chunk in chunks:
                Ke[chunk] = self.element_matrices(tangent, chunk)
            return np.bincount(self.slot.ravel(), weights=Ke.ravel(), minlength=self.nnz)
        data = np.zeros(self.nnz)
        for chunk in chunks:
            Ke = self.element_matrices(tangent, chunk)
            data += np.bincount(self.slot[chunk].ravel(), weights=Ke.ravel(), minlength=self.nnz)
        return data

    def tangent(self, tangent: np.ndarray, u: np.ndarray | None = None,
                stress: np.ndarray | None = None) -> sp.csr_matrix:
        """Global tangent stiffness of Eq. (4.40) as CSR, ``(ndof, ndof)``."""
        return self.matrix(self.tangent_data(tangent, u, stress))

    def add_into(self, data: np.ndarray, K_extra: sp.spmatrix) -> bool:
        """Add ``K_extra`` to the values ``data`` of the assembler's pattern in place, if its entries lie inside
        the pattern (e.g. contact blocks on nodes of the mesh); returns False (``data`` untouched) otherwise."""
        K_extra = sp.coo_matrix(K_extra)
        keys = K_extra.row.astype(np.int64) * self.ndof + K_extra.col
        pos = np.minimum(np.searchsorted(self._keys, keys), self.nnz - 1)
        if not np.array_equal(self._keys[pos], keys):
            return False
        np.add.at(data, pos, K_extra.data)
        return True

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """CSR matrix with the assembler's pattern and the given values."""
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.ndof, self.ndof), copy=False)


# ---- scikit-fem generic forms: the reference implementation -----------------------------------------------------
def _mandel_strain_of(grad, dim):
    """Mandel components (list over the active components) of sym(grad) for a scikit-fem field."""
    table = MANDEL_GRADIENT_TABLE_2D if dim == 2 else MANDEL_GRADIENT_TABLE_3D
    comps = ACTIVE_COMPONENTS[dim]
    eps = {c: 0.0 for c in comps}
    for comp, i, k, weight in table:
        eps[comp] = eps[comp] + weight * grad[i, k]
    return [eps[c] for c in comps]


@skfem.BilinearForm
def _tangent_form(u, v, w):
    dim = u.grad.shape[0]
    comps = ACTIVE_COMPONENTS[dim]
    C = np.asarray(w["C"])
    eu, ev = _mandel_strain_of(u.grad, dim), _mandel_strain_of(v.grad, dim)
    return sum(ev[a] * C[I, J] * eu[b] for a, I in enumerate(comps) for b, J in enumerate(comps))


@skfem.LinearForm
def _force_form(v, w):
    dim = v.grad.shape[0]
    comps = ACTIVE_COMPONENTS[dim]
    S = np.asarray(w["S"])
    ev = _mandel_strain_of(v.grad, dim)
    return sum(ev[a] * S[I] for a, I in enumerate(comps))


def skfem_tangent(basis: skfem.CellBasis, tangent: np.ndarray) -> sp.csr_matrix:
    """Eq. (4.40) with scikit-fem's generic ``BilinearForm`` (reference; slow for 3D vector problems)."""
    tangent = check_finite("tangent", tangent)
    return _tangent_form.assemble(basis, C=np.moveaxis(tangent, (0, 1), (2, 3)))


def skfem_internal_force(basis: skfem.CellBasis, stress: np.ndarray) -> np.ndarray:
    """Eq. (4.37), first term, with scikit-fem's generic ``LinearForm`` (reference)."""
    return _force_form.assemble(basis, S=np.moveaxis(np.asarray(stress), (0, 1), (1, 2)))
