"""abrakit: the abrasive-wear modelling chain of Hoormazdi (2021), readable and verified.

One package or module per chapter, each the door to the objects its chapter uses (``abrakit.<chapter>.__all__``):

==================  ==========================================================================================
``tensors``         Voigt and Mandel notation, spectral split, isotropic stiffness, sphere averages (Ch. 2.1)
``evolution``       evolution laws from potentials in one dimension, and their time integration (Ch. 2.6, 4)
``dem``             the discrete element engine: particles, contact laws, bonds, walls, measurements (Ch. 4.1)
``identification``  closed forms from contact parameters to elastic constants and strengths (Ch. 5.2)
``experiments``     DEM specimens and tests: genesis, compression, closed-form checks, bending (Ch. 5.3-5.4)
``materials``       constitutive models at a material point: plasticity, Model I and II damage (Ch. 6)
``fem``             finite elements on scikit-fem: kinematics, assembly, Newton solver, path following (Ch. 4.2)
``damage``          the regularised damage models on the specimens of Ch. 7, and the crack band of seed 001
``scratch``         the single scratch test: scene, run, indenters, groove and its volume, Hertz (Ch. 8.1-8.2)
``wear``            from single scratches to wear rates, and the ASTM G65 test (Ch. 8.3-8.4)
``g65``             the ASTM G65 dry-sand rubber-wheel test held against the wear rates (Ch. 8.4)
``fatigue``         the damage-plasticity fatigue bond of seed 002 with its cycle jump
==================  ==========================================================================================

Each loads on first use (``abrakit.dem``, ``abrakit.fem``, ...), so ``import abrakit`` stays cheap. The plumbing
(``abrakit.io``, ``abrakit.validation``, ``abrakit.threads``, ``abrakit.cli``, ...) is imported by its full name.
Units: the DEM and the identification in SI (m, N, Pa); the finite element chapters in N, mm, MPa.
"""

import importlib

from .threads import configure_threads

configure_threads()                 # before numba, MKL and the OpenMP runtimes load (abrakit.threads says why)

__version__ = "0.1.0"

#: The chapter packages and modules, reachable as attributes of the package.
MODULES = ("tensors", "evolution", "dem", "identification", "experiments", "materials", "fem", "damage", "scratch",
           "wear", "g65", "fatigue")
__all__ = ["__version__", "demo", *MODULES]


def demo(chapter: str) -> str:
    """Run the small scene of one book chapter and return its plain-text summary (what ``abrakit demo CHAPTER``
    prints); ``abrakit list`` names the chapters."""
    from ._demos import demo as _demo

    return _demo(chapter)


def __getattr__(name):
    if name in MODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
