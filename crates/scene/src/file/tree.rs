//! The format-neutral document tree both scene formats are parsed into: values with
//! the byte offset they start at, so every later check can name a line and column.
//! TOML comes through `toml_edit` (which keeps spans), JSON through
//! [`super::json_tree`].

use crate::error::SceneError;

/// A value and the byte offset in the source text where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub value: Value,
    pub pos: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Array(Vec<Node>),
    /// Entries in source order.
    Table(Vec<Entry>),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub key: String,
    /// Byte offset of the key (unknown-field errors point at it).
    pub key_pos: usize,
    pub node: Node,
}

impl Value {
    /// The type's name in messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Bool(_) => "a boolean",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a number",
            Value::Str(_) => "a string",
            Value::Array(_) => "an array",
            Value::Table(_) => "a table",
        }
    }
}

/// Parses TOML into a [`Node`] tree with positions.
pub fn parse_toml(text: &str) -> Result<Node, SceneError> {
    let doc = toml_edit::ImDocument::parse(text).map_err(|e| {
        let mut err = SceneError::input("", format!("TOML syntax error: {}", e.message().trim()));
        if let Some(span) = e.span() {
            let (l, c) = line_col(text, span.start);
            err = err.at(l, c);
        }
        err
    })?;
    Ok(toml_table(doc.as_table(), 0))
}

fn toml_table(table: &toml_edit::Table, fallback: usize) -> Node {
    let pos = table.span().map(|s| s.start).unwrap_or(fallback);
    let mut entries = Vec::new();
    for (key, item) in table.iter() {
        let key_pos = table
            .key(key)
            .and_then(|k| k.span())
            .map(|s| s.start)
            .unwrap_or(pos);
        if let Some(node) = toml_item(item, key_pos) {
            entries.push(Entry {
                key: key.to_string(),
                key_pos,
                node,
            });
        }
    }
    Node {
        value: Value::Table(entries),
        pos,
    }
}

fn toml_item(item: &toml_edit::Item, fallback: usize) -> Option<Node> {
    Some(match item {
        toml_edit::Item::None => return None,
        toml_edit::Item::Value(v) => toml_value(v, fallback),
        toml_edit::Item::Table(t) => toml_table(t, fallback),
        toml_edit::Item::ArrayOfTables(a) => {
            let pos = a.span().map(|s| s.start).unwrap_or(fallback);
            Node {
                value: Value::Array(a.iter().map(|t| toml_table(t, pos)).collect()),
                pos,
            }
        }
    })
}

fn toml_value(v: &toml_edit::Value, fallback: usize) -> Node {
    use toml_edit::Value as V;
    let pos = v.span().map(|s| s.start).unwrap_or(fallback);
    let value = match v {
        V::String(s) => Value::Str(s.value().clone()),
        V::Integer(i) => Value::Int(*i.value()),
        V::Float(f) => Value::Float(*f.value()),
        V::Boolean(b) => Value::Bool(*b.value()),
        V::Datetime(d) => Value::Str(d.value().to_string()),
        V::Array(a) => Value::Array(a.iter().map(|x| toml_value(x, pos)).collect()),
        V::InlineTable(t) => {
            let mut entries = Vec::new();
            for (key, val) in t.iter() {
                let key_pos = t
                    .key(key)
                    .and_then(|k| k.span())
                    .map(|s| s.start)
                    .unwrap_or(pos);
                entries.push(Entry {
                    key: key.to_string(),
                    key_pos,
                    node: toml_value(val, key_pos),
                });
            }
            Value::Table(entries)
        }
    };
    Node { value, pos }
}

/// 1-based line and column (in characters) of byte offset `pos`.
pub fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let pos = pos.min(text.len());
    let before = &text[..floor_char_boundary(text, pos)];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map(|i| i + 1).unwrap_or(0);
    let col = before[line_start..].chars().count() + 1;
    (line, col)
}

fn floor_char_boundary(text: &str, mut pos: usize) -> usize {
    while !text.is_char_boundary(pos) {
        pos -= 1;
    }
    pos
}

