"""abrakit: the abrasive-wear modelling chain of Hoormazdi (2021), readable and verified.

The chapters' modules load on first use (``abrakit.dem``, ``abrakit.fem``, ...), so ``import abrakit`` stays cheap.
"""

import importlib

from .threads import configure_threads

configure_threads()                 # before numba, MKL and the OpenMP runtimes load (abrakit.threads says why)

__version__ = "0.1.0"

#: The subpackages and modules reachable as attributes of the package.
MODULES = ("tensors", "evolution", "identification", "dem", "experiments", "materials", "fem", "damage", "scratch",
           "wear", "fatigue", "reproduction", "validation", "io", "cli", "threads")
__all__ = ["__version__", *MODULES]


def __getattr__(name):
    if name in MODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
