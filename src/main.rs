//! The `nklut` command line.

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

mod cli;

use cli::{BakeArgs, ChannelArgs, PageSelection, Paths, RecommendArgs, ValidateArgs};
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
    },
    /// Write output/report/index.html, report.md and one page per material from the tables the other stages wrote.
    Report {
        #[command(flatten)]
        pages: PageSelection,
        /// A folder of device results, one sub-folder per adapter holding its
        /// `gpu_timing.csv` (and `image_errors.csv`) of `nklut gpu run` (default: <out>/devices,
        /// where `make report` copies benchmarks/devices).
        #[arg(long, value_name = "DIR")]
        devices: Option<std::path::PathBuf>,
    },
    /// Bake Fresnel LUT textures, manifest.json and README.md into <out>/luts (all or nothing).
    Bake(BakeArgs),
    /// Print n and k of one page at the given wavelengths: one line "nm n k" each.
    Nk {
        /// Page id, e.g. main/Au/Johnson.
        page: String,
        /// Wavelength in nm (repeatable).
        #[arg(long = "nm", required = true)]
        nm: Vec<f64>,
    },
    /// Measure every Fresnel method's error against exact (SPEC §6); write errors.* and cost.*.
    Validate(ValidateArgs),
    /// Time and render the Fresnel methods on a GPU with wgpu, driven by a scene file.
    #[cfg(feature = "gpu")]
    Gpu {
        #[command(subcommand)]
        command: gpu_cli::GpuCommand,
    },
    /// The effects a scene names, on the CPU: multiple reflections and refractions (the f64
    /// reference and the distance-map twin with each method → effects_errors.*), surfel
    /// ambient occlusion and indirect light (against the ray-traced reference → ao_errors.*
    /// and pictures under ao_frames/).
    Effects {
        scene: std::path::PathBuf,
        /// Camera frames to render (default: the scene's).
        #[arg(long)]
        frames: Option<u32>,
        /// Frame size WxH (default: the scene's resolution).
        #[arg(long, value_parser = parse_resolution)]
        resolution: Option<[u32; 2]>,
        /// Reference rays per vertex for ambient occlusion and indirect light (1..=2^20).
        #[arg(long, default_value_t = 256)]
        ao_rays: u32,
        /// The largest surfel count run by brute force (n² per pass); above it, the tree only.
        #[arg(long, default_value_t = 20_000)]
        ao_max_brute: usize,
        /// The long side in pixels of the hero frame (frame 0 again, every variant beside the
        /// reference, for the report: effects_hero/); 0: none.
        #[arg(long, default_value_t = nklut::effects::hero::DEFAULT_HERO_SIZE)]
        hero_size: u32,
        #[command(flatten)]
        channels: ChannelArgs,
    },
    /// Spectral reference colours, index-approximation errors and effective channel
    /// indices per page; write colors.{csv,parquet}.
    Colors {
        #[command(flatten)]
        pages: PageSelection,
        #[command(flatten)]
        channels: ChannelArgs,
        /// LUT size whose texel centres (i + 0.5)/N are checked for out-of-gamut colours
        /// (1..=65536, the bounds of `bake --size`).
        #[arg(long, default_value_t = 256, value_parser = parse_texels)]
        texels: usize,
    },
    /// Engine parameters per page (F0, F82 tint, Gulbrandsen, generalized Schlick, fitted
    /// n,k, n_d/Abbe, the appearance and the volume's colour) with each model's error; write
    /// engine_params.*, materials.mtlx, materials.gltf + materials.bin, materials.usda and
    /// one paste-in file per page under params/.
    Params {
        #[command(flatten)]
        pages: PageSelection,
        #[command(flatten)]
        channels: ChannelArgs,
        /// One roughness in [0, 1] for every exported material (default: 0.2 for metals, 0
        /// for dielectrics).
        #[arg(long)]
        roughness: Option<f64>,
    },
    /// Per kept page and device (CPU and each device with timings): the cheapest method
    /// within an error bound against the spectral curve, its parameters, the runner-up and
    /// why others lose → recommendations.{csv,parquet,json}, method_errors.{csv,parquet}.
    Recommend(RecommendArgs),
}

fn parse_texels(text: &str) -> Result<usize, String> {
    let size: usize = text.parse().map_err(|e| format!("{text:?}: {e}"))?;
    if !(1..=nklut::bake::MAX_SIZE).contains(&size) {
        return Err(format!("must be between 1 and {} texels, got {size}", nklut::bake::MAX_SIZE));
    }
    Ok(size)
}

