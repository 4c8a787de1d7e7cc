//! Material previews rendered on the CPU: spheres seen orthographically along −z, each
//! pixel shaded F(θ) · L(r) — F the material's reflectance curve (linear sRGB per
//! channel, linearly interpolated on the curves' θ grid) at θ = acos(n·v), L the
//! environment's radiance in the mirror direction r = 2(n·v)n − v (the ideal specular
//! reflection) — then sRGB-encoded to 8 bits (IEC 61966-2-1). Deterministic: no random
//! sampling, no GPU. Also the colour-over-angle strips (F(θ) as a colour, 0° to 90°).
//!
//! A dielectric is seen through ([`transmitted`]): to the reflection each pixel adds what
//! passes through the sphere — (1 − F(θ))² (in, and out at the same angle by symmetry)
//! times the environment's radiance along the ray refracted in and out by Snell's law at
//! the channel's n (an exact sphere, analytic; internal reflections left out), times
//! Beer–Lambert's exp(−4πk/λ · chord) over a sphere [`SPHERE_DIAMETER_M`] across (the
//! volume's tint).

use std::io::Cursor;

use anyhow::{Context, Result};
use base64::Engine as _;
use image::{ImageFormat, RgbImage};

use nklut_optics::encoding::srgb_decode;

/// Side of one preview sphere in pixels (shown at this size on the material pages).
pub const PREVIEW_PX: u32 = 256;

/// Linear radiance of the background around the spheres (mid grey once encoded).
const BACKGROUND: f64 = 0.18;

/// What the spheres reflect.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Environment {
    /// A studio: a soft box behind the camera (the centre of the sphere shows F0),
    /// a floor-to-ceiling gradient, a bright horizontal strip and a rim light behind
    /// the sphere (the grazing rim shows F near 90°).
    Studio,
    /// The same radiance in every direction: each pixel is F(θ) times it.
    Uniform(f64),
}

impl Environment {
    /// Linear radiance (grey) in direction `r` (unit vector; +z toward the camera, +y up).
    pub fn radiance(self, r: [f64; 3]) -> f64 {
        match self {
            Environment::Uniform(value) => value,
            Environment::Studio => {
                let [_, y, z] = r;
                if (y - 0.45).abs() < 0.07 {
                    1.0
                } else if z > 0.8 {
                    0.9
                } else if z < -0.75 {
                    0.7
                } else {
                    0.06 + 0.3 * (0.5 * (y + 1.0)).clamp(0.0, 1.0)
                }
            }
        }
    }
}

/// Where a pixel of the sphere looks: the curve position and the environment's radiance.
#[derive(Clone, Copy, Debug)]
struct Texel {
    /// Index into the θ grid and the weight of the next sample.
    lower: usize,
    weight: f64,
    radiance: f64,
}

/// The geometry of a sphere image, shared by every material and method: per pixel,
/// `None` outside the sphere, else where it samples the curve and the environment.
pub struct SphereLayout {
    size: u32,
    texels: Vec<Option<Texel>>,
    environment: Environment,
}

/// The diameter of the preview sphere for the volume's absorption: 2 cm.
pub const SPHERE_DIAMETER_M: f64 = 0.02;

/// The direction `incident` (unit) refracted through a surface of unit `normal` (facing
/// against it) from index 1 into relative index `eta` = n_from / n_to; `None` at total
/// internal reflection.
fn refract(incident: [f64; 3], normal: [f64; 3], eta: f64) -> Option<[f64; 3]> {
    let cos_i = -(incident[0] * normal[0] + incident[1] * normal[1] + incident[2] * normal[2]);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| std::array::from_fn(|c| eta * incident[c] + (eta * cos_i - k.sqrt()) * normal[c]))
}

