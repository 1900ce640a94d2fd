//! A strict well-formedness check of the markup the page inlines: every element closed in
//! order, attributes quoted, `&` only in character references, one root element. The SVG
//! figures of a run's directory pass through it before they are put in the page, so a
//! truncated or foreign file is refused with its name instead of breaking the page.

/// `Ok` when `text` is one well-formed XML element (with optional comments, processing
/// instructions and whitespace around it); otherwise what is wrong and on which line.
pub fn check_well_formed(text: &str) -> Result<(), String> {
    let b = text.as_bytes();
    let line_at = |i: usize| 1 + b[..i.min(b.len())].iter().filter(|&&c| c == b'\n').count();
    let err = |i: usize, m: &str| Err(format!("line {}: {m}", line_at(i)));
    let mut stack: Vec<&str> = Vec::new();
    let mut roots = 0;
    let mut i = 0;
    while i < b.len() {
        if b[i] != b'<' {
            if b[i] == b'&' {
                let end = match text[i..].find(';') {
                    Some(e) => i + e,
                    None => return err(i, "an '&' that starts no character reference"),
                };
                let name = &text[i + 1..end];
                let ok = match name.strip_prefix('#') {
                    Some(n) => match n.strip_prefix('x') {
                        Some(h) => !h.is_empty() && h.chars().all(|c| c.is_ascii_hexdigit()),
                        None => !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()),
                    },
                    None => matches!(name, "amp" | "lt" | "gt" | "quot" | "apos"),
                };
                if !ok {
                    return err(i, &format!("an unknown character reference '&{name};'"));
                }
            } else if stack.is_empty() && !b[i].is_ascii_whitespace() {
                return err(i, "text outside the root element");
            }
            i += 1;
            continue;
        }
        let rest = &text[i..];
        let skip = |open: &str, close: &str| -> Option<Result<usize, String>> {
            rest.starts_with(open).then(|| {
                rest[open.len()..]
                    .find(close)
                    .map(|e| i + open.len() + e + close.len())
                    .ok_or_else(|| format!("line {}: '{open}' is never closed", line_at(i)))
            })
        };
        if let Some(next) = skip("<!--", "-->")
            .or_else(|| skip("<?", "?>"))
            .or_else(|| skip("<![CDATA[", "]]>"))
        {
            i = next?;
            continue;
        }
        if rest.starts_with("<!") {
            return err(i, "a declaration inside the document");
        }
        if let Some(after) = rest.strip_prefix("</") {
            let end = match after.find('>') {
                Some(e) => e,
                None => return err(i, "an end tag that is never closed"),
            };
            let name = after[..end].trim_end();
            match stack.pop() {
                Some(open) if open == name => {}
                Some(open) => {
                    return err(i, &format!("</{name}> closes <{open}>"));
                }
                None => return err(i, &format!("</{name}> closes nothing")),
            }
            i += 2 + end + 1;
            continue;
        }
        // A start tag: name, attributes, then '>' or '/>'.
        let mut j = i + 1;
        while j < b.len() && !b[j].is_ascii_whitespace() && b[j] != b'>' && b[j] != b'/' {
            j += 1;
        }
        let name = &text[i + 1..j];
        if name.is_empty() {
            return err(i, "a '<' that starts no tag");
        }
        if stack.is_empty() {
            roots += 1;
            if roots > 1 {
                return err(i, &format!("a second root element <{name}>"));
            }
        }
        loop {
            while j < b.len() && b[j].is_ascii_whitespace() {
                j += 1;
            }
            if j >= b.len() {
                return err(i, &format!("the tag <{name}> is never closed"));
            }
            if b[j] == b'>' {
                stack.push(name);
                j += 1;
                break;
            }
            if b[j] == b'/' {
                if b.get(j + 1) != Some(&b'>') {
                    return err(j, &format!("a '/' inside <{name}>"));
                }
                j += 2;
                break;
            }
            // attribute name = "value"
            let start = j;
            while j < b.len() && b[j] != b'=' && !b[j].is_ascii_whitespace() && b[j] != b'>' {
                j += 1;
            }
            if j == start || b.get(j) != Some(&b'=') {
                return err(
                    j,
                    &format!("an attribute of <{name}> without a quoted value"),
                );
            }
            j += 1;
            let quote = match b.get(j) {
                Some(&q) if q == b'"' || q == b'\'' => q,
                _ => return err(j, &format!("an unquoted attribute value in <{name}>")),
            };
            let close = match b[j + 1..].iter().position(|&c| c == quote) {
                Some(p) => j + 1 + p,
                None => return err(j, &format!("an attribute value in <{name}> never closed")),
            };
            if b[j + 1..close].contains(&b'<') {
                return err(j, &format!("a '<' in an attribute value of <{name}>"));
            }
            j = close + 1;
        }
        i = j;
    }
    if let Some(open) = stack.last() {
        return err(
            b.len(),
            &format!("<{open}> is never closed (the text ends first)"),
        );
    }
    if roots == 0 {
        return Err("no element".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_well_formed_markup() {
        for ok in [
            "<svg xmlns=\"http://www.w3.org/2000/svg\"><g a='1'><text>a &amp; b &#8722; &#x3c;</text></g><rect/></svg>",
            "<?xml version=\"1.0\"?>\n<!-- c --><svg>\n</svg>\n",
            "<a><![CDATA[ <not a tag> ]]></a>",
        ] {
            check_well_formed(ok).unwrap_or_else(|e| panic!("{ok}: {e}"));
        }
    }

    #[test]
    fn refuses_what_a_browser_would_mangle() {
        for (bad, why) in [
            ("<svg><g></svg>", "</svg> closes <g>"),
            ("<svg><rect>", "<rect> is never closed"),
            ("<svg>a & b</svg>", "'&' that starts"),
            ("<svg width=10></svg>", "unquoted"),
            ("<svg></svg><svg></svg>", "second root"),
            ("<svg><text>1 < 2</text></svg>", "'<' that starts no tag"),
            ("text", "outside the root"),
            ("", "no element"),
            ("<svg><line x1=\"3", "never closed"),
        ] {
            let e = check_well_formed(bad).unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }
}
