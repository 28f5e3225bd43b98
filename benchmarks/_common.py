"""What every benchmark script shares: saving its figure and its command line."""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def save_figure(fig, path, dpi: int = 120) -> Path:
    """Lay out, write and close ``fig``."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return Path(path)


def study_dirs(outdir, name: str) -> tuple[Path, Path]:
    """Create ``outdir`` and its ``<name>_checkpoints`` folder (where a study's runs keep their resumable state);
    return both."""
    outdir = Path(outdir)
    checkpoints = outdir / f"{name}_checkpoints"
    checkpoints.mkdir(parents=True, exist_ok=True)
    return outdir, checkpoints


def command_line(main, doc: str, quick_help: str = "a smaller, faster study", report=None):
    """Run ``main(outdir, quick)`` from the command line (``--quick``, ``--outdir``) and print its report.

    ``report(result) -> str`` formats the result; by default its ``"summary"`` entry is printed.
    """
    parser = argparse.ArgumentParser(description=doc.strip().splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=quick_help)
    parser.add_argument("--outdir", type=Path, default=RESULTS)
    args = parser.parse_args()
    result = main(args.outdir, quick=args.quick)
    if report is not None:
        print(report(result))
    elif isinstance(result, dict) and "summary" in result:
        print(result["summary"])
    return result
