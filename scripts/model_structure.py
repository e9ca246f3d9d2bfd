#!/usr/bin/env python3
"""Rewrite the <ModelStructure> of modelDescription/modelDescription.xml from the variables.

FMI 2.0 names ModelStructure entries by the 1-based position of a ScalarVariable, so adding
or moving one variable renumbers the whole section. This tool recomputes it:

- Outputs: every variable with causality="output", in order. Its dependencies are kept by
  *name*: the inputs an output depended on before (read from the current file, or from the
  files given with --deps-from) stay its dependencies at their new indices. A new output
  without an entry gets the dependencies given by --depends NAME=INPUT[,INPUT] or none.
- InitialUnknowns: the outputs with initial approx/calculated and the calculated parameters
  (the rule build.rs checks).
- The "<!-- N -->" comment line before each ScalarVariable is set to its index.

Usage: python3 scripts/model_structure.py [--deps-from OTHER.xml ...] [--depends mu_eff=T_load]
The file is rewritten in place; `cargo build` then checks it.
"""
import argparse
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

SOURCE = Path(__file__).resolve().parent.parent / "modelDescription" / "modelDescription.xml"


def variables(text):
    """(name, causality, initial) of every ScalarVariable, in document order."""
    out = []
    for m in re.finditer(r"<ScalarVariable\b([^>]*)>", text):
        attrs = dict(re.findall(r'(\w+)="([^"]*)"', m.group(1)))
        out.append((attrs["name"], attrs.get("causality", "local"), attrs.get("initial")))
    return out


def output_dependencies(text):
    """name -> (tuple of input names, kinds string or None) from a file's ModelStructure."""
    names = [v[0] for v in variables(text)]
    section = re.search(r"<Outputs>(.*?)</Outputs>", text, re.S)
    deps = {}
    if not section:
        return deps
    for m in re.finditer(r"<Unknown\b([^>]*)/>", section.group(1)):
        attrs = dict(re.findall(r'(\w+)="([^"]*)"', m.group(1)))
        name = names[int(attrs["index"]) - 1]
        ins = tuple(names[int(i) - 1] for i in attrs.get("dependencies", "").split())
        deps[name] = (ins, attrs.get("dependenciesKind"), "dependencies" in attrs)
    return deps


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--file", type=Path, default=SOURCE)
    ap.add_argument("--deps-from", type=Path, action="append", default=[],
                    help="other versions of the file whose output dependencies are merged in")
    ap.add_argument("--depends", action="append", default=[],
                    help="NAME=INPUT[,INPUT]: dependencies of an output not described elsewhere")
    a = ap.parse_args()

    text = a.file.read_text()
    deps = {}
    for other in a.deps_from:
        deps.update(output_dependencies(other.read_text()))
    # A ModelStructure with merge-conflict markers is not parsed; its outputs come from
    # --deps-from.
    if "<<<<<<<" not in text:
        deps.update(output_dependencies(text))
    for d in a.depends:
        name, ins = d.split("=", 1)
        ins = tuple(i for i in ins.split(",") if i)
        deps[name] = (ins, " ".join(["dependent"] * len(ins)) or None, True)

    vs = variables(text)
    index = {name: i + 1 for i, (name, _, _) in enumerate(vs)}
    lines = []
    for name, caus, _ in vs:
        if caus != "output":
            continue
        ins, kinds, has = deps.get(name, ((), None, True))
        attrs = f'index="{index[name]}"'
        if has:
            attrs += ' dependencies="' + " ".join(str(index[i]) for i in ins) + '"'
        if ins and kinds:
            attrs += f' dependenciesKind="{kinds}"'
        lines.append(f"      <Unknown {attrs}/>")
    init = [
        index[name]
        for name, caus, ini in vs
        if (caus == "output" and ini in ("approx", "calculated")) or caus == "calculatedParameter"
    ]

    # The "<!-- N -->" line before each ScalarVariable is its index: renumber those too.
    counter = iter(range(1, len(vs) + 1))
    text = re.sub(
        r"<!-- \d+ -->(\s*<ScalarVariable\b)", lambda m: f"<!-- {next(counter)} -->{m.group(1)}", text
    )

    start = text.index("<ModelStructure>")
    end = text.index("</ModelStructure>")
    body = text[start:end]
    comment = "".join(re.findall(r"\s*<!--.*?-->", body.split("<Outputs>")[0], re.S))
    new = (
        "<ModelStructure>" + comment + "\n    <Outputs>\n" + "\n".join(lines)
        + "\n    </Outputs>\n    <InitialUnknowns>\n"
        + "\n".join(f'      <Unknown index="{i}"/>' for i in init)
        + "\n    </InitialUnknowns>\n  "
    )
    a.file.write_text(text[:start] + new + text[end:])
    ET.fromstring(a.file.read_text().encode())  # still well-formed
    print(f"{a.file}: {len(lines)} outputs, {len(init)} initial unknowns", file=sys.stderr)


if __name__ == "__main__":
    main()
