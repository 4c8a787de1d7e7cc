//! Each Fresnel method's error against a page's spectral reference curve RGB(μ) (SPEC §4),
//! for the methods no other table measures that way: the closed forms of SPEC §5 on the
//! three-channel (n, k) (errors.csv measures them against exact Fresnel of that same
//! index, not against the spectrum), and LUTs baked from the spectral curve itself
//! (`nklut bake --source spectral`) in every size × encoding of the validate sweep.
//!
//! The figures are those of `engine_params.csv` for the engine models
//! ([`crate::params::curve_error`]): CIEDE2000 between the method's colour and RGB(μ) at
//! the colour module's angle-quadrature nodes (mean with its weights, the largest node),
//! and per channel the mean of |F − F_ref|/F_ref. A LUT is sampled as a GPU does (decoded
//! texels at (i + ½)/N, linear filtering, clamp-to-edge: `fresnel::Lut`); a unorm
//! encoding clamps a spectral value above 1.

use nklut_optics::color::{AngleQuadrature, PreparedSpectrum};
use nklut_optics::fresnel::{texel_values, Lut, LutSpec, Method, Model, Prepared, LUT_SIZES};
use nklut_optics::spectrum::ChannelIndex;

use crate::params::{curve_error, CurveError, Reference};

/// The closed forms measured on the three-channel index: every method but those that read
/// a texture (`lut`, measured per size and encoding instead), in the order of `Method::ALL`.
pub fn three_channel_methods() -> Vec<Method> {
    Method::ALL.into_iter().filter(|m| !m.reads_texture()).collect()
}

/// One method's error on one page.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodError {
    pub method: Method,
    /// `three-channel` (the closed form on the channel (n, k)) or `spectral` (a LUT of the spectral curve).
    pub source: &'static str,
    pub lut: Option<LutSpec>,
    pub error: CurveError,
}

/// Every method of [`three_channel_methods`] on `index`, then a spectral LUT per size ×
/// encoding of the sweep. `prepared` gives each channel's prepared parameters (the
/// `nvidia` fit from a memo where the caller has one).
pub fn method_errors(
    index: &ChannelIndex,
    prepared: &dyn Fn(nklut_optics::spectrum::Index) -> Prepared,
    spectrum: &PreparedSpectrum,
    reference: &Reference,
    rule: &AngleQuadrature,
) -> Vec<MethodError> {
    let prepared: [Prepared; 3] = index.map(prepared);
    let mut out = Vec::new();
    for method in three_channel_methods() {
        let models = [0, 1, 2].map(|c| Model::from_prepared(prepared[c].clone(), method, LutSpec::default()));
        let curve: Vec<[f64; 3]> = rule.cosines.iter().map(|&mu| [0, 1, 2].map(|c| models[c].reflectance(mu))).collect();
        out.push(MethodError { method, source: "three-channel", lut: None, error: curve_error(&curve, reference, rule) });
    }
    for size in LUT_SIZES {
        let centres = texel_values(size, |c| c);
        let at_centres = spectrum.curve(&centres);
        let channel_values: [Vec<f64>; 3] = [0, 1, 2].map(|c| at_centres.iter().map(|rgb| rgb[c]).collect());
        for spec in LutSpec::sweep().into_iter().filter(|s| s.texels == size) {
            let luts = channel_values.each_ref().map(|values| Lut::from_values(spec, values));
            let curve: Vec<[f64; 3]> = rule.cosines.iter().map(|&mu| [0, 1, 2].map(|c| luts[c].sample(mu))).collect();
            out.push(MethodError { method: Method::Lut, source: "spectral", lut: Some(spec), error: curve_error(&curve, reference, rule) });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::color::{angle_quadrature, sample_spectrum};
    use nklut_optics::db::parse_page;
    use nklut_optics::fresnel::Encoding;
    use nklut_optics::spectrum::{evaluate, Channels, Coverage};

    #[test]
    fn a_flat_spectrum_makes_exact_fresnel_and_a_float_lut_of_it_error_free() {
        // Constant (n, k): the spectral colour is exact Fresnel of that index in every channel.
        let yaml = "DATA:\n  - type: tabulated nk\n    data: |\n        0.30 0.27 2.9\n        0.90 0.27 2.9\n";
        let material = evaluate(parse_page("flat.yml", yaml).unwrap(), &Channels::default(), Coverage::default()).unwrap();
        let rule = angle_quadrature();
        let (spectrum, _) = sample_spectrum(&material.data);
        let prepared = PreparedSpectrum::new(&spectrum);
        let reference = Reference::new(&prepared, rule);
        let errors = method_errors(&material.channels, &Prepared::new, &prepared, &reference, rule);
        assert_eq!(errors.len(), three_channel_methods().len() + LutSpec::sweep().len());
        assert!(three_channel_methods().contains(&Method::SchlickFitted) && !three_channel_methods().contains(&Method::Lut));
        let exact = &errors[0];
        assert_eq!(exact.method, Method::Exact);
        assert!(exact.error.delta_e_max < 1e-3 && exact.error.relative.iter().all(|r| *r < 1e-9), "{exact:?}");
        // Schlick's curve is not Fresnel's: it must show an error.
        assert!(errors[1].error.delta_e_max > 0.1, "{:?}", errors[1]);
        // A 1024-texel f32 LUT of the curve: linear interpolation error only, ~(1/1024)² · F''.
        let fine = errors.iter().find(|e| e.lut == Some(LutSpec::new(1024, Encoding::F32))).unwrap();
        assert!(fine.error.delta_e_max < 0.01 && fine.error.relative.iter().all(|r| *r < 1e-4), "{fine:?}");
        // unorm8 quantises to 1/255 (≤ 0.5/255 absolute): visibly worse than f32 at the same size.
        let coarse = errors.iter().find(|e| e.lut == Some(LutSpec::new(1024, Encoding::Unorm8))).unwrap();
        assert!(coarse.error.relative[0] > fine.error.relative[0]);
    }
}
