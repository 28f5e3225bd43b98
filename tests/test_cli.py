"""The command line runs each chapter's demo and rejects unknown names."""

import io

import pytest

from abrakit import cli


def test_every_demo_runs_and_reports():
    out = io.StringIO()
    times = cli.run_demos(out=out)
    assert set(times) == set(cli.DEMOS)
    assert "all demos" in out.getvalue()


def test_unknown_demo_is_refused():
    with pytest.raises(ValueError, match="unknown demo"):
        cli.run_demos(["nope"])
    with pytest.raises(SystemExit):
        cli.main(["demo", "nope"])
    assert cli.main(["list"]) == 0
