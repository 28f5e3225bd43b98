"""The cyclic test of the four-point beam (seed 002, Sec. 5.2): haversine load cycles with the cycle jump, the
fatigue life from the flexural modulus, the quasi-static check and the stages of the modulus degradation.

The beam, its fixture and the flexural measures are :mod:`abrakit.experiments.bending`'s.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from numpy.typing import ArrayLike

from abrakit.dem.simulation import Simulation
from abrakit.experiments.bending import SEATING, Beam, flexural
from abrakit.io import RunRecord, VtuSeries, load_state, save_state
from abrakit.validation import (
    check_finite,
    check_integer,
    check_option,
    check_positive,
    check_range,
    number_arguments,
)

COLUMNS = ("measured_at", "cycles", "modulus", "deflection", "residual", "damaged", "yielding", "broken")
"""What :func:`cyclic_bending` records per simulated cycle."""


def cyclic_bending(beam: Beam, load_max: float, *, load_min_ratio: float | None = None, steps_per_cycle: int = 8000,
                   jump: float | None = None, plasticity: str = "frozen", settle: int = 0,
                   life_ratio: float = 0.5, max_cycles: int = 100_000,
                   reference_cycles: int = 50, csv=None, time_limit: float | None = None, checkpoint=None,
                   max_simulated: int | None = None, vtu=None, quasi_static_check: bool = True) -> dict:
    """Haversine cyclic load between ``load_min_ratio`` × and 1 × ``load_max`` [N] (Fig. 16), shared by the loading
    particles. ``load_min_ratio`` defaults to :data:`SEATING` on the rockers (one-sided supports need a seating load)
    and to 0 on the pads.

    Each simulated cycle runs ``steps_per_cycle`` steps (8000 by default: on the 98-disk beam at 0.86 P_max the
    smallest resolution at which the first cycles are converged: δ_peak/δ_static within 0.2 %, the bonds
    fatigued in a cycle the same as at 16 000 and 32 000; the life is not converged there: the damaged beam's
    damage per cycle is twice the converged one, and the life is 24 % short of the 32 000-step life, against
    4 % at 16 000 steps, ``benchmarks/bench_fatigue_convergence.py``);
    at its peak the fatigue update of every bond is applied
    (with the cycle jump ``jump`` if given, Eqs. 40, 41; ``plasticity`` as in
    :meth:`~abrakit.dem.fatigue_bonds.FatigueBonds.onset_of_unloading`; after each jump ``settle`` cycles are
    simulated one by one before the next sample, letting the beam settle from the jump's sudden relaxation) and
    E_f (:func:`flexural`) is taken from the peak load and deflection. E_f,0 is the mean over the cycles measured
    up to ``reference_cycles`` (the paper's first 50); the run ends when E_f/E_f,0 ≤ ``life_ratio`` (the fatigue
    life: the cycle in which that E_f was measured), when the beam fails, or when a whole cycle left every bond's
    damage unchanged (``"shakedown"``: the next cycle would repeat it). Returns per simulated cycle
    ``measured_at`` (the cycle in which its E_f and δ were measured: one after the count before it),
    ``cycles`` (the count after its fatigue update, the jump's skipped cycles included: ``cycles − measured_at``
    of them), ``modulus``, ``deflection``, ``residual`` (δ at the cycle's end), ``damaged`` (D > 2 D₀),
    ``yielding`` (bonds that yielded in the sampled cycle, hence got no fatigue) and ``broken`` bond counts, plus
    ``life`` (or None), ``stopped``, ``amplification`` and ``seconds``, the run's wall time over all the calls that
    computed it (a checkpoint keeps it; checkpoints written before it did count from their resumption); with ``csv``
    each row is written as it is
    computed. With ``checkpoint`` (a file) the state is saved after every simulated cycle and a
    run that finds the file resumes from it, rewriting ``csv`` from the saved records: an interrupted run loses at
    most the cycle it was in and then finishes with the same history; a finished run (life, failure, shakedown) is
    read back, not continued. With ``vtu`` (a directory) every simulated cycle also writes the bonds as line cells
    with their damage, fatigue and plastic displacements and yield flag (``bonds_*.vtu`` and ``bonds.pvd`` for
    ParaView, time = cycle count). ``max_simulated`` stops after that many simulated cycles in this call (an
    interruption on purpose).

    Quasi-static by measurement (``quasi_static_check``): in the first cycle of a fresh run the state at the peak
    is held at ``load_max`` until it rests (:func:`static_deflection`, on a copy that is put back);
    ``amplification`` = δ_peak/δ_static − 1 is returned and a :class:`RuntimeWarning` names ``steps_per_cycle``
    if it exceeds :data:`QUASI_STATIC_TOLERANCE` (NaN, with a warning, where the held beam collapses)."""
    load_min_ratio = _checked_cyclic(beam, load_max, load_min_ratio, jump, plasticity, settle, quasi_static_check)
    _check_counts(steps_per_cycle=steps_per_cycle, max_cycles=max_cycles, reference_cycles=reference_cycles,
                  max_simulated=max_simulated)
    check_range("life_ratio", life_ratio, 0.0, 1.0, low_open=True, high_open=True)
    if time_limit is not None:
        check_positive("time_limit", time_limit)
    sim = beam.sim
    saved = _resume(beam, checkpoint)
    record = RunRecord(COLUMNS, csv, None if saved is None else saved["record"])
    cycles = record.data["cycles"][-1] if len(record) else 0
    series = None if vtu is None else VtuSeries(vtu, "bonds")
    if series is not None:                 # a resumed run keeps the files it wrote before the interruption
        series.entries = [(float(n), f"bonds_{k:05d}.vtu") for k, n in enumerate(record.data["cycles"])]
    clock, stopped, simulated = time.perf_counter(), "max_cycles", 0
    earlier = 0.0 if saved is None else saved.get("seconds", 0.0)     # the calls before this one
    if saved is not None and saved.get("stopped"):  # a finished run read back from its checkpoint
        stopped, max_cycles = saved["stopped"], cycles
    phase = np.arange(1, steps_per_cycle + 1) / steps_per_cycle
    profile = load_min_ratio + (1.0 - load_min_ratio) * 0.5 * (1.0 - np.cos(2.0 * np.pi * phase))
    amplification = None
    while cycles < max_cycles:
        before = sim.fatigue_bonds.damage.copy()
        measured_at = cycles + 1
        counted, d_peak, yielding, measured = _cycle(
            beam, load_max, profile, jump=None if _settling(record.data["cycles"], settle) else jump,
            plasticity=plasticity, max_cycles=max_cycles - cycles, measure=quasi_static_check and measured_at == 1)
        cycles += counted
        amplification = amplification if measured is None else measured
        b = sim.fatigue_bonds
        modulus = float(flexural(load_max, d_peak, beam.spec)["modulus"])
        record.add(measured_at=measured_at, cycles=cycles, modulus=modulus, deflection=d_peak,
                   residual=beam.deflection(), damaged=int(np.sum(b.damage > 2 * b.params.initial_damage)),
                   yielding=yielding, broken=len(sim.cracks))
        if series is not None:
            _write_bonds(series, cycles, sim)
        simulated += 1
        ended = _ended(record.data, life_ratio, reference_cycles, beam.spec.height)
        if not ended and len(before) == len(b) and np.array_equal(before, b.damage):
            ended = "shakedown"              # a cycle that changed no damage repeats itself: nothing grows
        if checkpoint is not None:
            save_state(checkpoint, {"sim": sim.snapshot(), "record": record.data, "stopped": ended,
                                    "rollers": None if beam.rollers is None else beam.rollers.state(),
                                    "seconds": earlier + time.perf_counter() - clock})
        reason = ended or _interrupted(clock, time_limit, simulated, max_simulated)
        if reason:
            stopped = reason
            break
    record.close()
    out = record.arrays()
    out.update(life=int(out["measured_at"][-1]) if stopped == "life" else None, stopped=stopped,
               simulated_cycles=len(record), amplification=amplification,
               seconds=earlier + (0.0 if saved is not None and saved.get("stopped") else time.perf_counter() - clock))
    return out


def _checked_cyclic(beam, load_max, load_min_ratio, jump, plasticity, settle, quasi_static_check) -> float:
    """:func:`cyclic_bending`'s arguments checked at the door; returns ``load_min_ratio`` with its default."""
    check_positive("load_max", load_max)
    if load_min_ratio is None:
        load_min_ratio = 0.0 if beam.rollers is None else SEATING
    check_range("load_min_ratio", load_min_ratio, 0.0, 1.0, high_open=True)
    if jump is not None:
        check_positive("jump", jump)
    check_option("plasticity", plasticity, ("frozen", "extrapolated"))
    if not isinstance(quasi_static_check, bool):
        raise TypeError(f"quasi_static_check must be True or False, got {quasi_static_check!r}")
    if int(settle) != settle or settle < 0:
        raise ValueError(f"settle must be a whole number of cycles ≥ 0, got {settle!r}")
    if beam.control != "force":
        raise ValueError("cyclic_bending needs a beam built with control='force'")
    if beam.rollers is not None and load_min_ratio <= 0.0:
        raise ValueError("load_min_ratio must be > 0 with the 'rockers' fixture: one-sided rollers need a seating "
                         "load, or the unloaded beam leaves its supports (0.1, R = 0.1, is usual)")
    return load_min_ratio


def _check_counts(**counts) -> None:
    """Each count (``None`` where it is optional and absent) a whole number ≥ 1, or an error naming it."""
    for name, value in counts.items():
        if value is not None:
            check_integer(name, value, 1)


def _resume(beam: Beam, checkpoint) -> dict | None:
    """The state saved in ``checkpoint``, put into ``beam`` (None and the beam unchanged without one)."""
    saved = None if checkpoint is None else load_state(checkpoint)
    if saved is not None:
        sim = beam.sim
        kernel = sim.kernel                 # the state is the checkpoint's, how it is computed the beam's
        sim.restore(saved["sim"])
        sim.kernel = kernel
        if beam.rollers is not None:
            beam.rollers.restore(saved["rollers"])
    return saved


def _cycle(beam: Beam, load_max: float, profile: np.ndarray, *, jump, plasticity: str, max_cycles: int,
           measure: bool):
    """One simulated cycle through the loads ``load_max`` × ``profile`` [N], one per step; at its peak the bonds'
    fatigue update (with the cycle jump ``jump``, at most ``max_cycles`` cycles counted). Returns the cycles it
    counts, δ at the peak, the bonds that yielded in it and, with ``measure``, the dynamic amplification of the
    peak (else None)."""
    sim, peak_step = beam.sim, len(profile) // 2 - 1
    for k, level in enumerate(profile):
        beam.set_load(load_max * level)
        beam.step()
        if k == peak_step:
            d_peak = beam.deflection()
            amplification = _amplification(beam, load_max, d_peak, len(profile)) if measure else None
            yielding = int(sim.fatigue_bonds.yielded.sum())
            counted = sim.fatigue_bonds.onset_of_unloading(jump=jump, max_cycles=max_cycles, plasticity=plasticity)
    return counted, d_peak, yielding, amplification


def _interrupted(clock: float, time_limit, simulated: int, max_simulated) -> str | None:
    """"time_limit" or "max_simulated" once this call has run that long or simulated that many cycles."""
    if time_limit is not None and time.perf_counter() - clock > time_limit:
        return "time_limit"
    if max_simulated is not None and simulated >= max_simulated:
        return "max_simulated"
    return None


def _write_bonds(series: VtuSeries, cycles: int, sim: Simulation) -> None:
    """One VTU of the bonds (line cells between particle centres) with their state, at time = ``cycles``."""
    b = sim.fatigue_bonds
    series.write(cycles, sim.particles.x, [("line", np.column_stack([b.i, b.j]))],
                 point_data={"radius": sim.particles.radius},
                 cell_data={"damage": [b.damage], "fatigue_displacement": [b.fatigue.sum(axis=0)],
                            "plastic_displacement": [b.plastic.sum(axis=0)], "yielded": [b.yielded.astype(float)]})


QUASI_STATIC_TOLERANCE = 0.02
"""Largest dynamic amplification δ_peak/δ_static − 1 of a cycle's peak deflection that counts as quasi-static."""

FAILURE_SAG = 0.1
"""A beam whose mid-span deflection exceeds this fraction of its height has failed (the cyclic test stops with
"failed"; held under a load it has no static state)."""


@number_arguments
def static_deflection(beam: Beam, load: float, *, block: int = 250, rtol: float = 1e-4,
                      max_steps: int = 40_000) -> float:
    """Mid-span deflection [m] of ``beam`` (force control) at rest under the constant ``load`` [N], starting from
    its present state, which is left unchanged: the simulation (and the rocker pads) are copied, stepped under the
    held load in blocks of ``block`` steps until δ changes by less than ``rtol`` of itself over a block (the local
    damping removes the motion), and put back. A beam that breaks a bond or sinks by :data:`FAILURE_SAG` of its
    height under the held load has no static state there: :class:`RuntimeError` says so."""
    if not isinstance(beam, Beam):
        raise TypeError(f"beam must be a Beam (four_point_beam), got {type(beam).__name__}")
    check_positive("load", load)
    check_positive("rtol", rtol)
    check_range("block", block, 1, None)
    check_range("max_steps", max_steps, 1, None)
    if beam.control != "force":
        raise ValueError("static_deflection needs a beam built with control='force'")
    sim, rollers = beam.sim, beam.rollers
    saved, saved_rollers = sim.snapshot(), None if rollers is None else rollers.state()
    try:
        beam.set_load(load)
        previous, steps, cracks = beam.deflection(), 0, len(sim.cracks)
        while steps < max_steps:
            beam.step(block)
            steps += block
            now = beam.deflection()
            if len(sim.cracks) > cracks or now > FAILURE_SAG * beam.spec.height:
                raise RuntimeError(f"the beam does not rest under {load:g} N: held there, it collapses ("
                                   f"{len(sim.cracks) - cracks} bonds broken, deflection {now:.3g} m after {steps} "
                                   f"steps)")
            if abs(now - previous) <= rtol * abs(now):
                return float(now)
            previous = now
        raise RuntimeError(f"the beam did not come to rest under {load:g} N within max_steps = {max_steps} steps "
                           f"(deflection still changing by {abs(now - previous):.2e} m per {block} steps)")
    finally:
        sim.restore(saved)
        if rollers is not None:
            rollers.restore(saved_rollers)


def _amplification(beam: Beam, load: float, peak: float, steps_per_cycle: int) -> float:
    """δ_peak/δ_static − 1 of the first cycle, with a warning naming ``steps_per_cycle`` beyond the tolerance (NaN
    and a warning if the beam has no static state under the peak load)."""
    try:
        amplification = peak / static_deflection(beam, load) - 1.0
    except RuntimeError as collapse:
        warnings.warn(f"the dynamic amplification could not be measured: {collapse}", RuntimeWarning, stacklevel=4)
        return float("nan")
    if abs(amplification) > QUASI_STATIC_TOLERANCE:
        warnings.warn(f"the cycle is not quasi-static: its peak deflection is {100 * amplification:+.1f} % off the "
                      f"static one (tolerance {100 * QUASI_STATIC_TOLERANCE:g} %); raise steps_per_cycle "
                      f"(now {steps_per_cycle})", RuntimeWarning, stacklevel=4)
    return amplification


def measured_cycles(cycles: ArrayLike) -> np.ndarray:
    """The cycle in which each simulated cycle's E_f was measured, from ``cycles`` (the counts after each simulated
    cycle's fatigue update, as :func:`cyclic_bending` records them): one after the count before it. For records
    written before the ``measured_at`` column existed."""
    cycles = np.asarray(cycles, dtype=np.int64)
    if cycles.ndim != 1 or np.any(np.diff(cycles) < 1) or (cycles.size and cycles[0] < 1):
        raise ValueError("cycles must be a rising sequence of cycle counts ≥ 1, one per simulated cycle")
    return np.concatenate([[1], cycles[:-1] + 1]) if cycles.size else cycles


STAGES = (0.1, 0.9)
"""Bounds of the three stages of the modulus degradation as fractions N/N_f of the life (initial, middle, final):
the paper names the stages and shows them (Fig. 17a) without bounds (decision "three stages of the modulus
degradation")."""


def stage_slopes(measured_at: ArrayLike, modulus_ratio: ArrayLike, life: float, bounds=STAGES) -> dict:
    """Slopes d(E_f/E_f,0)/d(N/N_f) of the initial, middle and final stage of a fatigue run: least-squares lines
    through the points (``measured_at`` / ``life``, ``modulus_ratio``) with N/N_f in [0, b₁], [b₁, b₂] and [b₂, 1]
    (``bounds`` = (b₁, b₂), :data:`STAGES`); NaN for a stage with fewer than two distinct points. ``initial_over_
    middle`` says whether the degradation starts fast, as the paper's first stage does."""
    n, ratio = (np.asarray(check_finite(name, v), float) for name, v in (("measured_at", measured_at),
                                                                         ("modulus_ratio", modulus_ratio)))
    if n.ndim != 1 or n.shape != ratio.shape:
        raise ValueError(f"measured_at and modulus_ratio must be 1-D of one length, got {n.shape} and {ratio.shape}")
    if np.unique(n).size < 2 or n.min() < 0:
        raise ValueError(f"measured_at must hold cycle counts >= 0, at least two distinct, got {measured_at!r}")
    check_positive("life", life)
    low, high = (float(b) for b in bounds)
    if not 0.0 < low < high < 1.0:
        raise ValueError(f"bounds must be two fractions 0 < b1 < b2 < 1, got {bounds!r}")
    x = n / life
    slopes = {}
    for stage, (a, b) in {"initial": (0.0, low), "middle": (low, high), "final": (high, 1.0)}.items():
        inside = (x >= a) & (x <= b)
        slopes[stage] = float(np.polyfit(x[inside], ratio[inside], 1)[0]) if np.unique(x[inside]).size > 1 \
            else float("nan")
    slopes["initial_over_middle"] = slopes["initial"] / slopes["middle"] if slopes["middle"] else float("nan")
    return slopes


def _settling(cycles, settle: int) -> bool:
    """True while fewer than ``settle`` single cycles have followed the last cycle jump in the record ``cycles``."""
    steps = np.diff(np.concatenate([[0], cycles])).astype(int)
    if settle <= 0 or not np.any(steps > 1):
        return False
    return int(np.argmax(steps[::-1] != 1)) < settle


def _ended(history: dict, life_ratio: float, reference_cycles: int, height: float) -> str | None:
    """"life" if the last E_f has fallen to ``life_ratio`` × E_f,0 (the mean up to ``reference_cycles``), "failed"
    if it is not finite or the deflection exceeds :data:`FAILURE_SAG` of the ``height``, else None."""
    early = [m for m, n in zip(history["modulus"], history["measured_at"], strict=True) if n <= reference_cycles]
    reference = float(np.mean(early or history["modulus"][:1]))
    modulus, deflection = history["modulus"][-1], history["deflection"][-1]
    if modulus <= life_ratio * reference:
        return "life"
    if not np.isfinite(modulus) or deflection > FAILURE_SAG * height:
        return "failed"
    return None
