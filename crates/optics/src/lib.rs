//! Optical constants of the refractiveindex.info database, turned into what a renderer
//! needs, with no heavier dependency than a YAML reader: the database reader ([`db`]),
//! n and k at any wavelength and per colour channel ([`spectrum`]), every Fresnel method
//! of the pipeline in f64 and f32 with its derivation ([`fresnel`]), and the colour
//! science of the spectral reference colours — CIE 1931, D65, sRGB, CIEDE2000, effective
//! channel indices ([`color`]) — and what light does inside a material at a scene's size:
//! transparent, tinted or opaque, and the colour of its volume ([`appearance`]).
//!
//! The main paths, on a page given as text (the database's files are this YAML):
//!
//! ```
//! use nklut_optics::color::{reflectance_rgb, sample_spectrum};
//! use nklut_optics::db::parse_page;
//! use nklut_optics::fresnel::{exact, schlick, Encoding, Lut, LutSpec};
//! use nklut_optics::spectrum::{index_at, Channels};
//!
//! // A page: wavelength (µm), n, k per row.
//! let text = "DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.5 0.0\n        0.90 1.5 0.0\n";
//! let page = parse_page("example/glass.yml", text)?;
//!
//! // page → (n, k) at each channel's wavelength → F(θ).
//! for nm in Channels::default().nanometres() {
//!     let at = index_at(&page, nm)?;
//!     let f0 = exact(at.n, at.k, 1.0); // θ = 0: ((n − 1)/(n + 1))² = 0.04
//!     assert!((f0 - 0.04).abs() < 1e-12);
//!     let at_60 = exact(at.n, at.k, 0.5); // θ = 60°
//!     assert!(schlick(f0, 0.5) < at_60); // Schlick's approximation falls short here
//! }
//!
//! // The spectral colour: the page on the 1 nm grid, lit by D65, seen by the CIE 1931
//! // observer, in linear sRGB. A flat spectrum is white light times F.
//! let (spectrum, _extrapolated) = sample_spectrum(&page);
//! for channel in reflectance_rgb(&spectrum, 1.0) {
//!     assert!((channel - 0.04).abs() < 1e-4);
//! }
//!
//! // A lookup texture of 256 texels over cos θ, sampled as a GPU's linear filter does.
//! let lut = Lut::bake(LutSpec::new(256, Encoding::F32), |c| exact(1.5, 0.0, c));
//! assert!((lut.sample(1.0) - 0.04).abs() < 1e-5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The database itself, at a folder the program chooses (the library reads no environment
//! variable):
//!
//! ```no_run
//! use nklut_optics::db::Database;
//! use nklut_optics::fresnel::exact;
//! use nklut_optics::spectrum::{index_at, Channels};
//!
//! let db = Database::open("refractiveindex/database")?;
//! let gold = db.read_page(&db.catalog()?.find("3d/metals/gold").ok_or("no gold")?.data)?;
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
//! and `memo` (results remembered between the commands of one output folder, as bytes: the
//! program that runs the commands keeps the files; this crate writes no file).
//!
//! "SPEC §n" in comments is section n of `docs/SPEC.md` in the nklut repository.

// `!(a <= b)` is written where a NaN must take the branch that `a > b` would skip: the
// comparison's whole point, not a style to refactor.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![deny(missing_docs)]

pub mod appearance;
pub mod color;
pub mod db;
pub mod encoding;
pub mod fresnel;
pub mod memo;
pub mod minimise;
pub mod spectrum;

/// The README's example, compiled and run with the doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