/// Write a line to standard output. A reader that closed the pipe (`nklut nk … | head -1`)
/// is not an error: [`main`] ends quietly with status 0 when it sees [`PipeClosed`].
fn print_line(line: &str) -> Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{line}").and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(PipeClosed.into()),
        other => Ok(other?),
    }
}

/// Standard output was closed by its reader.
#[derive(Debug, thiserror::Error)]
#[error("standard output closed")]
struct PipeClosed;

/// `WIDTHxHEIGHT`, e.g. `1920x1080`.
fn parse_resolution(text: &str) -> Result<[u32; 2], String> {
    let parts: Vec<&str> = text.split(['x', 'X']).collect();
    match parts.as_slice() {
        [w, h] => match (w.trim().parse::<u32>(), h.trim().parse::<u32>()) {
            (Ok(w), Ok(h)) if w > 0 && h > 0 => Ok([w, h]),
            _ => Err(format!("{text:?}: expected WIDTHxHEIGHT, e.g. 1920x1080")),
        },
        _ => Err(format!("{text:?}: expected WIDTHxHEIGHT, e.g. 1920x1080")),
    }
}

fn run(cli: Cli) -> Result<()> {
    // A memory budget that is set but is not a size stops every command before any work.
    let budget = nklut::budget::MemoryBudget::from_environment()?;
    let command = match cli.command {
        #[cfg(feature = "gpu")]
        Command::Gpu { command } => return gpu_cli::run(command, &cli.paths),
        other => other,
    };
    let open_db = || nklut::open_database(cli.paths.db.as_deref());
    // The effects open the database only when their scene needs materials.
    let command = match command {
        Command::Effects { scene, frames, resolution, ao_rays, ao_max_brute, hero_size, channels } => {
            let request = nklut::effects::command::EffectsRequest {
                scene,
                frames,
                resolution,
                ao_rays,
                ao_max_brute,
                hero_size: Some(hero_size),
                config: channels.config(),
                budget,
            };
            let outcome = nklut::effects::command::command(&request, &open_db, nklut::output::parquet, &cli.paths.out, &mut |line| {
                eprintln!("{line}")
            })?;
            for path in &outcome.written {
                eprintln!("  wrote {}", path.display());
            }
            let stats = outcome.stats;
            eprintln!(
            "effects: {} cube maps × {} layers, {} reference frames, {} distance-map frames; {} surfels, {} tree nodes, {} AO passes, {} indirect gathers",
            stats.cube_maps, stats.layers, stats.reference_frames, stats.twin_frames, stats.surfels, stats.tree_nodes, stats.ao_passes, stats.indirect_bounces
        );
            return Ok(());
        }
        other => other,
    };
    let db = open_db()?;
    match command {
        Command::Ingest { pages, channels } => {
            let result = ingest::ingest(&db, &pages.selection(), &channels.config())?;
            let written = ingest::write_tables(&result, &cli.paths.out)?;
            eprintln!(
                "ingest: {} pages selected, {} kept, {} excluded {:?}",
                result.selected,
                result.kept.len(),
                result.excluded.len(),
                result.excluded_by_reason()
            );
            if !result.listed_twice.is_empty() {
                eprintln!(
                    "  {} page ids are listed twice in the catalog with the same file (kept once): {}",
                    result.listed_twice.len(),
                    nklut::escape::terminal(&result.listed_twice.join(", "))
                );
            }
            if !result.warnings.is_empty() {
                eprintln!("  {} data warning(s) outside the evaluated wavelengths (warnings.csv)", result.warnings.len());
            }
            for path in written {
                eprintln!("  wrote {}", path.display());
            }
            result.check_strict()?;
            exiting_with(result);
        }
        Command::Report { pages, devices } => {
            let written = nklut::report::command(&db, &cli.paths.out, &pages.selection(), devices.as_deref())?;
            eprintln!("report: {} files under {}", written.len(), cli.paths.out.join("report").display());
        }
        Command::Bake(args) => {
            let summary = nklut::bake::run(&db, &cli.paths.out, &args.request())?;
            eprintln!(
                "bake: {} rows, {} files, {} clamped texels -> {}",
                summary.rows,
                summary.files,
                summary.clamped_texels,
                summary.luts.display()
            );
        }
        Command::Nk { page, nm } => {
            let catalog = db.catalog()?;
            let entry = catalog.find(&page).ok_or_else(|| anyhow::anyhow!("unknown page {page:?}"))?;
            let data = db.read_page(&entry.data)?;
            for wavelength in nm {
                let index = spectrum::index_at(&data, wavelength).map_err(|e| anyhow::anyhow!("{page}: {e}"))?;
                print_line(&format!("{wavelength} {} {}", index.n, index.k))?;
            }
        }
        Command::Validate(args) => {
            let outcome = nklut::validate::run(&args.request(), Some(&db), &cli.paths.out)?;
            for line in outcome.summary.lines() {
                print_line(line)?;
            }
            for path in outcome.written {
                eprintln!("  wrote {}", path.display());
            }
        }
        #[cfg(feature = "gpu")]
        Command::Gpu { .. } => unreachable!("handled before the database is opened"),
        Command::Params { pages, channels, roughness } => {
            let settings = nklut::params::ExportSettings { roughness };
            for path in nklut::params::command(&db, &pages.selection(), &channels.config(), &settings, &cli.paths.out)? {
                eprintln!("  wrote {}", path.display());
            }
        }
        Command::Recommend(args) => {
            for path in nklut::recommend::command(&db, &cli.paths.out, &args.request())? {
                eprintln!("  wrote {}", path.display());
            }
        }
        Command::Effects { .. } => unreachable!("handled before the database is opened"),
        Command::Colors { pages, channels, texels } => {
            for path in nklut::colors::command(&db, &pages.selection(), &channels.config(), &cli.paths.out, texels)? {
                eprintln!("  wrote {}", path.display());
            }
        }
    }
    Ok(())
}

