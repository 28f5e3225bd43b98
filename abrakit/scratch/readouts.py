"""Readouts of a scratch run: the groove's cross-sections, where its material went, and the removed elements.

* :func:`groove_section`: the spatial cross-section of the deformed top surface at z (default: mid-length) and its
  :class:`~abrakit.scratch.groove.GrooveMetrics` — A_g, A_s, w, f_ab (Eq. 8.5), D_p (Eq. 8.6) and the regime;
  :func:`groove_along` the same at many z along the wake;
* :func:`groove_balance`: A_g − A_s = ∫∂u_z/∂z dA − ∫tr ε dA over the section (divergence theorem,
  :class:`GrooveBalance`);
* :func:`element_damage`, :func:`removed_elements`, :func:`surface_nodes_of`: Model II's damage per element and the
  elements (and surface nodes) of removed, fully damaged material.

Lengths mm, areas mm² (the summaries in µm, µm²), whole grain (twice the half model).

Example::

    result = run_scratch(DEMO_SCENE, vtu_every=0)
    metrics, profile, why = groove_section(result.specimen, result.u, result.scene)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from abrakit.fem.kinematics import Kinematics
from abrakit.scratch.groove import at_cap, groove_metrics, profile_from_surface_nodes
from abrakit.scratch.scene import ScratchScene, ScratchSpecimen
from abrakit.validation import check_finite


def groove_section(specimen: ScratchSpecimen, u: np.ndarray, scene: ScratchScene, z: float | None = None):
    """(:class:`~abrakit.scratch.groove.GrooveMetrics` or None, half :class:`~abrakit.scratch.groove.Profile` or
    None, reason) of the spatial cross-section at ``z`` (default: mid-length of the scratch); the metrics are None
    (and ``reason`` says why) where the profile has no groove, the profile too where the deformed surface folds
    along z (no spatial section exists)."""
    disp = u[np.asarray(specimen.basis.nodal_dofs)].T
    try:                                      # a surface folded over itself (a chip, a lapped prow) has none
        profile = profile_from_surface_nodes(specimen.mesh.p.T, disp, scene.z_section if z is None else z)
    except ValueError as exc:
        return None, None, str(exc)
    try:
        return groove_metrics(profile.x, profile.y, half=True, depth=scene.depth, tol=2e-3 * scene.depth), \
            profile, None
    except ValueError as exc:
        return None, profile, str(exc)


class GrooveAlong(NamedTuple):
    """Groove sections along the wake (µm², whole grain): positions z (mm), A_g, A_s, f_ab (NaN where the
    section has no groove)."""

    z: np.ndarray
    groove_area: np.ndarray
    shoulder_area: np.ndarray
    degree_of_wear: np.ndarray


def groove_along(specimen: ScratchSpecimen, u: np.ndarray, scene: ScratchScene, z: np.ndarray) -> GrooveAlong:
    """:func:`groove_section` at every position of ``z``: where along the scratch the section reaches a plateau."""
    rows = []
    for zi in np.asarray(z, dtype=float):
        g = groove_section(specimen, u, scene, zi)[0]
        rows.append((np.nan, np.nan, np.nan) if g is None
                    else (g.groove_area * 1e6, g.shoulder_area * 1e6, g.degree_of_wear))
    values = np.array(rows).reshape(-1, 3).T
    return GrooveAlong(np.asarray(z, dtype=float), *values)


def element_damage(state) -> np.ndarray:
    """One damage value per element: the largest sub-domain damage of Model II's ERVE, averaged over the
    element's quadrature points, ``(nel,)``."""
    return state["d"].max(axis=-1).mean(axis=1)


def removed_elements(material):
    """``f(state) -> (nel,) bool``: the elements whose :func:`element_damage` reached the material's cap
    (:func:`~abrakit.scratch.groove.at_cap`, the criterion of :func:`~abrakit.scratch.groove.removed_material`),
    for the volume audit."""
    return lambda state: at_cap(element_damage(state), material.d_max)


def surface_nodes_of(mesh, nodes):
    """``f(removed) -> (len(nodes),) bool``: the surface ``nodes`` all of whose elements the element mask
    ``removed`` (nel,) flags (a node with one intact element keeps touching the tip)."""
    incidence = sp.csr_matrix((np.ones(mesh.t.size), (mesh.t.ravel(), np.tile(np.arange(mesh.t.shape[1]),
                                                                                 mesh.t.shape[0]))),
                              shape=(mesh.p.shape[1], mesh.t.shape[1]))[nodes]
    count = np.asarray(incidence.sum(axis=1)).ravel()
    return lambda removed: incidence @ removed.astype(float) >= count


class GrooveBalance(NamedTuple):
    """Where the groove's material went, per unit length of scratch at a cross-section (whole model, mm²).

    With u_x = 0 on the symmetry plane and the far side and u_y = 0 on the bottom, integrating
    tr ε = ∂u_x/∂x + ∂u_y/∂y + ∂u_z/∂z over the section gives ∫u_y dx over the top = A_s − A_g (material
    section) = ∫tr ε dA − ∫∂u_z/∂z dA. So A_g − A_s = carried_forward − volume_change: material pushed along
    the scratch (the bow ahead of the tip, ∫∂u_z/∂z dA > 0 where sections nearer the end were pushed further)
    minus the elastic volume change ∫tr ε dA. ``finite_volume_change`` = ∫(det(I + ∇u) − 1) dA is the volume
    change a finite-strain model would see for the same displacements: its difference from ∫tr ε dA is the
    second-order error of the small-strain kinematics in the areas A_g and A_s.
    """

    surface_change: float
    volume_change: float
    carried_forward: float
    finite_volume_change: float


def groove_balance(result, z: float | None = None) -> GrooveBalance:
    """:class:`GrooveBalance` of the final state of ``result`` (a ScratchResult) in the element layer that
    contains ``z`` (default: the mid-length section), whole model (twice the half model's integrals)."""
    kin = Kinematics.from_basis(result.specimen.basis)
    z = result.scene.z_section if z is None else check_finite("z", z)
    zs = np.unique(np.round(result.specimen.mesh.p[2], 12))
    k = int(np.clip(np.searchsorted(zs, z, side="right") - 1, 0, zs.size - 2))
    z0, z1 = zs[k], zs[k + 1]
    qz = kin.quadrature_points[2]
    weight = 2.0 * kin.dx * ((qz >= z0) & (qz <= z1)) / (z1 - z0)
    grad = kin.displacement_gradient(result.u)
    return GrooveBalance(
        surface_change=float(np.sum((grad[..., 0, 0] + grad[..., 1, 1]) * weight)),
        volume_change=float(np.sum(np.trace(grad, axis1=-2, axis2=-1) * weight)),
        carried_forward=float(np.sum(grad[..., 2, 2] * weight)),
        finite_volume_change=float(np.sum((np.linalg.det(np.eye(3) + grad) - 1.0) * weight)),
    )
