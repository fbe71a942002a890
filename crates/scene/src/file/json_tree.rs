//! JSON into the positioned [`Node`] tree. `serde_json` first checks the syntax (its
//! messages carry line and column); a small scanner then walks the now-valid text to
//! record where every value and key starts, delegating string and number decoding back
//! to `serde_json` so both agree exactly.

use super::tree::{line_col, Entry, Node, Value};
use crate::error::SceneError;

pub fn parse_json(text: &str) -> Result<Node, SceneError> {
    // A number too large for f64 (`1e999`) is valid JSON syntax that serde_json refuses;
    // the scanner reads it as an infinity so that validation names its field ("must be
    // finite"), as it does for TOML's `inf`.
    let out_of_range = |e: &serde_json::Error| e.to_string().starts_with("number out of range");
    match serde_json::from_str::<serde_json::Value>(text) {
        Err(e) if !out_of_range(&e) => {
            let full = e.to_string();
            // serde_json appends " at line L column C"; we print the position ourselves.
            let message = match full.rfind(" at line ") {
                Some(i) => full[..i].to_string(),
                None => full,
            };
            let mut err = SceneError::input("", format!("JSON syntax error: {message}"));
            if e.line() > 0 {
                err = err.at(e.line(), e.column().max(1));
            }
            return Err(err);
        }
        _ => {}
    }
    let mut s = Scanner { text, pos: 0 };
    s.value().map_err(|m| {
        let (l, c) = line_col(text, s.pos);
        SceneError::input("", format!("JSON: {m}")).at(l, c)
    })
}

struct Scanner<'a> {
    text: &'a str,
    pos: usize,
}

impl Scanner<'_> {
    fn skip_ws(&mut self) {
        let b = self.text.as_bytes();
        while self.pos < b.len() && matches!(b[self.pos], b' ' | b'\t' | b'\n' | b'\r') {
            self.pos += 1;
        }
    }

    fn peek(&self) -> u8 {
        self.text.as_bytes().get(self.pos).copied().unwrap_or(0)
    }

    fn expect(&mut self, c: u8) -> Result<(), String> {
        self.skip_ws();
        if self.peek() == c {
            self.pos += 1;
            Ok(())
        } else {
            Err(format!("expected `{}`", c as char))
        }
    }

    /// The end of the string literal starting at `self.pos` (which is at the quote).
    fn string(&mut self) -> Result<String, String> {
        let b = self.text.as_bytes();
        let start = self.pos;
        let mut i = start + 1;
        while i < b.len() {
            match b[i] {
                b'\\' => i += 2,
                b'"' => break,
                _ => i += 1,
            }
        }
        self.pos = (i + 1).min(b.len());
        serde_json::from_str::<String>(&self.text[start..self.pos]).map_err(|e| e.to_string())
    }

    fn value(&mut self) -> Result<Node, String> {
        self.skip_ws();
        let pos = self.pos;
        let value = match self.peek() {
            b'{' => {
                self.pos += 1;
                let mut entries = Vec::new();
                self.skip_ws();
                if self.peek() == b'}' {
                    self.pos += 1;
                } else {
                    loop {
                        self.skip_ws();
                        let key_pos = self.pos;
                        let key = self.string()?;
                        self.expect(b':')?;
                        let node = self.value()?;
                        entries.push(Entry { key, key_pos, node });
                        self.skip_ws();
                        match self.peek() {
                            b',' => self.pos += 1,
                            b'}' => {
                                self.pos += 1;
                                break;
                            }
                            _ => return Err("expected `,` or `}`".into()),
                        }
                    }
                }
                Value::Table(entries)
            }
            b'[' => {
                self.pos += 1;
                let mut items = Vec::new();
                self.skip_ws();
                if self.peek() == b']' {
                    self.pos += 1;
                } else {
                    loop {
                        items.push(self.value()?);
                        self.skip_ws();
                        match self.peek() {
                            b',' => self.pos += 1,
                            b']' => {
                                self.pos += 1;
                                break;
                            }
                            _ => return Err("expected `,` or `]`".into()),
                        }
                    }
                }
                Value::Array(items)
            }
            b'"' => Value::Str(self.string()?),
            b't' if self.text[pos..].starts_with("true") => {
                self.pos += 4;
                Value::Bool(true)
            }
            b'f' if self.text[pos..].starts_with("false") => {
                self.pos += 5;
                Value::Bool(false)
            }
            b'n' if self.text[pos..].starts_with("null") => {
                return Err("null is not a valid value here".into());
            }
            _ => {
                let b = self.text.as_bytes();
                let mut i = pos;
                while i < b.len() && matches!(b[i], b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9')
                {
                    i += 1;
                }
                self.pos = i;
                let lit = &self.text[pos..i];
                if lit.is_empty() {
                    return Err("expected a value".into());
                }
                if let Ok(v) = lit.parse::<i64>() {
                    Value::Int(v)
                } else {
                    let v = match serde_json::from_str::<f64>(lit) {
                        Ok(v) => v,
                        // Out of range (the only error left after the syntax check):
                        // Rust's parser rounds it to an infinity (or zero).
                        Err(e) => lit.parse::<f64>().map_err(|_| e.to_string())?,
                    };
                    Value::Float(v)
                }
            }
        };
        Ok(Node { value, pos })
    }
}
