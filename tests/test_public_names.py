"""The public surface is one face per chapter: ``abrakit.__all__`` names the chapter packages and modules, each
lists in its ``__all__`` the objects its chapter uses, the book and the examples import from the faces only, and
every name a face lists is used by the book, an example or another chapter's code."""

import ast
import importlib
import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

import abrakit

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "abrakit"
CELL = re.compile(r"```\{code-cell\}[^\n]*\n(.*?)```", re.S)

FACES = ("tensors", "evolution", "dem", "identification", "experiments", "materials", "fem", "damage", "scratch",
         "wear", "g65", "fatigue")
"""The chapters, in the book's order: each a package whose ``__init__`` is its face, or a module."""

PLUMBING = ("io", "reproduction", "decisions")
"""Modules of the package that are no chapter but that the book may import by full name (files, stored results,
the decision log); their ``__all__`` says what."""

PUBLIC_NAMES = 243
"""The names the twelve faces list, in all (``sum(len(abrakit.<face>.__all__))``); the surface is recorded here, so
a change of it is a change of this number."""

BOOK = "api.md"
"""The API reference shows the faces; it does not count as a use of a name."""


def face(name: str):
    return importlib.import_module(f"abrakit.{name}")


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
        if path.name != BOOK:
            yield path.name, "\n".join(cell_code(c) for c in CELL.findall(path.read_text()))
    for path in sorted((ROOT / "examples").glob("*.py")):
        yield path.name, path.read_text()


def parsed(text: str) -> ast.Module:
    lines = [ln for ln in text.split("\n") if not ln.lstrip().startswith(("%", "!"))]   # IPython magics
    return ast.parse("\n".join(lines))


def references(tree: ast.Module):
    """``(module, name)`` of every ``from abrakit... import name`` and every ``alias.name`` of an imported abrakit
    module (``import abrakit.x as alias``, ``from abrakit import x``), except where the alias is rebound."""
    aliases = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("abrakit"):
            for a in node.names:
                yield node.module, a.name
                if node.module == "abrakit":
                    aliases[a.asname or a.name] = f"abrakit.{a.name}"
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("abrakit"):
                    yield a.name, None
                    if a.asname:
                        aliases[a.asname] = a.name
    rebound = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases
                and node.value.id not in rebound):
            yield aliases[node.value.id], node.attr


def allowed(module: str, name: str | None) -> bool:
    """``from abrakit import <face>``, ``from abrakit.<face> import <listed name>``, the same for the plumbing."""
    if module == "abrakit":
        return name is None or name in FACES or name in PLUMBING
    parts = module.split(".")
    if len(parts) != 2 or parts[1] not in FACES + PLUMBING:
        return False
    return name is None or name in importlib.import_module(module).__all__


def implementation_modules():
    """The modules inside the chapter packages (not their faces)."""
    for path in sorted(PACKAGE.glob("*/*.py")):
        if path.name != "__init__.py" and not path.parent.name.startswith("_"):
            yield path


def test_the_top_level_names_the_chapters_and_loads_them_on_first_use():
    assert [n for n in abrakit.__all__ if n not in ("__version__", "demo")] == list(FACES) == list(abrakit.MODULES)
    code = "import abrakit; abrakit.g65, abrakit.scratch.ScratchScene; print(sorted(abrakit.__all__)[0])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "__version__"


@pytest.mark.parametrize("name", FACES)
def test_every_face_lists_objects_it_holds(name):
    module = face(name)
    listed = module.__all__
    assert len(listed) == len(set(listed)), f"abrakit.{name} lists a name twice"
    assert 1 <= len(listed) <= 30, f"abrakit.{name} lists {len(listed)} names"
    for item in listed:
        obj = getattr(module, item)                     # AttributeError: listed but not there
        assert not inspect.ismodule(obj), f"abrakit.{name}.{item} is a module: list its objects instead"
        assert item != "demo" and not item.startswith("_")


def test_the_public_surface_has_its_recorded_size():
    sizes = {name: len(face(name).__all__) for name in FACES}
    assert sum(sizes.values()) == PUBLIC_NAMES, sizes


def test_implementation_modules_declare_no_public_list():
    """The face says what is public; a module inside a chapter package does not repeat it."""
    declaring = [str(p.relative_to(ROOT)) for p in implementation_modules()
                 if any(isinstance(n, ast.Assign) and any(getattr(t, "id", None) == "__all__" for t in n.targets)
                        for n in ast.parse(p.read_text()).body)]
    assert declaring == []


@pytest.mark.parametrize("name,text", list(sources()), ids=[n for n, _ in sources()])
def test_the_book_and_the_examples_import_from_the_faces_only(name, text):
    below = sorted({f"{m}.{n}" if n else m for m, n in references(parsed(text)) if not allowed(m, n)})
    assert below == [], f"{name} reaches below the faces: {below}"


def _chapter(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in FACES else None


def _used_by_other_chapters() -> set[int]:
    """Ids of the objects that a module of one chapter imports from another chapter."""
    used = set()
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(ROOT).with_suffix("").parts
        here = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        package = here if path.name == "__init__.py" else here.rsplit(".", 1)[0]
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("abrakit") or _chapter(target) is None or _chapter(target) == _chapter(here):
                continue
            module = importlib.import_module(target)
            used.update(id(getattr(module, a.name)) for a in node.names if hasattr(module, a.name))
    return used


def test_every_public_name_is_used_by_the_book_an_example_or_another_chapter():
    """A name counts as used where a chapter or an example names it (in code or text), where another chapter's
    code imports it, or where it is the type of a parameter or result of a used name of its face."""
    words = set()
    for path in [*(ROOT / "book").glob("*.md"), *(ROOT / "examples").glob("*.py")]:
        if path.name != BOOK:
            words.update(re.findall(r"\w+", path.read_text()))
    elsewhere = _used_by_other_chapters()
    unused = []
    for name in FACES:
        module = face(name)
        used = {n for n in module.__all__ if n in words or id(getattr(module, n)) in elsewhere}
        annotations = " ".join(str(getattr(getattr(module, n), "__annotations__", "")) + " "
                               + str(getattr(getattr(getattr(module, n), "__init__", None), "__annotations__", ""))
                               for n in used if callable(getattr(module, n)))
        unused += [f"abrakit.{name}.{n}" for n in module.__all__
                   if n not in used and not re.search(rf"\b{n}\b", annotations)]
    assert unused == [], "\n".join(unused)
