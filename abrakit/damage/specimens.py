"""The three boundary value problems of Ch. 7, ready for Model I and Model II, at three mesh levels.

- :func:`plate_with_hole_specimen` — quarter of a plate with a central hole pulled at its top edge (Ch. 7.1.1);
- :func:`double_notched` — strip with two asymmetric edge notches, bottom clamped, top pulled (Ch. 7.1.2, 7.2.2);
- :func:`sharp_notch` — half of the 50 x 40 mm specimen with a 25 mm sharp horizontal notch (Ch. 7.2.1).

Each takes a mesh ``level``: ``"coarse"``, ``"medium"``, ``"fine"`` (about 1000, 4000 and 8000 elements, the
seed's 900-1010 / 4033-4080 / 8014-8477) or an integer element target, and returns a :class:`DamageSpecimen` with the
mesh, the displacement basis, the Dirichlet conditions as functions of the load factor, the name of the loaded
boundary (its reaction is the force of the force–displacement curve) and the prescribed displacement at load
factor 1. Every mesh is refined where the damage band goes.

**Plane strain, forces for a 3 mm plate.** The seed's specimens are 3 mm plates modelled with one 3D element
through the thickness, i.e. essentially plane stress. The finite element core of abrakit is plane strain (the
material models are 3D; plane stress would need a local iteration for eps_33 at every point, which no model
offers), so the default ``formulation="plane_strain"`` solves per mm of thickness and multiplies forces and
works by ``thickness = 3 mm`` (``force_scale``). This matters for Model II: its rate limit ``alpha l_ext`` is in
1/(N mm) for the seed's 3 mm specimen. Plane strain constrains eps_33, so yield and damage start at somewhat
higher loads than in the seed's plates. ``formulation="extruded"`` builds the seed's discretisation instead
(one layer of trilinear hexahedra through the 3 mm, front face held in z, free back face: plane stress in effect)
for a check: the elastic plate is 1.12 times softer (about 1/(1 - nu^2)), and Model II on the double notch
(~300 elements, alpha = 0.005) peaks 12 % lower, at six times the cost.

**Dimensions** (the seed's Figures 7.1, 7.8, 7.14 are missing; these are choices, all in mm):

=================  =======================================================================================
plate with hole    plate 100 x 100, hole diameter 20 (quarter 50 x 50, R = 10); symmetry on x = 0 and y = 0;
                   top edge pulled by u (u_x free). The band runs along y = 0 from the hole to the right edge.
double notched     strip 50 x 100, notches 10 deep and 2 wide, the left one 10 above and the right one 10 below
                   mid-height (as ``abrakit.fem.meshes.double_notched_specimen``); bottom clamped, top pulled by u
                   with u_x = 0 (grips).
sharp notch        specimen 50 x 40 with a 25 mm notch from the left edge at mid-height; the upper half
                   50 x 20 is modelled, the ligament y = 0, x > 25 is the symmetry line (u_y = 0), the notch
                   faces are free; the top edge is pulled by u, free in x (u_x = 0 only at the ligament's
                   end (50, 0), against rigid-body motion; a clamped top edge draws spurious damage
                   bands to its corner).
=================  =======================================================================================

For the band-width metric, ``band_mirror = 2`` says the band lies on a symmetry line (the modelled part holds
half of it), and ``band_length`` is its nominal length (ligament), ``None`` where it is measured from the field.

:func:`abrakit.damage.runs.run_specimen` loads a specimen with either model and returns the same record for both;
:func:`plot_field` draws an element field on the whole specimen (quarter and half models mirrored).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import skfem

from ..fem import Dirichlet, meshes, vector_basis
from ..fem.boundary import node_row_dofs
from ..validation import check_finite, check_option, check_positive, check_range, number_arguments

#: Element targets of the named mesh levels (the seed: 900-1010, 4033-4080, 8014-8477 elements).
LEVELS = {"coarse": 1000, "medium": 4000, "fine": 8000}
FORMULATIONS = ("plane_strain", "extruded")
THICKNESS = 3.0  # mm, all three specimens (Ch. 7)
_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class DamageSpecimen:
    """A ready boundary value problem: mesh, basis, Dirichlet conditions and what to measure.

    ``dirichlet``: conditions as functions of the load factor (the loaded one is named ``loaded``, so the solver
    records ``u_<loaded>`` and ``F_<loaded>``). ``displacement``: prescribed displacement of the loaded edge at
    load factor 1 (mm). ``force_scale``: factor from the solver's forces to the specimen's (N): the thickness in
    plane strain, 1 for the extruded 3D model. ``plane_mesh``: the 2D mesh (element ``e`` of the 3D mesh sits on
    element ``e`` of it). ``band_length`` (mm) / ``band_mirror``: see the module docstring.
    """

    name: str
    level: str
    mesh: skfem.Mesh
    basis: skfem.CellBasis
    dirichlet: tuple[Dirichlet, ...]
    loaded: str
    displacement: float
    formulation: str
    thickness: float
    plane_mesh: skfem.Mesh
    band_length: float | None
    band_mirror: int
    dimensions: dict = field(default_factory=dict)
    description: str = ""

    @property
    def force_scale(self) -> float:
        return self.thickness if self.formulation == "plane_strain" else 1.0

    @property
    def elements(self) -> int:
        return int(self.plane_mesh.t.shape[1])

    @property
    def loaded_dofs(self) -> np.ndarray:
        return next(c.dofs for c in self.dirichlet if c.name == self.loaded)

    def gauge(self, low: float, high: float) -> tuple[np.ndarray, np.ndarray]:
        """Extensometer between the heights ``low`` and ``high`` (mm): the y-DOFs of the node rows nearest to them,
        (upper, lower), for the opening control of :class:`~abrakit.fem.PathFollowingSolver`."""
        rows = [node_row_dofs(self.basis, "y", height, "y") for height in (high, low)]
        if rows[0].size == 0 or rows[1].size == 0 or np.intersect1d(*rows).size:
            raise ValueError(f"gauge: low = {low} and high = {high} mm must pick two different node rows")
        return rows[0], rows[1]

    def summary(self) -> str:
        return (f"{self.name} ({self.level}): {self.elements} elements, {self.basis.N} DOF, {self.formulation}, "
                f"t = {self.thickness:g} mm, u = {self.displacement:g} mm on '{self.loaded}'")


# ---- meshes refined along the damage band -------------------------------------------------------------------------
@number_arguments
def plate_with_hole_mesh(n_angular: int, n_radial: int, *, width: float = 50.0, height: float = 50.0,
                         radius: float = 10.0, angular_grading: float = 8.0, radial_grading: float = 2.0):
    """Quarter plate with a hole, rays from the hole to the outer edges, refined towards the ligament y = 0.

    As :func:`abrakit.fem.meshes.plate_with_hole`, but the ray angles are graded geometrically from theta = 0
    (``angular_grading`` = largest / smallest angle step), so that the band along y = 0 is resolved, and the ray
    through the corner (width, height) is kept. Boundaries: ``hole``, ``left``, ``bottom``, ``right``, ``top``.
    """
    width, height = check_positive("width", width), check_positive("height", height)
    radius = check_range("radius", radius, 0.0, min(width, height), low_open=True, high_open=True)
    n_angular = int(check_range("n_angular", n_angular, 2, None))
    corner = np.arctan2(height, width)
    theta = (np.pi / 2) * meshes.graded(n_angular, angular_grading)
    k = int(np.clip(np.argmin(np.abs(theta - corner)), 1, n_angular - 1))
    theta[k] = corner  # the corner must be a ray: the outer boundary kinks there
    return meshes.plate_with_hole(width, height, radius, n_radial=int(check_range("n_radial", n_radial, 1, None)),
                                  grading=radial_grading, angles=theta)


@number_arguments
def sharp_notch_mesh(n_x: int, n_y: int, *, width: float = 50.0, height: float = 40.0, notch: float = 25.0,
                     grading_y: float = 8.0, grading_left: float = 4.0, grading_right: float = 2.0):
    """Upper half ``[0, width] x [0, height/2]`` of the sharp-notch specimen, refined along the ligament.

    x: finest at the notch tip, coarsening by ``grading_left`` towards the free left end and only by
    ``grading_right`` along the ligament (where the band runs); y: finest at the ligament, coarsening by
    ``grading_y`` towards the grip. ``n_x`` elements in x (split in proportion 3 : 7 between notch and
    ligament sides), ``n_y`` in y. Boundaries: ``notch``, ``ligament``, ``top``, ``left``, ``right``.
    """
    width, height = check_positive("width", width), check_positive("height", height)
    notch = check_range("notch", notch, 0.0, width, low_open=True, high_open=True)
    n_x = int(check_range("n_x", n_x, 4, None))
    n_left = max(1, int(round(0.3 * n_x)))
    left = notch - notch * meshes.graded(n_left, grading_left)[::-1]
    right = notch + (width - notch) * meshes.graded(n_x - n_left, grading_right)
    xs = np.concatenate((left, right[1:]))
    ys = (height / 2) * meshes.graded(int(check_range("n_y", n_y, 1, None)), grading_y)
    mesh = skfem.MeshQuad.init_tensor(xs, ys)
    return mesh.with_boundaries({
        "notch": lambda x: (x[1] < _TOL * height) & (x[0] < notch),
        "ligament": lambda x: (x[1] < _TOL * height) & (x[0] > notch),
        "top": lambda x: x[1] > height / 2 * (1 - _TOL),
        "left": lambda x: x[0] < _TOL * width,
        "right": lambda x: x[0] > width * (1 - _TOL),
    })


@number_arguments
def double_notched_mesh(h: float, *, width: float = 50.0, height: float = 100.0, notch_depth: float = 10.0,
                        notch_width: float = 2.0, offset: float = 10.0, margin: float = 10.0, growth: float = 1.25):
    """Strip ``width`` x ``height`` with two rectangular edge notches at mid-height +/- ``offset``, refined between.

    Same geometry and boundary names as :func:`abrakit.fem.meshes.double_notched_specimen` (``bottom``,
    ``top``, ``left``, ``right``, ``notches``), but every grid line is placed so that the notch edges are grid
    lines and no sliver elements appear: squares of size about ``h`` over the full width in the band from
    ``margin`` below the lower notch to ``margin`` above the upper one, element heights growing by ``growth``
    towards the clamped ends.
    """
    h = check_positive("h", h)
    check_range("notch_depth", notch_depth, 0.0, width / 2, low_open=True, high_open=True)
    mid, half = height / 2, notch_width / 2
    y_upper, y_lower = mid + offset, mid - offset
    band = (y_lower - half - margin, y_upper + half + margin)
    check_range("band", band[0], 0.0, None, low_open=True)

    def split(breaks):
        parts = [np.linspace(a, b, max(1, int(round((b - a) / h))) + 1)[:-1]
                 for a, b in zip(breaks[:-1], breaks[1:], strict=True)]
        return np.concatenate(parts + [[breaks[-1]]])

    def towards_end(length):  # from the band edge (size h) to the end, sizes growing by ``growth``
        sizes = [h]
        while sum(sizes) < length:
            sizes.append(sizes[-1] * growth)
        sizes = np.array(sizes) * length / sum(sizes)
        return np.concatenate(([0.0], np.cumsum(sizes)))

    ys_band = split([band[0], y_lower - half, y_lower + half, y_upper - half, y_upper + half, band[1]])
    ys = np.concatenate((band[0] - towards_end(band[0])[::-1], ys_band[1:-1],
                         band[1] + towards_end(height - band[1])))
    ys[0], ys[-1] = 0.0, height
    xs = split([0.0, notch_depth, width - notch_depth, width])
    mesh = skfem.MeshQuad.init_tensor(xs, ys)
    centre = mesh.p[:, mesh.t].mean(axis=1)
    notches = [(0.0, notch_depth, y_upper - half, y_upper + half),
               (width - notch_depth, width, y_lower - half, y_lower + half)]
    keep = np.ones(mesh.t.shape[1], dtype=bool)
    for x0, x1, y0, y1 in notches:
        keep &= ~((centre[0] > x0) & (centre[0] < x1) & (centre[1] > y0) & (centre[1] < y1))
    used, t = np.unique(mesh.t[:, keep], return_inverse=True)
    mesh = skfem.MeshQuad(np.ascontiguousarray(mesh.p[:, used]), np.ascontiguousarray(t.reshape(4, -1)))

    def in_notch(x):
        return np.any([(x[0] >= a - _TOL) & (x[0] <= b + _TOL) & (x[1] >= c - _TOL) & (x[1] <= d + _TOL)
                       for a, b, c, d in notches], axis=0)

    return mesh.with_boundaries({
        "bottom": lambda x: x[1] < _TOL * height,
        "top": lambda x: x[1] > height * (1 - _TOL),
        "notches": in_notch,
        "left": lambda x: (x[0] < _TOL * width) & ~in_notch(x),
        "right": lambda x: (x[0] > width * (1 - _TOL)) & ~in_notch(x),
    })


# ---- element targets -> mesh parameters -------------------------------------------------------------------------
def _target(level) -> tuple[str, int]:
    if isinstance(level, str):
        check_option("level", level, tuple(LEVELS))
        return level, LEVELS[level]
    if isinstance(level, bool) or not isinstance(level, int | np.integer):
        raise TypeError(f"level must be one of {tuple(LEVELS)} or an element count (int), got {level!r}")
    n = int(check_range("level", level, 50, 200_000))
    return f"{n} elements", n


def _closest(count, target: int, lo: float, hi: float) -> float:
    """Scale s in [lo, hi] whose mesh ``count(s)`` is closest to ``target`` (counts grow with s)."""
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if count(mid) < target:
            lo = mid
        else:
            hi = mid
    return lo if abs(count(lo) - target) <= abs(count(hi) - target) else hi


@lru_cache(maxsize=32)
def _double_notch_h(target: int) -> float:
    def count(log_inv_h):
        return double_notched_mesh(float(np.exp(-log_inv_h))).t.shape[1]
    return float(np.exp(-_closest(count, target, np.log(1 / 8.0), np.log(1 / 0.2))))


def _scaled(base: tuple[int, int], target: int) -> tuple[int, int]:
    s = np.sqrt(target / (base[0] * base[1]))
    return max(2, int(round(base[0] * s))), max(1, int(round(base[1] * s)))


# ---- assembling a specimen --------------------------------------------------------------------------------------
def _finish(name, level, plane_mesh, conditions, loaded, displacement, formulation, band_length, band_mirror,
            dimensions, description) -> DamageSpecimen:
    check_option("formulation", formulation, FORMULATIONS)
    displacement = check_positive("displacement", displacement)
    mesh = plane_mesh if formulation == "plane_strain" else meshes.extrude(plane_mesh, THICKNESS, 1)
    basis = vector_basis(mesh)
    bcs = []
    for boundary, comps, value in conditions:
        if isinstance(boundary, tuple):  # a point (x, y): hold the nearest node, against rigid-body motion
            distance = np.linalg.norm(mesh.p[:2].T - np.asarray(boundary), axis=1)
            nodes = np.flatnonzero(distance <= distance.min() + 1e-9)  # one node, or a column in 3D
            dofs = np.asarray(basis.nodal_dofs)[["xyz".index(c) for c in comps]][:, nodes]
            bcs.append(Dirichlet(dofs, value))
        else:
            bcs.append(Dirichlet.on(basis, boundary, comps, value,
                                    name=(loaded if boundary == loaded and value else "")))
    if formulation == "extruded":
        bcs.insert(0, Dirichlet.on(basis, "front", "z"))
    return DamageSpecimen(name, level, mesh, basis, tuple(bcs), loaded, displacement, formulation, THICKNESS,
                          plane_mesh, band_length, band_mirror, dimensions, description)


def plate_with_hole_specimen(level="coarse", *, displacement: float = 0.12,
                             formulation: str = "plane_strain") -> DamageSpecimen:
    """Quarter plate 50 x 50 mm with a hole of radius 10 mm (plate 100 x 100, Ch. 7.1.1), top edge pulled.

    Mesh: rays graded towards the ligament y = 0 (40 x 25 elements for 1000). Symmetry ``left`` (u_x = 0) and
    ``bottom`` (u_y = 0); ``top`` moves by ``displacement`` in y, free in x.
    """
    label, target = _target(level)
    n_angular, n_radial = _scaled((40, 25), target)
    mesh = plate_with_hole_mesh(n_angular, n_radial)
    conditions = [("left", "x", 0.0), ("bottom", "y", 0.0), ("top", "y", displacement)]
    return _finish("plate_with_hole", label, mesh, conditions, "top", displacement, formulation, 40.0, 2,
                   {"width": 100.0, "height": 100.0, "hole_diameter": 20.0, "model": "quarter 50 x 50"},
                   "plate 100 x 100 mm with a 20 mm hole, quarter model, pulled at the top edge")


def double_notched(level="coarse", *, displacement: float = 0.3, formulation: str = "plane_strain",
                   offset: float = 10.0) -> DamageSpecimen:
    """Strip 50 x 100 mm with asymmetric edge notches (10 mm deep, 2 mm wide, +/-``offset`` off mid-height).

    Mesh: :func:`double_notched_mesh`, squares of size ``h`` in the band 10 mm beyond the notches, graded
    towards the ends; ``h`` is chosen for the element target (at the default offset). ``bottom``
    clamped; ``top`` moves by ``displacement`` in y with u_x = 0. The seed's figure with the dimensions is
    missing; ``offset`` = 10 mm is our reconstruction, and the band shape of Model I depends on it relative to
    the regularisation length (see the chapter "Comparing the models").
    """
    label, target = _target(level)
    offset = check_range("offset", offset, 1.0, 35.0)
    h = _double_notch_h(target)
    mesh = double_notched_mesh(h, offset=offset)
    conditions = [("bottom", "xy", 0.0), ("top", "x", 0.0), ("top", "y", displacement)]
    return _finish("double_notched", label, mesh, conditions, "top", displacement, formulation, None, 1,
                   {"width": 50.0, "height": 100.0, "notch_depth": 10.0, "notch_width": 2.0, "offset": offset,
                    "h": h},
                   f"strip 50 x 100 mm, notches 10 x 2 mm at mid-height +/- {offset:g} mm, bottom clamped, top pulled")


def sharp_notch(level="coarse", *, displacement: float = 0.1, formulation: str = "plane_strain") -> DamageSpecimen:
    """Upper half of the 50 x 40 mm specimen with a 25 mm sharp notch (Ch. 7.2.1), top edge pulled.

    Mesh: :func:`sharp_notch_mesh` (40 x 25 elements for 1000). ``ligament`` u_y = 0 (symmetry), notch faces
    free, ``top`` moves by ``displacement`` in y, free in x (u_x = 0 at the node (50, 0) only); the full
    specimen opens by twice ``displacement``.
    """
    label, target = _target(level)
    n_x, n_y = _scaled((40, 25), target)
    mesh = sharp_notch_mesh(n_x, n_y)
    conditions = [("ligament", "y", 0.0), ((50.0, 0.0), "x", 0.0), ("top", "y", displacement)]
    return _finish("sharp_notch", label, mesh, conditions, "top", displacement, formulation, 25.0, 2,
                   {"width": 50.0, "height": 40.0, "notch": 25.0, "model": "upper half 50 x 20"},
                   "specimen 50 x 40 mm with a 25 mm sharp notch, half model, pulled at the top edge")


#: The three problems by name.
SPECIMENS = {"plate_with_hole": plate_with_hole_specimen, "double_notched": double_notched, "sharp_notch": sharp_notch}


def specimen(name: str, level="coarse", **options) -> DamageSpecimen:
    """``SPECIMENS[name](level, **options)`` with a clear message for unknown names."""
    check_option("name", name, tuple(SPECIMENS))
    return SPECIMENS[name](level, **options)


# ---- pictures ---------------------------------------------------------------------------------------------------
def _mirrors(specimen: DamageSpecimen) -> list[tuple[float, float]]:
    """Reflections (sx, sy) that complete the modelled part to the whole specimen."""
    if specimen.name == "plate_with_hole":
        return [(1, 1), (-1, 1), (1, -1), (-1, -1)]
    if specimen.name == "sharp_notch":
        return [(1, 1), (1, -1)]
    return [(1, 1)]


def plot_field(specimen: DamageSpecimen, values, ax=None, *, whole: bool = True, edges: bool = False, colorbar=True,
               label: str = "", **style):
    """Element field ``values`` (one per element of ``specimen.plane_mesh``) as coloured polygons.

    ``whole=True`` mirrors quarter/half models to the whole specimen. ``style`` goes to
    :class:`matplotlib.collections.PolyCollection` (e.g. ``cmap``, ``vmin``/``clim``). Returns the axes.
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    mesh = specimen.plane_mesh
    values = np.asarray(check_finite("values", values), dtype=float)
    if values.shape != (mesh.t.shape[1],):
        raise ValueError(f"values must have one entry per element ({mesh.t.shape[1]}), got shape {values.shape}")
    ax = ax if ax is not None else plt.gca()
    polygons = mesh.p[:, mesh.t].transpose(2, 1, 0)  # (nel, corners, 2)
    style.setdefault("cmap", "inferno_r")
    collection = None
    for sx, sy in (_mirrors(specimen) if whole else [(1, 1)]):
        collection = PolyCollection(polygons * np.array([sx, sy]), array=values,
                                    edgecolors="k" if edges else "face", linewidths=0.1 if edges else 0.05,
                                    **style)
        ax.add_collection(collection)
    ax.autoscale_view()
    ax.set_aspect("equal")
    if colorbar and collection is not None:
        ax.figure.colorbar(collection, ax=ax, label=label, shrink=0.8)
    return ax
