//! Optical constants of the refractiveindex.info database, turned into what a renderer
//! needs, with no heavier dependency than a YAML reader: the database reader ([`db`]),
//! n and k at any wavelength and per colour channel ([`spectrum`]), every Fresnel method
//! of the pipeline in f64 and f32 with its derivation ([`fresnel`]), and the colour
//! science of the spectral reference colours — CIE 1931, D65, sRGB, CIEDE2000, effective
//! channel indices ([`color`]) — and what light does inside a material at a scene's size:
//! transparent, tinted or opaque, and the colour of its volume ([`appearance`]).
//!
//! ```no_run
//! use nklut_optics::db::Database;
//! use nklut_optics::fresnel::exact;
//! use nklut_optics::spectrum::{index_at, Channels};
//!
//! let db = Database::open(None)?; // refractiveindex/database, or NKLUT_DB
//! let gold = db.read_page(&db.catalog()?.find("3d/metals/gold").unwrap().data)?;
//! for nm in Channels::default().nanometres() {
//!     let at = index_at(&gold, nm)?;
//!     let f = exact(at.n, at.k, 0.5); // F at cos θ = 0.5 (60°)
//!     println!("{nm} nm: n = {:.3}, k = {:.3}, F(60°) = {f:.4}", at.n, at.k);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Modules follow the data, and every import points one way — a module uses only modules
//! before it in this order (the workspace's `tests/module_order.rs` checks it): `db` →
//! `spectrum` → `fresnel` → `color` → `appearance`. Leaves any module may use: `encoding` (the sRGB
//! transfer function, texel encodings and centres), `minimise` (Brent's 1D minimiser),
//! `atomic` (files replaced whole) and `memo` (results remembered between the commands of
//! one output folder, in plain files).
//!
//! "SPEC §n" in comments is section n of `docs/SPEC.md` in the nklut repository.

// `!(a <= b)` is written where a NaN must take the branch that `a > b` would skip: the
// comparison's whole point, not a style to refactor.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod appearance;
pub mod atomic;
pub mod color;
pub mod db;
pub mod encoding;
pub mod fresnel;
pub mod memo;
pub mod minimise;
pub mod spectrum;
