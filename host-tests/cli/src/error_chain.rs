//! An error with its causes on one line, for the binaries' messages.
//!
//! The error types of this workspace's host side keep a cause out of their own message and
//! return it from [`Error::source`] instead, so printing the chain repeats nothing.

use std::error::Error;
use std::fmt;

/// Displays an error followed by each of its [`Error::source`]s, separated by `: `.
pub struct Chain<'a>(pub &'a (dyn Error + 'static));

impl fmt::Display for Chain<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)?;
        let mut cause = self.0.source();
        while let Some(c) = cause {
            write!(f, ": {c}")?;
            cause = c.source();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("cannot write out/metrics.json")]
    struct Outer(#[source] std::io::Error);

    #[test]
    fn prints_every_cause_once() {
        let e = Outer(std::io::Error::other("disk full"));
        assert_eq!(
            Chain(&e).to_string(),
            "cannot write out/metrics.json: disk full"
        );
        let alone = std::io::Error::other("disk full");
        assert_eq!(Chain(&alone).to_string(), "disk full");
    }
}
