//! Arguments shared by every subcommand.

use std::path::PathBuf;

use clap::Args;

use crate::ingest::Selection;
use crate::spectrum::Channels;

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

/// `--channels R,G,B` in nm.
#[derive(Args, Clone, Debug)]
pub struct ChannelArgs {
    /// Channel wavelengths red,green,blue in nm.
    #[arg(long, value_name = "R,G,B", default_value = "685,535,475", value_parser = parse_channels)]
    pub channels: Channels,
}

fn parse_channels(text: &str) -> Result<Channels, String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>().map_err(|e| format!("{v:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match values.as_slice() {
        &[red_nm, green_nm, blue_nm] if values.iter().all(|v| *v > 0.0) => Ok(Channels { red_nm, green_nm, blue_nm }),
        _ => Err("expected three positive wavelengths in nm, e.g. 685,535,475".into()),
    }
}
