"""Run the abrakit benchmarks and print a summary table.

    python benchmarks/run.py [--quick] [--outdir DIR] [names...]

Every ``benchmarks/bench_<name>.py`` exposes ``main(outdir, quick=False) -> dict`` and writes
``<outdir>/<name>.{csv,json,png}``. Without names all benchmarks run, in alphabetical order. A benchmark that
raises is reported as FAILED with its traceback, the others still run, and the exit code is 1.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent


def discover(directory: Path = HERE) -> dict[str, Path]:
    """Map benchmark name (``bench_<name>.py``) to its file."""
    return {path.stem.removeprefix("bench_"): path for path in sorted(directory.glob("bench_*.py"))}


def load(path: Path):
    """Import a benchmark script as a module (its folder on ``sys.path`` for the shared ``_common``)."""
    if str(path.parent) not in sys.path:
        sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location(f"abrakit_bench_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run(names, outdir: Path, quick: bool) -> list[dict]:
    """Run the named benchmarks; one record per benchmark with status, wall time and summary."""
    available = discover()
    unknown = [n for n in names if n not in available]
    if unknown:
        raise SystemExit(f"unknown benchmark(s) {unknown}; available: {sorted(available)}")
    records = []
    for name in names or sorted(available):
        tic = time.perf_counter()
        try:
            result = load(available[name]).main(outdir, quick=quick)
            status = "ok"
            summary = result.get("summary", ", ".join(map(str, result))) if isinstance(result, dict) else ""
        except Exception:
            traceback.print_exc()
            status, summary = "FAILED", traceback.format_exc().strip().splitlines()[-1]
        records.append({"name": name, "status": status, "seconds": time.perf_counter() - tic,
                        "summary": str(summary)})
        print(f"[{status}] {name} in {records[-1]['seconds']:.1f} s", flush=True)
    return records


def table(records) -> str:
    width = max([len("benchmark")] + [len(r["name"]) for r in records])
    lines = [f"{'benchmark':<{width}}  status  time [s]  summary", "-" * (width + 28)]
    lines += [f"{r['name']:<{width}}  {r['status']:<6}  {r['seconds']:8.1f}  {r['summary']}" for r in records]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="Run abrakit benchmarks (speed against error).")
    parser.add_argument("names", nargs="*", help="benchmark names (bench_<name>.py); default: all")
    parser.add_argument("--quick", action="store_true", help="small problem sizes, for smoke tests")
    parser.add_argument("--outdir", type=Path, default=HERE / "results", help="where results are written")
    args = parser.parse_args(argv)
    records = run(args.names, args.outdir, args.quick)
    print()
    print(table(records))
    return 0 if all(r["status"] == "ok" for r in records) else 1


if __name__ == "__main__":
    sys.exit(main())
