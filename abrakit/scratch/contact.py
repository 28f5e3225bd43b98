"""Penalty contact with Coulomb friction against a rigid indenter, Eq. (8.1)–(8.4), as a point-wise law.

A pure, vectorised function of (old state, new kinematics) in the spirit of a material model: for n specimen
surface points (quadrature points or nodes, the law does not care) it returns the traction on the specimen, its
consistent 3×3 tangent and the new state, and never touches the old state.

Kinematics (from :mod:`abrakit.scratch.indenters`): signed gap g_N (> 0 open), outward unit normal n of the
indenter at the closest point, its gradient G = ∂n/∂x, and the relative displacement increment of the point with
respect to the moving rigid indenter over the load step, Δ = (x − x_old) − (tip − tip_old).

The law, with p the contact pressure and P = I − n⊗n:

* normal, Eq. (8.3) with the KKT conditions (8.1) regularised by the penalty: the seed's t_N = c_N g_N ≤ 0
  while g_N < 0, t_N = 0 while open; here p = −t_N = c_N ⟨−g_N⟩ ≥ 0 and the normal traction on the specimen is
  p n (it pushes the point out of the tip);
* tangential, Eq. (8.4) and (8.2) as an elastic-plastic return map: the elastic slip e (the stick part of the
  tangential gap g_T, stored as a global vector) is transported to the current tangent plane and incremented,
  e_tr = P (e_old + Δ); the trial traction is −c_T e_tr. Stick if c_T |e_tr| ≤ μ p (t_T = −c_T e_tr, e = e_tr);
  otherwise slip (t_T = −μ p s with s = e_tr/|e_tr|, e = (μ p / c_T) s, and the slip path grows by
  |e_tr| − μ p / c_T). So |t_T| ≤ μ p always, and the traction is continuous across the stick/slip limit.

The traction on the specimen is t = p n + t_T (force per area, MPa). The tangent is the exact derivative
J = ∂t/∂x = ∂t/∂u (the indenter position and the old state held fixed), with dg_N/dx = n, dn/dx = G and
dΔ/dx = I:

    stick:  J = −c_N n⊗n + p G − c_T E
    slip:   J = −c_N n⊗n + p G + μ c_N s⊗n − (μ p / |e_tr|)(I − s⊗s) E
    open:   J = 0,            with  E = ∂e_tr/∂x = P − (n·a) G − n⊗(Gᵀ a) (``de_tr``),  a = e_old + Δ.

Included: the normal-rotation terms of a curved rigid surface (p G, and G inside E). They are exact for the
analytic indenters; p G softens the normal response by the factor g_N/(R + g_N) of a sphere, tiny for small
penetrations, and they can be dropped by passing ``normal_gradient=None`` (flat-surface tangent; the traction
is unchanged). Dropped (they belong to the finite element): the change of the surface area element with the
deformation (small strain) and any indenter rotation (the tip only translates). The slip tangent is not
symmetric, as usual for Coulomb friction.

For the finite element solver: the contact adds −∫ Nᵀ t dA to the residual R = f_int − f_ext and −∫ Nᵀ J N dA
to the stiffness, with t and J evaluated at the surface points; the state is accepted with the converged step.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from abrakit.validation import check_finite, check_positive, check_shape

OPEN, STICK, SLIP = 0, 1, 2
"""Values of ``state["status"]``."""

STATE_KEYS = ("elastic_slip", "slip_path", "status")


class ContactResponse(NamedTuple):
    """Result of :func:`contact_response` over n points.

    traction: (n, 3) traction on the specimen t = p n + t_T, MPa;
    tangent: (n, 3, 3) ∂t_a/∂x_b = ∂t_a/∂u_b, N/mm³;
    pressure: (n,) contact pressure p = c_N ⟨−g_N⟩ ≥ 0, MPa (the seed's t_N = −p);
    state: the new state dict (see :func:`initial_state`).
    """

    traction: np.ndarray
    tangent: np.ndarray
    pressure: np.ndarray
    state: dict


def initial_state(n: int) -> dict:
    """State of n points that have never touched the tip.

    ``elastic_slip`` (n, 3): elastic (stick) part e of the tangential gap, mm, global components; t_T = −c_T e.
    ``slip_path`` (n,): accumulated slip length ∫|ġ_T^slip| dt, mm (history; kept while open).
    ``status`` (n,) int8: :data:`OPEN` = 0, :data:`STICK` = 1, :data:`SLIP` = 2 after the last update.
    """
    return {
        "elastic_slip": np.zeros((n, 3)),
        "slip_path": np.zeros(n),
        "status": np.zeros(n, dtype=np.int8),
    }


def penalty_from_stiffness(E, h, factor=1.0):
    """Normal penalty c_N = factor · E / h in N/mm³ (MPa/mm), from the specimen's Young's modulus E (MPa) and the
    element size h (mm) normal to the contact surface.

    E/h is the stiffness per unit area of one surface element layer in compression, the "slave surface stiffness"
    the seed scales by its default factor 1 (Sec. 8.2.1). The penetration it allows is g_N = −p/c_N, i.e. a
    fraction (p/E)/factor of the element size: at the steel's hardness p ≈ 2 GPa and factor 1 this is about 1 %
    of h. Raising ``factor`` reduces the penetration and worsens the conditioning of the Newton system.
    """
    E = check_positive("E", E)
    h = check_positive("h", h)
    factor = check_positive("factor", factor)
    c_N = factor * np.asarray(E) / h
    return float(c_N) if c_N.ndim == 0 else c_N


def _outer(a, b):
    return a[:, :, None] * b[:, None, :]


def contact_response(gap, normal, increment, state, *, c_N, c_T=None, mu=0.1, normal_gradient=None,
                     held_direction=None):
    """Penalty contact with Coulomb friction at n points, Eq. (8.1)–(8.4); see the module docstring.

    - gap: (n,) signed normal gap g_N, mm (> 0 open);
    - normal: (n, 3) outward unit normal of the indenter at the closest point;
    - increment: (n, 3) relative displacement increment Δ = (x − x_old) − (tip − tip_old) over the step, mm
      (its normal part is removed by the projection);
    - state: old state dict of :func:`initial_state` (not modified);
    - c_N, c_T: normal and tangential penalty stiffness, N/mm³ (c_T defaults to c_N);
    - mu: Coulomb friction coefficient (≥ 0), the seed's μ = 0.1;
    - normal_gradient: (n, 3, 3) ∂n/∂x of the indenter, 1/mm, or None for a flat surface (geometric terms dropped);
    - held_direction: (n, 3) or None: rows of unit vectors for closed points held in slip along that fixed
      direction, t_T = −μ p s_held (zero rows: not held). The active-set hold of
      :class:`~abrakit.scratch.IndenterContact` for points that chatter between stick and slip or reverse their
      slip: |t_T| = μ p stays on the cone and the law is smooth; only the direction is frozen.

    Returns a :class:`ContactResponse` (traction, tangent, pressure, new state).
    """
    gap = np.atleast_1d(check_finite("gap", gap))
    n_pts = gap.shape[0]
    check_shape("gap", gap, (n_pts,))
    n = check_shape("normal", np.atleast_2d(check_finite("normal", normal)), (n_pts, 3))
    if np.any(np.abs(np.linalg.norm(n, axis=1) - 1.0) > 1e-8):
        raise ValueError("normal must be unit vectors (|n| = 1 within 1e-8)")
    delta = check_shape("increment", np.atleast_2d(check_finite("increment", increment)), (n_pts, 3))
    missing = [k for k in STATE_KEYS if k not in state]
    if missing:
        raise ValueError(f"state lacks {missing}; build it with initial_state(n)")
    e_old = check_shape("state['elastic_slip']", np.asarray(state["elastic_slip"], dtype=float), (n_pts, 3))
    c_N = check_positive("c_N", c_N)
    c_T = c_N if c_T is None else check_positive("c_T", c_T)
    mu = check_positive("mu", mu, allow_zero=True)
    if normal_gradient is None:
        G = None
    else:
        G = np.asarray(check_finite("normal_gradient", normal_gradient))
        G = check_shape("normal_gradient", G[None] if G.ndim == 2 else G, (n_pts, 3, 3))

    closed = gap < 0.0
    p = c_N * np.where(closed, -gap, 0.0)                                        # Eq. (8.3): p = −t_N
    eye = np.broadcast_to(np.eye(3), (n_pts, 3, 3))

    a = e_old + delta
    e_tr = a - np.einsum("ni,ni->n", n, a)[:, None] * n                        # P (e_old + Δ)
    de_tr = eye - _outer(n, n)
    if G is not None:
        de_tr = de_tr - np.einsum("ni,ni->n", n, a)[:, None, None] * G - _outer(n, np.einsum("nki,nk->ni", G, a))
    norm_tr = np.linalg.norm(e_tr, axis=1)
    slip = closed & (c_T * norm_tr > mu * p)                                    # Coulomb limit, Eq. (8.2)
    held = np.zeros(n_pts, dtype=bool)
    if held_direction is not None:
        s_held = check_shape("held_direction", np.asarray(held_direction, dtype=float), (n_pts, 3))
        held = closed & (np.linalg.norm(s_held, axis=1) > 0.0)
        slip |= held
    stick = closed & ~slip

    s = e_tr / np.where(slip, norm_tr, 1.0)[:, None]
    if held.any():
        s[held] = s_held[held]
    t_T = np.where(slip[:, None], -mu * p[:, None] * s, -c_T * e_tr)            # Eq. (8.4)
    t_T = np.where(closed[:, None], t_T, 0.0)
    traction = p[:, None] * n + t_T

    J = -c_N * _outer(n, n)
    if G is not None:
        J = J + p[:, None, None] * G
    J_stick = J - c_T * de_tr
    ratio = np.where(slip & ~held, mu * p / np.where(slip, norm_tr, 1.0), 0.0)        # a held s does not turn
    J_slip = J + mu * c_N * _outer(s, n) - ratio[:, None, None] * np.einsum("nij,njk->nik", eye - _outer(s, s), de_tr)
    tangent = np.where(slip[:, None, None], J_slip, np.where(stick[:, None, None], J_stick, 0.0))

    e_new = np.where(slip[:, None], (mu * p / c_T)[:, None] * s, e_tr)
    e_new = np.where(closed[:, None], e_new, 0.0)
    slip_path = np.asarray(state["slip_path"], dtype=float) + np.where(slip, np.maximum(norm_tr - mu * p / c_T, 0.0),
                                                                       0.0)
    status = np.where(slip, SLIP, np.where(stick, STICK, OPEN)).astype(np.int8)
    new_state = {"elastic_slip": e_new, "slip_path": slip_path, "status": status}
    return ContactResponse(traction, tangent, p, new_state)
