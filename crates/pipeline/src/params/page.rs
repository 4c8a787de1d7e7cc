//! Every engine parameter of one page and each model's error against the page's spectral
//! reference curve RGB(μ) (docs/colors.md: CIE 1931 2°, D65, linear sRGB; μ = cosθ).
//!
//! - F0 = RGB(1) in linear Rec.709, in ACEScg (Bradford D65 → ACES white, `color::acescg`)
//!   and 8-bit sRGB (per-channel clamp to [0, 1], then the IEC 61966-2-1 encoding).
//! - The models of [`super::models`], fitted to RGB(μ) over θ; the fitted (n, k) of
//!   `color::fit_effective_index` (the `effective_*` of colors.csv).
//! - Dielectrics: n at the Fraunhofer d line (587.56 nm), F (486.13 nm) and C (656.27 nm),
//!   Abbe number V_d = (n_d − 1)/(n_F − n_C) (ISO 7944), and the glTF `KHR_materials_ior`
//!   reflectance, which glTF viewers evaluate as Schlick with F0 = ((n_d − 1)/(n_d + 1))².
//! - Error of each model over θ uniform in [0°, 90°] on the angle quadrature: mean and
//!   largest CIEDE2000 between the model's colour and RGB(μ) (CIELAB, D65 white), and per
//!   channel the mean of |F − F_ref|/F_ref.

use super::models::{F82Tint, GeneralizedSchlick, Gulbrandsen, EDGE_COS};
use nklut_optics::appearance::{self, Appearance, Volume};
use nklut_optics::color::{self, acescg, srgb, AngleQuadrature, EffectiveIndex, Lab, PreparedSpectrum};
use nklut_optics::fresnel::{self, ExactTerms};
use nklut_optics::spectrum::{self, Channels, Index, Material};

/// Fraunhofer lines of the Abbe number (nm): d (helium), F (hydrogen), C (hydrogen).
pub const D_LINE_NM: f64 = 587.56;
pub const F_LINE_NM: f64 = 486.13;
pub const C_LINE_NM: f64 = 656.27;

/// The parameterisations whose error is measured, in table order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EngineModel {
    /// F0 only, F = F0 + (1 − F0)(1 − μ)⁵: glTF metallic, Unreal, most real-time engines.
    Schlick,
    /// F0 + F82 tint (Hoffman): OpenPBR, Adobe Standard Material, Blender 4.
    F82Tint,
    /// Gulbrandsen's (r, g) → (n, k) → exact Fresnel: MaterialX `artistic_ior`.
    Gulbrandsen,
    /// Hoffman's generalized Schlick: MaterialX `generalized_schlick_bsdf`.
    GeneralizedSchlick,
    /// Exact Fresnel of the fitted per-channel (n, k): MaterialX `conductor_bsdf`,
    /// Blender's physical conductor, pbrt/Mitsuba RGB conductors.
    FittedNk,
    /// Dielectrics only: Schlick with F0 from n_d, as a glTF viewer renders
    /// `KHR_materials_ior`.
    GltfIor,
}

impl EngineModel {
    pub const ALL: [EngineModel; 6] = [
        EngineModel::Schlick,
        EngineModel::F82Tint,
        EngineModel::Gulbrandsen,
        EngineModel::GeneralizedSchlick,
        EngineModel::FittedNk,
        EngineModel::GltfIor,
    ];

