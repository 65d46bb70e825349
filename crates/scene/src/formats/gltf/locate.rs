//! Where a glTF JSON path (`meshes[0].primitives[1].attributes["POSITION"]`, the form the
//! `gltf` crate's validation reports) points in the file's text, so that every error about
//! the document can name a line and column. A small scanner over the JSON text, not a
//! second parser: it only skips values to find the one the path names.

use std::ops::Range;

/// One step of a path: an object's member or an array's element.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

/// The steps of `path`; `None` if it is not of the form above.
fn steps(path: &str) -> Option<Vec<Step>> {
    let mut out = Vec::new();
    let mut rest = path;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("[\"") {
            let end = r.find("\"]")?;
            out.push(Step::Key(r[..end].to_string()));
            rest = &r[end + 2..];
        } else if let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']')?;
            out.push(Step::Index(r[..end].parse().ok()?));
            rest = &r[end + 1..];
        } else {
            let r = rest.strip_prefix('.').unwrap_or(rest);
            let end = r.find(['.', '[']).unwrap_or(r.len());
            out.push(Step::Key(r[..end].to_string()));
            rest = &r[end..];
        }
    }
    Some(out)
}

/// The byte span of the value `path` names in the JSON `text`: as deep as the path can be
/// followed (a member the file leaves out points at the object that should have it).
pub fn locate(text: &str, path: &str) -> Range<usize> {
    let b = text.as_bytes();
    let mut at = skip_ws(b, 0);
    for step in steps(path).unwrap_or_default() {
        let Some(next) = child(b, at, &step) else { break };
        at = next;
    }
    at..value_end(b, at).max(at)
}

fn skip_ws(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}

/// The end of the string starting at `i` (a quote), past its closing quote.
fn string_end(b: &[u8], mut i: usize) -> usize {
    i += 1;
    while i < b.len() {
        match b[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    b.len()
}

/// The end of the value starting at `i`.
fn value_end(b: &[u8], i: usize) -> usize {
    match b.get(i) {
        Some(b'"') => string_end(b, i),
        Some(b'{' | b'[') => {
            let mut depth = 0usize;
            let mut j = i;
            while j < b.len() {
                match b[j] {
                    b'"' => {
                        j = string_end(b, j);
                        continue;
                    }
                    b'{' | b'[' => depth += 1,
                    b'}' | b']' => {
                        depth -= 1;
                        if depth == 0 {
                            return j + 1;
                        }
                    }
                    _ => {}
                }
                j += 1;
            }
            b.len()
        }
        _ => {
            let mut j = i;
            while j < b.len() && !matches!(b[j], b',' | b'}' | b']') && !b[j].is_ascii_whitespace() {
                j += 1;
            }
            j
        }
    }
}

/// The start of the member or element `step` of the object or array at `i`.
fn child(b: &[u8], i: usize, step: &Step) -> Option<usize> {
    match (b.get(i)?, step) {
        (b'{', Step::Key(key)) => {
            let mut j = skip_ws(b, i + 1);
            while b.get(j) == Some(&b'"') {
                let name_end = string_end(b, j);
                let name = std::str::from_utf8(&b[j + 1..name_end.saturating_sub(1).max(j + 1)]).ok();
                let colon = skip_ws(b, name_end);
                if b.get(colon) != Some(&b':') {
                    return None;
                }
                let value = skip_ws(b, colon + 1);
                if name == Some(key.as_str()) {
                    return Some(value);
                }
                j = skip_ws(b, value_end(b, value));
                if b.get(j) != Some(&b',') {
                    return None;
                }
                j = skip_ws(b, j + 1);
            }
            None
        }
        (b'[', Step::Index(n)) => {
            let mut j = skip_ws(b, i + 1);
            for _ in 0..*n {
                if matches!(b.get(j), None | Some(b']')) {
                    return None;
                }
                j = skip_ws(b, value_end(b, j));
                if b.get(j) != Some(&b',') {
                    return None;
                }
                j = skip_ws(b, j + 1);
            }
            (!matches!(b.get(j), None | Some(b']'))).then_some(j)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_lead_to_their_values() {
        let text = r#"{ "asset": {"version": "2.0"},
  "meshes": [ {"primitives": [ {"attributes": {"NORMAL": 3, "POSITION": 7}, "indices": 0} ]},
              {"name": "a \"quoted\" ] name", "primitives": [ {"attributes": {"POSITION": [1, {"x": 2}]}} ]} ] }"#;
        let at = |path: &str| &text[locate(text, path)];
        assert_eq!(at(r#"meshes[0].primitives[0].attributes["POSITION"]"#), "7");
        assert_eq!(at("meshes[0].primitives[0].indices"), "0");
        assert_eq!(at("asset.version"), "\"2.0\"");
        assert_eq!(at("meshes[1].name"), r#""a \"quoted\" ] name""#);
        assert_eq!(at(r#"meshes[1].primitives[0].attributes["POSITION"][1].x"#), "2");
        assert_eq!(
            at(r#"meshes[1].primitives[0].attributes["POSITION"][1]"#),
            r#"{"x": 2}"#
        );
        // As deep as the path goes: a missing member points at its object.
        assert!(at("meshes[0].primitives[0].material").starts_with("{\"attributes\""));
        assert!(at("meshes[5]").starts_with("[ {\"primitives\""));
        // Malformed text or paths never panic.
        for cut in 0..text.len() {
            let _ = locate(&text[..cut], r#"meshes[1].primitives[0].attributes["POSITION"][1].x"#);
        }
        let _ = locate(text, "meshes[x");
        let _ = locate("", "a");
    }
}
