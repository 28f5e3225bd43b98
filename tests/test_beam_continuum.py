"""The elastic continuum beam (abrakit.experiments.beam_continuum): Timoshenko where beam theory holds, the load
introduction where it does not, mesh convergence, bad input."""

import pytest

from abrakit.experiments.beam_continuum import continuum_flexural_modulus
from abrakit.experiments.bending import BeamSpec, beam_theory_deflection, flexural

E, NU = 1.9e9, 0.2


def timoshenko(spec):
    return flexural(1.0, beam_theory_deflection(1.0, E, NU, spec), spec)["modulus"]


def test_a_slender_beam_is_timoshenkos():
    """S/H = 10, third-point loading: the continuum's E_f equals Timoshenko's within 0.2 % (measured 0.1 %)."""
    spec = BeamSpec(length=0.6, span=0.5, roller_spacing=0.5 / 3)
    assert continuum_flexural_modulus(spec, E, NU, element_size=0.005)["modulus"] == pytest.approx(
        timoshenko(spec), rel=2e-3)


def test_the_short_beam_sinks_further_where_the_load_enters_through_a_shorter_pad():
    """S/H = 3 (the paper's beam): through 10 mm pads the continuum's E_f converges to first order in h (the
    pressure jumps at the pad edges; measured differences 0.59 % and 0.30 % from h = 5 to 2.5 to 1.25 mm) towards
    2.9 % below Timoshenko (Richardson's limit); through 2 mm pads, nearly point loads, about 7 % below."""
    spec = BeamSpec()
    E_h = [continuum_flexural_modulus(spec, E, NU, pad=0.01, element_size=h)["modulus"]
           for h in (0.005, 0.0025, 0.00125)]
    first, second = E_h[0] - E_h[1], E_h[1] - E_h[2]
    assert second / first == pytest.approx(0.5, abs=0.1)
    limit = E_h[2] - second                       # Richardson, first order
    assert limit / timoshenko(spec) - 1 == pytest.approx(-0.029, abs=0.003)
    narrow = continuum_flexural_modulus(spec, E, NU, pad=0.002, element_size=0.0025)["modulus"]
    assert narrow / timoshenko(spec) - 1 == pytest.approx(-0.074, abs=0.01)


def test_bad_input_is_refused():
    spec = BeamSpec()
    with pytest.raises(ValueError, match="poisson"):
        continuum_flexural_modulus(spec, E, 0.5)
    with pytest.raises(ValueError, match="modulus"):
        continuum_flexural_modulus(spec, -E, NU)
    with pytest.raises(ValueError, match="pad"):
        continuum_flexural_modulus(spec, E, NU, pad=0.04)
    with pytest.raises(ValueError, match="element_size"):
        continuum_flexural_modulus(spec, E, NU, element_size=0.0)
    with pytest.raises(TypeError, match="spec"):
        continuum_flexural_modulus("beam", E, NU)
