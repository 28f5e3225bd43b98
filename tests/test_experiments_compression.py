"""DEM compression experiments (Ch. 5.3–5.4): genesis, the three measurement schemes, E and ν, the rate check,
Table 5.3 bond strengths; plus exact checks of the measurement helpers on hand-built scenes.

The DEM tests share one small specimen (300 spheres, seed 0), generated once per session into a temporary cache
(about 20 s), and run small-strain tests of a few seconds each. Reference values of large specimens come from the
benchmark ``benchmarks/bench_experiments_elastic.py`` (see ``LARGE``)."""

import numpy as np
import pytest

from abrakit.dem import Particles, Simulation, Walls, unbalanced_force_ratio
from abrakit.dem.measure import love_weber_stress
from abrakit.experiments import closed_form_checks as cfc
from abrakit.experiments.compression import (
    CompressionCurve,
    best_fit_gradient,
    crack_initiation_stress,
    elastic_moduli,
    elastic_test,
    sphere_stress,
)
from abrakit.experiments.specimen import (
    CLUMP_MEMBER_RADIUS,
    DemMaterial,
    DemSpecimen,
    SpecimenSpec,
    genesis,
    members,
)

# E [Pa] and ν of large specimens (wall scheme): mean of five 2400-sphere specimens (seeds 0-4), σ_c = 1 MPa,
# Table 5.4 micro-parameters; benchmarks/bench_experiments_elastic.py (elastic version 3), JSON entry
# elastic.<kind>.large, run of 2026-11-22T01:46Z. Seed-to-seed spread at N = 2400: ±1.5 % in E, ±0.005 in ν.
LARGE = {
    "granular": {"E": 33.57e9, "nu": 0.2260},
    "bonded": {"E": 36.42e9, "nu": 0.2151},
}

SPEC = SpecimenSpec(n_particles=300, seed=0)


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("specimens")


@pytest.fixture(scope="module")
def specimen(cache):
    return genesis(SPEC, cache=cache)


@pytest.fixture(scope="module")
def granular(specimen):
    return elastic_test(specimen, SPEC.material())


@pytest.fixture(scope="module")
def bonded(specimen):
    return elastic_test(specimen, SPEC.material().with_bonds(1e30, 1e30))


# ---------------------------------------------------------------------------------------------- helpers, exact
def lattice(n=6, radius=1e-3, squeeze=1e-6, kn=1e6):
    """A simple cubic lattice of n³ touching spheres (overlap ``squeeze``·2r) in a box whose walls touch it."""
    a = 2 * radius * (1 - squeeze)
    g = np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), -1).reshape(-1, 3)
    x = radius + g * a
    p = Particles.spheres(x, radius, kn=kn, friction=0.5)
    upper = x.max(axis=0) + radius * (1 - squeeze)
    walls = Walls.box(np.full(3, radius * squeeze), upper)
    sim = Simulation(p, walls=walls, track_energy=False)
    sim.run(1, progress=False)
    return sim


def test_contact_density_counts_interior_contacts_of_a_lattice():
    """Eq. (5.29) on a 6×6×6 simple cubic lattice: a margin of 1.25 diameters keeps 3 × 3·4·4 = 144 contacts in
    a window of (7r)³ (window faces fall between contact points)."""
    r = 1e-3
    sim = lattice(radius=r)
    stats = cfc.contact_statistics(sim, margin=1.25)
    assert stats["n_c"] == 144
    assert stats["volume"] == pytest.approx((7 * r) ** 3, rel=1e-5)
    assert stats["rho_c"] == pytest.approx(144 / (7 * r) ** 3, rel=1e-5)
    assert stats["kn"] == pytest.approx(0.5e6) and stats["kt"] == pytest.approx(0.5e6)
    assert stats["radius"] == pytest.approx(r)
    assert stats["rho_c_vessel"] == pytest.approx(3 * 5 * 36 / (12 * r) ** 3, rel=1e-5)   # 540 contacts
    with pytest.raises(ValueError, match="margin"):
        cfc.contact_statistics(sim, margin=3.5)


