"""documentation/index.html of the .fmu (issue 25): the notes are rendered into the page at
packaging time (no raw Markdown: no code fences, no `[text](target)` outside code, every
in-page link has its target), the example result is the steady state, and the bounds that
mean "> 0" read so instead of a converted 1e-300."""

from __future__ import annotations

import re
import zipfile


def _page(fmu_path) -> str:
    return zipfile.ZipFile(fmu_path).read("documentation/index.html").decode("utf-8")


def test_notes_are_rendered_in_the_page(fmu_path):
    html = _page(fmu_path)
    for note in ("model", "friction", "fmu", "validity", "radau5", "drivetrain"):
        assert f'<details id="note-{note}">' in html, note
    assert '<h3 id="note-model-2-gear-pair-geometry-iso-21771-din-3960-conventions">' in html
    assert '<h4 id="note-friction-two-loss-factors-the-model-s-h-v-and-the-standard-s-h-v-iso">' in html
    # outside <pre> blocks nothing is left in Markdown syntax
    text = re.sub(r"<pre.*?</pre>", "", html, flags=re.S)
    text = re.sub(r"<code>.*?</code>", "", text, flags=re.S)
    assert "```" not in text
    assert not re.search(r"\]\([\w./#-]+\)", text), re.search(r".{60}\]\([\w./#-]+\).{20}", text)
    assert not re.search(r"^#+ ", text, flags=re.M)
    # every in-page link has its target
    ids = set(re.findall(r'id="([^"]+)"', html))
    for target in set(re.findall(r'href="#([^"]+)"', html)):
        assert target in ids, target
    # the figure of the model note is shown from the archive
    assert '<img src="figures/geared_rotor.svg"' in html


def test_example_result_is_the_steady_state(fmu_path):
    html = _page(fmu_path)
    i = html.index("<h2>Example result</h2>")
    part = html[i:i + 200000]
    assert part.index("<svg") < part.index('<img src="result.svg"')  # steady state first
    assert "on the periodic orbit (4 mesh periods)" in part
    assert "T_damp" in part


def test_bounds_greater_than_zero_read_so(fmu_path):
    html = _page(fmu_path)
    assert "e-297" not in html
    assert '<td class="min">1e-300 (&gt; 0)</td>' in html
