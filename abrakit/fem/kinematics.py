"""Strain–displacement operator B of Eq. (4.27)–(4.33) on scikit-fem bases, in Mandel notation.

The strain at a quadrature point is ``eps = B u_e`` (Eq. 4.29), with ``B`` built from the physical gradients of
the shape functions, ``dN/dx = J^{-1} dN/dxi`` (Eq. 4.33), which scikit-fem's :class:`~skfem.CellBasis` already
holds. Strains and stresses are 6-vectors in Mandel order (11, 22, 33, 23, 13, 12) with shear components
multiplied by sqrt(2), so that ``sigma . eps`` is the double contraction and ``B^T C B`` is the tangent.

Plane strain (2D meshes) uses the same 6-vectors with eps33 = eps23 = eps13 = 0; the in-plane operator
carries the Mandel components ``(0, 1, 5)``.

``bbar=True`` selects the B-bar operator (Hughes 1980; "selectively reduced integration" of Abaqus' CPE4/C3D8):
the volumetric strain at each quadrature point is replaced by its element mean,
``eps_bar = eps + (theta_bar - theta) I / 3``, which removes volumetric locking of bilinear/trilinear elements
in nearly incompressible (e.g. fully plastic) flow. In plane strain eps33 = (theta_bar - theta)/3 is then
non-zero and the operator carries components ``(0, 1, 2, 5)``. The default is the seed's standard B (Eq. 4.29).

Units: coordinates in mm, displacements in mm, strains dimensionless.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
import skfem
from numpy.typing import ArrayLike

from ..compiled import HAVE_NUMBA
from ..validation import check_finite, check_indices, check_instance, check_shape, number_arguments
from . import _fbar_kernels

SQRT1_2 = np.sqrt(0.5)

# eps_I = sum over rows (I, i, k, w) of w * du_i/dx_k   -- the rows of Eq. (4.28) in Mandel form
MANDEL_GRADIENT_TABLE_3D = (
    (0, 0, 0, 1.0), (1, 1, 1, 1.0), (2, 2, 2, 1.0),
    (3, 1, 2, SQRT1_2), (3, 2, 1, SQRT1_2),
    (4, 0, 2, SQRT1_2), (4, 2, 0, SQRT1_2),
    (5, 0, 1, SQRT1_2), (5, 1, 0, SQRT1_2),
)
MANDEL_GRADIENT_TABLE_2D = ((0, 0, 0, 1.0), (1, 1, 1, 1.0), (5, 0, 1, SQRT1_2), (5, 1, 0, SQRT1_2))
ACTIVE_COMPONENTS = {2: (0, 1, 5), 3: (0, 1, 2, 3, 4, 5)}
BBAR_COMPONENTS = {2: (0, 1, 2, 5), 3: (0, 1, 2, 3, 4, 5)}
IDENTITY = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])

# Explicit quadrature per element: 2x2(x2) Gauss for bilinear/trilinear, one point for constant-strain simplices.
_CENTROID_TRI = (np.array([[1.0 / 3.0], [1.0 / 3.0]]), np.array([0.5]))
DEFAULT_INTORDER = {
    "ElementQuad1": 3, "ElementHex1": 3, "ElementTetP1": 1,
    "ElementTriP2": 2, "ElementTetP2": 2, "ElementQuad2": 5, "ElementHex2": 5,
}
LINEAR_ELEMENT = {
    "MeshQuad1": skfem.ElementQuad1, "MeshTri1": skfem.ElementTriP1,
    "MeshHex1": skfem.ElementHex1, "MeshTet1": skfem.ElementTetP1,
}


def vector_basis(mesh: skfem.Mesh, element: skfem.Element | None = None, intorder: int | None = None):
    """Displacement basis on ``mesh`` with the quadrature chosen explicitly.

    ``element`` is the scalar Lagrange element (default: the linear element of the mesh type). Quadrature:
    2x2 (2x2x2) Gauss for ``ElementQuad1`` (``ElementHex1``), the centroid for ``ElementTriP1``/``ElementTetP1``,
    and the orders in ``DEFAULT_INTORDER`` otherwise; ``intorder`` overrides it.
    """
    if element is None:
        name = type(mesh).__name__
        if name not in LINEAR_ELEMENT:
            raise TypeError(f"mesh must be one of {tuple(LINEAR_ELEMENT)}, got {name}")
        element = LINEAR_ELEMENT[name]()
    elem = skfem.ElementVector(element)
    name = type(element).__name__
    if intorder is None and name == "ElementTriP1":
        return skfem.CellBasis(mesh, elem, quadrature=_CENTROID_TRI)
    order = intorder if intorder is not None else DEFAULT_INTORDER.get(name, 2 * element.maxdeg)
    return skfem.CellBasis(mesh, elem, intorder=order)


@dataclass(frozen=True, eq=False)
class Kinematics:
    """Precomputed shape-function gradients of a vector basis: the data behind B of Eq. (4.29).

    Attributes
    ----------
    basis : the scikit-fem vector :class:`~skfem.CellBasis` (``ElementVector`` of a scalar element).
    grad_N : ``(nel, nqp, nnode, dim)`` physical gradients dN_a/dx_k at the quadrature points, Eq. (4.33), 1/mm.
    dx : ``(nel, nqp)`` quadrature weight times |det J|, Eq. (4.35), mm^dim.
    element_dofs : ``(nel, nbf)`` global DOF of local DOF ``a * dim + i`` (node a, component i).
    """

    basis: skfem.CellBasis
    grad_N: np.ndarray
    dx: np.ndarray
    element_dofs: np.ndarray
    bbar: bool = False

    def __post_init__(self):
        check_instance("basis", self.basis, skfem.CellBasis)
        grad_N = check_shape("grad_N", check_finite("grad_N", self.grad_N), (None, None, None, None))
        check_shape("dx", check_finite("dx", self.dx), grad_N.shape[:2])
        check_shape("element_dofs", check_indices("element_dofs", self.element_dofs, self.basis.N),
                    (grad_N.shape[0], grad_N.shape[2] * grad_N.shape[3]))
        check_instance("bbar", self.bbar, (bool, np.bool_))

    @classmethod
    def from_basis(cls, basis: skfem.CellBasis, bbar: bool = False, finite_strain: bool = False) -> Kinematics:
        """Kinematics of ``basis``: small strain (optionally B-bar), or total Lagrangian with ``finite_strain``."""
        if finite_strain and cls is Kinematics:
            return (FBarKinematics if bbar else TotalLagrangianKinematics).from_basis(basis)
        elem = basis.elem
        if not isinstance(elem, skfem.ElementVector) or elem.dim != basis.mesh.dim():
            raise TypeError(
                "basis must be a displacement basis ElementVector(<scalar element>) of the mesh dimension, "
                f"got {type(elem).__name__}"
            )
        dim = elem.dim
        nnode = basis.Nbfun // dim
        # local DOF j = a * dim + i is component i of scalar shape function a (skfem.ElementVector.gbasis)
        grad_N = np.stack([basis.basis[a * dim][0].grad[0] for a in range(nnode)], axis=0)  # (a, k, e, q)
        return cls(
            basis=basis,
            grad_N=np.ascontiguousarray(grad_N.transpose(2, 3, 0, 1)),
            dx=np.asarray(basis.dx),
            element_dofs=np.ascontiguousarray(basis.element_dofs.T),
            bbar=bool(bbar),
        )

    @classmethod
    def from_mesh(cls, mesh: skfem.Mesh, element=None, intorder: int | None = None, bbar: bool = False
                  ) -> Kinematics:
        return cls.from_basis(vector_basis(mesh, element, intorder), bbar)

    # ---- sizes ---------------------------------------------------------------------------------------------
    @property
    def dim(self) -> int:
        return self.grad_N.shape[-1]

    @property
    def nel(self) -> int:
        return self.grad_N.shape[0]

    @property
    def nqp(self) -> int:
        return self.grad_N.shape[1]

    @property
    def nbf(self) -> int:
        return self.element_dofs.shape[1]

    @property
    def ndof(self) -> int:
        return self.basis.N

    @property
    def components(self) -> tuple[int, ...]:
        """Mandel components carried by B: (0, 1, 5) in plane strain ((0, 1, 2, 5) with B-bar), all six in 3D."""
        return (BBAR_COMPONENTS if self.bbar else ACTIVE_COMPONENTS)[self.dim]

    @property
    def measure_size(self) -> int:
        """Length of the strain (stress) vectors: 6 (Mandel) for small strain, 9 (F, P) for finite strain."""
        return 6

    @property
    def table(self):
        return MANDEL_GRADIENT_TABLE_2D if self.dim == 2 else MANDEL_GRADIENT_TABLE_3D

    @cached_property
    def volume(self) -> float:
        """Volume (3D, mm^3) or area (plane strain, mm^2 per mm thickness) of the mesh."""
        return float(self.dx.sum())

    @cached_property
    def quadrature_points(self) -> np.ndarray:
        """Global coordinates of the quadrature points, ``(dim, nel, nqp)``."""
        return np.asarray(self.basis.mapping.F(self.basis.X))

    # ---- Eq. (4.29) ----------------------------------------------------------------------------------------
    def displacement_gradient(self, u: np.ndarray) -> np.ndarray:
        """grad u at every quadrature point, ``(nel, nqp, dim, dim)`` with ``[..., i, k] = du_i/dx_k``."""
        u_e = np.asarray(u)[self.element_dofs].reshape(self.nel, -1, self.dim)  # (e, a, i)
        return np.matmul(np.swapaxes(u_e, -1, -2)[:, None], self.grad_N)      # Σ_a u_ai ∂N_a/∂x_k: (e, q, i, k)

    @cached_property
    def shape_values(self) -> np.ndarray:
        """N_a at every quadrature point, ``(nel, nqp, nnode)`` (vertex-only elements)."""
        nnode = self.nbf // self.dim
        return np.stack([np.asarray(self.basis.basis[a * self.dim][0])[0] for a in range(nnode)], axis=-1)

    def displacement_at_points(self, u: np.ndarray) -> np.ndarray:
        """u at every quadrature point, ``(nel, nqp, dim)``."""
        u_e = np.asarray(u)[self.element_dofs].reshape(self.nel, -1, self.dim)   # (e, a, i)
        return np.einsum("eqa,eai->eqi", self.shape_values, u_e)

    def project(self, values: np.ndarray) -> np.ndarray:
        """L2 projection of a quadrature-point field ``(nel, nqp)`` onto the mesh vertices (linear elements).

        Consistent mass where the quadrature makes it regular (quadrilaterals, hexahedra), lumped mass otherwise
        (one-point simplices). Used to recover nodal stresses, e.g. the stress concentration at a hole.
        """
        import scipy.sparse as sp
        import scipy.sparse.linalg as spla

        values = np.asarray(values, dtype=float)
        nnode = self.nbf // self.dim
        if nnode != self.basis.mesh.t.shape[0]:
            raise ValueError("project() needs a linear (vertex-only) element")
        N = self.shape_values                                                   # (e, q, a)
        nodes = self.element_dofs[:, :: self.dim] // self.dim
        n = self.basis.mesh.p.shape[1]
        rhs = np.bincount(nodes.ravel(), np.einsum("eqa,eq->ea", N, values * self.dx).ravel(), minlength=n)
        if self.nqp < nnode:
            mass = np.bincount(nodes.ravel(), np.einsum("eqa,eq->ea", N, self.dx).ravel(), minlength=n)
            return rhs / mass
        Me = np.einsum("eqa,eqb,eq->eab", N, N, self.dx)
        rows = np.repeat(nodes, nnode, axis=1).ravel()
        cols = np.tile(nodes, (1, nnode)).ravel()
        M = sp.csc_matrix((Me.ravel(), (rows, cols)), shape=(n, n))
        return spla.spsolve(M, rhs)

    @cached_property
    def mean_grad_N(self) -> np.ndarray:
        """Volume average of dN_a/dx_k over each element, ``(nel, nnode, dim)`` (the B-bar divergence)."""
        return np.einsum("eqak,eq->eak", self.grad_N, self.dx) / self.dx.sum(axis=1)[:, None, None]

    def strain(self, u: np.ndarray) -> np.ndarray:
        """Small strain eps = B u (Eq. 4.26, 4.29) as Mandel 6-vectors, ``(nel, nqp, 6)``."""
        grad_u = self.displacement_gradient(u)
        eps = np.zeros(grad_u.shape[:2] + (6,))
        for comp, i, k, weight in self.table:
            eps[..., comp] += weight * grad_u[..., i, k]
        if self.bbar:
            theta = np.trace(grad_u, axis1=-2, axis2=-1)
            theta_bar = np.einsum("eq,eq->e", theta, self.dx) / self.dx.sum(axis=1)
            eps += ((theta_bar[:, None] - theta) / 3.0)[..., None] * IDENTITY
        return eps

    def B(self, elements=slice(None)) -> np.ndarray:
        """Strain operator of Eq. (4.29), ``(n, nqp, ncomp, nbf)``; rows are ``self.components``."""
        grad_N = self.grad_N[elements]
        n, nqp, nnode, dim = grad_N.shape
        row = {c: r for r, c in enumerate(self.components)}
        B = np.zeros((n, nqp, len(row), nnode, dim))
        for comp, i, k, weight in self.table:
            B[:, :, row[comp], :, i] += weight * grad_N[..., k]
        if self.bbar:  # B_bar = B + m (x) (b_vol_mean - b_vol) / 3, with b_vol[a, i] = dN_a/dx_i
            correction = (self.mean_grad_N[elements][:, None] - grad_N) / 3.0
            for comp in range(3):
                B[:, :, row[comp]] += correction
        return B.reshape(n, nqp, len(row), nnode * dim)

    def element_forces(self, stress: np.ndarray) -> np.ndarray:
        """int_e B^T sigma dV for every element, ``(nel, nbf)`` (the first term of Eq. 4.37)."""
        T = np.zeros(stress.shape[:2] + (self.dim, self.dim))
        for comp, i, k, weight in self.table:  # B^T sigma = sum_k dN_a/dx_k T_ik
            T[..., i, k] += weight * stress[..., comp]
        T *= self.dx[..., None, None]
        f = np.matmul(self.grad_N, np.swapaxes(T, -1, -2)).sum(axis=1)           # Σ_q,k ∂N_a/∂x_k T_ik: (e, a, i)
        if self.bbar:
            p_dx = stress[..., :3].sum(axis=-1) * self.dx / 3.0  # tr(sigma)/3 dV
            f += (np.einsum("eak,e->eak", self.mean_grad_N, p_dx.sum(axis=1))
                  - np.einsum("eqak,eq->eak", self.grad_N, p_dx))
        return f.reshape(self.nel, -1)


# Row-major components F_iJ -> 3 i + J carried in plane strain (F_33 = 1, no out-of-plane shear) and in 3D.
GRADIENT_COMPONENTS = {2: (0, 1, 3, 4), 3: tuple(range(9))}


@dataclass(frozen=True, eq=False)
class TotalLagrangianKinematics(Kinematics):
    """Finite-strain kinematics on the reference mesh (total Lagrangian): the "strain" measure is the deformation
    gradient F = I + ∇_X u as 9-vectors (row-major F_iJ), the stress its work conjugate P (first Piola–Kirchhoff),
    the tangent A = ∂P/∂F (9 × 9); B becomes the gradient operator G with (G u_e)_iJ = Σ_a u_ai ∂N_a/∂X_J, so

        f_int = Σ_e ∫ Gᵀ P dV_0,        K = Σ_e ∫ Gᵀ A G dV_0                 (Eq. 4.37/4.40 in the reference frame)

    and the assembly of :class:`~abrakit.fem.Assembler` serves both kinematics unchanged. Plane strain keeps
    F_33 = 1 (components (11, 12, 21, 22) carried). The finite-strain counterpart of B-bar is
    :class:`FBarKinematics` (``Kinematics.from_basis(basis, bbar=True, finite_strain=True)``).
    """

    @property
    def components(self) -> tuple[int, ...]:
        return GRADIENT_COMPONENTS[self.dim]

    @property
    def measure_size(self) -> int:
        return 9

    def strain(self, u: np.ndarray) -> np.ndarray:
        """Deformation gradient F = I + ∇u, ``(nel, nqp, 9)`` (row-major; plane strain: F_33 = 1)."""
        grad_u = self.displacement_gradient(u)
        F = np.zeros(grad_u.shape[:2] + (3, 3))
        F[..., : self.dim, : self.dim] = grad_u
        F += np.eye(3)
        return F.reshape(*F.shape[:2], 9)

    def B(self, elements=slice(None)) -> np.ndarray:
        """Gradient operator G, ``(n, nqp, ncomp, nbf)``: row (i, J) holds ∂N_a/∂X_J in the column of u_ai."""
        grad_N = self.grad_N[elements]
        n, nqp, nnode, dim = grad_N.shape
        G = np.zeros((n, nqp, len(self.components), nnode, dim))
        for row, comp in enumerate(self.components):
            i, J = divmod(comp, 3)
            G[:, :, row, :, i] = grad_N[..., J]
        return G.reshape(n, nqp, len(self.components), nnode * dim)

    def element_forces(self, stress: np.ndarray) -> np.ndarray:
        """∫_e Gᵀ P dV_0 for every element, ``(nel, nbf)``, from P as 9-vectors ``(nel, nqp, 9)``."""
        P = stress.reshape(*stress.shape[:2], 3, 3)[..., : self.dim, : self.dim] * self.dx[..., None, None]
        return self.gradient_transpose(P).sum(axis=1)

    def gradient_transpose(self, A: np.ndarray, elements: np.ndarray | None = None) -> np.ndarray:
        """Gᵀ vec A at every quadrature point from tensors ``(nel, nqp, dim, dim)``: (Gᵀ vec A)_ai = Σ_J A_iJ
        ∂N_a/∂X_J, ``(nel, nqp, nbf)`` (without forming G: dim × nnode × dim products per point); ``elements``:
        for these elements only, ``A`` given for them."""
        grad_N = self.grad_N if elements is None else self.grad_N[elements]
        return np.matmul(grad_N, np.swapaxes(A, -1, -2)).reshape(grad_N.shape[0], self.nqp, self.nbf)


class FBarState(NamedTuple):
    """Per-displacement quantities of the F-bar operator (see :class:`FBarKinematics`)."""

    F: np.ndarray          # (nel, nqp, 3, 3)
    F_inv: np.ndarray      # (nel, nqp, 3, 3)
    J: np.ndarray          # (nel, nqp)
    J_bar: np.ndarray      # (nel,) deformed over reference element volume
    alpha: np.ndarray      # (nel, nqp) (J_bar / J)^(1/3)
    m: np.ndarray          # (nel, nbf) δJ_bar / J_bar = m · δu
    h: np.ndarray          # (nel, nqp, nbf) m − Gᵀ g, g = vec(F⁻ᵀ)
    Gtg: np.ndarray        # (nel, nqp, nbf) Gᵀ g


@dataclass(frozen=True, eq=False)
class FBarKinematics(TotalLagrangianKinematics):
    """Total Lagrangian kinematics with the F-bar (mean-dilatation) deformation gradient against volumetric
    locking of trilinear hexahedra in isochoric plastic flow (de Souza Neto, Perić, Dutko & Owen 1996; the
    finite-strain counterpart of B-bar, and of the selectively reduced C3D8 of Abaqus):

        F̄ = (J̄ / J)^{1/3} F,     J̄ = ∫_e J dV_0 / V_e  (the element's deformed over its reference volume),

    so every quadrature point keeps its own isochoric part and the element's mean volume change. The internal
    force is variational, f = Σ ∫ B̄ᵀ P(F̄) dV_0 with δF̄ = B̄ δu, B̄ = α [G + ⅓ f ⊗ h], α = (J̄/J)^{1/3},
    f = vec F, h = m − Gᵀ vec F⁻ᵀ, m = ∫ J Gᵀ vec F⁻ᵀ dV_0 / (V_e J̄); the tangent is its exact derivative,

        K_e = ∫ B̄ᵀ A B̄ dV_0 + ∫ (α/3) [X ⊗ h + h ⊗ Gᵀp] dV_0 + c_e (M_e − m ⊗ m) − ∫ (α s / 3) Gᵀ D G dV_0,

    with p = vec P, s = F : P, X = Gᵀ p + (s/3) h, c_e = ∫ α s / 3 dV_0, D the derivative of vec F⁻ᵀ by vec F,
    M_e = ∫ J Gᵀ (vec F⁻ᵀ ⊗ vec F⁻ᵀ + D) G dV_0 / (V_e J̄). Checked against finite differences of the force.
    3D only (plane strain would need F_33 in the average).

    :meth:`use_plain_gradient` switches F-bar off in selected elements (eroded material in the scratch): they take
    F = I + ∇u with the plain total Lagrangian force and tangent, and they may invert (no det F check there).
    """

    def __post_init__(self):
        super().__post_init__()
        if self.dim != 3:
            raise ValueError("F-bar kinematics are implemented for 3D meshes only")
        object.__setattr__(self, "_memo", [None, None])
        object.__setattr__(self, "_plain", [np.zeros(self.nel, dtype=bool)])

    def use_plain_gradient(self, elements: np.ndarray) -> None:
        """The elements flagged in ``elements`` ((nel,) bool) take the plain gradient F = I + ∇u from now on
        (class docstring); all others keep F-bar."""
        elements = np.asarray(elements, dtype=bool)
        if elements.shape != (self.nel,):
            raise ValueError(f"elements must flag every element, shape ({self.nel},), got {elements.shape}")
        self._plain[0] = elements.copy()
        self._memo[0] = self._memo[1] = None

    @property
    def plain(self) -> np.ndarray:
        """The elements on the plain gradient, (nel,) bool (:meth:`use_plain_gradient`)."""
        return self._plain[0]

    def _with_plain(self, state: FBarState) -> FBarState:
        """``state`` after the one det F check of both paths (the F-bar elements must not be inverted), with α = 1,
        m = h = 0 in the plain elements (the F-bar terms vanish there)."""
        plain = self.plain
        checked = state.J[~plain]
        if checked.size and not checked.min() > 0.0:
            raise FloatingPointError(f"det F = {checked.min():.3g} <= 0: an element is inverted (cut the step back)")
        if plain.any():
            state.alpha[plain], state.m[plain], state.h[plain] = 1.0, 0.0, 0.0
        return state

    @cached_property
    def gradient_operator(self) -> np.ndarray:
        """G of every element, ``(nel, nqp, 9, nbf)`` (kept: F-bar needs it for forces and tangents)."""
        return TotalLagrangianKinematics.B(self)

    def fbar_state(self, u: np.ndarray, compiled: bool | None = None) -> FBarState:
        """The :class:`FBarState` at ``u`` (kept for the last ``u``); ``compiled`` (default: where numba is
        installed) by :func:`abrakit.fem._fbar_kernels.fbar_state`, else vectorised NumPy (same numbers)."""
        memo = self._memo
        if memo[0] is not None and np.array_equal(memo[0], u):
            return memo[1]
        if HAVE_NUMBA if compiled is None else compiled:
            state = self._fbar_state_compiled(u)
            memo[0], memo[1] = np.array(u, copy=True), state
            return state
        F = TotalLagrangianKinematics.strain(self, u).reshape(self.nel, self.nqp, 3, 3)
        J = np.linalg.det(F)
        F_inv = np.linalg.inv(np.where((J == 0.0)[..., None, None], np.eye(3), F))
        volume = self.dx.sum(axis=1)
        J_bar = np.einsum("eq,eq->e", J, self.dx) / volume
        with np.errstate(divide="ignore", invalid="ignore"):     # inverted elements: refused or plain, below
            alpha = np.cbrt(J_bar[:, None] / J)
            Gtg = self.gradient_transpose(np.swapaxes(F_inv, -1, -2))
            m = np.einsum("eq,eqb->eb", J * self.dx, Gtg) / (volume * J_bar)[:, None]
        h = m[:, None, :] - Gtg
        state = self._with_plain(FBarState(F, F_inv, J, J_bar, alpha, m, h, Gtg))
        memo[0], memo[1] = np.array(u, copy=True), state
        return state

    def _fbar_state_compiled(self, u: np.ndarray) -> FBarState:
        nel, nqp, nbf = self.nel, self.nqp, self.nbf
        F, F_inv = np.empty((nel, nqp, 3, 3)), np.empty((nel, nqp, 3, 3))
        J, alpha, J_bar = np.empty((nel, nqp)), np.empty((nel, nqp)), np.empty(nel)
        m, h, Gtg = np.empty((nel, nbf)), np.empty((nel, nqp, nbf)), np.empty((nel, nqp, nbf))
        u_e = np.ascontiguousarray(np.asarray(u, dtype=float)[self.element_dofs])
        _fbar_kernels.fbar_state(self._grad_N_c, self._dx_c, u_e, F, F_inv, J, J_bar, alpha, m, h, Gtg)
        return self._with_plain(FBarState(F, F_inv, J, J_bar, alpha, m, h, Gtg))

    @cached_property
    def _grad_N_c(self) -> np.ndarray:
        return np.ascontiguousarray(self.grad_N, dtype=float)

    @cached_property
    def _dx_c(self) -> np.ndarray:
        return np.ascontiguousarray(self.dx, dtype=float)

    def strain(self, u: np.ndarray) -> np.ndarray:
        """F̄ = (J̄/J)^{1/3} F as 9-vectors, ``(nel, nqp, 9)``."""
        st = self.fbar_state(u)
        return (st.alpha[..., None, None] * st.F).reshape(self.nel, self.nqp, 9)

    def element_forces(self, stress: np.ndarray, u: np.ndarray | None = None,
                       compiled: bool | None = None) -> np.ndarray:
        """∫_e B̄ᵀ P dV_0 for every element, ``(nel, nbf)``; ``compiled`` (default: where numba is installed) by
        :func:`abrakit.fem._fbar_kernels.element_forces`, else vectorised NumPy (same numbers, tested)."""
        if u is None:
            raise ValueError("F-bar element forces need the displacement u")
        st = self.fbar_state(u)
        if HAVE_NUMBA if compiled is None else compiled:
            return _fbar_kernels.element_forces(self._grad_N_c, self._dx_c, st.F, st.alpha, st.h,
                                                np.ascontiguousarray(stress, dtype=float))
        s = np.einsum("eqm,eqm->eq", st.F.reshape(self.nel, self.nqp, 9), stress)    # B̄ᵀp = α [Gᵀp + (s/3) h]
        Gtp = self.gradient_transpose(stress.reshape(self.nel, self.nqp, 3, 3))
        return np.einsum("eq,eqb->eb", self.dx * st.alpha, Gtp + (s / 3.0)[..., None] * st.h)

    def element_tangents(self, tangent: np.ndarray, stress: np.ndarray, u: np.ndarray,
                         compiled: bool | None = None, elements: np.ndarray | None = None) -> np.ndarray:
        """The exact element tangents of the F-bar force, ``(nel, nbf, nbf)`` (class docstring); ``compiled``
        (default: where numba is installed) by :func:`abrakit.fem._fbar_kernels.element_tangents` (5× faster on
        the scratch), else vectorised NumPy (same numbers to round-off, tested). ``elements`` (indices): the
        tangents of these elements only, ``(n, nbf, nbf)``, with ``tangent`` and ``stress`` given for them alone."""
        K = self._fbar_tangents(tangent, stress, u, compiled, elements)
        selected = np.arange(self.nel) if elements is None else np.asarray(elements)
        plain = np.flatnonzero(self.plain[selected])
        if plain.size:                               # the plain elements: ∫ Gᵀ A G dV_0
            G = self.gradient_operator[selected[plain]]
            AG = np.matmul(tangent[plain] * self.dx[selected[plain]][..., None, None], G)
            n = plain.size
            K[plain] = np.matmul(G.reshape(n, -1, self.nbf).transpose(0, 2, 1), AG.reshape(n, -1, self.nbf))
        return K

    def _fbar_tangents(self, tangent, stress, u, compiled, elements):
        st = self.fbar_state(u)
        grad_N, dx = self._grad_N_c, self._dx_c
        if elements is not None:
            elements = np.asarray(elements)
            st = FBarState(*(np.ascontiguousarray(field[elements]) for field in st))
            grad_N, dx = np.ascontiguousarray(grad_N[elements]), np.ascontiguousarray(dx[elements])
        if HAVE_NUMBA if compiled is None else compiled:
            return _fbar_kernels.element_tangents(
                grad_N, dx, st.F, st.J, st.J_bar, st.alpha, st.m, st.h, st.Gtg,
                np.ascontiguousarray(tangent, dtype=float), np.ascontiguousarray(stress, dtype=float))
        G = self.gradient_operator if elements is None else self.gradient_operator[elements]
        nel, nqp, nbf = dx.shape[0], self.nqp, self.nbf
        p = stress
        s = np.einsum("eqm,eqm->eq", st.F.reshape(nel, nqp, 9), p)
        Gtp = self.gradient_transpose(p.reshape(nel, nqp, 3, 3), elements)
        X = Gtp + (s / 3.0)[..., None] * st.h
        w = dx * st.alpha / 3.0

        def gram(left, right):                     # Σ_q leftᵀ right over (nel, nqp, 9, nbf) operands
            return np.matmul(left.reshape(nel, nqp * 9, nbf).transpose(0, 2, 1), right.reshape(nel, nqp * 9, nbf))

        def outer_sum(weight, a, b):                # Σ_q weight a ⊗ b over (nel, nqp, nbf) vectors
            return np.matmul((a * weight[..., None]).transpose(0, 2, 1), b)

        f = st.F.reshape(nel, nqp, 9)               # B̄ = α [G + ⅓ f ⊗ h]
        B_bar = st.alpha[..., None, None] * (G + f[..., :, None] * st.h[..., None, :] / 3.0)
        K = gram(B_bar, np.matmul(tangent * dx[..., None, None], B_bar))
        K += outer_sum(w, X, st.h) + outer_sum(w, st.h, Gtp)
        # D[(iJ), (Lk)] = −F⁻¹_ki F⁻¹_JL: the derivative of vec F⁻ᵀ by vec F
        Fi = st.F_inv
        D = -np.einsum("eqki,eqJL->eqiJLk", Fi, Fi).reshape(nel, nqp, 9, 9)
        c = np.einsum("eq,eq->e", w, s)
        r = st.J * dx / (dx.sum(axis=1) * st.J_bar)[:, None]                # weights of M_e
        K += gram(G, np.matmul(D * (c[:, None] * r - w * s)[..., None, None], G))
        Gtg = st.Gtg
        K += c[:, None, None] * (outer_sum(r, Gtg, Gtg) - st.m[:, :, None] * st.m[:, None, :])
        return K


@number_arguments
def element_mean(values: ArrayLike, dx: ArrayLike) -> np.ndarray:
    """Volume average over each element of a quadrature-point field ``(nel, nqp)``: ``int_e v dV / V_e``,
    ``(nel,)`` (``dx``: the quadrature weights times the Jacobians, :attr:`Kinematics.dx`)."""
    return np.einsum("eq,eq->e", values, dx) / np.sum(dx, axis=1)
