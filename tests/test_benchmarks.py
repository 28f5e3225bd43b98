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