/// glibc's malloc gives each thread that meets contention an arena of its own (up to eight
/// per core), and pages freed in one arena are not reused by another: after the whole
/// database is read in parallel, validate's peak grew by ≈ 40 MB of such freed pages
/// (314–322 MB against 274 MB with two arenas, the same run time; BENCHMARKS.md). Two
/// arenas for the two threads of work.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn limit_malloc_arenas() {
    // SAFETY: mallopt only sets a parameter of the allocator; it is called before any
    // thread is started.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, 2);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn limit_malloc_arenas() {}

/// Let go of `value` without handing its memory back: the process ends after this
/// command, and the operating system takes the memory back whole, where freeing a
/// database's pages one allocation at a time is milliseconds of work after the outputs
/// are written.
fn exiting_with<T>(value: T) {
    std::mem::forget(value);
}

fn main() -> ExitCode {
    limit_malloc_arenas();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if error.is::<PipeClosed>() => ExitCode::SUCCESS,
        Err(error) => {
            // Ids and names from the database are shown as text, never as terminal controls.
            let text = format!("{error:#}");
            eprintln!("error: {}", text.lines().map(nklut::escape::terminal).collect::<Vec<_>>().join("\n"));
            ExitCode::FAILURE
        }
    }
}

#[cfg(feature = "gpu")]
mod gpu_cli {
    use std::path::PathBuf;

    use super::parse_resolution;
    use anyhow::{bail, Result};
    use clap::{Args, Subcommand};

    use crate::cli::{ChannelArgs, Paths};
    use nklut::gpu;
    use nklut::scene::{Experiment, Scene};

    #[derive(Args, Clone, Debug)]
    pub struct AdapterArg {
        /// Use the adapter whose name contains this (case-insensitive); see `nklut gpu adapters`.
        #[arg(long, value_name = "SUBSTRING")]
        adapter: Option<String>,
        /// Use this backend only: vulkan, and where the platform has them metal (macOS), dx12
        /// (Windows) and gl (Linux, Android; on Mesa's desktop GL nklut enables
        /// GL_ARB_color_buffer_float for the float targets itself).
        #[arg(long, value_name = "BACKEND")]
        backend: Option<String>,
    }

