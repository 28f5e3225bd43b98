"""The command line: one demo per chapter of the book, each runs and says what its chapter says; plain-text help."""

import io
import re
from pathlib import Path

import pytest

import abrakit
from abrakit import _demos, cli

BOOK = Path(__file__).resolve().parent.parent / "book"

#: The caveat the chapter "From our scratches to a wear rate" draws on the f_ab of a short scratch.
TRANSIENT = ("transient reading", "not in steady removal")

#: What each demo's summary must contain (its chapter's checks, in the words the demo prints them).
CLAIMS = {
    "intro": ("Table 8.4", "benchmarks/reproduction.py"),
    "tensors": ("Eq. (5.18)", "max error", "positive part"),
    "evolution": ("observed orders", "plasticity", "damage"),
    "dem": ("restitution", "t* =", "wave speed", "particle-steps/s"),
    "identification": ("published", "consistent", "affine", "0.6667"),
    "dem_identification": ("Eq. (5.20)", "wall", "not reproduced"),
    "fem": ("Quarter plate with a hole", "Newton iterations", "DOF/s"),
    "plasticity": ("sqrt(2 r_d E)", "error"),
    "localisation": ("local", "model_one", "model_two", "finest/coarsest"),
    "model_one": ("fallbacks 0", "quads", "Model I", "peak"),
    "model_two": ("Model II", "peak force", "balance error"),
    "comparison": ("Model I ", "Model II", "weak", "strong", "fractured"),
    "anisotropic_damage": ("1 element(s)", "64 element(s)", "G_Ic A"),
    "contacting": ("N_c D^2 =", "Eq. 8.7"),
    "wear": ("114.62 mm2", "8.07", "0.44", "wedging"),
    "scratch": ("|t_T|/p = 0.1000, slip", "stick", "Hertz", "finite strain with F-bar", "f_ab = ", *TRANSIENT),
    "scratch_volume": ("closure", "small strain", "finite strain"),
    "scratch_to_wear": ("x 1e-7 m3/s", "seed's grain", "f_ab = ", *TRANSIENT),
    "material_removal": ("eps_f = 1.747", "inf (eta = -0.4)", "130.0 N", "0 mm3 if single passes remove nothing"),
    "fatigue": ("closed form", "cycle jump", "paper: 2008"),
    "four_point_bending": ("Eq. (44)", "Timoshenko", "Euler-Bernoulli"),
}


def code_chapters() -> list[str]:
    """The book's pages in the order of ``book/_toc.yml`` (root first) without the reference pages."""
    toc = (BOOK / "_toc.yml").read_text()
    pages = [line.split(":", 1)[1].strip() for line in toc.splitlines()
             if line.strip().startswith(("root:", "- file:"))]
    return [p for p in pages if p not in _demos.REFERENCE_PAGES]


def test_abrakit_list_is_the_books_chapters_with_code(capsys):
    assert cli.main(["list"]) == 0
    listed = capsys.readouterr().out.split()
    assert listed == code_chapters() == list(_demos.DEMOS)
    assert listed[0] == "intro" and listed[-1] == "four_point_bending"
    for page in _demos.REFERENCE_PAGES:                     # the pages without a demo are the book's pages too
        assert (BOOK / f"{page}.md").exists()
    for chapter in listed:                                  # every chapter with a demo has code cells
        assert "{code-cell}" in (BOOK / f"{chapter}.md").read_text(), chapter


def test_every_demo_has_its_claims():
    assert set(CLAIMS) == set(_demos.DEMOS)


@pytest.mark.parametrize("name", list(_demos.DEMOS))
def test_every_demo_runs_and_says_what_its_chapter_says(name):
    """One test per chapter's demo, so that test workers share them."""
    out = io.StringIO()
    times = cli.run_demos([name], out=out)
    text = out.getvalue()
    assert set(times) == {name} and times[name] > 0
    assert text.startswith(f"== {name} (") and "all demos" in text
    for claim in CLAIMS[name]:
        assert claim in text, f"demo {name!r} does not say {claim!r}"
    assert not re.search(r"<\w+>", text), "a summary is plain text, not markup"
    assert "mm3/s" not in text and "mm³/s" not in text                  # wear rates in m3/s, as the book


def test_the_intro_demo_is_one_line_per_recomputed_verdict():
    from abrakit.reproduction import recomputed

    lines = abrakit.demo("intro").splitlines()
    claims = recomputed()
    assert len(lines) == len(claims) + 1 and "benchmarks/reproduction.py" in lines[-1]
    assert all(line.strip().startswith(c.verdict) for line, c in zip(lines, claims, strict=False))


def test_unknown_demo_is_refused(capsys):
    with pytest.raises(ValueError, match="unknown demo"):
        cli.run_demos(["nope"])
    with pytest.raises(SystemExit):
        cli.main(["demo", "nope"])
    assert "unknown demo" in capsys.readouterr().err
    with pytest.raises(ValueError, match="chapter must be one of"):
        abrakit.demo("decisions")
    with pytest.raises(TypeError, match="chapter"):
        abrakit.demo(3)


@pytest.mark.parametrize("argv", [["--help"], ["demo", "--help"], ["list", "--help"]], ids=" ".join)
def test_help_is_plain_text(argv, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 0
    text = capsys.readouterr().out
    assert text.startswith("usage: abrakit")
    for markup in ("``", ":func:", ":mod:", ":data:", ":class:", "`"):
        assert markup not in text, f"{markup!r} in abrakit {' '.join(argv)}"
    if argv[0] != "list":
        assert "four_point_bending" in text and "decisions" in text


def test_version_is_the_package_version(capsys):
    tomllib = pytest.importorskip("tomllib")             # Python >= 3.11

    from abrakit import __version__

    project = tomllib.loads((BOOK.parent / "pyproject.toml").read_text())["project"]
    assert __version__ == project["version"]
    with pytest.raises(SystemExit) as exit_:
        cli.main(["--version"])
    assert exit_.value.code == 0 and capsys.readouterr().out.strip() == f"abrakit {__version__}"
    assert (BOOK.parent / "LICENSE").read_text().startswith(f"{project['license']} License")


def test_no_module_outside_the_demos_defines_a_demo():
    """The chapters' demos live in one place, under distinct names: no module of the package defines ``demo``."""
    package = Path(abrakit.__file__).parent
    offenders = [str(p.relative_to(package)) for p in package.rglob("*.py")
                 if "_demos" not in p.parts and p != package / "__init__.py"        # abrakit.demo serves them
                 and re.search(r"^def demo\(", p.read_text(), re.MULTILINE)]
    assert offenders == []
    names = [f.__name__ for f in _demos.DEMOS.values()]
    assert len(set(names)) == len(names) and all(n.startswith("demo_") for n in names)


def test_every_chapter_module_is_an_attribute_of_the_package():
    for name in abrakit.MODULES:
        assert getattr(abrakit, name).__name__ == f"abrakit.{name}"
    with pytest.raises(AttributeError, match="no attribute"):
        _ = abrakit.nonexistent
