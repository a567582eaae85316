"""How one setting is declared: a dataclass field whose metadata holds its range, choices, command-line flag and
Blender label. `Settings` (settings/table.py) and the add-on's own settings are such dataclasses; from their fields come
the checks of `validate()`, the argparse options (here) and the Blender properties (the add-on's properties.py),
so that a range, a default or a description is written once.
"""

from __future__ import annotations

import argparse
import math
import numbers
from collections.abc import Callable
from dataclasses import MISSING, dataclass, field, fields
from typing import Any, TypeVar

import numpy as np

T = TypeVar("T")
SPEC = "restircl.spec"  # the key of a field's metadata that holds its Spec


class SettingError(ValueError):
    """A setting out of its range; `names` are the settings involved (one, or those of a joint limit)."""

    def __init__(self, message: str, names: tuple[str, ...]) -> None:
        super().__init__(message)
        self.names = names


@dataclass(frozen=True)
class Choice:
    """One value of a setting with choices. `number` is the value Blender stores in a .blend file for it: kept
    from the first release, so that saved files keep their choice; the add-on lists the choices in its order."""

    id: str
    label: str
    description: str
    number: int


@dataclass(frozen=True)
class Range:
    """The numbers a setting takes: NaN never; infinity only when there is no maximum and `finite` is False;
    `off` is one more value outside the range that switches the feature off (0 for "never")."""

    kind: type = float  # int or float
    min: float | None = None
    max: float | None = None
    min_open: bool = False  # the minimum itself is not allowed
    max_open: bool = False
    finite: bool = False
    off: float | None = None

    def contains(self, value: Any) -> bool:
        if not isinstance(value, numbers.Real) or isinstance(value, bool):
            return False
        value = float(value)
        if self.off is not None and value == self.off:
            return True
        if math.isnan(value) or (math.isinf(value) and (self.finite or self.max is not None)):
            return False
        if self.kind is int and not (math.isfinite(value) and float(value).is_integer()):
            return False
        if self.min is not None and (value <= self.min if self.min_open else value < self.min):
            return False
        return not (self.max is not None and (value >= self.max if self.max_open else value > self.max))

    def text(self) -> str:
        """'an integer in [1, 4096]', 'a finite number > 0', '0 (off) or a number > 1'."""
        what = "an integer" if self.kind is int else "a finite number" if self.finite else "a number"
        lo = None if self.min is None else ("(" if self.min_open else "[") + _num(self.min)
        hi = None if self.max is None else _num(self.max) + (")" if self.max_open else "]")
        if lo and hi:
            bounds = f" in {lo}, {hi}"
        elif lo:
            bounds = f" {'>' if self.min_open else '>='} {lo[1:]}"
        elif hi:
            bounds = f" {'<' if self.max_open else '<='} {hi[:-1]}"
        else:
            bounds = ""
        off = f"{_num(self.off)} (off) or " if self.off is not None else ""
        return off + what + bounds

    def parse(self, text: str) -> int | float:
        """An argparse type: the number in `text`, or an ArgumentTypeError saying which numbers are allowed."""
        try:
            value = self.kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not {self.text()}") from None
        if not self.contains(value):
            raise argparse.ArgumentTypeError(f"{text} is out of range: must be {self.text()}")
        return value

    def parse_list(self, text: str) -> list[int | float]:
        """An argparse type for a comma-separated list of such numbers."""
        return [self.parse(part) for part in text.split(",")]

    def nearest(self, value: float) -> float:
        """The allowed value nearest to `value` (for sliders that can reach the gap between `off` and the range)."""
        if self.contains(value):
            return value
        candidates = [v for v in (self.lowest(), self.highest(), self.off) if v is not None]
        return min(candidates, key=lambda v: abs(v - value)) if candidates else value

    def lowest(self) -> float | None:
        """The smallest allowed value (for an open minimum: the next float32 or integer above it)."""
        return _step(self.min, self.kind, up=True) if self.min_open else self.min

    def highest(self) -> float | None:
        return _step(self.max, self.kind, up=False) if self.max_open else self.max


