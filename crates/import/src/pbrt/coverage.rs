//! What a pbrt file uses and how the importer treats each use: supported, warned
//! (imported with an approximation or left out, with a warning) or refused (an error).

use std::collections::BTreeMap;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Supported,
    Warned,
    Refused,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Supported => "supported",
            Status::Warned => "warned",
            Status::Refused => "refused",
        }
    }
}

/// Counts per (category, name) and status: `("shape", "plymesh") → {supported: 12}`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coverage {
    pub counts: BTreeMap<(String, String), BTreeMap<Status, usize>>,
    /// Errors met (the survey goes on after each), as `line:col: message`.
    pub errors: Vec<String>,
}

impl Coverage {
    pub fn add(&mut self, category: &str, name: &str, status: Status) {
        *self
            .counts
            .entry((category.to_string(), name.to_string()))
            .or_default()
            .entry(status)
            .or_default() += 1;
    }

    /// Adds another file's counts.
    pub fn merge(&mut self, other: &Coverage) {
        for (k, m) in &other.counts {
            let e = self.counts.entry(k.clone()).or_default();
            for (s, n) in m {
                *e.entry(*s).or_default() += n;
            }
        }
        self.errors.extend(other.errors.iter().cloned());
    }

    /// How often `(category, name)` was seen, all statuses together.
    pub fn total(&self, category: &str, name: &str) -> usize {
        self.counts
            .get(&(category.to_string(), name.to_string()))
            .map_or(0, |m| m.values().sum())
    }
}