    pub fn name(self) -> &'static str {
        match self {
            EngineModel::Schlick => "schlick",
            EngineModel::F82Tint => "f82_tint",
            EngineModel::Gulbrandsen => "gulbrandsen",
            EngineModel::GeneralizedSchlick => "generalized_schlick",
            EngineModel::FittedNk => "fitted_nk",
            EngineModel::GltfIor => "gltf_ior",
        }
    }

    /// Who reads this parameterisation, for the table's descriptions.
    pub fn engines(self) -> &'static str {
        match self {
            EngineModel::Schlick => "F0 alone with Schlick's (1 - mu)^5 curve: glTF metallic-roughness, Unreal, Unity, Filament",
            EngineModel::F82Tint => {
                "F0 + F82 tint (Hoffman): OpenPBR specular_color, Adobe Standard Material edge color, Blender 4 Principled specular tint"
            }
            EngineModel::Gulbrandsen => {
                "Gulbrandsen reflectivity + edge tint -> (n, k) -> exact Fresnel: MaterialX artistic_ior, Autodesk Standard Surface"
            }
            EngineModel::GeneralizedSchlick => {
                "Hoffman generalized Schlick (color0, color82, color90 = 1, one exponent): MaterialX generalized_schlick_bsdf"
            }
            EngineModel::FittedNk => {
                "exact Fresnel of the fitted per-channel (n, k): MaterialX conductor_bsdf, Blender physical conductor, pbrt/Mitsuba RGB"
            }
            EngineModel::GltfIor => "dielectrics: Schlick with F0 = ((n_d - 1)/(n_d + 1))^2, how glTF viewers render KHR_materials_ior",
        }
    }
}

/// A dielectric's index figures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    pub n_d: f64,
    /// n at the F and C lines; `None` where the page's data give no index there (a page
    /// kept for a narrower range than 486–656 nm).
    pub n_f: Option<f64>,
    pub n_c: Option<f64>,
    /// (n_d − 1)/(n_F − n_C); `None` where n_F ≤ n_C (no normal dispersion, e.g. a
    /// constant n) or either line is missing.
    pub abbe: Option<f64>,
    /// ((n_d − 1)/(n_d + 1))²: the F0 a glTF viewer derives from `KHR_materials_ior`.
    pub gltf_f0: f64,
}

/// One model's error against the spectral reference over θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelError {
    pub model: EngineModel,
    /// Mean over θ of CIEDE2000(model colour, reference colour).
    pub delta_e_mean: f64,
    /// The largest CIEDE2000 at the quadrature nodes.
    pub delta_e_max: f64,
    /// Per channel, mean over θ of |F − F_ref|/F_ref (nodes with F_ref = 0 left out).
    pub relative: [f64; 3],
}

/// Everything `engine_params.csv` holds for one page.
#[derive(Clone, Debug, PartialEq)]
pub struct EngineParams {
    /// RGB(1), linear Rec.709/sRGB primaries (may leave [0, 1]).
    pub f0: [f64; 3],
    pub f0_acescg: [f64; 3],
    /// 8-bit sRGB-encoded F0 (clamped per channel).
    pub f0_srgb8: [u8; 3],
    /// RGB(μ̄), μ̄ = 1/7.
    pub reference_at_edge: [f64; 3],
    pub f82: [F82Tint; 3],
    pub gulbrandsen: [Gulbrandsen; 3],
    pub generalized_schlick: GeneralizedSchlick,
    pub fitted: [EffectiveIndex; 3],
    /// The three-wavelength (n, k) of materials.csv.
    pub channel_index: [Index; 3],
    /// Set for dielectric pages (without an Abbe number for an opaque one: its light never
    /// travels far enough to disperse).
    pub dielectric: Option<Dielectric>,
    /// What light does inside the material at a scene's size, and its volume's colour.
    pub volume: Volume,
    /// One per model of [`EngineModel::ALL`] that applies (GltfIor only for dielectrics).
    pub errors: Vec<ModelError>,
}

impl EngineParams {
    /// The per-channel (n, k) an export pastes as optics: the fitted index, or where the
    /// fit ended on its search box ([`EffectiveIndex::at_bound`]: a curve fit, not the
    /// material) the index at the channel's wavelength.
    pub fn exported_index(&self) -> [Index; 3] {
        [0, 1, 2].map(|c| if self.fitted[c].at_bound() { self.channel_index[c] } else { self.fitted[c].index })
    }

    pub fn error(&self, model: EngineModel) -> Option<&ModelError> {
        self.errors.iter().find(|e| e.model == model)
    }

