"""The checkout's stored benchmark results, for the book's chapters: ``benchmarks/reproduction.py`` imported by path.

The chapters execute in ``book/``; the stored studies and the claims read from them belong to the checkout, not to
the installed package, so the chapters take :func:`stored_result`, :func:`status` and :func:`markdown` from here.
"""

import importlib.util
import sys
from pathlib import Path

_PATH = Path(__file__).resolve().parent.parent / "benchmarks" / "reproduction.py"
_NAME = "abrakit_benchmarks_reproduction"

if _NAME not in sys.modules:
    _spec = importlib.util.spec_from_file_location(_NAME, _PATH)
    sys.modules[_NAME] = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(sys.modules[_NAME])
_module = sys.modules[_NAME]

RESULTS, markdown, status, stored_result = _module.RESULTS, _module.markdown, _module.status, _module.stored_result

__all__ = ["RESULTS", "markdown", "status", "stored_result"]
