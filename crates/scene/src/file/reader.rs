//! Typed reading of the positioned document tree: every accessor knows the field's
//! path (`objects[2].radius`) and position, so every error names file, line and field.
//! Tables remember which keys the schema asked for; [`Table::finish`] rejects the rest
//! (unknown fields) and suggests the closest valid name.

use super::tree::{line_col, Entry, Node, Value};
use crate::error::SceneError;
use glam::Vec3;
use irradia_core::Rgb;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// The document being read: its text (for line numbers), the name used in messages,
/// and the folder relative paths are resolved against.
pub struct Doc<'a> {
    pub text: &'a str,
    pub file: Option<PathBuf>,
    pub dir: PathBuf,
}

impl Doc<'_> {
    /// A bad-input error at byte offset `pos` for `field`.
    pub fn error_at(&self, pos: usize, field: &str, message: impl Into<String>) -> SceneError {
        let (l, c) = line_col(self.text, pos);
        let mut e = SceneError::input(field, message).at(l, c);
        e.file = self.file.clone();
        e
    }

    /// Whether this is a built-in scene (its files are embedded: [`crate::builtin::asset`]).
    pub fn is_builtin(&self) -> bool {
        self.file
            .as_ref()
            .is_some_and(|f| f.to_string_lossy().starts_with("builtin:"))
    }

    /// Resolves a path written in the scene relative to the scene file's folder.
    pub fn resolve(&self, p: &str) -> PathBuf {
        let p = Path::new(p);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.dir.join(p)
        }
    }
}

/// One value of the document with its field path.
#[derive(Clone)]
pub struct Val<'d> {
    pub doc: &'d Doc<'d>,
    pub node: &'d Node,
    pub path: String,
}

pub type Error = SceneError;
pub type Result<T> = std::result::Result<T, SceneError>;

impl<'d> Val<'d> {
    pub fn root(doc: &'d Doc<'d>, node: &'d Node) -> Self {
        Val {
            doc,
            node,
            path: String::new(),
        }
    }

    /// An error about this value.
    pub fn err(&self, message: impl Into<String>) -> SceneError {
        self.doc.error_at(self.node.pos, &self.path, message)
    }

    fn wrong_type(&self, expected: &str) -> SceneError {
        self.err(format!(
            "expected {expected}, found {}",
            self.node.value.type_name()
        ))
    }

    pub fn is_table(&self) -> bool {
        matches!(self.node.value, Value::Table(_))
    }
    pub fn is_array(&self) -> bool {
        matches!(self.node.value, Value::Array(_))
    }
    pub fn is_number(&self) -> bool {
        matches!(self.node.value, Value::Int(_) | Value::Float(_))
    }
    pub fn is_str(&self) -> bool {
        matches!(self.node.value, Value::Str(_))
    }

    /// A finite number (integers are accepted).
    pub fn f64(&self) -> Result<f64> {
        let v = match self.node.value {
            Value::Int(i) => i as f64,
            Value::Float(f) => f,
            _ => return Err(self.wrong_type("a number")),
        };
        if !v.is_finite() {
            return Err(self.err(format!("must be a finite number (got {v})")));
        }
        Ok(v)
    }

    /// A finite number that fits in f32.
    pub fn f32(&self) -> Result<f32> {
        let v = self.f64()?;
        let f = v as f32;
        if !f.is_finite() {
            return Err(self.err(format!("is too large (got {v})")));
        }
        Ok(f)
    }

    pub fn positive(&self) -> Result<f32> {
        let v = self.f32()?;
        if v <= 0.0 {
            return Err(self.err(format!("must be positive (got {v})")));
        }
        Ok(v)
    }

    pub fn non_negative(&self) -> Result<f32> {
        let v = self.f32()?;
        if v < 0.0 {
            return Err(self.err(format!("must not be negative (got {v})")));
        }
        Ok(v)
    }

    /// A number in `[lo, hi]`.
    pub fn in_range(&self, lo: f32, hi: f32) -> Result<f32> {
        let v = self.f32()?;
        if !(lo..=hi).contains(&v) {
            return Err(self.err(format!("must be between {lo} and {hi} (got {v})")));
        }
        Ok(v)
    }

    pub fn u32(&self) -> Result<u32> {
        match self.node.value {
            Value::Int(i) if (0..=u32::MAX as i64).contains(&i) => Ok(i as u32),
            Value::Int(i) => Err(self.err(format!(
                "must be a whole number from 0 to {} (got {i})",
                u32::MAX
            ))),
            _ => Err(self.wrong_type("an integer")),
        }
    }

