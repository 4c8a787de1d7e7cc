//! Tests of the Fresnel methods against independently computed values.

use proptest::prelude::*;

use super::methods::{f82_tint::F82Tint, lazanyi::Lazanyi, nvidia::Nvidia, schlick_compensated::SchlickCompensated};
use super::reference::{exact_complex, exact_complex_textbook};
use super::*;

/// n log-uniform in [1e-3, 1e3].
fn any_n() -> impl Strategy<Value = f64> {
    (-3.0f64..=3.0).prop_map(|e| 10f64.powf(e))
}

/// k = 0 or log-uniform in [1e-8, 1e3].
fn any_k() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 3 => (-8.0f64..=3.0).prop_map(|e| 10f64.powf(e))]
}

/// cosθ in [0, 1] with the end points themselves often.
fn any_cos() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 1 => Just(1.0), 6 => 0.0f64..=1.0]
}

fn close(value: f64, reference: f64, relative: f64) -> bool {
    (value - reference).abs() <= relative * reference.abs().max(1e-12)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn every_method_is_finite_and_exact_is_a_reflectance(n in any_n(), k in any_k(), c in any_cos()) {
        let prepared = Prepared::new(Index::new(n, k));
        for method in Method::ALL {
            let model = Model::from_prepared(prepared.clone(), method, LutSpec::new(64, Encoding::Unorm8Srgb));
            let f = model.reflectance(c);
            let g = model.reflectance_f32(c as f32);
            prop_assert!(f.is_finite(), "{method} f64 ({n}, {k}, {c}) = {f}");
            prop_assert!(g.is_finite(), "{method} f32 ({n}, {k}, {c}) = {g}");
        }
        let f = exact(n, k, c);
        prop_assert!((0.0..=1.0).contains(&f));
        prop_assert!((0.0..=1.0).contains(&exact_f32(n as f32, k as f32, c as f32)));
        prop_assert!(prepared.params::<Nvidia>().power.is_finite() && prepared.params::<Nvidia>().bias.is_finite() && prepared.params::<Nvidia>().scale.is_finite());
    }

    #[test]
    fn exact_agrees_with_complex_arithmetic(n in any_n(), k in any_k(), c in any_cos()) {
        let f = exact(n, k, c);
        let reference = exact_complex(n, k, c);
        prop_assert!(close(f, reference, 1e-12), "exact({n}, {k}, {c}) = {f:e}, complex {reference:e}");
    }

    #[test]
    fn schlick_equals_schlick_nk(n in any_n(), k in any_k(), c in any_cos()) {
        let a = schlick(schlick_f0(n, k), c);
        let b = schlick_nk(n, k, c);
        prop_assert!(close(a, b, 1e-12), "schlick {a:e} schlick_nk {b:e}");
    }

    #[test]
    fn compensated_and_lazanyi_are_exact_at_their_anchor(n in any_n(), k in any_k()) {
        let p = Prepared::new(Index::new(n, k));
        let anchor = p.exact.reflectance(COMPENSATION_COS);
        let compensated = p.analytic(Method::SchlickCompensated, COMPENSATION_COS).unwrap();
        if p.params::<SchlickCompensated>().fallback.is_none() {
            prop_assert!((compensated - anchor).abs() <= 1e-12 * n.max(1.0), "{compensated} vs {anchor}");
        } else {
            prop_assert_eq!(compensated, schlick_nk(n, k, COMPENSATION_COS));
        }
        let anchor = p.exact.reflectance(LAZANYI_COS);
        let lazanyi = p.analytic(Method::Lazanyi, LAZANYI_COS).unwrap();
        prop_assert!((lazanyi - anchor).abs() <= 1e-12, "{lazanyi} vs {anchor}");
    }

    /// `f82_tint` with the colours unauthored is `lazanyi` (the same model, b formed from
    /// F0 and the tint); authored, it meets F_S(μ̄)·tint at μ̄ and its colours differ from
    /// the unauthored ones by at most half an 8-bit sRGB step.
    #[test]
    fn f82_tint_is_lazanyi_fed_authored_colours(n in any_n(), k in any_k(), c in any_cos()) {
        let p = Prepared::new(Index::new(n, k));
        let tint = p.exact.reflectance(LAZANYI_COS) / schlick(p.f0, LAZANYI_COS);
        if p.f0 <= 1.0 && tint.is_finite() {
            let unauthored = f82_tint(p.f0, tint, c);
            let lazanyi = p.analytic(Method::Lazanyi, c).unwrap();
            prop_assert!((unauthored - lazanyi).abs() <= 1e-12 * (1.0 + p.params::<Lazanyi>().abs()), "{unauthored} vs {lazanyi}");
        }
        let F82Colours { f0, tint: authored } = *p.params::<F82Tint>();
        let at_mu = p.analytic(Method::F82Tint, LAZANYI_COS).unwrap();
        prop_assert!((at_mu - schlick(f0, LAZANYI_COS) * authored).abs() <= 1e-12, "{at_mu}");
        // Half a code of 8-bit sRGB is at most 0.5/255 in the encoded value; its slope
        // in linear is at most 1/12.92 below the knee and 2.4/1.055 · V^1.4 ≤ 2.28 above.
        let step = 2.3 * 0.5 / 255.0;
        prop_assert!((f0 - p.f0.min(1.0)).abs() <= step, "{f0} vs {}", p.f0);
        prop_assert!((authored - tint.clamp(0.0, 1.0)).abs() <= step || !tint.is_finite(), "{authored} vs {tint}");
    }

    /// The shader version computes the same F to 1e-5 absolute, for indices representable
    /// in f32, away from the critical angle of weakly absorbing n < 1 (where F has a
    /// square-root kink and f32 rounding of A = n² − k² − s² moves it; docs/precision.md).
    #[test]
    fn exact_f32_is_within_1e5_of_f64(n in any_n(), k in any_k(), c in any_cos()) {
        let (n32, k32, c32) = (n as f32, k as f32, c as f32);
        let (n, k, c) = (n32 as f64, k32 as f64, c32 as f64);
        let sin = (1.0 - c * c).sqrt();
        prop_assume!(!(n < 1.0 && k < 0.1 && (sin - n).abs() < 1e-2));
        let f = exact(n, k, c);
        let g = exact_f32(n32, k32, c32) as f64;
        prop_assert!((f - g).abs() <= 1e-5, "exact({n}, {k}, {c}) = {f}, f32 {g}");
    }
}

