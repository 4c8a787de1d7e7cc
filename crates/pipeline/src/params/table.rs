//! `engine_params.{csv,parquet,json}`: one row per kept page, every column described in
//! `engine_params.columns.json` with its unit, its formula and the engine fields it goes
//! into (so a report or a script can build a "paste it in" panel from the table alone).

use super::caveats::{transparent_depth_limit_m, Caveat, LARGE_OBJECT_KEEPS, LARGE_OBJECT_M, LOW_K};
use super::models::{EXPONENT_RANGE, GULBRANDSEN_MAX_R};
use super::mtlx::{display_names, DISPLAY_CHARS};
use super::page::{EngineModel, EngineParams, C_LINE_NM, D_LINE_NM, F_LINE_NM};
use super::ExportSettings;
use crate::ingest::KeptPage;
use crate::output::Table;
use nklut_optics::appearance::{SCENE_SCALE_M, THIN_LIMIT_M};
use nklut_optics::color::angle_average::{NODES, PANELS};
use nklut_optics::color::srgb::hex_swatch;

/// Column suffixes of the per-channel columns (red, green, blue).
pub const SUFFIXES: [&str; 3] = ["r", "g", "b"];

/// The angle rule of the fits and errors, in words.
fn quadrature_words() -> String {
    format!("theta uniform in [0, 90] deg, {PANELS}x{NODES}-node composite Gauss-Legendre")
}

fn per_channel(table: &mut Table, rows: &[EngineParams], stem: &str, meaning: &str, value: impl Fn(&EngineParams, usize) -> f64) {
    for (c, suffix) in SUFFIXES.iter().enumerate() {
        table.float(&format!("{stem}_{suffix}"), meaning, rows.iter().map(|p| value(p, c)).collect());
    }
}

fn optional(table: &mut Table, rows: &[EngineParams], name: &str, meaning: &str, value: impl Fn(&EngineParams) -> Option<f64>) {
    table.optional_float(name, meaning, rows.iter().map(value).collect());
}

/// The table of `rows` (one per page of `kept`, same order), with the exports' `settings`.
pub fn engine_params_table(kept: &[KeptPage], rows: &[EngineParams], caveats: &[Vec<Caveat>], settings: &ExportSettings) -> Table {
    let mut table = Table::new();
    table
        .text("page", "page id shelf/book/page", kept.iter().map(|p| p.id()).collect())
        .text(
            "display_name",
            &format!("the short name the exports give the material: the catalog's page name on the 3d shelf, else the book's name and the page (at most {DISPLAY_CHARS} characters); a name two pages share gains the book's name, then the page id"),
            display_names(kept),
        )
        .text("synonyms", "the material's names, '; '-separated (about.yml NAMES, as materials.csv's names)", kept.iter().map(|p| p.names.join("; ")).collect())
        .text("data_file", "data file relative to database/data/", kept.iter().map(|p| p.page.data.clone()).collect())
        .text("kind", "conductor or dielectric (as in materials.csv)", kept.iter().map(|p| p.material.kind.as_str().into()).collect());
    appearance_columns(&mut table, rows, settings);
    table.text(
        "caveats",
        &format!(
            "where the data mislead, '; '-separated 'code: sentence with the numbers' (empty for most pages): conductor_passes_light (a conductor by the k >= 1 rule that some channel passes, classed by its depths), opaque_low_k (opaque, yet k < {LOW_K} everywhere in 390-700 nm: a thin-film model's k), shared_data_file (a main-shelf page whose data file is another book's and listed under several books), transparent_absorbs (transparent, but a {LARGE_OBJECT_M} m piece keeps less than {LARGE_OBJECT_KEEPS} of a channel: its absorption depth is under {:.2} m, and a large piece looks tinted)",
            transparent_depth_limit_m()
        ),
        caveats.iter().map(|list| list.iter().map(Caveat::line).collect::<Vec<_>>().join("; ")).collect(),
    );
    f0_columns(&mut table, rows);
    model_columns(&mut table, rows);
    dielectric_columns(&mut table, rows);
    error_columns(&mut table, rows);
    table
}

