"""Tests of the shared input checks and of the result files written as a run goes."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import ArrayLike

from abrakit import io
from abrakit import validation as V
from abrakit.damage.laplacian import taylor_matrix
from abrakit.damage.metrics import path_work
from abrakit.damage.model_one_path import DamageControl
from abrakit.experiments.specimen import members
from abrakit.fem.boundary import Constraints
from abrakit.fem.linsolve import banded_wins
from abrakit.fem.output import cell_fields
from abrakit.materials.anisotropic_damage import ProjectedBandWidth
from abrakit.materials.plasticity import plastic_step
from abrakit.scratch.checkpoint import fingerprint


def test_range_checks_name_the_parameter_and_the_interval():
    assert V.check_range("x", 0.5, 0, 1) == 0.5
    with pytest.raises(ValueError, match=r"nu must lie in \(-1, 0.5\)"):
        V.check_poisson("nu", 0.5)
    with pytest.raises(ValueError, match=r"kn must lie in \(0, inf\]"):
        V.check_positive("kn", [1.0, -2.0])
    assert V.check_positive("kn", 0.0, allow_zero=True) == 0.0
    with pytest.raises(ValueError, match="d must be finite"):
        V.check_range("d", np.nan, 0, 1)
    with pytest.raises(TypeError, match="d must be a real number"):
        V.check_range("d", "abc", 0, 1)


def test_option_and_shape_checks():
    assert V.check_option("kind", "a", ("a", "b")) == "a"
    with pytest.raises(ValueError, match="kind must be one of"):
        V.check_option("kind", "c", ("a", "b"))
    V.check_shape("eps", np.zeros((4, 2, 6)), (..., 6))
    V.check_shape("eps", np.zeros((4, 6)), (None, 6))
    with pytest.raises(ValueError, match=r"eps must have shape \('...', 6\)"):
        V.check_shape("eps", np.zeros((4, 5)), (..., 6))
    assert V.broadcast_shapes(a=np.zeros(3), b=1.0) == (3,)
    with pytest.raises(ValueError, match=r"a\(3,\), b\(2,\)"):
        V.broadcast_shapes(a=np.zeros(3), b=np.zeros(2))


def test_curve_writer_keeps_rows_of_an_interrupted_run(tmp_path):
    path = tmp_path / "curve.csv"
    w = io.CurveWriter(path, ["u", "F"])
    w.write(u=0.0, F=0.0)
    w.write(u=0.1, F=np.float64(2.5))
    # no close(): the rows are on disk already
    data = io.read_curve(path)
    np.testing.assert_array_equal(data["F"], [0.0, 2.5])
    w.close()
    with io.CurveWriter(path, ["u", "F"], append=True) as w2:
        w2.write(u=0.2, F=3.0)
    assert len(io.read_curve(path)["u"]) == 3
    with pytest.raises(ValueError, match="missing"), io.CurveWriter(tmp_path / "x.csv", ["a"]) as w3:
        w3.write(b=1)


def test_json_and_vtu_series(tmp_path):
    p = io.write_json(tmp_path / "r.json", {"a": np.arange(3), "b": np.float64(1.5)})
    assert io.read_json(p) == {"a": [0, 1, 2], "b": 1.5}
    series = io.VtuSeries(tmp_path / "fields")
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    for t in (0.0, 1.0):
        series.write(t, pts, [("triangle", np.array([[0, 1, 2]]))], point_data={"u": pts * t})
    pvd = (tmp_path / "fields" / "step.pvd").read_text()
    assert pvd.count("<DataSet") == 2
    import meshio

    m = meshio.read(tmp_path / "fields" / "step_00001.vtu")
    np.testing.assert_allclose(m.point_data["u"], pts)


def test_json_is_strict_and_gives_non_finite_numbers_back(tmp_path):
    """No NaN/Infinity tokens (other JSON readers refuse them); read_json restores the floats, None stays None,
    and files written before (with NaN tokens) still read."""
    import json

    data = {"peak": np.nan, "curve": np.array([1.0, np.inf, -np.inf]), "note": None, "nested": [{"x": np.nan}]}
    path = io.write_json(tmp_path / "r.json", data)
    text = path.read_text()
    assert "NaN" not in text.replace('"NaN"', "") and "Infinity" not in text.replace('"Infinity"', "").replace(
        '"-Infinity"', "")
    json.loads(text, parse_constant=lambda token: pytest.fail(f"non-strict token {token}"))
    back = io.read_json(path)
    assert np.isnan(back["peak"]) and back["curve"][1:] == [np.inf, -np.inf] and back["note"] is None
    assert np.isnan(back["nested"][0]["x"])
    (tmp_path / "old.json").write_text('{"peak": NaN, "x": [Infinity]}')
    old = io.read_json(tmp_path / "old.json")
    assert np.isnan(old["peak"]) and old["x"] == [np.inf]


def _write_many(path, tag, count):
    from abrakit.io import write_json

    for k in range(count):
        write_json(path, {"writer": tag, "k": k, "payload": list(range(2000))})


def test_two_processes_writing_one_json_file_leave_it_whole(tmp_path):
    """Concurrent writers of the same result file: every read sees one complete version, no temporary is left."""
    import multiprocessing

    from abrakit.io import read_json

    path = tmp_path / "case.json"
    context = multiprocessing.get_context("spawn")
    workers = [context.Process(target=_write_many, args=(path, tag, 60)) for tag in ("a", "b")]
    for w in workers:
        w.start()
    seen = 0
    while any(w.is_alive() for w in workers):
        if path.exists():
            data = read_json(path)                       # a torn file would raise here
            assert data["writer"] in ("a", "b") and len(data["payload"]) == 2000
            seen += 1
    for w in workers:
        w.join()
        assert w.exitcode == 0
    assert read_json(path)["k"] == 59 and not list(tmp_path.glob("*.tmp"))


def test_run_record_keeps_columns_writes_them_and_takes_over_saved_rows(tmp_path):
    from abrakit.io import RunRecord, read_curve

    record = RunRecord(("n", "d"), tmp_path / "run.csv", rows={"n": [1, 2], "d": [0.1, 0.2]})
    record.add(n=3, d=0.3)
    with pytest.raises(ValueError, match="columns"):
        record.add(n=4)
    record.close()
    assert len(record) == 3 and record.arrays()["d"].tolist() == [0.1, 0.2, 0.3]
    assert read_curve(tmp_path / "run.csv")["n"].tolist() == [1.0, 2.0, 3.0]


def test_every_stored_result_is_strict_json():
    """The committed benchmark results hold no NaN/Infinity tokens (they were rewritten by write_json)."""
    import json
    from pathlib import Path

    results = Path(__file__).resolve().parents[1] / "benchmarks" / "results"
    offenders = []
    for path in results.rglob("*.json"):
        try:
            json.loads(path.read_text(), parse_constant=lambda token: (_ for _ in ()).throw(ValueError(token)))
        except ValueError:
            offenders.append(path.relative_to(results))
    assert not offenders, f"non-strict JSON: {offenders[:5]}"


def test_number_fields_of_parameter_classes_are_checked_by_their_annotation():
    from abrakit.fem import StepControl
    from abrakit.materials import LinearElastic
    from abrakit.scratch import SphericalIndenter

    with pytest.raises(TypeError, match="radius must be a real number"):
        SphericalIndenter("0.05")
    with pytest.raises(ValueError, match="E must be a number, got nan"):
        LinearElastic(np.nan, 0.3)
    with pytest.raises(TypeError, match="easy_steps must be an integer"):
        StepControl(easy_steps=None)
    with pytest.raises(ValueError, match="easy_steps must be an integer, got 2.5"):
        StepControl(easy_steps=2.5)
    assert StepControl(easy_steps=np.int64(3)).easy_steps == 3           # numpy integers are integers


def test_number_arguments_checks_annotated_arguments_and_keeps_arrays():
    from abrakit.fem import meshes
    from abrakit.materials.driver import ramp
    from abrakit.validation import number_arguments

    with pytest.raises(TypeError, match="n_radial must be an integer"):
        meshes.ring_sector(n_radial="3")
    with pytest.raises(ValueError, match="angle must be a number, got nan"):
        meshes.ring_sector(angle=np.nan)
    with pytest.raises(ValueError, match="n_steps must be an integer, got 2.5"):
        ramp(1.0, 2.5)

    @number_arguments
    def scaled(x: float, factor: float | None = None):
        return np.asarray(x) * (factor or 1.0)

    assert np.array_equal(scaled(np.arange(3.0), 2.0), [0.0, 2.0, 4.0])        # arrays where a float is annotated
    with pytest.raises(ValueError, match="x must not hold NaN"):
        scaled(np.array([1.0, np.nan]))
    assert scaled.__wrapped__.__name__ == "scaled"

    @number_arguments
    def doubled(values: ArrayLike, limit: ArrayLike | None = None):
        return 2.0 * np.asarray(values, dtype=float)

    assert doubled(1.5) == 3.0 and np.array_equal(doubled([[1.0], [2.0]]), [[2.0], [4.0]])
    assert doubled(1.0, limit=None) == 2.0
    for bad, error, message in ((None, TypeError, "values must be a real number or an array of them, got None"),
                                ("abc", TypeError, "values must be a real number"),
                                ([1.0, np.nan], ValueError, "values must not hold NaN"),
                                (np.nan, ValueError, "values must be a number, got nan")):
        with pytest.raises(error, match=message):
            doubled(bad)


def test_check_range_refuses_an_interval_that_is_not_numbers_and_a_servo_a_bad_area():
    from abrakit.dem.walls import Servo

    for bad in (np.nan, "abc"):
        with pytest.raises(TypeError, match="check_range for x: low must be a number or None"):
            V.check_range("x", 1.0, bad)
        with pytest.raises(TypeError, match="high must be a number or None"):
            V.check_range("x", 1.0, 0.0, bad)
    assert V.check_range("x", 1.0, None, np.inf) == 1.0
    for area in (np.nan, -1.0, "abc", None):
        with pytest.raises((TypeError, ValueError), match="area"):
            Servo(wall=0, target_stress=1e4, area=area)
    assert Servo(wall=0, target_stress=1e4, area=lambda walls: 1.0).current_area(None) == 1.0


def test_all_finite_is_exact_also_where_the_sum_overflows():
    """``all_finite`` takes the one-reduction shortcut of a finite sum, and checks entry by entry only when the sum
    is not finite: large finite entries whose sum overflows are still finite, a NaN or an inf anywhere is not."""
    from abrakit.validation import all_finite

    big = np.full(4, 1e308)
    with np.errstate(over="ignore"):
        assert all_finite(big) and not np.isfinite(big.sum())
    assert all_finite(np.zeros(0)) and all_finite(np.ones((3, 2)))
    for bad in (np.nan, np.inf, -np.inf):
        a = np.ones(7)
        a[3] = bad
        assert not all_finite(a)
    assert not all_finite(np.array([np.inf, -np.inf]))


@pytest.mark.parametrize("call, name", [
    (lambda: Constraints([], None), "ndof"),
    (lambda: Constraints([], 2.5), "ndof"),
    (lambda: ProjectedBandWidth(np.zeros((1, 3, 2)), factor="two"), "factor"),
    (lambda: ProjectedBandWidth(np.full((1, 3, 2), np.nan)), "vertices"),
    (lambda: cell_fields(np.full((1, 4, 6), np.nan), {}), "stress"),
    (lambda: taylor_matrix([[np.nan, 0.0]]), "dx"),
    (lambda: members(np.zeros((1, 3)), np.ones(1), np.zeros(1, int), np.full((1, 3, 3), np.nan)), "rotation"),
    (lambda: DamageControl(float("nan"), np.ones(2)), "tau"),
    (lambda: DamageControl(0.1, np.array([1.0, np.nan])), "weights"),
    (lambda: banded_wins(None, 10, "superlu"), "n"),
    (lambda: fingerprint("scene", "many"), "ndof"),
    (lambda: path_work([0.0, np.nan], [0.0, 1.0]), "u"),
    (lambda: plastic_step(np.zeros(6), np.zeros(6), 0.0, 80e3, 100.0, "stiff", "implicit"), "K_H"),
])
def test_set_up_functions_refuse_nan_and_non_numbers_by_name(call, name):
    """Functions called once per run (constraints, band widths, output, Taylor rows, clump members) check their
    input; the kernels inside a time step or return map trust their callers (README)."""
    with pytest.raises((ValueError, TypeError), match=name):
        call()


def test_the_source_fingerprint_follows_the_code_it_hashes():
    """source_fingerprint hashes a package's files, a module's file, a function's source: equal code, equal hash;
    other code, another hash; anything else is refused by name."""
    import abrakit.dem
    import abrakit.dem.state
    from abrakit.experiments.specimen import SpecimenSpec, genesis_fingerprint
    from abrakit.io import source_fingerprint

    assert source_fingerprint(abrakit.dem) == source_fingerprint(abrakit.dem)
    assert len({source_fingerprint(abrakit.dem), source_fingerprint(abrakit.dem.state),
                source_fingerprint(source_fingerprint), source_fingerprint(SpecimenSpec)}) == 4
    assert source_fingerprint(abrakit.dem.state, abrakit.dem) != source_fingerprint(abrakit.dem)
    assert genesis_fingerprint() == genesis_fingerprint()
    with pytest.raises(TypeError, match="sources must be modules"):
        source_fingerprint("abrakit.dem")


def test_a_specimen_key_changes_with_the_genesis_code(monkeypatch):
    import abrakit.experiments.specimen as sp

    spec = sp.SpecimenSpec(n_particles=60, seed=5)
    key = spec.key()
    monkeypatch.setattr(sp, "genesis_fingerprint", lambda: "0" * 16)
    assert spec.key() != key
