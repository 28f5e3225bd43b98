"""Results written as a run goes: particle snapshots as VTU (ParaView) and histories as CSV.

Both writers are callables ``writer(sim)`` to pass as ``Simulation.run(callback=..., every=...)``; combine several
with :func:`callbacks`.

- :class:`VtuWriter`: one ``.vtu`` per call through :class:`abrakit.io.VtuSeries` — particles as vertices with
  radius, velocity, angular velocity, clump id and contact count; force-carrying contacts as lines with their
  normal force (a force-chain picture). Open the ``.pvd`` index in ParaView and glyph the points by ``radius``.
- :class:`HistoryWriter`: one CSV row per call through :class:`abrakit.io.CurveWriter`, with named quantities
  (callables of the simulation).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from abrakit.dem.measure import contact_counts, coordination_number
from abrakit.io import CurveWriter, VtuSeries


class VtuWriter:
    """Write the particles (and force-carrying contacts) of ``sim`` to ``directory/stem_00000.vtu`` …"""

    def __init__(self, directory, stem: str = "particles", contacts: bool = True):
        self.series = VtuSeries(directory, stem)
        self.contacts = contacts

    def __call__(self, sim) -> None:
        p = sim.particles
        n = len(p)
        cells = [("vertex", np.arange(n).reshape(-1, 1))]
        cell_data = {"normal_force": [np.zeros(n)]}
        c = sim.contacts
        if self.contacts and c.fn is not None and len(c):
            t = c.touching
            if t.any():
                cells.append(("line", np.column_stack([c.i[t], c.j[t]])))
                cell_data["normal_force"].append(c.fn[t])
        point_data = {"radius": p.radius, "velocity": p.v, "angular_velocity": p.w,
                      "clump": p.clump.astype(float), "contacts": contact_counts(sim).astype(float)}
        self.series.write(sim.time, p.x, cells, point_data=point_data, cell_data=cell_data)


ENERGY_COLUMNS = ("kinetic", "elastic", "dissipated", "work")


def default_history(energy: bool = True) -> dict[str, Callable]:
    """time, step, dt, coordination number and, with ``energy``, kinetic/elastic/dissipated energy and work (a
    simulation keeps those only with ``track_energy=True``)."""
    history = {
        "time": lambda s: s.time,
        "step": lambda s: s.step_count,
        "dt": lambda s: s.dt,
        "kinetic": lambda s: s.energy.kinetic,
        "elastic": lambda s: s.energy.elastic,
        "dissipated": lambda s: s.energy.dissipated,
        "work": lambda s: s.energy.work,
        "coordination": coordination_number,
    }
    return history if energy else {k: f for k, f in history.items() if k not in ENERGY_COLUMNS}


class HistoryWriter:
    """Append one CSV row of ``quantities`` (name → callable(sim)) per call; flushed at once.

    The default quantities (:func:`default_history`) include the energies only when ``energy`` is true; a
    simulation without ``track_energy`` has none to record, and a writer asked for them refuses it at the first
    row rather than writing zeros."""

    def __init__(self, path, quantities: dict[str, Callable] | None = None, *, energy: bool = True):
        self.quantities = default_history(energy) if quantities is None else dict(quantities)
        self.writer = CurveWriter(path, list(self.quantities))
        self._checked = False

    def __call__(self, sim) -> None:
        if not self._checked:
            wanted = [k for k in ENERGY_COLUMNS if k in self.quantities]
            if wanted and not sim.track_energy:
                raise ValueError(f"HistoryWriter records {wanted} but the simulation has track_energy=False: "
                                 "use HistoryWriter(path, energy=False) or Simulation(track_energy=True)")
            self._checked = True
        self.writer.write(**{name: float(f(sim)) for name, f in self.quantities.items()})

    def close(self) -> None:
        self.writer.close()


def callbacks(*fns: Callable) -> Callable:
    """One callback that calls each of ``fns`` in turn."""
    def call(sim):
        for f in fns:
            f(sim)
    return call
