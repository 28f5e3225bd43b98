"""The ``abrakit`` command line: ``abrakit demo`` runs one small scene of each chapter in under a minute."""

from __future__ import annotations

import argparse
import importlib
import sys
import time

__all__ = ["main", "run_demos"]

#: Book chapter (its file name in ``book/``, like ``examples/<chapter>.py``) -> the modules whose ``demo()`` returns a
#: one-paragraph summary of a small scene of that chapter; ``intro`` prints the reproduction verdicts.
DEMOS = {
    "intro": ("abrakit.reproduction",),
    "tensors": ("abrakit.tensors",),
    "evolution": ("abrakit.evolution",),
    "dem": ("abrakit.dem",),
    "identification": ("abrakit.identification",),
    "dem_identification": ("abrakit.experiments.closed_form_checks",),
    "fem": ("abrakit.fem",),
    "plasticity": ("abrakit.materials",),
    "localisation": ("abrakit.damage.localisation",),
    "model_one": ("abrakit.damage.laplacian", "abrakit.damage.model_one_fe"),
    "model_two": ("abrakit.damage.model_two_fe",),
    "anisotropic_damage": ("abrakit.damage.crack_band",),
    "contacting": ("abrakit.experiments.contacting",),
    "wear": ("abrakit.wear",),
    "scratch": ("abrakit.scratch", "abrakit.scratch.scene"),
    "fatigue": ("abrakit.fatigue",),
}


def run_demos(names=None, out=sys.stdout) -> dict[str, float]:
    """Run the named chapter demos (all by default); print each summary and return the wall times in seconds."""
    names = list(names or DEMOS)
    unknown = [n for n in names if n not in DEMOS]
    if unknown:
        raise ValueError(f"unknown demo(s) {unknown}; choose from {list(DEMOS)}")
    times = {}
    for name in names:
        start = time.perf_counter()
        summary = "\n".join(importlib.import_module(module).demo() for module in DEMOS[name])
        times[name] = time.perf_counter() - start
        print(f"== {name} ({times[name]:.1f} s)\n{summary}\n", file=out, flush=True)
    print(f"all demos: {sum(times.values()):.1f} s", file=out)
    return times


def main(argv=None) -> int:
    from abrakit import __version__

    parser = argparse.ArgumentParser(prog="abrakit", description=__doc__)
    parser.add_argument("--version", action="version", version=f"abrakit {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run one small scene of each chapter")
    demo.add_argument("names", nargs="*", help=f"chapters to run (default all): {', '.join(DEMOS)}")
    sub.add_parser("list", help="list the chapter demos")
    args = parser.parse_args(argv)
    if args.command == "list":
        print("\n".join(DEMOS))
        return 0
    try:
        run_demos(args.names)
    except ValueError as exc:
        parser.error(str(exc))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