def test_static_lattice_is_in_equilibrium_and_sphere_stress_is_love_weber():
    sim = lattice()
    assert unbalanced_force_ratio(sim) < 1e-9
    centre = sim.particles.x.mean(axis=0)
    big = 1.0                                                  # a sphere holding every contact point
    volume = 4 / 3 * np.pi * big**3
    lw = love_weber_stress(sim, volume, include_walls=False, compression_positive=True)
    np.testing.assert_allclose(sphere_stress(sim, centre, big), lw, rtol=1e-12, atol=1e-30)
    assert sphere_stress(sim, centre, 1e-5)[0, 0] == 0.0     # no contact point inside


def test_best_fit_gradient_recovers_an_affine_field():
    rng = np.random.default_rng(3)
    x0 = rng.uniform(size=(40, 3))
    G = rng.normal(size=(3, 3)) * 1e-3
    np.testing.assert_allclose(best_fit_gradient(x0, x0 + x0 @ G.T + [1.0, -2.0, 0.5]), G, atol=1e-13)


def _curve(eps, sigma, lateral, cracks=None, confinement=0.0):
    scheme = {"eps_axial": eps, "sigma_axial": sigma, "eps_lateral": lateral, "sigma_lateral": np.zeros_like(eps)}
    return CompressionCurve({s: scheme for s in ("wall", "specimen", "sphere")}, eps, cracks
                            if cracks is not None else np.zeros(len(eps), int), np.zeros(len(eps)), 1.0,
                            confinement)


def test_elastic_moduli_eq_5_27_5_28_on_a_linear_curve():
    eps = np.linspace(0, 1e-4, 21)
    curve = _curve(eps, 1e6 + 30e9 * eps, -0.22 * eps)
    for m in elastic_moduli(curve).values():
        assert m["E"] == pytest.approx(30e9) and m["nu"] == pytest.approx(0.22)


def test_crack_initiation_is_one_percent_of_the_cracks_at_peak():
    eps = np.linspace(0, 1e-2, 11)
    sigma = np.array([0, 10, 20, 30, 40, 50, 60, 70, 60, 50, 40.0])
    cracks = np.array([0, 0, 0, 0, 1, 3, 20, 200, 400, 500, 600])
    assert crack_initiation_stress(_curve(eps, sigma, eps, cracks)) == 50.0      # first with >= 2 of 200
    assert np.isnan(crack_initiation_stress(_curve(eps, sigma, eps)))


def test_mohr_coulomb_fit_recovers_friction_angle_and_cohesion():
    phi, c = np.radians(32.0), 2e6
    N = (1 + np.sin(phi)) / (1 - np.sin(phi))
    s3 = np.array([0.1, 1.0, 10.0, 20.0]) * 1e6
    fit = cfc.mohr_coulomb_fit(s3, N * s3 + 2 * c * np.sqrt(N))
    assert fit["friction_angle"] == pytest.approx(32.0) and fit["cohesion"] == pytest.approx(c)
    with pytest.raises(ValueError, match="two or more"):
        cfc.mohr_coulomb_fit([1e6], [3e6])
    with pytest.raises(ValueError, match="slope"):
        cfc.mohr_coulomb_fit([1e6, 2e6], [3e6, 3.5e6])


def test_mean_interval_by_hand():
    r = cfc.mean_interval([1.0, 2.0, 3.0, np.nan])
    assert r["mean"] == 2.0 and r["std"] == 1.0 and r["n"] == 3
    assert r["half_width"] == pytest.approx(4.302652729749464 / np.sqrt(3))   # t_{0.975, 2}
    assert np.isnan(cfc.mean_interval([5.0])["half_width"])


