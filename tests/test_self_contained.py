"""The repository and the .fmu are self-contained: no reference points to a file
outside them.

Checked in every tracked text file (and every text file inside the built .fmu):
- no path into the project's private notes (a `shared/` directory next to or above
  the repository, or an absolute path under /work);
- every `*.md` file named exists (a bare name anywhere in the repository, a path
  relative to the repository root or to the referring file; inside the .fmu: in
  the archive);
- every `model.md §X`, `radau5.md §X` or `fmu.md §X` (also written `model.md 9.7`,
  `model.md §5-§8`) names a section that is a heading of docs/<file>, and every
  `fmu.md "Title"` a heading containing that title.

The scanner is plain Python; the last tests feed it bad references to show that it
fails on them.
"""

from __future__ import annotations

import re
import subprocess
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ("model.md", "radau5.md", "fmu.md")
# Built from pieces so that this file does not flag itself.
NOTES_DIR = "sha" + "red/"
FORBIDDEN = [
    re.compile(r"(?<![\w-])" + re.escape(NOTES_DIR) + r"(spec|data|paper)\b"),
    re.compile(r"\.\./" + re.escape(NOTES_DIR)),
    re.compile(r"/wo" + r"rk/"),
]
# a file name, not a Python attribute such as `pkg.md.guid`
MD_NAME = re.compile(r"(?<![\w/.-])((?:\.{1,2}/)*(?:[\w-]+/)*[\w-]+\.md)\b(?!\.\w)")
DOC_REF = re.compile(r"\b(model|radau5|fmu)\.md\b`?")
# what may follow a doc name: section numbers like "§3.4", "9.7", "§5-§8", "§2, §3"
SECTION_RUN = re.compile(
    r"^[ \t]*(?:§[ \t]*)?\d+(?:\.\d+)*(?:[ \t]*(?:,|/|–|-|and|&)[ \t]*(?:§[ \t]*)?\d+(?:\.\d+)*)*"
)
SECTION_NUM = re.compile(r"\d+(?:\.\d+)*")
# Python objects named like a file (`pkg.md` is FMPy's model description of the package)
PY_ATTRIBUTES = {"self.md", "pkg.md"}
TITLE_REF = re.compile(r'^[ \t]*"([^"\n]+)"')
# `README "Input smoothing"`, `docs/development.md "Benchmarks"` (may span a line break)
TITLED_REF = re.compile(r'\b(README|[\w/-]+\.md)`?\s+"([^"\n]+)"')
HEADING = re.compile(r"^#+[ \t]+(.*)$", re.M)
TEXT_SUFFIXES = {
    ".rs", ".py", ".md", ".toml", ".xml", ".sh", ".txt", ".html", ".svg", ".csv", ".cfg",
    ".ini", ".yml", ".yaml", ".json", "",
}


def headings(text: str) -> tuple[set[str], list[str]]:
    """Section numbers and titles of the headings of a markdown text."""
    numbers, titles = set(), []
    for h in HEADING.findall(text):
        titles.append(h)
        m = re.match(r"(\d+(?:\.\d+)*)\.?(\s|$)", h)
        if m:
            numbers.add(m.group(1))
    return numbers, titles


def scan(files: dict[str, str], docs: dict[str, str], exists,
         others: dict[str, str] | None = None) -> list[str]:
    """All bad references in `files` (name -> text). `docs` maps model.md etc. to
    their text; `exists(referrer, md_path)` says whether an .md reference resolves;
    `others` maps further markdown files (README.md, development.md) to their text for
    `README "Title"` references."""
    heads = {name: headings(text) for name, text in docs.items()}
    other_heads = {name: headings(text)[1] for name, text in (others or {}).items()}
    bad = []
    for fname, text in files.items():
        for lineno, line in enumerate(text.splitlines(), 1):
            where = f"{fname}:{lineno}"
            for pat in FORBIDDEN:
                if pat.search(line):
                    bad.append(f"{where}: path outside the repository: {line.strip()}")
            for m in MD_NAME.finditer(line):
                if "://" in line[max(0, m.start() - 60):m.start()]:
                    continue  # part of a URL
                if fname.endswith(".py") and m.group(1) in PY_ATTRIBUTES:
                    continue
                if not exists(fname, m.group(1)):
                    bad.append(f"{where}: {m.group(1)} does not exist: {line.strip()}")
            for m in DOC_REF.finditer(line):
                doc = m.group(1) + ".md"
                rest = line[m.end():]
                if doc not in heads:
                    bad.append(f"{where}: {doc} is not in the documentation")
                    continue
                numbers, titles = heads[doc]
                run = SECTION_RUN.match(rest)
                if run:
                    for num in SECTION_NUM.findall(run.group(0)):
                        if num not in numbers:
                            bad.append(f"{where}: {doc} has no section {num}: {line.strip()}")
                t = TITLE_REF.match(rest)
                if t and not any(t.group(1) in h for h in titles):
                    bad.append(f'{where}: {doc} has no section "{t.group(1)}": {line.strip()}')
        for m in TITLED_REF.finditer(text):
            doc, title = m.group(1), m.group(2)
            key = "README.md" if doc == "README" else doc.rsplit("/", 1)[-1]
            if key in DOCS or key not in other_heads:
                continue  # docs are checked above; unknown files by the name check
            if not any(title in h for h in other_heads[key]):
                bad.append(f'{fname}: {doc} has no section "{title}"')
    return bad


