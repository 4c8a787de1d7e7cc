//! `luts/manifest.json` and `luts/README.md`: everything an engine needs to use the
//! textures without this code (SPEC §7). Plain serde structs; `Vec`s only, so the JSON
//! has a stable order, and no timestamps. Per row it carries F0 (exact Fresnel at
//! normal incidence, SPEC §5.1: ((n − 1)² + k²)/((n + 1)² + k²) per channel), the error
//! figures of `accuracy` (their maximum includes θ = 90°, the silhouette) and the
//! recommended size × encoding (`accuracy::recommend`).

use serde::Serialize;

use crate::output::Table;
use nklut_optics::color;
use nklut_optics::db::Reason;
use nklut_optics::spectrum::{Channels, CHANNEL_NAMES};

use super::accuracy::{Choice, LutError, RecommendationBound};
use super::texel::Encoding;
use super::{Layout, Source};

/// Bumped when a field changes meaning or disappears (2: `channels` became
/// `channel_wavelengths`, per-set `color_meaning`, per-row (n, k) and data file, `color`;
/// 3: `max_absolute` includes θ = 0° and 90°, per-row `f0`, `f0_source`, `recommended`,
/// `grazing_absolute` and the top-level `recommendation`).
pub const FORMAT_VERSION: u32 = 3;

/// How to read the 16-bit PNGs without losing bits.
pub const SIXTEEN_BIT_PNG_NOTE: &str = "unorm16 PNGs store 16 bits per channel, big-endian as PNG requires. Many loaders silently reduce them to 8 bits: Pillow (PIL) opens 16-bit RGB as 8-bit 'RGB', OpenCV's default cv2.imread flag converts to 8 bits. Read them with a 16-bit path, e.g. Python cv2.imread(path, cv2.IMREAD_UNCHANGED) (uint16, channels in B G R order: reverse them), pypng png.Reader(filename=path).asDirect(), or Rust image/png crates (Rgb16); check that the values you get go up to 65535 and divide by 65535.";

#[derive(Clone, Debug, Serialize)]
pub struct Manifest {
    pub format_version: u32,
    pub generator: String,
    /// N, texels per row (the texture width).
    pub size: usize,
    pub sampling: Sampling,
    /// The channel wavelengths of the `three-channel` and `effective` sources (the
    /// `spectral` source's channels are sRGB primaries, see `textures[].color_meaning`).
    pub channel_wavelengths: Vec<ChannelInfo>,
    /// The colour science behind the `spectral` source and the colour chunks of the PNGs.
    pub color: ColorInfo,
    /// Reading the unorm16 PNGs.
    pub sixteen_bit_png: String,
    pub row_order: String,
    pub error: ErrorDefinition,
    /// How `rows[].recommended` is chosen.
    pub recommendation: RecommendationDefinition,
    pub sources: Vec<Described>,
    pub encodings: Vec<EncodingInfo>,
    pub layouts: Vec<Described>,
    pub textures: Vec<TextureSet>,
    /// Page ids the catalog lists more than once (same data); each is baked once, as the
    /// first entry in catalog order.
    pub duplicate_catalog_pages: Vec<String>,
    /// The tables next to `luts/` (written by `nklut ingest`), column by column; only
    /// those present when the bake ran.
    pub tables: Vec<TableDoc>,
}

/// The spectral reference colour's definition and the PNG colour tagging.
#[derive(Clone, Debug, Serialize)]
pub struct ColorInfo {
    pub spectral_reference: String,
    pub observer: String,
    pub illuminant: String,
    /// XYZ (Y of the illuminant = 1) → linear sRGB, row-major: RGB = M · XYZ.
    pub xyz_to_linear_srgb: [[f64; 3]; 3],
    /// The illuminant's XYZ over the integration grid (Y = 1); M maps it to (1, 1, 1).
    pub white_xyz: [f64; 3],
    pub primaries: String,
    pub png_chunks: String,
}