fn appearance_columns(table: &mut Table, rows: &[EngineParams], settings: &ExportSettings) {
    table.text(
        "appearance",
        &format!(
            "what light does inside the material at a scene's size, from the absorption depths: metal (a conductor absorbed within the thin limit in every channel; a conductor that a channel passes is classed by its depths); opaque (every channel absorbed within {} mm); tinted (some channel within {} m, the largest size of the {}-{} m scene scale); transparent (every channel's depth at least {} m). The exports follow it (docs/engine-integration.md)",
            THIN_LIMIT_M * 1e3,
            SCENE_SCALE_M.1,
            SCENE_SCALE_M.0,
            SCENE_SCALE_M.1,
            SCENE_SCALE_M.1
        ),
        rows.iter().map(|p| p.volume.appearance.name().into()).collect(),
    );
    for (c, suffix) in SUFFIXES.iter().enumerate() {
        optional(
            table,
            rows,
            &format!("absorption_depth_m_{suffix}"),
            "absorption depth lambda/(4 pi k) at the channel wavelength (m): the distance over which light falls to 1/e (Beer-Lambert); empty where k = 0",
            |p| Some(p.volume.depths_m[c]).filter(|d| d.is_finite()),
        );
    }
    optional(
        table,
        rows,
        "attenuation_distance_m",
        "tinted materials: the smallest channel absorption depth D (m), the distance of the volume colour. Paste into: glTF KHR_materials_volume attenuationDistance, OpenPBR transmission_depth, Unity HDRP Absorption Distance",
        |p| p.volume.attenuation.map(|a| a.distance_m),
    );
    for (c, suffix) in SUFFIXES.iter().enumerate() {
        optional(
            table,
            rows,
            &format!("attenuation_colour_{suffix}"),
            "tinted materials: the colour white light takes after attenuation_distance_m, linear sRGB of the spectral transmittance exp(-4 pi k(lambda) D / lambda) under D65 and the CIE 1931 observer. Paste into: glTF attenuationColor, OpenPBR transmission_color, Unity HDRP Transmittance Color",
            |p| p.volume.attenuation.map(|a| a.colour[c]),
        );
    }
    table.text(
        "attenuation_hex",
        "attenuation colour as 8-bit sRGB #rrggbb (empty unless tinted)",
        rows.iter().map(|p| p.volume.attenuation.map_or(String::new(), |a| hex_swatch(a.colour))).collect(),
    );
    table.float(
        "export_roughness",
        &format!("the roughness every export gives the material: {}", settings.describe()),
        rows.iter().map(|p| settings.roughness(p.volume.appearance)).collect(),
    );
}

fn f0_columns(table: &mut Table, rows: &[EngineParams]) {
    per_channel(
        table,
        rows,
        "f0_linear",
        "F0: spectral reference reflectance at normal incidence, linear Rec.709/sRGB primaries, D65 (may leave [0,1]). Paste into: \
         OpenPBR base_color (metals, base_metalness 1), Blender Principled Base Color (metallic 1), glTF baseColorFactor (metallic 1), \
         Unreal Base Color (Metallic 1), MaterialX generalized_schlick_bsdf color0",
        |p, c| p.f0[c],
    );
    per_channel(
        table,
        rows,
        "f0_acescg",
        "F0 in ACEScg (linear AP1 primaries, ACES white ~D60): f0_linear adapted from D65 with the Bradford transform (the matrix \
         of MaterialX's srgb_texture_to_acescg and OpenColorIO's ACES configs). Paste into: ACEScg pipelines (Arnold/Maya/Houdini with OCIO ACES)",
        |p, c| p.f0_acescg[c],
    );
    for (c, suffix) in SUFFIXES.iter().enumerate() {
        table.integer(
            &format!("f0_srgb8_{suffix}"),
            "F0 for 8-bit sRGB colour pickers: round(255 * srgb_encode(clamp(f0_linear, 0, 1))), each channel clamped on its own \
             (an out-of-gamut colour shifts hue; see f0_out_of_gamut). Paste into: colour pickers that take sRGB 0-255",
            rows.iter().map(|p| i64::from(p.f0_srgb8[c])).collect(),
        );
    }
    table.text("f0_srgb_hex", "the same 8-bit sRGB colour as #rrggbb", rows.iter().map(|p| hex_swatch(p.f0)).collect());
    table.boolean(
        "f0_out_of_gamut",
        "f0_linear has a channel outside [0,1] (clamped in f0_srgb8 and in the MaterialX/glTF exports)",
        rows.iter().map(|p| p.f0_out_of_gamut()).collect(),
    );
    table.boolean(
        "f0_acescg_out_of_gamut",
        "f0_acescg has a channel outside [0,1]",
        rows.iter().map(|p| p.f0_acescg_out_of_gamut()).collect(),
    );
}

