"""Contacting particles (Ch. 8.3, abrakit.experiments.contacting): exact counts on hand-built layers, wall zones,
a small pressed bed, exact similarity in D and L, and the fits of Eq. (8.7) and (8.10)–(8.12)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.dem import Particles, Simulation, Walls
from abrakit.experiments.contacting import (
    SEED_COEFFICIENT,
    contact_census,
    contacting_case,
    count_touching,
    fit_contact_coefficient,
    fit_mixture_exponent,
    floor_profile,
    loose_column,
    pressed_bed,
    seed_exponents,
    touching_mask,
    unbalanced_force_ratio,
)
from abrakit.wear import contacting_particles, contacting_particles_mixture

D = 1e-3
FLOOR = ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))


def square_layer(m, spacing=D, z=D / 2):
    """m × m spheres of diameter D on a square lattice, contact points at ((i + ½) a, (j + ½) a)."""
    i, j = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
    return np.column_stack([(i.ravel() + 0.5) * spacing, (j.ravel() + 0.5) * spacing, np.full(m * m, z)])


def hexagonal_layer(m, rows):
    """``rows`` rows of m touching spheres, alternate rows shifted by D/2: areal density 2/(√3 D²)."""
    j, i = np.meshgrid(np.arange(rows), np.arange(m), indexing="ij")
    x = (i + np.where(j % 2, 0.75, 0.25)) * D
    y = (j + 0.5) * np.sqrt(3) / 2 * D
    return np.column_stack([x.ravel(), y.ravel(), np.full(x.size, D / 2)])


# --- the count on hand-built layers -------------------------------------------------------------------------


@pytest.mark.parametrize("k", [1, 3, 7])
def test_square_layer_counts_exactly_one_grain_per_d_squared(k):
    x = square_layer(8)
    window = ((0, 0, -np.inf), (k * D, k * D, np.inf))
    assert count_touching(x, D / 2, FLOOR, 1e-9, window) == k * k      # N_c D² = 1 exactly
    assert count_touching(x, D / 2, FLOOR, 1e-9) == 64


@pytest.mark.parametrize(("m", "pairs"), [(4, 1), (6, 3), (10, 5)])
def test_hexagonal_layer_gives_two_over_root_three(m, pairs):
    x = hexagonal_layer(m, 2 * pairs + 3)
    height = 2 * pairs * np.sqrt(3) / 2 * D
    n = count_touching(x, D / 2, FLOOR, 1e-9, ((0, 0, -1), (m * D, height, 1)))
    assert n == 2 * pairs * m
    assert n / (m * D * height) * D**2 == pytest.approx(2 / np.sqrt(3), rel=1e-12)


def test_only_grains_within_the_tolerance_touch():
    """A second layer resting in the pockets, and grains lifted just below / above the tolerance."""
    first = square_layer(4)
    pockets = square_layer(3, z=D / 2 + D / np.sqrt(2)) + [D / 2, D / 2, 0.0]   # on four grains each
    tol = 1e-3 * D
    lifted = np.array([[10 * D, 0.5 * D, D / 2 + 0.999 * tol], [12 * D, 0.5 * D, D / 2 + 1.001 * tol],
                       [14 * D, 0.5 * D, D / 2 - 1e-2 * D]])                     # the last one overlaps the face
    x = np.vstack([first, pockets, lifted])
    mask = touching_mask(x, D / 2, FLOOR, tol)
    assert mask.tolist() == [True] * 16 + [False] * 9 + [True, False, True]
    assert count_touching(x, D / 2, FLOOR, 0.0) == 17                             # tol = 0: gap ≤ 0 only


def test_any_plane_orientation_and_per_grain_radii():
    """The hexagonal layer turned onto the wall x = 5 mm (normal −x), with mixed radii, counts the same."""
    x = hexagonal_layer(6, 6)
    radii = np.where(np.arange(len(x)) % 2, D / 2, D / 4)
    x[:, 2] = radii                                                              # small grains touch as well
    turned = np.column_stack([5e-3 - x[:, 2], x[:, 0], x[:, 1]])
    wall = ((5e-3, 0.0, 0.0), (-3.0, 0.0, 0.0))                                  # any length of normal
    window = ((-np.inf, 0.0, 0.0), (np.inf, 6 * D, 4 * np.sqrt(3) / 2 * D))
    assert count_touching(turned, radii, wall, 1e-9, window) == count_touching(
        x, radii, FLOOR, 1e-9, ((0, 0, -1), (6 * D, 4 * np.sqrt(3) / 2 * D, 1))) == 24


def test_bad_input_is_refused_with_the_parameter_named():
    x = square_layer(2)
    with pytest.raises(ValueError, match="behind the plane"):
        count_touching(x - [0, 0, D], D / 2, FLOOR, 0.0)
    with pytest.raises(ValueError, match="tol"):
        count_touching(x, D / 2, FLOOR, -1e-9)
    with pytest.raises(ValueError, match="radii"):
        count_touching(x, 0.0, FLOOR, 0.0)
    with pytest.raises(ValueError, match="window"):
        count_touching(x, D / 2, FLOOR, 0.0, ((1, 1, 1), (0, 0, 0)))
    with pytest.raises(ValueError, match="normal"):
        count_touching(x, D / 2, ((0, 0, 0), (0, 0, 0)), 0.0)
    with pytest.raises(TypeError, match="plane"):
        count_touching(x, D / 2, (0, 0, 1), 0.0)


def box_with_wall_rows(L_over_D=10):
    """A square box floor: an interior square lattice (pitch 1.25 D) plus a dense row of grains along each side
    wall, 0.5 D from it — wall layering by hand. Returns the simulation and the interior grain count."""
    L = L_over_D * D
    interior = square_layer(6, spacing=1.25 * D) + [1.25 * D, 1.25 * D, 0.0]     # contact points 1.875 … 8.125 D
    along = (np.arange(1, L_over_D) + 0.0) * D
    rows = [np.column_stack([along, np.full_like(along, D / 2), np.full_like(along, D / 2)]),
            np.column_stack([along, np.full_like(along, L - D / 2), np.full_like(along, D / 2)]),
            np.column_stack([np.full_like(along, D / 2), along, np.full_like(along, D / 2)]),
            np.column_stack([np.full_like(along, L - D / 2), along, np.full_like(along, D / 2)])]
    x = np.vstack([interior] + rows)
    keep = np.ones(len(x), bool)                       # drop the corner duplicates of the four rows
    _, first = np.unique(np.round(x / D, 6), axis=0, return_index=True)
    keep[:] = False
    keep[first] = True
    sim = Simulation(Particles.spheres(x[keep], D / 2, kn=1e4, friction=0.0),
                     walls=Walls.box((0, 0, 0), (L, L, 3 * D)))
    return sim, len(interior)


def test_wall_zones_are_excluded_from_the_census():
    sim, interior = box_with_wall_rows()
    whole = contact_census(sim, wall_zone=0.0, tol=1e-9)
    census = contact_census(sim, wall_zone=D, tol=1e-9)
    assert census["all"]["count"] == interior == 36
    assert census["area"] == pytest.approx((8 * D) ** 2)
    assert whole["all"]["count"] == len(sim.particles) > interior
    assert census["all"]["N_c_D2"] == pytest.approx(36 / 64)
    profile = floor_profile(sim, bin_width=0.5 * D, tol=1e-9)
    assert profile["count"][1] == len(sim.particles) - interior                # all wall rows at 0.5 D
    assert profile["count"].sum() == len(sim.particles)
    with pytest.raises(ValueError, match="wall_zone"):
        contact_census(sim, wall_zone=5 * D, tol=0.0)


# --- the bed ------------------------------------------------------------------------------------------------


def test_loose_column_places_grains_without_overlap_inside_the_box():
    rng = np.random.default_rng(1)
    radii = np.concatenate([np.full(30, 0.5), np.full(400, 0.5 / 3)])
    x = loose_column(radii, (0, 0, 0), (5, 5, 6), rng)
    assert np.all(x - radii[:, None] >= 0) and np.all(x + radii[:, None] <= [5, 5, 6])
    i, j = np.triu_indices(len(x), 1)
    assert np.all(np.linalg.norm(x[i] - x[j], axis=1) >= radii[i] + radii[j])
    with pytest.raises(ValueError, match="too full"):
        loose_column(np.full(200, 0.5), (0, 0, 0), (4, 4, 4), rng, max_rounds=20)


def test_unbalanced_force_ratio_vanishes_at_rest_and_is_infinite_in_free_fall():
    g, k = 9.81, 1e4
    resting = Particles.spheres([[0, 0, 0]], D / 2, kn=k)
    resting.x[0, 2] = D / 2 - resting.mass[0] * g / k                          # equilibrium overlap m g / k
    floor = Walls()
    floor.add((0, 0, 0), (0, 0, 1))
    sim = Simulation(resting, walls=floor, gravity=(0, 0, -g), dt=1e-6)
    sim.step()
    assert unbalanced_force_ratio(sim) < 1e-9
    falling = Simulation(Particles.spheres([[0, 0, 1.0]], D / 2, kn=k), walls=floor, gravity=(0, 0, -g))
    falling.step()
    assert unbalanced_force_ratio(falling) == np.inf


@pytest.fixture(scope="module")
def small_bed():
    return pressed_bed(D, box=6 * D, layers=3, seed=0)


def test_a_small_pressed_bed_is_in_equilibrium_and_dense(small_bed):
    sim, bed = small_bed
    assert bed["converged"] and bed["unbalanced"] < 1e-3
    assert bed["plate_stress_ratio"] == pytest.approx(1.0, abs=1e-3)
    assert 0.55 < bed["solid_fraction"] < 0.66                                 # random packing, frictionless
    assert 0.1e-2 < bed["floor_overlap"] < 1e-2                                # ≈ ε/2 with ε = 10⁻²


def test_the_count_agrees_with_the_engines_own_floor_contacts(small_bed):
    """tol = 0 counts exactly the grains whose floor contact carries force (independent implementation)."""
    sim, _ = small_bed
    floor = sim.walls.index("zmin")
    c = sim.wall_contacts
    carrying = np.unique(c.j[(c.i == floor) & (c.overlap > 0)])
    assert count_touching(sim.particles.x, sim.particles.radius, FLOOR, 0.0) == len(carrying)
    assert contact_census(sim, wall_zone=0.0, tol=0.0)["all"]["count"] == len(carrying)


def test_a_small_pressed_bed_gives_eq_8_7_within_its_sampling_band(small_bed):
    """16 D² of window hold ≈ 16 grains. The benchmark's beds of this size give N_c D² = 1.04 ± 0.04 (mean ± std
    over seeds; frictionless, ε = 10⁻²: 15 % above the seed's 0.9, see the chapter), so this bed must lie within
    4 std of 1.04, and within 0.9 ± 0.25 of Eq. (8.7). Counting nothing, or every grain twice, falls outside."""
    sim, _ = small_bed
    census = contact_census(sim, wall_zone=D, tol=1e-3 * D)
    assert census["area"] == pytest.approx(16 * D**2)
    assert abs(census["all"]["N_c_D2"] - 1.04) < 0.15
    assert abs(census["all"]["N_c_D2"] - SEED_COEFFICIENT) < 0.25
    assert census["all"]["N_c"] == pytest.approx(census["all"]["N_c_D2"] * contacting_particles(D) / 0.9)
    tolerances = [contact_census(sim, wall_zone=D, tol=t * D)["all"]["count"] for t in (0.0, 1e-3, 1e-2)]
    assert len(set(tolerances)) == 1                                           # gaps are bimodal


def test_exact_similarity_doubling_d_and_l_gives_the_same_bed():
    """With every dimensionless group held, the seed's "D in a fixed box" is the same experiment as "L at fixed
    D": doubling all lengths doubles every position to the bit and leaves the count unchanged."""
    one, bed_one = pressed_bed(D, box=4 * D, layers=2, seed=3, kernel="numpy")
    two, bed_two = pressed_bed(2 * D, box=8 * D, layers=2, seed=3, kernel="numpy")
    assert bed_one["steps"] == bed_two["steps"]
    np.testing.assert_array_equal(2 * one.particles.x, two.particles.x)
    assert (contact_census(one, wall_zone=D, tol=1e-6)["all"]["N_c_D2"]
            == contact_census(two, wall_zone=2 * D, tol=2e-6)["all"]["N_c_D2"])


