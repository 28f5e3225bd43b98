r"""The blocks that couple displacements and damage in a monolithic Newton step of Model I.

The staggered step of :class:`~abrakit.damage.ModelIPathFollowingSolver` solves the displacements at frozen
damage and the damage at frozen displacements, and repeats. The monolithic step solves both at once: unknowns
``u`` (free DOFs), the element damage functions ``f`` and the load factor ``λ``, equations

* equilibrium ``R_u(u, λ, f) = f_int(u, f) - λ f̂ = 0`` (4.37, the stress ``f E : (ε - ε_p)`` of Eq. 6.40 with
  the plastic step of Eq. 6.59-6.61 taken from the start of the step at the current f),
* the damage complementarity of Eq. (6.64)/(6.76) per element, ``H_i(f, Psibar0(u, f)) = 0``
  (:func:`~abrakit.damage.model_one_fe.fischer_burmeister`),
* the path constraint ``g(u, λ) = 0``.

Its Jacobian needs, besides the tangent ``K`` and the damage block of
:func:`~abrakit.damage.model_one_fe.coupled_damage_function`, how the stress depends on f and how the driving
energy depends on the strain and on f. Each point's stress and ``Psi0+`` depend only on its own strain and its
element's f (the return map is local), so these partial derivatives are *pointwise* and one central difference
with every point perturbed at once gives all of them (:func:`_point_sensitivities`: 2 + 2 n_c material updates, n_c
the active strain components); the element integrals then turn them into the sparse blocks
``K_uf = ∂R_u/∂f`` and ``G = ∂Psibar0/∂u`` (:func:`coupling_blocks`). A central difference is exact for
the quadratic elastic energy and second order elsewhere; the test compares the assembled blocks with a finite
difference of the whole residual.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

#: Relative step of the central differences in f and in the strain.
RELATIVE_STEP = 1e-6


@dataclass(frozen=True)
class _PointSensitivities:
    """Pointwise partial derivatives at ``(nel, nqp)`` points: ``dstress_df`` (MPa, Mandel ``(nel, nqp, 6)``),
    ``dpsi_df`` (MPa) and ``dpsi_deps`` (MPa, ``(nel, nqp, 6)``, zero on inactive components)."""

    dstress_df: np.ndarray
    dpsi_df: np.ndarray
    dpsi_deps: np.ndarray


def _point_sensitivities(material, state_old: dict, eps: np.ndarray, f: np.ndarray, components,
                        elements=None) -> _PointSensitivities:
    """Central differences of the Model I stress and driving energy ``Psi0+`` at every point with respect to its
    element's damage function ``f`` (``(nel,)``) and to each active strain component, from ``state_old`` (the
    plastic state at the start of the step). Every point is perturbed at once (the update is local).
    ``elements``: compute them on these elements only (zero elsewhere): a monolithic step needs them on the
    elements whose f is an unknown, a few of the mesh's."""
    if elements is not None:
        part = _point_sensitivities(material, {k: v[elements] for k, v in state_old.items()}, eps[elements],
                                   f[elements], components)
        full = _PointSensitivities(np.zeros(eps.shape), np.zeros(eps.shape[:2]), np.zeros(eps.shape))
        for name in ("dstress_df", "dpsi_df", "dpsi_deps"):
            getattr(full, name)[elements] = getattr(part, name)
        return full
    nqp = eps.shape[1]

    def update(f_values, strain):
        trial = {**state_old, "d": np.repeat(-np.log(f_values)[:, None], nqp, axis=1)}
        response = material.update(trial, strain, damage=False)
        return response.stress, response.state["psi0"]

    h_f = RELATIVE_STEP * f
    (s_plus, p_plus), (s_minus, p_minus) = update(f + h_f, eps), update(f - h_f, eps)
    dstress_df = (s_plus - s_minus) / (2.0 * h_f[:, None, None])
    dpsi_df = (p_plus - p_minus) / (2.0 * h_f[:, None])
    h_eps = RELATIVE_STEP * max(float(np.max(np.abs(eps), initial=0.0)), 1e-8)
    dpsi_deps = np.zeros(eps.shape)
    for c in components:
        shift = np.zeros(6)
        shift[c] = h_eps
        dpsi_deps[..., c] = (update(f, eps + shift)[1] - update(f, eps - shift)[1]) / (2.0 * h_eps)
    return _PointSensitivities(dstress_df, dpsi_df, dpsi_deps)


def coupling_blocks(assembler, sens: _PointSensitivities) -> tuple[sp.csr_matrix, sp.csr_matrix, np.ndarray]:
    """The element integrals of the pointwise sensitivities over all DOFs:

    * ``K_uf`` ``(ndof, nel)``: column e is ``int_e B^T dσ/df_e dV`` (N), how the internal force follows f_e;
    * ``G`` ``(nel, ndof)``: row e is ``int_e B^T dPsi0+/dε dV / V_e`` (MPa/mm), how the element-mean driving
      energy ``Psibar0_e`` follows the displacements;
    * ``dpsibar_df`` ``(nel,)``: ``d Psibar0_e / d f_e`` through the plastic step (zero for an elastic material).
    """
    kin = assembler.kin
    nel, nbf, dofs = kin.nel, kin.nbf, kin.element_dofs
    volumes = kin.dx.sum(axis=1)
    columns = np.repeat(np.arange(nel), nbf)
    K_uf = sp.csr_matrix((assembler.element_forces(sens.dstress_df).ravel(), (dofs.ravel(), columns)),
                         shape=(kin.ndof, nel))
    G = sp.csr_matrix(((assembler.element_forces(sens.dpsi_deps) / volumes[:, None]).ravel(),
                       (columns, dofs.ravel())), shape=(nel, kin.ndof))
    dpsibar_df = np.sum(kin.dx * sens.dpsi_df, axis=1) / volumes
    return K_uf, G, dpsibar_df
