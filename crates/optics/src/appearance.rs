//! What light does inside a material at the size of a scene: from the extinction
//! coefficient k, the absorption coefficient α = 4πk/λ (Beer–Lambert: intensity falls as
//! e^(−αx)) and its inverse, the absorption depth δ = λ/(4πk), the distance over which
//! light falls to 1/e. By the depths at the channel wavelengths a material is
//!
//! - a **metal**: a conductor (k ≥ 1 somewhere in 390–700 nm, `spectrum::Kind`) whose
//!   every channel is absorbed within the thin limit. A conductor by that rule whose some
//!   channel passes (PbI2, a yellow crystal: k ≥ 1 in the violet, k = 0 in the red) is
//!   classed by its depths like a dielectric instead — the depths come first;
//! - **opaque**: every channel is absorbed within the thin limit ([`THIN_LIMIT_M`], 1 mm:
//!   a 1 mm sheet passes less than 1/e, a 1 cm object less than e⁻¹⁰) — silicon (δ of
//!   0.4–33 µm in the visible) and soot (about 0.1 µm) look like a mirror-dark solid, not
//!   like glass;
//! - **tinted**: not opaque, and some channel is absorbed within the scene scale's largest
//!   size ([`SCENE_SCALE_M`], 1 cm to 1 m) — coloured glass (soda-lime green, δ 0.7–23 cm);
//! - **transparent**: every channel's depth is at least the scene scale's largest size —
//!   clear glass, water (δ of metres to kilometres), or k = 0.
//!
//! For a tinted material the colour of its volume is the spectral transmittance
//! T(λ) = e^(−α(λ)D) over a distance D, summed against D65 and the CIE 1931 observer into
//! linear sRGB like every reference colour (SPEC §4): what white light becomes after D,
//! with D the smallest channel depth (the most absorbed channel falls to about 1/e there).
//! glTF's `KHR_materials_volume` (attenuationColor at attenuationDistance) and OpenPBR's
//! `transmission_color` at `transmission_depth` take exactly this pair.

use crate::color::spectral::reflectance_spectrum_rgb;
use crate::db::PageData;
use crate::spectrum::{index_held, spectral_wavelength_nm, ChannelIndex, Channels, Kind, SPECTRAL_SAMPLES, VISIBLE_NM};

/// The thin limit: absorbed within it in every channel, a material is opaque.
pub const THIN_LIMIT_M: f64 = 1e-3;
/// The scene scale the tinted class is judged at: objects from 1 cm to 1 m.
pub const SCENE_SCALE_M: (f64, f64) = (1e-2, 1.0);

/// How a material looks at the size of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Appearance {
    /// A conductor: its surface reflects, its volume is never seen.
    Metal,
    /// Every channel's absorption depth is at least the scene scale's largest size.
    Transparent,
    /// Not opaque, and some channel is absorbed within the scene scale: its volume has a colour.
    Tinted,
    /// Every channel is absorbed within [`THIN_LIMIT_M`].
    Opaque,
}

impl Appearance {
    /// Every class, in the order of the tables.
    pub const ALL: [Appearance; 4] = [Appearance::Metal, Appearance::Transparent, Appearance::Tinted, Appearance::Opaque];

    /// The name in tables and exports.
    pub fn name(self) -> &'static str {
        match self {
            Appearance::Metal => "metal",
            Appearance::Transparent => "transparent",
            Appearance::Tinted => "tinted",
            Appearance::Opaque => "opaque",
        }
    }

    /// Whether light passes through it (transparent or tinted).
    pub fn transmits(self) -> bool {
        matches!(self, Appearance::Transparent | Appearance::Tinted)
    }
}