/// Per pixel of the layout's sphere (`None` outside it), per channel: the radiance that
/// comes through a dielectric of `index` (n, k per channel at `nanometres`) before the
/// (1 − F)² of the two surfaces — the environment along the ray refracted in at the pixel
/// and out where it leaves (unit sphere, view along −z), times exp(−4πk/λ · chord) with the
/// chord 2·cos θₜ of the sphere [`SPHERE_DIAMETER_M`] across. A channel without a finite
/// n ≥ 1 passes nothing.
pub fn transmitted(layout: &SphereLayout, index: &nklut_optics::spectrum::ChannelIndex, nanometres: [f64; 3]) -> Vec<Option<[f64; 3]>> {
    let size = layout.size;
    (0..size * size)
        .map(|i| {
            let normal = pixel_normal(i % size, i / size, size)?;
            Some(std::array::from_fn(|c| {
                let (n, k) = (index[c].n, index[c].k);
                if !(n >= 1.0) || !n.is_finite() {
                    return 0.0;
                }
                let inside = match refract([0.0, 0.0, -1.0], normal, 1.0 / n) {
                    Some(t) => t,
                    None => return 0.0,
                };
                // The chord from the entry point (= the normal on a unit sphere) along t.
                let cos_t = -(inside[0] * normal[0] + inside[1] * normal[1] + inside[2] * normal[2]);
                let chord = 2.0 * cos_t;
                let exit: [f64; 3] = std::array::from_fn(|a| normal[a] + chord * inside[a]);
                let out = refract(inside, exit.map(|v| -v), n).unwrap_or(inside);
                let alpha = 4.0 * std::f64::consts::PI * k.max(0.0) / (nanometres[c] * 1e-9);
                layout.environment.radiance(out) * (-alpha * chord * SPHERE_DIAMETER_M / 2.0).exp()
            }))
        })
        .collect()
}

/// cos θ at the centre of pixel (`px`, `py`) of a sphere `size` pixels wide, `None`
/// outside the disc: the normal is (x, y, √(1 − x² − y²)) with x, y ∈ [−1, 1].
pub fn pixel_normal(px: u32, py: u32, size: u32) -> Option<[f64; 3]> {
    let x = 2.0 * (px as f64 + 0.5) / size as f64 - 1.0;
    let y = 1.0 - 2.0 * (py as f64 + 0.5) / size as f64;
    let r2 = x * x + y * y;
    (r2 < 1.0).then(|| [x, y, (1.0 - r2).sqrt()])
}

impl SphereLayout {
    /// The layout for curves sampled at `theta_points` angles uniform over [0°, 90°].
    pub fn new(size: u32, theta_points: usize, environment: Environment) -> Self {
        let step = 90.0 / (theta_points - 1) as f64;
        let texels = (0..size * size)
            .map(|i| {
                let normal = pixel_normal(i % size, i / size, size)?;
                let cos = normal[2];
                let reflected = [2.0 * cos * normal[0], 2.0 * cos * normal[1], 2.0 * cos * normal[2] - 1.0];
                let position = (cos.acos().to_degrees() / step).min((theta_points - 1) as f64);
                let lower = (position.floor() as usize).min(theta_points - 2);
                Some(Texel { lower, weight: position - lower as f64, radiance: environment.radiance(reflected) })
            })
            .collect();
        Self { size, texels, environment }
    }

    pub fn size(&self) -> u32 {
        self.size
    }
}

impl Texel {
    /// F(θ) · L(r) of this pixel: the curve interpolated linearly between the grid's
    /// samples, times the environment's radiance.
    #[inline(always)]
    fn shade(&self, curve: &[[f64; 3]]) -> [f64; 3] {
        self.reflectance(curve).map(|f| f * self.radiance)
    }

    /// F(θ) of this pixel, interpolated on the curve.
    #[inline(always)]
    fn reflectance(&self, curve: &[[f64; 3]]) -> [f64; 3] {
        let (a, b) = (curve[self.lower], curve[self.lower + 1]);
        std::array::from_fn(|c| a[c] + (b[c] - a[c]) * self.weight)
    }
}