#[test]
fn grazing_conductor_with_cancellation() {
    // n = 0.05, k = 5 (silver-like): A = n² − k² − s² ≪ 0, r + A cancels in the printed form.
    for c in [0.0, 1e-12, 1e-8, 1e-6, 1e-3, 0.01, 0.1, 0.5, 1.0] {
        let f = exact(0.05, 5.0, c);
        let reference = exact_complex(0.05, 5.0, c);
        assert!(close(f, reference, 1e-12), "c = {c}: {f:e} vs {reference:e}");
    }
    assert_eq!(exact(0.05, 5.0, 0.0), 1.0);
    let f0 = (0.95f64 * 0.95 + 25.0) / (1.05 * 1.05 + 25.0);
    assert!(close(exact(0.05, 5.0, 1.0), f0, 1e-15));
}

#[test]
fn textbook_complex_form_agrees_where_it_is_accurate() {
    for (n, k) in [(0.2, 3.5), (1.5, 0.0), (2.4, 0.0), (0.5, 0.0), (2.0, 3.6), (1.33, 1e-9)] {
        for i in 0..=100 {
            let c = i as f64 / 100.0;
            let (a, b) = (exact(n, k, c), exact_complex_textbook(n, k, c));
            assert!(close(a, b, 1e-12), "({n}, {k}, {c}): {a:e} vs {b:e}");
        }
    }
}

/// Snell-form dielectric reflectance with cancellation-free numerators, derived
/// independently of both implementations: t = cosθ_t = √(n² − s²)/n,
///   c − n t = (1 − n²)/(c + n t),   t − n c = (n² − 1)(1 − c²(n² + 1))/(n²(t + n c)).
fn dielectric_closed_form(n: f64, c: f64) -> f64 {
    let n2_minus_1 = (n - 1.0) * (n + 1.0);
    let t = (n2_minus_1 + c * c).sqrt() / n; // √(n² − s²)/n
    let rs = (n2_minus_1 / ((c + n * t) * (c + n * t))).powi(2);
    let rp = (n2_minus_1 * (1.0 - c * c * (n * n + 1.0)) / (n * n * (t + n * c) * (t + n * c))).powi(2);
    (rs + rp) / 2.0
}

