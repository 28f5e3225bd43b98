"""Keep the book's execution cache honest: clear it when anything the chapters execute against has changed.

Jupyter Book's ``execute_notebooks: cache`` re-executes a chapter only when its code cells change. The chapters also
run the package and read the stored benchmark results, so this script hashes ``abrakit/**/*.py``,
``benchmarks/results/**``, the module that reads them (``benchmarks/reproduction.py``, ``book/benchmark_results.py``)
and ``pyproject.toml`` and deletes ``book/_build/.jupyter_cache`` and Sphinx's saved
environment (``.doctrees``) when the hash differs from the one of the last build (``make book`` runs it first; a
fresh clone has no cache and executes everything).
"""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BUILD = ROOT / "book" / "_build"
STAMP = BUILD / ".abrakit_cache_key"


def current_key() -> str:
    digest = hashlib.sha256()
    files = sorted([*ROOT.glob("abrakit/**/*.py"), *(p for p in ROOT.glob("benchmarks/results/**/*") if p.is_file()),
                    ROOT / "benchmarks" / "reproduction.py", ROOT / "book" / "benchmark_results.py",
                    ROOT / "pyproject.toml"])
    for path in files:
        digest.update(str(path.relative_to(ROOT)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def main() -> None:
    key = current_key()
    if not STAMP.exists() or STAMP.read_text() != key:
        # the execution cache, and Sphinx's saved environment: without it Sphinx would re-read (and so re-execute)
        # only the chapters whose source changed
        shutil.rmtree(BUILD / ".jupyter_cache", ignore_errors=True)
        shutil.rmtree(BUILD / ".doctrees", ignore_errors=True)
        BUILD.mkdir(parents=True, exist_ok=True)
        STAMP.write_text(key)
        print("book: package or results changed, execution cache cleared")


if __name__ == "__main__":
    main()