/// 8-bit sRGB code of a linear value, clamped to [0, 1]: round(255 · encode(linear)),
/// the number of the codes' rounding thresholds decode((c + ½)/255) at or below it,
/// instead of a `powf` per pixel channel. The count is looked up for the start of the
/// value's bucket of width 1/BUCKETS; thresholds lie at least 1/(255 · 12.92) ≈ 3.0e-4
/// apart (the slope of decode is smallest at 0), more than a bucket, so at most one more
/// threshold lies inside the bucket and one comparison settles it.
#[inline]
pub fn encode8(linear: f64) -> u8 {
    code_table().encode(linear)
}

/// Buckets of [`encode8`]'s table over [0, 1].
const BUCKETS: usize = 4096;

/// The rounding thresholds of the 8-bit codes and, per bucket, how many lie at or below
/// its start.
struct CodeTable {
    /// decode((c + ½)/255) for c = 0…254, then +∞.
    thresholds: [f64; 256],
    /// Thresholds at or below b/BUCKETS, for each bucket b.
    below: [u8; BUCKETS],
}

impl CodeTable {
    /// [`encode8`] with the table in hand.
    #[inline(always)]
    fn encode(&self, linear: f64) -> u8 {
        if !(linear > 0.0) {
            // 0, negative or NaN: below the first threshold.
            return 0;
        }
        if linear >= 1.0 {
            return 255;
        }
        // linear · BUCKETS is exact (a power of two), so b/BUCKETS ≤ linear.
        let bucket = ((linear * BUCKETS as f64) as usize).min(BUCKETS - 1);
        let below = self.below[bucket];
        below + (self.thresholds[below as usize] <= linear) as u8
    }
}

fn code_table() -> &'static CodeTable {
    static TABLE: std::sync::OnceLock<CodeTable> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let thresholds: [f64; 256] = std::array::from_fn(|c| if c < 255 { srgb_decode((c as f64 + 0.5) / 255.0) } else { f64::INFINITY });
        let below = std::array::from_fn(|b| thresholds.partition_point(|&t| t <= b as f64 / BUCKETS as f64) as u8);
        CodeTable { thresholds, below }
    })
}

/// Spheres side by side, one per curve, in one image `size · curves` pixels wide.
pub fn sheet(layout: &SphereLayout, curves: &[&[[f64; 3]]]) -> RgbImage {
    sheet_through(layout, curves, None)
}

/// [`sheet`] with, where `through` is given ([`transmitted`] of the material), the light
/// that passes through each sphere added: (1 − F(θ))² times it, per channel.
pub fn sheet_through(layout: &SphereLayout, curves: &[&[[f64; 3]]], through: Option<&[Option<[f64; 3]>]>) -> RgbImage {
    let size = layout.size() as usize;
    let width = size * curves.len();
    let mut image = RgbImage::new(width as u32, size as u32);
    let table = code_table();
    let background = [table.encode(BACKGROUND); 3];
    // Row by row of each sphere, straight into the image's bytes (3 per pixel).
    let bytes: &mut [u8] = &mut image;
    for (i, curve) in curves.iter().enumerate() {
        for (y, row) in layout.texels.chunks(size).enumerate() {
            let start = 3 * (y * width + i * size);
            for (x, (pixel, texel)) in bytes[start..start + 3 * size].chunks_exact_mut(3).zip(row).enumerate() {
                let rgb = texel.map_or(background, |t| {
                    let mut rgb = t.shade(curve);
                    if let Some(Some(passed)) = through.map(|p| p[y * size + x]) {
                        let f = t.reflectance(curve);
                        for c in 0..3 {
                            rgb[c] += (1.0 - f[c]).powi(2) * passed[c];
                        }
                    }
                    let [r, g, b] = rgb;
                    [table.encode(r), table.encode(g), table.encode(b)]
                });
                pixel.copy_from_slice(&rgb);
            }
        }
    }
    image
}

/// PNG bytes of an image (deterministic: same pixels, same bytes).
pub fn png(image: &RgbImage) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image.write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png).context("encoding a preview PNG")?;
    Ok(bytes)
}

