"""The public API under invalid input (tools/api_fuzz.py): calls the test suite makes, replayed with one argument
made invalid, and with one number scaled (hypothesis).

The public surface is what each module lists in ``__all__`` (kernels and helpers are left out, most with a leading
underscore); ``benchmarks/results/api_fuzz.json`` stores the counts of ``python tools/api_fuzz.py fuzz``.

- Valid calls give finite results (except the documented sentinels of ``NON_FINITE_BY_DESIGN``).
- Every invalid input (NaN, a NaN entry, a string or None where a number is meant) is refused with a
  ``ValueError``/``TypeError`` that names the parameter: no NaN or infinity returned, nothing accepted, no
  exception from inside numpy or scipy, no call past its time bound.
- A valid number scaled by 1/2 … 2 gives a finite result or a ``ValueError``/``TypeError`` that names a parameter.
"""

import copy
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parent.parent
spec = importlib.util.spec_from_file_location("api_fuzz", ROOT / "tools" / "api_fuzz.py")
fuzz = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fuzz)

BASELINE = json.loads((ROOT / "benchmarks" / "results" / "api_fuzz.json").read_text())
FAST = 0.05                 # s: calls slower than this are studies, fuzzed by the tool, not in the default suite


@pytest.fixture(scope="module")
def catalogue():
    return fuzz.load_catalogue()


@pytest.fixture(scope="module")
def result(catalogue):
    return fuzz.fuzz(catalogue, slow=FAST, limit=2.0, skip=set(BASELINE["slow"]))


def test_the_catalogue_covers_the_public_api(catalogue):
    assert len(catalogue) >= 250 and len(fuzz.public_callables()) >= 300


def test_valid_calls_give_finite_results(result):
    assert result["counts"]["valid calls"] >= 600
    assert result["valid_non_finite"] == []


def test_every_invalid_input_is_refused_by_name(result):
    """NaN, a NaN entry, a string, None: over the harvested calls (the face fuzz below adds more values and the
    hand-written calls, with its own bounds)."""
    refused = result["counts"]["named"]
    others = [(c["callable"], c["parameter"], c["value"], c["outcome"]) for c in result["cases"]
              if c["outcome"] != "named" and c["value"] not in fuzz.FACE_LABELS
              and c["callable"] not in fuzz.HAND_NAMES]
    assert refused >= 3000 and others == [], f"{len(others)} invalid inputs not refused by name, e.g. {others[:5]}"


def test_the_fuzz_guards_every_callable_a_chapter_face_lists():
    import abrakit

    guarded = fuzz.public_callables()
    listed = {}
    for chapter in abrakit.MODULES:
        face = getattr(abrakit, chapter)
        assert face.__all__, f"abrakit.{chapter} lists no public names"
        for name in face.__all__:
            obj = getattr(face, name)
            if fuzz._callable(obj) and obj.__module__.startswith("abrakit"):
                listed[f"{obj.__module__}.{obj.__name__}"] = obj
    assert listed and set(listed) <= set(guarded), sorted(set(listed) - set(guarded))[:10]


def scalable(catalogue):
    calls = fuzz.valid_calls(catalogue, slow=FAST, skip=set(BASELINE["slow"]))
    return [(name, call, kwargs, p) for name, call, kwargs in calls for p, v in kwargs.items()
            if isinstance(v, float | np.floating) and not isinstance(v, bool) and np.isfinite(v) and v != 0.0]


@pytest.fixture(scope="module")
def numbers(catalogue):
    return scalable(catalogue)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(choice=st.integers(min_value=0), factor=st.floats(0.5, 2.0))
def test_a_valid_number_scaled_gives_a_finite_result_or_a_named_error(numbers, choice, factor):
    name, call, kwargs, parameter = numbers[choice % len(numbers)]
    if name in fuzz.NON_FINITE_BY_DESIGN:
        return
    scaled = copy.deepcopy(kwargs)
    scaled[parameter] = kwargs[parameter] * factor
    kind, text = fuzz.outcome(call, scaled, parameter, limit=2.0)
    if kind == "timeout":           # a new specimen built and relaxed (not cached): a study, not a finding
        return
    assert kind == "accepted" or (kind in ("named", "unnamed") and fuzz.names_a_parameter(call, text)), \
        f"{name}({parameter} × {factor:.3g}): {kind} {text}"


#: What the face fuzz still finds (+inf, zero, negative on top of NaN, a string, None), as upper bounds that can
#: only shrink; the goal is 0 of each.
FACE_BOUNDS = {"non_finite_from_finite": 0, "accepted": 0, "timeout": 0}
#: Face callables without a valid call in the catalogue (neither harvested nor written in the tool's hand table).
WITHOUT_A_VALID_CALL = 0


def face_cases(result, outcome):
    """The face cases of ``outcome`` as (callable, parameter, value)."""
    faces = fuzz.face_callables()
    return [(c["callable"], c["parameter"], c["value"]) for c in result["cases"]
            if c["callable"] in faces and c["outcome"] == outcome]


def test_every_face_callable_has_a_valid_call(catalogue):
    report = fuzz.face_report(catalogue)
    missing = sorted(name for name, how in report.items() if how == "none")
    assert len(report) >= 200 and len(missing) <= WITHOUT_A_VALID_CALL, missing


def test_finite_bad_input_to_a_face_gives_no_nan_or_inf(result):
    found = [c for c in face_cases(result, "non_finite") if c[2] in fuzz.FINITE_LABELS]
    assert result["face_counts"]["non_finite_from_finite"] == len(found)
    assert len(found) <= FACE_BOUNDS["non_finite_from_finite"], found


def test_no_invalid_input_to_a_face_is_accepted(result):
    found = face_cases(result, "accepted")
    assert len(found) <= FACE_BOUNDS["accepted"], found


def test_no_invalid_input_to_a_face_hangs(result):
    found = face_cases(result, "timeout")
    assert len(found) <= FACE_BOUNDS["timeout"], found
