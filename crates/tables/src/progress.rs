//! Progress bars for long work: drawn on a terminal, silent in CI or when piped.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

/// A progress bar of `len` steps labelled `label`; hidden unless stderr is a terminal and
/// `CI` is unset.
pub fn bar(len: usize, label: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() || std::env::var_os("CI").is_some() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix:>10} [{bar:40}] {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_prefix(label.to_string());
    bar
}

/// `f(i)` for every i in 0..len, in parallel, collected in order, with a progress bar of
/// `label` that advances as each finishes.
pub fn par_map<U: Send>(len: usize, label: &str, f: impl Fn(usize) -> U + Sync) -> Vec<U> {
    let bar = bar(len, label);
    let values = (0..len)
        .into_par_iter()
        .map(|i| {
            let value = f(i);
            bar.inc(1);
            value
        })
        .collect();
    bar.finish_and_clear();
    values
}
