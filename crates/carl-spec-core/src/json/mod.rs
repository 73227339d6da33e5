//! JSON with source positions: a span-keeping parser, JSON-pointer lookup and line/column mapping.

mod lines;
mod parse;

use std::ops::Range;

pub use lines::LineIndex;
pub use parse::{MAX_DEPTH, ParseError, parse};

/// A JSON value with the byte span it occupies in the source.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    pub span: Range<usize>,
    pub kind: NodeKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum NodeKind {
    Null,
    Bool(bool),
    /// `int` is set when the literal had no fraction or exponent (and fits i128).
    Number {
        value: f64,
        int: Option<i128>,
    },
    String(String),
    Array(Vec<Node>),
    /// Members in source order; duplicate keys are kept so the validator can report them.
    Object(Vec<Member>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    pub key: String,
    pub key_span: Range<usize>,
    pub value: Node,
}

impl Node {
    /// The member of an object by key (the last one wins, as in serde_json).
    pub fn get(&self, key: &str) -> Option<&Node> {
        self.member(key).map(|m| &m.value)
    }

    pub fn member(&self, key: &str) -> Option<&Member> {
        match &self.kind {
            NodeKind::Object(members) => members.iter().rev().find(|m| m.key == key),
            _ => None,
        }
    }

    pub fn index(&self, i: usize) -> Option<&Node> {
        match &self.kind {
            NodeKind::Array(items) => items.get(i),
            _ => None,
        }
    }

    pub fn as_str(&self) -> Option<&str> {
        match &self.kind {
            NodeKind::String(s) => Some(s),
            _ => None,
        }
    }

    /// Resolve an RFC 6901 JSON pointer (`/features/3/default`).
    pub fn pointer(&self, pointer: &str) -> Option<&Node> {
        self.pointer_target(pointer).map(|(node, _)| node)
    }

    /// Resolve a pointer, also returning the span of the key when the last step is an object member
    /// (errors about a property's name underline the key, errors about its value the value).
    pub fn pointer_target(&self, pointer: &str) -> Option<(&Node, Option<Range<usize>>)> {
        if pointer.is_empty() {
            return Some((self, None));
        }
        let mut node = self;
        let mut key_span = None;
        for raw in pointer.strip_prefix('/')?.split('/') {
            let token = raw.replace("~1", "/").replace("~0", "~");
            match &node.kind {
                NodeKind::Object(_) => {
                    let m = node.member(&token)?;
                    key_span = Some(m.key_span.clone());
                    node = &m.value;
                }
                NodeKind::Array(items) => {
                    node = items.get(token.parse::<usize>().ok()?)?;
                    key_span = None;
                }
                _ => return None,
            }
        }
        Some((node, key_span))
    }

    /// Convert to a serde_json value (integers stay integers so `u64` fields deserialize).
    pub fn to_value(&self) -> serde_json::Value {
        use serde_json::Value as V;
        match &self.kind {
            NodeKind::Null => V::Null,
            NodeKind::Bool(b) => V::Bool(*b),
            NodeKind::Number { value, int } => match int {
                Some(i) if *i >= 0 && *i <= u64::MAX as i128 => V::from(*i as u64),
                Some(i) if *i < 0 && *i >= i64::MIN as i128 => V::from(*i as i64),
                _ => serde_json::Number::from_f64(*value).map_or(V::Null, V::Number),
            },
            NodeKind::String(s) => V::String(s.clone()),
            NodeKind::Array(items) => V::Array(items.iter().map(Node::to_value).collect()),
            NodeKind::Object(members) => {
                V::Object(members.iter().map(|m| (m.key.clone(), m.value.to_value())).collect())
            }
        }
    }
}

/// Escape one reference token for a JSON pointer.
pub fn escape_token(token: &str) -> String {
    token.replace('~', "~0").replace('/', "~1")
}

#[cfg(test)]
mod tests;