/// The absorption depth δ = λ/(4πk) in metres of light of `nm` nanometres in a material of
/// extinction coefficient `k`; infinite for k ≤ 0 (no absorption).
///
/// ```
/// use nklut_optics::appearance::absorption_depth_m;
/// // k = 1e-7 at 500 nm: 500e-9 / (4π · 1e-7) = 0.398 m.
/// assert!((absorption_depth_m(1e-7, 500.0) - 0.3979).abs() < 1e-4);
/// assert_eq!(absorption_depth_m(0.0, 500.0), f64::INFINITY);
/// ```
pub fn absorption_depth_m(k: f64, nm: f64) -> f64 {
    if k > 0.0 {
        nm * 1e-9 / (4.0 * std::f64::consts::PI * k)
    } else {
        f64::INFINITY
    }
}

/// The class of a material from its kind and its absorption depths at the channel
/// wavelengths: a conductor absorbed within the thin limit in every channel is a metal;
/// anything else is classed by its depths.
pub fn classify(kind: Kind, depths_m: [f64; 3]) -> Appearance {
    let deepest = depths_m.iter().copied().fold(0.0, f64::max);
    let shallowest = depths_m.iter().copied().fold(f64::INFINITY, f64::min);
    if deepest < THIN_LIMIT_M {
        if kind == Kind::Conductor {
            Appearance::Metal
        } else {
            Appearance::Opaque
        }
    } else if shallowest < SCENE_SCALE_M.1 {
        Appearance::Tinted
    } else {
        Appearance::Transparent
    }
}

/// A material's volume at the scene scale: its class, the absorption depth per channel,
/// and for a tinted one the colour white light turns after the attenuation distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    /// The class at the scene scale.
    pub appearance: Appearance,
    /// δ per channel (m); infinite where k = 0.
    pub depths_m: [f64; 3],
    /// For a tinted material: the distance D (m, the smallest channel depth) and the linear
    /// sRGB of the spectral transmittance e^(−α(λ)D).
    pub attenuation: Option<Attenuation>,
    /// The largest k over 390–700 nm (every nanometre, k held beyond the data) and where.
    pub k_peak: KPeak,
}

/// The largest extinction coefficient of a page over the visible range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KPeak {
    /// The largest k.
    pub k: f64,
    /// Where it is (nm; the first wavelength where it ties).
    pub nm: f64,
}

/// The largest k over 390–700 nm at every whole nanometre (the first where it ties).
pub fn k_peak(data: &PageData) -> KPeak {
    let (lo, hi) = (VISIBLE_NM.0 as usize, VISIBLE_NM.1 as usize);
    (lo..=hi).map(|nm| nm as f64).fold(KPeak { k: 0.0, nm: VISIBLE_NM.0 }, |best, nm| {
        let k = index_held(data, nm).k;
        if k > best.k {
            KPeak { k, nm }
        } else {
            best
        }
    })
}

/// The colour white light turns after `distance_m` in a medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attenuation {
    /// The distance travelled (m).
    pub distance_m: f64,
    /// Linear sRGB of white light after that distance.
    pub colour: [f64; 3],
}

/// The least transmittance an exported attenuation colour channel takes: a channel the
/// colour matrix sends to 0 or below (an out-of-gamut spectrum) would make −ln(c) infinite;
/// at 10⁻⁶ the channel is black to any display and its coefficient finite (13.8/D).
pub const MIN_TRANSMITTANCE: f64 = 1e-6;

impl Attenuation {
    /// The colour every export writes: each channel clamped to [[`MIN_TRANSMITTANCE`], 1]
    /// (a transmittance is at most 1; the linear sRGB of a saturated spectrum can leave it).
    pub fn exported_colour(&self) -> [f64; 3] {
        self.colour.map(|c| if c.is_nan() { MIN_TRANSMITTANCE } else { c.clamp(MIN_TRANSMITTANCE, 1.0) })
    }