    /// The model with the smallest mean CIEDE2000 (ties: the earlier in [`EngineModel::ALL`]).
    pub fn best(&self) -> &ModelError {
        self.errors.iter().fold(&self.errors[0], |best, e| if e.delta_e_mean < best.delta_e_mean { e } else { best })
    }

    /// Whether linear F0 leaves [0, 1] in Rec.709 (sRGB) primaries.
    pub fn f0_out_of_gamut(&self) -> bool {
        self.f0.iter().any(|v| !(0.0..=1.0).contains(v))
    }

    pub fn f0_acescg_out_of_gamut(&self) -> bool {
        self.f0_acescg.iter().any(|v| !(0.0..=1.0).contains(v))
    }
}

/// The spectral reference a page's parameters are computed from.
#[derive(Clone, Debug)]
pub struct Reference {
    pub f0: [f64; 3],
    pub at_edge: [f64; 3],
    /// RGB at the quadrature nodes, one vector per channel.
    pub at_nodes: [Vec<f64>; 3],
    /// CIELAB (D65 white) of the colour at each node, for the CIEDE2000 of every model.
    pub lab_at_nodes: Vec<Lab>,
}

impl Reference {
    pub fn new(spectrum: &PreparedSpectrum, rule: &AngleQuadrature) -> Self {
        Self::from_curve(spectrum, &spectrum.curve(&rule.cosines))
    }

    /// The reference with `curve`, the spectrum's colour at the quadrature's nodes.
    pub fn from_curve(spectrum: &PreparedSpectrum, curve: &[[f64; 3]]) -> Self {
        let weights = color::spectral_weights();
        Self {
            f0: spectrum.rgb(1.0),
            at_edge: spectrum.rgb(EDGE_COS),
            at_nodes: std::array::from_fn(|c| curve.iter().map(|rgb| rgb[c]).collect()),
            lab_at_nodes: curve.iter().map(|rgb| weights.lab(*rgb)).collect(),
        }
    }
}

/// n at the d, F and C lines of a dielectric page; `None` where its data give no valid
/// index at the d line (outside their range), and each of F and C likewise.
pub fn dielectric(material: &Material) -> Option<Dielectric> {
    let n_at = |nm: f64| spectrum::index_at(&material.data, nm).ok().map(|i| i.n);
    let n_d = n_at(D_LINE_NM)?;
    let (n_f, n_c) = (n_at(F_LINE_NM), n_at(C_LINE_NM));
    let abbe = n_f
        .zip(n_c)
        .map(|(f, c)| f - c)
        .filter(|dispersion| *dispersion > 0.0)
        .map(|dispersion| (n_d - 1.0) / dispersion)
        .filter(|v| v.is_finite());
    Some(Dielectric { n_d, n_f, n_c, abbe, gltf_f0: fresnel::schlick_f0(n_d, 0.0) })
}

/// Every parameter of a page from its spectral reference (`rule` the angle quadrature of
/// the fits and errors).
pub fn engine_params(material: &Material, reference: &Reference, rule: &AngleQuadrature, channels: &Channels) -> EngineParams {
    let f0 = reference.f0;
    let volume = appearance::volume(&material.data, material.kind, &material.channels, channels);
    // Every page that is not a metal has the dielectric's figures: a conductor by the
    // k ≥ 1 rule that some channel passes is classed by its depths (`appearance::classify`).
    let dielectric = (volume.appearance != Appearance::Metal)
        .then(|| dielectric(material).map(|d| Dielectric { abbe: d.abbe.filter(|_| volume.appearance.transmits()), ..d }))
        .flatten();
    let f82 = [0, 1, 2].map(|c| F82Tint::new(f0[c], reference.at_edge[c]));
    let gulbrandsen = [0, 1, 2].map(|c| Gulbrandsen::fit(f0[c], &reference.at_nodes[c], rule));
    let generalized_schlick = GeneralizedSchlick::fit(f0, reference.at_edge, &reference.at_nodes, rule);
    // Gulbrandsen's best (n, k) already lies near the (n, k) optimum: one Levenberg–Marquardt
    // start from it instead of the colour module's three (same minimum, a third of the work;
    // compared with colors.csv over the whole database in docs/engine-parameters.md).
    let fitted = [0, 1, 2].map(|c| color::fit_effective_index_from(&reference.at_nodes[c], &[gulbrandsen[c].index()], rule));
    let mut params = EngineParams {
        f0,
        f0_acescg: acescg::srgb_to_acescg(f0),
        f0_srgb8: srgb::srgb8(f0),
        reference_at_edge: reference.at_edge,
        f82,
        gulbrandsen,
        generalized_schlick,
        fitted,
        channel_index: material.channels,
        dielectric,
        volume,
        errors: Vec::new(),
    };
    params.errors = EngineModel::ALL
        .iter()
        .filter_map(|&m| model_curve(&params, m, &rule.cosines).map(|curve| model_error(m, &curve, reference, rule)))
        .collect();
    params
}