    /// A whole number of at least 1.
    pub fn count(&self) -> Result<u32> {
        let v = self.u32()?;
        if v == 0 {
            return Err(self.err("must be at least 1 (got 0)"));
        }
        Ok(v)
    }

    pub fn bool(&self) -> Result<bool> {
        match self.node.value {
            Value::Bool(b) => Ok(b),
            _ => Err(self.wrong_type("true or false")),
        }
    }

    pub fn str(&self) -> Result<&'d str> {
        match &self.node.value {
            Value::Str(s) => Ok(s),
            _ => Err(self.wrong_type("a string")),
        }
    }

    /// A string that must be one of `choices`.
    pub fn choice(&self, choices: &[&'static str]) -> Result<&'static str> {
        let s = self.str()?;
        match choices.iter().find(|c| **c == s) {
            Some(c) => Ok(c),
            None => Err(self.err(unknown_name_message("value", s, choices))),
        }
    }

    pub fn array(&self) -> Result<Vec<Val<'d>>> {
        match &self.node.value {
            Value::Array(items) => Ok(items
                .iter()
                .enumerate()
                .map(|(i, node)| Val {
                    doc: self.doc,
                    node,
                    path: format!("{}[{i}]", self.path),
                })
                .collect()),
            _ => Err(self.wrong_type("an array")),
        }
    }

    /// An array of exactly `n` numbers.
    pub fn numbers(&self, n: usize) -> Result<Vec<f32>> {
        let items = self.array()?;
        if items.len() != n {
            return Err(self.err(format!(
                "expected an array of {n} numbers, found {} elements",
                items.len()
            )));
        }
        items.iter().map(|v| v.f32()).collect()
    }

    pub fn vec3(&self) -> Result<Vec3> {
        if !self.is_array() {
            return Err(self.wrong_type("an array of 3 numbers [x, y, z]"));
        }
        let v = self.numbers(3)?;
        Ok(Vec3::new(v[0], v[1], v[2]))
    }

    /// A vector of non-zero length (a direction or an axis).
    pub fn direction(&self) -> Result<Vec3> {
        let v = self.vec3()?;
        if v.length_squared() == 0.0 || !v.normalize().is_finite() {
            return Err(self.err("must be a non-zero vector"));
        }
        Ok(v)
    }

    /// A colour: one number (grey) or `[r, g, b]`, non-negative.
    pub fn rgb(&self) -> Result<Rgb> {
        let c = if self.is_number() {
            Rgb::splat(self.f32()?)
        } else if self.is_array() {
            let v = self.numbers(3)?;
            Rgb::new(v[0], v[1], v[2])
        } else {
            return Err(self.wrong_type("a colour (a number or [r, g, b])"));
        };
        if c.r < 0.0 || c.g < 0.0 || c.b < 0.0 {
            return Err(self.err(format!(
                "colour components must not be negative (got [{}, {}, {}])",
                c.r, c.g, c.b
            )));
        }
        Ok(c)
    }

    pub fn table(&self) -> Result<Table<'d>> {
        match &self.node.value {
            Value::Table(entries) => Ok(Table {
                val: self.clone(),
                entries,
                known: RefCell::new(Vec::new()),
            }),
            _ => Err(self.wrong_type("a table")),
        }
    }
}

/// A table being read; keys not asked for are reported by [`Table::finish`].
pub struct Table<'d> {
    pub val: Val<'d>,
    entries: &'d [Entry],
    known: RefCell<Vec<&'static str>>,
}

impl<'d> Table<'d> {
    pub fn path(&self) -> &str {
        &self.val.path
    }

    pub fn err(&self, message: impl Into<String>) -> SceneError {
        self.val.err(message)
    }