fn model_columns(table: &mut Table, rows: &[EngineParams]) {
    per_channel(
        table,
        rows,
        "f82_tint",
        "F82 tint = F_spectral(mu_bar) / F_Schlick(F0, mu_bar), mu_bar = cos(theta) = 1/7 (81.8 deg); model F = F_Schlick(mu) - b mu (1-mu)^6 \
         (Hoffman). Paste into: OpenPBR specular_color (metals), Adobe Standard Material specular edge color, Blender 4 Principled \
         Specular Tint (metallic 1; Blender clamps it to [0,1], see f82_tint_above_one), MaterialX generalized_schlick_bsdf color82 with exponent 5",
        |p, c| p.f82[c].tint,
    );
    table.text(
        "f82_tint_hex",
        "the F82 tint as 8-bit sRGB #rrggbb (each channel clamped to [0, 1]), as Adobe publishes it",
        rows.iter().map(|p| hex_swatch(p.f82.map(|f| f.tint))).collect(),
    );
    per_channel(
        table,
        rows,
        "f82_coeff_b",
        "b of the F82-tint model, b = F_Schlick(mu_bar) (1 - tint) / (mu_bar (1-mu_bar)^6): the coefficient a shader evaluates (formerly f82_b_*)",
        |p, c| p.f82[c].b,
    );
    table.boolean(
        "f82_tint_above_one",
        "some f82_tint channel exceeds 1 (Blender and OpenPBR UIs clamp it to 1; the exports clamp it)",
        rows.iter().map(|p| p.f82.iter().any(|f| f.tint > 1.0)).collect(),
    );
    per_channel(
        table,
        rows,
        "gulbrandsen_reflectivity",
        &format!(
            "Gulbrandsen 2014 reflectivity r = F0 clamped to [0, {GULBRANDSEN_MAX_R}] (as MaterialX artistic_ior clamps). Paste into: \
             MaterialX artistic_ior reflectivity, Autodesk Standard Surface / Arnold base_color (metalness 1, base 1) (formerly gulbrandsen_r_*)"
        ),
        |p, c| p.gulbrandsen[c].r,
    );
    per_channel(
        table,
        rows,
        "gulbrandsen_edge_tint",
        &format!(
            "Gulbrandsen 2014 edge tint g in [0,1], chosen so that exact Fresnel of (n(r,g), k(r,g)) best fits the spectral curve: \
             minimum of the mean over {} of ((F - F_spectral)/F_spectral)^2 (grid scan + Brent's method). Paste into: MaterialX \
             artistic_ior edge_color, Autodesk Standard Surface / Arnold specular_color (metalness 1, base 1) (formerly gulbrandsen_g_*)",
            quadrature_words()
        ),
        |p, c| p.gulbrandsen[c].g,
    );
    per_channel(
        table,
        rows,
        "generalized_schlick_color82",
        "Hoffman generalized Schlick color82 (with color0 = f0_linear, color90 = 1 and generalized_schlick_exponent): makes the model \
         equal the spectral curve at mu_bar = 1/7. Paste into: MaterialX generalized_schlick_bsdf color82",
        |p, c| p.generalized_schlick.color82[c],
    );
    table.float(
        "generalized_schlick_exponent",
        &format!(
            "the one exponent of MaterialX generalized_schlick_bsdf (a float input, shared by the channels), fitted in [{}, {}] to the \
             spectral curve over {} (relative least squares summed over channels; color82 follows the exponent)",
            EXPONENT_RANGE.0,
            EXPONENT_RANGE.1,
            quadrature_words()
        ),
        rows.iter().map(|p| p.generalized_schlick.exponent).collect(),
    );
    per_channel(
        table,
        rows,
        "fitted_n",
        "fitted per-channel refractive index n: exact Fresnel of (n, k) closest to the spectral curve over theta (relative least squares, \
         Levenberg-Marquardt started from Gulbrandsen's best (n, k); the effective_n of colors.csv, or a better minimum). Paste into: MaterialX conductor_bsdf ior, Blender Metallic BSDF (Physical Conductor) IOR, \
         pbrt/Mitsuba RGB conductor eta",
        |p, c| p.fitted[c].index.n,
    );
    per_channel(
        table,
        rows,
        "fitted_k",
        "fitted per-channel extinction coefficient k (same fit). Paste into: MaterialX conductor_bsdf extinction, Blender Metallic BSDF \
         Extinction, pbrt/Mitsuba RGB conductor k",
        |p, c| p.fitted[c].index.k,
    );
    for (c, suffix) in SUFFIXES.iter().enumerate() {
        table.boolean(
            &format!("fitted_at_bound_{suffix}"),
            "the fit of fitted_n, fitted_k ended on its search box (n in [1e-3, 100], k up to 100): a curve fit, not the material's optics; the exports paste channel_n, channel_k of this channel instead",
            rows.iter().map(|p| p.fitted[c].at_bound()).collect(),
        );
    }
    per_channel(table, rows, "channel_n", "n at the channel wavelength (three-wavelength index of materials.csv)", |p, c| {
        p.channel_index[c].n
    });
    per_channel(table, rows, "channel_k", "k at the channel wavelength (three-wavelength index of materials.csv)", |p, c| {
        p.channel_index[c].k
    });
}

