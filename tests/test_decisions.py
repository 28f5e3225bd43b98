"""Every decision of abrakit.decisions names tests and benchmarks that exist, and the book renders them."""

import ast
from pathlib import Path

import pytest

from abrakit.decisions import DECISIONS, markdown

ROOT = Path(__file__).resolve().parent.parent
KINDS = {"misprint", "ambiguity", "reconstruction", "choice"}


def _functions(path: Path) -> set[str]:
    return {node.name for node in ast.walk(ast.parse(path.read_text())) if isinstance(node, ast.FunctionDef)}


@pytest.mark.parametrize("decision", DECISIONS, ids=lambda d: d.topic[:40])
def test_every_decision_is_pinned_by_an_existing_test(decision):
    assert decision.kind in KINDS
    assert decision.tests, decision.topic
    for reference in decision.tests:
        file, _, name = reference.partition("::")
        assert (ROOT / file).is_file(), reference
        if name:
            assert name in _functions(ROOT / file), reference
    assert (ROOT / "book" / f"{decision.chapter}.md").is_file(), decision.chapter


def test_the_book_has_a_decisions_page_that_renders_them():
    page = (ROOT / "book" / "decisions.md").read_text()
    assert "abrakit.decisions" in page and "decisions" in (ROOT / "book" / "_toc.yml").read_text()
    table = markdown()
    assert table.count("\n") == len(DECISIONS) + 1


def test_bars_inside_cells_are_escaped():
    rows = markdown().splitlines()[2:]
    assert all(row.replace("\\|", "").count("|") == 7 for row in rows)
