"""What a scratch run records after every converged increment: forces, the volume audit, fields.

:class:`ScratchRecorder` is the ``on_step`` callback of the scratch's solver. Per increment it commits the contact
history, appends one row to ``forces.csv`` (flushed at once, so an interrupted run keeps every finished increment)
with the contact resultants and the :mod:`~abrakit.scratch.budget` volume audit, and writes the fields to the VTU
series every ``vtu_every`` increments. Units: N, mm, mm² and mm³ (whole grain).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from abrakit.fem.output import cell_fields, meshio_cells
from abrakit.io import CurveWriter, VtuSeries
from abrakit.scratch.budget import BoundaryFaces, VolumeBudget, volume_budget
from abrakit.validation import number_arguments

PHASES = {"indentation": 0, "scratching": 1, "unloading": 2}
BUDGET_COLUMNS = tuple(f"V_{name}" for name in VolumeBudget._fields)
"""Volume audit per increment, mm³ (whole grain): V_groove, V_shoulders, V_prow, V_sink, V_faces,
V_volume_change (∫(J − 1) dV_0), V_residual (the closure, round-off) and V_removed (elements at the damage
cap)."""
CURVE_COLUMNS = ("step", "tau", "phase", "tip_y", "tip_z", "slide", "normal_force", "tangential_force",
                 "contact_area", "max_penetration", "closed_nodes", "slipping_nodes", "iterations",
                 "wall_time") + BUDGET_COLUMNS


class ScratchRecorder:
    """``on_step`` callback of a scratch run (see the module docstring).

    path: the :class:`~abrakit.scratch.ScratchPath`; contact: the :class:`~abrakit.scratch.IndenterContact`;
    kinematics: the solver's kinematics; output: directory or None; vtu_every: field output interval (0: none);
    extra_fields: ``f(state) -> {name: (nel,) array}`` added to the VTU cell data (e.g. the effective damage);
    removed: ``f(state) -> (nel,) bool``, the elements counted as removed in the volume audit (damage runs).
    """

    def __init__(self, path, contact, kinematics, *, output=None, vtu_every: int = 10, extra_fields=None,
                 removed=None):
        self.path = path
        self.contact = contact
        self.kin = kinematics
        self.mesh = kinematics.basis.mesh
        self.faces = BoundaryFaces(self.mesh)
        self.extra_fields = extra_fields
        self.removed = removed
        self.removed_mask: np.ndarray | None = None       # the elements removed at the last audit
        self.rows: list[dict] = []
        self.budget: VolumeBudget | None = None
        self.t_start = time.perf_counter()
        out = Path(output) if output is not None else None
        self.curves_file = CurveWriter(out / "forces.csv", CURVE_COLUMNS) if out is not None else None
        self.vtu_every = vtu_every if out is not None else 0
        self.vtu = VtuSeries(out / "fields", stem="step") if self.vtu_every else None
        self._cells = meshio_cells(self.mesh) if self.vtu is not None else None
        self._last_fields = None

    def budget_at(self, u: np.ndarray, tau: float, state=None) -> VolumeBudget:
        """Volume audit of ``u`` split at the apex position of pseudo-time ``tau`` (with the removed elements of
        ``state`` where the run counts removal)."""
        tip = self.path.position(tau)
        removed = self.removed(state) if self.removed is not None and state is not None else None
        self.removed_mask = removed
        return volume_budget(self.faces, self.kin, self.mesh.p, u, float(tip[2]),
                             symmetry_factor=self.contact.symmetry_factor, removed=removed)

    def __call__(self, result) -> None:
        self.contact.on_step(result)
        tau = float(result.load_factors[-1])
        tip = self.path.position(tau)
        f = self.contact.forces
        self.budget = self.budget_at(result.u, tau, result.state)
        row = {"step": len(self.rows) + 1, "tau": tau, "phase": PHASES[self.path.phase(tau)],
               "tip_y": float(tip[1]), "tip_z": float(tip[2]), "slide": float(tip[2] - self.path.z_start),
               "normal_force": f.normal, "tangential_force": f.tangential, "contact_area": f.area,
               "max_penetration": f.max_penetration, "closed_nodes": f.closed, "slipping_nodes": f.slipping,
               "iterations": int(result.iterations[-1]), "wall_time": time.perf_counter() - self.t_start}
        row |= {f"V_{k}": v for k, v in self.budget._asdict().items()}
        self.rows.append(row)
        if self.curves_file is not None:
            self.curves_file.write(**row)
        if self.vtu is not None and len(self.rows) % self.vtu_every == 0:
            self.write_fields(tau, result.u, result.response.stress, result.state)

    def write_fields(self, tau, u, stress, state) -> None:
        """Displacement, contact pressure and element fields at pseudo-time ``tau`` (once per ``tau``)."""
        if self.vtu is None or self._last_fields == tau:
            return
        fields = {k: v for k, v in cell_fields(stress, state).items() if np.ndim(v) == 1}
        if self.extra_fields is not None:
            fields |= self.extra_fields(state)
        nodal = np.asarray(self.kin.basis.nodal_dofs)
        self.vtu.write(tau, self.mesh.p.T, self._cells,
                       point_data={"displacement": u[nodal].T,
                                   "contact_pressure": self.contact.pressure_field(self.mesh.p.shape[1])},
                       cell_data={k: [v] for k, v in fields.items()})
        self._last_fields = tau

    def position(self) -> dict:
        """Where the record stands (JSON-able, for a checkpoint): its rows, the last volume audit, the VTU entries."""
        return {"rows": self.rows, "budget": None if self.budget is None else self.budget._asdict(),
                "vtu": VtuSeries.position(self.vtu),
                "last_fields": self._last_fields}

    def restart(self, position: dict) -> None:
        """Continue from a checkpoint's :meth:`position`: ``forces.csv`` is rewritten with exactly its rows, the VTU
        files of later increments are removed, and the wall-time column goes on from its last row."""
        self.rows = [dict(row) for row in position["rows"]]
        self.budget = None if position["budget"] is None else VolumeBudget(**position["budget"])
        if self.curves_file is not None:
            self.curves_file.rewrite(self.rows)
        if self.vtu is not None:
            self.vtu.restart(position["vtu"])
        self._last_fields = position["last_fields"]
        self.t_start = time.perf_counter() - (self.rows[-1]["wall_time"] if self.rows else 0.0)

    def curves(self) -> dict[str, np.ndarray]:
        return {k: np.array([r[k] for r in self.rows]) for k in CURVE_COLUMNS}

    def close(self) -> None:
        if self.curves_file is not None:
            self.curves_file.close()


@number_arguments
def slide_mean(slide: ArrayLike, values: ArrayLike) -> float:
    """Mean of ``values`` over the slide distance, ∫ v dz / Δz by the trapezoidal rule over the increments' slide
    positions ``slide`` (NaN if empty, the value itself for one increment).

    Why not the mean over increments: a cutback puts several short increments where the step was hard, and the
    per-increment mean weighs that stretch of the groove by their number. Measured on a small plastic scene whose
    runs differ only in round-off (compiled against NumPy internal forces): one run cut back twice, the other not;
    their per-increment mean normal forces lay 2.7 % apart, their slide means 0.6 % (tangential 5 % and 0.8 %)."""
    slide = np.asarray(slide, dtype=float)
    values = np.asarray(values, dtype=float)
    if slide.shape != values.shape or slide.ndim != 1:
        raise ValueError(f"slide and values must be 1D arrays of one shape, got {slide.shape} and {values.shape}")
    if slide.size == 0:
        return float("nan")
    if slide.size == 1 or slide[-1] == slide[0]:
        return float(np.mean(values))
    return float(np.trapezoid(values, slide) / (slide[-1] - slide[0]))