/// An (n, k) of one channel.
#[derive(Clone, Debug, Serialize)]
pub struct ChannelIndexEntry {
    pub channel: String,
    /// The wavelength the index was evaluated at; null for fitted indices (they describe
    /// a whole channel of the spectral reference, not one wavelength).
    pub wavelength_nm: Option<f64>,
    pub n: f64,
    pub k: f64,
}

/// One entry per channel; `channels` gives the wavelengths of a three-wavelength index.
pub fn index_entries(index: &nklut_optics::spectrum::ChannelIndex, channels: Option<&Channels>) -> Vec<ChannelIndexEntry> {
    let wavelengths = channels.map(|c| c.nanometres());
    CHANNEL_NAMES
        .iter()
        .enumerate()
        .map(|(c, name)| ChannelIndexEntry {
            channel: name.to_string(),
            wavelength_nm: wavelengths.map(|w| w[c]),
            n: index[c].n,
            k: index[c].k,
        })
        .collect()
}

/// What R, G and B of a texture set mean.
pub fn color_meaning(source: Source, channels: &Channels) -> String {
    let [r, g, b] = channels.nanometres();
    match source {
        Source::ThreeChannel => format!(
            "R, G, B = exact Fresnel reflectance of the page's (n, k) at the single wavelengths {r} nm, {g} nm, {b} nm (rows[].index_three_channel); not a colorimetric colour"
        ),
        Source::Effective => "R, G, B = exact Fresnel reflectance of the per-channel (n, k) fitted to the spectral reference colour (rows[].index_fitted); approximates the linear sRGB colour of the `spectral` source".into(),
        Source::Spectral => "R, G, B = the spectral reference colour in linear sRGB (Rec.709 primaries, D65 white; color.xyz_to_linear_srgb), integrated over 360-830 nm: the channels are colour primaries, not wavelengths".into(),
    }
}

