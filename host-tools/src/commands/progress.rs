//! The progress bar of the batch commands (simulate, eval): on stderr, hidden when not wanted.

/// A bar over `len` items, `noun` naming them (`"scenes"`, `"bundles"`); hidden unless `show`.
pub fn bar(len: u64, noun: &str, show: bool) -> indicatif::ProgressBar {
    let bar = if show {
        indicatif::ProgressBar::new(len)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{{msg}} [{{bar:40}}] {{pos}}/{{len}} {noun}, {{elapsed}} (eta {{eta}})"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}
