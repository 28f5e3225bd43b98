"""Material removal in the scratch: elements eroded by ductile failure, the removal model of the wear chain.

The steel's ductile damage indicator (:mod:`abrakit.materials.ductile_failure`, Johnson and Cook's linear
accumulation with Bao and Wierzbicki's cut-off)

    D_{n+1} = D_n + Δε̄ᵖ / ε_f(η_{n+1}),      η = σ_m / σ_eq of the Kirchhoff stress,

is updated at every quadrature point after every *converged* increment of the finite-strain plasticity
(:func:`~abrakit.materials.finite_strain.ductile_damage_update`). The erosion is staggered: an increment is solved
with the elements eroded so far, then the elements whose damage reached 1 are eroded, and the next increment
re-equilibrates the body without them (Newton starts from the unbalanced forces they leave).

Regularisation: a nonlocal damage with a fixed length ℓ (:attr:`Erosion.length`). An intact element e erodes when

    D̄_e = Σ_j w_ej V_j D_j / Σ_j w_ej V_j ≥ 1,      w_ej = (1 − r_ej²/ℓ²)² for r_ej < ℓ,

the bell-shaped average of the element-mean damages D_j over the *intact* elements j whose centres lie within ℓ of
e's centre (Pijaudier-Cabot and Bažant's nonlocal integral, J. Eng. Mech. 113 (1987) 1512, applied to the failure
indicator). The average stops the erosion from following one element row: what fails is a volume of size ℓ,
whatever the mesh, and ℓ below the element size leaves the element's own damage (local erosion). Eroded elements
are left out of the average, so that their damage (≥ 1) does not erode their neighbours without new plastic strain.

An eroded element leaves

* the stiffness: its points carry P = c (F − I) with c = :attr:`Erosion.residual` · E (a spring that only keeps its
  nodes defined where no intact element holds them; no det F check, so a crushed eroded element cannot stop the
  run), their state frozen at the erosion;
* the contact: surface nodes all of whose elements are eroded no longer touch the tip
  (:func:`~abrakit.scratch.readouts.surface_nodes_of`);
* the volume audit: its current volume is the budget's ``removed`` term (:mod:`~abrakit.scratch.budget`), which
  keeps the budget's closure exact.

The energy the erosion releases, the stored energy ψ(ε_e) + ½ K_H α_p² of each eroded element at its erosion
(N mm, whole grain), is kept per point in the state (``released``) and summed by :meth:`ErosionStep.released`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from abrakit.fem.kinematics import element_mean
from abrakit.materials.ductile_failure import JohnsonCookFailure
from abrakit.materials.finite_strain import DeferredTangentResponse, LogStrainPlasticity, ductile_damage_update
from abrakit.validation import check_instance, check_number_fields, check_positive, check_range

EROSION_KEYS = ("ductile", "eroded", "released")
"""The state an eroding material adds to its base's: the damage indicator D, the erosion flag (the same on all
points of an element) and the stored energy released at the erosion (MPa, per unit reference volume)."""


@dataclass(frozen=True)
class Erosion:
    """How a scratch removes material (module docstring): the failure ``criterion`` (default Johnson and Cook's
    4340 steel with the cut-off η_c = −1/3), the nonlocal ``length`` ℓ (mm; default 1 µm: half the seed's depth,
    so that a 2 µm groove can shed a layer, and above the top element layer of the meshes that resolve it) and the
    ``residual`` stiffness of an eroded element relative to E."""

    criterion: JohnsonCookFailure = field(default_factory=JohnsonCookFailure)
    length: float = 0.001
    residual: float = 1e-6

    def __post_init__(self):
        check_number_fields(self)
        if not callable(getattr(self.criterion, "update", None)):
            raise TypeError(f"criterion must be a failure model with update(damage, plastic_strain_increment, "
                            f"stress), e.g. JohnsonCookFailure, got {type(self.criterion).__name__}")
        check_positive("length", self.length, allow_zero=True)
        check_range("residual", self.residual, 0.0, 1e-2, low_open=True)


class ErodingMaterial:
    """:class:`~abrakit.materials.LogStrainPlasticity` whose eroded elements carry only ``residual`` · E (module
    docstring). The state adds :data:`EROSION_KEYS`; everything else is the base's."""

    def __init__(self, base: LogStrainPlasticity, residual: float):
        check_instance("base", base, LogStrainPlasticity)
        if not base.plastic or base.damaged:
            raise ValueError("erosion needs the plastic LogStrainPlasticity of the steel (no Model II damage): "
                             "its damage indicator integrates the plastic strain")
        self.base = base
        self.residual = check_range("residual", residual, 0.0, 1e-2, low_open=True)
        self.stiffness = self.residual * base.E

    def __getattr__(self, name):                        # E, nu, plastic, damaged, ... of the base
        if name == "base":
            raise AttributeError(name)
        return getattr(self.base, name)

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        state = self.base.initial_state(shape)
        state.update(ductile=np.zeros(shape), eroded=np.zeros(shape, dtype=bool), released=np.zeros(shape))
        return state

    def update(self, state, F, dt: float = 1.0, **loading) -> DeferredTangentResponse:
        """P, A = ∂P/∂F and the new state at the deformation gradients ``F`` (nel, nqp, 9): the base's on the
        intact elements, P = c (F − I) and A = c I on the eroded ones (their state unchanged)."""
        F = np.asarray(F, dtype=float)
        eroded = np.asarray(state["eroded"], dtype=bool)
        carried = {k: state[k] for k in EROSION_KEYS}
        base_state = {k: v for k, v in state.items() if k not in EROSION_KEYS}
        if not eroded.any():
            response = self.base.update(base_state, F, dt, **loading)
            response.state.update(carried)
            return response
        gone = eroded.reshape(eroded.shape[0], -1).any(axis=1)
        intact = np.flatnonzero(~gone)
        response = self.base.update({k: v[intact] for k, v in base_state.items()}, F[intact], dt, **loading)
        new_state = {k: v.copy() for k, v in base_state.items()}
        for k, v in response.state.items():
            new_state[k][intact] = v
        new_state.update(carried)
        spring = np.where(np.isfinite(F[gone]), F[gone], 0.0) - np.eye(3).ravel()
        P = np.empty_like(F)
        P[intact], P[gone] = response.stress, self.stiffness * spring
        position = np.full(gone.size, -1)
        position[intact] = np.arange(intact.size)
        spring_tangent = self.stiffness * np.eye(9)
        points = F.shape[1:-1]

        def partial(elements):
            elements = np.asarray(elements)
            where = position[elements]
            out = np.broadcast_to(spring_tangent, (elements.size, *points, 9, 9)).copy()
            keep = where >= 0
            if keep.any():
                out[keep] = response.tangent_of(where[keep])
            return out

        yielding = np.ones(F.shape[:-1], dtype=bool)      # eroded: always rebuilt (its tangent is trivial)
        if response.yielding is not None:
            yielding[intact] = response.yielding
        return DeferredTangentResponse(P, new_state, lambda: partial(np.arange(gone.size)), partial=partial,
                                       yielding=yielding)

    def stored_energy(self, state) -> np.ndarray:
        """The base's stored energy, zero at eroded points (theirs was released, ``state['released']``)."""
        return np.where(state["eroded"], 0.0, self.base.stored_energy(state))

    def dissipation(self, state) -> np.ndarray:
        return self.base.dissipation(state)


