"""The book's chapters read stored benchmark results through benchmarks/reproduction.py's stored_result."""

import importlib.util
import json
from pathlib import Path

_spec = importlib.util.spec_from_file_location(
    "abrakit_benchmarks_reproduction", Path(__file__).resolve().parent.parent / "benchmarks" / "reproduction.py")
_module = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_module)
stored_result = _module.stored_result


def test_stored_result_reads_the_file(tmp_path):
    (tmp_path / "thing.json").write_text(json.dumps({"a": 1}))
    assert stored_result("thing", results=tmp_path) == {"a": 1}


def test_missing_result_names_its_command_and_runs_the_quick_mode(tmp_path, capsys):
    results = tmp_path / "results"
    results.mkdir()
    assert stored_result("absent", results=results) is None                 # no script: says so, returns None
    assert "python benchmarks/bench_absent.py" in capsys.readouterr().out
    (tmp_path / "bench_tiny.py").write_text(
        "import argparse, json, pathlib\n"
        "p = argparse.ArgumentParser(); p.add_argument('--quick', action='store_true'); p.add_argument('--outdir')\n"
        "a = p.parse_args()\n"
        "pathlib.Path(a.outdir, 'tiny.json').write_text(json.dumps({'quick': a.quick}))\n")
    assert stored_result("tiny", results=results) == {"quick": True}
    out = capsys.readouterr().out
    assert "tiny.json is missing" in out and "--quick" in out
    assert stored_result("tiny", results=results, fallback=False) is None