    fn child_path(&self, key: &str) -> String {
        if self.val.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.val.path)
        }
    }

    /// The value of `key`, if present (marks `key` as part of the schema).
    pub fn get(&self, key: &'static str) -> Option<Val<'d>> {
        self.known.borrow_mut().push(key);
        self.entries.iter().find(|e| e.key == key).map(|e| Val {
            doc: self.val.doc,
            node: &e.node,
            path: self.child_path(key),
        })
    }

    /// Whether `key` is present (marks it as known).
    pub fn has(&self, key: &'static str) -> bool {
        self.get(key).is_some()
    }

    /// The value of a required `key`.
    pub fn req(&self, key: &'static str) -> Result<Val<'d>> {
        self.get(key).ok_or_else(|| {
            // A misspelt key is the likelier story than a forgotten one: say so.
            if let Some(e) = self
                .entries
                .iter()
                .find(|e| e.key != key && closest(&e.key, &[key]).is_some())
            {
                return self.val.doc.error_at(
                    e.key_pos,
                    &self.child_path(&e.key),
                    format!("unknown field `{}`; did you mean `{key}`?", e.key),
                );
            }
            self.val.doc.error_at(
                self.val.node.pos,
                &self.child_path(key),
                "missing required field",
            )
        })
    }

    /// Entries in source order (for tables of named things: materials); marks all known.
    pub fn entries(&self) -> Vec<(&'d str, Val<'d>)> {
        self.entries
            .iter()
            .map(|e| {
                (
                    e.key.as_str(),
                    Val {
                        doc: self.val.doc,
                        node: &e.node,
                        path: self.child_path(&e.key),
                    },
                )
            })
            .collect()
    }

    pub fn f32_or(&self, key: &'static str, default: f32) -> Result<f32> {
        self.get(key).map_or(Ok(default), |v| v.f32())
    }
    pub fn non_negative_or(&self, key: &'static str, default: f32) -> Result<f32> {
        self.get(key).map_or(Ok(default), |v| v.non_negative())
    }
    pub fn positive_or(&self, key: &'static str, default: f32) -> Result<f32> {
        self.get(key).map_or(Ok(default), |v| v.positive())
    }
    pub fn u32_or(&self, key: &'static str, default: u32) -> Result<u32> {
        self.get(key).map_or(Ok(default), |v| v.u32())
    }
    pub fn count_or(&self, key: &'static str, default: u32) -> Result<u32> {
        self.get(key).map_or(Ok(default), |v| v.count())
    }
    pub fn bool_or(&self, key: &'static str, default: bool) -> Result<bool> {
        self.get(key).map_or(Ok(default), |v| v.bool())
    }
    pub fn rgb_or(&self, key: &'static str, default: Rgb) -> Result<Rgb> {
        self.get(key).map_or(Ok(default), |v| v.rgb())
    }
    pub fn vec3_or(&self, key: &'static str, default: Vec3) -> Result<Vec3> {
        self.get(key).map_or(Ok(default), |v| v.vec3())
    }

    /// Rejects keys the schema did not ask for (suggesting the closest valid one) and
    /// keys given twice (JSON allows that syntactically).
    pub fn finish(&self) -> Result<()> {
        let known = self.known.borrow();
        for (i, e) in self.entries.iter().enumerate() {
            let field = self.child_path(&e.key);
            if self.entries[..i].iter().any(|p| p.key == e.key) {
                return Err(self
                    .val
                    .doc
                    .error_at(e.key_pos, &field, "field given more than once"));
            }
            if !known.iter().any(|k| *k == e.key) {
                let mut valid: Vec<&str> = known.to_vec();
                valid.sort_unstable();
                valid.dedup();
                return Err(self.val.doc.error_at(
                    e.key_pos,
                    &field,
                    unknown_name_message("field", &e.key, &valid),
                ));
            }
        }
        Ok(())
    }
}

/// "unknown field `radus`; did you mean `radius`? (valid: ...)".
pub fn unknown_name_message(what: &str, got: &str, valid: &[&str]) -> String {
    let mut msg = format!("unknown {what} `{got}`");
    if let Some(best) = closest(got, valid) {
        msg += &format!("; did you mean `{best}`?");
    }
    if !valid.is_empty() {
        msg += &format!(" (valid: {})", valid.join(", "));
    }
    msg
}

/// The valid name closest to `got` by edit distance, if it is close enough to be a typo.
pub fn closest<'a>(got: &str, valid: &[&'a str]) -> Option<&'a str> {
    let got_l = got.to_lowercase();
    valid
        .iter()
        .map(|v| (levenshtein(&got_l, &v.to_lowercase()), *v))
        .filter(|(d, v)| *d <= (v.len().max(got.len()) / 3).max(2))
        .min_by_key(|(d, _)| *d)
        .map(|(_, v)| v)
}

fn levenshtein(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_pick_the_nearest_name() {
        assert_eq!(closest("radus", &["radius", "center"]), Some("radius"));
        assert_eq!(closest("xyzzy", &["radius", "center"]), None);
        assert_eq!(levenshtein("kitten", "sitting"), 3);
    }
}
