"""Micro–macro parameter identification of Ch. 5.2: DEM contact parameters <-> continuum elastic constants.

The energy-minimisation approach of the seed (Eq. 5.7–5.26) averages the contact energies of a
monodisperse, isotropic packing of spheres of radius r with ``rho_c`` contacts per unit volume over all
contact directions n, subject to a kinematic constraint that ties the contact displacements u(n) to the
macroscopic displacement gradient, Eq. (5.10)::

    grad u^m = alpha / r * <u (x) n>,        alpha = 1 as published.

An affine field, whose relative centre displacement is u(n) = 2 r grad u^m . n (branch vector 2 r n), gives
``1/r <u (x) n> = 2/3 grad u^m`` because ``<n (x) n> = I/3``: it does not satisfy the published constraint.
The *consistent* prefactor is ``alpha = 3/2``; since the energy is quadratic in the constraint, every
modulus scales with ``1/alpha**2`` (E_consistent = 4/9 E_published) and Poisson's ratio is unchanged.

Three variants are offered everywhere a closed form depends on this choice:

``"published"``   Eq. (5.20)/(5.21)/(5.26) exactly as printed (alpha = 1);
``"consistent"``  the same minimisation with alpha = 3/2 (an affine field satisfies the constraint);
``"affine"``      the uniform-strain (Voigt) estimate: every contact follows the affine field.

Units: stiffnesses K in N/m, radius r in m, contact density rho_c in 1/m^3, so rho_c r^2 K is in Pa;
bond strengths f in N, so rho_c r f is in Pa (any consistent set works, e.g. N, mm, MPa).

The module also holds the contact stiffness rules of Ch. 4.1.3 (series springs, Hertz–Mindlin) and an
independent numerical solution of the constrained minimisation, Eq. (5.12), over a spherical quadrature.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from scipy.sparse.linalg import splu

from .tensors import (
    from_voigt,
    from_voigt4,
    identity4_dev,
    identity4_vol,
    sphere_quadrature,
    to_mandel4,
    to_voigt,
)
from .validation import (
    check_finite,
    check_option,
    check_poisson,
    check_positive,
    check_range,
    check_shape,
    number_arguments,
)

__all__ = [
    "POISSON_RANGE", "VARIANTS", "particle_number_density", "contact_density", "measured_contact_density",
    "elastic_constants", "contact_stiffnesses", "failure_stresses", "bond_strengths", "series_stiffness",
    "hertz_contact_radius", "hertz_normal_stiffness", "hertz_shear_stiffness", "affine_contact_displacements",
    "constraint_gradient", "minimise_contact_energy", "affine_stiffness", "numerical_elastic_constants",
    "isotropic_part"
]

VARIANTS = ("published", "consistent", "affine")

#: alpha in the kinematic constraint grad u^m = alpha / r <u (x) n>, Eq. (5.10); also scales Eq. (5.24).
CONSTRAINT_PREFACTOR = {"published": 1.0, "consistent": 1.5}

#: Poisson's ratios each variant can produce with positive stiffnesses 0 < Kt/Kn < inf (open intervals).
POISSON_RANGE = {"published": (-1.0 / 3.0, 0.5), "consistent": (-1.0 / 3.0, 0.5), "affine": (-1.0, 0.25)}


# --- contact density, Eq. (5.9) and (5.29) ----------------------------------------------------------------


def particle_number_density(porosity, radius):
    """Particles per unit volume ``(1 - eta) / (4/3 pi r^3)`` of a packing of porosity eta (1/m^3).

    This is the factor of Eq. (5.9) that turns the coordination number into a contact density.
    """
    porosity = check_range("porosity", porosity, 0.0, 1.0, high_open=True)
    radius = check_positive("radius", radius)
    return (1.0 - porosity) / (4.0 / 3.0 * np.pi * radius**3)


def contact_density(coordination, porosity, radius):
    """Contacts per unit volume, Eq. (5.9): ``rho_c = c/2 (1 - eta) / (4/3 pi r^3)`` (1/m^3).

    Each of the c contacts of a particle is shared by two particles, hence c/2.
    """
    coordination = check_positive("coordination", coordination)
    return coordination / 2.0 * particle_number_density(porosity, radius)


def measured_contact_density(n_contacts, volume):
    """Contact density measured in a specimen, Eq. (5.29): ``rho_c = n_c / V`` (1/m^3)."""
    n_contacts = check_positive("n_contacts", n_contacts, allow_zero=True)
    volume = check_positive("volume", volume)
    return n_contacts / volume


# --- elastic constants, Eq. (5.20) and (5.21) -------------------------------------------------------------


def _check_variant(variant, allowed=VARIANTS):
    return check_option("variant", variant, allowed)


def elastic_constants(kn, kt, rho_c, radius, variant: str = "published"):
    """Macroscopic Young's modulus E (Pa) and Poisson's ratio nu from contact stiffnesses, Eq. (5.20).

    ``"published"``:  E = 15 rho_c r^2 (3/Kn + 2/Kt)^-1,          nu = (Kn - Kt) / (2 Kn + 3 Kt)   (5.20)
    ``"consistent"``: E = 20/3 rho_c r^2 (3/Kn + 2/Kt)^-1,        nu as published (alpha = 3/2)
    ``"affine"``:     E = 4/3 rho_c r^2 Kn (2 Kn + 3 Kt)/(4 Kn + Kt),  nu = (Kn - Kt) / (4 Kn + Kt)

    Arguments broadcast; stiffnesses in N/m, rho_c in 1/m^3, radius in m.
    """
    _check_variant(variant)
    kn, kt = check_positive("kn", kn), check_positive("kt", kt)
    scale = check_positive("rho_c", rho_c) * check_positive("radius", radius) ** 2
    if variant == "affine":
        E = 4.0 / 3.0 * scale * kn * (2.0 * kn + 3.0 * kt) / (4.0 * kn + kt)
        return E, (kn - kt) / (4.0 * kn + kt)
    alpha = CONSTRAINT_PREFACTOR[variant]
    E = 15.0 / alpha**2 * scale / (3.0 / kn + 2.0 / kt)
    return E, (kn - kt) / (2.0 * kn + 3.0 * kt)


def contact_stiffnesses(E, nu, rho_c, radius, variant: str = "published"):
    """Contact stiffnesses (Kn, Kt) in N/m that give the macroscopic E (Pa) and nu, Eq. (5.21).

    ``"published"``:  Kn = E / (3 rho_c r^2 (1 - 2 nu)),  Kt = E / (3 rho_c r^2 (1 + 3 nu)),  -1/3 < nu < 1/2
    ``"consistent"``: both times 9/4 (alpha^2),                                             -1/3 < nu < 1/2
    ``"affine"``:     Kn = 3 E / (4 rho_c r^2 (1 - 2 nu)),  Kt/Kn = (1 - 4 nu)/(1 + nu),     -1 < nu < 1/4

    Outside these open intervals one of the stiffnesses would be infinite or negative: ``ValueError``.
    """
    _check_variant(variant)
    low, high = POISSON_RANGE[variant]
    nu = check_range("nu", nu, low, high, low_open=True, high_open=True)
    E = check_positive("E", E)
    scale = check_positive("rho_c", rho_c) * check_positive("radius", radius) ** 2
    if variant == "affine":
        kn = 3.0 * E / (4.0 * scale * (1.0 - 2.0 * nu))
        return kn, kn * (1.0 - 4.0 * nu) / (1.0 + nu)
    alpha = CONSTRAINT_PREFACTOR[variant]
    base = alpha**2 * E / (3.0 * scale)
    return base / (1.0 - 2.0 * nu), base / (1.0 + 3.0 * nu)


# --- bonded material: contact forces and failure stresses, Eq. (5.22)–(5.26) -----------------------------


@number_arguments
def contact_forces(sigma: ArrayLike, directions: ArrayLike, rho_c: ArrayLike, radius: ArrayLike,
                   variant: str = "published"):
    """Normal and tangential contact forces (N) under the macroscopic stress sigma (Pa), Eq. (5.24).

    ``t^n = alpha/(rho_c r) (n.sigma.n) n``, ``t^t = alpha/(rho_c r) (sigma.n - (n.sigma.n) n)`` with
    alpha = 1 as published and 3/2 consistent. Returns two ``(m, 3)`` arrays for ``directions`` ``(m, 3)``.
    With alpha = 3/2 the Love–Weber average ``rho_c <t (x) 2 r n>`` of these forces gives back sigma.
    """
    alpha = CONSTRAINT_PREFACTOR[_check_variant(variant, tuple(CONSTRAINT_PREFACTOR))]
    sigma = check_shape("sigma", np.asarray(sigma, dtype=float), (3, 3))
    n = check_shape("directions", np.asarray(directions, dtype=float), (None, 3))
    scale = alpha / (check_positive("rho_c", rho_c) * check_positive("radius", radius))
    traction = n @ sigma.T  # sigma . n for every direction
    sigma_n = np.einsum("mi,mi->m", n, traction)
    t_n = scale * sigma_n[:, None] * n
    return t_n, scale * traction - t_n


def failure_stresses(f_n, f_t, rho_c, radius, variant: str = "published"):
    """Rankine and Tresca failure stresses (Pa) of a bonded packing, Eq. (5.26).

    ``sigma_y^Rankine = rho_c r f^{n,c} / alpha`` and ``sigma_y^Tresca = rho_c r f^{t,c} / alpha`` with the
    bond strengths f in N; alpha = 1 as published, 3/2 consistent. The weaker of the two governs.
    """
    alpha = CONSTRAINT_PREFACTOR[_check_variant(variant, tuple(CONSTRAINT_PREFACTOR))]
    f_n, f_t = check_positive("f_n", f_n), check_positive("f_t", f_t)
    scale = check_positive("rho_c", rho_c) * check_positive("radius", radius) / alpha
    return scale * f_n, scale * f_t


def bond_strengths(sigma_rankine, sigma_tresca, rho_c, radius, variant: str = "published"):
    """Bond strengths (f^{n,c}, f^{t,c}) in N from the failure stresses in Pa, the inverse of Eq. (5.26)."""
    alpha = CONSTRAINT_PREFACTOR[_check_variant(variant, tuple(CONSTRAINT_PREFACTOR))]
    sigma_rankine = check_positive("sigma_rankine", sigma_rankine)
    sigma_tresca = check_positive("sigma_tresca", sigma_tresca)
    scale = alpha / (check_positive("rho_c", rho_c) * check_positive("radius", radius))
    return scale * sigma_rankine, scale * sigma_tresca


# --- contact stiffness rules, Eq. (4.11)–(4.14) -----------------------------------------------------------


def series_stiffness(k_a, k_b):
    """Contact stiffness of two springs in series, Eq. (4.11)/(4.12): ``K = k_a k_b / (k_a + k_b)`` (N/m).

    The same rule gives the normal (4.11) and the tangential (4.12) contact stiffness, of two particles or of a
    particle and a wall; the DEM's contact laws call it per contact. Each stiffness lies in [0, inf] (0: no
    spring, which gives K = 0; inf: a rigid side, which gives the other side's stiffness); NaN or a negative
    value is refused. Arguments broadcast.
    """
    stiffnesses = []
    for name, k in (("k_a", k_a), ("k_b", k_b)):
        try:
            k = np.asarray(k, float)
        except (TypeError, ValueError):
            raise TypeError(f"{name} must be a stiffness in [0, inf] (N/m), got {k!r}") from None
        stiffnesses.append(k)
        if k.size and not k.min() >= 0.0:                       # one pass: a NaN fails the comparison too
            raise ValueError(f"{name} must lie in [0, inf] (a stiffness, N/m), got {k[np.isnan(k) | (k < 0)][:3]}")
    k_a, k_b = stiffnesses
    with np.errstate(divide="ignore"):                        # 1/0 = inf: a side without spring gives 0
        return 1.0 / (1.0 / k_a + 1.0 / k_b)


def hertz_contact_radius(r_a, r_b=None):
    """Radius r~ entering Eq. (4.13)/(4.14): ``2 r_a r_b / (r_a + r_b)`` for two balls, ``r_a`` for a wall.

    The seed calls r~ the "mean particle radius"; this is the PFC convention, for which Eq. (4.13)/(4.14)
    coincide with Hertz/Mindlin theory (r~ = r for two equal balls).
    """
    r_a = check_positive("r_a", r_a)
    if r_b is None:
        return r_a
    r_b = check_positive("r_b", r_b)
    return 2.0 * r_a * r_b / (r_a + r_b)


def _hertz_material(shear_modulus, poisson, radius):
    G = check_positive("shear_modulus", shear_modulus)
    return G, check_poisson("poisson", poisson), check_positive("radius", radius)


def hertz_normal_stiffness(shear_modulus, poisson, radius, overlap):
    """Secant normal stiffness of the Hertz model, Eq. (4.13) (N/m), so that ``F^n = K^n U^n``.

    ``K^n = 2 <G> sqrt(2 r~) / (3 (1 - <nu>)) sqrt(U^n)`` with the mean shear modulus <G> (Pa), the mean
    Poisson's ratio <nu>, r~ from :func:`hertz_contact_radius` (m) and the overlap U^n >= 0 (m).
    The model carries no tension: a negative overlap is refused.
    """
    G, nu, r = _hertz_material(shear_modulus, poisson, radius)
    overlap = check_positive("overlap", overlap, allow_zero=True)
    return 2.0 * G * np.sqrt(2.0 * r) / (3.0 * (1.0 - nu)) * np.sqrt(overlap)


def hertz_shear_stiffness(shear_modulus, poisson, radius, normal_force):
    """Tangent shear stiffness of the Hertz–Mindlin model, Eq. (4.14) (N/m).

    ``K^t = 2 (3 <G>^2 (1 - <nu>) r~)^(1/3) / (2 - <nu>) |F^n|^(1/3)`` with the normal force magnitude in N.
    """
    G, nu, r = _hertz_material(shear_modulus, poisson, radius)
    normal_force = np.abs(check_finite("normal_force", normal_force))
    return 2.0 * np.cbrt(3.0 * G**2 * (1.0 - nu) * r) / (2.0 - nu) * np.cbrt(normal_force)


# --- the kinematic constraint, Eq. (5.10) -----------------------------------------------------------------


def _directions_and_weights(degree, directions, weights):
    if directions is None:
        if weights is not None:
            raise ValueError("weights given without directions")
        return sphere_quadrature(degree)
    n = check_shape("directions", np.asarray(directions, dtype=float), (None, 3))
    if not np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-12):
        raise ValueError("directions must be unit vectors")
    if weights is None:
        w = np.full(len(n), 1.0 / len(n))
    else:
        w = check_positive("weights", check_shape("weights", np.asarray(weights, dtype=float), (len(n),)))
        if abs(w.sum() - 1.0) > 1e-12:
            raise ValueError(f"weights must sum to 1 (a directional average, Eq. 5.7), got {w.sum()!r}")
    return n, np.atleast_1d(w)


@number_arguments
def constraint_gradient(u: ArrayLike, directions: ArrayLike, weights: ArrayLike, radius: ArrayLike,
                        variant: str = "published"):
    """Macroscopic displacement gradient implied by contact displacements, Eq. (5.10).

    ``grad u^m = alpha / r <u (x) n>`` with ``<.>`` the weighted average over ``directions`` ``(m, 3)``;
    alpha = 1 as published, 3/2 consistent. ``u`` is ``(..., m, 3)``; returns ``(..., 3, 3)``.
    """
    alpha = CONSTRAINT_PREFACTOR[_check_variant(variant, tuple(CONSTRAINT_PREFACTOR))]
    n, w = _directions_and_weights(None, directions, weights)
    u = check_shape("u", np.asarray(u, dtype=float), (..., len(n), 3))
    return alpha / check_positive("radius", radius) * np.einsum("m,...mi,mj->...ij", w, u, n)


@number_arguments
def affine_contact_displacements(grad_u: ArrayLike, directions: ArrayLike, radius: ArrayLike):
    """Relative centre displacements of an affine field, ``u(n) = grad u . (2 r n)`` (branch vector 2 r n)."""
    grad_u = check_shape("grad_u", np.asarray(grad_u, dtype=float), (..., 3, 3))
    n = check_shape("directions", np.asarray(directions, dtype=float), (None, 3))
    return 2.0 * check_positive("radius", radius) * np.einsum("...ij,mj->...mi", grad_u, n)


# --- numerical solution of the constrained minimisation, Eq. (5.12)–(5.16) --------------------------------


class ContactSolution(NamedTuple):
    """Minimiser of Eq. (5.12) for one or more macroscopic displacement gradients (leading axes ``...``)."""

    u: np.ndarray  #: contact displacements u(n), (..., m, 3), m
    omega: np.ndarray  #: average particle rotation omega of Eq. (5.12), (..., 3), rad
    sigma: np.ndarray  #: Lagrange multiplier sigma_bar = macroscopic stress, (..., 3, 3), Pa
    energy: np.ndarray  #: macroscopic free energy Psi^m per unit volume, (...,), Pa
    directions: np.ndarray  #: the m contact directions n, (m, 3)
    weights: np.ndarray  #: their weights in the average <.>, (m,)


def _cross_matrices(n):
    """``[n]_x`` with ``[n]_x a = n x a`` for every direction, (m, 3, 3)."""
    z = np.zeros(len(n))
    return np.stack(
        [
            np.stack([z, -n[:, 2], n[:, 1]], axis=-1),
            np.stack([n[:, 2], z, -n[:, 0]], axis=-1),
            np.stack([-n[:, 1], n[:, 0], z], axis=-1),
        ],
        axis=-2,
    )


def _contact_stiffness_matrices(n, kn, kt):
    """Contact stiffness ``A(n) = Kn n (x) n + Kt (I - n (x) n)`` of Eq. (5.4), (m, 3, 3)."""
    nn = np.einsum("mi,mj->mij", n, n)
    return kn * nn + kt * (np.eye(3) - nn)


def _kkt_matrix(n, w, kn, kt, rho_c, radius, alpha):
    """Saddle-point matrix of the Lagrangian (5.13), unknowns ``[u_1..u_m, omega | sigma_bar]``.

    The elastic contact displacement is ``e_k = u_k + 2 r omega x n_k = u_k + B_k omega`` with
    ``B_k = -2 r [n_k]_x``; the energy is ``1/2 sum_k rho_c w_k e_k.A_k e_k`` and the constraint rows
    ``(i, j)`` read ``alpha/r sum_k w_k u_ki n_kj = grad_u_ij``.
    """
    m = len(n)
    A = _contact_stiffness_matrices(n, kn, kt)
    B = -2.0 * radius * _cross_matrices(n)
    s = (rho_c * w)[:, None, None]
    H_uu = s * A
    H_uw = s * A @ B
    H_ww = np.sum(s * np.swapaxes(B, 1, 2) @ A @ B, axis=0)

    k, i, j = np.meshgrid(np.arange(m), np.arange(3), np.arange(3), indexing="ij")
    rows, cols, vals = [3 * k + i], [3 * k + j], [H_uu]
    rows += [3 * k + i, 3 * m + j]
    cols += [3 * m + j, 3 * k + i]
    vals += [H_uw, H_uw]
    ii, jj = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
    rows.append(3 * m + ii)
    cols.append(3 * m + jj)
    vals.append(H_ww)
    # constraint row 3i+j, column 3k+i: alpha/r w_k n_kj
    c_rows = 3 * m + 3 + 3 * i + j
    c_vals = alpha / radius * w[:, None, None] * n[:, None, :] * np.ones((1, 3, 1))
    rows += [c_rows, 3 * k + i]
    cols += [3 * k + i, c_rows]
    vals += [c_vals, c_vals]
    size = 3 * m + 12
    K = sp.coo_matrix(
        (np.concatenate([v.ravel() for v in vals]),
         (np.concatenate([r.ravel() for r in rows]), np.concatenate([c.ravel() for c in cols]))),
        shape=(size, size),
    )
    return K.tocsc()


@number_arguments
def minimise_contact_energy(grad_u: ArrayLike, kn: float, kt: float, rho_c: float, radius: float,
                            variant: str = "published", degree: int = 6, directions=None,
                            weights=None) -> ContactSolution:
    """Solve the constrained minimisation of Eq. (5.12) numerically over a set of contact directions.

    Unknowns are the contact displacements u(n_k) of every direction and the common rotation omega;
    the Lagrange multiplier sigma_bar of the kinematic constraint (5.10) is the macroscopic stress.
    The stationarity conditions (5.14)/(5.15) and the constraint form one linear saddle-point system,
    solved with a sparse LU factorisation for all gradients in ``grad_u`` ``(..., 3, 3)`` at once.

    Directions default to :func:`abrakit.tensors.sphere_quadrature` of ``degree`` (exact for Eq. 5.18 from
    degree 4 on); ``directions`` ``(m, 3)`` with optional ``weights`` (equal by default) model a finite
    contact fabric instead. ``variant`` is ``"published"`` (alpha = 1) or ``"consistent"`` (alpha = 3/2).
    """
    alpha = CONSTRAINT_PREFACTOR[_check_variant(variant, tuple(CONSTRAINT_PREFACTOR))]
    kn, kt = check_positive("kn", kn), check_positive("kt", kt)
    rho_c, radius = check_positive("rho_c", rho_c), check_positive("radius", radius)
    n, w = _directions_and_weights(degree, directions, weights)
    fabric = np.einsum("m,mi,mj->ij", w, n, n)
    eig = np.linalg.eigvalsh(fabric)
    if eig[0] <= 1e-10 * eig[-1]:
        raise ValueError(
            f"the {len(n)} contact directions do not span three dimensions (fabric eigenvalues {eig}); "
            "the constraint (5.10) cannot be met: use sphere_quadrature degree >= 2 or more directions"
        )
    grad_u = check_shape("grad_u", np.asarray(grad_u, dtype=float), (..., 3, 3))
    batch = grad_u.shape[:-2]
    m = len(n)
    rhs = np.zeros((3 * m + 12, int(np.prod(batch, dtype=int))))
    rhs[3 * m + 3:] = grad_u.reshape(-1, 9).T
    x = splu(_kkt_matrix(n, w, kn, kt, rho_c, radius, alpha)).solve(rhs)
    u = x[: 3 * m].T.reshape(*batch, m, 3)
    omega = x[3 * m: 3 * m + 3].T.reshape(*batch, 3)
    sigma = -x[3 * m + 3:].T.reshape(*batch, 3, 3)
    e = u + 2.0 * radius * np.cross(omega[..., None, :], n)
    A = _contact_stiffness_matrices(n, kn, kt)
    energy = 0.5 * rho_c * np.einsum("m,...mi,mij,...mj->...", w, e, A, e)
    return ContactSolution(u, omega, sigma, energy, n, w)


class NumericalElasticity(NamedTuple):
    """Stiffness of a contact fabric found numerically, with its closest isotropic E and nu."""

    E: float  #: Young's modulus of the isotropic part, Pa
    nu: float  #: Poisson's ratio of the isotropic part
    stiffness: np.ndarray  #: 6x6 Voigt stiffness (stress = C @ engineering strain), Pa
    anisotropy: float  #: |C - C_iso| / |C| in Mandel form; round-off for an exact sphere rule


@number_arguments
def isotropic_part(stiffness: ArrayLike):
    """Closest isotropic (E, nu) to a 6x6 Voigt stiffness and the relative distance to it (Mandel norm).

    Bulk modulus 3K = (I(x)I/3) :: C and shear modulus 2 mu = (I^dev :: C)/5, the orthogonal projections.
    """
    C = to_mandel4(from_voigt4(check_shape("stiffness", check_finite("stiffness", stiffness), (6, 6))))
    if not np.all(np.isfinite(C)) or not np.any(C):
        raise ValueError("stiffness must be a finite, non-zero 6x6 Voigt matrix (a vanishing one has no isotropic "
                         "E and nu)")
    P_vol, P_dev = to_mandel4(identity4_vol()), to_mandel4(identity4_dev())
    three_k = np.sum(P_vol * C)
    two_mu = np.sum(P_dev * C) / 5.0
    C_iso = three_k * P_vol + two_mu * P_dev
    bulk, mu = three_k / 3.0, two_mu / 2.0
    E = 9.0 * bulk * mu / (3.0 * bulk + mu)
    nu = (3.0 * bulk - 2.0 * mu) / (2.0 * (3.0 * bulk + mu))
    return E, nu, np.linalg.norm(C - C_iso) / np.linalg.norm(C)


def _unit_strains():
    """The six unit engineering strains of Voigt notation as tensors, (6, 3, 3)."""
    return from_voigt(np.eye(6), "strain")


def affine_stiffness(kn, kt, rho_c, radius, degree: int = 6, directions=None, weights=None):
    """6x6 Voigt stiffness of the uniform-strain (affine, Voigt) estimate by quadrature over directions.

    Every contact follows ``e(n) = 2 r eps . n`` (particles spin with the continuum), so
    ``Psi = rho_c <1/2 e.A(n) e>`` and ``sigma = rho_c <sym(A(n) e (x) 2 r n)>`` (Love–Weber).
    """
    kn, kt = check_positive("kn", kn), check_positive("kt", kt)
    rho_c, radius = check_positive("rho_c", rho_c), check_positive("radius", radius)
    n, w = _directions_and_weights(degree, directions, weights)
    eps = _unit_strains()
    e = affine_contact_displacements(eps, n, radius)
    t = np.einsum("mij,smj->smi", _contact_stiffness_matrices(n, kn, kt), e)
    sigma = rho_c * 2.0 * radius * np.einsum("m,smi,mj->sij", w, t, n)
    sigma = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
    return to_voigt(sigma, "stress").T


def numerical_elastic_constants(kn, kt, rho_c, radius, variant: str = "published", degree: int = 6,
                                directions=None, weights=None) -> NumericalElasticity:
    """Independent numerical counterpart of Eq. (5.20) (and of its variants).

    ``"published"``/``"consistent"``: solve the minimisation (5.12) for the six unit strains with
    :func:`minimise_contact_energy`; ``"affine"``: average the affine contact energy with
    :func:`affine_stiffness`.
    The macroscopic stiffness is read off the stresses, and E, nu from its isotropic part.
    """
    _check_variant(variant)
    if variant == "affine":
        C = affine_stiffness(kn, kt, rho_c, radius, degree, directions, weights)
    else:
        sol = minimise_contact_energy(
            _unit_strains(), kn, kt, rho_c, radius, variant, degree, directions, weights
        )
        sigma = 0.5 * (sol.sigma + np.swapaxes(sol.sigma, 1, 2))
        C = to_voigt(sigma, "stress").T
    E, nu, anisotropy = isotropic_part(C)
    return NumericalElasticity(float(E), float(nu), C, float(anisotropy))
