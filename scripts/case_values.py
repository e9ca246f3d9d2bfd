"""`--set NAME=VALUE[unit]` for the main job: parses a parameter or input setting and
converts it to SI with the units the FMU's model description declares.

    omega1=1500rpm   beta=15deg   mu=0.1   k1.x=150N/um   T_load=0.05kN.m   z1=31

A value without a unit is taken in the variable's SI unit. A unit must be the
variable's unit or one of its declared display units (display = factor * SI + offset);
"µm" may be written for "um". Integer and Enumeration variables take whole numbers,
Booleans true/false.
"""

from __future__ import annotations

import difflib
import re

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_PATTERN = re.compile(rf"^\s*([A-Za-z_][\w.\[\]]*)\s*=\s*({_NUMBER}|true|false)\s*(\S*)\s*$")


class SetError(ValueError):
    """A --set argument that cannot be applied; the message says what to write instead."""


def unit_of(var) -> str:
    if var.unit:
        return var.unit
    return var.declaredType.unit if var.declaredType is not None and var.declaredType.unit else ""


def display_units(md, unit: str) -> dict[str, tuple[float, float]]:
    for u in md.unitDefinitions:
        if u.name == unit:
            return {d.name: (d.factor, d.offset) for d in u.displayUnits}
    return {}


def parse_set(md, text: str) -> tuple[str, float | int | bool]:
    """(name, value in SI) of one --set argument, checked against the model description."""
    m = _PATTERN.match(text)
    if not m:
        raise SetError(f"--set {text!r}: write NAME=VALUE or NAME=VALUEunit, e.g. omega1=1500rpm")
    name, number, unit = m.groups()
    variables = {v.name: v for v in md.modelVariables}
    if name not in variables:
        close = difflib.get_close_matches(name, variables, n=3)
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        raise SetError(f"--set {text!r}: the FMU has no variable {name!r}{hint}")
    var = variables[name]
    if var.causality not in ("parameter", "input"):
        raise SetError(f"--set {text!r}: {name} is a {var.causality}; only parameters and inputs can be set")
    if var.type == "Boolean":
        if number not in ("true", "false") or unit:
            raise SetError(f"--set {text!r}: {name} is Boolean, write {name}=true or {name}=false")
        return name, number == "true"
    if number in ("true", "false"):
        raise SetError(f"--set {text!r}: {name} is {var.type}, not Boolean")
    value = float(number)
    si = unit_of(var)
    if unit.replace("µ", "u") in ("", si):
        pass
    else:
        table = display_units(md, si)
        key = unit.replace("µ", "u")
        if key not in table:
            accepted = [si or "(none)"] + list(table)
            raise SetError(f"--set {text!r}: unit {unit!r} is not declared for {name}; "
                           f"use one of {', '.join(accepted)}")
        factor, offset = table[key]
        value = (value - offset) / factor
    if var.type in ("Integer", "Enumeration"):
        if value != round(value):
            raise SetError(f"--set {text!r}: {name} is {var.type}, give a whole number")
        return name, int(round(value))
    return name, value