@dataclass(frozen=True)
class Spec:
    """Everything about a setting besides its name, type and default (the dataclass field's)."""

    label: str  # Blender's label
    description: str  # Blender's tooltip and the command line's help
    flag: str | None = None  # command-line option; for a bool, the flag that turns it away from its default
    range: Range | None = None
    choices: tuple[Choice, ...] = ()
    panel: str | None = None  # the Blender panel that shows it (None: not shown in Blender)
    # Blender greys it out unless each named setting holds one of the listed values (it has no effect then)
    applies_when: tuple[tuple[str, tuple[Any, ...]], ...] = ()
    soft_max: float | None = None  # Blender's slider end (typing allows up to the range's maximum)
    subtype: str = "NONE"  # Blender's property subtype (PIXEL, FACTOR, ...)
    precision: int = 3  # digits Blender shows
    kernel_limit: str | None = None  # the kernels get the range's maximum as this -D define

    def choice_ids(self) -> tuple[str, ...]:
        return tuple(c.id for c in self.choices)


def setting(default: T, label: str, description: str, **spec: Any) -> T:
    """A dataclass field declaring a setting (see Spec for the keywords)."""
    return field(default=default, metadata={SPEC: Spec(label, description, **spec)})


@dataclass(frozen=True)
class Declared:
    """A setting as read from its dataclass field."""

    name: str
    kind: type  # bool, int, float or str: the type of the default
    default: Any
    spec: Spec

    def problem(self, value: Any) -> str | None:
        """Why `value` is not allowed, or None."""
        spec = self.spec
        if spec.choices and value not in spec.choice_ids():
            return f"is not one of {', '.join(spec.choice_ids())}"
        if spec.range is not None and not spec.range.contains(value):
            return f"is out of range: must be {spec.range.text()}"
        return None


def declared(cls: type) -> tuple[Declared, ...]:
    """The settings of a dataclass declared with `setting`, in field order."""
    out = []
    for f in fields(cls):
        spec = f.metadata.get(SPEC)
        if spec is not None and f.default is not MISSING:
            out.append(Declared(f.name, type(f.default), f.default, spec))
    return tuple(out)


def check(obj: Any) -> None:
    """Raise a SettingError naming the first setting of `obj` out of its range."""
    for d in declared(type(obj)):
        value = getattr(obj, d.name)
        why = d.problem(value)
        if why is not None:
            raise SettingError(f"setting {d.name}={value!r} {why}", (d.name,))


def add_arguments(group: argparse._ActionsContainer, cls: type) -> None:
    """One command-line option per setting of `cls` that has a flag."""
    for d in declared(cls):
        spec = d.spec
        if spec.flag is None:
            continue
        help_text = spec.description.replace("%", "%%")
        if d.kind is bool:
            group.add_argument(spec.flag, dest=d.name, action="store_false" if d.default else "store_true",
                               help=f"{spec.label} {'off' if d.default else 'on'} ({help_text})")
        elif spec.choices:
            listed = "; ".join(f"{c.id}: {c.description}" for c in spec.choices).replace("%", "%%")
            group.add_argument(spec.flag, dest=d.name, choices=spec.choice_ids(), default=d.default,
                               help=f"{help_text} ({listed}) (default: %(default)s)")
        else:
            parse: Callable[[str], Any] = spec.range.parse if spec.range is not None else d.kind
            group.add_argument(spec.flag, dest=d.name, type=parse, default=d.default, metavar=d.kind.__name__.upper(),
                               help=f"{help_text} (default: %(default)s)")


def from_arguments(cls: type[T], args: argparse.Namespace) -> T:
    """An instance of `cls` from the options that add_arguments made (settings without a flag keep defaults)."""
    kwargs = {d.name: getattr(args, d.name) for d in declared(cls) if d.spec.flag is not None}
    return cls(**kwargs)


def flag_of(cls: type, name: str) -> str:
    """The command-line flag of setting `name` (the name itself if it has none)."""
    for d in declared(cls):
        if d.name == name:
            return d.spec.flag or name
    return name


def _num(x: float) -> str:
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:g}"


def _step(x: float | None, kind: type, up: bool) -> float | None:
    if x is None:
        return None
    if kind is int:
        return x + 1 if up else x - 1
    # Blender stores floats as float32: the next one it can hold
    return float(np.nextafter(np.float32(x), np.float32(np.inf if up else -np.inf)))
