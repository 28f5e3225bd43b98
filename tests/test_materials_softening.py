"""LinearSofteningDamage: the closed-form stress–strain line, the consistent tangent, the dissipation, bad input."""

import numpy as np
import pytest

from abrakit.materials import LinearSofteningDamage
from abrakit.materials.base import finite_difference_tangent

E, EPS_0, EPS_F = 1000.0, 1e-3, 2e-2


def uniaxial(eps):
    out = np.zeros(np.shape(eps) + (6,))
    out[..., 0] = eps
    return out


def test_uniaxial_strain_follows_the_linear_softening_line_and_unloads_to_the_origin():
    m = LinearSofteningDamage(E, 0.0, EPS_0, EPS_F)
    state = m.initial_state(())
    for eps in np.linspace(0.0, 1.5e-2, 31)[1:]:
        r = m.update(state, uniaxial(eps))
        state = r.state
        expected = E * eps if eps <= EPS_0 else E * EPS_0 * (EPS_F - eps) / (EPS_F - EPS_0)
        assert r.stress[0] == pytest.approx(expected, rel=1e-12)
    back = m.update(state, uniaxial(0.5 * 1.5e-2))                  # secant unloading: half the strain, half σ
    assert back.stress[0] == pytest.approx(0.5 * r.stress[0], rel=1e-12)
    assert back.state["kappa"] == state["kappa"]


@pytest.mark.parametrize("eps", [uniaxial(3e-3), np.array([3e-3, -1e-3, 5e-4, 2e-4, -3e-4, 1e-3])])
def test_tangent_matches_finite_differences_while_softening_and_unloading(eps):
    m = LinearSofteningDamage(E, 0.2, EPS_0, EPS_F)
    state = m.initial_state(())
    loaded = m.update(state, 0.9 * eps).state                      # damaged already: next step loads further
    for s, label in ((loaded, "softening"), (m.update(loaded, 0.5 * eps).state, "unloading")):
        target = eps if label == "softening" else 0.4 * eps
        r = m.update(s, target)
        fd = finite_difference_tangent(m, s, target, h=1e-9)
        assert np.allclose(r.tangent, fd, rtol=1e-5, atol=1e-6 * E), label


def test_dissipation_is_the_area_of_the_softening_triangle():
    """D(kappa) closes W = D + ½ σ ε along a uniaxial path and equals ½ f_t eps_f at failure."""
    m = LinearSofteningDamage(E, 0.0, EPS_0, EPS_F)
    state, work, sigma_old, eps_old = m.initial_state(()), 0.0, 0.0, 0.0
    for eps in np.linspace(0.0, EPS_F, 401)[1:]:
        r = m.update(state, uniaxial(eps))
        work += 0.5 * (sigma_old + r.stress[0]) * (eps - eps_old)
        state, sigma_old, eps_old = r.state, r.stress[0], eps
        assert work == pytest.approx(float(m.dissipation(state)) + 0.5 * r.stress[0] * eps, rel=1e-9, abs=1e-9)
    assert float(m.dissipation(state)) == pytest.approx(0.5 * E * EPS_0 * EPS_F, rel=1e-12)


def test_damage_stays_below_its_cap_and_refuses_bad_input():
    m = LinearSofteningDamage(E, 0.0, EPS_0, EPS_F)
    r = m.update(m.initial_state(()), uniaxial(10 * EPS_F))
    assert r.state["d"] == pytest.approx(m.d_max) and np.all(np.isfinite(r.tangent))
    with pytest.raises(ValueError, match="eps_f"):
        LinearSofteningDamage(E, 0.0, EPS_0, 0.5 * EPS_0)
    with pytest.raises(ValueError, match="nu"):
        LinearSofteningDamage(E, 0.5, EPS_0, EPS_F)
    with pytest.raises(ValueError, match="eps_0"):
        LinearSofteningDamage(E, 0.0, -EPS_0, EPS_F)