    /// The absorption coefficient per channel σ_c = −ln(c)/D (per metre) of the exported
    /// colour c at the distance D: KHR_materials_volume's definition (and three.js',
    /// Filament's `absorption`, Unity HDRP's), so that white light keeps e^(−σx) = c^(x/D)
    /// after x metres. Finite and ≥ 0.
    pub fn coefficients_per_m(&self) -> [f64; 3] {
        self.exported_colour().map(|c| (-c.ln()).max(0.0) / self.distance_m)
    }

    /// What white light keeps per channel after `x_m` metres: e^(−σ_c x).
    pub fn transmittance(&self, x_m: f64) -> [f64; 3] {
        self.coefficients_per_m().map(|sigma| (-sigma * x_m).exp())
    }

    /// The same medium as Blender's Volume Absorption node.
    pub fn volume_absorption(&self) -> VolumeAbsorption {
        VolumeAbsorption::from_coefficients(self.coefficients_per_m())
    }
}

/// Blender's Volume Absorption node (Cycles and EEVEE): a medium whose absorption
/// coefficient per channel is (1 − Color_c)·Density per scene unit (Cycles'
/// `svm_node_closure_volume`: the closure weight of an absorption volume is
/// (1 − color)·density). Its colour is therefore *not* a transmittance: the colour whose
/// coefficients are σ_c is Density = max_c σ_c, Color_c = 1 − σ_c/Density, which
/// keeps every channel in [0, 1] and reproduces σ exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeAbsorption {
    /// Color_c = 1 − σ_c/Density, linear, in [0, 1].
    pub colour: [f64; 3],
    /// Per metre (a scene whose unit is the metre).
    pub density: f64,
}

impl VolumeAbsorption {
    /// Density = max σ, Color = 1 − σ/max σ; a medium that absorbs nothing is white at
    /// density 0.
    pub fn from_coefficients(sigma: [f64; 3]) -> Self {
        let density = sigma.iter().copied().fold(0.0, f64::max);
        if density > 0.0 {
            Self { colour: sigma.map(|s| (1.0 - s / density).clamp(0.0, 1.0)), density }
        } else {
            Self { colour: [1.0; 3], density: 0.0 }
        }
    }

    /// (1 − Color_c)·Density: what Blender absorbs per scene unit.
    pub fn coefficients(&self) -> [f64; 3] {
        self.colour.map(|c| (1.0 - c) * self.density)
    }
}

/// The volume of a page whose channel indices at `channels` are `index`.
pub fn volume(data: &PageData, kind: Kind, index: &ChannelIndex, channels: &Channels) -> Volume {
    let nm = channels.nanometres();
    let depths_m = [0, 1, 2].map(|c| absorption_depth_m(index[c].k, nm[c]));
    let appearance = classify(kind, depths_m);
    let attenuation = (appearance == Appearance::Tinted).then(|| {
        let distance_m = depths_m.iter().copied().fold(f64::INFINITY, f64::min);
        Attenuation { distance_m, colour: transmittance_rgb(data, distance_m) }
    });
    Volume { appearance, depths_m, attenuation, k_peak: k_peak(data) }
}

