"""Input checks shared by every module: each failure names the parameter and the allowed range.

All checks return the (converted) value so they can be used inline::

    nu = check_range("nu", nu, -1.0, 0.5, high_open=True)
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
from collections.abc import Iterable

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["all_finite", "broadcast_shapes", "check_callable", "check_finite", "check_indices", "check_instance",
           "check_integer", "check_number_fields", "check_option", "check_poisson", "check_positive", "check_range",
           "check_shape", "number_arguments"]


def _describe(low, high, low_open, high_open) -> str:
    left = "(" if low_open else "["
    right = ")" if high_open else "]"
    lo = "-inf" if low is None else f"{low:g}"
    hi = "inf" if high is None else f"{high:g}"
    return f"{left}{lo}, {hi}{right}"


def check_finite(name: str, value):
    """Return ``value`` as a float array (or float) and raise ``ValueError`` if any entry is NaN or infinite."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a real number or array of real numbers, got {value!r}") from exc
    if not all_finite(arr):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return float(arr) if arr.ndim == 0 else arr


def all_finite(arr: np.ndarray) -> bool:
    """Whether every entry is finite: a finite sum proves it in one reduction (a NaN or inf entry makes the sum
    NaN or inf); only a non-finite sum, which overflow of large finite entries can also give, is checked entry by
    entry."""
    with np.errstate(over="ignore", invalid="ignore"):
        total = arr.sum()
    return bool(np.isfinite(total)) or bool(np.all(np.isfinite(arr)))


def check_range(name: str, value, low=None, high=None, *, low_open: bool = False, high_open: bool = False):
    """Return ``value`` if every entry lies in the interval, else raise ``ValueError`` naming it.

    ``low``/``high`` of ``None`` mean unbounded; ``*_open`` excludes the end point.
    """
    arr = np.asarray(check_finite(name, value))
    for bound, given in (("low", low), ("high", high)):        # the interval itself: numbers or None
        if given is not None and not (isinstance(given, int | float | np.number) and not np.isnan(given)):
            raise TypeError(f"check_range for {name}: {bound} must be a number or None, got {given!r}")
    bad = np.zeros(arr.shape, dtype=bool)
    if low is not None:
        bad |= (arr <= low) if low_open else (arr < low)
    if high is not None:
        bad |= (arr >= high) if high_open else (arr > high)
    if np.any(bad):
        shown = float(arr) if arr.ndim == 0 else arr[bad].ravel()[:3]
        raise ValueError(
            f"{name} must lie in {_describe(low, high, low_open, high_open)}, got {shown!r}"
        )
    return float(arr) if arr.ndim == 0 else arr


def check_integer(name: str, value, low: int | None = None, high: int | None = None) -> int:
    """Return ``value`` as an ``int`` if it is a whole number (an integer, or a float without a fraction) in
    ``[low, high]`` (``None``: unbounded); else ``TypeError`` (not a number) or ``ValueError`` (NaN, infinity, a
    fraction, out of range) naming the parameter::

        steps = check_integer("steps", steps, 1)
    """
    allowed = f"an integer in [{'-inf' if low is None else low}, {'inf' if high is None else high}]"
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise TypeError(f"{name} must be {allowed}, got {value!r}")
    if not np.isfinite(value) or value != int(value):
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    if (low is not None and value < low) or (high is not None and value > high):
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    return int(value)


def check_positive(name: str, value, *, allow_zero: bool = False):
    """Raise ``ValueError`` unless ``value`` > 0 (or >= 0 with ``allow_zero``) everywhere."""
    return check_range(name, value, 0.0, None, low_open=not allow_zero)


def check_poisson(name: str, nu):
    """Poisson's ratio of an isotropic, positive-definite elastic solid: -1 < nu < 1/2."""
    return check_range(name, nu, -1.0, 0.5, low_open=True, high_open=True)


def check_option(name: str, value, allowed: Iterable[str]):
    """Raise ``ValueError`` unless ``value`` is one of ``allowed``."""
    allowed = tuple(allowed)
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    return value


def check_instance(name: str, value, types, *, optional: bool = False):
    """Return ``value`` if it is an instance of ``types`` (a class or a tuple of them), or ``None`` where
    ``optional``; else raise ``TypeError`` naming the parameter and the allowed types."""
    if (value is None and optional) or isinstance(value, types):
        return value
    names = " or ".join(t.__name__ for t in (types if isinstance(types, tuple) else (types,)))
    raise TypeError(f"{name} must be a {names}{' or None' if optional else ''}, got {value!r}")


def check_callable(name: str, value, *, optional: bool = False):
    """Return ``value`` if it is callable (or ``None`` where ``optional``), else raise ``TypeError`` naming it."""
    if (value is None and optional) or callable(value):
        return value
    raise TypeError(f"{name} must be a function{' or None' if optional else ''}, got {value!r}")


def check_indices(name: str, value, size: int) -> np.ndarray:
    """Return ``value`` as an index array into ``size`` entries: integers in [-size, size) or a boolean mask of
    length ``size``; else raise ``TypeError``/``ValueError`` naming the parameter."""
    arr = np.asarray(value)
    if arr.dtype == bool:
        if arr.shape != (size,):
            raise ValueError(f"{name} must be a boolean mask of length {size}, got shape {arr.shape}")
        return arr
    if arr.dtype.kind not in "iu":
        raise TypeError(f"{name} must be integer indices or a boolean mask, got {value!r}")
    if arr.size and (arr.min() < -size or arr.max() >= size):
        raise ValueError(f"{name} must hold indices in [{-size}, {size}), got {arr.min()} .. {arr.max()}")
    return arr


