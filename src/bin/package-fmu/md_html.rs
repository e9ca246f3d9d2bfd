//! A small Markdown-to-HTML converter for the subset the notes in `docs/` use, run when the
//! .fmu is packaged, so that `documentation/index.html` shows the notes rendered (no
//! Markdown viewer needed, no new dependency).
//!
//! Blocks: ATX headings (`#`..`####`, with ids), paragraphs, fenced code blocks (```` ``` ````
//! with an optional language), indented code blocks (4 spaces, after a blank line, outside
//! lists), bulleted (`-`, `*`) and numbered (`1.`) lists whose items continue on indented
//! lines, pipe tables (`| a | b |` with a `|---|` row), block quotes (`>`). Inline: code
//! spans, `**bold**`, images `![alt](src)` and links `[text](target)`; a link to one of
//! the notes shipped in the same page (`model.md#...`) becomes an in-page link, other
//! relative links (files of the repository that are not in the .fmu) keep only their text.
//! Everything else is escaped and shown as written.

use std::fmt::Write as _;

/// HTML-escapes `s`.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The id of a heading: `prefix` and the lower-case words of `text`, joined by `-`.
pub fn slug(prefix: &str, text: &str) -> String {
    let words: Vec<String> = text
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
        .collect();
    let mut s = String::from(prefix);
    for w in words {
        if !s.is_empty() {
            s.push('-');
        }
        s.push_str(&w);
    }
    s
}

/// Where a link goes in the page: `notes` maps a note's file name (`model.md`) to the id of
/// its section; `None` for a relative link to a file that is not in the page or archive.
fn link_target(target: &str, notes: &[(&str, &str)], files: &[&str]) -> Option<String> {
    if target.contains("://") || target.starts_with('#') || target.starts_with("mailto:") {
        return Some(target.to_string());
    }
    let (path, frag) = match target.split_once('#') {
        Some((p, f)) => (p, Some(f)),
        None => (target, None),
    };
    let file = path.rsplit('/').next().unwrap_or(path);
    if let Some((_, id)) = notes.iter().find(|(n, _)| *n == file) {
        return Some(match frag {
            Some(f) => format!("#{}", slug(id, f)),
            None => format!("#{id}"),
        });
    }
    files.contains(&path).then(|| path.to_string())
}

