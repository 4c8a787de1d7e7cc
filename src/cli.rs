//! Arguments shared by every subcommand.

use std::path::PathBuf;

use clap::Args;

use crate::ingest::{Config, Selection};
use crate::spectrum::{Channels, Coverage};

/// `--db DIR` and `--out DIR`, the same for every subcommand.
#[derive(Args, Clone, Debug)]
pub struct Paths {
    /// The refractiveindex.info database (the `database` folder or the repository above
    /// it). Default: $NKLUT_DB, else refractiveindex/database.
    #[arg(long, value_name = "DIR", global = true)]
    pub db: Option<PathBuf>,
    /// Where outputs go.
    #[arg(long, value_name = "DIR", default_value = "output", global = true)]
    pub out: PathBuf,
}

/// Which pages: `--page ID`, `--shelf NAME` (both repeatable) or `--all`.
#[derive(Args, Clone, Debug, Default)]
pub struct PageSelection {
    /// A page id such as main/Au/Johnson or 3d/metals/gold (repeatable).
    #[arg(long = "page", value_name = "ID")]
    pub pages: Vec<String>,
    /// A catalog shelf such as 3d or main (repeatable).
    #[arg(long = "shelf", value_name = "NAME")]
    pub shelves: Vec<String>,
    /// Every page of the catalog (the default when no --page or --shelf is given).
    #[arg(long)]
    pub all: bool,
}

impl PageSelection {
    pub fn selection(&self) -> Selection {
        if self.all {
            return Selection::default();
        }
        Selection { shelves: self.shelves.clone(), pages: self.pages.clone() }
    }
}

/// How every command that reads pages reads them: `--channels R,G,B`, `--visible`,
/// `--strict`.
#[derive(Args, Clone, Debug)]
pub struct ChannelArgs {
    /// Channel wavelengths red,green,blue in nm (each in 360-830 nm).
    #[arg(long, value_name = "R,G,B", default_value = "685,535,475", value_parser = parse_channels)]
    pub channels: Channels,
    /// Which wavelengths a kept page's data must cover: `channels` (the three channel
    /// wavelengths; the spectral colour holds the nearest measured value outside the data)
    /// or `full` (390-700 nm).
    #[arg(long, value_name = "RULE", default_value = "channels", value_parser = parse_coverage)]
    pub visible: Coverage,
    /// Any data error other than missing coverage, and any data warning, is fatal.
    #[arg(long)]
    pub strict: bool,
}

impl Default for ChannelArgs {
    fn default() -> Self {
        Self { channels: Channels::default(), visible: Coverage::default(), strict: false }
    }
}

impl ChannelArgs {
    pub fn config(&self) -> Config {
        Config { channels: self.channels, coverage: self.visible, strict: self.strict }
    }
}

fn parse_channels(text: &str) -> Result<Channels, String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>().map_err(|e| format!("{v:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match values.as_slice() {
        &[red_nm, green_nm, blue_nm] => Channels::new(red_nm, green_nm, blue_nm),
        _ => Err("expected three wavelengths in nm, e.g. 685,535,475".into()),
    }
}

fn parse_coverage(text: &str) -> Result<Coverage, String> {
    match text {
        "channels" => Ok(Coverage::Channels),
        "full" => Ok(Coverage::Full),
        _ => Err(format!("{text:?}: expected channels or full")),
    }
}
