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

__all__ = ["HAVE_NUMBA"]


@njit(cache=True, inline="always")
def inverse3(F, F_inv):  # pragma: no cover - compiled where numba is installed
    """det F, and F⁻¹ into ``F_inv``, of a 3 × 3 matrix by cofactors (F_inv zero where det F = 0): the one
    inverse of the compiled finite-strain and F-bar kernels."""
    c00 = F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1]
    c01 = F[1, 2] * F[2, 0] - F[1, 0] * F[2, 2]
    c02 = F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]
    det = F[0, 0] * c00 + F[0, 1] * c01 + F[0, 2] * c02
    inv = 1.0 / det if det != 0.0 else 0.0
    F_inv[0, 0] = c00 * inv
    F_inv[1, 0] = c01 * inv
    F_inv[2, 0] = c02 * inv
    F_inv[0, 1] = (F[0, 2] * F[2, 1] - F[0, 1] * F[2, 2]) * inv
    F_inv[1, 1] = (F[0, 0] * F[2, 2] - F[0, 2] * F[2, 0]) * inv
    F_inv[2, 1] = (F[0, 1] * F[2, 0] - F[0, 0] * F[2, 1]) * inv
    F_inv[0, 2] = (F[0, 1] * F[1, 2] - F[0, 2] * F[1, 1]) * inv
    F_inv[1, 2] = (F[0, 2] * F[1, 0] - F[0, 0] * F[1, 2]) * inv
    F_inv[2, 2] = (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]) * inv
    return det