/// A `data:` URI of PNG bytes, for an `<img src>` that keeps the page self-contained.
pub fn data_uri(png: &[u8]) -> String {
    format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(png))
}

/// A CSS `linear-gradient` left (0°) to right (90°) through the colour of each sample of
/// a curve on a θ grid uniform over [0°, 90°] (clamped, sRGB-encoded).
pub fn angle_gradient(curve: &[[f64; 3]]) -> String {
    use std::fmt::Write;
    let last = (curve.len() - 1) as f64;
    let mut css = String::from("linear-gradient(to right");
    for (i, rgb) in curve.iter().enumerate() {
        let _ = write!(css, ",{} {:.1}%", nklut_optics::color::srgb::hex_swatch(*rgb), 100.0 * i as f64 / last);
    }
    css.push(')');
    css
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::curves::theta_grid;
    use nklut_optics::fresnel::exact;

    fn decode8(code: u8) -> f64 {
        srgb_decode(code as f64 / 255.0)
    }

    /// One 8-bit step in linear terms around `value`.
    fn step_at(value: f64) -> f64 {
        let code = encode8(value) as f64 / 255.0;
        srgb_decode((code + 1.0 / 255.0).min(1.0)) - srgb_decode((code - 1.0 / 255.0).max(0.0))
    }

    #[test]
    fn a_sphere_of_constant_index_shows_f0_at_its_centre_and_the_grazing_value_at_its_rim() {
        for (n, k) in [(1.5, 0.0), (0.18, 3.4), (2.4, 0.0)] {
            let theta = theta_grid(91);
            let curve: Vec<[f64; 3]> = theta.iter().map(|t| [exact(n, k, t.to_radians().cos()); 3]).collect();
            let size = 95;
            let layout = SphereLayout::new(size, theta.len(), Environment::Uniform(1.0));
            let image = sheet(&layout, &[&curve]);
            // The centre pixel looks straight back along the view: θ = 0, F = F0.
            let f0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            let centre = image.get_pixel(size / 2, size / 2).0;
            assert_eq!(centre[0], encode8(f0), "n {n} k {k}: centre {} vs F0 {f0}", decode8(centre[0]));
            // The outermost pixel on the horizontal diameter: its own θ from geometry.
            let rim_cos = pixel_normal(0, size / 2, size).unwrap()[2];
            let grazing = exact(n, k, rim_cos);
            let rim = decode8(image.get_pixel(0, size / 2).0[1]);
            assert!((rim - grazing).abs() <= step_at(grazing), "n {n} k {k}: rim {rim} vs {grazing} at cos {rim_cos}");
            assert!(rim_cos < 0.2 && grazing > f0, "the rim is near grazing and brighter than F0");
            // Outside the disc: the background.
            assert_eq!(image.get_pixel(0, 0).0, [encode8(BACKGROUND); 3]);
        }
    }

    #[test]
    fn the_studio_shows_f0_in_the_centre_and_a_brighter_rim() {
        let layout = SphereLayout::new(PREVIEW_PX, 91, Environment::Studio);
        let curve: Vec<[f64; 3]> = theta_grid(91).iter().map(|t| [exact(1.5, 0.0, t.to_radians().cos()); 3]).collect();
        let image = sheet(&layout, &[&curve]);
        let centre = decode8(image.get_pixel(PREVIEW_PX / 2, PREVIEW_PX / 2).0[0]);
        assert!((centre - 0.9 * 0.04).abs() < step_at(0.036), "{centre}");
        let png = png(&image).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert!(data_uri(&png).starts_with("data:image/png;base64,iVBOR"));
    }

    /// A glass sphere (n 1.5, k 0) under a uniform sky of 1: the centre shows
    /// F0 + (1 − F0)² = 0.04 + 0.9216 = 0.9616, not a black ball. With k = 1e-6 at 550 nm the
    /// centre ray crosses the whole 2 cm: exp(−4π · 1e-6 / 550e-9 · 0.02) = 0.6333 of it
    /// passes. In the studio the centre sees straight through to the rim light behind
    /// (0.7) and reflects the soft box (0.9): 0.9 · 0.04 + 0.9216 · 0.7.
    #[test]
    fn a_dielectric_is_seen_through() {
        let theta = theta_grid(91);
        let curve: Vec<[f64; 3]> = theta.iter().map(|t| [exact(1.5, 0.0, t.to_radians().cos()); 3]).collect();
        let size = 95;
        let clear = [nklut_optics::spectrum::Index::new(1.5, 0.0); 3];
        let nm = [550.0; 3];
        let layout = SphereLayout::new(size, theta.len(), Environment::Uniform(1.0));
        let through = transmitted(&layout, &clear, nm);
        assert!(through[0].is_none(), "outside the disc");
        let centre = (size / 2 * size + size / 2) as usize;
        assert!((through[centre].unwrap()[0] - 1.0).abs() < 1e-12);
        let image = sheet_through(&layout, &[&curve], Some(&through));
        assert_eq!(image.get_pixel(size / 2, size / 2).0[0], encode8(0.04 + 0.96 * 0.96));
        let tinted = [nklut_optics::spectrum::Index::new(1.5, 1e-6); 3];
        let passed = transmitted(&layout, &tinted, nm)[centre].unwrap()[1];
        // The centre pixel of an odd size looks along the axis: the chord is the diameter.
        assert_eq!(pixel_normal(size / 2, size / 2, size).unwrap(), [0.0, 0.0, 1.0]);
        let expected = (-4.0 * std::f64::consts::PI * 1e-6 / 550e-9 * 0.02).exp();
        assert!((passed - expected).abs() < 1e-12 && (expected - 0.6333).abs() < 1e-3, "{passed} vs {expected}");
        let studio = SphereLayout::new(size, theta.len(), Environment::Studio);
        let image = sheet_through(&studio, &[&curve], Some(&transmitted(&studio, &clear, nm)));
        assert_eq!(image.get_pixel(size / 2, size / 2).0[1], encode8(0.9 * 0.04 + 0.96 * 0.96 * 0.7));
        // A conductor-like index (n < 1) passes nothing: the plain reflection.
        let metal = [nklut_optics::spectrum::Index::new(0.2, 3.0); 3];
        assert!(transmitted(&layout, &metal, nm)[centre].unwrap().iter().all(|&v| v == 0.0));
    }

    #[test]
    fn no_bucket_of_the_8_bit_table_holds_two_thresholds() {
        let table = code_table();
        for b in 0..BUCKETS {
            let end = if b + 1 < BUCKETS { table.below[b + 1] as usize } else { 255 };
            assert!(end - table.below[b] as usize <= 1, "bucket {b}");
        }
    }

    #[test]
    fn the_8_bit_encoder_rounds_like_the_transfer_function() {
        for i in 0..=20_000 {
            let linear = i as f64 / 20_000.0;
            assert_eq!(encode8(linear), (nklut_optics::encoding::srgb_encode(linear) * 255.0).round() as u8, "{linear}");
        }
        assert_eq!((encode8(-0.5), encode8(1.7), encode8(f64::NAN), encode8(0.0), encode8(1.0)), (0, 255, 0, 0, 255));
        // Exactly at each rounding threshold and one ulp either side: the plain count.
        for c in 0..255 {
            let t = srgb_decode((c as f64 + 0.5) / 255.0);
            for v in [t, f64::from_bits(t.to_bits() - 1), f64::from_bits(t.to_bits() + 1)] {
                let count = (0..255).filter(|&d| srgb_decode((d as f64 + 0.5) / 255.0) <= v).count();
                assert_eq!(encode8(v) as usize, count, "{v}");
            }
        }
    }

    #[test]
    fn gradients_run_from_normal_incidence_to_grazing() {
        let g = angle_gradient(&[[0.0; 3], [1.0; 3]]);
        assert_eq!(g, "linear-gradient(to right,#000000 0.0%,#ffffff 100.0%)");
    }
}