    #[derive(Subcommand)]
    pub enum GpuCommand {
        /// List the adapters wgpu sees (name, backend, type, driver).
        Adapters,
        /// Time the surfel ambient-occlusion pass against surfel count, brute force and
        /// hierarchy, over the bunny and the sculpture decimated and subdivided → ao_timing.*.
        AoTiming {
            /// Folder holding stanford-bunny.obj and nefertiti.obj.
            #[arg(long, default_value = "../shared/meshes")]
            meshes: PathBuf,
            /// The largest surfel count timed by brute force (n² per pass).
            #[arg(long, default_value_t = 40_000)]
            max_brute: usize,
            /// Timed samples per configuration (after one untimed).
            #[arg(long, default_value_t = 3)]
            repeats: u32,
            /// Time only the sweep meshes whose name contains this (e.g. `bunny-subdivided`).
            #[arg(long)]
            only: Option<String>,
            /// AO scenes timed as they are (their surfel pass, 1–3 passes, and GTAO where
            /// they name it), on the same run.
            #[arg(long, num_args = 0.., default_values = ["scenes/ao-bunny.yaml", "scenes/ao-sculpture.yaml", "scenes/ao-bunny-gtao.yaml"])]
            scenes: Vec<PathBuf>,
            /// Frame sizes GTAO is timed at: N (N × N) or WxH, comma-separated.
            #[arg(long, value_delimiter = ',', value_parser = nklut::gpu::ao_timing::frame_size, default_values = ["256", "1024", "1920x1080"])]
            gtao_resolutions: Vec<[u32; 2]>,
            #[command(flatten)]
            adapter: AdapterArg,
        },
        /// Run a scene file: the measurements it names, for its objects, materials and methods.
        Run {
            scene: PathBuf,
            #[command(flatten)]
            adapter: AdapterArg,
            #[command(flatten)]
            read: ChannelArgs,
        },
        /// Time each (material, method) of a scene in a fullscreen pass → gpu_timing.csv.
        Bench {
            #[arg(default_value = "scenes/default.yaml")]
            scene: PathBuf,
            /// The study's method: time an expensive pass alone and with the method on top.
            #[arg(long)]
            subtract: bool,
            /// One F evaluation per pixel per pass (no amplification: the single-draw design,
            /// for comparison).
            #[arg(long)]
            single_draw: bool,
            /// Seed of the order of the (material, method) pairs in each round.
            #[arg(long)]
            seed: Option<u64>,
            /// Timed passes per (material, method).
            #[arg(long)]
            repeats: Option<u32>,
            /// Untimed passes first.
            #[arg(long)]
            warmup: Option<u32>,
            /// Pass size WxH (default 1920x1080).
            #[arg(long, value_parser = parse_resolution)]
            resolution: Option<[u32; 2]>,
            #[command(flatten)]
            adapter: AdapterArg,
            #[command(flatten)]
            read: ChannelArgs,
        },
        /// Write the browser bench of each scene: one self-contained page, <out>/web/<scene>.html,
        /// that runs the scene's F-only measurements (timing, image error), or for a scene
        /// with reflections or refractions the timing of its map update and shading pass
        /// (effects_timing), in any WebGPU browser, phones included, from file:// or a static host, and offers the result
        /// as device-<adapter>-<date>.json (`nklut report --devices` reads it). The folder
        /// web/ is replaced as a whole by the pages of this run.
        Web {
            #[arg(required = true)]
            scenes: Vec<PathBuf>,
            #[command(flatten)]
            read: ChannelArgs,
        },
        /// Render each object of a scene with its methods and exact → image_errors.csv.
        ImageError {
            #[arg(default_value = "scenes/default.yaml")]
            scene: PathBuf,
            /// Frames of the orbit (default: the scene's, 180).
            #[arg(long)]
            frames: Option<u32>,
            /// Degrees between frames (default: the scene's, 1).
            #[arg(long)]
            degrees_per_frame: Option<f64>,
            /// Render target WxH.
            #[arg(long, value_parser = parse_resolution)]
            resolution: Option<[u32; 2]>,
            #[command(flatten)]
            adapter: AdapterArg,
            #[command(flatten)]
            read: ChannelArgs,
        },
    }

