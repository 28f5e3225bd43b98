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


def test_snap_back_example_follows_the_branch_that_displacement_control_jumps(tmp_path):
    summary = load("model_one_snap_back").main(tmp_path)
    path, jumped = summary["path"], summary["displacement"]
    assert path["jumps"] == 0 and jumped["jumps"] >= 1
    assert path["smallest_u_after_peak_mm"] < 0.7 * path["u_peak_mm"]                 # the branch returns
    assert jumped["smallest_u_after_peak_mm"] == pytest.approx(jumped["u_peak_mm"])    # displacement control cannot
    assert path["energy_missed"] < 0.1 < jumped["energy_missed"]
    assert (tmp_path / "snap_back_path.csv").read_text().count("\n") > 50


def test_thick_cylinder_example_is_on_hills_solution():
    assert load("thick_cylinder_collapse").main() < 0.01