/// The model's colour at each of `cosines`; `None` for a model that does not apply.
pub fn model_curve(params: &EngineParams, model: EngineModel, cosines: &[f64]) -> Option<Vec<[f64; 3]>> {
    let per_channel = |f: &dyn Fn(usize, f64) -> f64| cosines.iter().map(|&mu| [0, 1, 2].map(|c| f(c, mu))).collect();
    Some(match model {
        EngineModel::Schlick => per_channel(&|c, mu| fresnel::schlick(params.f0[c], mu)),
        EngineModel::F82Tint => per_channel(&|c, mu| params.f82[c].reflectance(mu)),
        EngineModel::Gulbrandsen => {
            let terms = params.gulbrandsen.map(|g| ExactTerms::new(g.index()));
            per_channel(&|c, mu| terms[c].reflectance(mu))
        }
        EngineModel::GeneralizedSchlick => per_channel(&|c, mu| params.generalized_schlick.reflectance(c, mu)),
        EngineModel::FittedNk => {
            let terms = params.fitted.map(|f| ExactTerms::new(f.index));
            per_channel(&|c, mu| terms[c].reflectance(mu))
        }
        EngineModel::GltfIor => {
            let f0 = params.dielectric?.gltf_f0;
            per_channel(&|_, mu| fresnel::schlick(f0, mu))
        }
    })
}

/// CIEDE2000 and relative errors of a model curve (at `rule.cosines`) against the reference.
pub fn model_error(model: EngineModel, curve: &[[f64; 3]], reference: &Reference, rule: &AngleQuadrature) -> ModelError {
    let CurveError { delta_e_mean, delta_e_max, relative } = curve_error(curve, reference, rule);
    ModelError { model, delta_e_mean, delta_e_max, relative }
}

/// The figures of [`ModelError`] for any colour curve over θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveError {
    pub delta_e_mean: f64,
    pub delta_e_max: f64,
    pub relative: [f64; 3],
}

/// CIEDE2000 (mean over θ, largest at a node) and per-channel mean relative error of any
/// curve at `rule.cosines` against the reference: the one definition the engine models'
/// and every other method's error against the spectral curve share.
pub fn curve_error(curve: &[[f64; 3]], reference: &Reference, rule: &AngleQuadrature) -> CurveError {
    let weights = color::spectral_weights();
    let delta_e: Vec<f64> =
        curve.iter().zip(&reference.lab_at_nodes).map(|(rgb, lab)| color::delta_e2000(weights.lab(*rgb), *lab)).collect();
    CurveError {
        delta_e_mean: rule.mean(delta_e.iter().copied()),
        delta_e_max: delta_e.iter().copied().fold(0.0, f64::max),
        relative: [0, 1, 2].map(|c| mean_relative(curve.iter().map(|rgb| rgb[c]), &reference.at_nodes[c], rule)),
    }
}

