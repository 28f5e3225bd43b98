"""The fatigue beam of the convergence study runs to its life at the default settings (a slow study)."""

from __future__ import annotations

import warnings

import pytest

from abrakit.experiments import BeamSpec, cyclic_bending, four_point_beam, monotonic_bending

SCHEDULE = ((0.003, 10), (0.01, 6), (0.02, None))
"""ΔD_jump 0.003 for ten simulated cycles, 0.01 for six, then 0.02 (``benchmarks/bench_fatigue_convergence.py``)."""


@pytest.mark.slow
def test_the_small_rocker_beam_at_86_percent_runs_to_its_life_at_the_default_steps(tmp_path):
    """98 disks, 245 bonds, force control at 0.86 P_max, ratcheting extrapolated with one settling cycle, the jump
    schedule in stages resumed from a checkpoint: the run reaches its life (E_f/E_f,0 ≤ 0.5) without an exception.
    It used to stop on a bond at D = 1 − 2·10⁻⁶ whose return "did not converge" (decision "failure damage of a
    bond")."""
    spec = BeamSpec(radius=5e-3, seed=3)
    p_max = float(monotonic_bending(four_point_beam(spec), speed=1e-3, drop=0.9)["load"].max())
    beam = four_point_beam(spec, control="force")
    checkpoint, done, bound = tmp_path / "run.pkl", 0, 0
    for jump, count in SCHEDULE:
        bound = None if count is None else bound + count
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            r = cyclic_bending(beam, 0.86 * p_max, jump=jump, plasticity="extrapolated", settle=1,
                               max_cycles=1_000_000, checkpoint=checkpoint,
                               max_simulated=None if bound is None else bound - done)
        done = len(r["cycles"])
        if r["stopped"] != "max_simulated":
            break
    assert r["stopped"] == "life" and r["life"] > 1000
    assert r["modulus"][-1] <= 0.5 * r["modulus"][0]