#[test]
fn gases_keep_relative_accuracy() {
    // Air-like n − 1 ≈ 3e-4 (formula 6 pages) and closer to 1: F ~ 1e-8 … 1e-20.
    for n in [1.000_293, 1.000_035, 1.0 + 1e-6, 1.0 + 1e-9] {
        for i in 0..=200 {
            let c = 0.005 + 0.995 * i as f64 / 200.0;
            let (f, reference) = (exact(n, 0.0, c), dielectric_closed_form(n, c));
            assert!(close(f, reference, 1e-12), "n = {n}, c = {c}: {f:e} vs {reference:e}");
            let complex = exact_complex(n, 0.0, c);
            assert!(close(complex, reference, 1e-12), "n = {n}, c = {c}: complex {complex:e} vs {reference:e}");
        }
    }
    // Normal incidence: ((n − 1)/(n + 1))².
    let n = 1.000_293f64;
    assert!(close(exact(n, 0.0, 1.0), (0.000_293 / 2.000_293f64).powi(2), 1e-11));
}

#[test]
fn n_towards_one_goes_to_zero() {
    let mut previous = 1.0;
    for e in 1..=12 {
        let f = exact(1.0 + 10f64.powi(-e), 0.0, 0.7);
        assert!(f < previous && f > 0.0, "n = 1 + 1e-{e}: {f}");
        previous = f;
    }
    assert!(previous < 1e-24);
    assert_eq!(exact(1.0, 0.0, 0.7), 0.0);
}

#[test]
fn below_one_reflects_totally_beyond_the_critical_angle() {
    let n: f64 = 0.75; // critical sinθ = 0.75, cosθ = 0.6614
    let critical = (1.0 - n * n).sqrt();
    for i in 0..100 {
        let c = critical * i as f64 / 100.0;
        assert_eq!(exact(n, 0.0, c), 1.0, "c = {c}");
    }
    for i in 1..=100 {
        let c = critical + (1.0 - critical) * i as f64 / 100.0;
        let (f, reference) = (exact(n, 0.0, c), dielectric_closed_form(n, c));
        assert!(close(f, reference, 1e-12) && f < 1.0, "c = {c}: {f} vs {reference}");
    }
    // Continuous at the critical angle: F → 1 from above.
    assert!(exact(n, 0.0, critical * (1.0 + 1e-12)) > 0.999);
}

#[test]
fn gold_green_has_no_compensation_exponent() {
    // 3d/metals/gold (main/Au/nk/Rakic-BB.yml) at 535 nm, as ingested: D < 0.
    let gold_green = Index::new(0.5215829479768784, 2.1741294797687862);
    let p = Prepared::new(gold_green);
    assert_eq!(p.params::<SchlickCompensated>().fallback, Some(CompensationFallback::WrongSign));
    assert_eq!(p.params::<SchlickCompensated>().weight, 0.0);
    for i in 0..=100 {
        let c = i as f64 / 100.0;
        let f = p.analytic(Method::SchlickCompensated, c).unwrap();
        assert_eq!(f, schlick_nk(gold_green.n, gold_green.k, c));
        assert!(p.shader_params().analytic(Method::SchlickCompensated, c as f32).unwrap().is_finite());
    }
    // Gold's red (n = 0.17, k = 3.75) does have one: λ = ln(D/2n)/ln 0.9 ≈ 30.18.
    let red = Prepared::new(Index::new(0.17054450589301903, 3.7487680870353586));
    assert!(red.params::<SchlickCompensated>().fallback.is_none());
    assert!((red.params::<SchlickCompensated>().lambda - 30.1827).abs() < 1e-3, "{}", red.params::<SchlickCompensated>().lambda);
}

