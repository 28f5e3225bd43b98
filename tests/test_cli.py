"""The command line runs each chapter's demo and rejects unknown names."""

import io

import pytest

from abrakit import cli


@pytest.mark.parametrize("name", list(cli.DEMOS))
def test_every_demo_runs_and_reports(name):
    """One test per chapter's demo (about 50 s in all; separate tests let the test workers share them)."""
    out = io.StringIO()
    times = cli.run_demos([name], out=out)
    assert set(times) == {name}
    assert f"== {name} (" in out.getvalue() and "all demos" in out.getvalue()


def test_demos_are_named_like_the_chapters():
    from pathlib import Path

    toc = (Path(__file__).parent.parent / "book" / "_toc.yml").read_text()
    chapters = {line.split("file:")[1].strip() for line in toc.splitlines() if "file:" in line}
    assert set(cli.DEMOS) <= chapters | {"intro"}


def test_unknown_demo_is_refused():
    with pytest.raises(ValueError, match="unknown demo"):
        cli.run_demos(["nope"])
    with pytest.raises(SystemExit):
        cli.main(["demo", "nope"])
    assert cli.main(["list"]) == 0


def test_version_is_the_package_version(capsys):
    from pathlib import Path

    tomllib = pytest.importorskip("tomllib")             # Python >= 3.11

    from abrakit import __version__

    project = tomllib.loads((Path(__file__).parent.parent / "pyproject.toml").read_text())["project"]
    assert __version__ == project["version"]
    with pytest.raises(SystemExit) as exit_:
        cli.main(["--version"])
    assert exit_.value.code == 0 and capsys.readouterr().out.strip() == f"abrakit {__version__}"
    assert (Path(__file__).parent.parent / "LICENSE").read_text().startswith(f"{project['license']} License")


def test_every_chapter_module_is_an_attribute_of_the_package():
    import abrakit

    for name in abrakit.MODULES:
        assert getattr(abrakit, name).__name__ == f"abrakit.{name}"
    with pytest.raises(AttributeError, match="no attribute"):
        _ = abrakit.nonexistent
