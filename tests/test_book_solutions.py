"""Exercise solutions are computed at build time (book/check_solutions.py): every solution runs a code cell, and a
number its prose states that none of its cells printed is found."""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parent.parent / "book"
CHAPTERS = sorted(p for p in BOOK.glob("*.md") if p.stem not in {"api", "bibliography", "decisions"})


def _check():
    spec = importlib.util.spec_from_file_location("check_solutions", BOOK / "check_solutions.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["check_solutions"] = module
    spec.loader.exec_module(module)
    return module


check = _check()


@pytest.mark.parametrize("chapter", CHAPTERS, ids=lambda p: p.stem)
def test_every_solution_runs_a_code_cell(chapter):
    problems = check.source_problems(chapter)
    if chapter.stem in check.TYPED_PENDING:
        assert any("is typed" in p for p in problems), f"{chapter.stem} is converted: remove it from TYPED_PENDING"
    else:
        assert problems == []


def test_a_typed_solution_and_one_without_code_are_found(tmp_path):
    chapter = tmp_path / "x.md"
    chapter.write_text("```{solution} typed\n:class: dropdown\nE = 19.84 GPa\n```\n\n"
                       "```{solution-start} empty\n```\nE = 19.84 GPa\n```{solution-end}\n```\n\n"
                       "```{solution-start} computed\n```\n```{code-cell} ipython3\nprint(1)\n```\n"
                       "```{solution-end}\n```\n")
    problems = check.source_problems(chapter)
    assert len(problems) == 2 and "'typed'" in problems[0] and "'empty'" in problems[1]


def test_a_stale_number_is_found_and_a_printed_one_matches_to_its_digits():
    solution = check.Solution("x", "y", prose="E = 19.84 GPa at windows 0.03 and 0.1 (−3 %), 1.77·10⁻⁵, "
                              "34 180 cycles; Eq. (5.21), Table 8.4, `f(0.22)`, 10 transits",
                              code=["print(E)"], outputs=["19.8412 0.03 1.7712e-05 34180 -3.0"])
    assert check.unmatched(solution, exercise="windows 0.1 and 0.3") == []
    solution.outputs = ["20.98 0.03 1.7712e-05 34180 -3.0"]
    assert check.unmatched(solution, exercise="windows 0.1 and 0.3") == ["19.84"]


def test_an_executed_notebook_yields_its_solution_prose_code_and_outputs(tmp_path):
    cells = [
        {"cell_type": "markdown", "source": "```{exercise}\n:label: ex-a\nUse a window of 0.3.\n```\n"},
        {"cell_type": "markdown", "source": "```{solution-start} ex-a\n:class: dropdown\n```\nE is 20.98 GPa."},
        {"cell_type": "code", "source": "print(20.977)", "outputs": [{"output_type": "stream", "text": "20.977\n"}]},
        {"cell_type": "markdown", "source": "```{solution-end}\n```"},
    ]
    notebook = tmp_path / "chapter.ipynb"
    notebook.write_text(json.dumps({"cells": cells}))
    solutions, exercises = check.executed_solutions(notebook)
    assert [s.label for s in solutions] == ["ex-a"] and "0.3" in exercises["ex-a"]
    assert check.unmatched(solutions[0], exercises["ex-a"]) == []
