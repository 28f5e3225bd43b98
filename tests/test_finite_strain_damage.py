"""Model II's damage on the logarithmic-strain kinematics (LogStrainPlasticity around ModelIIDamage).

The small-strain limit, the energy budget at large strain (its splitting error halves with the step), the
consistent tangent against finite differences, objectivity of a damaged point, and the refusals."""

import numpy as np
import pytest

from abrakit import tensors as T
from abrakit.materials import LogStrainPlasticity, ModelIIDamage
from abrakit.materials.model_two import damage_function, effective_damage_function

E, NU, R_P, K_H = 210000.0, 0.33, 289.9, 666.7


def model(r_d=0.1, r_p=R_P, **kw):
    return ModelIIDamage(E, NU, r_d, n=20, alpha=0.05, r_p=r_p, K_H=K_H, integration="implicit", **kw)


def _rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def test_small_strains_reduce_to_the_small_strain_model_with_damage():
    """|∇u| = 1e-7 with a threshold small enough that the ERVE damages in the first step: P of the log-strain
    model equals σ of the small-strain Model II to 1e-6 of its size (they differ at first order in |∇u|), and
    the damage variables are the same."""
    base = model(r_d=1e-12, r_p=None)
    finite = LogStrainPlasticity(base)
    grad = 1e-7 * np.array([[1.0, 0.3, 0.0], [0.3, -0.5, 0.2], [0.0, 0.2, 0.1]])
    r_f = finite.update(finite.initial_state(()), (np.eye(3) + grad).ravel(), external_work=2.0)
    r_s = base.update(base.initial_state(()), T.to_mandel(grad), external_work=2.0)
    assert r_s.state["d"].max() > 0                                  # the ERVE did damage
    np.testing.assert_allclose(r_f.state["d"], r_s.state["d"], atol=1e-15)
    sigma = T.from_mandel(r_s.stress)
    assert np.abs(r_f.stress.reshape(3, 3) - sigma).max() <= 1e-6 * np.abs(sigma).max()


def energy_budget(steps: int):
    """Drive one point along F(t) = I + t G to 40 % stretch with shear; return (W, ψ, D_p, D_d) [MPa]: the
    work of P on F (trapezoid), the stored energy, the plastic and the released damage energy."""
    base = model()
    material = LogStrainPlasticity(base)
    G = np.array([[0.4, 0.2, 0.0], [0.0, -0.1, 0.0], [0.0, 0.0, -0.1]])
    state = material.initial_state(())
    P_old, F_old = np.zeros(9), np.eye(3).ravel()
    work = released = 0.0
    for k in range(1, steps + 1):
        F = (np.eye(3) + k / steps * G).ravel()
        r = material.update(state, F, external_work=8.0 / steps)    # α·W: 0.4 per sub-domain over the path
        f_old = effective_damage_function(damage_function(state["d"]))
        f_new = effective_damage_function(damage_function(r.state["d"]))
        released += float((f_old - f_new) * base.elastic_energy(r.state["eps_e"]))
        work += 0.5 * float((P_old + r.stress) @ (F - F_old))
        state, P_old, F_old = r.state, r.stress, F
    threshold = base.r_d / base.n * float(np.sum(state["d"]))
    plastic = float(state["dissipation"]) - threshold
    return work, float(material.stored_energy(state)), plastic, released, state


def test_the_energy_budget_closes_at_large_strain_to_first_order_in_the_step():
    """W = ψ + D_p + D_d at 40 % stretch: the gap is the splitting error of the explicit damage step and halves
    with the step (0.30 % and 0.15 % of the work); plastic and damage dissipation are a tenth and a third of it."""
    gaps = []
    for steps in (200, 400):
        work, stored, plastic, released, state = energy_budget(steps)
        assert state["d"].max() > 0.1 and state["alpha_p"] > 0.1
        assert plastic > 0.05 * work and released > 0.2 * work
        gaps.append(abs(work - stored - plastic - released) / work)
    assert gaps[1] < 0.01
    assert gaps[1] < 0.7 * gaps[0]


def test_consistent_tangent_matches_finite_differences_at_large_strain():
    material = LogStrainPlasticity(model())
    rng = np.random.default_rng(3)
    F0 = np.eye(3) + 0.15 * rng.standard_normal((4, 3, 3))
    F0[np.linalg.det(F0) < 0.5] = np.eye(3) * 1.1
    first = material.update(material.initial_state((4,)), F0.reshape(4, 9), external_work=4.0)
    assert first.state["d"].max() > 0
    F1 = (F0 + 0.02 * rng.standard_normal((4, 3, 3))).reshape(4, 9)
    loading = {"external_work": 2.0}
    exact = material.update(first.state, F1, **loading).tangent
    h = 1e-7
    columns = []
    for k in range(9):
        step = np.zeros(9)
        step[k] = h
        columns.append((material.update(first.state, F1 + step, **loading).stress
                        - material.update(first.state, F1 - step, **loading).stress) / (2 * h))
    fd = np.stack(columns, axis=-1)
    assert np.abs(exact - fd).max() <= 1e-5 * np.abs(fd).max()


def test_a_rigid_rotation_of_a_damaged_point_changes_no_stress_invariant():
    material = LogStrainPlasticity(model())
    F = np.diag([1.2, 0.92, 0.93])
    F[0, 1] = 0.1
    first = material.update(material.initial_state(()), F.ravel(), external_work=8.0)
    assert first.state["d"].max() > 0.1
    no_growth = {"external_work": 0.0}
    same = material.update(first.state, F.ravel(), **no_growth)
    R = _rotation([1.0, 2.0, 0.5], 0.7)
    turned = material.update(first.state, (R @ F).ravel(), **no_growth)
    s, s_r = T.from_mandel(same.state["cauchy"]), T.from_mandel(turned.state["cauchy"])
    for invariant in (np.trace, lambda a: np.trace(a @ a), np.linalg.det):
        assert invariant(s_r) == pytest.approx(invariant(s), rel=1e-10, abs=1e-9)
    np.testing.assert_allclose(s_r, R @ s @ R.T, atol=1e-8)
    np.testing.assert_array_equal(turned.state["d"], same.state["d"])


def test_damage_is_capped_and_finite_and_model_two_needs_its_rate_limit():
    material = LogStrainPlasticity(model())
    F = np.diag([1.5, 0.8, 0.85]).ravel()
    state = material.initial_state(())
    for _ in range(60):
        r = material.update(state, F, external_work=20.0)
        assert np.all(r.state["d"] >= state["d"]) and np.all(np.isfinite(r.stress))
        state = r.state
    assert state["d"].max() == pytest.approx(0.999)
    with pytest.raises(ValueError, match="external_power"):
        material.update(material.initial_state(()), F)
    with pytest.raises(ValueError, match="implicit"):
        LogStrainPlasticity(ModelIIDamage(E, NU, 0.1, r_p=R_P, integration="explicit"))