/// The colour science of the spectral source, from the weights the colour module uses.
pub fn color_info() -> ColorInfo {
    let weights = color::spectral_weights();
    ColorInfo {
        spectral_reference: "RGB(theta) = M . sum over lambda = 360..830 nm (1 nm) of R(theta, lambda) S(lambda) [xbar ybar zbar](lambda) / sum S ybar, R = exact unpolarised Fresnel reflectance of n(lambda) + i k(lambda) (docs/colors.md)"
            .into(),
        observer: "CIE 1931 2 degree colour-matching functions, 1 nm".into(),
        illuminant: "CIE standard illuminant D65 (5 nm table, linearly interpolated to 1 nm)".into(),
        xyz_to_linear_srgb: weights.xyz_to_rgb,
        white_xyz: weights.white_xyz,
        primaries: "IEC 61966-2-1 (sRGB = Rec.709) primaries red (0.64, 0.33), green (0.30, 0.60), blue (0.15, 0.06); M is derived from them and white_xyz, so a perfect reflector maps to (1, 1, 1)"
            .into(),
        png_chunks: super::files::PNG_CHUNKS_NOTE.into(),
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Sampling {
    pub convention: String,
    pub u: String,
    pub texel_centre: String,
    pub atlas_v: String,
    pub filter: String,
    pub address_mode: String,
    pub mipmaps: String,
    pub image_origin: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct ChannelInfo {
    pub channel: String,
    pub image_channel: String,
    pub wavelength_nm: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ErrorDefinition {
    pub definition: String,
    pub samples: usize,
    pub quadrature: String,
    pub error_vs_exact: String,
    /// θ nodes of `error_vs_spectral` (its own rule, see the text).
    pub spectral_samples: usize,
    pub error_vs_spectral: String,
}

/// The rule behind `rows[].recommended`.
#[derive(Clone, Debug, Serialize)]
pub struct RecommendationDefinition {
    pub definition: String,
    pub bound: RecommendationBound,
    /// The texture widths tried.
    pub sizes: Vec<usize>,
    pub cost: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct Described {
    pub name: String,
    pub description: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct EncodingInfo {
    pub name: String,
    pub file_format: String,
    pub bits_per_channel: u32,
    pub color_space: String,
    pub decode: String,
    pub out_of_range: String,
    pub gpu_formats: String,
}

/// One source × encoding: its files and the per-row figures.
#[derive(Clone, Debug, Serialize)]
pub struct TextureSet {
    pub source: String,
    pub encoding: String,
    pub color_space: String,
    /// What R, G and B hold in this set.
    pub color_meaning: String,
    /// The PNG colour chunks of this set's files (null for EXR).
    pub png_color_chunks: Option<String>,
    /// Texels clamped to [0, 1] over the whole set (0 for float encodings).
    pub clamped_texels: usize,
    pub atlas: Option<ImageFile>,
    pub strips: Option<StripFolder>,
    pub rows: Vec<RowEntry>,
}

#[derive(Clone, Debug, Serialize)]
pub struct ImageFile {
    /// Relative to the folder holding this manifest.
    pub file: String,
    pub width: usize,
    pub height: usize,
    pub clamped_texels: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct StripFolder {
    pub folder: String,
    pub width: usize,
    pub height: usize,
    pub file_name_rule: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct RowEntry {
    /// The atlas row (v = (row + 0.5)/rows).
    pub row: usize,
    pub page: String,
    pub names: Vec<String>,
    pub kind: String,
    /// The page's data file, relative to the database's data/ folder.
    pub data_file: String,
    /// (n, k) at the channel wavelengths: `exact` of it is the three-channel source and
    /// the reference of `error_vs_exact`.
    pub index_three_channel: Vec<ChannelIndexEntry>,
    /// The effective (n, k) per channel (the effective source); null only for rows baked
    /// through the library API without it.
    pub index_fitted: Option<Vec<ChannelIndexEntry>>,
    /// F0 per channel: exact Fresnel (SPEC 5.1) of `index_three_channel` at normal
    /// incidence (cos θ = 1), the reference of `error_vs_exact` there. Not the last texel,
    /// which holds F at cos θ = 1 − 0.5/N.
    pub f0: [f64; 3],
    /// F of this set's source at normal incidence: `f0` for three-channel, exact Fresnel of
    /// `index_fitted` for effective, the spectral reference colour at θ = 0 for spectral
    /// (may exceed 1); null where the bake did not compute it.
    pub f0_source: Option<[f64; 3]>,
    /// Sizes × encodings that reproduce this source's exact curve within
    /// `recommendation.bound`: per encoding the smallest width that does, cheapest first
    /// (`recommendation.cost`); the first is the recommendation. Empty when none does;
    /// null for the spectral source (see `recommendation.definition`).
    pub recommended: Option<Vec<Choice>>,
    /// This page's strip, relative to the manifest; null without the strip layout.
    pub strip_file: Option<String>,
    /// Texels of this row with a channel clamped to [0, 1].
    pub clamped_texels: usize,
    pub error_vs_exact: LutError,
    /// Against the page's spectral reference colour (see `error.error_vs_spectral`); null
    /// only for rows baked without one (the library API), never from `nklut bake`.
    pub error_vs_spectral: Option<LutError>,
    /// Share of the luminance weight ∫ S(λ) ȳ(λ) dλ over 360-830 nm at wavelengths outside
    /// the page's data, where the spectral reference holds the nearest measured n and k
    /// (a fraction; 0 when the data cover the whole grid; null without a spectral
    /// reference).
    pub extrapolated_share: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct TableDoc {
    /// Relative to the folder holding this manifest.
    pub files: Vec<String>,
    pub rows: String,
    pub columns: Vec<Described>,
    /// Reason codes and their meaning, for tables that have a `reason` column.
    pub codes: Vec<Described>,
}

pub fn sampling() -> Sampling {
    Sampling {
        convention: "Each row is F(cos_theta) for one page: N texels over cos_theta in [0, 1], texel i holding F at its centre \
                     cos_theta = (i + 0.5)/N. Sampling at u = cos_theta with linear filtering and clamp-to-edge reproduces the \
                     LUT model (SPEC 5.7) exactly: between centres F is linear in cos_theta, beyond the outer centres it is held."
            .into(),
        u: "u = cos_theta".into(),
        texel_centre: "texel i centre = (i + 0.5)/N".into(),
        atlas_v: "v = (row + 0.5)/rows (exact row centres, so vertical filtering never mixes pages)".into(),
        filter: "linear (magnification and minification)".into(),
        address_mode: "clamp-to-edge in u and v".into(),
        mipmaps: "none (sample level 0)".into(),
        image_origin: "row 0 is the first row stored in the file (the top of the PNG/EXR); upload rows in file order, do not flip".into(),
    }
}

pub fn channels(channels: &Channels) -> Vec<ChannelInfo> {
    CHANNEL_NAMES
        .iter()
        .zip(["R", "G", "B"])
        .zip(channels.nanometres())
        .map(|((name, image), nm)| ChannelInfo { channel: name.to_string(), image_channel: image.into(), wavelength_nm: nm })
        .collect()
}

/// `samples`: θ samples of the midpoint rule (`error_vs_exact`); `spectral_samples`: nodes
/// of the colour module's angle quadrature (`error_vs_spectral`).
pub fn error_definition(samples: usize, spectral_samples: usize) -> ErrorDefinition {
    ErrorDefinition {
        definition: "Per channel, with F_lut the LUT model on the decoded texels (decode, linear filtering, clamp-to-edge): \
                     mean_relative = mean of |F_lut - F_ref| / F_ref over theta uniform in [0, 90] degrees (samples with \
                     F_ref = 0 excluded and counted); max_absolute = max |F_lut - F_ref| over the samples and the two ends \
                     theta = 0 and theta = 90 degrees; grazing_absolute = |F_lut - F_ref| at theta = 90 degrees (cos_theta = 0, \
                     the silhouette, where clamp(dot(N, V), 0, 1) gives 0, the sampler returns texel 0 and exact F is 1): \
                     for steep rows the largest error of all. *_rgb: mean (relative) or max (absolute) of the three channels \
                     (SPEC 6)."
            .into(),
        samples,
        quadrature: format!(
            "midpoint rule: theta_j = (j + 0.5) * 90 deg / {samples}, j = 0..{samples}-1 (M = clamp(32 N, 4096, 262144)), \
             plus theta = 90 and 0 degrees with weight 0 (in the maximum, not in the mean)"
        ),
        error_vs_exact: "F_ref = exact Fresnel (SPEC 5.1) of the page's three-channel (n, k) at the channel wavelengths; for \
                         the three-channel source this is the sampling + quantisation error alone"
            .into(),
        spectral_samples,
        error_vs_spectral: format!(
            "F_ref = the page's spectral reference colour RGB(theta) in linear sRGB (SPEC 4; 471 wavelengths, 360-830 nm, \
             may exceed 1), per channel. Because each F_ref value is a 471-wavelength sum it is not evaluated on the \
             midpoint rule above but on the colour module's angle quadrature: composite Gauss-Legendre in theta, \
             {} equal panels of [0, 90] degrees x {} nodes = {spectral_samples} nodes, mean_relative weighted by the \
             Gauss-Legendre weights (renormalised over the nodes with F_ref > 0), max_absolute the largest difference at \
             those nodes and at theta = 0 and 90 degrees (a lower bound of the true maximum between nodes). The rule resolves errors that are smooth in theta, such as \
             the three-channel index approximation (SPEC 4) and the effective fit residual (about 4 significant \
             digits, as tested in the colour module); it does not resolve the texel-scale sampling error between texel \
             centres, which error_vs_exact measures densely. For the spectral source in an integer encoding it \
             includes the clamping of values above 1",
            color::angle_average::PANELS,
            color::angle_average::NODES
        ),
    }
}

/// The rule of `rows[].recommended` for a bake of `size` texels per row.
pub fn recommendation_definition(size: usize) -> RecommendationDefinition {
    let bound = super::accuracy::RECOMMENDATION_BOUND;
    RecommendationDefinition {
        definition: format!(
            "For each encoding, the smallest width N among `sizes` whose texture reproduces the set's source curve with \
             max_absolute_rgb <= {} (theta = 90 degrees included) and mean_relative_rgb <= {}, measured as error_vs_exact \
             is, on the same rule (error.samples midpoint nodes and both ends, for every width), against the exact \
             Fresnel curve of the source: index_three_channel for three-channel, index_fitted for effective (so at the \
             bake's own N the figures equal error_vs_exact of the three-channel sets). Null for the spectral source, whose reference is a 471-wavelength sum per angle: \
             use its page's effective row, whose curve is fitted to it. Bake again with --size N to get a recommended \
             width other than this one.",
            bound.max_absolute, bound.mean_relative
        ),
        bound,
        sizes: super::accuracy::candidate_sizes(size),
        cost: "gpu_bytes = 4 channels (RGBA: WebGPU and Vulkan have no 3-channel formats) x bytes per channel x N; \
               cheapest first, then the smaller max_absolute_rgb"
            .into(),
    }
}

pub fn encoding_info(encoding: Encoding) -> EncodingInfo {
    EncodingInfo {
        name: encoding.name().into(),
        file_format: if encoding.is_float() {
            "OpenEXR, RGB channels R G B, ZIP16 compression".into()
        } else {
            format!("PNG, RGB; {}", super::files::png_color_chunks(encoding))
        },
        bits_per_channel: encoding.bits_per_channel(),
        color_space: encoding.color_space().into(),
        decode: encoding.decode_rule().into(),
        out_of_range: if encoding.is_float() {
            "kept (F > 1 from the spectral source is stored as is)"
        } else {
            "clamped to [0, 1] before quantising (round to nearest); counted in clamped_texels"
        }
        .into(),
        gpu_formats: encoding.gpu_formats().into(),
    }
}

pub fn source_info(source: Source) -> Described {
    Described { name: source.name().into(), description: source.description().into() }
}

pub fn layout_info(layout: Layout) -> Described {
    Described { name: layout.name().into(), description: layout.description().into() }
}

/// A table's documentation from its own column descriptions (the names and units
/// `nklut ingest` writes).
pub fn table_doc(table: &Table, files: &[&str], rows: &str, codes: Vec<Described>) -> TableDoc {
    TableDoc {
        files: files.iter().map(|f| f.to_string()).collect(),
        rows: rows.into(),
        columns: table.columns.iter().map(|c| Described { name: c.name.clone(), description: c.description.clone() }).collect(),
        codes,
    }
}

/// The `excluded.csv` reason codes (SPEC §2).
pub fn reason_codes() -> Vec<Described> {
    Reason::ALL.iter().map(|r| Described { name: r.code().into(), description: r.meaning().into() }).collect()
}

/// `luts/README.md`: the manifest's conventions in prose, for people.
pub fn readme(manifest: &Manifest) -> String {
    let mut s = String::new();
    let mut line = |text: &str| {
        s.push_str(text);
        s.push('\n');
    };
    line("# nklut Fresnel lookup textures");
    line("");
    line("Generated by `nklut bake`; `manifest.json` holds the same facts in machine-readable form, plus per-row errors.");
    line("");
    line("## Sampling");
    line("");
    let sm = &manifest.sampling;
    for text in [&sm.convention, &sm.u, &sm.texel_centre, &sm.atlas_v, &sm.filter, &sm.address_mode, &sm.mipmaps, &sm.image_origin] {
        line(&format!("- {text}"));
    }
    line(&format!("- N = {} texels per row.", manifest.size));
    line(&format!("- Rows (atlas) and strips: {}", manifest.row_order));
    if !manifest.duplicate_catalog_pages.is_empty() {
        line(&format!("- Listed twice in the catalog, baked once: {}", manifest.duplicate_catalog_pages.join(", ")));
    }
    line("");
    line("## Channels");
    line("");
    line("What R, G and B mean depends on the source (manifest `textures[].color_meaning`):");
    line("");
    for d in &manifest.sources {
        if let Some(set) = manifest.textures.iter().find(|t| t.source == d.name) {
            line(&format!("- `{}`: {}", d.name, set.color_meaning));
        }
    }
    line("");
    line("Each row in the manifest (`textures[].rows[]`) names its page id, data file, the (n, k) at the channel wavelengths (`index_three_channel`) and the fitted per-channel (n, k) (`index_fitted`).");
    line("");
    line("## Colour");
    line("");
    let c = &manifest.color;
    line(&format!("- Spectral reference: {}.", c.spectral_reference));
    line(&format!("- Observer: {}; illuminant: {}.", c.observer, c.illuminant));
    line(&format!("- {}.", c.primaries));
    let m = &c.xyz_to_linear_srgb;
    line("- XYZ -> linear sRGB (RGB = M XYZ, white Y = 1):");
    line("");
    line("  ```");
    for row in m {
        line(&format!("  {:>20} {:>20} {:>20}", row[0], row[1], row[2]));
    }
    line("  ```");
    line("");
    line(&format!("- White XYZ: {:?}.", c.white_xyz));
    line(&format!("- PNG colour chunks: {}", c.png_chunks));
    line(&format!("- 16-bit PNGs: {}", manifest.sixteen_bit_png));
    line("");
    line("## Sources, encodings, layouts");
    line("");
    for d in manifest.sources.iter().chain(&manifest.layouts) {
        line(&format!("- `{}`: {}", d.name, d.description));
    }
    for e in &manifest.encodings {
        line(&format!(
            "- `{}`: {} {}-bit, {}; decode {}; out of range: {}; GPU formats: {}",
            e.name, e.file_format, e.bits_per_channel, e.color_space, e.decode, e.out_of_range, e.gpu_formats
        ));
    }
    line("");
    line("## Files");
    line("");
    for t in &manifest.textures {
        let atlas = t.atlas.as_ref().map(|a| format!("atlas `{}` ({}×{})", a.file, a.width, a.height));
        let strips = t.strips.as_ref().map(|f| format!("strips in `{}/` ({}×{} each)", f.folder, f.width, f.height));
        let files: Vec<String> = atlas.into_iter().chain(strips).collect();
        line(&format!("- {} / {}: {}; {} clamped texels", t.source, t.encoding, files.join(", "), t.clamped_texels));
    }
    line("");
    line("## Error figures (manifest `rows[].error_vs_exact`, `rows[].error_vs_spectral`)");
    line("");
    line(&manifest.error.definition);
    line(&format!("Quadrature: {}.", manifest.error.quadrature));
    line(&format!("Reference: {}.", manifest.error.error_vs_exact));
    line(&format!("`error_vs_spectral`: {}.", manifest.error.error_vs_spectral));
    line("");
    line("Each row also names `f0` (exact F at normal incidence per channel; the last texel is F at cos_theta = 1 - 0.5/N, not F0) and `f0_source` (the set's source at normal incidence).");
    line("");
    line("## Recommended size and encoding (manifest `rows[].recommended`)");
    line("");
    line(&manifest.recommendation.definition);
    line(&format!("Widths tried: {:?}. Cost: {}.", manifest.recommendation.sizes, manifest.recommendation.cost));
    line("");
    line("## Tables (paths relative to this folder)");
    if manifest.tables.is_empty() {
        line("");
        line("None: no `nklut ingest` table was next to this folder when it was baked; the manifest's rows hold each page's (n, k).");
    }
    for t in &manifest.tables {
        line("");
        line(&format!("### {}", t.files.join(", ")));
        line("");
        line(&format!("One row per {}.", t.rows));
        line("");
        line("| column | meaning and unit |");
        line("|---|---|");
        for c in &t.columns {
            line(&format!("| `{}` | {} |", c.name, c.description));
        }
        if !t.codes.is_empty() {
            line("");
            line("| reason code | meaning |");
            line("|---|---|");
            for c in &t.codes {
                line(&format!("| `{}` | {} |", c.name, c.description));
            }
        }
    }
    s
}