/// Linear sRGB of the spectral transmittance e^(−4πk(λ)x/λ) over `distance_m`, the page's
/// k held beyond its data as every reference colour holds it (SPEC §4): (1, 1, 1) for a
/// medium that absorbs nothing.
pub fn transmittance_rgb(data: &PageData, distance_m: f64) -> [f64; 3] {
    let transmittance: Vec<f64> = (0..SPECTRAL_SAMPLES)
        .map(|i| {
            let nm = spectral_wavelength_nm(i);
            (-distance_m / absorption_depth_m(index_held(data, nm).k, nm)).exp()
        })
        .collect();
    reflectance_spectrum_rgb(&transmittance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::parse_page;
    use crate::spectrum::Index;

    const CHANNELS: [f64; 3] = [685.0, 535.0, 475.0];

    fn depths(k: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|c| absorption_depth_m(k[c], CHANNELS[c]))
    }

    /// Depths computed by hand, δ = λ/(4πk), and the classes they give.
    #[test]
    fn classes_of_hand_computed_absorption_depths() {
        // Water at 685 nm, k = 2.678e-8 (3d/liquids/water): δ = 685e-9/(4π·2.678e-8) = 2.035 m.
        let water = depths([2.678e-8, 1.576e-9, 9.35e-10]);
        assert!((water[0] - 2.0355).abs() < 1e-3, "{water:?}");
        assert_eq!(classify(Kind::Dielectric, water), Appearance::Transparent);
        // BK7, k ≈ 1e-8: δ ≈ 5 m.
        assert_eq!(classify(Kind::Dielectric, depths([1.03e-8, 7.59e-9, 1.0e-8])), Appearance::Transparent);
        // Soda-lime green, k = 4.847e-6 at 685 nm: δ = 685e-9/(4π·4.847e-6) = 1.125 cm.
        let green = depths([4.847e-6, 1.0785e-6, 8.446e-7]);
        assert!((green[0] - 0.011246).abs() < 1e-5, "{green:?}");
        assert_eq!(classify(Kind::Dielectric, green), Appearance::Tinted);
        // Silicon, k = 0.0447 at 475 nm: δ = 0.85 µm; the red channel's k = 0.0027: 20 µm.
        let silicon = depths([0.0026979, 0.0094138, 0.044972]);
        assert!(silicon.iter().all(|d| *d < 3e-5), "{silicon:?}");
        assert_eq!(classify(Kind::Dielectric, silicon), Appearance::Opaque);
        // Diesel soot, k ≈ 0.28: δ ≈ 0.19 µm.
        assert_eq!(classify(Kind::Dielectric, depths([0.2915, 0.2765, 0.2705])), Appearance::Opaque);
        // A flat dielectric (k = 0) is transparent; a conductor is a metal whatever its depths.
        assert_eq!(classify(Kind::Dielectric, depths([0.0; 3])), Appearance::Transparent);
        assert_eq!(classify(Kind::Conductor, depths([3.7, 2.2, 1.8])), Appearance::Metal);
        // A conductor by the k ≥ 1 rule whose red passes: PbI2 (k = 0 at 685 nm, 0.33 at
        // 535 nm: δ = 0.13 µm, k ≥ 1 only in the violet) is classed by its depths.
        assert_eq!(classify(Kind::Conductor, depths([0.0, 0.33, 0.6])), Appearance::Tinted);
        assert_eq!(classify(Kind::Conductor, depths([1e-9, 1e-9, 1e-9])), Appearance::Transparent);
        // The boundaries: exactly the scene scale is transparent, just below it tinted.
        assert_eq!(classify(Kind::Dielectric, [1.0, 2.0, 3.0]), Appearance::Transparent);
        assert_eq!(classify(Kind::Dielectric, [0.999, 2.0, 3.0]), Appearance::Tinted);
        assert_eq!(classify(Kind::Dielectric, [0.999e-3, 0.5e-3, 1e-6]), Appearance::Opaque);
        assert_eq!(classify(Kind::Dielectric, [1e-3, 0.5e-3, 1e-6]), Appearance::Tinted);
    }

    /// Blender's Volume Absorption absorbs (1 − Color)·Density: with Density = max σ and
    /// Color = 1 − σ/max σ a slab of x passes what glTF's pair (c, D) gives, c^(x/D);
    /// by hand with c = (0.4, 0.75, 0.7) at D = 2 cm.
    #[test]
    fn volume_absorption_reproduces_the_gltf_transmittance() {
        let a = Attenuation { distance_m: 0.02, colour: [0.4, 0.75, 0.7] };
        // σ = −ln(c)/D: red −ln 0.4 / 0.02 = 45.814 537 /m.
        let sigma = a.coefficients_per_m();
        assert!((sigma[0] - 45.814_536_593_707_76).abs() < 1e-9, "{sigma:?}");
        let blender = a.volume_absorption();
        assert_eq!(blender.density, sigma[0]);
        assert_eq!(blender.colour[0], 0.0);
        // Green: 1 − ln 0.75 / ln 0.4 = 1 − 0.313 963 = 0.686 037.
        assert!((blender.colour[1] - (1.0 - 0.75f64.ln() / 0.4f64.ln())).abs() < 1e-15);
        for x in [0.0, 0.02, 0.05, 0.3] {
            let expected = a.colour.map(|c| c.powf(x / 0.02));
            let slab = blender.coefficients().map(|s| (-s * x).exp());
            for c in 0..3 {
                assert!((slab[c] - expected[c]).abs() < 1e-12, "{x}: {slab:?} vs {expected:?}");
            }
        }
        // The old reading (Color = c, Density = 1/D) lets through far more: red at 5 cm
        // e^(−0.6·50·0.05) = 0.223 against 0.4^2.5 = 0.101.
        let old = VolumeAbsorption { colour: a.colour, density: 1.0 / a.distance_m };
        assert!(((-old.coefficients()[0] * 0.05).exp() - (-1.5f64).exp()).abs() < 1e-12);
        // Out-of-range colours are clamped before the logarithm: finite, non-negative.
        let wild = Attenuation { distance_m: 0.01, colour: [-0.02, 1.03, f64::NAN] };
        let sigma = wild.coefficients_per_m();
        assert!(sigma.iter().all(|s| s.is_finite() && *s >= 0.0), "{sigma:?}");
        assert_eq!(sigma[1], 0.0);
        assert!((sigma[0] - (-MIN_TRANSMITTANCE.ln()) / 0.01).abs() < 1e-9);
        assert_eq!(VolumeAbsorption::from_coefficients([0.0; 3]), VolumeAbsorption { colour: [1.0; 3], density: 0.0 });
    }

    /// A medium of constant k transmits e^(−x/δ) of every wavelength's light, so its colour
    /// over δ(λ) is grey at e^(−δ(535)/δ(λ)) weighted over λ; for k = 0 it is white, and
    /// the colour darkens monotonically with the distance.
    #[test]
    fn transmittance_of_flat_and_absorbing_media() {
        let clear = parse_page("c.yml", "DATA:\n  - type: tabulated n\n    data: |\n        0.3 1.5\n        0.9 1.5\n").unwrap();
        let white = transmittance_rgb(&clear, 1.0);
        assert!(white.iter().all(|v| (v - 1.0).abs() < 1e-9), "{white:?}");
        // k ∝ λ: α = 4πk/λ is the same at every wavelength, so T = e^(−αx) everywhere: grey.
        let grey =
            parse_page("g.yml", "DATA:\n  - type: tabulated nk\n    data: |\n        0.3 1.5 0.3e-6\n        0.9 1.5 0.9e-6\n").unwrap();
        let alpha = 4.0 * std::f64::consts::PI * 1e-6 / 1e-6; // k/λ = 1e-6/1 µm
        for x in [0.01, 0.1] {
            let rgb = transmittance_rgb(&grey, x);
            let expected = (-alpha * x).exp();
            assert!(rgb.iter().all(|v| (v - expected).abs() < 1e-9), "{x}: {rgb:?} vs {expected}");
        }
        let index: ChannelIndex = CHANNELS.map(|nm| Index::new(1.5, 1e-6 * nm / 1000.0));
        let v = volume(&grey, Kind::Dielectric, &index, &Channels::default());
        assert_eq!(v.appearance, Appearance::Tinted);
        let attenuation = v.attenuation.unwrap();
        // D is the smallest depth, 1/α: the colour there is e^(−1) in every channel.
        assert!((attenuation.distance_m - 1.0 / alpha).abs() < 1e-12);
        assert!(attenuation.colour.iter().all(|c| (c - (-1f64).exp()).abs() < 1e-9), "{attenuation:?}");
    }
}