#[test]
fn nvidia_fit_is_deterministic_and_beats_the_schlick_shape() {
    for index in [Index::new(1.5, 0.0), Index::new(0.17, 3.75), Index::new(2.05, 3.63), Index::new(1.0003, 0.0)] {
        let p = Prepared::new(index);
        assert_eq!(p.params::<Nvidia>(), Prepared::new(index).params::<Nvidia>());
        let fit = *p.params::<Nvidia>();
        assert!((0.5..1024.0).contains(&fit.power), "{fit:?}");
        // RMS over the same θ grid of the Schlick-shaped choice bias = F0, scale = 1 − F0, power = 5.
        let m = nvidia::NVIDIA_FIT_SAMPLES;
        let rms = |bias: f64, scale: f64, power: f64| {
            let sum: f64 = (0..m)
                .map(|j| {
                    let c = ((j as f64 + 0.5) * std::f64::consts::FRAC_PI_2 / m as f64).cos();
                    (bias + scale * (1.0 - c).powf(power) - p.exact.reflectance(c)).powi(2)
                })
                .sum();
            (sum / m as f64).sqrt()
        };
        let fitted = rms(fit.bias, fit.scale, fit.power);
        assert!((fitted - fit.rms_residual).abs() < 1e-12);
        assert!(fitted <= rms(p.f0, 1.0 - p.f0, 5.0) + 1e-15, "{index:?}: {fitted} vs schlick shape");
        // A local minimum in power: nudging it does not help.
        for factor in [0.99, 1.01] {
            let power = fit.power * factor;
            let (bias, scale, _) = nvidia_solve_for_test(&p, power);
            assert!(rms(bias, scale, power) >= fitted - 1e-12, "{index:?} {fit:?}: power {power} gives {}", rms(bias, scale, power));
        }
    }
}

/// The closed-form least squares at a given power, recomputed independently.
fn nvidia_solve_for_test(p: &Prepared, power: f64) -> (f64, f64, f64) {
    let m = nvidia::NVIDIA_FIT_SAMPLES;
    let points: Vec<(f64, f64)> = (0..m)
        .map(|j| {
            let c = ((j as f64 + 0.5) * std::f64::consts::FRAC_PI_2 / m as f64).cos();
            ((1.0 - c).powf(power), p.exact.reflectance(c))
        })
        .collect();
    let count = m as f64;
    let (sx, sy): (f64, f64) = points.iter().fold((0.0, 0.0), |a, &(x, y)| (a.0 + x, a.1 + y));
    let (sxx, sxy) = points.iter().fold((0.0, 0.0), |a, &(x, y)| (a.0 + x * x, a.1 + x * y));
    let scale = (count * sxy - sx * sy) / (count * sxx - sx * sx);
    let bias = (sy - scale * sx) / count;
    (bias, scale, 0.0)
}

#[test]
fn nvidia_clamps_to_unit_interval() {
    assert_eq!(nvidia(-0.5, 0.2, 2.0, 1.0), 0.0);
    assert_eq!(nvidia(0.5, 2.0, 2.0, 0.0), 1.0);
    assert!((nvidia(0.1f64, 0.5, 2.0, 0.5) - 0.225).abs() < 1e-15);
    assert_eq!(nvidia(-0.5, 0.2, 2.0, 1.0), 0.0);
}

#[test]
fn lut_returns_texels_at_centres_and_clamps_to_edge() {
    let texels: Vec<f64> = (0..16).map(|i| (i * i) as f64 / 300.0).collect();
    let texels_f32: Vec<f32> = texels.iter().map(|&t| t as f32).collect();
    for (i, &t) in texels.iter().enumerate() {
        assert_eq!(sample_lut(&texels, crate::encoding::texel_cos(i, 16)), t);
        assert_eq!(sample_lut(&texels_f32, crate::encoding::texel_cos(i, 16) as f32), t as f32);
    }
    // Clamp-to-edge: below the first centre and above the last.
    for c in [0.0, 0.01, 0.5 / 16.0] {
        assert_eq!(sample_lut(&texels, c), texels[0]);
    }
    for c in [1.0, 0.99, 15.5 / 16.0] {
        assert_eq!(sample_lut(&texels, c), texels[15]);
    }
    assert_eq!(sample_lut(&texels_f32, 0.0), texels_f32[0]);
    assert_eq!(sample_lut(&texels_f32, 1.0), texels_f32[15]);
    // Halfway between centres 3 and 4 (c = 4/16): the mean.
    assert!((sample_lut(&texels, 4.0 / 16.0) - (9.0 + 16.0) / 600.0).abs() < 1e-16);
    // A quarter of the way: x = 3.25.
    assert!((sample_lut(&texels, 3.75 / 16.0) - (0.75 * 9.0 + 0.25 * 16.0) / 300.0).abs() < 1e-16);
    assert_eq!(sample_lut(&[], 0.5), 0.0);
    assert_eq!(sample_lut(&[0.25], 0.9), 0.25);
}

