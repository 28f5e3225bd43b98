"""White-noise strength and toughness statistics of seed 001 (abrakit.materials.strength_statistics): the drawn
values follow the seed's normal and Weibull CDFs (Kolmogorov–Smirnov), their mean and coefficient of variation match
the closed forms, a seed fixes the field, the modes scale strength, toughness and crack opening as the seed says."""

import numpy as np
import pytest
from scipy import special, stats
from scipy.integrate import quad

from abrakit.materials import AnisotropicSofteningDamage, StrengthStatistics
from abrakit.materials.softening_laws import softening_law
from abrakit.materials.strength_statistics import (
    MAX_NORMAL_CV,
    P_RANGE,
    normal_cdf,
    truncated_cdf,
    weibull_cdf,
    weibull_cv,
    weibull_mean,
)

N = 50_000


def test_normal_values_follow_the_seeds_cdf():
    """KS test against p = 1/2 [1 + erf((r - 1)/(C_v sqrt 2))] renormalised to p in [0.001, 0.999]."""
    r = StrengthStatistics("normal", cv=0.15, seed=4).relative_values(np.ones(N))
    result = stats.kstest(r, lambda x: truncated_cdf(lambda y: normal_cdf(y, 0.15), x))
    assert result.pvalue > 0.01
    assert r.min() >= 1.0 + 0.15 * special.ndtri(P_RANGE[0]) - 1e-12
    assert r.mean() == pytest.approx(1.0, abs=4 * 0.15 / np.sqrt(N))


@pytest.mark.parametrize("shape", [2.0, 5.0, 12.0])
def test_weibull_values_follow_the_seeds_cdf_and_its_size_effect(shape):
    """KS test against p = 1 - exp(-(V_p/V_0)(r Gamma(1 + 1/alpha))^alpha) (renormalised), for points twice the
    reference volume; mean and C_v against the closed forms <r> = (V_0/V_p)^(1/alpha) and
    sqrt(Gamma(1 + 2/alpha)/Gamma(1 + 1/alpha)^2 - 1): exactly (to sampling) once the truncation of p is integrated,
    and within 0.2 % (mean) and 1.5 % (C_v) of the untruncated closed forms."""
    V0, Vp = 3.0, 6.0
    r = StrengthStatistics("weibull", shape=shape, V0=V0, seed=5).relative_values(np.full(N, Vp))
    result = stats.kstest(r, lambda x: truncated_cdf(lambda y: weibull_cdf(y, shape, V0, Vp), x))
    assert result.pvalue > 0.01

    def quantile(p):
        return (-(V0 / Vp) * np.log1p(-p)) ** (1.0 / shape) / special.gamma(1.0 + 1.0 / shape)

    width = P_RANGE[1] - P_RANGE[0]
    mean = quad(quantile, *P_RANGE)[0] / width
    second = quad(lambda p: quantile(p) ** 2, *P_RANGE)[0] / width
    cv = np.sqrt(second - mean**2) / mean
    assert r.mean() == pytest.approx(mean, rel=4 * cv / np.sqrt(N))
    assert r.std() / r.mean() == pytest.approx(cv, rel=0.02)
    assert mean == pytest.approx(weibull_mean(shape, V0, Vp), rel=2e-3)
    assert cv == pytest.approx(weibull_cv(shape), rel=1.5e-2)


def test_larger_points_are_weaker_on_average():
    statistics = StrengthStatistics("weibull", shape=4.0, V0=1.0, seed=0)
    small, large = statistics.relative_values(np.full(N, 0.5)), statistics.relative_values(np.full(N, 8.0))
    assert large.mean() / small.mean() == pytest.approx(16.0 ** -0.25, rel=1e-12)   # same p, scaled


def test_a_seed_fixes_the_field():
    a = StrengthStatistics("normal", cv=0.1, seed=7).relative_values(np.ones((10, 4)))
    b = StrengthStatistics("normal", cv=0.1, seed=7).relative_values(np.ones((10, 4)))
    c = StrengthStatistics("normal", cv=0.1, seed=8).relative_values(np.ones((10, 4)))
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert a.shape == (10, 4)


@pytest.mark.parametrize("law", ["linear", "exponential"])
def test_modes_scale_strength_toughness_and_crack_opening_as_the_seed_says(law):
    """Mode 1: strength only, the opening grows as 1/r (toughness kept); mode 2: toughness only, the opening
    shrinks as r (strength kept); mode 3: both, the opening is kept. Checked on the softening law's opening at
    half strength."""
    f = softening_law(law)
    volumes = np.ones(200)
    for mode, ratio in ((1, lambda r: 1.0 / r), (2, lambda r: r), (3, lambda r: np.ones_like(r))):
        rs, rt = StrengthStatistics("normal", cv=0.1, mode=mode, seed=1).sample(volumes)
        r = rs if mode != 2 else rt
        strength, toughness = 2.0 * rs, 0.5 * rt
        half = np.array([_opening_at(f, 0.5 * s, s, t) for s, t in zip(strength, toughness, strict=True)])
        base = _opening_at(f, 1.0, 2.0, 0.5)
        np.testing.assert_allclose(half / base, ratio(r), rtol=1e-9)


def _opening_at(f, traction, strength, toughness):
    """The opening at which the law carries ``traction``."""
    from scipy.optimize import brentq
    return brentq(lambda x: f.traction(x, strength, toughness) - traction, 0.0, 100.0, xtol=1e-14, rtol=1e-14)


def test_statistics_feed_the_material_per_point():
    rs, rt = StrengthStatistics("normal", cv=0.1, mode=3, seed=2).sample(np.ones((5, 4)))
    m = AnisotropicSofteningDamage(1000.0, 0.2, 30.0, 20.0, 0.5, 0.8, band_width=0.2, relative_strength=rs,
                                   relative_toughness=rt)
    strain = np.zeros((5, 4, 6))
    strain[..., 0] = 30.0 / m.C11                                        # sigma_11 = sigma_c exactly
    cracked = m.update(m.initial_state((5, 4)), strain).state["initiated"]
    np.testing.assert_array_equal(cracked, rs <= 1.0)


@pytest.mark.parametrize("options, match", [
    ({"distribution": "normal"}, "cv"), ({"distribution": "normal", "cv": MAX_NORMAL_CV}, "cv"),
    ({"distribution": "normal", "cv": -0.1}, "cv"),
    ({"distribution": "weibull", "shape": 2.0}, "V0"), ({"distribution": "weibull", "shape": -1.0, "V0": 1.0}, "shape"),
    ({"distribution": "lognormal", "cv": 0.1}, "distribution"), ({"distribution": "normal", "cv": 0.1, "mode": 4},
                                                                  "mode"),
])
def test_bad_statistics_are_refused_by_name(options, match):
    with pytest.raises(ValueError, match=match):
        StrengthStatistics(**options)


def test_point_volumes_must_be_positive():
    with pytest.raises(ValueError, match="volumes"):
        StrengthStatistics("weibull", shape=3.0, V0=1.0).relative_values(np.array([1.0, 0.0]))