@pytest.mark.parametrize("name, count", [("dyad", 2), ("peanut", 3)])
def test_clump_member_radius_gives_the_volume_of_the_sphere(name, count):
    """Monte Carlo volume of the union of the members equals 4/3 π R³ (R = 1), independent of the lens formula."""
    x, r, ids = members(np.zeros((1, 3)), np.ones(1), np.array([{"dyad": 1, "peanut": 2}[name]]),
                        np.eye(3)[None])
    assert len(r) == count and np.all(ids == 0) and r[0] == pytest.approx(CLUMP_MEMBER_RADIUS[name])
    pts = np.random.default_rng(0).uniform(-2, 2, (400_000, 3))
    inside = np.any(np.linalg.norm(pts[:, None, :] - x[None], axis=2) < r, axis=1)
    assert inside.mean() * 64 == pytest.approx(4 / 3 * np.pi, rel=0.01)


@pytest.mark.parametrize("kwargs, name", [
    ({"n_particles": 5}, "n_particles"),
    ({"porosity": 0.2}, "porosity"),
    ({"shapes": (0.5, 0.2, 0.2)}, "shapes"),
    ({"kernel": "cuda"}, "kernel"),
])
def test_specimen_spec_refuses_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        SpecimenSpec(**kwargs)


def test_material_needs_both_bond_strengths():
    with pytest.raises(ValueError, match="both"):
        DemMaterial(bond_normal_strength=1.0)
    assert DemMaterial().with_bonds(2.0, 3.0).bonded


# ---------------------------------------------------------------------------------------------- genesis
def test_genesis_hits_the_target_porosity(specimen):
    info = specimen.info
    assert info["porosity_expanded"] == pytest.approx(SPEC.porosity, abs=1e-9)     # expansion: by the radii
    # consolidation releases the locked-in stress of the expanded packing (GPa) to σ0 = 1 MPa: the vessel
    # porosity rises (loose wall layers), the interior stays near random close packing
    assert 0.35 < info["porosity_interior"] < 0.42
    assert 0.40 < info["porosity"] < 0.46
    # frictionless packings near jamming creep: genesis stops within 15 % of σ0 (prepare() then holds 1 %)
    np.testing.assert_allclose(info["stress"], SPEC.stress, rtol=0.15)
    assert min(info["stress_expanded"]) > 100 * SPEC.stress


@pytest.fixture
def lenient_acceptance(monkeypatch):
    """The 60-grain packings of the caching tests end 13–28 % from σ0 depending on the processor's rounding
    (the same code and packages: seed 2 ended 13 % off on the machine of 2026-11-28, 24.7 % on an AMD EPYC on
    2026-11-29; seeds 1, 3, 5 there 16–64 %, seed 2 with 20 000 steps 28 %): a chaotic frictionless packing. These
    tests are about the cache, not the acceptance (pinned on the full-size SPEC above and by
    ``test_genesis_warns_and_does_not_cache_an_unconsolidated_specimen``), so they accept up to 100 %."""
    import abrakit.experiments.specimen as module

    monkeypatch.setattr(module, "ACCEPTED_STRESS", 1.0)


def test_genesis_is_reproducible_and_cached(tmp_path, lenient_acceptance):
    spec = SpecimenSpec(n_particles=60, seed=2, aspect=1.0)
    a = genesis(spec, cache=tmp_path)
    b = genesis(spec, cache=False)
    np.testing.assert_array_equal(a.x, b.x)
    c = DemSpecimen.load(next(tmp_path.glob("specimen_*.npz")))
    np.testing.assert_array_equal(a.x, c.x)
    assert c.spec == spec and c.info == a.info and a.info["consolidation_accepted"]
    assert SpecimenSpec(n_particles=60, seed=5, aspect=1.0).key() != spec.key()


