"""The stored removal study (``benchmarks/bench_scratch_removal.py``, its ``scratch_removal.json``) against the
physics it must show and the literature it is held against.

- every stored run closes its volume budget with erosion to round-off;
- rounded tips at low penetration remove nothing (removal f_ab below 0.03 for D_p ≤ 0.1 at μ = 0.1), and removal
  does not fall as the penetration rises;
- the G65 grains' D_p under the balanced load lies far below the map's first point (so the map's smallest D_p is
  the value the balanced loss takes);
- Hokkirigawa and Kato's cutting transition (removal f_ab = 0.1 at D_p within 0.1–0.3, earlier with more friction)
  is *not* reproduced by the erosion model at 4340's ductility: a strict expected failure with the measured reason,
  so that a model that does reproduce it turns the suite red until the record is updated.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from abrakit import g65

STORED = Path(__file__).resolve().parents[1] / "benchmarks" / "results" / "scratch_removal.json"


@pytest.fixture(scope="module")
def study():
    if not STORED.exists():
        pytest.skip("the removal study is not stored (python benchmarks/bench_scratch_removal.py)")
    return json.loads(STORED.read_text())


def series(study, tip, mu):
    rows = [r for r in study["runs"].values()
            if r["finished"] and r["tip"] == tip and r["mu"] == mu and r["mesh"] == study["map_mesh"]]
    return sorted(rows, key=lambda r: r["D_p"])


def test_every_stored_run_closes_its_budget_with_erosion(study):
    finished = [r for r in study["runs"].values() if r["finished"]]
    assert len(finished) >= 8
    assert max(r["worst_residual_rel"] for r in finished) <= 1e-6


def test_rounded_tips_at_low_penetration_remove_nothing_and_removal_does_not_fall_with_penetration(study):
    spheres = series(study, "sphere", 0.1)
    assert spheres and spheres[0]["D_p"] <= 0.1 + 1e-9
    assert all(r["removal_f_ab"] < 0.03 for r in spheres if r["D_p"] <= 0.1 + 1e-9)
    assert all(r["eroded"] == 0 for r in spheres if r["D_p"] <= 0.3 + 1e-9)     # plowing up to D_p = 0.3
    f_ab = [r["removal_f_ab"] for r in spheres]
    assert f_ab[-1] > f_ab[0] and f_ab[-1] == max(f_ab)


def test_the_g65_grains_sit_far_below_the_maps_first_point(study):
    first = series(study, "sphere", 0.1)[0]["D_p"]
    for D in (212e-6, 256e-6, 300e-6):
        loss = g65.balanced_loss(D, g65.STEEL_CONTACT_PRESSURE, np.zeros_like)
        assert loss.depth_ratio.max() < 0.1 * first


@pytest.mark.xfail(strict=True, reason="measured: at 4340's ductility (eps_f 1.75 in tension, 3.49 in shear) the "
                   "spheres at mu = 0.1 reach removal f_ab = 0.1 only at D_p = 0.45, above Hokkirigawa and Kato's "
                   "cutting band 0.2-0.3; the erosion model removes a few elements per 30 um slide there")
def test_the_cutting_transition_lies_in_hokkirigawa_and_katos_band(study):
    low, high = study["hokkirigawa_kato_bands"][0][0], study["hokkirigawa_kato_bands"][1][1]
    assert low <= study["transition_D_p"]["mu0.1"] <= high
