"""The penalty/Coulomb contact of Eq. (8.1)–(8.4) as a term of the finite element solver (Sec. 8.1.2, 8.2.1).

:class:`IndenterContact` plugs the point-wise law :func:`abrakit.scratch.contact.contact_response` into
:class:`abrakit.fem.Solver` as an ``extra_terms`` item ``term(u, ctx) -> (R_extra, K_extra)``:

    R_extra = −Σ_i A_i t_i        K_extra = −Σ_i A_i ∂t_i/∂u_i          (node i of the contact surface)

The contact points are the **nodes** of the specimen's top surface, each carrying its share A_i = ∫ N_i dA of
the surface (the nodal quadrature of the face integral −∫ Nᵀ t dA). Why nodes rather than face Gauss points:

* it is the seed's discretisation: "each slave (specimen) node is checked for penetration through the master
  (abrasive particle) surface" (Sec. 8.2.1), so "no node penetrates the tip by more than the penalty allows"
  is a statement about exactly the points the law acts on;
* the tangent is block diagonal, one 3×3 block per surface node, inside the stiffness matrix's own sparsity
  pattern: contact adds no couplings, whatever the tip does;
* with a rigid analytic tip the gap is exact at every node, and the nodal (trapezoidal) rule integrates the
  tractions of trilinear faces to second order in h, the order of the elements themselves; Gauss points would
  resolve a pressure that ends inside a face somewhat better on coarse meshes, at four times the points and
  12×12 coupling blocks — the Hertz test of the scene measures what the nodal rule costs.

Contact history (the elastic slip of the Coulomb return map) must be accepted only when a load step has
converged. The solver has no post-convergence hook for extra terms; it does call ``on_step(result)`` after
every converged step, so the term works by composition: every evaluation keeps its new state as *pending*,
:meth:`IndenterContact.on_step` (pass it to ``Solver.run(on_step=...)``) or :meth:`IndenterContact.commit`
accepts it, and an evaluation whose step does not start from the committed state raises, so a forgotten
commit cannot go unnoticed. Rejected Newton iterates and cut-back steps never touch the committed history.

Stick/slip chatter. The Coulomb law is only piecewise smooth: a node whose trial tangential traction lies at the
cone's edge can switch between stick and slip at every Newton iteration, and Newton then cycles at a residual of
the size of the two laws' difference (measured on the demo mesh under finite strain: four to eight nodes at the
front of the prow switching in every iteration, the residual stalling at 1e-3 N whatever the step, the run
stopping at 97 % of its slide). These nodes are pushed along by the tip: their trial elastic slip over a 1.5 µm
step is about 0.3 nm, so their slip direction e_tr/|e_tr| is ill-defined and they also reverse it from one
iteration to the next. The term therefore holds a node that has switched between stick and slip, or reversed its
slip, :data:`CHATTER_FLIPS` times within one load step in slip along its last slip direction for the rest of the
step (an active-set hold: t_T = −μ p s_held is smooth, Newton converges, and |t_T| = μ p stays on the Coulomb
cone). Only the direction of the held nodes' friction is frozen; their share of the contact's Coulomb force
Σ A μ p bounds what that can change and is reported (:attr:`IndenterContact.holds`, the scratch's notes). Holding
them in stick was tried first: it converges too, but the held tangential traction left the cone, in some
increments by 84 % of the whole contact's Coulomb force. A step without chatter is computed exactly as before.

Forces are reported for the whole grain (``symmetry_factor`` = 2 for the half model with the plane x = 0):
the normal force F_N pressing the tip up (+y), the tangential force F_T the tip needs to be dragged along +z,
the contact area and the deepest penetration. Units: N, mm, MPa.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import skfem

from abrakit.scratch.contact import OPEN, SLIP, STICK, contact_response, initial_state
from abrakit.scratch.indenters import SurfaceGap
from abrakit.validation import check_positive

CHATTER_FLIPS = 2
"""Stick/slip switches (or reversals of the slip) of one node within one load step after which it slips along its
last slip direction for the rest of the step."""


class ContactForces(NamedTuple):
    """Resultants of the contact tractions on the whole grain (the half model times ``symmetry_factor``).

    normal F_N (N, > 0 pressing the tip up), tangential F_T (N, > 0 resisting the slide along +z, i.e. the drag
    force), force (3,) the force of the specimen on the tip (lateral x part zero by symmetry), area (mm²) of the
    surface carried by closed nodes, max_penetration (mm, ≥ 0) the largest −g_N, closed/slipping node counts.
    """

    normal: float
    tangential: float
    force: np.ndarray
    area: float
    max_penetration: float
    closed: int
    slipping: int


def surface_facets(mesh, top: float = 0.0, tol: float | None = None) -> np.ndarray:
    """Boundary facets of ``mesh`` lying in the plane y = ``top`` (the specimen's upper face)."""
    size = float(np.ptp(mesh.p, axis=1).max()) or 1.0
    tol = 1e-9 * size if tol is None else tol
    facets = mesh.boundary_facets()
    on_top = np.all(np.abs(mesh.p[1, mesh.facets[:, facets]] - top) <= tol, axis=0)
    if not np.any(on_top):
        raise ValueError(f"no boundary facet of the mesh lies in the plane y = {top:g}")
    return facets[on_top]


def nodal_areas(mesh, facets) -> tuple[np.ndarray, np.ndarray]:
    """Nodes of the given facets and their surface shares A_i = ∫ N_i dA (mm²), exact for the linear element."""
    scalar = {"MeshHex1": skfem.ElementHex1, "MeshTet1": skfem.ElementTetP1}[type(mesh).__name__]()
    fbasis = skfem.FacetBasis(mesh, scalar, facets=facets, intorder=2)

    @skfem.LinearForm
    def share(v, w):
        return v

    weights = share.assemble(fbasis)
    nodes = np.unique(mesh.facets[:, facets])
    return nodes, weights[nodes]


class IndenterContact:
    """Penalty contact with Coulomb friction between a rigid analytic tip and the specimen's top surface.

    Parameters
    ----------
    basis : the displacement basis of the solver (scikit-fem vector ``CellBasis`` or its :class:`Kinematics`).
    indenter : a :class:`~abrakit.scratch.SphericalIndenter` or :class:`~abrakit.scratch.ConicalIndenter`.
    position : ``position(load_factor) -> (3,)`` apex of the tip, mm (e.g. ``ScratchPath.position``).
    c_N, c_T : normal and tangential penalty, N/mm³ (:func:`~abrakit.scratch.penalty_from_stiffness`).
    mu : Coulomb coefficient, the seed's 0.1.
    facets : facets of the contact surface (default: the boundary facets in the plane y = ``top``).
    curvature : keep the normal-rotation terms of the curved tip in the tangent (exact linearisation).
    symmetry_factor : multiplies the reported forces and area (2 for the half model, 1 for a full one).
    """

    def __init__(self, basis, indenter, position: Callable[[float], np.ndarray], *, c_N: float,
                 c_T: float | None = None, mu: float = 0.1, facets=None, top: float = 0.0,
                 curvature: bool = True, symmetry_factor: float = 2.0):
        from abrakit.fem import Kinematics

        basis = basis.basis if isinstance(basis, Kinematics) else basis
        mesh = basis.mesh
        self.indenter = indenter
        self.position = position
        self.c_N = check_positive("c_N", c_N)
        self.c_T = self.c_N if c_T is None else check_positive("c_T", c_T)
        self.mu = check_positive("mu", mu, allow_zero=True)
        self.curvature = bool(curvature)
        self.symmetry_factor = check_positive("symmetry_factor", symmetry_factor)
        self.facets = surface_facets(mesh, top) if facets is None else np.asarray(facets)
        self.nodes, self.areas = nodal_areas(mesh, self.facets)
        self.ndof = basis.N
        self.dofs = np.asarray(basis.nodal_dofs)[:, self.nodes].T.copy()           # (n, 3)
        self.reference = mesh.p[:, self.nodes].T.copy()                            # (n, 3) X of the nodes
        rows = np.repeat(self.dofs, 3, axis=1).ravel()                             # block (i, a, b) -> dof_a
        cols = np.tile(self.dofs, (1, 3)).ravel()
        pattern = sp.csr_matrix((np.arange(rows.size, dtype=float) + 1.0, (rows, cols)),
                                shape=(self.ndof, self.ndof))
        self._indptr, self._indices = pattern.indptr, pattern.indices
        self._order = pattern.data.astype(np.int64) - 1                            # CSR slot -> block entry
        self.reset()

    # ---- history ---------------------------------------------------------------------------------------------
    def reset(self, load_factor: float | None = None, u: np.ndarray | None = None) -> None:
        """Forget all contact history (virgin surface); the next evaluation fixes the start of the first step."""
        self.holds: list[tuple[float, int, float]] = []   # (tau, nodes held, their share of the Coulomb force)
        self.active = np.ones(self.nodes.size, dtype=bool)   # nodes of removed material leave the contact
        self._step = None
        self.state = initial_state(self.nodes.size)
        self._tau = load_factor
        self._u = None if u is None else np.array(u, dtype=float)
        self._pending = None
        self.forces = self._resultants(np.zeros(self.nodes.size), np.zeros((self.nodes.size, 3)),
                                       np.full(self.nodes.size, np.inf), self.state)
        self.pressure = np.zeros(self.nodes.size)

    def commit(self, u: np.ndarray, load_factor: float) -> None:
        """Accept the contact state at the converged ``u`` and ``load_factor`` as the start of the next step."""
        u = np.asarray(u, dtype=float)
        pending = self._pending
        if pending is None or pending["tau"] != load_factor or not np.array_equal(pending["u"], u):
            held = self._held_direction if self._step is not None and self._step[0] == load_factor else None
            pending = self._evaluate(u, load_factor, self._tau, self._u, held)
        if pending["held"] is not None:
            self.holds.append((float(load_factor), *pending["held"]))
        self._step = None
        self.state, self.forces, self.pressure = pending["state"], pending["forces"], pending["pressure"]
        self._tau, self._u = float(load_factor), u.copy()
        self._pending = None

    def snapshot(self) -> tuple[dict, dict]:
        """The committed history a resumed run needs, as (arrays, JSON-able numbers); :meth:`restore` takes it back."""
        arrays = {f"contact_state__{k}": v for k, v in self.state.items()}
        arrays |= {"contact_pressure": self.pressure, "contact_u": self._u, "contact_active": self.active}
        forces = self.forces._asdict() | {"force": [float(v) for v in self.forces.force]}
        return arrays, {"tau": self._tau, "forces": forces}

    def restore(self, arrays: dict, meta: dict) -> None:
        """Take up the committed history of :meth:`snapshot` again (the start of the next step)."""
        self.state = {k.removeprefix("contact_state__"): np.array(v) for k, v in arrays.items()
                      if k.startswith("contact_state__")}
        self.pressure = np.array(arrays["contact_pressure"], dtype=float)
        if "contact_active" in arrays:                     # checkpoints written before removal: all active
            self.active = np.array(arrays["contact_active"], dtype=bool)
        self._u = None if meta["tau"] is None else np.array(arrays["contact_u"], dtype=float)
        self._tau = meta["tau"]
        self.forces = ContactForces(**{**meta["forces"], "force": np.array(meta["forces"]["force"])})
        self._pending = None

    def on_step(self, result) -> None:
        """``Solver.run(on_step=...)`` callback: commits the converged step of ``result``."""
        self.commit(result.u, float(result.load_factors[-1]))

    def remove(self, nodes) -> int:
        """Take the surface nodes flagged in ``nodes`` (bool, one per surface node) out of the contact for good:
        they belong to removed material, which the tip passes through. Returns how many were newly removed."""
        nodes = np.asarray(nodes, dtype=bool)
        if nodes.shape != self.active.shape:
            raise ValueError(f"nodes must flag every surface node, shape {self.active.shape}, got {nodes.shape}")
        newly = int(np.sum(nodes & self.active))
        self.active &= ~nodes
        return newly

    def _surface(self, x, tip) -> SurfaceGap:
        """The tip's gap, normal and ∂n/∂x at the surface nodes ``x`` (n, 3); removed nodes are reported far and
        open (gap of one tip radius, no curvature), so they carry nothing and never count as penetrating."""
        if self.active.all():
            return self.indenter.gap(x, tip)
        live = self.indenter.gap(x[self.active], tip)
        n = x.shape[0]
        gap = np.full(n, float(self.indenter.radius))
        normal = np.tile(np.array([0.0, -1.0, 0.0]), (n, 1))
        closest = x.copy()
        gradient = np.zeros((n, 3, 3))
        gap[self.active], normal[self.active] = live.gap, live.normal
        closest[self.active], gradient[self.active] = live.closest, live.normal_gradient
        return SurfaceGap(gap, normal, closest, gradient)

    # ---- the solver term -------------------------------------------------------------------------------------
    def __call__(self, u, ctx):
        """``(R_extra, K_extra)`` at the iterate ``u`` of the step ``ctx`` (see :class:`abrakit.fem.StepContext`)."""
        start = ctx.load_factor - ctx.delta
        if self._tau is None:
            self._tau, self._u = float(start), np.array(ctx.u_old, dtype=float)
        elif not (abs(start - self._tau) <= 1e-12 * max(1.0, abs(start)) and np.array_equal(ctx.u_old, self._u)):
            raise RuntimeError(
                f"contact history was not committed: the step starts at load factor {start:.9g} but the last "
                f"committed state is at {self._tau:.9g}; pass on_step=contact.on_step to Solver.run (or call "
                "contact.commit(u, load_factor) after every converged step)"
            )
        step = (ctx.load_factor, ctx.delta)
        if step != self._step:                             # a new step (or a retry after a cutback): no hold yet
            self._step, self._seen = step, None
            self._flips = np.zeros(self.nodes.size, dtype=int)
            self._held_direction = np.zeros((self.nodes.size, 3))     # zero rows: not held
            self._slip_direction = np.zeros((self.nodes.size, 3))     # the last slip direction seen in the step
        try:
            pending = self._evaluate(u, ctx.load_factor, self._tau, self._u, self._held_direction)
        except ValueError:
            # a node deeper than the tip radius: unphysical iterate; a non-finite residual makes the solver cut back
            return np.full(self.ndof, np.nan), None
        status, slip = pending["state"]["status"], pending["state"]["elastic_slip"]
        if self._seen is not None and self.mu > 0.0:   # count stick <-> slip switches and reversals of the slip;
            # hold the chatterers (frictionless contact has no tangential law to chatter)
            seen, seen_slip = self._seen
            reversed_ = (status == SLIP) & (seen == SLIP) & (np.sum(slip * seen_slip, axis=1) < 0.0)
            self._flips += (((status == STICK) & (seen == SLIP)) | ((status == SLIP) & (seen == STICK)) | reversed_)
            length = np.linalg.norm(slip, axis=1)
            sliding = (status == SLIP) & (length > 0.0)
            self._slip_direction[sliding] = slip[sliding] / length[sliding, None]
            new = ((self._flips >= CHATTER_FLIPS) & ~self.held & (np.linalg.norm(self._slip_direction, axis=1) > 0.0))
            self._held_direction[new] = self._slip_direction[new]
        self._seen = (status, slip)
        self._pending = pending
        return pending["residual"], pending["tangent"]

    @property
    def trial_status(self) -> np.ndarray | None:
        """Status (OPEN, STICK, SLIP) of every surface node at the last evaluated iterate, None if not evaluated."""
        return None if self._pending is None else self._pending["state"]["status"]

    @property
    def held(self) -> np.ndarray:
        """Which surface nodes slip along a held direction in the current step (bool, one per node)."""
        if self._step is None:
            return np.zeros(self.nodes.size, dtype=bool)
        return np.linalg.norm(self._held_direction, axis=1) > 0.0

    def _evaluate(self, u, load_factor, tau_old, u_old, held=None):
        tip = np.asarray(self.position(load_factor), dtype=float)
        tip_old = np.asarray(self.position(tau_old), dtype=float)
        x = self.reference + u[self.dofs]
        x_old = self.reference + u_old[self.dofs]
        surface = self._surface(x, tip)
        increment = (x - x_old) - (tip - tip_old)
        held = None if held is None or not held.any() else held          # zero rows: not held
        response = contact_response(
            surface.gap, surface.normal, increment, self.state, c_N=self.c_N, c_T=self.c_T,
            mu=self.mu, normal_gradient=surface.normal_gradient if self.curvature else None, held_direction=held)
        closed = response.state["status"] != OPEN
        hold = None
        k = None if held is None else (np.linalg.norm(held, axis=1) > 0.0) & closed
        if k is not None and k.any():                                 # the held nodes' share of the Coulomb force
            share = self.areas[k] @ response.pressure[k]
            capacity = self.areas[closed] @ response.pressure[closed]
            hold = (int(k.sum()), float(share / capacity) if capacity > 0.0 else 0.0)
        residual = np.zeros(self.ndof)
        residual[self.dofs] = -self.areas[:, None] * response.traction
        tangent = None
        if np.any(closed):
            blocks = -self.areas[:, None, None] * response.tangent                # (n, 3, 3)
            tangent = sp.csr_matrix((blocks.ravel()[self._order], self._indices, self._indptr),
                                    shape=(self.ndof, self.ndof))
        forces = self._resultants(self.areas, response.traction, surface.gap, response.state)
        return {"u": np.array(u, dtype=float), "tau": float(load_factor), "state": response.state,
                "residual": residual, "tangent": tangent, "forces": forces, "pressure": response.pressure,
                "held": hold}

    def _resultants(self, areas, traction, gap, state) -> ContactForces:
        k = self.symmetry_factor
        on_specimen = areas @ traction                                             # half model, (3,)
        force = -k * on_specimen
        force[0] = 0.0                                                             # cancels with the mirror half
        closed = state["status"] != OPEN
        return ContactForces(
            normal=float(force[1]),
            tangential=float(-force[2]),
            force=force,
            area=float(k * areas[closed].sum()),
            max_penetration=float(max(0.0, -np.min(gap, initial=np.inf))),
            closed=int(closed.sum()),
            slipping=int(np.sum(state["status"] == 2)),
        )

    def penetration(self, u, load_factor) -> np.ndarray:
        """Penetration ⟨−g_N⟩ of every surface node at ``u`` for the tip at ``load_factor``, mm."""
        x = self.reference + np.asarray(u)[self.dofs]
        return np.maximum(-self._surface(x, np.asarray(self.position(load_factor))).gap, 0.0)

    def pressure_field(self, n_points: int) -> np.ndarray:
        """Committed contact pressure at every mesh node (zero off the surface), MPa, for field output."""
        field = np.zeros(n_points)
        field[self.nodes] = self.pressure
        return field
