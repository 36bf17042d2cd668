//! The README's table of the numbers a user decides by quotes generated documents: every
//! number in a row must stand in the document named in its last column, so that a
//! regenerated document that changed a number fails here until the README follows.

use std::fs;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// The numbers of a cell: runs of digits (with a decimal point), as the documents write them.
fn numbers(cell: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for c in cell.chars().chain(std::iter::once(' ')) {
        if c.is_ascii_digit() || (c == '.' && !current.is_empty()) {
            current.push(c);
        } else if !current.is_empty() {
            out.push(current.trim_end_matches('.').to_string());
            current.clear();
        }
    }
    out
}

#[test]
fn every_number_of_the_readme_table_stands_in_its_document() {
    let readme = fs::read_to_string(root().join("README.md")).expect("README.md");
    let begin = readme
        .find("<!-- numbers: begin -->")
        .expect("numbers markers in README.md");
    let end = readme.find("<!-- numbers: end -->").expect("end marker");
    let rows: Vec<&str> = readme[begin..end]
        .lines()
        .filter(|l| l.starts_with('|') && !l.starts_with("|---") && !l.starts_with("| question"))
        .collect();
    assert!(rows.len() >= 4, "the table lost its rows: {rows:?}");
    for row in rows {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let (answer, source) = (cells[2], cells[3].trim_matches('`'));
        let doc = fs::read_to_string(root().join(source))
            .unwrap_or_else(|e| panic!("{source} (named in README.md): {e}"));
        let found = numbers(answer);
        assert!(!found.is_empty(), "a row without numbers: {row}");
        for n in found {
            // Documents write thousands without separators in tables, or with a thin space.
            let spaced = if n.len() > 3 && !n.contains('.') {
                let (a, b) = n.split_at(n.len() - 3);
                format!("{a} {b}")
            } else {
                n.clone()
            };
            assert!(
                doc.contains(&n) || doc.contains(&spaced),
                "README.md quotes {n} from {source}, which no longer holds it (row: {row})"
            );
        }
    }
}
