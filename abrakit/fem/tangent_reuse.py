"""Element tangents kept across Newton iterations where the deformation has not moved (F-bar kinematics).

A scratch changes only near the tip: in one Newton iteration most of the block deforms by less than 10⁻⁵ in F
and stays elastic, yet the full tangent (the material tangent ∂P/∂F at every point, the F-bar element tangents
and their scatter into the global matrix) costs about a third of the iteration. :class:`ElementTangentReuse`
recomputes the tangent of an element only if

* some component of F at one of its points has moved by more than ``tolerance`` since its tangent was computed,
* or one of its points flows plastically now, or did when its tangent was computed (the algorithmic tangent is
  not the elastic one, and the plastic metric C_p has changed);

every other element keeps its tangent, and the global values are updated by the difference of the refreshed
element tangents. The residual is always exact, so the converged solution is the same to the Newton tolerance;
only the Newton matrix differs from the exact one, by a relative amount of the order of ``tolerance`` in the
elements kept (the elastic tangent is smooth in F). ``tolerance = 0`` refreshes every element whose F changed at
all and reproduces the full tangent to round-off (``tests/test_tangent_reuse.py``). Every ``resum_every``
refreshes the global values are summed afresh from the kept element tangents, so round-off cannot accumulate.

It applies where the material response says which points yield (``response.yielding``, e.g.
:class:`~abrakit.materials.LogStrainPlasticity` without damage) and can give the tangent of selected elements
(``response.tangent_of``); :meth:`ElementTangentReuse.applies` tells, and the solver falls back to the full tangent
otherwise.
"""

from __future__ import annotations

import numpy as np

from ..validation import check_positive, check_range
from .assembly import Assembler
from .kinematics import FBarKinematics


class ElementTangentReuse:
    """The values of the global tangent (in the assembler's CSR pattern) with element tangents reused where the
    deformation has not moved (module docstring). Counters: ``refreshed`` (element tangents computed) and
    ``calls``."""

    def __init__(self, assembler: Assembler, tolerance: float, resum_every: int = 50):
        if not isinstance(assembler.kin, FBarKinematics):
            raise TypeError("element tangents are reused for F-bar kinematics only "
                            f"(got {type(assembler.kin).__name__})")
        self.assembler = assembler
        self.tolerance = check_positive("tolerance", tolerance, allow_zero=True)
        self.resum_every = check_range("resum_every", resum_every, 1, None)
        self._Ke = None
        self._F = None
        self._yielded = None
        self._data = None
        self.calls = self.refreshed = 0

    @staticmethod
    def applies(response) -> bool:
        """Whether ``response`` says where its points yield and can give the tangent of selected elements."""
        return getattr(response, "yielding", None) is not None and hasattr(response, "tangent_of")

    def data(self, response, u: np.ndarray) -> np.ndarray:
        """The tangent's values at ``u`` (a fresh array the caller may modify)."""
        asm, kin = self.assembler, self.assembler.kin
        F = kin.fbar_state(u).F.reshape(kin.nel, -1)
        yielding = np.asarray(response.yielding, dtype=bool).reshape(kin.nel, -1).any(axis=1)
        self.calls += 1
        if self._Ke is None:                                   # the first call computes every element
            self._Ke = kin.element_tangents(response.tangent, response.stress, u)
            self._F, self._yielded = F.copy(), yielding
            self._data = self._summed()
            self.refreshed += kin.nel
            return self._data.copy()
        moved = np.abs(F - self._F).max(axis=1) > self.tolerance
        elements = np.flatnonzero(moved | yielding | self._yielded)
        if elements.size:
            Ke = kin.element_tangents(response.tangent_of(elements), response.stress[elements], u, elements=elements)
            change = Ke - self._Ke[elements]
            self._Ke[elements] = Ke
            self._F[elements], self._yielded[elements] = F[elements], yielding[elements]
            self.refreshed += elements.size
            if self.calls % self.resum_every == 0:
                self._data = self._summed()
            else:
                self._data += np.bincount(asm.slot[elements].ravel(), weights=change.ravel(), minlength=asm.nnz)
        return self._data.copy()

    def _summed(self) -> np.ndarray:
        """The global values summed afresh from every kept element tangent."""
        asm = self.assembler
        return np.bincount(asm.slot.ravel(), weights=self._Ke.ravel(), minlength=asm.nnz)
