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
    /// Write output/report/index.html and report.md from the tables the other stages wrote.
    Report {
        #[command(flatten)]
        pages: PageSelection,
        /// Leave out the per-material Fresnel plots (smaller HTML for --all).
        #[arg(long)]
        no_plots: bool,
    },
    /// Bake Fresnel LUT textures, manifest.json and README.md into <out>/luts (all or nothing).
    Bake(nklut::bake::BakeArgs),
    /// Print n and k of one page at the given wavelengths: one line "nm n k" each.
    Nk {
        /// Page id, e.g. main/Au/Johnson.
        page: String,
        /// Wavelength in nm (repeatable).
        #[arg(long = "nm", required = true)]
        nm: Vec<f64>,
    },
    /// Measure every Fresnel method's error against exact (SPEC §6); write errors.* and cost.*.
    Validate(nklut::validate::ValidateArgs),
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
            if !result.listed_twice.is_empty() {
                eprintln!("  {} page ids are listed twice in the catalog with the same file (kept once): {}", result.listed_twice.len(), result.listed_twice.join(", "));
            }
            for problem in &result.catalog_problems {
                eprintln!("  catalog: {problem}");
            }
            for path in written {
                eprintln!("  wrote {}", path.display());
            }
            if strict {
                result.check_strict()?;
            }
        }
        Command::Report { pages, no_plots } => {
            let written = report_command(&cli.paths.out, &pages, !no_plots)?;
            for path in written {
                eprintln!("  wrote {}", path.display());
            }
        }
        Command::Bake(args) => {
            let summary = nklut::bake::run(&db, &cli.paths.out, &args)?;
            eprintln!("bake: {} rows, {} files, {} clamped texels -> {}", summary.rows, summary.files, summary.clamped_texels, summary.luts.display());
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
        Command::Validate(args) => {
            for path in nklut::validate::run(&args, Some(&db), &cli.paths.out)? {
                eprintln!("  wrote {}", path.display());
            }
        }
    }
    Ok(())
}

/// The report details the selected pages (default: the 3d shelf) found in materials.csv.
fn report_command(out: &std::path::Path, pages: &PageSelection, plots: bool) -> Result<Vec<std::path::PathBuf>> {
    use nklut::report;
    use nklut::spectrum::Index;
    let inputs = report::Inputs::load(out)?;
    let m = &inputs.materials;
    let selection = if pages.all || !pages.pages.is_empty() || !pages.shelves.is_empty() {
        pages.selection()
    } else {
        ingest::Selection::shelf("3d")
    };
    let all = selection.shelves.is_empty() && selection.pages.is_empty();
    let chosen: Vec<String> = m
        .rows
        .iter()
        .filter(|r| all || selection.shelves.iter().any(|s| s == m.text(r, "shelf")) || selection.pages.iter().any(|p| p == m.text(r, "page")))
        .map(|r| m.text(r, "page").to_string())
        .collect();
    let curves = |page: &str| {
        let row = m.rows_where("page", page).next()?;
        let index = ["red", "green", "blue"].map(|c| Index::new(m.number(row, &format!("n_{c}")).unwrap_or(1.0), m.number(row, &format!("k_{c}")).unwrap_or(0.0)));
        Some(report::curves::method_curves(&index, 91))
    };
    let built = report::build(&inputs, &report::Options { pages: chosen, plots }, &curves)?;
    report::write(&built, out)
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