def tracked_files() -> list[Path]:
    try:
        out = subprocess.run(
            ["git", "ls-files", "--cached", "--others", "--exclude-standard"],
            cwd=ROOT, capture_output=True, text=True, check=True,
        ).stdout
        paths = [ROOT / p for p in out.splitlines()]
    except (OSError, subprocess.CalledProcessError):  # a tarball without git
        skip = {"target", ".venv", "out", ".git", "__pycache__", ".pytest_cache"}
        paths = [p for p in ROOT.rglob("*") if not skip & set(p.relative_to(ROOT).parts)]
    return [p for p in paths if p.is_file() and p.suffix in TEXT_SUFFIXES]


def read_text(p: Path) -> str | None:
    try:
        return p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        return None


def repo_docs() -> dict[str, str]:
    return {d: (ROOT / "docs" / d).read_text(encoding="utf-8") for d in DOCS}


def repo_exists(md_names: set[str], md_paths: set[str]):
    def exists(referrer: str, ref: str) -> bool:
        if "/" not in ref or ref.startswith("documentation/"):
            # a bare name, or a path inside the .fmu (the packager's file list)
            return ref.rsplit("/", 1)[-1] in md_names
        here = (ROOT / referrer).parent
        return any((base / ref).resolve().relative_to(ROOT).as_posix() in md_paths
                   for base in (ROOT, here) if (base / ref).resolve().is_relative_to(ROOT))
    return exists


def repo_scan() -> list[str]:
    files = {}
    for p in tracked_files():
        if p == Path(__file__).resolve():
            continue  # its own examples of bad references
        text = read_text(p)
        if text is not None:
            files[p.relative_to(ROOT).as_posix()] = text
    md_paths = {n for n in files if n.endswith(".md")}
    md_names = {n.rsplit("/", 1)[-1] for n in md_paths}
    others = {n.rsplit("/", 1)[-1]: files[n] for n in md_paths}
    return scan(files, repo_docs(), repo_exists(md_names, md_paths), others)


def test_repository_has_no_reference_outside_it():
    bad = repo_scan()
    assert not bad, "\n".join(bad)


def test_fmu_has_no_reference_outside_it(fmu_path):
    z = zipfile.ZipFile(fmu_path)
    files = {}
    for name in z.namelist():
        if Path(name).suffix in TEXT_SUFFIXES - {""}:
            files[name] = z.read(name).decode("utf-8")
    names = set(z.namelist())
    md_names = {n.rsplit("/", 1)[-1] for n in names if n.endswith(".md")}
    docs = {d: files[f"documentation/{d}"] for d in DOCS if f"documentation/{d}" in files}
    assert "model.md" in docs, "documentation/model.md missing from the .fmu"

    def exists(referrer: str, ref: str) -> bool:
        return ref.rsplit("/", 1)[-1] in md_names

    # Inside the .fmu the docs are flat in documentation/: references by name resolve
    # there; repository paths such as docs/model.md resolve by their file name.
    bad = scan(files, docs, exists)
    assert not bad, "\n".join(bad)


# --- the scanner fails on bad references ------------------------------------------------

def _scan_one(text: str) -> list[str]:
    files = {"src/x.rs": text}
    md_paths = {f"docs/{d}" for d in DOCS} | {"README.md", "docs/development.md"}
    md_names = {n.rsplit("/", 1)[-1] for n in md_paths}
    others = {n.rsplit("/", 1)[-1]: (ROOT / n).read_text(encoding="utf-8") for n in md_paths}
    return scan(files, repo_docs(), repo_exists(md_names, md_paths), others)


@pytest.mark.parametrize("text", [
    "// see `" + NOTES_DIR + "spec/model.md` §3",
    "//! runs `../" + NOTES_DIR + "data/radau5/reference.md`",
    "// details in notes/missing.md",
    "// details in docs/nothere.md",
    "// (model.md §14)",
    "// (model.md §9.11)",
    "// radau5.md §10",
    "/// model.md 3.7",
    "// model.md §5-§15",
    '// (docs/fmu.md "No such section")',
    '// the filter of README "Input smoothness"',
    '/// see docs/development.md "Benchmark figures"',
])
def test_scanner_reports_a_bad_reference(text):
    assert _scan_one(text), f"not reported: {text}"


@pytest.mark.parametrize("text", [
    "// (model.md §3.4, equation (3.10))",
    "// model.md 9.7",
    "// `model.md` §5-§8",
    "// radau5.md §8; docs/radau5.md §3",
    '// (docs/fmu.md "Mesh events")',
    "// see README.md and docs/model.md",
    '// the filter of README "Input smoothing"',
    '/// see docs/development.md "Benchmarks"',
])
def test_scanner_accepts_a_good_reference(text):
    assert _scan_one(text) == []
