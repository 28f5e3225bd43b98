"""Result files written as a run goes, so an interrupted run loses nothing already computed.

- :class:`CurveWriter` appends one CSV row per step and flushes it at once; :class:`RunRecord` keeps a run's columns
  in memory and writes them through one.
- :func:`write_json` writes strict JSON (NaN and infinities as the strings "NaN", "Infinity", "-Infinity", which
  :func:`read_json` reads back as floats) atomically (temporary file, then rename); :func:`save_state` and
  :func:`load_state` pickle a run's state the same way, for resuming.
- :func:`progress_bar` is the one tqdm bar every long run shows.
- :class:`VtuSeries` writes one ``.vtu`` per step with meshio and keeps a ParaView ``.pvd`` index current.
"""

from __future__ import annotations

import csv
import hashlib
import inspect
import json
import os
import pickle
import tempfile
import types
from pathlib import Path

import numpy as np

__all__ = ["CurveWriter", "RunRecord", "VtuSeries", "dumps", "from_strict_json", "jsonable", "load_state", "loads",
           "progress_bar", "read_curve", "read_json", "save_state", "source_fingerprint", "strict_json",
           "write_atomically", "write_json"]

#: Non-finite floats in result files. JSON has no token for them (Python's ``NaN`` and ``Infinity`` are an extension
#: other readers refuse), so they are written as these strings, the mapping of Protocol Buffers' canonical JSON,
#: and :func:`read_json` turns them back into floats.
NON_FINITE = {"NaN": float("nan"), "Infinity": float("inf"), "-Infinity": float("-inf")}


def source_fingerprint(*sources) -> str:
    """A 16-digit hash of the source code of ``sources``: a package stands for every ``.py`` file in its directory, a
    module for its file, a function or class for its own source. Part of the key of a cached result (the graded
    beam sample, the compression specimens), so that an edit of the code that made it never serves it again: a
    version number kept by hand was once never raised, and a stale sample gave a beam 21 % weaker than the code's."""
    digest = hashlib.sha1()
    for source in sources:
        if isinstance(source, types.ModuleType):
            path = Path(source.__file__)
            files = sorted(path.parent.glob("*.py")) if path.name == "__init__.py" else [path]
            for file in files:
                digest.update(file.read_bytes())
        elif inspect.isfunction(source) or inspect.isclass(source):
            digest.update(inspect.getsource(source).encode())
        else:
            raise TypeError(f"sources must be modules, functions or classes, got {type(source).__name__}")
    return digest.hexdigest()[:16]


def jsonable(obj):
    """``obj`` with numpy arrays and scalars turned into lists and Python numbers, recursively."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def progress_bar(iterable=None, **kwargs):
    """A tqdm progress bar: the notebook widget where ipywidgets is installed, the text bar otherwise (tqdm.auto
    without ipywidgets warns "IProgress not found" into every notebook that imports it)."""
    try:
        import ipywidgets  # noqa: F401
        from tqdm.auto import tqdm
    except ImportError:
        from tqdm.std import tqdm
    return tqdm(iterable, **kwargs)


def write_atomically(path, payload: bytes) -> Path:
    """Write ``payload`` into a temporary file of a unique name beside ``path``, then rename it over ``path``: two
    processes writing the same file never mix their bytes (the last rename wins), a reader sees one whole version,
    and an interruption leaves the previous file intact."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("wb", dir=path.parent, prefix=f".{path.name}.", suffix=".tmp",
                                     delete=False) as handle:
        handle.write(payload)
    os.chmod(handle.name, 0o644)          # a temporary file is private (0600); a result file is not
    os.replace(handle.name, path)
    return path


def strict_json(data) -> object:
    """``data`` as strict JSON values: :func:`jsonable`, with NaN and ±inf as the strings of :data:`NON_FINITE`."""
    data = jsonable(data)
    if isinstance(data, float) and not np.isfinite(data):
        return "NaN" if np.isnan(data) else "Infinity" if data > 0 else "-Infinity"
    if isinstance(data, dict):
        return {k: strict_json(v) for k, v in data.items()}
    if isinstance(data, list):
        return [strict_json(v) for v in data]
    return data


def from_strict_json(data) -> object:
    """The inverse of :func:`strict_json`: the strings of :data:`NON_FINITE` become floats again."""
    if isinstance(data, str):
        return NON_FINITE.get(data, data)
    if isinstance(data, dict):
        return {k: from_strict_json(v) for k, v in data.items()}
    if isinstance(data, list):
        return [from_strict_json(v) for v in data]
    return data


def dumps(data, **options) -> str:
    """Strict JSON text of ``data`` (:func:`strict_json`; no ``NaN``/``Infinity`` tokens)."""
    return json.dumps(strict_json(data), allow_nan=False, **options)


def loads(text: str):
    """``data`` from :func:`dumps` text, non-finite numbers restored; the ``NaN`` tokens of older files are read
    too."""
    return from_strict_json(json.loads(text))


def write_json(path, data) -> Path:
    """Write ``data`` (dicts, lists, numpy values) as indented strict JSON (:func:`dumps`), atomically
    (:func:`write_atomically`)."""
    return write_atomically(path, dumps(data, indent=2).encode())


