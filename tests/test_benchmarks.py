"""Every benchmark script imports and has the shared entry point; in quick mode (slow) it writes its files."""

import importlib.util
import inspect
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))
import run  # noqa: E402

SCRIPTS = sorted(run.discover())


@pytest.mark.parametrize("name", SCRIPTS)
def test_benchmark_exposes_main_with_outdir_and_quick(name):
    module = run.load(run.discover()[name])
    params = inspect.signature(module.main).parameters
    assert list(params)[:2] == ["outdir", "quick"], name


def test_runner_refuses_unknown_names(tmp_path):
    with pytest.raises(SystemExit, match="unknown benchmark"):
        run.run(["no_such_benchmark"], tmp_path, quick=True)


@pytest.mark.slow
@pytest.mark.parametrize("name", SCRIPTS)
def test_benchmark_quick_mode_writes_its_results(name, tmp_path):
    records = run.run([name], tmp_path, quick=True)
    assert records[0]["status"] == "ok"
    assert list(tmp_path.glob("*.json")), name
    assert importlib.util.find_spec("matplotlib")


def test_bench_damage_follows_model_one_by_an_opening_on_every_specimen():
    """The path-following gauges of bench_damage: two rows across the band where the mesh has rows; on the plate
    with a hole (polar mesh) the hole's nodes within 2 mm above the symmetry line against that line, on every
    formulation."""
    import numpy as np

    from abrakit.damage.specimens import SPECIMENS, specimen

    bench = run.load(run.discover()["damage"])
    for name in SPECIMENS:
        for formulation in ("plane_strain", "extruded"):
            sp = specimen(name, 250, formulation=formulation)
            plus, minus = bench.crack_opening(sp)
            assert plus.size and minus.size and not np.intersect1d(plus, minus).size, (name, formulation)
            y = sp.basis.doflocs[1]
            assert np.all(y[plus] > y[minus].max()), (name, formulation)
            if name == "plate_with_hole":
                x = sp.basis.doflocs[0]
                assert np.allclose(np.hypot(x[plus], y[plus]), 10.0) and np.all(y[plus] <= 2.0)
                assert np.all(y[minus] == 0.0)
