"""The package's arguments checked and converted for the extension: integers and numbers (numpy's
too), scenarios (a path, a dict or :class:`Toml`), dotted-key overrides as TOML literals. Every
refusal names the argument or key: :class:`UsageError` for an argument, :class:`ScenarioError`
for a scenario value."""

from __future__ import annotations

import json
import math
import numbers
import operator
import os
from dataclasses import dataclass
from typing import Any, List, Mapping, Optional, Sequence, Tuple, Union

from ._stickslip import ScenarioError, UsageError

MAX_I64 = 2**63 - 1  # TOML's integers (run.seed, run.realizations) are 64-bit signed
MAX_U32 = 2**32 - 1  # the resolutions


@dataclass(frozen=True)
class Toml:
    """Scenario TOML text, told apart from a path by its type.

    A ``str`` or ``os.PathLike`` scenario is always a path (sweep cells are named like
    ``hive/mass=1/scene.toml``); TOML text is passed wrapped.

    Parameters
    ----------
    text : str
        The scenario as TOML (keys it omits keep the paper's values).

    Examples
    --------
    >>> import stickslip
    >>> stickslip.Toml("[belt]\\nswitch_rate = 1.0\\n").text
    '[belt]\\nswitch_rate = 1.0\\n'
    """

    text: str

    def __post_init__(self) -> None:
        if not isinstance(self.text, str):
            raise UsageError(f"Toml(text): text must be a str of TOML, not {type(self.text).__name__}")


Scenario = Union[str, "os.PathLike[str]", Mapping[str, Any], Toml, None]


def is_bool(v: Any) -> bool:
    """A Python or numpy boolean (``numpy.bool_``; named ``bool`` from numpy 2)."""
    return isinstance(v, bool) or (type(v).__module__ == "numpy" and type(v).__name__ in ("bool_", "bool"))


def integer(name: str, value: Any, low: int = 1, high: int = MAX_I64) -> int:
    """``value`` as an int in [low, high] (a numpy integer too; not a bool or a float), else a
    :class:`UsageError` naming ``name`` and the value."""
    n: Any = value
    if not is_bool(value):
        try:
            n = operator.index(value)
        except TypeError:
            pass
    if not isinstance(n, int) or isinstance(n, bool) or not low <= n <= high:
        raise UsageError(f"{name} = {n!r}: must be an integer between {low} and {high}")
    return n


def optional_integer(name: str, value: Any, low: int = 1, high: int = MAX_I64) -> Optional[int]:
    return None if value is None else integer(name, value, low, high)


def real(name: str, value: Any) -> float:
    """``value`` as a finite float (any real number, numpy's too; not a bool), else a :class:`UsageError`."""
    f = float(value) if isinstance(value, numbers.Real) and not is_bool(value) else None
    if f is None or not math.isfinite(f):
        raise UsageError(f"{name} = {value if f is None else f!r}: must be a finite number")
    return f


def times(name: str, value: Any) -> Optional[List[float]]:
    """A number or a sequence of them (finite, >= 0) as a list of floats; None stays None."""
    if value is None:
        return None
    values = [value] if isinstance(value, numbers.Real) else list(value)
    if not values:
        raise UsageError(f"{name} = []: give at least one value, or None for the default")
    checked = [real(name, t) for t in values]
    if any(t < 0 for t in checked):
        raise UsageError(f"{name} = {min(checked)!r}: must be a finite number >= 0")
    return checked


def scenario(value: Scenario) -> Tuple[str, Optional[str]]:
    """The extension's scenario: ``("paper", None)``, ``("file", path)`` for a str or
    ``os.PathLike`` (always a path), ``("text", toml)`` for :class:`Toml` or a dict of sections."""
    if value is None:
        return ("paper", None)
    if isinstance(value, Toml):
        return ("text", value.text)
    if isinstance(value, Mapping):
        return ("text", sections_toml(value))
    if isinstance(value, str):
        if "\n" in value:
            shown = value if len(value) <= 60 else value[:57] + "..."
            raise UsageError(f"scenario {shown!r}: a str is taken as a path, and this one holds a newline; TOML text must be given as stickslip.Toml(text)")
        return ("file", value)
    if isinstance(value, os.PathLike):
        return ("file", os.fsdecode(value))
    raise UsageError(f"scenario: a path (str or os.PathLike), a dict of sections or stickslip.Toml(text), not {type(value).__name__}")


def sets(value: Optional[Mapping[str, Any]]) -> List[str]:
    """Dotted keys and values as the CLI's ``--set KEY=VALUE`` arguments (TOML values); every
    error names the key."""
    if value is None:
        return []
    if not isinstance(value, Mapping):
        raise UsageError(f"set: a dict of dotted keys and values, e.g. {{'model.damping': 0.5}}, not {type(value).__name__}")
    out = []
    for key, v in value.items():
        if not isinstance(key, str) or not key or "=" in key:
            raise ScenarioError(f"set: key {key!r}: must be a dotted scenario key such as 'model.damping'")
        out.append(f"{key}={toml_literal(v, f'set: {key}')}")
    return out


def toml_literal(v: Any, where: str = "set") -> str:
    """A Python value as a TOML literal: booleans (numpy's too), integers (any ``numbers.Integral``),
    finite floats (any ``numbers.Real``), strings, lists and tuples (and numpy arrays, via
    ``.tolist()``), dicts as inline tables. ``where`` (``"set: model.damping"``) names the key in
    the :class:`ScenarioError` for anything else, NaN and infinities included."""
    if is_bool(v):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        if not math.isfinite(f):
            raise ScenarioError(f"{where} = {f!r}: must be a finite number")
        return repr(f)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{k} = {toml_literal(x, where)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_literal(x, where) for x in v) + "]"
    if callable(getattr(v, "tolist", None)):
        return toml_literal(v.tolist(), where)
    raise ScenarioError(f"{where} = {v!r}: not a scenario value (a number, string, boolean, list or dict)")


def sections_toml(d: Mapping[str, Any]) -> str:
    lines = []
    for section, keys in d.items():
        if not isinstance(keys, Mapping):
            raise ScenarioError(f"scenario: section {section!r} must be a dict of keys")
        lines.append(f"[{section}]")
        lines += [f"{k} = {toml_literal(v, f'scenario: {section}.{k}')}" for k, v in keys.items()]
    return "\n".join(lines) + "\n"


def state(value: Any) -> Tuple[float, float, float]:
    """``(x, v, v_belt)``: three finite numbers (a numpy array too)."""
    values = value.tolist() if callable(getattr(value, "tolist", None)) else value
    values = list(values) if isinstance(values, (list, tuple)) else None
    if values is None or len(values) != 3 or not all(isinstance(s, numbers.Real) and not is_bool(s) and math.isfinite(s) for s in values):
        raise UsageError(f"state = {value!r}: must be three finite numbers (x [m], mass velocity [m/s], belt velocity [m/s])")
    x, v, belt = (float(s) for s in values)
    return (x, v, belt)


def strings(name: str, value: Optional[Sequence[str]]) -> Optional[List[str]]:
    """A sequence of str (``pairs``, ``target_se``) as a list; a lone str is one item."""
    if value is None:
        return None
    items = [value] if isinstance(value, str) else list(value)
    if not all(isinstance(s, str) for s in items):
        raise UsageError(f"{name} = {value!r}: must be strings such as 'T1,T2'")
    return items
