//! What the audit reports: a finding, located by increment, node, body and element.

/// Something the audit found wrong, located.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// The increment it is in.
    pub increment: usize,
    /// The node it concerns, by user id.
    pub node: Option<u32>,
    /// The body (or obstacle) it concerns.
    pub body: Option<String>,
    /// The element it concerns (index).
    pub element: Option<usize>,
    /// What is wrong, in a sentence.
    pub what: String,
}

impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "increment {}: {}", self.increment, self.what)
    }
}
