"""The ``abrakit`` command line: ``abrakit demo`` runs the small scene of each book chapter, ``abrakit list`` names
them (the chapters' file names in ``book/``); the scenes live in :mod:`abrakit._demos`."""

from __future__ import annotations

import argparse
import sys
import textwrap
import time

from ._demos import DEMOS, REFERENCE_PAGES, demo

__all__ = ["main", "run_demos"]

DESCRIPTION = "\n\n".join(textwrap.fill(paragraph, 79) for paragraph in (
    "abrakit: the abrasive-wear modelling chain of Hoormazdi (2021).",
    "'abrakit demo' runs one small scene of each book chapter and prints its summary and wall time; 'abrakit demo "
    "CHAPTER ...' runs the chapters named; 'abrakit list' prints the chapters, one per line.",
))

CHAPTERS_HELP = (
    "Chapters, named like the book's files (book/<chapter>.md): " + ", ".join(DEMOS) + ". The reference pages ("
    + ", ".join(REFERENCE_PAGES) + ") have no demo; 'intro' prints the reproduction verdicts the package "
    "recomputes itself."
)


def run_demos(names=None, out=sys.stdout) -> dict[str, float]:
    """Run the named chapter demos (all by default, in the order of the book); print each summary with its wall
    time to ``out`` and return the wall times in seconds."""
    names = list(DEMOS) if names is None else list(names)
    unknown = [n for n in names if n not in DEMOS]
    if unknown:
        raise ValueError(f"unknown demo(s) {unknown}; choose from {list(DEMOS)}")
    times = {}
    for name in names:
        start = time.perf_counter()
        summary = demo(name)
        times[name] = time.perf_counter() - start
        print(f"== {name} ({times[name]:.1f} s)\n{summary}\n", file=out, flush=True)
    print(f"all demos: {sum(times.values()):.1f} s", file=out)
    return times


def _parser() -> argparse.ArgumentParser:
    from abrakit import __version__

    parser = argparse.ArgumentParser(prog="abrakit", description=DESCRIPTION, epilog=textwrap.fill(CHAPTERS_HELP, 79),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"abrakit {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="{demo,list}")
    demo_parser = sub.add_parser("demo", help="run the small scene of each chapter (or of those named)",
                                 description="Run the small scene of each chapter named (default: every chapter, "
                                 "in the order of the book) and print its summary and wall time.",
                                 epilog=CHAPTERS_HELP)
    demo_parser.add_argument("names", nargs="*", metavar="CHAPTER", help="a chapter to run (default: all)")
    sub.add_parser("list", help="print the chapters that have a demo, one per line",
                   description="Print the chapters that have a demo, one per line, in the order of the book.")
    return parser


def main(argv=None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.command == "list":
        print("\n".join(DEMOS))
        return 0
    try:
        run_demos(args.names or None)
    except ValueError as exc:
        parser.error(str(exc))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