def test_shaking_moves_the_side_walls_and_brings_them_back(monkeypatch):
    """``shake``: both x walls move together by ``shake`` D per half period, as many periods as asked, and end where
    they started; the shaken bed is another packing, still pressed to equilibrium. ``shake=0`` is the plain run."""
    from abrakit.dem import Simulation

    positions, run = [], Simulation.run

    def watched(self, steps, **kw):
        out = run(self, steps, **kw)
        positions.append(self.walls.point[[self.walls.index("xmin"), self.walls.index("xmax")], 0].copy())
        return out

    monkeypatch.setattr(Simulation, "run", watched)
    shaken, bed = pressed_bed(D, box=4 * D, layers=2, seed=3, kernel="numpy", shake=0.1, shake_cycles=2)
    monkeypatch.undo()
    home = np.array([0.0, 4 * D])
    np.testing.assert_allclose(positions[9] - home, 0.1 * D, rtol=0.01)          # +0.1 D, both walls, in 200 steps
    np.testing.assert_allclose(positions[19] - home, 0.0, atol=1e-3 * D)         # and back
    np.testing.assert_allclose(positions[39] - home, 0.0, atol=1e-3 * D)         # two periods
    walls = shaken.walls
    assert walls.point[walls.index("xmin"), 0] == 0.0 and walls.point[walls.index("xmax"), 0] == 4 * D
    assert bed["converged"]
    plain, _ = pressed_bed(D, box=4 * D, layers=2, seed=3, kernel="numpy")
    same, _ = pressed_bed(D, box=4 * D, layers=2, seed=3, kernel="numpy", shake=0.0)
    np.testing.assert_array_equal(plain.particles.x, same.particles.x)
    assert not np.array_equal(plain.particles.x, shaken.particles.x)
    with pytest.raises(ValueError, match="shake"):
        pressed_bed(D, box=4 * D, shake=-0.1)