#[test]
fn large_float_lut_converges_to_exact() {
    let p = Prepared::new(Index::new(0.17, 3.75));
    let error = |spec: LutSpec| {
        let lut = Lut::bake(spec, |c| p.exact.reflectance(c));
        (0..=10_000).map(|i| i as f64 / 10_000.0).map(|c| (lut.sample(c) - p.exact.reflectance(c)).abs()).fold(0.0, f64::max)
    };
    let coarse = error(LutSpec::new(16, Encoding::F32));
    let fine = error(LutSpec::new(1024, Encoding::F32));
    // Interior error is O(h²); the clamped half-texel at each edge is O(h·F').
    assert!(fine < coarse / 20.0, "{fine} vs {coarse}");
    assert!(fine < 1e-3, "{fine}");
    let interior = |spec: LutSpec| {
        let lut = Lut::bake(spec, |c| p.exact.reflectance(c));
        (0..=10_000).map(|i| 0.01 + 0.98 * i as f64 / 10_000.0).map(|c| (lut.sample(c) - p.exact.reflectance(c)).abs()).fold(0.0, f64::max)
    };
    assert!(interior(LutSpec::new(1024, Encoding::F32)) < 1e-6);
    // unorm8 cannot beat half a code step.
    assert!(interior(LutSpec::new(1024, Encoding::Unorm8)) > 0.3 / 255.0);
}

#[test]
fn encodings_quantise_as_stored() {
    assert_eq!(Encoding::Unorm8.quantise(0.5), 128.0 / 255.0);
    assert_eq!(Encoding::Unorm8.encode(1.7), 255);
    assert_eq!(Encoding::Unorm8.encode(f64::NAN), 0);
    assert_eq!(Encoding::Unorm16.quantise(0.04), (0.04f64 * 65535.0).round() / 65535.0);
    assert_eq!(Encoding::F16.quantise(0.1), 0.0999755859375); // nearest binary16
    assert_eq!(Encoding::F32.quantise(0.1), 0.1f32 as f64);
    // sRGB: 0.04 linear → 0.2200 encoded → code 56 → 0.03954 linear.
    assert_eq!(Encoding::Unorm8Srgb.encode(0.04), 56);
    assert!((Encoding::Unorm8Srgb.quantise(0.04) - 0.039546).abs() < 1e-6);
    for i in 0..=255 {
        let v = i as f64 / 255.0;
        assert!((crate::encoding::srgb_encode(crate::encoding::srgb_decode(v)) - v).abs() < 1e-12);
        for e in Encoding::ALL {
            let q = e.quantise(v);
            assert_eq!(e.quantise(q), q, "{} not idempotent at {v}", e.name());
        }
    }
    assert_eq!(Encoding::ALL.map(Encoding::bytes_per_channel), [1, 1, 2, 2, 4]);
    assert_eq!(LutSpec::new(256, Encoding::F16).texture_bytes(), 256 * 3 * 2);
}

#[test]
fn method_names() {
    let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
    assert_eq!(names, ["exact", "schlick", "schlick_nk", "schlick_compensated", "lazanyi", "nvidia", "lut", "f82_tint", "schlick_fitted"]);
    for m in Method::ALL {
        assert_eq!(Method::from_name(m.name()), Some(m));
        assert_eq!(Method::ALL[m.index()], m);
    }
    // The uniform members every method adds, in the order of the list.
    let members: Vec<&str> = Method::ALL.iter().flat_map(|m| m.uniform().iter().copied()).collect();
    assert_eq!(
        members,
        [
            "compensation_weight",
            "compensation_lambda",
            "lazanyi_a",
            "nvidia_bias",
            "nvidia_scale",
            "nvidia_power",
            "f82_f0",
            "f82_tint",
            "schlick_power"
        ]
    );
    assert_eq!(METHOD_UNIFORM_MEMBERS, members.len());
}