/// Building trees in code (the importers of other scene formats build Irradia's
/// schema this way): every node carries the byte offset, in the source text, of the
/// thing it was made from, so later errors still point into that file.
impl Node {
    pub fn new(value: impl Into<Value>, pos: usize) -> Node {
        let mut value = value.into();
        if let Value::Array(items) = &mut value {
            // Numbers made into a list without a place of their own take the list's.
            for item in items.iter_mut().filter(|i| i.pos == 0) {
                item.pos = pos;
            }
        }
        Node { value, pos }
    }

    /// An empty table at `pos`.
    pub fn table(pos: usize) -> Node {
        Node {
            value: Value::Table(Vec::new()),
            pos,
        }
    }

    /// Sets `key` of a table (replacing an earlier value of the same key), the key
    /// itself located at the value's position. Panics when `self` is not a table.
    pub fn set(&mut self, key: &str, node: Node) -> &mut Node {
        let Value::Table(entries) = &mut self.value else {
            panic!("Node::set on {}", self.value.type_name());
        };
        let entry = Entry {
            key: key.to_string(),
            key_pos: node.pos,
            node,
        };
        match entries.iter().position(|e| e.key == key) {
            Some(i) => entries[i] = entry,
            None => entries.push(entry),
        }
        self
    }

    /// Sets `key` to `value`, located at `pos`.
    pub fn put(&mut self, key: &str, value: impl Into<Value>, pos: usize) -> &mut Node {
        self.set(key, Node::new(value, pos))
    }

    /// The value of `key` in a table.
    pub fn get(&self, key: &str) -> Option<&Node> {
        match &self.value {
            Value::Table(entries) => entries.iter().find(|e| e.key == key).map(|e| &e.node),
            _ => None,
        }
    }

    /// The value of `key` in a table, mutable.
    pub fn get_mut(&mut self, key: &str) -> Option<&mut Node> {
        match &mut self.value {
            Value::Table(entries) => entries
                .iter_mut()
                .find(|e| e.key == key)
                .map(|e| &mut e.node),
            _ => None,
        }
    }

    /// Appends `node` to the array under `key`, creating the array when absent.
    pub fn push(&mut self, key: &str, node: Node) -> &mut Node {
        if self.get(key).is_none() {
            let pos = node.pos;
            self.set(key, Node::new(Value::Array(Vec::new()), pos));
        }
        match &mut self.get_mut(key).expect("just set").value {
            Value::Array(items) => items.push(node),
            other => panic!("Node::push onto {}", other.type_name()),
        }
        self
    }

    /// The same tree with every position set to 0 and every table's keys sorted (a
    /// table's key order carries no meaning): two trees with the same content are equal.
    pub fn canonical(&self) -> Node {
        let value = match &self.value {
            Value::Array(items) => Value::Array(items.iter().map(Node::canonical).collect()),
            Value::Table(entries) => {
                let mut entries: Vec<Entry> = entries
                    .iter()
                    .map(|e| Entry {
                        key: e.key.clone(),
                        key_pos: 0,
                        node: e.node.canonical(),
                    })
                    .collect();
                entries.sort_by(|a, b| a.key.cmp(&b.key));
                Value::Table(entries)
            }
            v => v.clone(),
        };
        Node { value, pos: 0 }
    }
}

impl From<bool> for Value {
    fn from(v: bool) -> Value {
        Value::Bool(v)
    }
}
impl From<i64> for Value {
    fn from(v: i64) -> Value {
        Value::Int(v)
    }
}
impl From<u32> for Value {
    fn from(v: u32) -> Value {
        Value::Int(v as i64)
    }
}
impl From<f64> for Value {
    fn from(v: f64) -> Value {
        Value::Float(v)
    }
}
impl From<f32> for Value {
    fn from(v: f32) -> Value {
        Value::Float(v as f64)
    }
}
impl From<&str> for Value {
    fn from(v: &str) -> Value {
        Value::Str(v.to_string())
    }
}
impl From<String> for Value {
    fn from(v: String) -> Value {
        Value::Str(v)
    }
}
impl<const N: usize> From<[f64; N]> for Value {
    /// A fixed-size list of numbers (a vector, a colour, a matrix row).
    fn from(v: [f64; N]) -> Value {
        Value::Array(v.iter().map(|x| Node::new(*x, 0)).collect())
    }
}
impl From<Vec<Node>> for Value {
    fn from(v: Vec<Node>) -> Value {
        Value::Array(v)
    }
}
