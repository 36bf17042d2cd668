//! The terminal an identification reports to: notes on stderr, results on stdout, and a
//! progress bar over the samples (`indicatif`) while the variants are evaluated. Used by
//! `rotorid identify` and `rotorid-lab identify`.

/// Why [`Terminal::new`] failed (re-exported so that callers need not depend on `indicatif`).
pub use indicatif::style::TemplateError;
use indicatif::{ProgressBar, ProgressStyle};

use crate::identify;

/// Prints an identification's notes to stderr and its text to stdout, with a progress bar.
pub struct Terminal {
    style: ProgressStyle,
    bar: Option<ProgressBar>,
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
        })
    }
}

impl identify::Progress for Terminal {
    fn note(&mut self, line: &str) {
        eprintln!("{line}");
    }
    fn print(&mut self, text: &str) {
        print!("{text}");
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
