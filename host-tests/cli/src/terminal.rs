//! The terminal an identification reports to: notes on stderr, results on stdout, and a
//! progress bar over the samples (`indicatif`) while the variants are evaluated. Used by
//! `rotorid identify` and `rotorid-lab identify`.

/// Why [`Terminal::new`] failed (re-exported so that callers need not depend on `indicatif`).
pub use indicatif::style::TemplateError;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::{ErrorKind, Write};

use crate::identify;

/// Prints an identification's notes to stderr and its text to stdout, with a progress bar.
pub struct Terminal {
    style: ProgressStyle,
    bar: Option<ProgressBar>,
    /// Standard output can no longer be written (a reader that stopped early, `| head`):
    /// the rest of the text is dropped and the identification, with its files, goes on.
    stdout_closed: bool,
}

impl Terminal {
    /// A terminal with no bar yet.
    ///
    /// # Errors
    /// The bar's template does not parse (a bug in this module, never the input's).
    pub fn new() -> Result<Self, TemplateError> {
        Ok(Self {
            style: ProgressStyle::with_template(
                "{msg:>12} [{bar:40}] {pos}/{len} samples ({eta})",
            )?
            .progress_chars("=> "),
            bar: None,
            stdout_closed: false,
        })
    }
}

impl identify::Progress for Terminal {
    fn note(&mut self, line: &str) {
        eprintln!("{line}");
    }
    fn print(&mut self, text: &str) {
        // `print!` panics when the reader has gone; a closed pipe is not an error of the
        // identification, any other failure is said once.
        if self.stdout_closed {
            return;
        }
        let mut out = std::io::stdout().lock();
        if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
            self.stdout_closed = true;
            if e.kind() != ErrorKind::BrokenPipe {
                eprintln!("cannot write to standard output ({e}); the files are still written");
            }
        }
    }
    fn start(&mut self, total: u64) {
        let bar = ProgressBar::new(total);
        bar.set_style(self.style.clone());
        self.bar = Some(bar);
    }
    fn variant(&mut self, name: &'static str) {
        if let Some(bar) = &self.bar {
            bar.set_message(name);
        }
    }
    fn tick(&mut self) {
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
    }
    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
