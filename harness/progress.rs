//! Progress bars with an estimate of the time left, hidden when output is not a terminal.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar over `[0, 1]` labelled `label`.
pub fn fraction_bar(label: &str) -> ProgressBar {
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template(
            "{prefix:>24} [{bar:40}] {percent:>3}% {elapsed_precise} left {eta}",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar.set_prefix(label.to_string());
    bar
}
