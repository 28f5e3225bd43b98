"""The thread policy of :mod:`abrakit.threads`: one count per pool shared among the workers, the user's word first."""

import json
import os
import subprocess
import sys

import pytest

from abrakit.threads import default_threads, limit_threads

PROBE = """
import json, os, numpy
import abrakit
from threadpoolctl import threadpool_info
print(json.dumps({"env": {k: os.environ.get(k) for k in ("OMP_WAIT_POLICY", "KMP_BLOCKTIME", "OMP_NUM_THREADS",
                                                           "MKL_NUM_THREADS", "NUMBA_NUM_THREADS",
                                                           "OPENBLAS_NUM_THREADS")},
                  "pools": [p["num_threads"] for p in threadpool_info()],
                  "openblas": [p["num_threads"] for p in threadpool_info() if p["internal_api"] == "openblas"]}))
"""


def probe(**env):
    clean = {k: v for k, v in os.environ.items()
             if k not in ("OMP_WAIT_POLICY", "KMP_BLOCKTIME", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
                          "NUMBA_NUM_THREADS", "OPENBLAS_NUM_THREADS", "ABRAKIT_THREADS", "PYTEST_XDIST_WORKER_COUNT",
                          "ABRAKIT_SET_THREADS")}
    out = subprocess.run([sys.executable, "-c", PROBE], env=clean | env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_workers_share_the_cores_and_the_wait_policy_is_the_libraries():
    cores = len(os.sched_getaffinity(0))
    seen = probe(PYTEST_XDIST_WORKER_COUNT=str(cores))
    assert seen["env"]["OMP_WAIT_POLICY"] is None and seen["env"]["KMP_BLOCKTIME"] is None
    assert seen["env"]["OMP_NUM_THREADS"] == seen["env"]["MKL_NUM_THREADS"] == seen["env"]["NUMBA_NUM_THREADS"] == "1"
    assert seen["pools"] and max(seen["pools"]) == 1          # numpy's OpenBLAS, loaded before abrakit, limited too


def test_a_child_of_an_abrakit_process_sets_its_own_counts_and_keeps_the_users():
    """A process started by an abrakit process inherits the counts abrakit set there; with its own ABRAKIT_THREADS
    it sets them again (a parent with two threads, a child asked for one), while a count the user set stays."""
    parent = probe()
    inherited = {k: v for k, v in parent["env"].items() if v is not None and k.endswith("_NUM_THREADS")}
    child = probe(**inherited, ABRAKIT_SET_THREADS="OMP_NUM_THREADS,NUMBA_NUM_THREADS,OPENBLAS_NUM_THREADS",
                  ABRAKIT_THREADS="1")
    assert child["env"]["OMP_NUM_THREADS"] == child["env"]["NUMBA_NUM_THREADS"] == "1"
    assert child["env"]["MKL_NUM_THREADS"] == inherited["MKL_NUM_THREADS"]      # not in the list: the user's


def test_the_users_settings_are_kept():
    seen = probe(OMP_WAIT_POLICY="ACTIVE", ABRAKIT_THREADS="1", MKL_NUM_THREADS="2")
    assert seen["env"]["OMP_WAIT_POLICY"] == "ACTIVE"
    assert seen["env"]["MKL_NUM_THREADS"] == "2" and seen["env"]["OMP_NUM_THREADS"] == "1"


def test_openblas_gets_one_thread_unless_the_user_sets_it():
    """OpenBLAS's spinning threads hold the cores the OpenMP pools need (abrakit.threads): one thread, also for
    numpy's OpenBLAS loaded before abrakit, while the OpenMP pools get the cores; the user's count is kept."""
    cores = len(os.sched_getaffinity(0))
    seen = probe(ABRAKIT_THREADS=str(max(cores, 2)))
    assert seen["env"]["OPENBLAS_NUM_THREADS"] == "1" and seen["openblas"] and set(seen["openblas"]) == {1}
    assert seen["env"]["OMP_NUM_THREADS"] == str(max(cores, 2))
    mine = probe(ABRAKIT_THREADS="1", OPENBLAS_NUM_THREADS="2")
    assert mine["env"]["OPENBLAS_NUM_THREADS"] == "2" and set(mine["openblas"]) == {2}
    child = probe(OPENBLAS_NUM_THREADS="1", ABRAKIT_SET_THREADS="OPENBLAS_NUM_THREADS", ABRAKIT_THREADS="2")
    assert child["env"]["OPENBLAS_NUM_THREADS"] == "1" and set(child["openblas"]) == {1}


def test_default_threads_divides_the_cores_by_the_workers(monkeypatch):
    monkeypatch.delenv("ABRAKIT_THREADS", raising=False)
    cores = len(os.sched_getaffinity(0))
    monkeypatch.setenv("PYTEST_XDIST_WORKER_COUNT", "1")
    assert default_threads() == cores
    monkeypatch.setenv("PYTEST_XDIST_WORKER_COUNT", str(4 * cores))
    assert default_threads() == 1


@pytest.mark.parametrize("bad", ["0", "-2", "two", "1.5"])
def test_a_bad_thread_count_is_refused_by_name(monkeypatch, bad):
    monkeypatch.setenv("ABRAKIT_THREADS", bad)
    with pytest.raises(ValueError, match="ABRAKIT_THREADS"):
        default_threads()


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_limit_threads_refuses_what_is_not_a_positive_integer(bad):
    with pytest.raises(ValueError, match="threads"):
        limit_threads(bad)
