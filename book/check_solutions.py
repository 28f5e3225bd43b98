"""Exercise solutions are computed, not typed: every solution runs code, and states only numbers that code printed.

Two checks, both run by ``make book``:

* **source** (before the build): every ``{solution}`` of a chapter is gated, ``{solution-start}`` ...
  ``{solution-end}``, with at least one code cell between, so its numbers come from the build.
* **executed** (after the build): every result number in a solution's prose (a number with a decimal point or an
  exponent, or an integer of three or more digits) is one that the solution's own code cells printed or wrote in
  their source, or that its exercise states. A number matches when it agrees with a printed one to the digits it
  shows (``19.84`` matches ``19.8412``); signs are ignored (a "−3 %" change may be printed as a fall of 3).

Equation, table, figure, section and chapter numbers ("Eq. (5.21)", "Table 8.4"), TeX subscripts (``S_{2323}``)
and inline code are not result numbers. Usage: ``python book/check_solutions.py [--source-only]``; exits non-zero naming each offending solution.
"""

from __future__ import annotations

import json
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

BOOK = Path(__file__).resolve().parent
EXECUTED = BOOK / "_build" / "jupyter_execute"
#: Chapters whose solutions are still typed, to be converted; the source check passes them over, and
#: ``tests/test_book_solutions.py`` fails once one of them has no typed solution left (so the list only shrinks).
TYPED_PENDING = frozenset({
    "dem_identification", "model_one", "scratch", "scratch_to_wear", "scratch_volume",
})

FENCE_OPEN = re.compile(r"^(`{3,}|:{3,})\{(solution|solution-start|solution-end|exercise)\}\s*(\S*)", re.M)
CODE_CELL = re.compile(r"^```\{code-cell\}", re.M)
SPACES = {ord(c): None for c in " \u2009\u202f\u00a0"}
SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
REFERENCE = re.compile(r"\b(?:Eqs?\.|Equations?|Tables?|Figs?\.|Figures?|Secs?\.|Sections?|Ch\.|Chapters?|"
                       r"Algorithms?|Appendix)\s*\(?[A-Z]?\d+(?:\.\d+)*\)?(?:\s*(?:[–,-]|and|to)\s*\(?\d+(?:\.\d+)+\)?)*")
NUMBER = re.compile(r"(?<![\w.])[−-]?(?:\d{1,3}(?:[ \u2009\u202f\u00a0]\d{3})+|\d+)(?:\.\d+)?"
                    r"(?:\s*[·×]\s*10([⁻⁺]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+)|[eE]([-+]?\d+))?(?![\w.]*\d)")


@dataclass
class Solution:
    chapter: str
    label: str
    prose: str = ""
    code: list[str] = field(default_factory=list)
    outputs: list[str] = field(default_factory=list)


def _value(match: re.Match) -> tuple[float, float] | None:
    """The number and half a unit of its last shown digit, or None for a small integer (an input, a count)."""
    text = match.group(0).replace("−", "-").translate(SPACES)
    mantissa = re.split(r"[·×eE]", text)[0].strip()
    exponent = match.group(1) or match.group(2)
    exponent = int(exponent.translate(SUPERSCRIPT)) if exponent else 0
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    if decimals == 0 and not exponent and abs(int(mantissa)) < 100:
        return None
    scale = 10.0 ** exponent
    return float(mantissa) * scale, 0.5 * 10.0 ** -decimals * scale


def _numbers(text: str, *, results_only: bool) -> list[tuple[str, float, float]]:
    text = re.sub(r"`[^`]*`", " ", text)
    text = re.sub(r"_\{[^}]*\}|_\w", " ", text)          # subscripts are indices, not results
    text = REFERENCE.sub(" ", text)
    found = []
    for match in NUMBER.finditer(text):
        value = _value(match)
        if value is None and results_only:
            continue
        if value is None:
            value = (float(match.group(0).replace("−", "-").translate(SPACES)), 0.5)
        found.append((match.group(0), *value))
    return found


