"""Checkpoints of a scratch run: a killed :func:`~abrakit.scratch.run_scratch` continues where it was saved.

A checkpoint (``last_converged.npz`` in the run's output directory, written atomically) holds what the next
increment starts from: the displacement, the material state, the pseudo-time τ, the committed contact history
(:meth:`~abrakit.scratch.IndenterContact.snapshot`), the record so far (rows of ``forces.csv``, volume audit, VTU
entries: :meth:`~abrakit.scratch.record.ScratchRecorder.position`), the Newton and cutback counters and, once the
slide's first half is done, the displacement at τ = 1.5 (the groove "with the tip in contact"). Inside a phase it
also holds the solver's :attr:`~abrakit.fem.SolveResult.continuation` (step size, cutback recovery, the previous
increment), so the resumed phase takes the increments the uninterrupted one would have taken. It is written every
``checkpoint_every`` increments and at the end of every phase, in the one checkpoint format of a run
(:func:`abrakit.fem.recorder.save_run`). A checkpoint of another scene or mesh is refused by name, not resumed.
"""

from __future__ import annotations

from pathlib import Path

from abrakit.fem.output import RunWriter
from abrakit.fem.recorder import continuation_arrays, load_run, save_run
from abrakit.validation import number_arguments

CHECKPOINT = RunWriter.CHECKPOINT


@number_arguments
def fingerprint(scene, ndof: int) -> dict:
    """What a checkpoint must match to be resumed: the scene (its exact repr) and the number of DOFs."""
    return {"scene": repr(scene), "dofs": int(ndof)}


def save_scratch_checkpoint(path, scene, *, u, state, tau: float, recorder, contact, iterations: int,
                            cutbacks: int, u_loaded=None, continuation: dict | None = None) -> Path:
    """Write the checkpoint of a scratch run that has converged up to pseudo-time ``tau`` (see the module doc).

    ``iterations``: Newton iterations so far; ``cutbacks``: cutbacks of the finished phases (those of the running
    phase are in its ``continuation``, which is ``None`` at a phase end)."""
    contact_arrays, contact_meta = contact.snapshot()
    arrays = contact_arrays | {"u_loaded": u_loaded} | continuation_arrays(continuation)
    return save_run(path, u, state, float(tau), float(tau), fingerprint=fingerprint(scene, u.size),
                    control=None if continuation is None else continuation["control"], arrays=arrays,
                    record=recorder.position(), contact=contact_meta, iterations=int(iterations),
                    cutbacks=int(cutbacks))


def load_scratch_checkpoint(path, scene, ndof: int) -> dict | None:
    """The checkpoint at ``path`` (``None`` if there is none), checked against ``scene`` and ``ndof``."""
    saved = load_run(path, fingerprint(scene, ndof), "scratch run (scene or mesh differ)")
    if saved is not None:
        saved["u_loaded"] = saved["arrays"].pop("u_loaded", None)
    return saved
