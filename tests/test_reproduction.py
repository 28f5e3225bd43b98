"""The reproduction table: every claim has a verdict; missing results say how to produce them.

The claims from stored studies are built by the checkout's ``benchmarks/reproduction.py``; the closed-form ones by
the package (``abrakit.reproduction``), which reads nothing of the checkout.
"""

import ast
import importlib.util
import inspect
import math
from pathlib import Path

import pytest

from abrakit import reproduction as P
from abrakit import wear

ROOT = Path(__file__).resolve().parent.parent
spec = importlib.util.spec_from_file_location("abrakit_benchmarks_reproduction",
                                              ROOT / "benchmarks" / "reproduction.py")
R = importlib.util.module_from_spec(spec)
spec.loader.exec_module(R)


def test_every_claim_has_a_verdict_and_table_8_4_from_the_seed_inputs_is_reproduced():
    claims = R.status()
    assert claims and all(c.verdict in R.VERDICTS for c in claims)
    seed_inputs = [c for c in claims if c.where == "Table 8.4" and "seed's" in c.quantity]
    assert seed_inputs[0].verdict == "reproduced"
    table = R.markdown(claims)
    assert table.startswith("| seed | quantity") and table.count("\n") == len(claims) + 1


def test_missing_results_are_not_computed_with_the_command(tmp_path):
    claims = R.status(tmp_path)
    missing = [c for c in claims if c.verdict == "not computed"]
    assert missing and all("python benchmarks/" in c.ours for c in missing)
    assert any(c.verdict == "reproduced" for c in claims)                 # the closed form needs no file


def test_grain_verdicts_follow_their_deviation(tmp_path):
    import json

    (tmp_path / "scratch_steady.json").write_text(json.dumps({
        "grains_at_2N": {"grain_100um": {"A_g_um2": 88.4, "f_ab": wear.GRAIN_100UM.f_ab, "f_ab_rates": 0.3},
                         "grain_200um": {"A_g_um2": 90.0, "f_ab": 0.5, "f_ab_rates": 0.4}},
        "table_8_4": {"from_sections": [1e-7] * 7, "seed_printed": [row[2] for row in wear.TABLE_8_4]}}))
    verdicts = {c.quantity: c.verdict for c in R.status(tmp_path) if c.where == "Sec. 8.2"}
    assert verdicts["groove area A_g, D = 100 µm grain at 2 N"] == "reproduced"
    assert verdicts["degree of wear f_ab, D = 100 µm grain"] == "reproduced"
    assert verdicts["groove area A_g, D = 200 µm grain at 2 N"] == "differs"


def test_grain_degree_of_wear_carries_its_spread_over_the_mesh_levels(tmp_path):
    import json

    grains = {"grain_100um": {"A_g_um2": 98.0, "f_ab": 0.18, "f_ab_rates": 0.08},
              "grain_200um": {"A_g_um2": 40.0, "f_ab": 0.18, "f_ab_rates": 0.089}}
    spread = {"100": {"levels": {"demo": {}, "coarse": {}}, "spread": {"f_ab_rates": 0.0033}},
              "200": {"levels": {"demo": {}}, "spread": {"f_ab_rates": 0.0}}}
    table = {"from_sections": [1e-7] * 7, "seed_printed": [row[2] for row in wear.TABLE_8_4]}
    (tmp_path / "scratch_steady.json").write_text(json.dumps({"grains_at_2N": grains, "mesh_spread": spread,
                                                              "table_8_4": table}))
    ours = {c.quantity: c.ours for c in R.status(tmp_path) if c.where == "Sec. 8.2"}
    assert ours["degree of wear f_ab, D = 100 µm grain"] == "0.18 (sections), 0.08 ± 0.003 over 2 meshes (rates)"
    assert ours["degree of wear f_ab, D = 200 µm grain"] == "0.18 (sections), 0.09 (rates)"      # one level: no ±


def test_anisotropic_claims_read_the_worst_bar_and_the_finest_dcb(tmp_path):
    import json

    rows = [{"study": "bar", "elements": n, "max_error_pct": e, "case": f"n = {n}", "size": n}
            for n, e in ((1, 0.001), (64, -0.3))]
    rows += [{"study": "dcb", "case": f"sigma_c = {s} MPa, h = {h} mm", "size": h, "error_pct": e}
             for s, h, e in ((30, 0.5, 5.0), (30, 0.125, 0.8), (60, 0.125, 6.0))]
    (tmp_path / "anisotropic_damage.json").write_text(json.dumps({"rows": rows}))
    claims = [c for c in R.status(tmp_path) if c.chapter == "anisotropic_damage"]
    assert claims[0].verdict == "reproduced" and "0.30%" in claims[0].ours
    assert "sigma_c = 30 MPa, h = 0.125 mm" in claims[1].quantity and claims[1].verdict == "reproduced"


def test_the_package_reads_nothing_of_the_checkout():
    tree = ast.parse(inspect.getsource(P))
    imported = {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import | ast.ImportFrom)
                for alias in node.names} | {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    names = {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}
    assert not imported & {"pathlib", "Path", "os", "subprocess", "read_json", "io"}
    assert not names & {"__file__", "open", "Path"}
    assert not hasattr(P, "status") and not hasattr(P, "stored_result")


def test_recomputed_claims_are_the_tables_closed_form_rows(tmp_path):
    ours = P.recomputed()
    assert [c.chapter for c in ours] == ["wear"] + ["fatigue"] * 6
    assert ours[0].verdict == "reproduced"
    assert [c for c in R.status(tmp_path) if c.chapter in ("wear", "fatigue")] == ours


@pytest.mark.parametrize("deviation, expected", [(0.0, "reproduced"), (-0.01, "reproduced"), (0.0101, "close"),
                                                 (-0.05, "close"), (0.0501, "differs")])
def test_verdict_bands(deviation, expected):
    assert P.verdict(deviation) == expected
    assert P.verdict(0.1, close=0.15) == "close" and P.verdict(0.0, close=0.0, reproduced=0.0) == "reproduced"


@pytest.mark.parametrize("kwargs, name", [({"deviation": math.nan}, "deviation"), ({"deviation": None}, "deviation"),
                                          ({"deviation": 0.0, "close": -0.1}, "close"),
                                          ({"deviation": 0.0, "reproduced": 0.1}, "reproduced")])
def test_verdict_refuses_bad_input_by_name(kwargs, name):
    with pytest.raises((ValueError, TypeError), match=name):
        P.verdict(**kwargs)
