"""The material-point driver: path builders, mixed control, batches, loading callbacks and failure messages."""

import numpy as np
import pytest

from abrakit.materials import (
    LinearElastic,
    ModelIDamage,
    ModelIIDamage,
    VonMisesPlasticity,
    cycles,
    pure_shear,
    ramp,
    uniaxial_strain,
    uniaxial_stress,
)
from abrakit.materials.driver import DriverError, drive

E, NU = 200000.0, 0.3


def test_path_builders():
    np.testing.assert_allclose(ramp(1.0, 4), [0.25, 0.5, 0.75, 1.0])
    wave = cycles(2.0, 2, 3)
    assert wave.shape == (24,)
    np.testing.assert_allclose(wave[[2, 8, 11, 14, 23]], [2.0, -2.0, 0.0, 2.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(np.abs(np.diff(np.r_[0.0, wave])), 2.0 / 3.0, rtol=1e-12)
    with pytest.raises(ValueError, match="n_steps"):
        ramp(1.0, 0)


def test_uniaxial_stress_of_an_elastic_point_gives_poisson_contraction():
    result = uniaxial_stress(LinearElastic(E, NU), ramp(1e-3, 3))
    np.testing.assert_allclose(result.stress_component("11"), E * result.strain_component("11"), rtol=1e-12)
    np.testing.assert_allclose(result.strain_component("22"), -NU * result.strain_component("11"), rtol=1e-12)
    np.testing.assert_allclose(result.strain_component("33"), -NU * result.strain_component("11"), rtol=1e-12)
    np.testing.assert_allclose(result.stress[:, 1:], 0.0, atol=1e-9)
    assert result.time.shape == (4,) and result.iterations.shape == (3,)
    assert np.all(result.iterations <= 1)  # linear: one Newton correction per step
    np.testing.assert_allclose(result.stress_tensor()[-1, 0, 0], 200.0)


def test_shear_components_are_reported_as_tensor_components():
    result = pure_shear(LinearElastic(E, NU), [2e-3])  # gamma_12 = 2 eps_12
    assert result.strain_component("12")[-1] == pytest.approx(1e-3)
    assert result.strain_component("21")[-1] == pytest.approx(1e-3)
    assert result.stress_component("12")[-1] == pytest.approx(E / (2 * (1 + NU)) * 2e-3)
    with pytest.raises(ValueError, match="component"):
        result.stress_component("14")


def test_mixed_control_falls_back_to_finite_differences_for_the_operator_split_tangent():
    """Model I's tangent f^m E ignores plastic flow; the driver still meets sigma_22 = sigma_33 = 0."""
    result = uniaxial_stress(ModelIDamage(E, NU, 0.05, r_p=60.0, K_H=8000.0), ramp(1e-2, 40))
    np.testing.assert_allclose(result.stress[:, 1:], 0.0, atol=1e-6)
    assert result.internal["alpha_p"][-1] > 0 and result.internal["d"][-1] > 0


def test_batches_of_paths_run_in_parallel():
    material = VonMisesPlasticity(E, NU, 60.0, 8000.0, "implicit")
    peaks = np.array([1e-3, 5e-3, 1e-2])
    batch = uniaxial_stress(material, ramp(1.0, 10)[:, None] * peaks)
    assert batch.stress.shape == (11, 3, 6)
    for j, peak in enumerate(peaks):
        single = uniaxial_stress(material, ramp(peak, 10))
        np.testing.assert_allclose(batch.stress[:, j], single.stress, atol=1e-8)


def test_loading_callable_gets_the_step_and_the_previous_state():
    seen = []

    def loading(step, state, eps):
        seen.append((step, float(state["d"].max())))
        return {"external_work": 0.0 if step < 5 else 1.0}

    result = uniaxial_strain(ModelIIDamage(E, NU, 0.1, n=4), ramp(4e-3, 10), loading=loading)
    assert [s for s, _ in seen] == list(range(10))
    assert np.all(result.internal["d"][:6] == 0.0) and result.internal["d"][-1].max() > 0.0


def test_non_convergence_raises_a_clear_error():
    with pytest.raises(DriverError, match="did not converge"):
        uniaxial_stress(VonMisesPlasticity(E, NU, 60.0), ramp(1e-2, 2), max_iter=0)


def test_bad_driver_input():
    with pytest.raises(ValueError, match="strain"):
        drive(LinearElastic(E, NU), np.zeros((3, 5)))
    with pytest.raises(ValueError, match="stress_controlled"):
        drive(LinearElastic(E, NU), np.zeros((3, 6)), stress_controlled=[True, False])
    with pytest.raises(ValueError, match="jacobian"):
        drive(LinearElastic(E, NU), np.zeros((3, 6)), jacobian="broyden")
