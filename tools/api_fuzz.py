"""Fuzz the public API with invalid input, starting from calls the test suite makes.

Two stages:

1. **harvest** runs the test suite (not the slow studies) with a profiler hook and keeps, for every public function
   and class of ``abrakit`` (module level, name without a leading underscore), up to ``PER_CALLABLE`` calls whose
   arguments are plain data: numbers, strings, ``None``, numpy arrays, tuples, lists and dicts of these, and
   abrakit dataclasses made of them. They are pickled into ``tools/api_calls.pkl``: valid calls, by construction.
2. **fuzz** replays each valid call (its result must hold no NaN or infinity) and then the same call with one
   numeric argument made invalid: NaN for a number, a NaN entry for an array, a string for a number, ``None`` where
   neither the default (``None``) nor the annotation (``... | None``) allows it. Every outcome falls in one class
   (:data:`OUTCOMES`):

   - ``named``: ``ValueError``/``TypeError`` whose message names the parameter (what the toolkit promises);
   - ``unnamed``: ``ValueError``/``TypeError`` that does not name it;
   - ``deep``: another exception, e.g. from inside numpy or scipy;
   - ``non_finite``: the call returned NaN or infinity;
   - ``accepted``: the call returned a finite result for the invalid input;
   - ``timeout``: the call ran longer than its limit (a study that an invalid input sent astray).

   Some arguments accept NaN by design (curves written as they come, statistics that count what they drop):
   :data:`NAN_ALLOWED` lists them with the reason.

``python tools/api_fuzz.py harvest [--merge] [tests ...]`` then ``python tools/api_fuzz.py fuzz`` writes the counts to
``benchmarks/results/api_fuzz.json``; ``tests/test_api_fuzz.py`` runs the fuzz stage on the stored calls.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import inspect
import pickle
import pkgutil
import re
import signal
import sys
import time
import warnings
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
CATALOGUE = ROOT / "tools" / "api_calls.pkl"
PER_CALLABLE = 3
MAX_ARRAY = 20_000
MAX_BYTES = 10_000         # a harvested call's pickled arguments: larger ones (whole meshes, long curves) are dropped
SLOW_CALL = 0.5            # s: valid calls slower than this are not fuzzed (a study, not an input check)
OUTCOMES = ("named", "unnamed", "deep", "non_finite", "accepted", "timeout")

#: (callable, parameter) pairs that take NaN on purpose, and why.
NAN_ALLOWED = {
    ("abrakit.experiments.closed_form_checks.mean_interval", "values"): "NaN samples are dropped and counted "
                                                                        "(``dropped``)",
    ("abrakit.io.jsonable", "obj"): "results hold NaN where a quantity is undefined; strict JSON writes it as the "
                                    "string \"NaN\"",
    ("abrakit.io.strict_json", "data"): "the same: NaN and infinities become the strings NaN, Infinity, -Infinity",
    ("abrakit.io.from_strict_json", "data"): "the inverse: the strings come back as NaN and infinities",
    ("abrakit.validation.check_shape", "array"): "a shape check returns the array as given; its values are the "
                                                 "business of check_finite",
    ("abrakit.validation.all_finite", "arr"): "it answers whether an array holds NaN or infinity",
}

#: Modules of input checks: their ``name`` argument is the parameter their errors must name (``check_range("x",
#: None)`` says "x must be ..."), so an error naming it is named.
VALIDATORS = re.compile(r"^abrakit\.validation$")

#: Records and state containers the toolkit builds and returns: their fields are outputs, checked where they are
#: computed, and the functions users call to make them (``Particles.spheres``, ``genesis``, ...) check their input.
RECORDS = {
    "abrakit.damage.localisation.BarRun", "abrakit.damage.metrics.BandWidth", "abrakit.dem.bonds.ParallelBonds",
    "abrakit.dem.clumps.Clumps", "abrakit.dem.simulation.EnergyAccount", "abrakit.dem.state.Particles",
    "abrakit.experiments.compression.CompressionCurve", "abrakit.experiments.specimen.Specimen",
    "abrakit.fem.pathfollow.PathPoint", "abrakit.fem.problems.ThickCylinderSolution",
    "abrakit.materials.base.MaterialResponse", "abrakit.materials.plasticity.PlasticStep",
    "abrakit.dem.neighbours.VerletList",
}

#: Callables whose valid calls may return a non-finite value, documented in their docstrings, and why.
NON_FINITE_BY_DESIGN = {
    "abrakit.damage.metrics.softening_displacement": "inf when the force never falls to the fraction (no drop)",
    "abrakit.experiments.closed_form_checks.mean_interval": "std and half-width of a single value are undefined "
                                                            "(NaN, as numpy's sample std)",
    "abrakit.experiments.compression.crack_initiation_stress": "NaN when no bond broke in the test",
    "abrakit.io.loads": "strict JSON's strings NaN, Infinity, -Infinity are read back as the numbers they stand for",
}


# ---- what is public --------------------------------------------------------------------------------------------
def _modules():
    """Every importable abrakit module (not ``cli``, not one whose name has a leading underscore)."""
    import abrakit

    for info in pkgutil.walk_packages(abrakit.__path__, "abrakit."):
        if any(part.startswith("_") for part in info.name.split(".")) or info.name.endswith(".cli"):
            continue
        try:
            yield importlib.import_module(info.name)
        except ImportError:            # an optional extra (numba, pypardiso) that is not installed
            continue


def _callable(obj) -> bool:
    return inspect.isfunction(obj) or (inspect.isclass(obj) and not issubclass(obj, BaseException))


def public_callables() -> dict[str, object]:
    """``{"module.name": callable}`` of the surface the fuzz guards: every function and class a module defines
    under a name without a leading underscore, keyed by its defining module. This holds every object the chapter
    faces list (they re-export the same objects, fuzzed once) and the public names of the implementation modules
    behind them; kernels carry a leading underscore and are left out."""
    return unprefixed_callables()


def unprefixed_callables() -> dict[str, object]:
    """The surface before it was curated: every function and class defined in a module whose name has no leading
    underscore (what the fuzz covered until each module declared its ``__all__``)."""
    found = {}
    for module in _modules():
        for name, obj in vars(module).items():
            if not name.startswith("_") and getattr(obj, "__module__", None) == module.__name__ and _callable(obj):
                found[f"{module.__name__}.{name}"] = obj
    return found


def _code_of(obj):
    """The code object that runs when ``obj`` is called (a decorated function's own, not its wrapper's)."""
    target = obj.__init__ if inspect.isclass(obj) else inspect.unwrap(obj)
    return getattr(target, "__code__", None)


# ---- plain data --------------------------------------------------------------------------------------------------
def is_plain(value, depth: int = 0) -> bool:
    """Data that can be stored and replayed: numbers, strings, None, small arrays, containers and abrakit
    dataclasses of these."""
    if depth > 4:
        return False
    if value is None or isinstance(value, bool | int | float | str | complex | np.generic):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype != object and value.size <= MAX_ARRAY
    if isinstance(value, tuple | list):
        return len(value) <= 200 and all(is_plain(v, depth + 1) for v in value)
    if isinstance(value, dict):
        return len(value) <= 200 and all(isinstance(k, str) and is_plain(v, depth + 1) for k, v in value.items())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return type(value).__module__.startswith("abrakit") and all(
            is_plain(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value))
    return False


# ---- stage 1: harvest --------------------------------------------------------------------------------------------
class Harvester:
    """A profiler hook that keeps plain-data calls of the public callables."""

    def __init__(self, per_callable: int = PER_CALLABLE):
        self.targets = {}
        for name, obj in public_callables().items():
            code = _code_of(obj)
            if code is not None:
                self.targets[code] = (name, obj)
        self.per_callable = per_callable
        self.calls: dict[str, list[dict]] = defaultdict(list)
        self._seen: set = set()

    def hook(self, frame, event, arg):
        if event != "call":
            return
        target = self.targets.get(frame.f_code)
        if target is None:
            return
        name, obj = target
        if len(self.calls[name]) >= self.per_callable:
            return
        try:
            signature = inspect.signature(obj)
        except (TypeError, ValueError):
            return
        local = frame.f_locals
        kwargs = {}
        for p in signature.parameters.values():
            if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) or p.name not in local:
                return
            kwargs[p.name] = local[p.name]
        if not all(is_plain(v) for v in kwargs.values()):
            return
        try:
            key = (name, pickle.dumps(kwargs))
            if key in self._seen:
                return
            self._seen.add(key)
            self.calls[name].append(copy.deepcopy(kwargs))
        except Exception:      # noqa: BLE001 - anything that does not pickle is not kept
            return


HARVEST_OPTIONS = ("-q", "-m", "not slow", "-p", "no:cacheprovider", "--ignore=tests/test_api_fuzz.py")
"""pytest's options of a harvest: the fast tests, without the fuzz test itself (its replays with invalid input
would enter the catalogue as valid calls)."""


def harvest(tests=("tests",), out: Path = CATALOGUE, merge: bool = False) -> dict:
    """Run the tests (paths or pytest node ids) under the hook and pickle the calls found (``{name: [kwargs,
    ...]}``). ``merge``: add the calls found to the stored catalogue (:func:`merged`) instead of replacing it (a
    whole harvest takes about three hours under the profiler, one of a few test files minutes)."""
    import pytest

    harvester = Harvester()
    sys.setprofile(harvester.hook)
    try:
        pytest.main([*HARVEST_OPTIONS, *tests])
    finally:
        sys.setprofile(None)
    calls = {k: [c for c in v if len(pickle.dumps(c)) <= MAX_BYTES] for k, v in harvester.calls.items()}
    calls = {k: v for k, v in calls.items() if v}
    calls = {k: [pickle.dumps(c, protocol=pickle.HIGHEST_PROTOCOL) for c in v] for k, v in calls.items()}
    if merge and out.exists():
        calls = merged(pickle.loads(out.read_bytes())["calls"], calls)
    out.write_bytes(pickle.dumps({"format": 2, "calls": calls}, protocol=pickle.HIGHEST_PROTOCOL))
    return calls


def merged(stored: dict, harvested: dict) -> dict:
    """The stored catalogue with the harvested calls added: per callable, its stored calls and the harvested ones
    it did not have (a test that calls a function with invalid input, to check its refusal, must not replace the
    valid calls of another test)."""
    out = {name: list(calls) for name, calls in stored.items()}
    for name, calls in harvested.items():
        known = set(out.get(name, []))
        out.setdefault(name, []).extend(c for c in calls if c not in known)
    return out


def load_catalogue(path: Path = CATALOGUE) -> dict:
    """The harvested calls, with callables resolved by name; names that no longer exist are dropped."""
    stored = pickle.loads(Path(path).read_bytes())["calls"]
    calls = {}
    for name, kept in stored.items():        # one pickle per call: a call whose classes moved away is dropped
        for data in kept:
            try:
                calls.setdefault(name, []).append(pickle.loads(data))
            except (ImportError, AttributeError):
                continue
    public = public_callables()
    return {name: (public[name], kwargs_list) for name, kwargs_list in calls.items() if name in public}


# ---- stage 2: fuzz -----------------------------------------------------------------------------------------------
def finite(value, depth: int = 0) -> bool:
    """No NaN or infinity anywhere in ``value`` (arrays, numbers, containers, dataclass fields)."""
    if depth > 4:
        return True
    if isinstance(value, bool | str | type(None)):
        return True
    if isinstance(value, int | float | np.number):
        return bool(np.isfinite(value))
    if isinstance(value, np.ndarray):
        return value.dtype.kind not in "fc" or bool(np.all(np.isfinite(value)))
    if isinstance(value, tuple | list):
        return all(finite(v, depth + 1) for v in value[:1000])
    if isinstance(value, dict):
        return all(finite(v, depth + 1) for v in list(value.values())[:1000])
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return all(finite(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value))
    return True


def invalid_values(value, none_valid: bool):
    """``(label, bad value)`` for one argument: only values that are invalid for every numeric parameter (``None``
    unless ``none_valid``: a default of ``None`` or an annotation that allows it)."""
    out = []
    if isinstance(value, bool) or not isinstance(value, int | float | np.number | np.ndarray):
        return out
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "f" and value.size:
            bad = value.copy()
            bad.flat[0] = np.nan
            out.append(("nan entry", bad))
        return out
    out.append(("nan", float("nan")))
    out.append(("string", "abc"))
    if not none_valid:
        out.append(("none", None))
    return out


class CallTimeout(Exception):
    """A fuzzed call ran longer than its time limit."""


def _alarm(signum, frame):
    raise CallTimeout


def outcome(call, kwargs, parameter, limit: float = 2.0) -> tuple[str, str]:
    """The class of one invalid call (:data:`OUTCOMES`, or ``"timeout"`` after ``limit`` seconds) and a short
    description."""
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with np.errstate(all="ignore"):
                result = call(**kwargs)
    except CallTimeout:
        return "timeout", f"ran longer than {limit:g} s"
    except (ValueError, TypeError) as exc:
        text = str(exc)
        names = {parameter} | ({str(kwargs["name"])} if VALIDATORS.match(getattr(call, "__module__", "") or "")
                                and "name" in kwargs else set())         # a check names what it was told to
        return ("named" if any(n in text for n in names) else "unnamed"), f"{type(exc).__name__}: {text[:160]}"
    except Exception as exc:       # noqa: BLE001 - classifying every escape is the point
        return "deep", f"{type(exc).__name__}: {str(exc)[:160]}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return ("accepted" if finite(result) else "non_finite"), ""


def replay(catalogue: dict, *, slow: float = SLOW_CALL, skip=()):
    """Run every call of the catalogue once; yield ``(name, call, kwargs, status, result)`` with ``status`` "ok",
    "slow" (ran longer than ``slow`` seconds) or "stale" (no longer runs: also a call the tests made inside
    ``pytest.raises``, which is harvested too; ``result`` then names the exception). Records and the callables in
    ``skip`` are left out."""
    for name, (call, kwargs_list) in sorted(catalogue.items()):
        if name in skip or name in RECORDS:
            continue
        parameters = set(inspect.signature(call).parameters)
        for kwargs in kwargs_list:
            if set(kwargs) != parameters:
                yield name, call, kwargs, "stale", "signature changed"
                continue
            start = time.perf_counter()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result = call(**copy.deepcopy(kwargs))
            except Exception as exc:   # noqa: BLE001 - a call that no longer works is stale, not a finding
                yield name, call, kwargs, "stale", type(exc).__name__
                continue
            yield name, call, kwargs, ("slow" if time.perf_counter() - start > slow else "ok"), result


def fuzz(catalogue: dict, *, slow: float = SLOW_CALL, limit: float = 2.0, skip=()) -> dict:
    """Replay and mutate the catalogue; counts per outcome, non-finite results of valid calls, and the cases.

    Valid calls slower than ``slow`` seconds are not mutated (listed as ``slow``), a mutated call is stopped after
    ``limit`` seconds (``timeout``), and the callables named in ``skip`` are left out."""
    counts = Counter()
    cases = []
    valid_non_finite, stale, skipped_slow = [], [], []
    functions = set()
    for name, call, kwargs, status, result in replay(catalogue, slow=slow, skip=skip):
        if status == "stale":
            stale.append(f"{name}: {result}")
            continue
        if status == "slow":
            skipped_slow.append(name)
            continue
        functions.add(name)
        counts["valid calls"] += 1
        if not finite(result) and name not in NON_FINITE_BY_DESIGN:
            valid_non_finite.append(name)
        signature = inspect.signature(call)
        for parameter, value in kwargs.items():
            if (name, parameter) in NAN_ALLOWED:
                continue
            declared = signature.parameters[parameter]
            none_valid = declared.default is None or "None" in str(declared.annotation)
            for label, bad in invalid_values(value, none_valid):
                mutated = copy.deepcopy(kwargs)
                mutated[parameter] = bad
                kind, text = outcome(call, mutated, parameter, limit)
                counts[kind] += 1
                cases.append({"callable": name, "parameter": parameter, "value": label, "outcome": kind,
                              "message": text})
    counts["invalid calls"] = sum(counts[k] for k in OUTCOMES)
    return {"functions": len(functions), "counts": {k: counts[k] for k in ("valid calls", "invalid calls",
                                                                            *OUTCOMES)},
            "valid_non_finite": sorted(set(valid_non_finite)), "stale": sorted(set(stale)),
            "slow": sorted(set(skipped_slow)), "cases": [c for c in cases if c["outcome"] != "named"]}


def valid_calls(catalogue: dict, *, slow: float = SLOW_CALL, skip=()) -> list[tuple[str, object, dict]]:
    """``(name, callable, kwargs)`` of the catalogue's calls that still run within ``slow`` seconds."""
    return [(name, call, kwargs) for name, call, kwargs, status, _ in replay(catalogue, slow=slow, skip=skip)
            if status == "ok"]


