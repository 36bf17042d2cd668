//! What a log reader found wrong but could read past (skipped records, garbage, a cut): one
//! remark per kind, with the byte offset of the first occurrence and a count, so that a log
//! with a million bad records gives one line, not a million.

/// Remarks gathered while reading, in the order their kinds first occurred.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Issues {
    items: Vec<Issue>,
}

/// One kind of remark.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Issue {
    /// Which kind (a fixed key, so that repeats are counted, not listed).
    pub key: &'static str,
    /// Byte offset of the first occurrence.
    pub offset: u64,
    /// How many times it occurred.
    pub count: u64,
    /// What was wrong and what the reader did, of the first occurrence (short; never a
    /// large excerpt of the input).
    pub message: String,
}

impl Issues {
    /// Records one occurrence of `key` at `offset`; `message` is built only for the first.
    pub fn add(&mut self, key: &'static str, offset: u64, message: impl FnOnce() -> String) {
        if let Some(i) = self.items.iter_mut().find(|i| i.key == key) {
            i.count = i.count.saturating_add(1);
        } else {
            self.items.push(Issue {
                key,
                offset,
                count: 1,
                message: message(),
            });
        }
    }

    /// The remarks.
    pub fn items(&self) -> &[Issue] {
        &self.items
    }

    /// Whether a remark of kind `key` was made.
    pub fn has(&self, key: &str) -> bool {
        self.items.iter().any(|i| i.key == key)
    }

    /// The remarks as notes for the user, each naming `file`.
    pub fn notes(&self, file: &str) -> Vec<String> {
        self.items
            .iter()
            .map(|i| format!("{file}: {}", i.describe()))
            .collect()
    }

    /// The first remark, described (for an error that may stem from it).
    pub fn first(&self) -> Option<String> {
        self.items.first().map(Issue::describe)
    }
}

impl Issue {
    /// What happened, where, and how often.
    pub fn describe(&self) -> String {
        if self.key == TRUNCATED {
            format!(
                "the log is truncated at byte {} (cut mid-record); using the data before the cut",
                self.offset
            )
        } else if self.count > 1 {
            format!(
                "{} at byte {} ({} times in all)",
                self.message, self.offset, self.count
            )
        } else {
            format!("{} at byte {}", self.message, self.offset)
        }
    }
}

/// The key of the remark that the input ends inside a record.
pub const TRUNCATED: &str = "truncated";

/// At most `max` characters of `bytes` for an error or note (lossy UTF-8, control characters
/// escaped, `…` when cut): never echo a large piece of the input.
pub fn excerpt(bytes: &[u8], max: usize) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut out: String = text
        .chars()
        .take(max)
        .flat_map(char::escape_debug)
        .collect();
    if text.chars().nth(max).is_some() {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeats_are_counted_at_their_first_offset() {
        let mut issues = Issues::default();
        issues.add("a", 10, || "bad a".into());
        issues.add("b", 20, || "bad b".into());
        issues.add("a", 30, || unreachable!("built once"));
        issues.add(TRUNCATED, 40, String::new);
        assert_eq!(
            issues.notes("f.bin"),
            vec![
                "f.bin: bad a at byte 10 (2 times in all)",
                "f.bin: bad b at byte 20",
                "f.bin: the log is truncated at byte 40 (cut mid-record); using the data before the cut",
            ]
        );
    }

    #[test]
    fn excerpts_are_short_and_escaped() {
        assert_eq!(excerpt(b"abc", 40), "abc");
        assert_eq!(excerpt(&[b'x'; 100], 5), "xxxxx…");
        assert_eq!(excerpt(b"a\nb", 40), "a\\nb");
    }
}