/// Inline Markdown of one block's text to HTML.
pub fn inline(text: &str, notes: &[(&str, &str)], files: &[&str]) -> String {
    let mut o = String::new();
    let b = text.as_bytes();
    let mut i = 0;
    let mut plain = String::new();
    let flush = |plain: &mut String, o: &mut String| {
        o.push_str(&esc(plain));
        plain.clear();
    };
    while i < b.len() {
        let rest = &text[i..];
        if rest.starts_with('`') {
            let ticks = rest.bytes().take_while(|&c| c == b'`').count();
            let fence = &rest[..ticks];
            if let Some(end) = rest[ticks..].find(fence) {
                flush(&mut plain, &mut o);
                let code = rest[ticks..ticks + end].trim();
                let _ = write!(o, "<code>{}</code>", esc(code));
                i += 2 * ticks + end;
                continue;
            }
        }
        if let Some(bold) = rest.strip_prefix("**") {
            if let Some(end) = bold.find("**") {
                if end > 0 {
                    flush(&mut plain, &mut o);
                    let _ = write!(o, "<b>{}</b>", inline(&bold[..end], notes, files));
                    i += 4 + end;
                    continue;
                }
            }
        }
        let image = rest.starts_with("![");
        if image || rest.starts_with('[') {
            let open = if image { 2 } else { 1 };
            if let Some((label, target, len)) = bracket_link(&rest[open..]) {
                flush(&mut plain, &mut o);
                if image {
                    let _ = write!(o, r#"<img src="{}" alt="{}">"#, esc(target), esc(label));
                } else {
                    let inner = inline(label, notes, files);
                    match link_target(target, notes, files) {
                        Some(t) => {
                            let _ = write!(o, r#"<a href="{}">{inner}</a>"#, esc(&t));
                        }
                        None => o.push_str(&inner),
                    }
                }
                i += open + len;
                continue;
            }
        }
        let c = rest.chars().next().unwrap_or(' ');
        plain.push(c);
        i += c.len_utf8();
    }
    flush(&mut plain, &mut o);
    o
}

/// `label](target)` at the start of `s`: (label, target, bytes consumed).
fn bracket_link(s: &str) -> Option<(&str, &str, usize)> {
    let mut depth = 0;
    let mut close = None;
    for (k, c) in s.char_indices() {
        match c {
            '[' => depth += 1,
            ']' if depth == 0 => {
                close = Some(k);
                break;
            }
            ']' => depth -= 1,
            '\n' => return None,
            _ => {}
        }
    }
    let close = close?;
    let after = &s[close + 1..];
    if !after.starts_with('(') {
        return None;
    }
    let end = after.find(')')?;
    let target = &after[1..end];
    if target.contains(' ') {
        return None;
    }
    Some((&s[..close], target, close + 1 + end + 1))
}

fn is_table_row(l: &str) -> bool {
    let t = l.trim();
    t.starts_with('|') && t.ends_with('|') && t.len() > 1
}

/// The cells of a table row; a `|` inside a code span does not split.
fn cells(l: &str) -> Vec<&str> {
    let t = l.trim();
    let inner = &t[1..t.len() - 1];
    let mut out = Vec::new();
    let (mut start, mut code) = (0, false);
    for (k, c) in inner.char_indices() {
        match c {
            '`' => code = !code,
            '|' if !code => {
                out.push(inner[start..k].trim());
                start = k + 1;
            }
            _ => {}
        }
    }
    out.push(inner[start..].trim());
    out
}

/// The list marker of a line: (indent, numbered, text after the marker).
fn list_item(l: &str) -> Option<(usize, bool, &str)> {
    let indent = l.len() - l.trim_start().len();
    let t = l.trim_start();
    if let Some(r) = t.strip_prefix("- ").or_else(|| t.strip_prefix("* ")) {
        return Some((indent, false, r));
    }
    let digits = t.bytes().take_while(u8::is_ascii_digit).count();
    if digits > 0 && t[digits..].starts_with(". ") {
        return Some((indent, true, &t[digits + 2..]));
    }
    None
}

/// The note `md` as HTML; heading ids start with `prefix` (e.g. `note-model`).
pub fn to_html(md: &str, prefix: &str, notes: &[(&str, &str)], files: &[&str]) -> String {
    let lines: Vec<&str> = md.lines().collect();
    let mut o = String::new();
    let mut i = 0;
    let inl = |s: &str| inline(s, notes, files);
    while i < lines.len() {
        let l = lines[i];
        let t = l.trim();
        if t.is_empty() {
            i += 1;
            continue;
        }
        // fenced code
        if t.starts_with("```") {
            let lang = t.trim_start_matches('`').trim();
            let mut code = Vec::new();
            i += 1;
            while i < lines.len() && !lines[i].trim_start().starts_with("```") {
                code.push(lines[i]);
                i += 1;
            }
            i += 1;
            let class = if lang.is_empty() {
                String::new()
            } else {
                format!(r#" class="lang-{}""#, esc(lang))
            };
            let _ = writeln!(
                o,
                "<pre{class}><code>{}</code></pre>",
                esc(&code.join("\n"))
            );
            continue;
        }
        // indented code (4 spaces)
        if l.starts_with("    ") && list_item(l).is_none() {
            let mut code = Vec::new();
            while i < lines.len() && (lines[i].starts_with("    ") || lines[i].trim().is_empty()) {
                code.push(lines[i].get(4..).unwrap_or(""));
                i += 1;
            }
            while code.last().is_some_and(|c| c.trim().is_empty()) {
                code.pop();
            }
            let _ = writeln!(o, "<pre><code>{}</code></pre>", esc(&code.join("\n")));
            continue;
        }
        // heading
        if t.starts_with('#') {
            let level = t.bytes().take_while(|&c| c == b'#').count();
            if (1..=6).contains(&level) && t[level..].starts_with(' ') {
                let text = t[level..].trim();
                // the note's own title is level 1; inside the page it sits under an h2
                let h = (level + 1).min(6);
                let _ = writeln!(
                    o,
                    r#"<h{h} id="{}">{}</h{h}>"#,
                    esc(&slug(prefix, text)),
                    inl(text)
                );
                i += 1;
                continue;
            }
        }
        // table
        if is_table_row(l) && i + 1 < lines.len() && lines[i + 1].trim().starts_with("|-")
            || is_table_row(l) && i + 1 < lines.len() && lines[i + 1].trim().starts_with("| -")
        {
            let head = cells(l);
            o.push_str("<table><tr>");
            for c in &head {
                let _ = write!(o, "<th>{}</th>", inl(c));
            }
            o.push_str("</tr>\n");
            i += 2;
            while i < lines.len() && is_table_row(lines[i]) {
                o.push_str("<tr>");
                for c in cells(lines[i]) {
                    let _ = write!(o, "<td>{}</td>", inl(c));
                }
                o.push_str("</tr>\n");
                i += 1;
            }
            o.push_str("</table>\n");
            continue;
        }
        // block quote
        if t.starts_with('>') {
            let mut text = Vec::new();
            while i < lines.len() && lines[i].trim_start().starts_with('>') {
                text.push(lines[i].trim_start()[1..].trim());
                i += 1;
            }
            let _ = writeln!(
                o,
                "<blockquote><p>{}</p></blockquote>",
                inl(&text.join(" "))
            );
            continue;
        }
        // list
        if let Some((indent0, numbered, _)) = list_item(l) {
            let tag = if numbered { "ol" } else { "ul" };
            let _ = writeln!(o, "<{tag}>");
            while i < lines.len() {
                let Some((ind, num, first)) = list_item(lines[i]) else {
                    break;
                };
                if ind != indent0 || num != numbered {
                    break;
                }
                let mut text = vec![first];
                let mut nested = String::new();
                i += 1;
                while i < lines.len() && !lines[i].trim().is_empty() {
                    match list_item(lines[i]) {
                        Some((ind2, _, _)) if ind2 <= indent0 => break,
                        Some(_) => {
                            // a nested list: its lines up to the next item of this level
                            let mut sub = Vec::new();
                            while i < lines.len()
                                && !lines[i].trim().is_empty()
                                && list_item(lines[i]).is_none_or(|(k, _, _)| k > indent0)
                            {
                                sub.push(lines[i]);
                                i += 1;
                            }
                            let strip = sub
                                .iter()
                                .map(|s| s.len() - s.trim_start().len())
                                .min()
                                .unwrap_or(0);
                            let sub: Vec<&str> = sub.iter().map(|s| &s[strip..]).collect();
                            nested.push_str(&to_html(&sub.join("\n"), prefix, notes, files));
                        }
                        None => {
                            text.push(lines[i].trim());
                            i += 1;
                        }
                    }
                }
                let _ = writeln!(o, "<li>{}{nested}</li>", inl(&text.join("\n")));
                // blank lines between items of this list keep it open
                let mut k = i;
                while k < lines.len() && lines[k].trim().is_empty() {
                    k += 1;
                }
                if k > i
                    && k < lines.len()
                    && list_item(lines[k])
                        .is_some_and(|(d, num, _)| d == indent0 && num == numbered)
                {
                    i = k;
                }
            }
            let _ = writeln!(o, "</{tag}>");
            continue;
        }
        // paragraph: up to a blank line or the start of another block
        let mut text = vec![t];
        i += 1;
        while i < lines.len() {
            let n = lines[i];
            let nt = n.trim();
            if nt.is_empty()
                || nt.starts_with("```")
                || nt.starts_with('#')
                || list_item(n).is_some()
                || is_table_row(n)
                || nt.starts_with('>')
            {
                break;
            }
            text.push(nt);
            i += 1;
        }
        let _ = writeln!(o, "<p>{}</p>", inl(&text.join("\n")));
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    const NOTES: &[(&str, &str)] = &[("model.md", "note-model")];

    #[test]
    fn blocks_and_inlines() {
        let md = "# Title\n\nSome `code` and **bold** text,\na [link](model.md#2-geometry) and [other](../src/x.rs).\n\n    y = a b    (1.1)\n\n- one\n  more\n- two\n  - inner\n\n1. first\n2. second\n\n| a | b |\n|---|---|\n| 1 | `x|y` |\n\n```sh\nbash <x>\n```\n![alt](figures/s.svg)\n";
        let h = to_html(md, "note-model", NOTES, &["figures/s.svg"]);
        assert!(h.contains(r#"<h2 id="note-model-title">Title</h2>"#), "{h}");
        assert!(h.contains("<code>code</code> and <b>bold</b> text,"), "{h}");
        assert!(
            h.contains(r##"<a href="#note-model-2-geometry">link</a> and other."##),
            "{h}"
        );
        assert!(
            h.contains("<pre><code>y = a b    (1.1)</code></pre>"),
            "{h}"
        );
        assert!(
            h.contains("<li>one\nmore</li>\n<li>two<ul>\n<li>inner</li>\n</ul>\n</li>"),
            "{h}"
        );
        assert!(h.contains("<td>1</td><td><code>x|y</code></td>"), "{h}");
        assert!(h.contains("<ol>\n<li>first</li>\n<li>second</li>"), "{h}");
        assert!(h.contains("<th>a</th><th>b</th>"), "{h}");
        assert!(
            h.contains(r#"<pre class="lang-sh"><code>bash &lt;x&gt;</code></pre>"#),
            "{h}"
        );
        assert!(h.contains(r#"<img src="figures/s.svg" alt="alt">"#), "{h}");
    }

    #[test]
    fn slugs() {
        assert_eq!(
            slug("note-model", "2. Gear pair geometry (ISO 21771)"),
            "note-model-2-gear-pair-geometry-iso-21771"
        );
        assert_eq!(slug("", "Law 3: ISO"), "law-3-iso");
    }
}
