"""The book and the examples use the public surface only: every name they import from abrakit, or reach as an
attribute of an imported abrakit module, is listed in that module's ``__all__`` (or is one of its submodules)."""

import ast
import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CELL = re.compile(r"```\{code-cell\}[^\n]*\n(.*?)```", re.S)


def cell_code(cell: str) -> str:
    """A code cell without its options: a ``---`` YAML block or ``:key: value`` lines at its top."""
    if cell.startswith("---\n"):
        cell = cell.split("\n---\n", 1)[1]
    lines = cell.split("\n")
    while lines and re.match(r"^:[\w-]+:", lines[0]):
        lines.pop(0)
    return "\n".join(lines)


def sources():
    for path in sorted((ROOT / "book").glob("*.md")):
        yield path.name, "\n".join(cell_code(c) for c in CELL.findall(path.read_text()))
    for path in sorted((ROOT / "examples").glob("*.py")):
        yield path.name, path.read_text()


def parsed(text: str) -> ast.Module:
    lines = [ln for ln in text.split("\n") if not ln.lstrip().startswith(("%", "!"))]   # IPython magics
    return ast.parse("\n".join(lines))


def public(module_name: str, name: str) -> bool:
    module = importlib.import_module(module_name)
    if name in getattr(module, "__all__", ()):
        return True
    try:
        importlib.import_module(f"{module_name}.{name}")
        return True
    except ImportError:
        return False


def used_names(tree: ast.Module):
    """``(module, name)`` of every ``from abrakit... import name`` and every ``alias.name`` of an imported abrakit
    module."""
    aliases = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("abrakit"):
            for a in node.names:
                target = f"{node.module}.{a.name}"
                try:
                    importlib.import_module(target)
                    aliases[a.asname or a.name] = target
                except ImportError:
                    yield node.module, a.name
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("abrakit") and a.asname:
                    aliases[a.asname] = a.name
    rebound = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases
                and node.value.id not in rebound):
            yield aliases[node.value.id], node.attr


@pytest.mark.parametrize("name,text", list(sources()), ids=[n for n, _ in sources()])
def test_the_book_and_the_examples_use_public_names_only(name, text):
    private = sorted({f"{m}.{n}" for m, n in used_names(parsed(text)) if not public(m, n)})
    assert private == [], f"{name} uses names outside __all__: {private}"
