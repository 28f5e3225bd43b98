"""Every script in examples/ runs and produces the numbers it claims (as scikit-fem tests its examples)."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_wear_table_example_reproduces_table_8_4(tmp_path):
    table = load("wear_table_8_4").main(tmp_path)
    assert np.all(np.abs(table["deviation"]) < 0.01)
    assert (tmp_path / "table_8_4.csv").read_text().count("\n") == 8


def test_contact_stiffness_example_round_trips():
    rho_c = load("contact_stiffness_from_E_nu").main()
    assert rho_c > 0


def test_damage_example_is_irreversible_and_rate_dependence_lags(tmp_path):
    runs = load("damage_1d_cyclic").main(tmp_path)
    for run in runs.values():
        assert np.all(np.diff(run["d"]) >= 0)
    assert runs["rate-dependent"]["d"][-1] < runs["rate-independent"]["d"][-1]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.py")), ids=lambda p: p.stem)
def test_every_example_has_a_test(path):
    assert path.stem in Path(__file__).read_text(), f"examples/{path.name} has no test"
