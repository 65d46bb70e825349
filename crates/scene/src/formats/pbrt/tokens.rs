//! The tokens of a pbrt-v4 file: directive names, quoted strings, numbers and brackets,
//! each with its byte span; `#` starts a comment to the end of the line.

use std::ops::Range;

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A directive or a bare word (`true`, `false`).
    Word(String),
    Str(String),
    Num(f64),
    Open,
    Close,
}

#[derive(Clone, Debug)]
pub struct Token {
    pub tok: Tok,
    pub span: Range<usize>,
}

/// The tokens of `text`, or the span and message of the first that is malformed.
pub fn tokenize(text: &str) -> Result<Vec<Token>, (Range<usize>, String)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let start = i;
        match c {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'[' | b']' => {
                i += 1;
                let tok = if c == b'[' { Tok::Open } else { Tok::Close };
                out.push(Token { tok, span: start..i });
            }
            b'"' => {
                i += 1;
                let mut s = String::new();
                loop {
                    match bytes.get(i) {
                        None | Some(b'\n') => return Err((start..i, "a string that never ends".into())),
                        Some(b'"') => break,
                        Some(b'\\') => {
                            // The escaped character may be any UTF-8 character, not one byte.
                            let Some(next) = text[i + 1..].chars().next() else {
                                return Err((start..i, "a string that never ends".into()));
                            };
                            s.push(match next {
                                'n' => '\n',
                                't' => '\t',
                                c => c,
                            });
                            i += 1 + next.len_utf8();
                        }
                        Some(_) => {
                            let ch = text[i..].chars().next().expect("inside the text");
                            s.push(ch);
                            i += ch.len_utf8();
                        }
                    }
                }
                i += 1;
                out.push(Token {
                    tok: Tok::Str(s),
                    span: start..i,
                });
            }
            _ => {
                while i < bytes.len() && !matches!(bytes[i], b' ' | b'\t' | b'\r' | b'\n' | b'[' | b']' | b'"' | b'#') {
                    i += 1;
                }
                let word = &text[start..i];
                let first = word.as_bytes()[0];
                let tok = if first.is_ascii_digit() || matches!(first, b'-' | b'+' | b'.') {
                    match word.parse::<f64>() {
                        Ok(x) if x.is_finite() => Tok::Num(x),
                        _ => return Err((start..i, format!("`{word}` is not a number"))),
                    }
                } else {
                    Tok::Word(word.to_string())
                };
                out.push(Token { tok, span: start..i });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_strings_numbers_brackets_and_comments() {
        let toks = tokenize("Shape \"sphere\" # a comment \"not a string\"\n \"float radius\" [ -2.5e1 ]").unwrap();
        let kinds: Vec<Tok> = toks.iter().map(|t| t.tok.clone()).collect();
        assert_eq!(
            kinds,
            vec![
                Tok::Word("Shape".into()),
                Tok::Str("sphere".into()),
                Tok::Str("float radius".into()),
                Tok::Open,
                Tok::Num(-25.0),
                Tok::Close
            ]
        );
        assert_eq!(toks[1].span, 6..14);
        assert!(tokenize("Shape \"sphere").is_err());
        assert!(tokenize("Translate 1 2 3x").is_err());
    }
}