def test_pressed_bed_input_checks():
    with pytest.raises(ValueError, match="box"):
        pressed_bed(D, box=2 * D)
    with pytest.raises(ValueError, match="fine_diameter"):
        pressed_bed(D, box=6 * D, fine_diameter=2 * D, theta_coarse=0.5)
    with pytest.raises(ValueError, match="theta_coarse"):
        pressed_bed(D, box=6 * D, theta_coarse=0.5)
    with pytest.raises(ValueError, match="overlap"):
        pressed_bed(D, box=6 * D, overlap=0.5)
    with pytest.raises(ValueError, match="unknown case parameter"):
        contacting_case({"diameter": D, "box": 6 * D, "pressure_kPa": 10})


def test_a_small_mixture_case_counts_both_grain_types():
    out = contacting_case({"diameter": D, "box": 5 * D, "fine_diameter": D / 2, "theta_coarse": 0.5,
                           "layers": 2, "seed": 0})
    census = out["census"]
    assert census["coarse"]["count"] > 0 and census["fine"]["count"] > 0
    assert census["coarse"]["count"] + census["fine"]["count"] == census["all"]["count"]
    assert census["fine"]["diameter"] == pytest.approx(D / 2)
    assert out["bed"]["theta_coarse_actual"] == pytest.approx(0.5, abs=0.05)