/// Mean over the quadrature of |F − F_ref|/|F_ref|, nodes with F_ref = 0 or not finite
/// left out (weights renormalised); 0 with none left.
fn mean_relative(values: impl Iterator<Item = f64>, reference: &[f64], rule: &AngleQuadrature) -> f64 {
    let (mut sum, mut weight) = (0.0, 0.0);
    for ((v, &r), &q) in values.zip(reference).zip(&rule.weights) {
        if r != 0.0 && r.is_finite() {
            sum += q * (v - r).abs() / r.abs();
            weight += q;
        }
    }
    if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::color::{angle_quadrature, sample_spectrum};
    use nklut_optics::db::parse_page;
    use nklut_optics::spectrum::{evaluate, Channels, Kind};

    /// A page with a constant (n, k) over 300–900 nm.
    fn flat(n: f64, k: f64) -> Material {
        let yaml = format!("DATA:\n  - type: tabulated nk\n    data: |\n        0.30 {n} {k}\n        0.90 {n} {k}\n");
        evaluate(parse_page("flat.yml", &yaml).unwrap(), &Channels::default(), nklut_optics::spectrum::Coverage::default()).unwrap()
    }

    /// A dielectric material from page data without the visible-range filter.
    fn evaluate_unchecked(data: nklut_optics::db::PageData) -> Material {
        let n = spectrum::index_held(&data, 535.0);
        Material { data, channels: [n; 3], kind: Kind::Dielectric, range_nm: (0.0, 0.0), max_visible_gap_nm: None }
    }

    fn params_of(material: &Material) -> EngineParams {
        let rule = angle_quadrature();
        let (spectrum, _) = sample_spectrum(&material.data);
        engine_params(material, &Reference::new(&PreparedSpectrum::new(&spectrum), rule), rule, &Channels::default())
    }

    #[test]
    fn a_flat_spectrum_gives_exact_fresnel_everywhere() {
        for (n, k) in [(0.27, 2.9), (1.5, 0.0), (2.4, 0.3), (0.05, 4.2)] {
            let material = flat(n, k);
            let params = params_of(&material);
            let exact_f0 = fresnel::exact(n, k, 1.0);
            for c in 0..3 {
                // Σ w = 1 per channel: a grey spectrum is its own colour to ~1e-15.
                assert!((params.f0[c] / exact_f0 - 1.0).abs() < 1e-12, "{n} {k}: {:?}", params.f0);
                assert!((params.f82[c].reflectance(1.0) / exact_f0 - 1.0).abs() < 1e-12);
                assert!((params.generalized_schlick.reflectance(c, 1.0) / exact_f0 - 1.0).abs() < 1e-12);
                let gulbrandsen = params.gulbrandsen[c].index();
                assert!((fresnel::exact(gulbrandsen.n, gulbrandsen.k, 1.0) / exact_f0 - 1.0).abs() < 1e-12);
                // Gulbrandsen's family and the (n, k) fit both contain the truth.
                let fitted = params.fitted[c].index;
                for index in [fitted, gulbrandsen] {
                    assert!((index.n / n - 1.0).abs() < 1e-4 && (index.k - k).abs() < 1e-4 * k.max(1.0), "{n} {k}: {index:?}");
                }
            }
            // Grey in, grey out: the three channels agree, and ACEScg keeps a grey grey.
            assert!(params.f0_acescg.iter().all(|v| (v / exact_f0 - 1.0).abs() < 1e-9), "{:?}", params.f0_acescg);
            let fitted = params.error(EngineModel::FittedNk).unwrap();
            assert!(fitted.delta_e_mean < 1e-3 && fitted.relative.iter().all(|e| *e < 1e-6), "{fitted:?}");
        }
    }

    #[test]
    fn a_flat_dielectric_has_its_constant_index_at_every_line() {
        let params = params_of(&flat(1.5, 0.0));
        let dielectric = params.dielectric.unwrap();
        assert_eq!((dielectric.n_d, dielectric.n_f, dielectric.n_c), (1.5, Some(1.5), Some(1.5)));
        assert_eq!(dielectric.abbe, None);
        assert!((dielectric.gltf_f0 - 0.04).abs() < 1e-15);
        // glTF's Schlick with the right F0 differs from exact Fresnel only through Schlick's curve.
        let gltf = params.error(EngineModel::GltfIor).unwrap();
        let schlick = params.error(EngineModel::Schlick).unwrap();
        assert!((gltf.delta_e_mean - schlick.delta_e_mean).abs() < 1e-9);
        assert!(params_of(&flat(0.2, 3.0)).dielectric.is_none());
    }

    #[test]
    fn abbe_number_of_a_cauchy_glass_by_hand() {
        // Cauchy n = 1.5 + 0.005 / λ² (λ in µm), formula 5: n = C1 + C2 λ^C3.
        let data =
            parse_page("c.yml", "DATA:\n  - type: formula 5\n    wavelength_range: 0.3 1.0\n    coefficients: 1.5 0.005 -2\n").unwrap();
        let material = evaluate(data, &Channels::default(), nklut_optics::spectrum::Coverage::default()).unwrap();
        let d = dielectric(&material).unwrap();
        let n = |um: f64| 1.5 + 0.005 / (um * um);
        let abbe = (n(0.58756) - 1.0) / (n(0.48613) - n(0.65627));
        assert!((d.abbe.unwrap() - abbe).abs() < 1e-9 * abbe, "{d:?} vs {abbe}");
        assert!(abbe > 50.0 && abbe < 70.0, "{abbe}");
        // Data over 500–700 nm only: n_d and n_C but no F line, so no Abbe number.
        let narrow = parse_page("n.yml", "DATA:\n  - type: tabulated n\n    data: |\n        0.50 1.52\n        0.70 1.51\n").unwrap();
        let d = dielectric(&evaluate_unchecked(narrow)).unwrap();
        assert_eq!((d.n_f, d.abbe), (None, None));
        assert!((d.n_d - (1.52 - 0.01 * (0.58756 - 0.5) / 0.2)).abs() < 1e-12 && d.n_c.is_some());
    }

    #[test]
    fn every_model_hits_f0_and_the_fitted_angle_on_a_dispersive_metal() {
        // Gold-like: k and n vary across the visible, so the spectral colour is not an exact curve.
        let data = parse_page(
            "au.yml",
            "DATA:\n  - type: tabulated nk\n    data: |\n        0.35 1.6 1.9\n        0.45 1.4 1.8\n        0.50 0.95 1.85\n        0.55 0.4 2.3\n        0.65 0.17 3.2\n        0.85 0.2 5.2\n",
        )
        .unwrap();
        let material = evaluate(data, &Channels::default(), nklut_optics::spectrum::Coverage::default()).unwrap();
        let params = params_of(&material);
        for c in 0..3 {
            assert_eq!(params.f82[c].reflectance(1.0), params.f0[c]);
            assert!((params.f82[c].reflectance(EDGE_COS) - params.reference_at_edge[c]).abs() < 1e-14);
            assert_eq!(params.generalized_schlick.reflectance(c, 1.0), params.f0[c]);
            assert!((params.generalized_schlick.reflectance(c, EDGE_COS) - params.reference_at_edge[c]).abs() < 1e-14);
            let g = params.gulbrandsen[c];
            if params.f0[c] <= 0.99 {
                let index = g.index();
                assert!((fresnel::exact(index.n, index.k, 1.0) - params.f0[c]).abs() < 1e-13);
            }
            let back = Gulbrandsen::from_index(g.index());
            assert!((back.g - g.g).abs() < 1e-9 && (back.r - g.r).abs() < 1e-12, "{g:?} → {back:?}");
        }
        // Each fitted model beats plain Schlick, and the best model is the smallest mean.
        let schlick = params.error(EngineModel::Schlick).unwrap().delta_e_mean;
        for m in [EngineModel::F82Tint, EngineModel::GeneralizedSchlick, EngineModel::FittedNk] {
            assert!(params.error(m).unwrap().delta_e_mean < schlick, "{m:?}");
        }
        assert!(params.errors.iter().all(|e| e.delta_e_mean >= params.best().delta_e_mean));
        assert!(params.error(EngineModel::GltfIor).is_none());
    }
}
