"""Anisotropic softening damage tied to fracture toughness (seed 001: "Isotropic Softening Material").

An isotropic elastic material that, once it fails, carries a crack plane with its own damage (Chaboche 1979;
Nairn, Hammerquist & Aimene 2017):

    sigma = (I - D) C (eps - eps_res),                                                     (AD.1)

with D built in the **crack axes** (x along the crack normal n, y and z along the crack plane tangents t1, t2)
from one normal and two shear damage variables,

    D_xx,xx = d_n,  D_yy,xx = D_zz,xx = d_n nu/(1 - nu),  D_xy,xy = d_xy,  D_xz,xz = d_xz,       (AD.2)

every other entry zero, and rotated to the global axes. The ``nu/(1 - nu)`` entries make a fully opened crack
(d_n = 1) traction free while the material beside it keeps its plane-stress stiffness; (I - D) C is symmetric.
Written out, with the effective stress ``sigma_e = C eps`` in crack axes, the crack carries the tractions

    T_n = (1 - d_n) C_11 e_n    (e_n = sigma_e,xx / C_11, the normal strain the crack opens by; d_n acts only for
    T_1 = (1 - d_xy) mu g_1     e_n > 0: a closed crack carries compression)                 (AD.3)
    T_2 = (1 - d_xz) mu g_2     (g_1 = 2 eps_xy, g_2 = 2 eps_xz),

and the cracking strains ``d_n e_n``, ``d_xy g_1``, ``d_xz g_2`` are the openings ``delta`` smeared over the crack
band width ``h``: ``delta = h d e`` (crack band; Bažant & Oh 1983).

**Initiation** (the seed's maximum-principal-stress law): a point cracks when sigma_1 >= r_s sigma_c (tension; crack
normal = the direction of sigma_1) or (sigma_1 - sigma_3)/2 >= r_s tau_c (shear; normal halfway between the
directions of sigma_1 and sigma_3, the plane of the largest shear), whichever ratio is larger. The crack axes are
then fixed. With ``plane=True`` (2D plane strain) only the in-plane stresses are analysed and the normal lies in the
x–y plane.

**Softening** (:mod:`.softening_laws`): the normal traction is bounded by ``S_I(delta_n)`` (strength r_s sigma_c,
toughness r_t G_Ic) and the shear tractions by ``S_II(delta_s)`` (r_s tau_c, r_t G_IIc). Damage grows when the
tractions leave the **traction failure surface** (seed 001, "Damage Generalizations"), numbered as in the seed:

- 0 ``cuboid``: |T_n| <= S_I, |T_1| <= S_II, |T_2| <= S_II, each with its own damage (uncoupled);
- 1 ``elliptical_cylinder``: T_n <= S_I; |(T_1, T_2)| <= S_II with one shear damage d_xy = d_xz;
- 2 ``ovoid`` (default): (T_n/S_I)^2 + (|(T_1, T_2)|/S_II)^2 <= 1 with one damage d_n = d_xy = d_xz, returned
  towards the origin;
- 3 ``coupled_cuboid``: max(T_n/S_I, |T_1|/S_II, |T_2|/S_II) <= 1 with one damage, returned towards the origin.

In compression (e_n <= 0) no surface fails in the normal direction; the ovoid is an elliptical cylinder there and
its shear damage still raises d_n. A damaging group solves ``f(d) = 1`` for its damage (``f`` the surface's ratio),
with the openings ``delta_i = max(delta_i,old, h d e_i)``; this has one root while the band is narrower than
:func:`~.softening_laws.max_band_width` (checked, with the stricter uniaxial-stress modulus E for mode I).
Unloading is secant: the stress returns to the origin (damage, not plasticity).

The tangent is the consistent one: the secant ``R^T (I - D) C R`` plus, for every damaging group,
``(d sigma / d d) (x) (d d / d eps)`` with ``d d/d eps`` from the implicit function ``f(d, e) = 1``.

Dissipation per volume is ``sum_k Y_k dd_k`` with the energy release rates ``Y_n = C_11 <e_n>_+^2/2``,
``Y_1 = mu g_1^2/2``, ``Y_2 = mu g_2^2/2`` (integrated by the trapezoidal rule over a step), kept as mode I and
mode II parts: at complete separation in a band of width h, mode I dissipates G_Ic/h per volume.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import tensors as T
from ..validation import check_finite, check_number_fields, check_option, check_positive, check_range, check_shape
from .base import IsotropicElasticity, MaterialResponse, check_strain
from .softening_laws import max_band_width, softening_law

#: The seed's traction failure surfaces, in its numbering 0–3.
SURFACES = ("cuboid", "elliptical_cylinder", "ovoid", "coupled_cuboid")
_SQRT2 = np.sqrt(2.0)
_ROOT_TOL = 1e-14
_ROOT_ITERATIONS = 200
#: Trailing shape of every state entry (the batch shape comes before it).
_TAILS = {"eps": (6,), "initiated": (), "axes": (3, 3), "band_width": (), "d": (3,), "delta": (3,),
          "dissipation_I": (), "dissipation_II": ()}


def _bracketed_root(ratio, low, high, g_low, g_high):
    """Root of ``ratio(d) = 1`` in [low, high] with ``g = ratio - 1`` > 0 at ``low`` and <= 0 at ``high``, for
    every point at once: false position with the Illinois modification (superlinear, never leaves the bracket),
    until |g| <= 1e-14 or the bracket is closed."""
    low, high, g_low, g_high = low.copy(), high.copy(), g_low.copy(), g_high.copy()
    root = high.copy()
    side = np.zeros(low.shape, dtype=int)
    open_ = (g_high < -_ROOT_TOL)
    with np.errstate(invalid="ignore", divide="ignore"):
        for _ in range(_ROOT_ITERATIONS):
            if not np.any(open_):
                break
            d = np.where(np.isfinite(g_low) & (g_low - g_high > 0.0),
                         high - g_high * (high - low) / (g_high - g_low), 0.5 * (low + high))
            d = np.where((d <= low) | (d >= high), 0.5 * (low + high), d)
            g = ratio(d) - 1.0
            root = np.where(open_, d, root)
            outside = (g > 0.0) & open_
            inside = ~outside & open_
            low, g_low = np.where(outside, d, low), np.where(outside, g, g_low)
            high, g_high = np.where(inside, d, high), np.where(inside, g, g_high)
            g_high = np.where(outside & (side == 1), 0.5 * g_high, g_high)          # Illinois: halve the stale end
            g_low = np.where(inside & (side == -1), 0.5 * g_low, g_low)
            side = np.where(outside, 1, np.where(inside, -1, side))
            open_ &= (np.abs(g) > _ROOT_TOL) & (high - low > 4e-16)
    return root


@dataclass(frozen=True)
class ProjectedBandWidth:
    """Crack band width of each point = the extent of its element along the crack normal (mm), fixed when the
    point cracks (Oliver 1989). ``vertices`` (..., n_vertices, dim): the element corners of every point."""

    vertices: np.ndarray
    factor: float | np.ndarray = 1.0

    def __post_init__(self):
        check_finite("vertices", self.vertices)
        check_positive("factor", check_finite("factor", self.factor))

    def width(self, normals: np.ndarray, where, batch: tuple[int, ...]) -> np.ndarray:
        """Width of the points ``where`` (flat indices into the batch ``batch``) for their ``normals`` (m, 3),
        times ``factor`` (e.g. 2 on a symmetry line, where the model holds half of the band)."""
        vertices = np.asarray(self.vertices)
        corners = np.broadcast_to(vertices, (*batch, *vertices.shape[-2:])).reshape(-1, *vertices.shape[-2:])[where]
        dim = corners.shape[-1]
        along = np.einsum("mvd,md->mv", corners, normals[:, :dim])
        factor = np.broadcast_to(self.factor, batch).reshape(-1)[where]
        return factor * (along.max(axis=-1) - along.min(axis=-1))


def projected_band_width(basis, mirror_y: bool = False) -> ProjectedBandWidth:
    """:class:`ProjectedBandWidth` of every quadrature point of a scikit-fem basis (element corners = the mesh's
    vertices of each element). ``mirror_y``: the line y = 0 is a symmetry line, so the elements with an edge on it
    hold half of a band that the mirror image completes; their width counts twice."""
    mesh = basis.mesh
    corners = mesh.p[:, mesh.t].transpose(2, 1, 0)                          # (nel, n_vertices, dim)
    nqp = basis.X.shape[-1]
    factor = 1.0
    if mirror_y:
        on_line = np.sum(np.isclose(corners[:, :, 1], 0.0), axis=1) >= 2
        factor = np.where(on_line, 2.0, 1.0)[:, None] * np.ones((1, nqp))
    return ProjectedBandWidth(np.broadcast_to(corners[:, None], (corners.shape[0], nqp, *corners.shape[1:])), factor)


def _crack_axes(normals: np.ndarray, plane: bool) -> np.ndarray:
    """Orthonormal crack axes (m, 3, 3), rows n, t1, t2, for unit ``normals`` (m, 3): in the plane, t1 = n turned
    by 90° about z and t2 = z; in 3D, t1 along n × (the axis least aligned with n)."""
    m = len(normals)
    if plane:
        t1 = np.stack([-normals[:, 1], normals[:, 0], np.zeros(m)], axis=1)
        t2 = np.broadcast_to([0.0, 0.0, 1.0], (m, 3))
    else:
        least = np.eye(3)[np.abs(normals).argmin(axis=1)]
        t1 = np.cross(normals, least)
        t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
        t2 = np.cross(normals, t1)
    return np.stack([normals, t1, t2], axis=1)


def _as_surface(surface) -> str:
    if isinstance(surface, (int, np.integer)) and not isinstance(surface, bool):
        check_range("surface", surface, 0, len(SURFACES) - 1)
        return SURFACES[int(surface)]
    return check_option("surface", surface, SURFACES)


@dataclass(frozen=True)
class AnisotropicSofteningDamage(IsotropicElasticity):
    """Seed 001's anisotropic softening damage (module docstring, Eq. AD.1–AD.3).

    ``E`` (MPa), ``nu``; strengths ``sigma_c`` (tension) and ``tau_c`` (shear), MPa; toughnesses ``G_Ic`` and
    ``G_IIc`` (N/mm); ``band_width`` h (mm; number, array over the points, or a :class:`ProjectedBandWidth`);
    softening laws ``softening_I``/``softening_II`` (``"linear"``, ``"exponential"``); ``surface`` (name or the
    seed's number 0–3); ``plane`` (2D: normals in the x–y plane); ``relative_strength``/``relative_toughness``
    (r_s, r_t per point, e.g. from :class:`~.strength_statistics.StrengthStatistics`); ``residual_strain``
    (Mandel, broadcast over the points); ``d_max`` caps every damage so the tangent keeps a trace of stiffness;
    ``tangent``: ``"consistent"`` or ``"secant"`` ((I - D) C, always positive definite); ``crack_normal``: a
    prescribed crack plane (unit normal, broadcast over the points) instead of the one the initiation law picks, for
    a crack path known in advance (an interface, the ligament of a fracture specimen): the point then cracks when its
    tractions on that plane leave the failure surface.
    """

    E: float
    nu: float
    sigma_c: float
    tau_c: float
    G_Ic: float
    G_IIc: float
    band_width: float | np.ndarray | ProjectedBandWidth = 1.0
    softening_I: str = "linear"
    softening_II: str = "linear"
    surface: str | int = "ovoid"
    plane: bool = False
    relative_strength: float | np.ndarray = 1.0
    relative_toughness: float | np.ndarray = 1.0
    residual_strain: np.ndarray | None = None
    d_max: float = 1.0 - 1e-9
    tangent: str = "consistent"
    crack_normal: np.ndarray | None = None

    def __post_init__(self):
        check_number_fields(self)
        check_positive("E", self.E)
        for name in ("sigma_c", "tau_c", "G_Ic", "G_IIc"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        object.__setattr__(self, "surface", _as_surface(self.surface))
        check_option("tangent", self.tangent, ("consistent", "secant"))
        if self.crack_normal is not None:
            normal = check_shape("crack_normal", np.asarray(self.crack_normal, dtype=float), (..., 3))
            length = np.linalg.norm(normal, axis=-1, keepdims=True)
            check_positive("crack_normal length", length)
            if self.plane and np.any(np.abs(normal[..., 2]) > 1e-12 * length[..., 0]):
                raise ValueError("crack_normal must lie in the x-y plane when plane=True")
            object.__setattr__(self, "crack_normal", normal / length)
        object.__setattr__(self, "law_I", softening_law(self.softening_I))
        object.__setattr__(self, "law_II", softening_law(self.softening_II))
        for name in ("relative_strength", "relative_toughness"):
            object.__setattr__(self, name, np.asarray(check_positive(name, getattr(self, name)), dtype=float))
        check_range("d_max", self.d_max, 0.0, 1.0, low_open=True, high_open=True)
        if self.residual_strain is not None:
            residual = check_shape("residual_strain", np.asarray(self.residual_strain, dtype=float), (..., 6))
            object.__setattr__(self, "residual_strain", residual)
        self._init_elasticity()      # checks nu
        object.__setattr__(self, "C11", float(self.stiffness[0, 0]))
        object.__setattr__(self, "nu_ratio", self.lam / (self.lam + 2.0 * self.mu))   # nu/(1 - nu)
        if not isinstance(self.band_width, ProjectedBandWidth):
            width = np.asarray(check_positive("band_width", self.band_width), dtype=float)
            object.__setattr__(self, "band_width", width)
            self.check_band_width(width, self.relative_strength, self.relative_toughness)

    # ---- the crack band --------------------------------------------------------------------------------------
    def max_band_widths(self, relative_strength=1.0, relative_toughness=1.0) -> tuple[np.ndarray, np.ndarray]:
        """Widest band (mm) without a local snap-back in mode I (modulus E) and mode II (modulus mu)."""
        rs, rt = np.asarray(relative_strength), np.asarray(relative_toughness)
        return (max_band_width(self.law_I, self.E, rs * self.sigma_c, rt * self.G_Ic),
                max_band_width(self.law_II, self.mu, rs * self.tau_c, rt * self.G_IIc))

    def check_band_width(self, width, relative_strength=1.0, relative_toughness=1.0) -> None:
        """Refuse a band (element) too wide for the softening laws: it would snap back at a single point."""
        for mode, h_max in zip(("I", "II"), self.max_band_widths(relative_strength, relative_toughness), strict=True):
            too_wide = np.asarray(width) >= h_max
            if np.any(too_wide):
                h = np.broadcast_to(width, np.broadcast_shapes(np.shape(width), np.shape(h_max)))[too_wide].max()
                raise ValueError(
                    f"band_width (element size across the crack) must be below {float(np.min(h_max)):.4g} mm for "
                    f"the mode {mode} softening law (h_max = factor·M·G_c/strength²), got {float(h):.4g} mm: "
                    "refine the mesh, or raise the toughness")

    # ---- state -----------------------------------------------------------------------------------------------
    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        fixed = not isinstance(self.band_width, ProjectedBandWidth)
        return {
            "eps": np.zeros((*shape, 6)),
            "initiated": np.zeros(shape, bool),
            "axes": np.zeros((*shape, 3, 3)),                 # rows: crack normal n, tangents t1, t2
            "band_width": np.broadcast_to(self.band_width, shape).copy() if fixed else np.zeros(shape),
            "d": np.zeros((*shape, 3)),                        # d_n, d_xy, d_xz
            "delta": np.zeros((*shape, 3)),                    # largest openings delta_n, delta_xy, delta_xz (mm)
            "dissipation_I": np.zeros(shape),
            "dissipation_II": np.zeros(shape),
        }

    def _mechanical(self, eps):
        return eps if self.residual_strain is None else eps - self.residual_strain

    # ---- initiation ------------------------------------------------------------------------------------------
    def initiation(self, stress: np.ndarray, relative_strength) -> tuple[np.ndarray, np.ndarray]:
        """Which points crack under the Mandel ``stress`` (m, 6), and their crack axes (m, 3, 3) (rows n, t1, t2).

        Tension: sigma_1 >= r_s sigma_c, n along sigma_1. Shear: (sigma_1 - sigma_3)/2 >= r_s tau_c, n = (v_1 +
        v_3)/sqrt 2, t1 = (v_1 - v_3)/sqrt 2. ``plane``: the in-plane principal stresses and directions only."""
        S = T.from_mandel(stress)
        m = S.shape[0]
        if self.plane:
            values, vectors2 = np.linalg.eigh(S[:, :2, :2])
            vectors = np.zeros((m, 3, 3))
            vectors[:, :2, 0], vectors[:, :2, 2] = vectors2[:, :, 0], vectors2[:, :, 1]
            vectors[:, 2, 1] = 1.0
            low, high = values[:, 0], values[:, 1]
        else:
            values, vectors = np.linalg.eigh(S)
            low, high = values[:, 0], values[:, 2]
        # eigenvector signs are arbitrary: make each one's largest component positive, so the shear plane (one of
        # the two conjugate planes of the largest shear) is chosen the same way on every machine
        largest = np.take_along_axis(vectors, np.abs(vectors).argmax(axis=1)[:, None, :], axis=1)
        vectors = vectors * np.where(largest < 0.0, -1.0, 1.0)
        v_min, v_mid, v_max = vectors[:, :, 0], vectors[:, :, 1], vectors[:, :, 2]
        rs = np.broadcast_to(relative_strength, (m,))
        tension = high / (rs * self.sigma_c)
        shear = 0.5 * (high - low) / (rs * self.tau_c)
        cracks = np.maximum(tension, shear) >= 1.0
        by_tension = (tension >= shear)[:, None, None]
        axes_tension = np.stack([v_max, v_mid, v_min], axis=1)
        axes_shear = np.stack([(v_max + v_min) / _SQRT2, (v_max - v_min) / _SQRT2, v_mid], axis=1)
        if self.plane:   # keep t2 = z out of plane, t1 in plane
            axes_tension = np.stack([v_max, v_min, v_mid], axis=1)
        return cracks, np.where(by_tension, axes_tension, axes_shear)

    def initiation_on_plane(self, strain, normals, h, rs, rt) -> tuple[np.ndarray, np.ndarray]:
        """Initiation on a prescribed crack plane (``crack_normal``): a point cracks when its tractions on that
        plane leave the failure surface at zero damage; returns (cracks, axes) like :meth:`initiation`."""
        axes = _crack_axes(normals, self.plane)
        local = np.einsum("mij,mj->mi", T.mandel_rotation(axes), strain)
        zero = np.zeros((len(normals), 3))
        d, _, _ = self._damage(local, zero, zero, h, rs, rt, derivatives=False)
        return np.any(d > 0.0, axis=1), axes

    # ---- the traction failure surfaces -----------------------------------------------------------------------
    def _groups(self, e_n, g1, g2):
        """The damage groups of the surface: each is ``(modes, combine)``, a mode ``(drive, modulus, mode I?,
        damage/opening columns)``; the drive is the opening strain (>= 0)."""
        normal = (np.maximum(e_n, 0.0), self.C11, True, (0,))
        s1, s2 = (np.abs(g1), self.mu, False, (1,)), (np.abs(g2), self.mu, False, (2,))
        both = (np.hypot(g1, g2), self.mu, False, (1, 2))
        return {"cuboid": [([normal], "max"), ([s1], "max"), ([s2], "max")],
                "elliptical_cylinder": [([normal], "max"), ([both], "max")],
                "ovoid": [([normal, both], "norm")],
                "coupled_cuboid": [([normal, s1, s2], "max")]}[self.surface]

    def traction_ratio(self, T_n, T_1, T_2=0.0) -> np.ndarray:
        """The failure surface of an undamaged crack plane in traction space: the largest group ratio f for the
        crack tractions ``T_n``, ``T_1``, ``T_2`` (MPa, broadcast); f = 1 on the surface, > 1 outside."""
        T_n, T_1, T_2 = np.broadcast_arrays(*(np.asarray(t, dtype=float).ravel() for t in (T_n, T_1, T_2)))
        e_n, g1, g2 = T_n / self.C11, T_1 / self.mu, T_2 / self.mu
        m = len(e_n)
        zero, ones = np.zeros(m), np.ones(m)
        ratios = [self._ratio(zero, modes, combine, np.zeros((m, 3)), ones, ones, ones)
                  for modes, combine in self._groups(e_n, g1, g2)]
        return np.max(ratios, axis=0)

    def _ratio(self, d, modes, combine, delta_old, h, rs, rt):
        """The surface ratio f(d) of a group at damage ``d`` (m,), > 1 outside."""
        ratios = []
        for drive, modulus, mode_I, columns in modes:
            law, strength, toughness = ((self.law_I, self.sigma_c, self.G_Ic) if mode_I
                                        else (self.law_II, self.tau_c, self.G_IIc))
            delta = np.maximum(delta_old[:, columns[0]], h * d * drive)
            S = law.traction(delta, rs * strength, rt * toughness)
            traction = (1.0 - d) * modulus * drive
            with np.errstate(divide="ignore", invalid="ignore"):
                ratios.append(np.where(traction > 0.0, traction / S, 0.0))
        ratios = np.stack(ratios)
        return ratios.max(axis=0) if combine == "max" else np.sqrt(np.sum(ratios**2, axis=0))

    def _solve_group(self, modes, combine, d_old, delta_old, h, rs, rt, derivatives: bool = True):
        """Damage of a group after the step and, where it grew, the derivatives ``df/dd``, ``df/de_i``."""
        grows = self._ratio(d_old, modes, combine, delta_old, h, rs, rt) > 1.0
        d = d_old.copy()
        dfdd = np.ones_like(d)
        dfde = [np.zeros_like(d) for _ in modes]
        if not np.any(grows):
            return d, grows, dfdd, dfde
        sub = [(drive[grows], modulus, mode_I, columns) for drive, modulus, mode_I, columns in modes]
        args = (delta_old[grows], h[grows], rs[grows], rt[grows])
        ratio = lambda d_, modes_=sub: self._ratio(d_, modes_, combine, *args)    # noqa: E731
        low, high = d_old[grows].copy(), np.full(int(grows.sum()), self.d_max)
        g_low, g_high = ratio(low) - 1.0, ratio(high) - 1.0
        failed = g_high > 0.0
        d_new = np.where(failed, self.d_max, _bracketed_root(ratio, low, high, g_low, np.minimum(g_high, 0.0)))
        d[grows] = d_new
        if not derivatives:
            return d, grows, dfdd, dfde
        # implicit function f(d, e) = 1: centred differences of the closed-form ratio
        live = ~failed
        step = np.minimum(1e-7, 0.5 * (1.0 - d_new))
        with np.errstate(invalid="ignore"):
            dfdd_g = (ratio(d_new + step) - ratio(d_new - step)) / (2.0 * step)
            dfdd[grows] = np.where(live, dfdd_g, 1.0)
            for k, (drive, modulus, mode_I, columns) in enumerate(sub):
                de = 1e-7 * np.abs(drive) + 1e-14
                plus = [m if j != k else (drive + de, modulus, mode_I, columns) for j, m in enumerate(sub)]
                minus = [m if j != k else (drive - de, modulus, mode_I, columns) for j, m in enumerate(sub)]
                value = (ratio(d_new, plus) - ratio(d_new, minus)) / (2.0 * de)
                dfde[k][grows] = np.where(live & (drive > 0.0), value, 0.0)
        return d, grows, dfdd, dfde

    def _drives(self, local):
        """``e_n`` (normal opening strain, Eq. AD.3), ``g_1``, ``g_2`` (engineering shears) of local strains."""
        return (local[:, 0] + self.nu_ratio * (local[:, 1] + local[:, 2]),
                _SQRT2 * local[:, 5], _SQRT2 * local[:, 4])

    def _damage(self, local, d_old, delta_old, h, rs, rt, derivatives: bool = True):
        """Damage (m, 3) and openings (m, 3) after a step to the local strains, with each group's derivatives."""
        e_n, g1, g2 = self._drives(local)
        d, delta = d_old.copy(), delta_old.copy()
        groups = []
        for modes, combine in self._groups(e_n, g1, g2):
            columns = sorted({c for *_, cols in modes for c in cols})
            d_group, grows, dfdd, dfde = self._solve_group(modes, combine, d_old[:, columns].max(axis=1),
                                                           delta_old, h, rs, rt, derivatives)
            for c in columns:
                d[:, c] = np.maximum(d_old[:, c], d_group)
            for drive, _, _, cols in modes:
                for c in cols:
                    delta[:, c] = np.maximum(delta_old[:, c], h * d_group * drive)
            groups.append((columns, grows, dfdd, dfde, modes))
        return d, delta, groups

    def _release_rates(self, local):
        """Energy release rates ``Y_n = C_11 <e_n>_+^2/2``, ``Y_1 = mu g_1^2/2``, ``Y_2 = mu g_2^2/2`` (3, m)."""
        e_n, g1, g2 = self._drives(local)
        return np.stack([0.5 * self.C11 * np.maximum(e_n, 0.0) ** 2, 0.5 * self.mu * g1**2, 0.5 * self.mu * g2**2])

    def _dissipated(self, local_old, local, d_old, d, delta_old, h, rs, rt):
        """``integral Y dd`` over the step, strain linear in the step: the damage is solved at s = 1/4, 1/2, 3/4
        as well and the rule is the composite trapezoid on those four intervals (error ~ 1/16 of one interval)."""
        grew = np.any(d > d_old, axis=1)
        gain = np.zeros((3, len(d)))
        if not np.any(grew):
            return gain
        a, b = local_old[grew], local[grew]
        args = (delta_old[grew], h[grew], rs[grew], rt[grew])
        ds = [d_old[grew]]
        Ys = [self._release_rates(a)]
        for s in (0.25, 0.5, 0.75):
            mid = a + s * (b - a)
            ds.append(self._damage(mid, d_old[grew], *args, derivatives=False)[0])
            Ys.append(self._release_rates(mid))
        ds.append(d[grew])
        Ys.append(self._release_rates(b))
        gain[:, grew] = sum(0.5 * (Ys[i] + Ys[i + 1]) * (ds[i + 1] - ds[i]).T for i in range(4))
        return gain

    # ---- the update ------------------------------------------------------------------------------------------
    def update(self, state, eps, dt: float = 1.0, **loading) -> MaterialResponse:
        """Stress (AD.1), consistent tangent and new state (initiation, then the surface's damage return)."""
        eps = check_strain(eps)
        batch = eps.shape[:-1]
        n = int(np.prod(batch))
        flat = {key: np.broadcast_to(value, (*batch, *_TAILS[key])).reshape(n, *_TAILS[key]).copy()
                for key, value in state.items()}
        mech = np.broadcast_to(self._mechanical(eps), (*batch, 6)).reshape(n, 6)
        rs = np.broadcast_to(self.relative_strength, batch).reshape(n)
        rt = np.broadcast_to(self.relative_toughness, batch).reshape(n)
        initiated, axes, h = flat["initiated"], flat["axes"], flat["band_width"]
        fresh = np.flatnonzero(~initiated)
        if fresh.size:
            if self.crack_normal is None:
                cracks, new_axes = self.initiation(mech[fresh] @ self.stiffness, rs[fresh])
            else:
                normals = np.broadcast_to(self.crack_normal, (*batch, 3)).reshape(n, 3)[fresh]
                cracks, new_axes = self.initiation_on_plane(mech[fresh], normals, h[fresh], rs[fresh], rt[fresh])
            where = fresh[cracks]
            initiated[where], axes[where] = True, new_axes[cracks]
            if isinstance(self.band_width, ProjectedBandWidth) and where.size:
                width = self.band_width.width(new_axes[cracks][:, 0], where, batch)
                self.check_band_width(width, rs[where], rt[where])
                h[where] = width
        stress = mech @ self.stiffness
        tangent = np.broadcast_to(self.stiffness, (n, 6, 6)).copy()
        cracked = np.flatnonzero(initiated)
        if cracked.size:
            R = T.mandel_rotation(axes[cracked])
            old = np.broadcast_to(self._mechanical(state["eps"]), (*batch, 6)).reshape(n, 6)[cracked]
            local = np.einsum("mij,mj->mi", R, mech[cracked])
            local_old = np.einsum("mij,mj->mi", R, old)
            s_loc, t_loc, d_c, delta_c, gain = self._crack_response(
                local, local_old, flat["d"][cracked], flat["delta"][cracked], h[cracked], rs[cracked], rt[cracked])
            stress[cracked] = np.einsum("mji,mj->mi", R, s_loc)
            tangent[cracked] = np.einsum("mki,mkl,mlj->mij", R, t_loc, R)
            flat["d"][cracked], flat["delta"][cracked] = d_c, delta_c
            flat["dissipation_I"][cracked] += gain[0]
            flat["dissipation_II"][cracked] += gain[1]
        flat["eps"] = eps.reshape(n, 6).copy()
        new_state = {key: value.reshape((*batch, *_TAILS[key])) for key, value in flat.items()}
        return MaterialResponse(stress.reshape((*batch, 6)), tangent.reshape((*batch, 6, 6)), new_state)

    def _secant(self, local, d):
        """Stress (I - D) C eps and the secant (I - D) C in crack axes (Eq. AD.1, AD.2) for the damages ``d``
        (m, 3); d_n acts only while the crack is open. Also returns sigma_e = C eps, the opening flags and the
        Poisson row ``a`` of D."""
        C, a = self.stiffness, np.array([1.0, self.nu_ratio, self.nu_ratio, 0.0, 0.0, 0.0])
        sig_e = local @ C
        opened = self._drives(local)[0] > 0.0
        d_n = np.where(opened, d[:, 0], 0.0)
        stress = sig_e.copy()
        stress -= (d_n * sig_e[:, 0])[:, None] * a
        stress[:, 5] *= 1.0 - d[:, 1]
        stress[:, 4] *= 1.0 - d[:, 2]
        tangent = np.broadcast_to(C, (len(d), 6, 6)).copy()
        tangent -= d_n[:, None, None] * a[None, :, None] * C[0][None, None, :]
        tangent[:, 5] *= (1.0 - d[:, 1])[:, None]
        tangent[:, 4] *= (1.0 - d[:, 2])[:, None]
        return stress, tangent, sig_e, opened, a

    def _crack_response(self, local, local_old, d_old, delta_old, h, rs, rt):
        """Stress, tangent, damage, openings and dissipation (mode I, mode II) in crack axes (all (m, ...))."""
        _, g1, g2 = self._drives(local)
        d, delta, groups = self._damage(local, d_old, delta_old, h, rs, rt)
        stress, tangent, sig_e, opened, a = self._secant(local, d)
        # consistent part: (d sigma/d d_k) (x) (dd/d eps) for the groups that damaged
        unit5, unit4 = np.eye(6)[5] * _SQRT2, np.eye(6)[4] * _SQRT2
        dsig_dd = {0: -np.where(opened, sig_e[:, 0], 0.0)[:, None] * a,
                   1: -sig_e[:, 5][:, None] * np.eye(6)[5], 2: -sig_e[:, 4][:, None] * np.eye(6)[4]}
        hyp = np.hypot(g1, g2)
        with np.errstate(invalid="ignore", divide="ignore"):
            d_drive = {(0,): np.where(opened, 1.0, 0.0)[:, None] * a,
                       (1,): np.sign(g1)[:, None] * unit5, (2,): np.sign(g2)[:, None] * unit4,
                       (1, 2): np.where(hyp[:, None] > 0.0,
                                        (g1[:, None] * unit5 + g2[:, None] * unit4) / hyp[:, None], 0.0)}
        for columns, grows, dfdd, dfde, modes in groups:
            if self.tangent == "secant" or not np.any(grows):
                continue
            dd_deps = -sum(dfde[k][:, None] * d_drive[cols] for k, (*_, cols) in enumerate(modes)) / dfdd[:, None]
            dd_deps[~grows] = 0.0
            for c in columns:
                tangent += dsig_dd[c][:, :, None] * dd_deps[:, None, :]
        gain = self._dissipated(local_old, local, d_old, d, delta_old, h, rs, rt)
        return stress, tangent, d, delta, (gain[0], gain[1] + gain[2])

    # ---- energies --------------------------------------------------------------------------------------------
    def stored_energy(self, state) -> np.ndarray:
        """``1/2 (eps - eps_res) : sigma`` (MPa): the secant energy of the damaged material, with the stress of the
        state's own damage (:meth:`_secant`; no update, so nothing initiates or grows)."""
        eps = np.asarray(state["eps"])
        batch = eps.shape[:-1]
        mech = np.broadcast_to(self._mechanical(eps), (*batch, 6)).reshape(-1, 6)
        stress = mech @ self.stiffness
        cracked = np.flatnonzero(np.reshape(state["initiated"], -1))
        if cracked.size:
            R = T.mandel_rotation(np.reshape(state["axes"], (-1, 3, 3))[cracked])
            local = np.einsum("mij,mj->mi", R, mech[cracked])
            local_stress = self._secant(local, np.reshape(state["d"], (-1, 3))[cracked])[0]
            stress[cracked] = np.einsum("mji,mj->mi", R, local_stress)
        return 0.5 * np.sum(mech * stress, axis=-1).reshape(batch)

    def dissipation(self, state) -> np.ndarray:
        """Energy dissipated per volume so far (MPa), mode I plus mode II."""
        return state["dissipation_I"] + state["dissipation_II"]