def names_a_parameter(call, text: str) -> bool:
    """Whether an error message names one of ``call``'s parameters."""
    try:
        return any(p in text for p in inspect.signature(call).parameters)
    except (TypeError, ValueError):
        return False


def report(result: dict) -> str:
    counts = result["counts"]
    lines = [f"{result['functions']} callables, {counts['valid calls']} valid calls, "
             f"{counts['invalid calls']} invalid calls"]
    lines += [f"  {k:11s} {counts[k]}" for k in OUTCOMES]
    lines.append(f"  valid calls with NaN/inf results: {len(result['valid_non_finite'])} "
                 f"{result['valid_non_finite'][:8]}")
    by = defaultdict(Counter)
    for case in result["cases"]:
        if case["outcome"] != "named":
            by[case["callable"]][case["outcome"]] += 1
    lines += [f"  {name}: {dict(c)}" for name, c in sorted(by.items())]
    return "\n".join(lines)


if __name__ == "__main__":
    import argparse
    import json

    parser = argparse.ArgumentParser(description="Fuzz abrakit's public API with invalid input")
    parser.add_argument("stage", choices=("harvest", "fuzz"))
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results" / "api_fuzz.json")
    parser.add_argument("--merge", action="store_true", help="harvest: add the calls found to the stored "
                                                              "catalogue")
    parser.add_argument("tests", nargs="*", default=["tests"], help="harvest: test files or node ids (all tests)")
    args = parser.parse_intermixed_args()
    if args.stage == "harvest":
        found = harvest(args.tests, merge=args.merge)
        print(f"harvested {sum(map(len, found.values()))} calls of {len(found)} callables into {CATALOGUE}")
    else:
        result = fuzz(load_catalogue())
        result["surface"] = {"public (__all__)": len(public_callables()),
                             "without a leading underscore": len(unprefixed_callables())}
        args.out.write_text(json.dumps({k: v for k, v in result.items()}, indent=1, allow_nan=False))
        print(report(result))