def test_genesis_warns_and_does_not_cache_an_unconsolidated_specimen(tmp_path):
    """2000 steps leave the 60 grains at 2 GPa, not σ0 = 1 MPa: a warning names the stress, nothing is cached, and a
    cache file holding such a specimen (written by an older version) is not reused."""
    spec = SpecimenSpec(n_particles=60, seed=4, aspect=1.0)
    with pytest.warns(UserWarning, match="not cached: give genesis more max_steps"):
        bad = genesis(spec, cache=tmp_path, max_steps=2000)
    assert not bad.info["consolidation_accepted"] and not list(tmp_path.iterdir())
    assert min(bad.info["stress"]) > 100 * spec.stress
    bad.save(tmp_path / f"specimen_{spec.key()}_steps2000.npz")
    with pytest.warns(UserWarning, match="not cached"):
        genesis(spec, cache=tmp_path, max_steps=2000)


def test_genesis_flags_a_specimen_cached_before_the_acceptance_existed(tmp_path, lenient_acceptance):
    """An accepted specimen saved without ``consolidation_accepted`` (an older cache) is returned with the flag."""
    spec = SpecimenSpec(n_particles=60, seed=2, aspect=1.0)
    good = genesis(spec, cache=False)
    del good.info["consolidation_accepted"]
    good.save(tmp_path / f"specimen_{spec.key()}.npz")
    assert genesis(spec, cache=tmp_path).info["consolidation_accepted"] is True


def test_servo_holds_the_confining_stress(granular):
    sim, curve = granular["sim"], granular["curve"]
    lateral = curve["wall"]["sigma_lateral"]
    np.testing.assert_allclose(lateral, SPEC.stress, rtol=0.01)
    assert granular["prepare"]["relax_confinement"]["converged"]
    assert unbalanced_force_ratio(sim) < 0.05


# ---------------------------------------------------------------------------------------------- E and ν
@pytest.mark.parametrize("kind", ["granular", "bonded"])
def test_three_schemes_agree(kind, request):
    """Fig. 5.2. Wall- and specimen-based E agree within 15 %, the specimen-based one being the stiffer (it leaves
    out the compliance of the particle–platen contacts; benchmark, N = 300, 5 seeds × 2 materials: 1.06–1.12).
    The measurement spheres hold about 40 particles each at N = 300 and scatter: sphere/wall E between 0.88 and
    1.45 in the benchmark (1.13–1.22 at N = 2400), ν within 0.10 of the wall value."""
    m = request.getfixturevalue(kind)["moduli"]
    wall, specimen, sphere = m["wall"], m["specimen"], m["sphere"]
    assert 1.0 < specimen["E"] / wall["E"] < 1.15
    assert 0.75 < sphere["E"] / wall["E"] < 1.6
    assert abs(specimen["nu"] - wall["nu"]) < 0.03
    assert abs(sphere["nu"] - wall["nu"]) < 0.12
    assert 0.15 < wall["nu"] < 0.35


@pytest.mark.slow
def test_three_schemes_agree_closely_on_a_larger_specimen():
    """1200 spheres: the measurement spheres hold ~150 particles; sphere/wall E 1.17–1.24 in the benchmark."""
    r = cfc.elastic_case({"n_particles": 1200, "seed": 0, "bonded": True})
    assert 1.0 < r["E_specimen"] / r["E_wall"] < 1.12
    assert 1.0 < r["E_sphere"] / r["E_wall"] < 1.35
    assert abs(r["nu_sphere"] - r["nu_wall"]) < 0.04


def test_halving_the_rate_changes_E_by_less_than_two_percent(specimen, granular):
    """Quasi-static loading: 40 → 80 wave transits over the window changes E by < 2 % and ν by < 0.01
    (the benchmark finds < 0.8 % in E from 20 transits on, for 300 and 1200 spheres)."""
    slow = elastic_test(specimen, SPEC.material(), crossings=80.0)
    assert slow["strain_rate"] == pytest.approx(granular["strain_rate"] / 2)
    for scheme in ("wall", "specimen"):
        assert slow["moduli"][scheme]["E"] == pytest.approx(granular["moduli"][scheme]["E"], rel=0.02)
    assert slow["moduli"]["wall"]["nu"] == pytest.approx(granular["moduli"]["wall"]["nu"], abs=0.01)


