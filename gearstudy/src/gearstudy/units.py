"""The FMU's variables and their units, read from its modelDescription at run time.

A study names variables by their FMU names and may give values as quantities in any unit the
modelDescription declares for that variable: its unit (``"314.159 rad/s"``) or one of that
unit's display units (``"3000 rpm"``, ``"20 deg"``). FMI 2.0 (section 2.2.2) defines a display
value as ``display = factor * value + offset``, so the value the FMU receives is
``(display - offset) / factor``. No unit table lives in this package: a new display unit in the
modelDescription works without a change here.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass

from fmpy import read_model_description

_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


class StudyError(ValueError):
    """A study file or a value in it that cannot be used; the message names the entry and
    what to change."""


@dataclass(frozen=True)
class DisplayUnit:
    name: str
    factor: float
    offset: float


@dataclass(frozen=True)
class Variable:
    """One FMU variable as the study tool needs it."""

    name: str
    value_reference: int
    type: str  # "Real", "Integer", "Enumeration", "Boolean", "String"
    causality: str
    variability: str
    unit: str | None
    display_unit: str | None
    display_units: tuple[DisplayUnit, ...]
    enum_items: tuple[tuple[str, int], ...]
    start: str | None
    description: str

    @property
    def settable(self) -> bool:
        return self.causality in ("parameter", "input")


class Catalog:
    """All variables of an FMU by name, with the unit conversions of its modelDescription."""

    def __init__(self, model_description):
        md = model_description
        units = {u.name: u for u in (md.unitDefinitions or [])}
        self.guid: str = md.guid
        self.model_identifier: str = md.coSimulation.modelIdentifier
        self.variables: dict[str, Variable] = {}
        for v in md.modelVariables:
            dt = v.declaredType
            unit = v.unit or (dt.unit if dt is not None else None)
            disp = v.displayUnit or (dt.displayUnit if dt is not None else None)
            dus: tuple[DisplayUnit, ...] = ()
            if unit in units:
                dus = tuple(
                    DisplayUnit(d.name, float(d.factor), float(d.offset or 0.0))
                    for d in units[unit].displayUnits
                )
            items: tuple[tuple[str, int], ...] = ()
            if v.type == "Enumeration" and dt is not None and dt.items:
                items = tuple((it.name, int(it.value)) for it in dt.items)
            self.variables[v.name] = Variable(
                name=v.name,
                value_reference=int(v.valueReference),
                type=v.type,
                causality=v.causality,
                variability=v.variability,
                unit=unit,
                display_unit=disp,
                display_units=dus,
                enum_items=items,
                start=None if v.start is None else str(v.start),
                description=v.description or "",
            )

    @classmethod
    def from_fmu(cls, fmu_path) -> "Catalog":
        try:
            md = read_model_description(str(fmu_path))
        except Exception as e:  # a zip error, a missing or malformed modelDescription.xml
            raise StudyError(f"{fmu_path}: not an FMU whose model description can be read ({e}); "
                             "give --fmu target/fmu/GearedRotor.fmu or build it with "
                             "`cargo run --release --bin package-fmu`") from None
        return cls(md)

    def __contains__(self, name: str) -> bool:
        return name in self.variables

    def get(self, name: str, where: str = "") -> Variable:
        try:
            return self.variables[name]
        except KeyError:
            close = difflib.get_close_matches(name, self.variables, n=3)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise StudyError(
                f"{where}'{name}' is not a variable of the FMU {self.model_identifier}{hint}"
            ) from None

    def settable(self, name: str, where: str = "") -> Variable:
        v = self.get(name, where)
        if not v.settable:
            raise StudyError(
                f"{where}'{name}' is a {v.causality}; a study can set only parameters and inputs"
            )
        return v

    def unit_note(self, name: str) -> str:
        """The units a value of `name` may be written in, for messages and docs."""
        v = self.variables[name]
        names = [v.unit or "1"] + [d.name for d in v.display_units]
        return ", ".join(f'"{n}"' for n in names)

    def to_fmu_value(self, name: str, value, where: str = ""):
        """The value the FMU receives for `value` given in the study (a number in the
        variable's unit, or a string "<number> <unit>" with the unit or a display unit)."""
        v = self.settable(name, where)
        label = f"{where}{name} = {value!r}"
        if v.type == "Boolean":
            if isinstance(value, bool):
                return value
            raise StudyError(f"{label}: '{name}' is Boolean; write true or false")
        if v.type == "Enumeration" and isinstance(value, str) and v.enum_items:
            for item, number in v.enum_items:
                if item == value.strip():
                    return number
        if isinstance(value, bool):
            raise StudyError(f"{label}: '{name}' is {v.type}, not Boolean")
        if isinstance(value, (int, float)):
            number, unit_name = float(value), None
        elif isinstance(value, str):
            m = _QUANTITY.match(value)
            if not m:
                raise StudyError(
                    f"{label}: not a number with an optional unit; write e.g. \"3000 rpm\" "
                    f"(units of {name}: {self.unit_note(name)})"
                )
            number, unit_name = float(m.group(1)), (m.group(2) or None)
        else:
            raise StudyError(f"{label}: expected a number or a string like \"20 deg\"")
        if unit_name is not None and unit_name != v.unit:
            du = next((d for d in v.display_units if d.name == unit_name), None)
            if du is None:
                raise StudyError(
                    f"{label}: unit '{unit_name}' is not declared for '{name}' in the "
                    f"modelDescription; use one of {self.unit_note(name)}"
                )
            number = (number - du.offset) / du.factor
        if v.type in ("Integer", "Enumeration"):
            if number != int(number):
                raise StudyError(f"{label}: '{name}' is {v.type}; give a whole number")
            # FMI Integers are 32-bit: a larger number would wrap before the FMU sees it.
            if not -2**31 <= number < 2**31:
                raise StudyError(f"{label}: '{name}' = {number:g} is outside the 32-bit range of "
                                 "an FMI Integer")
            return int(number)
        if v.type != "Real":
            raise StudyError(f"{label}: variables of type {v.type} cannot be set by a study")
        if unit_name is None:
            _warn_unitless(label, name, number, v.unit or "")
        return number


#: SI unit -> (largest plausible magnitude of a value given without a unit, the unit meant more
#: likely): a bare 3 for m_n is 3 m, a bare 1800 for omega1 is 1800 rad/s
PLAUSIBLE_WITHOUT_UNIT = {"m": (1.0, "mm"), "rad/s": (1000.0, "rpm"), "rad": (1.5707963267948966, "deg")}
_warned: set[str] = set()


def _warn_unitless(label: str, name: str, number: float, unit: str) -> None:
    """A warning on stderr (once per entry) for a bare number implausible in the SI unit."""
    if unit not in PLAUSIBLE_WITHOUT_UNIT or label in _warned:
        return
    limit, instead = PLAUSIBLE_WITHOUT_UNIT[unit]
    if abs(number) >= limit:
        _warned.add(label)
        import sys

        print(f"gearstudy: warning: {label} has no unit, so it is {number:g} {unit}, implausible for a "
              f"gear pair (>= {limit:g} {unit}); if you meant {instead}, write \"{number:g} {instead}\"",
              file=sys.stderr)


def parse_duration(text, time_units: Catalog, what: str) -> tuple[float, str]:
    """A duration "100 ms" (any unit of the FMU's time variables, or plain seconds) or a
    number of mesh periods "40 periods". Returns (value, "s" | "periods")."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text), "s"
    m = _QUANTITY.match(str(text))
    if not m:
        raise StudyError(f"{what} = {text!r}: write a duration like \"100 ms\" or \"40 periods\"")
    number, unit = float(m.group(1)), m.group(2)
    if number < 0:
        raise StudyError(f"{what} = {text!r}: must not be negative")
    if unit in ("period", "periods"):
        return number, "periods"
    if unit in ("", "s"):
        return number, "s"
    for v in time_units.variables.values():
        if v.unit == "s":
            for d in v.display_units:
                if d.name == unit:
                    return (number - d.offset) / d.factor, "s"
    raise StudyError(f"{what} = {text!r}: unknown time unit '{unit}'; use s, ms or periods")
