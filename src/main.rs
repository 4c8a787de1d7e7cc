//! The `nklut` command line.

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

use nklut::cli::{ChannelArgs, PageSelection, Paths};
use nklut::db::Database;
use nklut::ingest;
use nklut::spectrum;

#[derive(Parser)]
#[command(name = "nklut", version, about = "refractiveindex.info → per-channel (n, k), reference colours and Fresnel LUTs")]
struct Cli {
    #[command(flatten)]
    paths: Paths,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Read the catalog and every page; write materials.{csv,parquet,json} and excluded.csv.
    Ingest {
        #[command(flatten)]
        pages: PageSelection,
        #[command(flatten)]
        channels: ChannelArgs,
        /// Any data error other than no-visible-coverage is fatal.
        #[arg(long)]
        strict: bool,
    },
    /// Print n and k of one page at the given wavelengths: one line "nm n k" each.
    Nk {
        /// Page id, e.g. main/Au/Johnson.
        page: String,
        /// Wavelength in nm (repeatable).
        #[arg(long = "nm", required = true)]
        nm: Vec<f64>,
    },
    /// Spectral reference colours, index-approximation errors and effective channel
    /// indices per page; write colors.{csv,parquet}.
    Colors {
        #[command(flatten)]
        pages: PageSelection,
        #[command(flatten)]
        channels: ChannelArgs,
        /// LUT size whose texel centres (i + 0.5)/N are checked for out-of-gamut colours.
        #[arg(long, default_value_t = 256)]
        texels: usize,
    },
}

fn run(cli: Cli) -> Result<()> {
    let db = Database::open(cli.paths.db.as_deref())?;
    match cli.command {
        Command::Ingest { pages, channels, strict } => {
            let result = ingest::ingest(&db, &pages.selection(), &channels.channels)?;
            let written = ingest::write_tables(&result, &channels.channels, &cli.paths.out)?;
            eprintln!(
                "ingest: {} pages selected, {} kept, {} excluded {:?}",
                result.selected,
                result.kept.len(),
                result.excluded.len(),
                result.excluded_by_reason()
            );
            for path in written {
                eprintln!("  wrote {}", path.display());
            }
            if strict {
                result.check_strict()?;
            }
        }
        Command::Nk { page, nm } => {
            let (catalog, _) = db.catalog()?;
            let entry = catalog.find(&page).ok_or_else(|| anyhow::anyhow!("unknown page {page:?}"))?;
            let data = db.read_page(&entry.data)?;
            for wavelength in nm {
                let index = spectrum::index_at(&data, wavelength).map_err(|e| anyhow::anyhow!("{page}: {e}"))?;
                println!("{wavelength} {} {}", index.n, index.k);
            }
        }
        Command::Colors { pages, channels, texels } => {
            for path in nklut::color::command(&db, &pages.selection(), &channels.channels, &cli.paths.out, texels)? {
                eprintln!("  wrote {}", path.display());
            }
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