@pytest.mark.parametrize("kind", ["granular", "bonded"])
def test_small_specimen_against_the_large_specimen_values(kind, cache):
    """E, ν of a 300-sphere specimen against the mean of 2400-sphere specimens (``LARGE``, from the benchmark).

    Small specimens are systematically softer — their loose wall layers weigh more: over five seeds the benchmark
    finds E(300)/E(2400) = 0.51–0.79 (granular and bonded) and ν higher by 0.015–0.065. The bounds [0.45, 0.85]
    and ±0.08 are that range with a margin; they fail if genesis, loading or measurement change the packing's
    stiffness by more than the seed-to-seed scatter."""
    r = cfc.elastic_case({"n_particles": 300, "seed": 0, "bonded": kind == "bonded", "cache": str(cache)})
    ref = LARGE[kind]
    assert 0.45 * ref["E"] < r["E_wall"] < 0.85 * ref["E"]
    assert r["nu_wall"] == pytest.approx(ref["nu"], abs=0.08)
    # the closed forms: the DEM lies below the affine bound and far below the published Eq. (5.20)
    assert r["ratio_E_wall_affine"] < 1.0
    assert r["ratio_E_wall_published"] < 0.5
    assert r["E_pred_consistent"] == pytest.approx(4 / 9 * r["E_pred_published"])


@pytest.fixture(scope="module")
def bond_cases(cache):
    return {case: cfc.bond_strength_case({"n_particles": 300, "seed": 0, "case": case, "target_stress": 100e6,
                                          "cache": str(cache)}) for case in cfc.BOND_CASES}


def test_bond_strength_cases_of_table_5_3(bond_cases):
    """Test 1 (f^n = f^t) is the weakest; Test 2 (strong normal bonds) fails by shear cracks only, Test 3 (strong
    tangential bonds) by tensile cracks only; Eq. (5.26) (100 MPa here) overestimates every failure stress."""
    sigma = {c: r["sigma_f_wall"] for c, r in bond_cases.items()}
    assert sigma[1] < sigma[2] and sigma[1] < sigma[3]
    assert bond_cases[2]["tension_share"] == 0.0 and bond_cases[3]["tension_share"] == 1.0
    assert 0.0 < bond_cases[1]["tension_share"] < 1.0
    for r in bond_cases.values():
        governing = min(r["rankine_published"], r["tresca_published"])
        assert governing == pytest.approx(100e6)
        assert 0.2 < r["sigma_f_wall"] / governing < 1.0
        assert r["sigma_f_specimen"] == pytest.approx(r["sigma_f_wall"], rel=0.1)
        assert r["sigma_ci"] <= r["sigma_f_wall"]


@pytest.mark.slow
def test_granular_envelope_and_clump_mixture(cache):
    """Mohr–Coulomb: a friction angle in the range of DEM sphere packings (μ = 0.5); the Table 5.4 mixture is
    stronger than spheres at 1 MPa (Ch. 5.4.2)."""
    peaks = [cfc.envelope_case({"n_particles": 300, "seed": 0, "confinement": s3, "cache": str(cache)})
             for s3 in (1e6, 4e6)]
    fit = cfc.mohr_coulomb_fit([p["sigma3"] for p in peaks], [p["sigma1"] for p in peaks], cohesionless=True)
    assert 18.0 < fit["friction_angle"] < 40.0
    mixture = cfc.envelope_case({"n_particles": 300, "seed": 0, "confinement": 1e6, "cache": str(cache),
                                 "shapes": list(cfc.MIXTURE)})
    assert mixture["sigma1"] > peaks[0]["sigma1"]
