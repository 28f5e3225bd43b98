"""Poly-disperse disk packings: Fuller's grading, the genesis at a small confining stress, the graded beam."""

import time

import numpy as np
import pytest

from abrakit.experiments.bending import BeamSpec, four_point_beam
from abrakit.experiments.disk_packing import disk_packing, fuller_passing, fuller_radii


def test_fuller_radii_follow_the_grading_by_area_and_fill_the_requested_area():
    rng = np.random.default_rng(3)
    area = 4000 * np.pi * 2e-3**2
    r = fuller_radii(rng, 1e-3, 4e-3, area)
    assert r.min() >= 1e-3 and r.max() <= 4e-3
    total = np.pi * np.cumsum(r**2)
    assert total[-1] >= area > total[-2]                     # stops at the first disk that reaches the area
    order = np.argsort(r)
    empirical = np.cumsum(np.pi * r[order] ** 2) / total[-1]  # area fraction finer than r (Kolmogorov–Smirnov)
    assert np.max(np.abs(empirical - fuller_passing(r[order], 1e-3, 4e-3))) < 0.03
    assert fuller_passing(2.5e-3, 1e-3, 4e-3) == pytest.approx((2.5**0.5 - 1) / (2 - 1))
    with pytest.raises(ValueError, match="largest"):
        fuller_radii(rng, 2e-3, 1e-3, area)
    with pytest.raises(ValueError, match="exponent"):
        fuller_passing(1e-3, 1e-3, 2e-3, exponent=2.5)


def test_disk_packing_settles_jammed_at_the_requested_stress():
    rng = np.random.default_rng(0)
    size = np.array([0.06, 0.03])
    radii = fuller_radii(rng, 1.5e-3, 3e-3, 0.85 * size.prod())
    out = disk_packing(size, radii, rng, modulus=1e9, thickness=0.05, stress=2e3)
    assert out["stress"] == pytest.approx(2e3, rel=0.2)
    assert 0.75 < out["solid_fraction"] < 0.88
    x, r = out["xy"], out["radius"]
    assert np.all(x - r[:, None] > -1e-3 * r.min()) and np.all(x + r[:, None] < size + 1e-3 * r.min())
    d = np.linalg.norm(x[:, None] - x[None], axis=-1) + np.eye(len(x))
    overlap = (r[:, None] + r[None] - d) / r.min()
    assert overlap.max() < 1e-3                             # 2 kPa against 1 GPa: contacts barely touch
    with pytest.raises(ValueError, match="size"):
        disk_packing([0.1, 0.1, 0.1], radii, rng, modulus=1e9, thickness=0.05, stress=1e3)
    with pytest.raises(RuntimeError, match="did not settle"):                  # no shrinking allowed: a message
        disk_packing(size, radii, np.random.default_rng(1), modulus=1e9, thickness=0.05, stress=2e3, max_rounds=0)


def test_a_graded_beam_spec_refuses_an_unknown_grading_or_a_radius_ratio_of_one():
    with pytest.raises(ValueError, match="grading"):
        BeamSpec(grading="sieve")
    with pytest.raises(ValueError, match="radius_ratio"):
        BeamSpec(radius_ratio=1.0)


@pytest.mark.slow
def test_graded_beam_is_bonded_nearly_stress_free_and_cached(tmp_path, monkeypatch):
    """Slow (a genesis and a relaxation from an empty cache, 50–90 s: the longest test of ``make test`` until it was
    marked; the bending chapter builds the same beam in every book build)."""
    monkeypatch.setenv("ABRAKIT_CACHE", str(tmp_path))
    spec = BeamSpec(radius=6e-3, grading="fuller")
    beam = four_point_beam(spec, fixture="pads")
    b, p = beam.sim.fatigue_bonds, beam.sim.particles
    assert np.all(np.bincount(np.concatenate([b.i, b.j]), minlength=len(p)) > 0)   # no loose disks
    assert 150 < len(p) < 300 and 2 * len(b) / len(p) > 3.0                      # coordination of the bonds
    assert p.radius.min() >= spec.radius / spec.radius_ratio * 0.95
    assert np.abs(b.sigma).max() < 0.1 * 74e3 and not np.any(b.plastic > 0)          # locked-in stress is small
    assert len(beam.supports) >= 2 and len(beam.loading) >= 2 and len(beam.mid_bottom) >= 1
    assert len(list(tmp_path.rglob("beam_*.pkl"))) == 1
    tic = time.perf_counter()
    again = four_point_beam(spec, fixture="pads")
    assert np.array_equal(again.sim.particles.x, p.x) and time.perf_counter() - tic < 0.5 * 60
