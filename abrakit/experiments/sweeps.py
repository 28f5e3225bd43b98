"""Parameter sweeps that survive interruption: every case is written to its own JSON file the moment it finishes.

A sweep is a *case function* ``case_fn(params) -> dict`` and a list of parameter dicts::

    from abrakit.experiments import run_sweep

    def case(params):                       # any picklable function of one dict of JSON values
        return {"N_c_D2": ...}

    records = run_sweep(case, [{"ratio": r, "seed": s} for r in (1.5, 2, 3) for s in range(3)], "results/mix")
    records[0]["params"], records[0]["result"]

Files. Case ``params`` goes to ``<results_dir>/<case_key(params)>.json`` (written atomically by
:func:`abrakit.io.write_json`), holding ``params``, ``result``, the case function's name, the run time and the host.
The key is a hash of the parameters' canonical JSON (sorted keys), so it does not depend on the order of the list
or of the dict, and is the same in every process and on every machine; a ``"name"`` entry, when present, is put in
front of the hash to make the files readable. Running the same sweep again, after an interruption or with more
cases, reads the finished cases back and computes only the missing ones. Parameters are hashed as written:
``1`` and ``1.0`` are different cases. To invalidate old results after changing the case function, add a
``"version"`` entry to the parameters (or use a fresh directory). Parameters that only say where a case keeps its
files (a checkpoint path) are named in ``run_sweep(..., paths=[...])``: they reach the case but not the key, so the
stored records stay valid in another clone.

Backends. ``"serial"`` runs in this process; ``"joblib"`` (the default) runs local worker processes
(``n_jobs``, default: all cores); ``"dask"`` submits the cases to a ``dask.distributed`` scheduler:
give ``scheduler_address="tcp://host:8786"`` (or a connected ``distributed.Client``) and the same sweep runs on the
cluster. In every backend the results come back to this process, which writes the files as each case completes,
so the workers need no shared file system. The records returned are the JSON round trip of what was written, so
a fresh run, a resumed run and any backend return identical values.

A failing case raises (``errors="raise"``; the cases finished before it are on disk) or is recorded in
``<key>.failed.json`` with its traceback and the sweep goes on (``errors="record"``); a failed case is computed
again by the next run.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import socket
import time
import traceback
import warnings
from collections.abc import Callable, Iterable, Mapping
from datetime import datetime, timezone
from pathlib import Path

from abrakit.io import dumps, jsonable, loads, progress_bar, read_json, write_json
from abrakit.validation import check_integer, check_option

BACKENDS = ("serial", "joblib", "dask")


def canonical_params(params) -> str:
    """The canonical JSON text of one parameter dict: sorted keys, no spaces, numpy values as Python values.

    Raises ``TypeError`` if ``params`` is not a mapping with string keys or holds values JSON cannot write.
    """
    if not isinstance(params, Mapping):
        raise TypeError(f"params must be a dict of JSON values, got {type(params).__name__}: {params!r}")
    if not all(isinstance(k, str) for k in params):
        raise TypeError(f"params keys must be strings, got {list(params)!r}")
    try:
        return json.dumps(jsonable(dict(params)), sort_keys=True, separators=(",", ":"), allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"params must hold only finite JSON values (numbers, strings, lists, dicts): {exc}") from exc


def case_key(params, paths: Iterable[str] = ()) -> str:
    """Stable file stem of a case: ``<name>-<hash10>`` with a ``"name"`` entry, else ``<hash16>`` (SHA-1 hex). The
    entries named in ``paths`` (where the case keeps its files) are left out of the hash."""
    digest = hashlib.sha1(canonical_params(_without(params, paths)).encode()).hexdigest()
    name = params.get("name")
    if isinstance(name, str) and name:
        slug = re.sub(r"[^A-Za-z0-9_.=+-]+", "_", name).strip("_")[:60]
        return f"{slug}-{digest[:10]}"
    return digest[:16]


def _without(params, paths: Iterable[str]):
    """``params`` without the entries named in ``paths`` (``params`` itself if there are none)."""
    paths = set(paths)
    if not paths or not isinstance(params, Mapping):
        return params
    return {k: v for k, v in params.items() if k not in paths}


def _case_name(case_fn) -> str:
    fn = getattr(case_fn, "func", case_fn)            # functools.partial
    return f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', type(fn).__name__)}"


def _roundtrip(obj):
    """What JSON gives back: numpy arrays become lists, tuples lists, numpy scalars Python numbers."""
    return loads(dumps(obj))


def _execute(case_fn, key: str, params: dict, catch: bool) -> dict:
    """Run one case (in whichever process the backend chose) and return its record."""
    start = time.perf_counter()
    record = {"key": key, "case": _case_name(case_fn), "params": params, "result": None,
              "host": socket.gethostname(), "pid": os.getpid()}
    try:
        result = case_fn(dict(params))
    except Exception:
        if not catch:
            raise
        record["error"] = traceback.format_exc()
    else:
        if not isinstance(result, Mapping):
            raise TypeError(f"case function {record['case']} must return a dict, got {type(result).__name__}")
        record["result"] = jsonable(dict(result))
    record["seconds"] = time.perf_counter() - start
    record["finished"] = datetime.now(timezone.utc).isoformat(timespec="seconds")
    return record


def _finished(path: Path, canonical: str, paths: Iterable[str] = ()) -> dict | None:
    """The stored record of a case if it exists, is readable and belongs to these parameters (``canonical``, the
    entries named in ``paths`` left out)."""
    if not path.exists():
        return None
    try:
        record = read_json(path)
    except (OSError, ValueError):
        return None
    if canonical_params(_without(record.get("params", {}), paths)) != canonical:
        return None
    return record


def load_sweep(results_dir) -> list[dict]:
    """All finished records in ``results_dir`` (sorted by key). Failed and temporary files are skipped, and so is
    stray JSON that is not a case record (no ``key``, ``params`` and ``result``), with a warning naming it; a file
    that is not valid JSON (truncated) raises ``ValueError`` naming it."""
    directory = Path(results_dir)
    if not directory.is_dir():
        return []
    records = []
    for path in sorted(p for p in directory.glob("*.json") if not p.name.endswith(".failed.json")):
        try:
            record = read_json(path)
        except ValueError as exc:
            raise ValueError(f"{path} is not valid JSON (truncated or overwritten?): {exc}; delete it and rerun the "
                             "sweep to recompute that case") from exc
        if not (isinstance(record, dict) and {"key", "params", "result"} <= set(record)):
            warnings.warn(f"{path} is not a sweep record (no key, params and result): skipped", RuntimeWarning,
                          stacklevel=2)
            continue
        records.append(record)
    return records


def _map_serial(case_fn, jobs, catch, n_jobs, scheduler_address):
    for key, params in jobs:
        yield _execute(case_fn, key, params, catch)


def _map_joblib(case_fn, jobs, catch, n_jobs, scheduler_address):
    try:
        from joblib import Parallel, delayed
    except ImportError as exc:                                    # pragma: no cover - joblib is a dependency
        raise ImportError("backend='joblib' needs joblib: pip install joblib") from exc
    n_jobs = (os.cpu_count() or 1) if n_jobs is None else int(n_jobs)
    run = Parallel(n_jobs=n_jobs, return_as="generator_unordered")
    yield from run(delayed(_execute)(case_fn, key, params, catch) for key, params in jobs)


def _map_dask(case_fn, jobs, catch, n_jobs, scheduler_address):
    try:
        from distributed import Client, as_completed
    except ImportError as exc:
        raise ImportError("backend='dask' needs dask.distributed: pip install distributed") from exc
    if scheduler_address is None:
        raise ValueError("backend='dask' needs scheduler_address (e.g. 'tcp://host:8786') or a distributed.Client")
    own = not hasattr(scheduler_address, "submit")
    client = Client(scheduler_address) if own else scheduler_address
    try:
        futures = [client.submit(_execute, case_fn, key, params, catch, key=f"abrakit-sweep-{key}", pure=False)
                   for key, params in jobs]
        for future in as_completed(futures):
            yield future.result()
    finally:
        if own:
            client.close()


_MAPPERS = {"serial": _map_serial, "joblib": _map_joblib, "dask": _map_dask}


def run_sweep(case_fn: Callable[[dict], Mapping], params_list: Iterable[Mapping], results_dir, *,
              backend: str | None = None, n_jobs: int | None = None, scheduler_address=None,
              errors: str = "raise", progress: bool = False, paths: Iterable[str] = ()) -> list[dict]:
    """Run ``case_fn`` on every parameter dict, writing ``<results_dir>/<case_key>.json`` as each case finishes.

    Cases already in ``results_dir`` (same canonical parameters) are read back, not recomputed; duplicate
    parameter dicts run once. ``backend``: ``"serial"``, ``"joblib"`` (local processes, ``n_jobs`` of them,
    default all cores) or ``"dask"`` (``scheduler_address`` of a ``dask.distributed`` scheduler, or a
    ``distributed.Client``); ``None`` picks ``"dask"`` when an address is given, else ``"joblib"``.
    ``errors``: ``"raise"`` or ``"record"`` (see the module doc). ``paths``: the names of parameters that say where a
    case keeps its files (a checkpoint, say): passed to the case, but left out of its key and of the match with a
    stored record, so that the records of a sweep stay valid when the results move to another clone or machine.

    Returns one record per entry of ``params_list``, in its order: a dict with ``key``, ``params``, ``result``
    (``None`` for a recorded failure, with the traceback under ``error``), ``case``, ``seconds``, ``finished``,
    ``host`` and ``resumed`` (true if read from disk rather than computed by this call).
    """
    backend = ("dask" if scheduler_address is not None else "joblib") if backend is None else backend
    check_option("backend", backend, BACKENDS)
    check_option("errors", errors, ("raise", "record"))
    if n_jobs is not None and check_integer("n_jobs", n_jobs) == 0:
        raise ValueError(f"n_jobs must be a non-zero integer (negative counts back from all cores), got {n_jobs!r}")
    if isinstance(paths, str):
        raise TypeError(f"paths must be a list of parameter names, got the string {paths!r}")
    paths = tuple(paths)
    directory = Path(results_dir)
    directory.mkdir(parents=True, exist_ok=True)
    cases = []
    for index, params in enumerate(params_list):
        try:
            canonical = canonical_params(params)
            matched = canonical_params(_without(params, paths))
        except TypeError as exc:
            raise TypeError(f"params_list[{index}]: {exc}") from exc
        cases.append((case_key(params, paths), canonical, matched))
    records: dict[str, dict] = {}
    pending: dict[str, dict] = {}
    for key, canonical, matched in cases:
        if key in records or key in pending:
            continue
        stored = _finished(directory / f"{key}.json", matched, paths)
        if stored is not None:
            records[key] = {**stored, "resumed": True}
        else:
            pending[key] = json.loads(canonical)
    if pending:
        mapper = _MAPPERS[backend]
        jobs = list(pending.items())
        catch = errors == "record"
        bar = progress_bar(total=len(jobs), desc=f"sweep ({backend})", disable=not progress)
        for record in mapper(case_fn, jobs, catch, n_jobs, scheduler_address):
            key = record["key"]
            failed = directory / f"{key}.failed.json"
            if "error" in record:
                write_json(failed, record)
            else:
                write_json(directory / f"{key}.json", record)
                failed.unlink(missing_ok=True)
            records[key] = {**_roundtrip(record), "resumed": False}
            bar.update()
        bar.close()
    return [records[key] for key, _, _ in cases]
