//! pbrt-v4's tokens: bare words (directive names, numbers, `true`/`false`), quoted
//! strings, `[` and `]`; `#` starts a comment to the end of the line. Every token keeps
//! the byte offset it starts at, so every later error can name its line and column.

/// One token and the byte offset of its first character.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub kind: Kind,
    pub pos: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// A bare word: a directive name, a number, `true`, `false`.
    Word(String),
    /// A quoted string, its escapes resolved.
    Str(String),
    Open,
    Close,
}

/// A lexical error: what is wrong and the byte offset where.
#[derive(Clone, Debug, PartialEq)]
pub struct LexError {
    pub pos: usize,
    pub message: String,
}

/// Splits `text` into tokens.
pub fn tokenize(text: &str) -> Result<Vec<Token>, LexError> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c => i += 1,
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'[' => {
                out.push(Token {
                    kind: Kind::Open,
                    pos: i,
                });
                i += 1;
            }
            b']' => {
                out.push(Token {
                    kind: Kind::Close,
                    pos: i,
                });
                i += 1;
            }
            b'"' => {
                let start = i;
                i += 1;
                let mut s = String::new();
                loop {
                    let Some(ch) = text[i..].chars().next() else {
                        return Err(LexError {
                            pos: start,
                            message: "unterminated string (no closing \")".into(),
                        });
                    };
                    match ch {
                        '"' => {
                            i += 1;
                            break;
                        }
                        '\n' => {
                            return Err(LexError {
                                pos: start,
                                message: "unterminated string (a newline before the closing \")"
                                    .into(),
                            })
                        }
                        '\\' => {
                            let Some(e) = text[i + 1..].chars().next() else {
                                return Err(LexError {
                                    pos: start,
                                    message: "unterminated string (no closing \")".into(),
                                });
                            };
                            s.push(match e {
                                'n' => '\n',
                                't' => '\t',
                                'r' => '\r',
                                'b' => '\u{8}',
                                'f' => '\u{c}',
                                other => other,
                            });
                            i += 1 + e.len_utf8();
                        }
                        other => {
                            s.push(other);
                            i += other.len_utf8();
                        }
                    }
                }
                out.push(Token {
                    kind: Kind::Str(s),
                    pos: start,
                });
            }
            _ => {
                let start = i;
                while i < bytes.len()
                    && !matches!(
                        bytes[i],
                        b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c | b'"' | b'[' | b']' | b'#'
                    )
                {
                    i += 1;
                }
                // Non-ASCII bytes are part of the word; the slice ends on an ASCII byte
                // or at the end, so it is on a character boundary.
                out.push(Token {
                    kind: Kind::Word(text[start..i].to_string()),
                    pos: start,
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_strings_brackets_and_comments() {
        let t = tokenize("Shape \"sphere\" # c\n \"float radius\" [ 2.5 ]").unwrap();
        let kinds: Vec<Kind> = t.iter().map(|t| t.kind.clone()).collect();
        assert_eq!(
            kinds,
            vec![
                Kind::Word("Shape".into()),
                Kind::Str("sphere".into()),
                Kind::Str("float radius".into()),
                Kind::Open,
                Kind::Word("2.5".into()),
                Kind::Close
            ]
        );
        assert_eq!(t[2].pos, 20);
    }

    #[test]
    fn unterminated_string_is_an_error() {
        assert_eq!(tokenize("Shape \"sph").unwrap_err().pos, 6);
        assert!(tokenize("\"a\\").is_err());
    }
}
