"""Results written as a run goes: curves (CSV), fields (VTU time series + ParaView .pvd), checkpoints (.npz).

Field output per step: the displacement at the nodes, and per element the quadrature-point averages of the
stress tensor components (MPa), the von Mises stress and every scalar or vector state variable of the material;
crack axes (state ``"axes"``, rows n, t1, t2 per point) are written as the element's ``crack_normal``.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from .. import tensors as T
from ..io import CurveWriter, VtuSeries, dumps, loads, write_atomically
from ..validation import check_finite

SQRT2 = np.sqrt(2.0)
_MESHIO_TYPE = {"MeshQuad1": "quad", "MeshTri1": "triangle", "MeshHex1": "hexahedron", "MeshTet1": "tetra"}
_TENSOR_NAMES = ("xx", "yy", "zz", "yz", "xz", "xy")


def meshio_cells(mesh):
    """``[(cell_type, connectivity)]`` of a linear scikit-fem mesh in VTK node order."""
    name = type(mesh).__name__
    if name not in _MESHIO_TYPE:
        raise TypeError(f"field output supports {tuple(_MESHIO_TYPE)}, got {name}")
    t = mesh.t
    if name == "MeshHex1":
        from skfem.io.meshio import HEX_MAPPING

        t = t[HEX_MAPPING[:8]]
    return [(_MESHIO_TYPE[name], t.T)]


#: State variables stored as Mandel 6-vectors: written as full 3 × 3 tensors (9 components, row-major), which
#: ParaView labels XX, XY, ..., ZZ with the true shear values (a 6-component array would be read as its symmetric
#: tensor in the order XX, YY, ZZ, XY, YZ, XZ, which is not the Mandel order, and with the √2 left in the shears).
MANDEL_STATE = ("eps", "eps_p", "eps_e", "cauchy")


def cell_fields(stress: np.ndarray, state: dict) -> dict:
    """Element averages of the Mandel stress (as tensor components), von Mises stress and state variables
    (Mandel ones as 3 × 3 tensors, :data:`MANDEL_STATE`).

    Finite-strain models return P (9 components); their Cauchy stress ``state["cauchy"]`` is written instead."""
    stress = check_finite("stress", stress)
    if stress.shape[-1] != 6:
        stress = state["cauchy"]
    mean = stress.mean(axis=1)
    fields = {f"stress_{n}": mean[:, i] / (SQRT2 if i > 2 else 1.0) for i, n in enumerate(_TENSOR_NAMES)}
    dev = mean - (mean[:, :3].sum(axis=1) / 3.0)[:, None] * np.array([1, 1, 1, 0, 0, 0])
    fields["von_mises"] = np.sqrt(1.5 * np.sum(dev**2, axis=1))
    nel, nqp = stress.shape[:2]
    for name, value in state.items():
        value = np.asarray(value)
        if name == "axes" and value.shape[:2] == (nel, nqp) and value.shape[2:] == (3, 3):
            fields["crack_normal"] = value[:, 0, 0, :]         # crack axes (rows n, t1, t2): the first point's normal
        elif value.shape[:2] == (nel, nqp) and value.ndim <= 3 and name != "cauchy":
            mean_value = value.mean(axis=1)
            fields[name] = T.from_mandel(mean_value).reshape(nel, 9) \
                if name in MANDEL_STATE and value.shape[-1] == 6 else mean_value
        elif value.shape[:1] == (nel,) and value.ndim <= 2:
            fields[name] = value
    return fields


def save_checkpoint(path, u, state, load_factor: float, time: float, *, arrays: dict | None = None,
                    meta: dict | None = None) -> Path:
    """Write the last converged state so a run can be inspected or restarted (:func:`load_checkpoint`); atomically,
    so an interruption leaves the previous checkpoint whole. ``arrays`` (name -> array) and ``meta`` (JSON-able:
    the run's history and step control) are what a resumed run needs beyond ``u`` and the material state."""
    fields = {f"state__{k}": np.asarray(v) for k, v in state.items()}
    fields.update({f"extra__{k}": np.asarray(v) for k, v in (arrays or {}).items()})
    buffer = io.BytesIO()
    np.savez(buffer, u=u, load_factor=load_factor, time=time, meta=np.array(dumps(meta or {})),
             **fields)
    return write_atomically(path, buffer.getvalue())


def load_checkpoint(path) -> dict:
    """``{"u", "state", "load_factor", "time", "arrays", "meta"}`` from :func:`save_checkpoint`."""
    with np.load(path) as data:
        def prefixed(prefix):
            return {k.removeprefix(prefix): data[k] for k in data.files if k.startswith(prefix)}

        meta = loads(str(data["meta"])) if "meta" in data.files else {}
        return {"u": data["u"], "state": prefixed("state__"), "load_factor": float(data["load_factor"]),
                "time": float(data["time"]), "arrays": prefixed("extra__"), "meta": meta}


def load_matching_checkpoint(path, fingerprint: dict, run: str = "problem") -> dict | None:
    """:func:`load_checkpoint` of ``path`` for resuming a run whose ``fingerprint`` (what it must match: sizes,
    parameters) is given; ``None`` if there is no checkpoint. A checkpoint of another ``run`` (another
    fingerprint, or none: written by an older version) is refused by name, never resumed."""
    path = Path(path)
    if not path.exists():
        return None
    saved = load_checkpoint(path)
    found = saved["meta"].get("fingerprint")
    if found != fingerprint:
        raise ValueError(f"resume: the checkpoint {path} belongs to another {run} ({found} != {fingerprint}); "
                         "delete it or choose another output")
    return saved


class RunWriter:
    """Curves CSV (one row per converged step), VTU series every ``vtu_every`` steps, checkpoint on demand.

    :meth:`restart` takes a run up again from a checkpoint's rows: ``curves.csv`` is rewritten with exactly those
    rows and the VTU files of later steps (written before the interruption, to be recomputed) are removed."""

    CHECKPOINT = "last_converged.npz"

    def __init__(self, directory, mesh, curve_columns, vtu_every: int = 1):
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.mesh = mesh
        self.columns = list(curve_columns)
        self.curves = CurveWriter(self.directory / "curves.csv", self.columns)
        self.vtu = VtuSeries(self.directory / "fields", stem="step") if vtu_every else None
        self.vtu_every = vtu_every
        self._cells = meshio_cells(mesh) if vtu_every else None
        self._points = np.vstack([mesh.p, np.zeros((3 - mesh.dim(), mesh.p.shape[1]))]).T
        self._count = 0

    @property
    def checkpoint_path(self) -> Path:
        return self.directory / self.CHECKPOINT

    def write_step(self, row: dict, time: float, u: np.ndarray, nodal_dofs: np.ndarray, stress, state) -> None:
        self.curves.write(**row)
        if self.vtu is not None and self._count % self.vtu_every == 0:
            disp = np.zeros((self.mesh.p.shape[1], 3))
            disp[:, : nodal_dofs.shape[0]] = u[nodal_dofs].T
            self.vtu.write(time, self._points, self._cells, point_data={"displacement": disp},
                           cell_data={k: [v] for k, v in cell_fields(stress, state).items()})
        self._count += 1

    def position(self) -> dict:
        """Where the output stands (for a checkpoint): steps written and the VTU series' entries."""
        return {"count": self._count, "vtu": VtuSeries.position(self.vtu)}

    def restart(self, rows: list[dict], position: dict) -> None:
        """Continue the output of a run from a checkpoint: ``rows`` become ``curves.csv`` and the VTU series goes
        back to ``position`` (:meth:`position` when the checkpoint was written)."""
        self.curves.rewrite(rows)
        self._count = int(position["count"])
        if self.vtu is not None:
            self.vtu.restart(position["vtu"])

    def checkpoint(self, u, state, load_factor: float, time: float, *, arrays=None, meta=None) -> Path:
        return save_checkpoint(self.checkpoint_path, u, state, load_factor, time, arrays=arrays,
                               meta={**(meta or {}), "output": self.position()})

    def close(self) -> None:
        self.curves.close()
