"""The optional numba layer (extra ``fast``) shared by every compiled kernel: ``njit``, ``prange`` and
``HAVE_NUMBA``. Without numba, ``njit`` returns the function unchanged and ``prange`` is ``range``, so callers keep
one code path and choose the vectorised NumPy version where the pure-Python loop would be too slow."""

try:
    from numba import njit, prange

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - numba is an optional extra
    HAVE_NUMBA = False
    prange = range

    def njit(*args, **kwargs):
        return (lambda f: f) if not (args and callable(args[0])) else args[0]

__all__ = ["HAVE_NUMBA", "njit", "prange"]