# --- the fits -----------------------------------------------------------------------------------------------


def test_seed_exponents_reproduce_eq_8_12_of_the_wear_module():
    D_A, D_B, theta = 200e-6, 100e-6, np.array([0.1, 0.3, 0.7, 0.9])
    alpha_A, alpha_B = seed_exponents(D_A / D_B)
    assert (alpha_A, alpha_B) == (1.5, 0.5)
    N_A, N_B = contacting_particles_mixture(D_A, D_B, theta)
    np.testing.assert_allclose(N_A, 0.9 * theta**alpha_A / D_A**2, rtol=1e-14)
    np.testing.assert_allclose(N_B, 0.9 * (1 - theta) ** alpha_B / D_B**2, rtol=1e-14)
    assert seed_exponents(1.0) == (1.0, 1.0)
    with pytest.raises(ValueError, match="ratio"):
        seed_exponents(0.5)


def test_fit_contact_coefficient_recovers_eq_8_7():
    d_over_l = 1 / np.array([6, 8, 12, 16, 24.0])
    fit = fit_contact_coefficient(d_over_l, 0.9 * d_over_l**-2)
    assert fit["a"] == pytest.approx(0.9, rel=1e-12) and fit["a_spread"] == pytest.approx(0, abs=1e-12)
    assert fit["beta"] == pytest.approx(-2, rel=1e-12) and fit["a_free"] == pytest.approx(0.9, rel=1e-10)
    fit = fit_contact_coefficient(d_over_l, 0.9 * d_over_l**-2 * np.array([1.1, 0.9, 1.1, 0.9, 1.0]))
    assert 0.85 < fit["a"] < 0.95 and fit["a_spread"] > 0.05
    with pytest.raises(ValueError, match="matching"):
        fit_contact_coefficient([1.0], [1.0])


@settings(max_examples=30, deadline=None)
@given(alpha=st.floats(0.2, 2.5), a=st.floats(0.5, 1.2), fixed=st.booleans())
def test_fit_mixture_exponent_recovers_exact_data(alpha, a, fixed):
    theta = np.array([0.1, 0.25, 0.5, 0.75, 0.9])
    area, diameter = 36e-6, np.full(5, 1e-3)
    expected = a * theta**alpha * area / diameter**2
    fit = fit_mixture_exponent(theta, expected, area, diameter, a=a if fixed else None)
    assert fit["alpha"] == pytest.approx(alpha, abs=1e-8)
    assert fit["a"] == pytest.approx(a, rel=1e-8)


def test_fit_mixture_exponent_on_poisson_counts_lands_within_its_standard_error():
    rng = np.random.default_rng(7)
    theta = np.tile([0.1, 0.25, 0.5, 0.75, 0.9], 40)
    area, diameter = 100e-6, np.full(theta.shape, 1e-3)
    counts = rng.poisson(0.9 * theta**1.5 * area / diameter**2)
    for a in (None, 0.9):
        fit = fit_mixture_exponent(theta, counts, area, diameter, a=a)
        assert abs(fit["alpha"] - 1.5) < 3 * fit["alpha_stderr"] < 0.1
    with pytest.raises(ValueError, match="zero"):
        fit_mixture_exponent(theta[:3], [0, 0, 0], area, diameter[:3])
    with pytest.raises(ValueError, match="two different"):
        fit_mixture_exponent([0.5, 0.5], [3, 4], area, [1e-3, 1e-3])
