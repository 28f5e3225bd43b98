"""Thread counts of the numerical libraries, chosen in one place (at ``import abrakit``).

abrakit's hot paths run in up to four thread pools: OpenBLAS (numpy, scipy), MKL (PARDISO), numba's parallel
kernels (GNU OpenMP) and, in the test suite, pytest-xdist's worker processes. MKL's single dynamic library picks its
OpenMP runtime when it is loaded: GNU's (``libmkl_gnu_thread``), shared with numba, if numba's OpenMP pool is
already loaded, as in a finite element run whose compiled kernels run before the first factorisation; Intel's
(``libiomp5``) otherwise (read from ``/proc/self/maps``). Intel's settings (``KMP_BLOCKTIME``) then act on nothing.
Left alone, each pool starts one thread per core: two test workers (or two sweep processes) each starting two
threads per pool put four busy threads on two cores. Measured on the 2-core machine (``benchmarks/bench_threads.py``,
the scratch's coarse mesh): a Newton iteration of two concurrent processes costs 295 ms with the libraries'
defaults and 202 ms with one thread each.

So, unless the user has set them, every pool gets ``cores // workers`` threads, where ``workers`` is the number
of processes sharing the machine (pytest-xdist's ``PYTEST_XDIST_WORKER_COUNT``; 1 otherwise);
``ABRAKIT_THREADS`` overrides the count. The OpenMP wait policy is left to the libraries: passive waits
(``OMP_WAIT_POLICY=PASSIVE``) were measured too and rejected. They sped up PARDISO's factorisation on the
scratch's default mesh (452 → 376 ms), but cost 9 % of a scratch iteration on the coarse mesh and 27 % of the DEM
four-point-bending example (13.0 → 16.5 s), whose time steps wake the threads thousands of times.
Environment variables act on libraries that load later (MKL, numba, the OpenMP runtimes
are loaded lazily by abrakit); libraries already loaded (numpy's OpenBLAS, when numpy was imported first) are
limited at run time through threadpoolctl. :func:`limit_threads` changes the count later, in one call.

OpenBLAS is the exception: it gets :data:`OPENBLAS_THREADS` (one) thread, whatever the cores, unless the user sets
``OPENBLAS_NUM_THREADS``. Its pool is not OpenMP: its threads spin after every call on a vector long enough to be
split (numpy's ``dot``, ``vdot``, matrix-vector products) and hold the cores that numba's and PARDISO's OpenMP
threads then wait for. On the 2-core machine the first 45 increments of the scratch's coarse mesh on the 300 µm
block (cProfile) took 89.5 s with two threads in every pool, 58.8 s with one, and 42.3 s with two threads
everywhere but OpenBLAS: the material update 36 → 16 ms per call, a PARDISO call 21 → 9.5 ms. The pieces timed
alone (``benchmarks/bench_threads.py``) do not show it, a whole run does (its ``runs`` table). Nothing else in
abrakit gains from OpenBLAS's threads: the four-point-bending, Model I, localisation and DEM examples ran as fast
with one OpenBLAS thread as with two (three alternating runs each, within their ±10 % scatter)."""

from __future__ import annotations

import os

__all__ = ["configure_threads", "default_threads", "limit_threads"]

_COUNT_VARIABLES = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS")

OPENBLAS_THREADS = 1
"""OpenBLAS's thread count unless the user sets ``OPENBLAS_NUM_THREADS`` (the module docstring says why)."""


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:                                        # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def default_threads() -> int:
    """Threads per pool: ``ABRAKIT_THREADS`` if set (a positive integer), else the cores this process may use
    divided by the processes sharing them (pytest-xdist workers), at least 1."""
    chosen = os.environ.get("ABRAKIT_THREADS")
    if chosen:
        if not chosen.strip().isdigit() or int(chosen) < 1:
            raise ValueError(f"ABRAKIT_THREADS must be a positive integer, got {chosen!r}")
        return int(chosen)
    workers = os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")
    workers = int(workers) if workers.strip().isdigit() and int(workers) > 0 else 1
    return max(1, _cores() // workers)


_SET_BY_ABRAKIT = "ABRAKIT_SET_THREADS"
"""The environment variable that lists the count variables abrakit set itself (not the user): a process started
by an abrakit process inherits them, and computes them again for itself (with its own ``ABRAKIT_THREADS`` or
worker count) instead of taking them for the user's word. Without it a benchmark that starts two one-thread runs
from Python gave each the parent's two threads per pool: both ran twice as slowly."""


def configure_threads() -> int:
    """Set the thread policy of the module docstring for this process (where the user has not); returns the count.
    Called once by ``import abrakit``. Variables an abrakit parent process set (:data:`_SET_BY_ABRAKIT`) are set
    again, the user's are kept."""
    threads = default_threads()
    inherited = set(os.environ.get(_SET_BY_ABRAKIT, "").split(","))
    ours = [name for name in _COUNT_VARIABLES if name not in os.environ or name in inherited]
    for name in ours:
        os.environ[name] = str(OPENBLAS_THREADS if name == "OPENBLAS_NUM_THREADS" else threads)
    os.environ[_SET_BY_ABRAKIT] = ",".join(ours)
    _limit_loaded(threads)
    return threads


def _openblas_threads(threads: int) -> int:
    """OpenBLAS's count: the user's ``OPENBLAS_NUM_THREADS`` if set (and a number), else :data:`OPENBLAS_THREADS`."""
    inherited = os.environ.get(_SET_BY_ABRAKIT, "").split(",")
    chosen = os.environ.get("OPENBLAS_NUM_THREADS", "")
    if "OPENBLAS_NUM_THREADS" in inherited or not chosen.strip().isdigit() or int(chosen) < 1:
        return min(OPENBLAS_THREADS, threads)
    return int(chosen)


def _limit_loaded(threads: int) -> None:
    """Limit the BLAS/OpenMP pools already loaded in this process to ``threads`` (OpenBLAS's to
    :func:`_openblas_threads`; threadpoolctl, nothing if it is missing)."""
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:                                           # pragma: no cover - a dependency
        return
    blas = _openblas_threads(threads)
    for pool in ThreadpoolController().lib_controllers:          # one scan of the loaded libraries
        pool.set_num_threads(blas if pool.internal_api == "openblas" else threads)


def limit_threads(threads: int) -> None:
    """Use ``threads`` threads in every pool from now on: the loaded BLAS/OpenMP libraries (threadpoolctl) and
    numba's parallel kernels (up to the count numba started with)."""
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
        raise ValueError(f"threads must be a positive integer, got {threads!r}")
    os.environ["ABRAKIT_THREADS"] = str(threads)
    _limit_loaded(threads)
    from .compiled import HAVE_NUMBA

    if HAVE_NUMBA:
        import numba

        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