def _known(text: str) -> list[float]:
    """Every number written in code or printed output, as floats (integers and e-notation included)."""
    return [float(m) for m in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", text.replace("_", ""))]


def unmatched(solution: Solution, exercise: str = "") -> list[str]:
    """The result numbers of a solution's prose that none of its cells printed or wrote and its exercise lacks."""
    known = _known("\n".join(solution.code + solution.outputs))
    known += [value for _, value, _ in _numbers(exercise, results_only=False)]
    known += _known(exercise)
    missing = []
    for shown, value, half_unit in _numbers(solution.prose, results_only=True):
        tolerance = half_unit * (1 + 1e-9) + 1e-12 * abs(value)
        if not any(abs(abs(value) - abs(k)) <= tolerance for k in known):
            missing.append(shown)
    return missing


def source_problems(chapter: Path) -> list[str]:
    """Solutions of a chapter's MyST source that are not gated or run no code cell."""
    text = chapter.read_text(encoding="utf-8")
    problems, start = [], None
    for match in FENCE_OPEN.finditer(text):
        kind, label = match.group(2), match.group(3)
        if kind == "solution":
            problems.append(f"{chapter.stem}: solution {label!r} is typed, not computed (use solution-start/-end "
                            "around a code cell)")
        elif kind == "solution-start":
            start = (label, match.end())
        elif kind == "solution-end" and start is not None:
            if not CODE_CELL.search(text, start[1], match.start()):
                problems.append(f"{chapter.stem}: solution {start[0]!r} has no code cell")
            start = None
    return problems


def _cell_text(cell: dict) -> str:
    source = cell.get("source", "")
    return "".join(source) if isinstance(source, list) else source


def _output_text(cell: dict) -> list[str]:
    texts = []
    for output in cell.get("outputs", []):
        if "text" in output:
            texts.append("".join(output["text"]) if isinstance(output["text"], list) else output["text"])
        for mime in ("text/plain", "text/markdown", "text/html"):
            data = output.get("data", {}).get(mime)
            if data:
                texts.append("".join(data) if isinstance(data, list) else data)
    return texts


def executed_solutions(notebook: Path) -> tuple[list[Solution], dict[str, str]]:
    """The gated solutions of an executed chapter notebook, and its exercises' texts by label."""
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    solutions, exercises, current = [], {}, None
    for cell in cells:
        text = _cell_text(cell)
        if cell["cell_type"] == "markdown":
            for block in re.finditer(r"\{exercise\}[^\n]*\n:label:\s*(\S+)\n(.*?)\n(?:`{3,}|:{3,})\s*$", text,
                                     re.S | re.M):
                exercises[block.group(1)] = block.group(2)
            start = re.search(r"\{solution-start\}\s*(\S+)", text)
            if start:
                current = Solution(notebook.stem, start.group(1))
                solutions.append(current)
                text = text[start.end():]
            if current is not None:
                end = re.search(r"\{solution-end\}", text)
                current.prose += "\n" + (text[:end.start()] if end else text)
                if end:
                    current = None
        elif current is not None:
            current.code.append(text)
            current.outputs.extend(_output_text(cell))
    return solutions, exercises


def main(argv: list[str]) -> int:
    chapters = sorted(p for p in BOOK.glob("*.md") if p.stem not in {"api", "bibliography", "decisions"})
    problems = [problem for chapter in chapters if chapter.stem not in TYPED_PENDING
                for problem in source_problems(chapter)]
    checked = 0
    if "--source-only" not in argv:
        for chapter in chapters:
            notebook = EXECUTED / f"{chapter.stem}.ipynb"
            if not notebook.exists():
                continue
            solutions, exercises = executed_solutions(notebook)
            for solution in solutions:
                checked += 1
                missing = unmatched(solution, exercises.get(solution.label, ""))
                if missing:
                    problems.append(f"{solution.chapter}: solution {solution.label!r} states "
                                    f"{', '.join(missing)}, which none of its cells printed")
    for problem in problems:
        print(problem)
    print(f"solutions: {checked} executed solution(s) checked, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
