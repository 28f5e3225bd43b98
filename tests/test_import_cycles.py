"""No two modules of the package import each other, counting imports inside functions too (the runner of the
comparison chapter lives in ``damage.runs``, not beside the specimens; the experiments demo beside the closed-form
checks, not in the compression tests)."""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "abrakit"


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path: Path) -> set[str]:
    """abrakit modules imported anywhere in the module (module level and inside functions)."""
    tree = ast.parse(path.read_text())
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.startswith("abrakit"):
                found.add(target)
                found.update(f"{target}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("abrakit"))
    return found


def test_no_two_modules_import_each_other():
    modules = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {m: {t for t in imports(p) if t in modules and t != m} for m, p in modules.items()}
    # a package importing its own submodules (``__init__``) is not a cycle of two modules
    for a, targets in graph.items():
        for b in targets:
            if a.startswith(b + ".") or b.startswith(a + "."):
                continue
            assert a not in graph.get(b, set()), f"import cycle: {a} <-> {b}"


def test_no_two_chapters_import_each_other():
    """Between the chapter packages and modules the imports run one way (the DEM's contact laws take the series rule
    of Eq. (4.11) from the identification, which imports nothing of the DEM)."""
    def chapter(module: str) -> str:
        parts = module.split(".")
        return ".".join(parts[:2])

    modules = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for m, p in modules.items():
        if m.count(".") < 1 or m.split(".")[1].startswith("_"):
            continue
        graph.setdefault(chapter(m), set()).update(
            chapter(t) for t in imports(p) if t in modules and t.count(".") >= 1 and chapter(t) != chapter(m))
    for a, targets in graph.items():
        for b in targets:
            assert a not in graph.get(b, set()), f"the chapters {a} and {b} import each other"
