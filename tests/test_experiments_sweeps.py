"""Sweeps that survive interruption (abrakit.experiments.sweeps): keys, files, resume, joblib/serial/dask agree."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np
import pytest

from abrakit.experiments.sweeps import canonical_params, case_key, load_sweep, run_sweep


def polynomial_case(params):
    """A cheap case: logs each call (to count recomputations across processes) and fails on demand."""
    log = Path(params["log"])
    x = params["x"]
    with open(log / "calls.txt", "a") as fh:
        fh.write(f"{x}\n")
    if (log / f"fail-{x}").exists():
        raise RuntimeError(f"power cut at x = {x}")
    return {"square": x * x, "powers": np.arange(4) * x, "half": np.float64(x) / 2}


def calls(log: Path) -> list[float]:
    path = log / "calls.txt"
    return sorted(float(v) for v in path.read_text().split()) if path.exists() else []


def sweep(log: Path, n: int = 6) -> list[dict]:
    return [{"x": x, "log": str(log)} for x in range(n)]


def results(records):
    return [r["result"] for r in records]


# --- keys ---------------------------------------------------------------------------------------------------


def test_key_is_a_pinned_hash_of_the_canonical_json_independent_of_order():
    params = {"b": [1, 2], "a": 1}
    assert canonical_params(params) == '{"a":1,"b":[1,2]}'
    expected = hashlib.sha1(b'{"a":1,"b":[1,2]}').hexdigest()[:16]
    assert case_key(params) == expected == case_key({"a": 1, "b": [1, 2]})
    assert case_key({"a": 1, "b": [2, 1]}) != expected


def test_numpy_values_hash_like_python_values_and_names_prefix_the_key():
    assert case_key({"D": np.float64(0.1), "n": np.int64(3)}) == case_key({"D": 0.1, "n": 3})
    assert case_key({"D": np.arange(2)}) == case_key({"D": [0, 1]})
    key = case_key({"name": "box L=8/seed 0", "x": 1})
    assert key.startswith("box_L=8_seed_0-") and len(key.split("-")[-1]) == 10


@pytest.mark.parametrize("bad", [[1, 2], {"x": {1, 2}}, {"x": float("nan")}, {1: 2}])
def test_parameters_that_json_cannot_hold_are_refused(bad, tmp_path):
    with pytest.raises(TypeError):
        case_key(bad)
    with pytest.raises(TypeError, match=r"params_list\[0\]"):
        run_sweep(polynomial_case, [bad], tmp_path, backend="serial")


def test_bad_options_are_refused(tmp_path):
    with pytest.raises(ValueError, match="backend"):
        run_sweep(polynomial_case, sweep(tmp_path), tmp_path, backend="mpi")
    with pytest.raises(ValueError, match="errors"):
        run_sweep(polynomial_case, sweep(tmp_path), tmp_path, backend="serial", errors="ignore")
    with pytest.raises(ValueError, match="n_jobs"):
        run_sweep(polynomial_case, sweep(tmp_path), tmp_path, n_jobs=0)
    with pytest.raises(ValueError, match="scheduler_address"):
        run_sweep(polynomial_case, sweep(tmp_path), tmp_path, backend="dask")


# --- files and resume ---------------------------------------------------------------------------------------


def test_each_case_is_a_json_file_with_params_result_and_provenance(tmp_path):
    records = run_sweep(polynomial_case, sweep(tmp_path, 3), tmp_path / "out", backend="serial")
    assert [r["result"]["square"] for r in records] == [0, 1, 4]
    assert records[2]["result"]["powers"] == [0, 2, 4, 6]             # numpy arrays stored as lists
    for params, rec in zip(sweep(tmp_path, 3), records, strict=True):
        stored = json.loads((tmp_path / "out" / f"{case_key(params)}.json").read_text())
        assert stored["params"] == params and stored["result"] == rec["result"]
        assert stored["case"].endswith("polynomial_case") and stored["seconds"] >= 0 and stored["finished"]
        assert rec["resumed"] is False
    assert {r["key"] for r in load_sweep(tmp_path / "out")} == {r["key"] for r in records}


def test_an_interrupted_sweep_resumes_without_recomputing_finished_cases(tmp_path):
    log, out = tmp_path, tmp_path / "out"
    (log / "fail-3").touch()                                           # the machine dies at the 4th case
    with pytest.raises(RuntimeError, match="power cut"):
        run_sweep(polynomial_case, sweep(log), out, backend="serial")
    assert calls(log) == [0, 1, 2, 3]
    assert len(list(out.glob("*.json"))) == 3                          # the finished cases are on disk
    (log / "fail-3").unlink()
    resumed = run_sweep(polynomial_case, sweep(log), out, backend="serial")
    assert calls(log) == [0, 1, 2, 3, 3, 4, 5]                         # only the missing cases ran again
    assert [r["resumed"] for r in resumed] == [True, True, True, False, False, False]
    again = run_sweep(polynomial_case, sweep(log), out, backend="serial")
    assert all(r["resumed"] for r in again) and calls(log) == [0, 1, 2, 3, 3, 4, 5]
    fresh = run_sweep(polynomial_case, sweep(log), tmp_path / "fresh_out", backend="serial")
    assert results(resumed) == results(again) == results(fresh)         # as if never interrupted


def test_a_damaged_file_is_recomputed_and_duplicates_run_once(tmp_path):
    out = tmp_path / "out"
    params = sweep(tmp_path, 2)
    run_sweep(polynomial_case, params, out, backend="serial")
    (out / f"{case_key(params[1])}.json").write_text("{ not json")
    records = run_sweep(polynomial_case, params + [params[0]], out, backend="serial")
    assert calls(tmp_path) == [0, 1, 1]
    assert [r["resumed"] for r in records] == [True, False, True]


def test_recorded_failures_do_not_stop_the_sweep_and_are_retried(tmp_path):
    (tmp_path / "fail-1").touch()
    out = tmp_path / "out"
    records = run_sweep(polynomial_case, sweep(tmp_path, 3), out, backend="serial", errors="record")
    assert records[1]["result"] is None and "power cut at x = 1" in records[1]["error"]
    assert records[2]["result"]["square"] == 4
    failed = out / f"{case_key(sweep(tmp_path, 3)[1])}.failed.json"
    assert failed.exists() and len(load_sweep(out)) == 2
    (tmp_path / "fail-1").unlink()
    records = run_sweep(polynomial_case, sweep(tmp_path, 3), out, backend="serial", errors="record")
    assert records[1]["result"]["square"] == 1 and not failed.exists()
    assert calls(tmp_path) == [0, 1, 1, 2]


# --- backends -----------------------------------------------------------------------------------------------


def test_joblib_and_serial_give_the_same_records(tmp_path):
    serial = run_sweep(polynomial_case, sweep(tmp_path), tmp_path / "serial", backend="serial")
    parallel = run_sweep(polynomial_case, sweep(tmp_path), tmp_path / "joblib", backend="joblib", n_jobs=2)
    assert results(parallel) == results(serial)
    assert [r["key"] for r in parallel] == [r["key"] for r in serial]
    assert len({r["pid"] for r in parallel} - {os.getpid()}) >= 1       # really ran in worker processes
    assert calls(tmp_path) == sorted(2 * list(range(6)))


def test_dask_local_cluster_runs_and_resumes_the_same_sweep(tmp_path):
    distributed = pytest.importorskip("distributed")
    serial = run_sweep(polynomial_case, sweep(tmp_path, 4), tmp_path / "serial", backend="serial")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        on_cluster = run_sweep(polynomial_case, sweep(tmp_path, 4), tmp_path / "dask",
                               scheduler_address=cluster.scheduler_address)       # backend chosen: dask
        assert results(on_cluster) == results(serial)
        with distributed.Client(cluster) as client:                                # a Client works too
            again = run_sweep(polynomial_case, sweep(tmp_path, 5), tmp_path / "dask", backend="dask",
                              scheduler_address=client)
    assert [r["resumed"] for r in again] == [True] * 4 + [False]
    assert calls(tmp_path) == sorted(2 * list(range(4)) + [4])


def test_load_sweep_names_a_truncated_file_and_skips_stray_json(tmp_path):
    """A case file cut short (a killed writer on a file system without atomic rename) is named in the error; a JSON
    file that is not a case record (a summary someone saved beside the cases) is skipped with a warning."""
    out = tmp_path / "out"
    params = sweep(tmp_path, 2)
    run_sweep(polynomial_case, params, out, backend="serial")
    (out / "notes.json").write_text(json.dumps({"comment": "not a case"}))
    with pytest.warns(RuntimeWarning, match="notes.json is not a sweep record"):
        assert len(load_sweep(out)) == 2
    truncated = out / f"{case_key(params[1])}.json"
    truncated.write_text(truncated.read_text()[:25])
    with pytest.raises(ValueError, match=f"{truncated.name} is not valid JSON"):
        load_sweep(out)


def slow_case(params):
    """A case that takes a moment, so that two processes running one sweep overlap."""
    import time

    time.sleep(0.05)
    return polynomial_case(params)


def _run_sweep_in_process(log, out):
    run_sweep(slow_case, sweep(Path(log), 12), out, backend="serial")


def test_two_processes_running_one_sweep_leave_every_case_once_and_every_file_valid(tmp_path):
    """Two processes start the same sweep on one folder at once: each case ends up in exactly one valid file
    (written under a unique temporary name and renamed), no temporary file is left, and a third run reads all."""
    import multiprocessing

    out = tmp_path / "out"
    context = multiprocessing.get_context("spawn")
    workers = [context.Process(target=_run_sweep_in_process, args=(str(tmp_path), str(out))) for _ in range(2)]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join(timeout=120)
        assert worker.exitcode == 0
    files = sorted(out.iterdir())
    assert len(files) == 12 and all(f.suffix == ".json" for f in files)
    records = load_sweep(out)
    assert sorted(r["params"]["x"] for r in records) == list(range(12))
    assert all(r["result"]["square"] == r["params"]["x"] ** 2 for r in records)
    computed = calls(tmp_path)
    assert set(computed) == set(map(float, range(12))) and len(computed) <= 24
    again = run_sweep(slow_case, sweep(tmp_path, 12), out, backend="serial")
    assert all(r["resumed"] for r in again) and len(calls(tmp_path)) == len(computed)


def test_path_parameters_reach_the_case_but_not_its_key_so_records_move_between_clones(tmp_path):
    """``paths`` names parameters that say where a case keeps its files: the records written with one log directory
    are read back, not recomputed, when the same sweep names another (a clone elsewhere); every other parameter
    still makes a case of its own."""
    first, moved = tmp_path / "clone_a", tmp_path / "clone_b"
    first.mkdir(), moved.mkdir()
    out = tmp_path / "out"
    written = run_sweep(polynomial_case, sweep(first, 3), out, backend="serial", paths=["log"])
    assert len(calls(first)) == 3 and [r["key"] for r in written] == [case_key(p, ["log"]) for p in sweep(moved, 3)]
    again = run_sweep(polynomial_case, sweep(moved, 4), out, backend="serial", paths=("log",))
    assert calls(moved) == [3.0] and [r["resumed"] for r in again] == [True, True, True, False]
    assert results(again[:3]) == results(written)
    assert case_key({"x": 1, "log": "a"}, ["log"]) == case_key({"x": 1}) != case_key({"x": 1, "log": "a"})
    with pytest.raises(TypeError, match="paths must be a list"):
        run_sweep(polynomial_case, sweep(first, 1), out, backend="serial", paths="log")
