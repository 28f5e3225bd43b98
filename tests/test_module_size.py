"""Sizes a reader can hold: no module of the package over 600 lines, no function (or method) over 100 lines.

The modules and functions over these sizes are listed with their size as an upper bound that can only shrink (as the
bounds of ``tests/test_api_fuzz.py``): a listed one may shrink, never grow, and nothing new joins the list. One that
fits leaves the list; until it does, the test warns (``ListedButFits``) instead of failing, so a split that lands
while the list still names it breaks nothing."""

import ast
import warnings
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "abrakit"
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 100

#: Modules over ``MAX_MODULE_LINES`` and the most lines they may have (path relative to the repository).
ALLOWED_MODULES: dict[str, int] = {}

#: Functions over ``MAX_FUNCTION_LINES`` (``module path:qualified name``) and the most lines they may have.
ALLOWED_FUNCTIONS: dict[str, int] = {}


def relative(path: Path) -> str:
    return path.relative_to(PACKAGE.parent).as_posix()


def module_lines() -> dict[str, int]:
    return {relative(p): len(p.read_text().splitlines()) for p in sorted(PACKAGE.rglob("*.py"))}


def function_lines() -> dict[str, int]:
    """``{"path:Outer.name": end_lineno - lineno + 1}`` of every ``def`` and ``async def``, nested ones included."""
    out = {}

    def visit(node, prefix, path):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                name = f"{prefix}{child.name}"
                if not isinstance(child, ast.ClassDef):
                    out[f"{path}:{name}"] = child.end_lineno - child.lineno + 1
                visit(child, f"{name}.", path)
            else:
                visit(child, prefix, path)

    for p in sorted(PACKAGE.rglob("*.py")):
        visit(ast.parse(p.read_text()), "", relative(p))
    return out


def over(sizes: dict[str, int], limit: int, allowed: dict[str, int]) -> tuple[list[str], list[str], list[str]]:
    """(new offenders, allowed ones that grew, allowed ones that now fit or are gone)."""
    new = [f"{k}: {n} lines" for k, n in sizes.items() if n > limit and k not in allowed]
    grown = [f"{k}: {sizes[k]} lines, allowed {n}" for k, n in allowed.items() if sizes.get(k, 0) > n]
    fitting = [k for k in allowed if sizes.get(k, 0) <= limit]
    return new, grown, fitting


class ListedButFits(UserWarning):
    """An allowed module or function now fits its limit: remove it from the list."""


def test_no_module_over_600_lines():
    new, grown, fitting = over(module_lines(), MAX_MODULE_LINES, ALLOWED_MODULES)
    assert new == [], f"modules over {MAX_MODULE_LINES} lines: split them into modules of one job each"
    assert grown == [], "allowed modules may only shrink"
    if fitting:
        warnings.warn(f"fit now (or are gone), remove them from ALLOWED_MODULES: {fitting}", ListedButFits,
                      stacklevel=1)


def test_no_function_over_100_lines():
    new, grown, fitting = over(function_lines(), MAX_FUNCTION_LINES, ALLOWED_FUNCTIONS)
    assert new == [], f"functions over {MAX_FUNCTION_LINES} lines: split them"
    assert grown == [], "allowed functions may only shrink"
    if fitting:
        warnings.warn(f"fit now (or are gone), remove them from ALLOWED_FUNCTIONS: {fitting}", ListedButFits,
                      stacklevel=1)


def test_the_counts_see_what_they_should():
    """The walk finds modules of every depth and methods inside classes."""
    modules, functions = module_lines(), function_lines()
    assert "abrakit/__init__.py" in modules and "abrakit/damage/laplacian.py" in modules
    assert "abrakit/evolution/__init__.py:Dissipation.conjugate" in functions
    assert "abrakit/damage/laplacian.py:element_laplacian" in functions