fn dielectric_columns(table: &mut Table, rows: &[EngineParams]) {
    let d = |p: &EngineParams| p.dielectric;
    optional(
        table,
        rows,
        "n_d",
        &format!("dielectrics: n at the d line {D_LINE_NM} nm (empty for metals, and where the data do not reach the d line; then no gltf_ior model either). Paste into: glTF KHR_materials_ior ior, OpenPBR specular_ior, Blender IOR, Unreal refraction"),
        |p| d(p).map(|x| x.n_d),
    );
    optional(table, rows, "n_F", &format!("dielectrics: n at the F line {F_LINE_NM} nm (empty where the data do not reach it)"), |p| {
        d(p).and_then(|x| x.n_f)
    });
    optional(table, rows, "n_C", &format!("dielectrics: n at the C line {C_LINE_NM} nm (empty where the data do not reach it)"), |p| {
        d(p).and_then(|x| x.n_c)
    });
    optional(
        table,
        rows,
        "abbe_d",
        "dielectrics that transmit: Abbe number (n_d - 1)/(n_F - n_C); empty where n_F <= n_C (no normal dispersion), a line is missing, or the material is opaque (its light never travels far enough to disperse). Paste into: OpenPBR transmission_dispersion_abbe_number; glTF KHR_materials_dispersion dispersion = 20/abbe_d",
        |p| d(p).and_then(|x| x.abbe),
    );
    optional(
        table,
        rows,
        "gltf_ior_f0",
        "dielectrics: ((n_d - 1)/(n_d + 1))^2, the F0 a glTF viewer derives from KHR_materials_ior",
        |p| d(p).map(|x| x.gltf_f0),
    );
}

fn error_columns(table: &mut Table, rows: &[EngineParams]) {
    for model in EngineModel::ALL {
        let name = model.name();
        let error = |p: &EngineParams| p.error(model).copied();
        let applies = if model == EngineModel::GltfIor { " (every page but the metals; empty for metals)" } else { "" };
        optional(
            table,
            rows,
            &format!("{name}_de2000_mean"),
            &format!(
                "{}{applies}: mean over {} of CIEDE2000 between the model's colour and the spectral reference colour (CIELAB, D65 white)",
                model.engines(),
                quadrature_words()
            ),
            |p| error(p).map(|e| e.delta_e_mean),
        );
        optional(
            table,
            rows,
            &format!("{name}_de2000_max"),
            &format!("{name}: largest CIEDE2000 at the quadrature nodes (a lower bound of the maximum over theta)"),
            |p| error(p).map(|e| e.delta_e_max),
        );
        for (c, suffix) in SUFFIXES.iter().enumerate() {
            optional(
                table,
                rows,
                &format!("{name}_rel_error_{suffix}"),
                &format!("{name}: mean over theta of |F_model - F_spectral| / F_spectral in this channel (fraction)"),
                |p| error(p).map(|e| e.relative[c]),
            );
        }
    }
    let names: Vec<&str> = EngineModel::ALL.iter().map(|m| m.name()).collect();
    table.text(
        "best_model",
        &format!("the model with the smallest mean CIEDE2000 for this page, one of {}", names.join(", ")),
        rows.iter().map(|p| p.best().model.name().into()).collect(),
    );
    table.float("best_de2000_mean", "mean CIEDE2000 of best_model", rows.iter().map(|p| p.best().delta_e_mean).collect());
}