#[test]
fn f32_exact_of_water_keeps_relative_accuracy_but_gases_do_not() {
    let water = (1.3336f64, 0.0);
    let f = exact(water.0, water.1, 1.0);
    let g = exact_f32(water.0 as f32, 0.0, 1.0) as f64;
    assert!(((g - f) / f).abs() < 1e-5, "{f} {g}");
    // Air: n − 1 = 2.93e-4 rounds to f32 with relative error up to 2e-4 of n − 1.
    let air = 1.000_293f64;
    let f = exact(air, 0.0, 1.0);
    let g = exact_f32(air as f32, 0.0, 1.0) as f64;
    let from_rounded_n = exact((air as f32) as f64, 0.0, 1.0);
    assert!(((g - from_rounded_n) / from_rounded_n).abs() < 1e-5);
    assert!(((g - f) / f).abs() > 1e-5, "f32 should lose relative accuracy for gases: {f} {g}");
}

/// Hand-computed: glass (F0 = 0.04) with tint 1 is Schlick's curve (b = 0); gold's red
/// channel's authored colours are its sRGB codes' linear values.
#[test]
fn f82_tint_by_hand() {
    for c in [0.0, 0.1, 1.0 / 7.0, 0.5, 1.0] {
        assert!((f82_tint(0.04, 1.0, c) - schlick(0.04, c)).abs() < 1e-15);
    }
    // b = F_S(μ̄)(1 − t)/(μ̄(1 − μ̄)⁶) with F0 = 0.5, t = 0.5: F_S(μ̄) = 0.5 + 0.5·(6/7)⁵.
    let (mu, m): (f64, f64) = (1.0 / 7.0, 6.0 / 7.0);
    let at_mu = 0.5 + 0.5 * m.powi(5);
    let b = at_mu * 0.5 / (mu * m.powi(6));
    let c = 0.3;
    let expected = 0.5 + 0.5 * (0.7f64).powi(5) - b * c * (0.7f64).powi(6);
    assert!((f82_tint(0.5, 0.5, c) - expected).abs() < 1e-14);
    assert!((f82_tint(0.5_f32, 0.5, 0.3) as f64 - expected).abs() < 1e-6);
}

/// A method is fitted only when it is asked for, and once: the f32 twin reads the same
/// fit, and shader parameters round-trip through the uniform members.
#[test]
fn fits_are_lazy_and_shared_by_both_precisions() {
    use super::methods::Stored;
    let p = Prepared::new(Index::new(0.17, 3.75));
    assert!(Nvidia::cell(&p.fits).get().is_none(), "nothing fitted before it is asked for");
    let f = p.analytic(Method::Schlick, 0.5).unwrap();
    assert_eq!(f, schlick(p.f0, 0.5));
    assert!(Nvidia::cell(&p.fits).get().is_none(), "schlick fits nothing");
    let wide = p.analytic(Method::Nvidia, 0.3).unwrap();
    let fit = *Nvidia::cell(&p.fits).get().expect("fitted on first use");
    assert_eq!(fit, fit_nvidia(&p.exact));
    assert_eq!(wide, nvidia(fit.bias, fit.scale, fit.power, 0.3));
    let narrow = p.analytic_f32(Method::Nvidia, 0.3).unwrap();
    assert_eq!(narrow, nvidia(fit.bias as f32, fit.scale as f32, fit.power as f32, 0.3));
    let shader = p.shader_params();
    let again = ShaderParams::from_members(shader.channel(), &shader.members()).unwrap();
    assert_eq!(again, shader);
    for method in Method::ALL {
        assert_eq!(shader.analytic(method, 0.3), p.analytic_f32(method, 0.3), "{method}");
    }
    assert!(ShaderParams::from_members(shader.channel(), &shader.members()[1..]).is_none());
}