def check_shape(name: str, array, shape: tuple):
    """Raise ``ValueError`` unless ``array`` has ``shape``; ``None`` or ``...`` entries match any length.

    A leading ``...`` matches any number of leading axes (batched input).
    """
    arr = np.asarray(array)
    want = tuple(shape)
    if want and want[0] is Ellipsis:
        tail = want[1:]
        ok = arr.ndim >= len(tail) and all(
            w is None or w == s for w, s in zip(tail, arr.shape[arr.ndim - len(tail):], strict=True)
        )
    else:
        ok = arr.ndim == len(want) and all(w is None or w == s for w, s in zip(want, arr.shape, strict=True))
    if not ok:
        shown = tuple("..." if w is Ellipsis else ("any" if w is None else w) for w in want)
        raise ValueError(f"{name} must have shape {shown}, got {arr.shape}")
    return arr


def broadcast_shapes(**arrays) -> tuple:
    """Common broadcast shape of the named arrays; a mismatch raises ``ValueError`` naming all of them."""
    try:
        return np.broadcast_shapes(*(np.shape(a) for a in arrays.values()))
    except ValueError as exc:
        shapes = ", ".join(f"{k}{np.shape(v)}" for k, v in arrays.items())
        raise ValueError(f"shapes do not broadcast: {shapes}") from exc


_NUMBERS = {"float": (int, float, np.integer, np.floating), "int": (int, np.integer), "ArrayLike": ()}


def _number_kind(annotation) -> tuple[str, bool] | None:
    """``("float" | "int" | "ArrayLike", optional)`` for an annotation ``float``, ``int``, ``ArrayLike`` (numpy's:
    a number or an array of real numbers), each possibly ``| None``."""
    if annotation is ArrayLike:
        return ("ArrayLike", False)
    text = (annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation)))
    text = text.replace(" ", "")
    optional = text.endswith("|None") or text.startswith("None|")
    kind = text.replace("|None", "").replace("None|", "")
    return (kind, optional) if kind in _NUMBERS else None


def _check_number(name: str, value, kind: str, optional: bool) -> None:
    """A number of ``kind`` (or an array of them for ``float``) without NaN, or ``None`` if ``optional``."""
    if value is None and optional:
        return
    if kind != "int":                                  # the fast paths of kernels: a float, a float array
        if type(value) is float and value == value:
            return
        if type(value) is np.ndarray and value.dtype.kind == "f":
            if np.isnan(value).any():
                raise ValueError(f"{name} must not hold NaN")
            return
    elif type(value) is int:
        return
    allowed = f"a{'n integer' if kind == 'int' else ' real number'}{' or None' if optional else ''}"
    if kind == "ArrayLike":
        if value is None or isinstance(value, str | bytes):
            raise TypeError(f"{name} must be {allowed} or an array of them, got {value!r}")
        kind = "float"
    if kind == "float" and isinstance(value, np.ndarray | list | tuple) and not isinstance(value, bool):
        try:                                           # vectorised functions take arrays where a float is annotated
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"{name} must be {allowed} or an array of them, got {value!r}") from exc
        if np.any(np.isnan(array)):
            raise ValueError(f"{name} must not hold NaN")
        return
    if isinstance(value, bool) or not isinstance(value, _NUMBERS[kind]):
        error = ValueError if isinstance(value, _NUMBERS["float"]) and not isinstance(value, bool) else TypeError
        raise error(f"{name} must be {allowed}, got {value!r}")      # 2.5 for an integer is a wrong value
    if kind == "float" and np.isnan(value):
        raise ValueError(f"{name} must be a number, got nan")


def check_number_fields(obj) -> None:
    """Every field of the dataclass ``obj`` annotated ``float`` or ``int`` (or ``float | None``, ``int | None``)
    holds a real number of that kind that is not NaN (infinity may stand for "no limit"), or ``None`` where the
    annotation allows it; otherwise ``TypeError`` (not a number) or ``ValueError`` (NaN, a fraction for an integer)
    naming the field. The annotations are the contract; range checks of single fields follow it in each
    ``__post_init__``."""
    for f in dataclasses.fields(obj):
        rule = _number_kind(f.type)
        if rule is not None:
            _check_number(f.name, getattr(obj, f.name), *rule)


def number_arguments(func):
    """Decorator: the arguments of ``func`` annotated ``float``, ``int`` or ``ArrayLike`` (or ``... | None``) are
    checked on every call as :func:`check_number_fields` checks fields (a ``float`` argument may also be an array
    without NaN; an ``ArrayLike`` one is a number or an array of real numbers without NaN, never None or a string)."""
    parameters = inspect.signature(func).parameters.values()
    positional = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    index = {p.name: k for k, p in enumerate(parameters) if p.kind in positional}
    rules = [(p.name, index.get(p.name), rule) for p in parameters if (rule := _number_kind(p.annotation))]

    @functools.wraps(func)
    def checked(*args, **kwargs):            # the arguments given, by position or name (defaults are trusted)
        for name, position, rule in rules:
            if position is not None and position < len(args):
                _check_number(name, args[position], *rule)
            elif name in kwargs:
                _check_number(name, kwargs[name], *rule)
        return func(*args, **kwargs)

    return checked
