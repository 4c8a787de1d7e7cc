//! What the nklut pipeline and the effects both stand on, without the pipeline's heavy
//! dependencies (polars, plotters): the selected pages of the database read into materials
//! ([`ingest`]), tables as CSV and JSON and the files of one command published as one set
//! ([`output`]; the Parquet encoder is passed in by the layer that holds one), order
//! statistics, error summaries and histograms ([`stats`]), the memory a run may take
//! ([`budget`]), progress bars ([`progress`]), text escaped for each sink ([`escape`]),
//! stored texels and their PNG/EXR files ([`texel`], [`image_files`]) and the engine
//! parameterisations of a Fresnel curve with their fits ([`models`]), files replaced whole
//! ([`atomic`]), the memo files of an output folder ([`memo_file`]), and typed columns
//! ([`columns`]) with the tables of the effects ([`effects_tables`]) and of the GPU runner
//! ([`gpu_tables`]) listed in them: one source for the crates that write those tables and
//! the report that reads them.
//!
//! Leaves: `output`, `progress`, `budget`, `stats`, `escape`, `texel`, `image_files`,
//! `models`, `atomic` and `memo_file` use no module of this crate but `output` → `escape`,
//! `output` and `memo_file` → `atomic`, `image_files` → `texel`, `columns` → `output`, and
//! `effects_tables` and `gpu_tables` → `columns`; `ingest` uses `output`, `progress` and
//! `escape`.
//!
//! "SPEC §n" in comments is section n of `docs/SPEC.md`, the specification in this
//! repository.

// `!(a <= b)` is written where a NaN must take the branch that `a > b` would skip.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod atomic;
pub mod budget;
pub mod columns;
pub mod effects_tables;
pub mod escape;
pub mod gpu_tables;
pub mod image_files;
pub mod ingest;
pub mod memo_file;
pub mod models;
pub mod output;
pub mod progress;
pub mod stats;
pub mod texel;