    pub fn run(command: GpuCommand, paths: &Paths) -> Result<()> {
        let (scene, adapter, read) = match command {
            GpuCommand::Adapters => {
                let adapters = gpu::adapters();
                if adapters.is_empty() {
                    bail!("no adapter found; without a GPU install a software Vulkan driver (apt-get install mesa-vulkan-drivers)");
                }
                for line in adapters {
                    super::print_line(&line.to_string())?;
                }
                return Ok(());
            }
            GpuCommand::AoTiming { meshes, max_brute, repeats, only, scenes, gtao_resolutions, adapter } => {
                use nklut::gpu::ao_timing::{ao_timing_table, scene_rows, sweep, sweep_meshes, SweepSettings};
                use nklut::output::TableFiles;
                let device = gpu::open(adapter.adapter.as_deref(), adapter.backend.as_deref())?;
                eprintln!(
                    "adapter: {}{}",
                    device.line,
                    if device.timestamps { ", timestamp queries" } else { ", no timestamp queries (wall time)" }
                );
                let mut all = Vec::new();
                for (name, file) in [("bunny", "stanford-bunny.obj"), ("sculpture", "nefertiti.obj")] {
                    let mesh = nklut::scene::mesh::load_obj(&meshes.join(file))?;
                    all.extend(sweep_meshes(name, &mesh));
                }
                all.retain(|m| only.as_deref().is_none_or(|only| m.name.contains(only)));
                let settings = SweepSettings { max_brute, repeats: repeats.max(1), ..SweepSettings::default() };
                let mut rows = sweep(&device, &all, &settings, &mut |line| eprintln!("{line}"))?;
                for gather in ["brute_force", "hierarchy"] {
                    if let Some(row) = rows.iter().find(|r| r.gather.name() == gather) {
                        eprintln!("  {gather}: time ∝ n^{:.2}", row.fitted_exponent);
                    }
                }
                let scene_settings = SweepSettings { passes: 3, ..settings };
                for file in &scenes {
                    let scene = Scene::load(file)?;
                    let name = file.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
                    rows.extend(scene_rows(&device, &name, &scene, &gtao_resolutions, &scene_settings, &mut |line| eprintln!("{line}"))?);
                }
                for path in ao_timing_table(&rows, &device.line).write(&paths.out, nklut::effects_tables::ao_timing::STEM, false)? {
                    eprintln!("  wrote {}", path.display());
                }
                return Ok(());
            }
            GpuCommand::Web { scenes, read } => {
                let mut pages = Vec::new();
                let db = nklut::open_database(paths.db.as_deref())?;
                for file in scenes {
                    let scene = Scene::load(&file)?;
                    let (materials, _) = nklut::scene::read_materials(&scene, &db, &read.config())?;
                    let bench = gpu::web::plan(&scene, &materials)?;
                    if pages.iter().any(|p: &nklut::output::SetFile| p.name == gpu::web::page_name(&bench)) {
                        bail!("two scenes named {}: each page is web/<scene file stem>.html", bench.scene);
                    }
                    pages.push(nklut::output::SetFile::new(gpu::web::page_name(&bench), gpu::web::page(&bench)?.into_bytes()));
                }
                for path in nklut::output::publish_set(&paths.out, "web", &pages)? {
                    super::print_line(&path.display().to_string())?;
                }
                return Ok(());
            }
            GpuCommand::Run { scene, adapter, read } => (Scene::load(&scene)?, adapter, read),
            GpuCommand::Bench { scene, subtract, single_draw, seed, repeats, warmup, resolution, adapter, read } => {
                let mut scene = Scene::load(&scene)?;
                scene.experiments = vec![Experiment::Timing];
                scene.timing.subtract |= subtract;
                scene.timing.amplify &= !single_draw;
                scene.timing.seed = seed.unwrap_or(scene.timing.seed);
                scene.timing.repeats = repeats.unwrap_or(scene.timing.repeats).max(1);
                scene.timing.warmup = warmup.unwrap_or(scene.timing.warmup);
                scene.timing.resolution = resolution.unwrap_or(scene.timing.resolution);
                (scene, adapter, read)
            }
            GpuCommand::ImageError { scene, frames, degrees_per_frame, resolution, adapter, read } => {
                let mut scene = Scene::load(&scene)?;
                scene.experiments = vec![Experiment::ImageError];
                scene.camera.frames = frames.unwrap_or(scene.camera.frames).max(1);
                scene.camera.degrees_per_frame = degrees_per_frame.unwrap_or(scene.camera.degrees_per_frame);
                scene.resolution = resolution.unwrap_or(scene.resolution);
                (scene, adapter, read)
            }
        };
        // Overrides pass the same checks as the scene file's own values.
        scene.recheck()?;
        let device = gpu::open(adapter.adapter.as_deref(), adapter.backend.as_deref())?;
        eprintln!(
            "adapter: {}{}",
            device.line,
            if device.timestamps { ", timestamp queries" } else { ", no timestamp queries (wall time)" }
        );
        // The database is opened only when the scene names materials.
        let open_db = || nklut::open_database(paths.db.as_deref());
        let report = gpu::run_opening(&scene, &open_db, &read.config(), &device, &mut |line| eprintln!("{line}"))?;
        eprintln!("run: {}", report.stats);
        for path in gpu::runner::write_tables(&report, &paths.out)? {
            eprintln!("  wrote {}", path.display());
        }
        if !report.stats.failures.is_empty() {
            anyhow::bail!("the measurements above were written; these failed: {}", report.stats.failures.join("; "));
        }
        Ok(())
    }
}