def nonlocal_weights(centres: np.ndarray, volumes: np.ndarray, length: float) -> sp.csr_matrix:
    """The matrix of w_ej V_j, w_ej = (1 − r²/ℓ²)² for element centres closer than ℓ (module docstring), with the
    diagonal V_e; ℓ = 0 gives the diagonal alone (local)."""
    centres = np.asarray(centres, dtype=float)
    n = centres.shape[0]
    if length <= 0.0:
        return sp.diags(volumes).tocsr()
    tree = cKDTree(centres)
    pairs = tree.sparse_distance_matrix(tree, length, output_type="coo_matrix")
    off = pairs.row != pairs.col                       # each element weighs itself once, with w = 1
    rows = np.concatenate([pairs.row[off], np.arange(n)])
    cols = np.concatenate([pairs.col[off], np.arange(n)])
    weight = np.concatenate([(1.0 - (pairs.data[off] / length) ** 2) ** 2, np.ones(n)]) * volumes[cols]
    return sp.csr_matrix((weight, (rows, cols)), shape=(n, n))


class ErosionStep:
    """The staggered erosion after a converged increment (module docstring) for the elements of ``kinematics``.

    ``step(old_state, new_state)`` sets ``new_state['ductile']`` to D_{n+1}, erodes the intact elements whose
    nonlocal damage reached 1 (``eroded``, ``released``) and returns their indices. ``symmetry_factor`` scales the
    half model's energies to the whole grain."""

    def __init__(self, erosion: Erosion, kinematics, material: ErodingMaterial, symmetry_factor: float = 2.0):
        check_instance("erosion", erosion, Erosion)
        check_instance("material", material, ErodingMaterial)
        self.erosion, self.material, self.dx = erosion, material, kinematics.dx
        self.symmetry_factor = symmetry_factor
        volumes = kinematics.dx.sum(axis=1)
        centres = kinematics.quadrature_points.mean(axis=-1).T           # reference centres, (nel, 3)
        self.weights = nonlocal_weights(centres, volumes, erosion.length)

    def element_damage(self, state) -> np.ndarray:
        """The volume-weighted mean D of every element, (nel,)."""
        return element_mean(state["ductile"], self.dx)

    def nonlocal_damage(self, state) -> np.ndarray:
        """D̄ of every element over the intact ones (module docstring); NaN where no intact element is within ℓ."""
        intact = ~state["eroded"][:, 0]
        damage = self.element_damage(state)
        with np.errstate(invalid="ignore", divide="ignore"):
            return (self.weights @ (damage * intact)) / (self.weights @ intact.astype(float))

    def __call__(self, old_state: dict, new_state: dict) -> np.ndarray:
        new_state["ductile"] = ductile_damage_update(self.erosion.criterion, old_state["ductile"], old_state,
                                                     new_state)
        intact = ~new_state["eroded"][:, 0]
        failing = np.flatnonzero(intact & (self.nonlocal_damage(new_state) >= 1.0))
        if failing.size:
            energy = self.material.base.stored_energy({k: v[failing] for k, v in new_state.items()})
            new_state["eroded"] = new_state["eroded"].copy()
            new_state["released"] = new_state["released"].copy()
            new_state["eroded"][failing] = True
            new_state["released"][failing] = energy
        return failing

    def released(self, state) -> float:
        """The stored energy released by all erosions so far, N mm (whole grain)."""
        return float(self.symmetry_factor * np.sum(state["released"] * self.dx))

    @staticmethod
    def removed(state) -> np.ndarray:
        """The eroded elements, (nel,) bool: the budget's ``removed`` mask."""
        return np.asarray(state["eroded"])[:, 0].copy()


def erosion_summary(step: ErosionStep, state) -> dict:
    """Eroded element count, released energy (N mm) and the largest element damage of ``state``."""
    return {"eroded_elements": int(ErosionStep.removed(state).sum()), "erosion_energy": step.released(state),
            "max_ductile_damage": float(step.element_damage(state).max(initial=0.0))}