def save_state(path, state) -> Path:
    """Pickle a run's state (a simulation snapshot and its records) atomically, to resume it with
    :func:`load_state`. Only for files this toolkit wrote: unpickling runs code."""
    return write_atomically(path, pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL))


def load_state(path):
    """The state :func:`save_state` wrote, or ``None`` if ``path`` does not exist."""
    path = Path(path)
    return pickle.loads(path.read_bytes()) if path.exists() else None


def read_json(path):
    """What :func:`write_json` wrote to ``path``, NaN and infinities as floats (:func:`loads`)."""
    return loads(Path(path).read_text())


class CurveWriter:
    """Append-only CSV of named columns; every row is flushed to disk when written.

    >>> with CurveWriter("out/curve.csv", ["u", "F"]) as w:   # doctest: +SKIP
    ...     w.write(u=0.1, F=2.0)
    """

    def __init__(self, path, columns, *, append: bool = False):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.columns = list(columns)
        resume = append and self.path.exists() and self.path.stat().st_size > 0
        self._file = open(self.path, "a" if resume else "w", newline="")  # noqa: SIM115
        self._writer = csv.writer(self._file)
        if not resume:
            self._writer.writerow(self.columns)
            self._file.flush()

    def write(self, **values) -> None:
        missing = set(self.columns) - set(values)
        extra = set(values) - set(self.columns)
        if missing or extra:
            raise ValueError(f"CurveWriter row must have columns {self.columns}; missing {missing}, extra {extra}")
        self._writer.writerow([jsonable(values[c]) for c in self.columns])
        self._file.flush()

    def rewrite(self, rows) -> None:
        """Start the file again with the header and exactly ``rows`` (a resumed run goes back to its checkpoint)."""
        self._file.close()
        self._file = open(self.path, "w", newline="")  # noqa: SIM115
        self._writer = csv.writer(self._file)
        self._writer.writerow(self.columns)
        for row in rows:
            self.write(**row)
        self._file.flush()

    def close(self) -> None:
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class RunRecord:
    """Named columns of a run kept in memory and, with ``csv``, written row by row as they come (a
    :class:`CurveWriter`). ``rows`` (column -> list, e.g. from a checkpoint) are taken over and written first."""

    def __init__(self, columns, csv=None, rows=None):
        self.columns = tuple(columns)
        self.data = {c: [] for c in self.columns}
        self._writer = None if csv is None else CurveWriter(csv, self.columns)
        for values in zip(*(rows[c] for c in self.columns), strict=True) if rows else ():
            self.add(**dict(zip(self.columns, values, strict=True)))

    def add(self, **row) -> None:
        if set(row) != set(self.columns):
            raise ValueError(f"a row must have the columns {list(self.columns)}, got {sorted(row)}")
        for c in self.columns:
            self.data[c].append(row[c])
        if self._writer is not None:
            self._writer.write(**row)

    def __len__(self) -> int:
        return len(self.data[self.columns[0]])

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()

    def arrays(self) -> dict[str, np.ndarray]:
        return {c: np.array(v) for c, v in self.data.items()}


def read_curve(path) -> dict[str, np.ndarray]:
    """Read a :class:`CurveWriter` CSV back as a dict of float arrays."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], rows[1:]
    data = np.array(body, dtype=float).reshape(len(body), len(header))
    return {name: data[:, i] for i, name in enumerate(header)}


class VtuSeries:
    """A time series of meshio ``.vtu`` files plus a ParaView ``.pvd`` collection, rewritten after each step."""

    def __init__(self, directory, stem: str = "step"):
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.stem = stem
        self.entries: list[tuple[float, str]] = []

    def write(self, time: float, points, cells, point_data=None, cell_data=None) -> Path:
        """Write one step. ``cells`` is a list of ``(cell_type, connectivity)`` as meshio expects."""
        import meshio

        name = f"{self.stem}_{len(self.entries):05d}.vtu"
        mesh = meshio.Mesh(points, cells, point_data=point_data or {}, cell_data=cell_data or {})
        mesh.write(self.directory / name)
        self.entries.append((float(time), name))
        self._write_index()
        return self.directory / name

    def restart(self, entries: list[tuple[float, str]]) -> None:
        """Go back to ``entries`` (a shorter series written earlier): the ``.vtu`` files of later steps are deleted
        and the ``.pvd`` index is rewritten, so a resumed run recomputes those steps without stale files."""
        entries = [(float(t), str(name)) for t, name in entries]      # also the lists a JSON checkpoint holds
        keep = {name for _, name in entries}
        for path in self.directory.glob(f"{self.stem}_*.vtu"):
            if path.name not in keep:
                path.unlink()
        self.entries = entries
        self._write_index()

    @staticmethod
    def position(series: VtuSeries | None) -> list[list]:
        """The entries of ``series`` as JSON lists (``[]`` without a series): what a checkpoint keeps and
        :meth:`restart` takes back."""
        return [] if series is None else [list(e) for e in series.entries]

    def _write_index(self) -> None:
        lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "  <Collection>"]
        lines += [f'    <DataSet timestep="{t:.9g}" file="{f}"/>' for t, f in self.entries]
        lines += ["  </Collection>", "</VTKFile>", ""]
        write_atomically(self.directory / f"{self.stem}.pvd", "\n".join(lines).encode())
