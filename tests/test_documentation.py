"""documentation/ of the .fmu: index.html lists every variable of modelDescription.xml
with its declared start, min, max, unit and display unit (read from the XML here with
ElementTree, independently of the packager's reader); the files index.html links to
are in the archive; LICENSE.txt is the repository's LICENSE; generationDateAndTime is a
valid UTC date and equals the commit date of the sources when git is available."""

from __future__ import annotations

import os
import re
import subprocess
import xml.etree.ElementTree as ET
import zipfile
from datetime import datetime, timezone
from html.parser import HTMLParser
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASES = ("Real", "Integer", "Boolean", "String", "Enumeration")


class Rows(HTMLParser):
    """Cells of class start/min/max/unit/display of every <tr id="var-NAME">."""

    def __init__(self):
        super().__init__()
        self.rows: dict[str, dict[str, str]] = {}
        self.links: list[str] = []
        self._row = None
        self._cell = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr" and (a.get("id") or "").startswith("var-"):
            self._row = a["id"][4:]
            self.rows[self._row] = {}
        elif tag == "td" and self._row is not None and a.get("class"):
            self._cell = a["class"]
            self.rows[self._row][self._cell] = ""
        elif tag in ("a", "img"):
            self.links.append(a.get("href") or a.get("src") or "")

    def handle_endtag(self, tag):
        if tag == "td":
            self._cell = None
        elif tag == "tr":
            self._row = None

    def handle_data(self, data):
        if self._row is not None and self._cell is not None:
            self.rows[self._row][self._cell] += data


def declared(md: ET.Element) -> dict[str, dict[str, str]]:
    """name -> the attributes of the variable's type element completed from its declared type."""
    types = {}
    for st in md.iter("SimpleType"):
        el = next(c for c in st if c.tag in BASES)
        attrs = dict(el.attrib)
        items = [int(i.get("value")) for i in el.iter("Item")]
        if items:
            attrs.setdefault("min", str(min(items)))
            attrs.setdefault("max", str(max(items)))
        types[st.get("name")] = attrs
    out = {}
    for sv in md.iter("ScalarVariable"):
        el = next(c for c in sv if c.tag in BASES)
        attrs = dict(el.attrib)
        for k, v in types.get(attrs.get("declaredType"), {}).items():
            attrs.setdefault(k, v)
        out[sv.get("name")] = attrs
    return out


def test_index_html_lists_every_variable_with_bounds_and_units(fmu_path):
    z = zipfile.ZipFile(fmu_path)
    md = ET.fromstring(z.read("modelDescription.xml"))
    p = Rows()
    p.feed(z.read("documentation/index.html").decode("utf-8"))
    want = declared(md)
    assert len(want) > 100
    missing = sorted(set(want) - set(p.rows))
    assert not missing, f"variables missing from index.html: {missing}"
    checked_bounds = 0
    for name, attrs in want.items():
        row = p.rows[name]
        for key in ("start", "min", "max"):
            if key in attrs:
                assert row[key].startswith(attrs[key]), f"{name}: {key} {attrs[key]!r} vs {row[key]!r}"
                checked_bounds += key != "start"
            else:
                assert row[key] == "", f"{name}: {key} shown but not declared: {row[key]!r}"
        assert row["unit"] == attrs.get("unit", ""), f"{name}: unit"
        assert row["display"] == attrs.get("displayUnit", ""), f"{name}: display unit"
    assert checked_bounds >= 30


def test_display_values_are_converted_with_the_declared_factor(fmu_path):
    z = zipfile.ZipFile(fmu_path)
    p = Rows()
    p.feed(z.read("documentation/index.html").decode("utf-8"))
    # independent conversions: 20 deg, 3000 rpm, 200 N/um, 45 deg bound
    assert p.rows["alpha_n"]["start"].endswith("(20 deg)")
    assert p.rows["omega1"]["start"].endswith("(3000 rpm)")  # 314.159 rad/s, 6 digits
    assert p.rows["k1.x"]["start"].endswith("(200 N/um)")
    assert p.rows["beta"]["max"].endswith("(45 deg)")


def test_documentation_links_resolve_inside_the_archive(fmu_path):
    z = zipfile.ZipFile(fmu_path)
    names = set(z.namelist())
    p = Rows()
    p.feed(z.read("documentation/index.html").decode("utf-8"))
    local = [l for l in p.links if l and "://" not in l and not l.startswith("#")]
    assert len(local) >= 8
    for link in local:
        assert f"documentation/{link}" in names, f"index.html links to {link}, not in the .fmu"
    assert z.read("documentation/LICENSE.txt") == (ROOT / "LICENSE").read_bytes()
    assert b"MIT License" in z.read("documentation/LICENSE.txt")


def test_generation_date_is_the_commit_date(fmu_path):
    """The packager's order: git commit date, else SOURCE_DATE_EPOCH, else no attribute."""
    md = ET.fromstring(zipfile.ZipFile(fmu_path).read("modelDescription.xml"))
    stamp = md.get("generationDateAndTime")
    try:
        epoch = subprocess.run(["git", "log", "-1", "--format=%ct"], cwd=ROOT, capture_output=True,
                               text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):  # a tarball
        epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch is None:
        assert stamp is None, stamp
        return
    assert stamp is not None and re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", stamp), stamp
    assert stamp == datetime.fromtimestamp(int(epoch), tz=timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
