//! The nklut pipeline over the optics of `nklut_optics`: the selected pages of the
//! database into tables ([`ingest`]), their reference colours ([`colors`]), every Fresnel
//! method's error ([`validate`]), lookup textures ([`bake`]), engine parameters and their
//! exports ([`params`]), the report that draws them ([`report`]) and what to ship per page
//! and device ([`recommend`]).
//!
//! Modules follow the data, and every import points one way — a module uses only modules
//! before it in this order (the workspace's `tests/module_order.rs` checks it): `ingest` →
//! `colors` → `validate` / `bake` / `params` → `report` → `recommend` (which reads the
//! report's table readers). Leaves any module may use:
//! `output` (tables as CSV, Parquet and JSON; files and folders published as one set),
//! `progress` (bars on a terminal, quiet in CI), `budget` (the memory a run may take,
//! checked before large allocations), `escape` (text for a terminal, a CSV cell, Markdown
//! or XML) and `stats` (medians and quantiles of samples). All but Parquet (polars) live
//! in `nklut_tables`, the crate below this one and the effects, with ingest's reading of
//! pages, the texel images and the engine models; they are re-exported here at their old
//! paths. Stages take plain values; the command line lives in the `nklut` binary.
//!
//! "SPEC §n" in comments is section n of `docs/SPEC.md`, the specification in this
//! repository.

// `!(a <= b)` is written where a NaN must take the branch that `a > b` would skip.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bake;
pub mod colors;
pub mod ingest;
pub mod output;
pub mod params;
pub mod recommend;
pub mod report;
pub mod validate;

// The leaves that the effects share, from the crate below both (at their old paths here).
pub use nklut_tables::{budget, columns, effects_tables, escape, gpu_tables, memo_file, progress, stats};
