//! Screen-space ground-truth ambient occlusion (GTAO): Jimenez, Wu, Pesce and Jarabo,
//! "Practical Real-Time Strategies for Accurate Indirect Occlusion" (SIGGRAPH 2016 course
//! notes; Activision ATVI-TR-16-01), §3–4 and Algorithm 1 — the screen-space technique
//! engines ship (Unreal, Unity HDRP), measured beside surfel AO against the same
//! ray-traced reference, on the same frames.
//!
//! Derivation. Accessibility is the cosine-weighted open fraction of the hemisphere about
//! the unit normal n, A = (1/π) ∫ V(ω) (n·ω)⁺ dω. Parametrise the sphere by planes through
//! the view vector v (slices, at angle φ ∈ [0, π) in the image) and the angle θ from v
//! within a slice (θ ∈ (−π, π], positive toward the slice's image direction):
//! dω = |sin θ| dθ dφ. In a slice, n projects to n_φ = n − (n·a) a (a the slice plane's unit
//! normal), of length |n_φ| and at angle γ from v; then n·ω = |n_φ| cos(θ − γ). Where the
//! visible surface is a heightfield seen from the point (all between a horizon and the
//! tangent plane occluded), the open directions of the slice are θ ∈ [h₋, h₊], h₋ ≤ 0 ≤ h₊,
//! clamped to the hemisphere about n (γ − π/2 ≤ h₋, h₊ ≤ γ + π/2). Splitting the inner
//! integral at θ = 0, where |sin θ| changes sign, gives the paper's eq. 10:
//!
//!   â(φ) = |n_φ| · ¼ [(−cos(2h₋ − γ) + cos γ + 2h₋ sin γ) + (−cos(2h₊ − γ) + cos γ + 2h₊ sin γ)]
//!
//! and A = (1/π) ∫₀^π â(φ) dφ, here the mean over `slices` equally spaced φ (midpoints, the
//! same at every pixel: deterministic, no noise to filter). Check: an open plane facing the
//! viewer (γ = 0, h± = ±π/2) gives â = ¼ (2 + 2) = 1. φ must turn evenly about v: slices
//! taken evenly in image angle (as Algorithm 1 and XeGTAO do) are uneven about v away from
//! the image centre, and an open plane seen there at 60° off-axis comes out 0.99, not 1;
//! here φ is the angle about v and each slice's image direction is where P + ε·(its
//! direction) projects.
//!
//! Horizons (Algorithm 1): from the pixel's view-space point P, `steps` samples on each
//! side along the slice's image direction, evenly spaced out to the projected radius
//! (radius · f / −P_z pixels, f the focal length in pixels). Each reads the G-buffer's
//! sample at the pixel it falls in and takes the point where the ray through the sample's
//! own position meets that texel's plane ([`texel_plane_point`]); where 0 < |Q − P| <
//! radius it raises that side's horizon cosine (Q − P)·v / |Q − P|, which starts at the
//! tangent plane. A perspective camera maps the image line through P's pixel onto the
//! plane through the eye, P and the slice direction, so the samples lie in the slice. The normal's angle takes the saturated cosine (γ ∈ [−π/2, π/2]) as engines do,
//! so a normal interpolated past the silhouette does not flip the integral.
//!
//! What a depth buffer cannot show is not there: occluders off screen, behind the visible
//! surface or farther than the radius (the reference sees them all); and the visible
//! surface is taken as solid behind it (a thin object occludes like a wall). Off screen,
//! XeGTAO's clamping depth reads stand in for what is missing: a sample beyond the edge
//! reads the edge texel's depth at its own image position ([`edge_point`]), the surface at
//! the edge continued at its depth (`Heuristics::clamp_to_edge`; without it such samples
//! are skipped).
//!
//! One body over [`Real`]: f64 for the figures, and f32 in the operation order of
//! `shaders/gtao.wgsl`, its twin.

pub use crate::scene::gtao::{Heuristics, Preset};
use glam::DVec3;
use rayon::prelude::*;

use super::experiment::PixelSample;
use super::surfel::Surfel;
use crate::scene::surfels::Gtao;
use crate::trace::Camera;
use nklut_optics::fresnel::Real;

/// A covered pixel: its view-space point and unit normal (x right, y up, the camera at the
/// origin looking down −z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSample<T> {
    pub position: [T; 3],
    pub normal: [T; 3],
}

/// What GTAO reads: per pixel (row-major, top row first) the view-space sample or `None`
/// (no surface), and the focal length in pixels: the view-space point (x, y, z) lies at
/// pixel coordinates (w/2 + f·x/−z, h/2 − f·y/−z).
#[derive(Clone, Debug, PartialEq)]
pub struct GBuffer<T> {
    pub width: u32,
    pub height: u32,
    pub focal: T,
    pub samples: Vec<Option<ViewSample<T>>>,
}

impl<T: Real> GBuffer<T> {
    /// The sample at pixel coordinates (`x`, `y`) already floored; `None` off the image or
    /// where no surface is.
    fn at(&self, x: T, y: T) -> Option<&ViewSample<T>> {
        if x < T::ZERO || y < T::ZERO || !(x < T::count(self.width as usize)) || !(y < T::count(self.height as usize)) {
            return None;
        }
        self.samples.get(y.index() * self.width as usize + x.index())?.as_ref()
    }

    /// Whether pixel coordinates (`x`, `y`) already floored lie beyond the image's edge
    /// (NaN: not beyond, nothing to read).
    fn off_image(&self, x: T, y: T) -> bool {
        x < T::ZERO || y < T::ZERO || x > T::count(self.width as usize) - T::ONE || y > T::count(self.height as usize) - T::ONE
    }
}

impl GBuffer<f64> {
    /// The G-buffer of `camera`'s frame from what each pixel sees (`coverage`, from
    /// `SurfelScene::coverage`): the point and the smooth normal interpolated from the
    /// triangle's vertices (surfel centres and normals), as a rasteriser writes them.
    pub fn from_coverage(camera: &Camera, coverage: &[Option<PixelSample>], surfels: &[Surfel]) -> GBuffer<f64> {
        let samples = coverage
            .iter()
            .map(|pixel| {
                let pixel = pixel.as_ref()?;
                let (mut point, mut normal) = (DVec3::ZERO, DVec3::ZERO);
                for (&corner, &weight) in pixel.corners.iter().zip(&pixel.weights) {
                    point += weight * surfels[corner].centre;
                    normal += weight * surfels[corner].normal;
                }
                let normal = camera.view_direction(normal.try_normalize().unwrap_or(surfels[pixel.corners[0]].normal));
                Some(ViewSample { position: camera.view_point(point).to_array(), normal: normal.to_array() })
            })
            .collect();
        GBuffer { width: camera.width, height: camera.height, focal: camera.focal_pixels(), samples }
    }

    /// The same buffer in f32 (what the GPU pass is given).
    pub fn narrowed(&self) -> GBuffer<f32> {
        let narrow = |v: [f64; 3]| v.map(|x| x as f32);
        GBuffer {
            width: self.width,
            height: self.height,
            focal: self.focal as f32,
            samples: self
                .samples
                .iter()
                .map(|s| s.map(|s| ViewSample { position: narrow(s.position), normal: narrow(s.normal) }))
                .collect(),
        }
    }
}

fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn along<T: Real>(a: [T; 3], s: T, b: [T; 3]) -> [T; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// Eq. 10: a slice's open fraction, weighted by the projected normal's `length`, between
/// the horizons `h_minus` ≤ 0 ≤ `h_plus` (angles from v) with the normal at angle `gamma`.
/// The twin of `slice_visibility` in `shaders/gtao.wgsl`.
pub fn slice_visibility<T: Real>(h_minus: T, h_plus: T, gamma: T, length: T) -> T {
    let (cos_g, sin_g) = (gamma.cos(), gamma.sin());
    let two = T::of(2.0);
    let side_minus = -(two * h_minus - gamma).cos() + cos_g + two * h_minus * sin_g;
    let side_plus = -(two * h_plus - gamma).cos() + cos_g + two * h_plus * sin_g;
    length * T::of(0.25) * (side_minus + side_plus)
}

/// GTAO's parameters in a precision: the radius (scene units, before the multiplier), the
/// slices per pixel, the steps per side of a slice and the heuristics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameters<T> {
    pub radius: T,
    pub slices: u32,
    pub steps: u32,
    pub heuristics: Heuristics<T>,
}

impl Parameters<f64> {
    pub fn of(gtao: Gtao) -> Parameters<f64> {
        Parameters { radius: gtao.radius, slices: gtao.slices, steps: gtao.steps, heuristics: gtao.heuristics }
    }

    /// Algorithm 1 with `slices` × `steps` within `radius`.
    pub fn bare(radius: f64, slices: u32, steps: u32) -> Parameters<f64> {
        Parameters { radius, slices, steps, heuristics: Heuristics::BARE }
    }

    pub fn narrowed(self) -> Parameters<f32> {
        Parameters { radius: self.radius as f32, slices: self.slices, steps: self.steps, heuristics: self.heuristics.narrowed() }
    }

    /// G-buffer reads per covered pixel: both sides of every step of every slice, every frame.
    pub fn reads_per_pixel(&self) -> u64 {
        let frames = if self.heuristics.noise { self.heuristics.frames.max(1) } else { 1 };
        self.slices as u64 * 2 * self.steps as u64 * frames as u64
    }
}

/// The side of XeGTAO's Hilbert curve tile (level 6: 64 × 64 pixels).
pub const HILBERT_WIDTH: u32 = 64;

/// The position of pixel (`x`, `y`) mod [`HILBERT_WIDTH`] along the Hilbert curve that fills
/// the tile (0 ≤ index < 64², neighbours along the curve are neighbours in the tile): the
/// quadrant of each level, most significant first, numbered in the curve's order, the rest
/// of the coordinates turned into that quadrant's frame.
pub fn hilbert_index(x: u32, y: u32) -> u32 {
    let (mut x, mut y) = (x % HILBERT_WIDTH, y % HILBERT_WIDTH);
    let mut index = 0;
    let mut level = HILBERT_WIDTH / 2;
    while level > 0 {
        let right = u32::from(x & level != 0);
        let up = u32::from(y & level != 0);
        index += level * level * ((3 * right) ^ up);
        if up == 0 {
            if right == 1 {
                x = HILBERT_WIDTH - 1 - x;
                y = HILBERT_WIDTH - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        level /= 2;
    }
    index
}

/// The frame-to-frame stride of the noise index (XeGTAO `vaGTAO.hlsl`: 288 × (frame mod 64),
/// "the best so far" with a level-6 curve).
pub const NOISE_FRAME_STRIDE: u32 = 288;
/// The R2 sequence's steps, 1/g and 1/g² for g the plastic number (the real root of
/// x³ = x + 1): Roberts 2018, "The unreasonable effectiveness of quasirandom sequences".
pub const R2: [f64; 2] = [0.754_877_666_246_692_8, 0.569_840_290_998_053_3];
/// The R1 sequence's step, 1/φ (the golden ratio): the steps' offsets within a slice.
pub const R1: f64 = 0.618_033_988_749_894_9;

fn fraction<T: Real>(x: T) -> T {
    x - x.floor()
}

/// Pixel (`x`, `y`)'s noise in `frame`: (slice rotation, step offset), each in [0, 1): R2
/// at the pixel's Hilbert index plus [`NOISE_FRAME_STRIDE`] × (frame mod 64), offset by ½.
pub fn noise<T: Real>(x: u32, y: u32, frame: u32) -> [T; 2] {
    let index = hilbert_index(x, y) + NOISE_FRAME_STRIDE * (frame % 64);
    let i = T::count(index as usize);
    R2.map(|a| fraction(T::of(0.5) + i * T::of(a)))
}

/// Where the ray through pixel coordinates (`x`, `y`) meets the plane of the texel sample
/// `q` (its point and normal): the surface at the sample's own position rather than at
/// its texel's centre, so that a sample lies in its slice; `q`'s point where the ray
/// grazes that plane (|cos| ≤ 0.1) or meets it behind the eye. On a plane this is exact;
/// nearest-texel points alone lift the horizon of an open plane seen at 60° from its normal
/// by up to 0.03 in accessibility (the sample off the slice by up to half a pixel). The twin
/// of `texel_plane_point` in `shaders/gtao.wgsl`.
pub fn texel_plane_point<T: Real>(g: &GBuffer<T>, q: &ViewSample<T>, x: T, y: T) -> [T; 3] {
    let half = T::of(0.5);
    let ray = [(x - half * T::count(g.width as usize)) / g.focal, -(y - half * T::count(g.height as usize)) / g.focal, -T::ONE];
    let facing = dot(ray, q.normal);
    if !(facing.abs() > T::of(0.1) * dot(ray, ray).sqrt()) {
        return q.position;
    }
    let t = dot(q.position, q.normal) / facing;
    if t > T::ZERO {
        ray.map(|r| r * t)
    } else {
        q.position
    }
}

/// Where a sample at pixel coordinates (`x`, `y`) beyond the image's edge stands when it
/// reads the edge texel `q` ([`Heuristics::clamp_to_edge`]): on the ray through (`x`, `y`)
/// at `q`'s view-space depth, as XeGTAO reconstructs a clamped read. The twin of
/// `edge_point` in `shaders/gtao.wgsl`.
pub fn edge_point<T: Real>(g: &GBuffer<T>, q: &ViewSample<T>, x: T, y: T) -> [T; 3] {
    let half = T::of(0.5);
    let depth = -q.position[2];
    [(x - half * T::count(g.width as usize)) / g.focal * depth, -(y - half * T::count(g.height as usize)) / g.focal * depth, -depth]
}

/// The accessibility GTAO gives pixel (`x`, `y`) of `g` (`None`: no surface there): the
/// mean over the accumulated frames of each frame's value, each with its own noise (one
/// frame without noise: Algorithm 1's fixed slices and steps). The twin of
/// `pixel_visibility` in `shaders/gtao.wgsl` (bare heuristics).
pub fn pixel_visibility<T: Real>(g: &GBuffer<T>, x: u32, y: u32, p: Parameters<T>) -> Option<T> {
    let h = p.heuristics;
    if !h.noise {
        // Every frame is the same: one is their mean.
        return frame_visibility(g, x, y, p, [T::of(0.5), T::ONE]);
    }
    let frames = h.frames.max(1);
    let mut total = T::ZERO;
    for frame in 0..frames {
        total = total + frame_visibility(g, x, y, p, noise(x, y, frame))?;
    }
    Some(total / T::count(frames as usize))
}

/// One frame's accessibility at pixel (`x`, `y`) with slice rotation `offsets[0]` (slice i
/// at φ = π(i + offsets[0])/slices) and step offset `offsets[1]` (per slice the steps'
/// offsets follow R1 from it; with noise off every step's offset is `offsets[1]`).
fn frame_visibility<T: Real>(g: &GBuffer<T>, x: u32, y: u32, p: Parameters<T>, offsets: [T; 2]) -> Option<T> {
    let h = p.heuristics;
    let (px, py) = (T::count(x as usize), T::count(y as usize));
    let here = *g.at(px, py)?;
    let position = here.position;
    let distance = dot(position, position).sqrt();
    let depth = -position[2];
    if !(distance > T::ZERO) || !(depth > T::ZERO) || p.slices == 0 {
        return Some(T::ONE);
    }
    let v = position.map(|c| -c / distance);
    let n = here.normal;
    let half = T::of(0.5);
    let half_pi = T::of(std::f64::consts::FRAC_PI_2);
    let pi = T::of(std::f64::consts::PI);
    let radius = p.radius * h.radius_multiplier;
    let radius_pixels = radius * g.focal / depth;
    if radius_pixels < h.min_radius_pixels {
        return Some(T::ONE);
    }
    let radius_pixels = radius_pixels.min(h.max_radius_pixels);
    let radius2 = radius * radius;
    let hard_cut = !(h.falloff_range > T::ZERO);
    let thickness = T::ONE + h.thin_occluder;
    let uniform = h.distribution_power == T::ONE;
    let steps = T::count(p.steps as usize);
    let (last_x, last_y) = (T::count(g.width as usize) - T::ONE, T::count(g.height as usize) - T::ONE);
    // The slices turn about v evenly: e₁ the image's x axis made perpendicular to v (never
    // parallel: P lies in front of the eye), e₂ = v × e₁.
    let x_axis = [T::ONE, T::ZERO, T::ZERO];
    let e1 = along(x_axis, -v[0], v);
    let e1_length = dot(e1, e1).sqrt();
    let e1 = e1.map(|e| e / e1_length);
    let e2 = cross(v, e1);
    let mut total = T::ZERO;
    for slice in 0..p.slices {
        let phi = pi * (T::count(slice as usize) + offsets[0]) / T::count(p.slices as usize);
        let ortho = along(e1.map(|e| e * phi.cos()), phi.sin(), e2);
        // The slice's direction in the image: where P + ε·ortho projects, per ε.
        let screen_x = ortho[0] * depth + position[0] * ortho[2];
        let screen_y = -(ortho[1] * depth + position[1] * ortho[2]);
        let screen_length = (screen_x * screen_x + screen_y * screen_y).sqrt();
        if !(screen_length > T::ZERO) {
            continue;
        }
        let (c, s) = (screen_x / screen_length, screen_y / screen_length);
        let axis = cross(v, ortho);
        let projected = along(n, -dot(n, axis), axis);
        let length = dot(projected, projected).sqrt();
        if !(length > T::ZERO) {
            continue;
        }
        let cos_gamma = (dot(projected, v) / length).clamp(T::ZERO, T::ONE);
        let sign = if dot(projected, ortho) < T::ZERO { -T::ONE } else { T::ONE };
        let gamma = sign * cos_gamma.acos();
        // Horizon cosines, from the tangent plane: θ = γ + π/2 (plus side), γ − π/2 (minus).
        let (low_plus, low_minus) = ((gamma + half_pi).cos(), (gamma - half_pi).cos());
        let (mut cos_plus, mut cos_minus) = (low_plus, low_minus);
        for step in 0..p.steps {
            let offset = if h.noise { fraction(offsets[1] + T::count((slice + step * p.steps) as usize) * T::of(R1)) } else { offsets[1] };
            let position_in_steps = T::count(step as usize) + offset;
            let t = if uniform {
                radius_pixels * position_in_steps / steps
            } else {
                radius_pixels * (position_in_steps / steps).power(h.distribution_power)
            } + h.start_pixels;
            for side in [T::ONE, -T::ONE] {
                let (sample_x, sample_y) = (px + half + side * t * c, py + half + side * t * s);
                let (sx, sy) = (sample_x.floor(), sample_y.floor());
                if sx == px && sy == py {
                    continue;
                }
                let point = match g.at(sx, sy) {
                    Some(q) => texel_plane_point(g, q, sample_x, sample_y),
                    None if h.clamp_to_edge && g.off_image(sx, sy) => {
                        let Some(q) = g.at(sx.clamp(T::ZERO, last_x), sy.clamp(T::ZERO, last_y)) else { continue };
                        edge_point(g, q, sample_x, sample_y)
                    }
                    None => continue,
                };
                let delta = along(point, -T::ONE, position);
                let d2 = dot(delta, delta);
                if !(d2 > T::ZERO) {
                    continue;
                }
                // The distance the cut and the falloff see: the depth offset stretched.
                let thick = [delta[0], delta[1], delta[2] * thickness];
                let thick2 = dot(thick, thick);
                let cos_h = dot(delta, v) / d2.sqrt();
                let low = if side > T::ZERO { low_plus } else { low_minus };
                let cos_h = if hard_cut {
                    if !(thick2 < radius2) {
                        continue;
                    }
                    cos_h
                } else {
                    let weight = ((radius - thick2.sqrt()) / (h.falloff_range * radius)).clamp(T::ZERO, T::ONE);
                    low + weight * (cos_h - low)
                };
                if side > T::ZERO {
                    cos_plus = raised_horizon(cos_plus, cos_h, h.thickness_blend);
                } else {
                    cos_minus = raised_horizon(cos_minus, cos_h, h.thickness_blend);
                }
            }
        }
        let h_plus = gamma + (cos_plus.clamp(-T::ONE, T::ONE).acos() - gamma).min(half_pi);
        let h_minus = gamma + (-cos_minus.clamp(-T::ONE, T::ONE).acos() - gamma).max(-half_pi);
        let weight = length + h.normal_lerp * (T::ONE - length);
        total = total + slice_visibility(h_minus, h_plus, gamma, weight);
    }
    let open = (total / T::count(p.slices as usize)).clamp(T::ZERO, T::ONE);
    Some(if h.final_power == T::ONE { open } else { open.power(h.final_power) })
}

/// A slice side's horizon cosine after a sample of cosine `sample` (the falloff already
/// applied): a higher sample raises it to the sample; a lower one pulls it toward the sample
/// by `blend`² (Unreal's thickness heuristic, `r.GTAO.ThicknessBlend`: the horizon c becomes
/// lerp(sample, c, 1 − b²) = c − b²(c − sample)). With `blend` 0 it is the larger of the two,
/// Algorithm 1's horizon. The twin of `raised_horizon` in `shaders/gtao.wgsl`.
pub fn raised_horizon<T: Real>(horizon: T, sample: T, blend: T) -> T {
    if sample > horizon {
        sample
    } else {
        horizon - blend * blend * (horizon - sample)
    }
}

/// Every pixel's GTAO accessibility (row-major; `None` where no surface is): each pixel's
/// accumulated value, then the heuristics' denoiser passes over the image
/// ([`super::denoise`]; denoising each frame before accumulating gives the same, the
/// denoiser being linear in the values).
pub fn gtao<T: Real + Send + Sync>(g: &GBuffer<T>, p: Parameters<T>) -> Vec<Option<T>> {
    let values: Vec<Option<T>> = (0..g.width as usize * g.height as usize)
        .into_par_iter()
        .map(|i| pixel_visibility(g, (i % g.width as usize) as u32, (i / g.width as usize) as u32, p))
        .collect();
    super::denoise::denoise(g, &values, p.heuristics.denoise_passes, p.heuristics.denoise_beta)
}

#[cfg(test)]
mod tests {
    //! GTAO against closed forms, on G-buffers ray-cast here from analytic surfaces (no
    //! mesh, no tracer of the crate): a plane, a hemispherical bowl, a floor meeting a wall.

    use super::*;

    /// A pinhole camera at `eye` looking at `target` (world y up), `size`² pixels (odd, so
    /// that the target lies at the centre of the middle pixel) with a 60° field of view.
    struct Pinhole {
        eye: DVec3,
        right: DVec3,
        up: DVec3,
        forward: DVec3,
        size: u32,
        focal: f64,
    }

    impl Pinhole {
        fn new(eye: DVec3, target: DVec3, size: u32) -> Pinhole {
            let forward = (target - eye).normalize();
            let right = forward.cross(DVec3::Y).normalize();
            let up = right.cross(forward);
            Pinhole { eye, right, up, forward, size, focal: size as f64 / (2.0 * 30f64.to_radians().tan()) }
        }

        /// The G-buffer of the surface `hit(origin, direction) → (point, normal)`.
        fn gbuffer(&self, hit: impl Fn(DVec3, DVec3) -> Option<(DVec3, DVec3)>) -> GBuffer<f64> {
            let half = self.size as f64 / 2.0;
            let view = |d: DVec3| [d.dot(self.right), d.dot(self.up), -d.dot(self.forward)];
            let samples = (0..self.size * self.size)
                .map(|i| {
                    let (x, y) = ((i % self.size) as f64 + 0.5, (i / self.size) as f64 + 0.5);
                    let direction =
                        (self.forward + self.right * ((x - half) / self.focal) - self.up * ((y - half) / self.focal)).normalize();
                    let (point, normal) = hit(self.eye, direction)?;
                    Some(ViewSample { position: view(point - self.eye), normal: view(normal) })
                })
                .collect();
            GBuffer { width: self.size, height: self.size, focal: self.focal, samples }
        }

        fn centre(&self) -> (u32, u32) {
            (self.size / 2, self.size / 2)
        }
    }

    /// A hemispherical bowl (the lower half of the unit sphere, seen from inside through its
    /// opening) under an eye 4 above its centre: the camera and its G-buffer.
    fn bowl() -> (Pinhole, GBuffer<f64>) {
        let hit = |o: DVec3, d: DVec3| {
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - 1.0);
            if disc < 0.0 {
                return None;
            }
            // The far intersection: the inside of the sphere seen through the opening.
            let p = o + (-b + disc.sqrt()) * d;
            (p.y <= 0.0).then_some((p, -p))
        };
        let camera = Pinhole::new(DVec3::new(0.0, 4.0, 0.001), DVec3::new(0.0, -1.0, 0.0), 101);
        let g = camera.gbuffer(hit);
        (camera, g)
    }

    /// The nearest of the plane y = 0 (normal +y) where `keep` holds.
    fn floor(o: DVec3, d: DVec3, keep: impl Fn(DVec3) -> bool) -> Option<(f64, DVec3, DVec3)> {
        let t = -o.y / d.y;
        let p = o + t * d;
        (t > 0.0 && keep(p)).then_some((t, p, DVec3::Y))
    }

    #[test]
    fn an_open_plane_is_fully_accessible_from_any_view() {
        // Every sample lies in the tangent plane, so each horizon is the tangent plane and
        // â(φ) = |n_φ|(cos γ + γ sin γ), whose mean over φ is 1 exactly; 64 slices (midpoint
        // rule on a smooth periodic integrand) leave little. A sample off the slice plane
        // by the pixel it falls in can raise a horizon above the tangent line of the slice
        // by a hair: measured 6e-7.
        for eye in [DVec3::new(0.0, 3.0, 0.01), DVec3::new(-2.0, 1.0, 0.5), DVec3::new(1.0, 0.3, -1.5)] {
            let camera = Pinhole::new(eye, DVec3::ZERO, 41);
            let g = camera.gbuffer(|o, d| floor(o, d, |_| true).map(|(_, p, n)| (p, n)));
            let (x, y) = camera.centre();
            let open = pixel_visibility(&g, x, y, Parameters::bare(1.0, 64, 16)).unwrap();
            assert!((open - 1.0).abs() < 1e-5, "{eye}: {open}");
            // With 2 slices the midpoint rule is coarse where the view is oblique.
            let coarse = pixel_visibility(&g, x, y, Parameters::bare(1.0, 2, 16)).unwrap();
            assert!((coarse - 1.0).abs() < 0.2, "{eye}: {coarse}");
        }
    }

    /// Inside a sphere, dF = cos θ₁ cos θ₂ dA / (π s²) with s = 2R cos θ₁ = 2R cos θ₂, so
    /// the view factor from any point of it to any region is area / 4πR². The opening of a
    /// hemispherical bowl lets through exactly the rays that would meet the missing upper
    /// hemisphere (area 2πR²): every point of the bowl sees open sky 1/2.
    #[test]
    fn every_point_of_a_hemispherical_bowl_sees_half_the_sky() {
        let (camera, g) = bowl();
        let (x, y) = camera.centre();
        let error = |steps: u32| {
            let p = Parameters::bare(2.5, 16, steps);
            (pixel_visibility(&g, x, y, p).unwrap() - 0.5).abs()
        };
        // From the bottom (5 below the eye) the rim is 45° up and A = cos² e at horizon
        // elevation e (|dA/de| ≤ 1). A bowl point at polar angle α shows at ρ = sin α /
        // (4 + cos α) focal lengths from the centre, dρ/dα = 1/16 at the rim: a step of the
        // search, 0.5/steps focal lengths (radius 2.5 at depth 5), is up to 8/steps rad of
        // α there, and the last sample inside the rim falls short of it by at most that:
        // e by at most 4/steps, A by at most 4/steps.
        for steps in [16, 64, 256] {
            let e = error(steps);
            assert!(e <= 4.0 / steps as f64, "{steps} steps: {e}");
        }
        assert!(error(256) < error(16));
        // Every bowl point more than 0.5 below the rim (its search still reaches the far
        // rim, at most 2 away).
        let p = Parameters::bare(2.5, 16, 256);
        let (mut checked, mut largest) = (0, 0.0f64);
        for (i, sample) in g.samples.iter().enumerate() {
            let Some(s) = sample else { continue };
            let view = DVec3::from_array(s.position);
            let world = camera.eye + camera.right * view.x + camera.up * view.y - camera.forward * view.z;
            if -world.y < 0.5 {
                continue;
            }
            let a = pixel_visibility(&g, (i as u32) % g.width, (i as u32) / g.width, p).unwrap();
            largest = largest.max((a - 0.5).abs());
            checked += 1;
        }
        // Measured: 885 pixels, largest 0.028 (at the bottom 0.082, 0.029, 0.0098 with 16,
        // 64, 256 steps); a point up the side sees its near rim closer and more foreshortened.
        assert!(largest < 0.04, "{largest}");
        assert!(checked > 800, "{checked}");
    }

    /// A floor point at distance d from a wall, occluders counted within the radius R (the
    /// wall taller and longer than R): in the slice at angle φ from the wall's normal
    /// (vertical slices, n = up) the wall's part within R ends at height √(R² − D²),
    /// D = d/cos φ, so the open part of that slice is ½ + D²/2R² (eq. 10 with γ = 0,
    /// h₋ = −π/2, cos h₊ = D/R); outside |φ| < φ₀ = acos(d/R) the wall is out of reach.
    /// Integrating over φ: A = 1 − φ₀/π + d √(R² − d²) / (π R²). Accessibility is a
    /// property of the point, so an oblique camera's slices give the same A.
    #[test]
    fn a_floor_point_beside_a_wall_matches_the_closed_form() {
        let (radius, height) = (1.0f64, 10.0);
        for d in [0.15, 0.5, 0.8] {
            let scene = |o: DVec3, dir: DVec3| {
                let floor_hit = floor(o, dir, |p| p.x < d);
                let t = (d - o.x) / dir.x;
                let p = o + t * dir;
                let wall_hit = (t > 0.0 && p.y >= 0.0 && p.y <= height && p.z.abs() <= height).then_some((t, p, -DVec3::X));
                [floor_hit, wall_hit].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, p, n)| (p, n))
            };
            let phi0 = (d / radius).acos();
            let expected =
                1.0 - phi0 / std::f64::consts::PI + d * (radius * radius - d * d).sqrt() / (std::f64::consts::PI * radius * radius);
            for eye in [DVec3::new(-2.0, 2.5, 0.3), DVec3::new(-1.0, 3.0, -1.2)] {
                let camera = Pinhole::new(eye, DVec3::ZERO, 201);
                let g = camera.gbuffer(scene);
                let (x, y) = camera.centre();
                let got = pixel_visibility(&g, x, y, Parameters::bare(radius, 32, 128)).unwrap();
                // The sampled wall point nearest the sphere of radius R lies within one step
                // of it, so the horizon can only fall short (A too high); the slices'
                // midpoint rule adds a little either way. Measured +0.0008 … +0.0099.
                assert!((got - expected).abs() < 0.015, "d {d}, eye {eye}: {got} against {expected}");
                assert!(got > expected - 1e-3, "d {d}, eye {eye}: {got} below {expected}");
            }
        }
    }

    /// XeGTAO's heuristics one at a time: Algorithm 1 with `change` applied.
    fn with(change: impl Fn(&mut Heuristics<f64>), radius: f64, slices: u32, steps: u32) -> Parameters<f64> {
        let mut p = Parameters::bare(radius, slices, steps);
        change(&mut p.heuristics);
        p
    }

    /// The mean over φ ∈ [0, π) of `f` by the midpoint rule on `n` points.
    fn mean_over_half_turn(n: usize, f: impl Fn(f64) -> f64) -> f64 {
        (0..n).map(|i| f(std::f64::consts::PI * (i as f64 + 0.5) / n as f64)).sum::<f64>() / n as f64
    }

    /// The Hilbert index runs through every pixel of the 64² tile once, each step to a
    /// pixel beside the last (what makes neighbouring indices neighbouring pixels).
    #[test]
    fn the_hilbert_index_walks_the_tile_one_neighbour_at_a_time() {
        let mut at = vec![None; 64 * 64];
        for y in 0..64 {
            for x in 0..64 {
                let i = hilbert_index(x, y) as usize;
                assert!(at[i].is_none(), "index {i} twice");
                at[i] = Some((x as i32, y as i32));
            }
        }
        let at: Vec<(i32, i32)> = at.into_iter().map(Option::unwrap).collect();
        assert_eq!(at[0], (0, 0));
        for pair in at.windows(2) {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            assert_eq!((x0 - x1).abs() + (y0 - y1).abs(), 1, "{pair:?}");
        }
        // The tile repeats.
        assert_eq!(hilbert_index(64 + 5, 128 + 7), hilbert_index(5, 7));
        // Noise: R2 at the index, offset ½; frame f adds 288 f to the index (mod 64 frames).
        let [a, b] = noise::<f64>(0, 0, 1);
        let expected = |k: usize| (0.5 + 288.0 * R2[k]).fract();
        assert!((a - expected(0)).abs() < 1e-12 && (b - expected(1)).abs() < 1e-12, "{a} {b}");
        assert_eq!(noise::<f64>(3, 9, 2), noise::<f64>(3, 9, 66));
    }

    /// A floor point straight below the eye, a wall at distance d (taller than the search
    /// radius R = radius × 1.457): n = v, so γ = 0, |n_φ| = 1 and the tangent plane's horizon
    /// cosine is 0. In the slice at angle φ from the wall's normal the wall lies at D = d/cos φ;
    /// its point at distance r ≥ D has horizon cosine √(1 − D²/r²) and, with the falloff,
    /// counts as w(r)·√(1 − D²/r²), w = clamp((R − r)/(fR), 0, 1) (the lerp toward the
    /// tangent plane's 0). On [D, R(1 − f)] this grows; beyond, its derivative vanishes where
    /// r³ = R D². So the slice's horizon cosine is c = that at clamp(max(R(1 − f), (RD²)^⅓), D,
    /// R) (0 where D ≥ R), its open part 1 − c²/2 (eq. 10, h₋ = −π/2), and A = 1 − (1/2π)
    /// ∫ c² dφ over |φ| < π/2. A wall at 1.5 × radius lies beyond R = 1.457 × radius: A = 1.
    #[test]
    fn the_falloff_matches_its_closed_form_beside_a_wall() {
        let radius = 0.5;
        let xe = |h: &mut Heuristics<f64>| {
            h.radius_multiplier = Heuristics::XE.radius_multiplier;
            h.falloff_range = Heuristics::XE.falloff_range;
        };
        let big_r = radius * Heuristics::XE.radius_multiplier;
        let f = Heuristics::XE.falloff_range;
        let horizon = |d: f64, phi: f64| {
            let dd = d / phi.cos();
            if dd >= big_r {
                return 0.0;
            }
            let r = (big_r * (1.0 - f)).max((big_r * dd * dd).cbrt()).clamp(dd, big_r);
            ((big_r - r) / (f * big_r)).clamp(0.0, 1.0) * (1.0 - dd * dd / (r * r)).sqrt()
        };
        let closed = |d: f64| 1.0 - 0.5 * mean_over_half_turn(100_000, |phi| horizon(d, phi - std::f64::consts::FRAC_PI_2).powi(2));
        // The same wall with the hard cut at R: the form of the test above.
        let hard = |d: f64| {
            let phi0 = (d / big_r).acos();
            1.0 - phi0 / std::f64::consts::PI + d * (big_r * big_r - d * d).sqrt() / (std::f64::consts::PI * big_r * big_r)
        };
        let camera = Pinhole::new(DVec3::new(0.0, 1.6, 0.01), DVec3::ZERO, 401);
        let (x, y) = camera.centre();
        for (multiple, d) in [(0.5, 0.5 * radius), (1.5, 1.5 * radius)] {
            let scene = |o: DVec3, dir: DVec3| {
                let floor_hit = floor(o, dir, |p| p.x < d);
                let t = (d - o.x) / dir.x;
                let p = o + t * dir;
                let wall_hit = (t > 0.0 && p.y >= 0.0 && p.y <= 1.0 && p.z.abs() <= 3.0).then_some((t, p, -DVec3::X));
                [floor_hit, wall_hit].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, p, n)| (p, n))
            };
            let g = camera.gbuffer(scene);
            let got = pixel_visibility(&g, x, y, with(xe, radius, 64, 512)).unwrap();
            let expected = closed(d);
            if multiple > 1.0 {
                assert_eq!(expected, 1.0);
                assert!((got - 1.0).abs() < 1e-5, "wall at {multiple} × radius: {got}");
            } else {
                // The falloff lets go of most of the occlusion the hard cut at the same search
                // radius counts (0.922 against 0.714).
                assert!(expected - hard(d) > 0.1, "{expected} against {}", hard(d));
                // Sampled horizons fall short of the true maximum (A too high) by what a step
                // of 1/512 of the radius misses, at a maximum where the slope is 0; the eye
                // 0.01 off the vertical tilts v by 0.006 rad. Measured 5e-6.
                eprintln!("falloff, wall at {multiple} × radius: {got} against {expected} (hard cut {})", hard(d));
                assert!((got - expected).abs() < 1e-3, "wall at {multiple} × radius: {got} against {expected}");
            }
        }
    }

    /// A thin strip (a pillar of no depth, |y| ≤ 10, a ≤ x ≤ a + w) at height h in front of a
    /// wall facing the eye, seen from the pixel straight behind it on the wall (n = v, γ = 0),
    /// hard cut at R. The strip's nearest point in the slice at angle φ is its edge, at
    /// ρ = a/cos φ beside the pixel and h in front: horizon cosine h/√(ρ² + h²), open part
    /// 1 − ½ h²/(ρ² + h²). With thin-occluder compensation c the cut sees the depth offset
    /// × (1 + c): the edge counts while ρ² + (1 + c)²h² < R², i.e. |φ| < φ₀, cos φ₀ = a/ρ_max.
    /// Integrating, A = 1 − (1/π)[φ₀ − (a/√(a² + h²)) atan(a tan φ₀/√(a² + h²))]; where
    /// (1 + c)h ≥ R the strip never counts and the wall is open, A = 1.
    #[test]
    fn thin_occluder_compensation_lets_a_thin_pillar_in_front_of_a_wall_go() {
        let (a, w, h, big_r) = (0.2f64, 0.3, 0.6f64, 1.0f64);
        let camera = Pinhole::new(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO, 201);
        let g = camera.gbuffer(|o, d| {
            let wall = (-o.z / d.z, DVec3::Z);
            let t = (h - o.z) / d.z;
            let p = o + t * d;
            let strip = (p.x >= a && p.x <= a + w && p.y.abs() <= 10.0).then_some((t, DVec3::Z));
            let (t, n) = strip.unwrap_or(wall);
            (t > 0.0).then(|| (o + t * d, n))
        });
        let (x, y) = camera.centre();
        let closed = |c: f64| {
            let reach2 = big_r * big_r - ((1.0 + c) * h).powi(2);
            if reach2 <= a * a {
                return 1.0;
            }
            let phi0 = (a / reach2.sqrt()).acos();
            let k = (a * a + h * h).sqrt();
            1.0 - (phi0 - a / k * (a * phi0.tan() / k).atan()) / std::f64::consts::PI
        };
        let mut previous = 0.0;
        for c in [0.0, 0.5, 0.7] {
            let expected = closed(c);
            assert!(expected > previous + 0.03, "{c}: {expected}");
            previous = expected;
            let got = pixel_visibility(&g, x, y, with(|k| k.thin_occluder = c, big_r, 64, 256)).unwrap();
            // The strip's edge is sampled within a pixel (0.014 at its depth): a sample in a
            // wall texel short of the edge misses it, one in a strip texel past the edge is
            // projected onto the strip's plane; each moves ρ by at most a pixel, the horizon
            // cosine by at most 0.47 × 0.014 (|∂/∂ρ| of h/√(ρ² + h²) ≤ 0.47 there). Measured:
            // −4e-4 (c = 0), +3.4e-3 (c = 0.5).
            eprintln!("thin occluder {c}: {got} against {expected}");
            assert!((got - expected).abs() < 0.006, "c {c}: {got} against {expected}");
        }
        assert_eq!(closed(0.7), 1.0);
    }

    /// Unreal's thickness blend b pulls the horizon toward a lower sample by b². By hand,
    /// after samples of cosine 0.8, 0.2, 0.2: b = 0.5 gives 0.8, 0.8 − ¼ · 0.6 = 0.65,
    /// 0.65 − ¼ · 0.45 = 0.5375; b = 1 the last sample, 0.2; b = 0 the highest, 0.8; and a
    /// higher sample always takes over.
    #[test]
    fn thickness_blend_pulls_the_horizon_toward_lower_samples() {
        let after = |blend: f64| [0.8, 0.2, 0.2].into_iter().fold(-1.0, |c, s| raised_horizon(c, s, blend));
        assert_eq!(after(0.5), 0.5375);
        assert_eq!(after(1.0), 0.2);
        assert_eq!(after(0.0), 0.8);
        assert_eq!(raised_horizon(0.3f32, 0.9, 0.5), 0.9);
        assert_eq!(raised_horizon(0.3f64, 0.9, 1.0), 0.9);
    }

    /// A square patch (0.2 ≤ x ≤ 0.5, |y| ≤ 0.15) 0.6 in front of a wall facing the eye, seen
    /// from the wall's pixel straight ahead (n = v), hard cut R = 1, 16 steps (sample k at
    /// (k + 1)/16 of the radius). The patch lies within R of the pixel (its far corner
    /// √(0.5² + 0.15² + 0.6²) = 0.79 away), so with b = 0 it darkens the slices that cross
    /// it. A ray to a wall sample ρ out crosses the patch's plane 0.8ρ from the axis, beyond
    /// the patch (0.52 at most) once ρ > 0.65: the samples from 11/16 on lie on the open wall,
    /// horizon cosine 0, the outermost counted one (15/16) among them. With b = 1 the horizon
    /// is that last sample, so every slice is open and A = 1; in between, the patch's horizon
    /// decays by (1 − b²) per wall sample after it (five of them: × 0.72 at b = ¼, × 0.24 at
    /// b = ½), and A rises with b.
    #[test]
    fn thickness_blend_forgets_a_patch_the_outer_samples_pass() {
        let (big_r, h) = (1.0f64, 0.6f64);
        let camera = Pinhole::new(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO, 201);
        let g = camera.gbuffer(|o, d| {
            let wall = (-o.z / d.z, DVec3::Z);
            let t = (h - o.z) / d.z;
            let p = o + t * d;
            let patch = (p.x >= 0.2 && p.x <= 0.5 && p.y.abs() <= 0.15).then_some((t, DVec3::Z));
            let (t, n) = patch.unwrap_or(wall);
            (t > 0.0).then(|| (o + t * d, n))
        });
        let (x, y) = camera.centre();
        let at = |b: f64| pixel_visibility(&g, x, y, with(|k| k.thickness_blend = b, big_r, 64, 16)).unwrap();
        let values: Vec<f64> = [0.0, 0.25, 0.5, 1.0].into_iter().map(at).collect();
        eprintln!("thickness blend 0, ¼, ½, 1: {values:?}");
        assert!(values[0] < 0.99, "the patch counts without the blend: {}", values[0]);
        assert!(values.windows(2).all(|w| w[1] > w[0]), "{values:?}");
        assert!((values[3] - 1.0).abs() < 1e-9, "{}", values[3]);
    }

    /// The final power raises the accessibility: the wall's closed form A becomes A^p,
    /// within p·A^(p−1) times the bare form's own bound (|x^p − y^p| ≤ p max(x, y)^(p−1)
    /// |x − y| for p ≥ 1). And the samples' distribution power 2 puts sample k at
    /// ((k + 1)/steps)² of the radius: at the rim of the bowl (the test above) a step is
    /// 2/steps of the radius instead of 1/steps, so the bowl's bound doubles to 8/steps.
    #[test]
    fn the_final_and_distribution_powers_meet_their_closed_forms() {
        let (radius, d, p) = (1.0f64, 0.5f64, Heuristics::XE.final_power);
        let scene = |o: DVec3, dir: DVec3| {
            let floor_hit = floor(o, dir, |q| q.x < d);
            let t = (d - o.x) / dir.x;
            let q = o + t * dir;
            let wall_hit = (t > 0.0 && q.y >= 0.0 && q.y <= 10.0 && q.z.abs() <= 10.0).then_some((t, q, -DVec3::X));
            [floor_hit, wall_hit].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, q, n)| (q, n))
        };
        let phi0 = (d / radius).acos();
        let closed = 1.0 - phi0 / std::f64::consts::PI + d * (radius * radius - d * d).sqrt() / (std::f64::consts::PI * radius * radius);
        let camera = Pinhole::new(DVec3::new(-2.0, 2.5, 0.3), DVec3::ZERO, 201);
        let g = camera.gbuffer(scene);
        let (x, y) = camera.centre();
        let plain = pixel_visibility(&g, x, y, Parameters::bare(radius, 32, 128)).unwrap();
        let powered = pixel_visibility(&g, x, y, with(|h| h.final_power = p, radius, 32, 128)).unwrap();
        assert!((powered - plain.powf(p)).abs() < 1e-12, "{powered} against {plain}^{p}");
        let bound = p * closed.max(plain).powf(p - 1.0) * 0.015;
        assert!((powered - closed.powf(p)).abs() < bound, "{powered} against {} ± {bound}", closed.powf(p));
        assert!(closed - closed.powf(p) > 5.0 * bound, "the power must show: {closed} → {}", closed.powf(p));

        let (camera, g) = bowl();
        let (x, y) = camera.centre();
        for steps in [16, 64, 256] {
            let a = pixel_visibility(&g, x, y, with(|h| h.distribution_power = 2.0, 2.5, 16, steps)).unwrap();
            assert!((a - 0.5).abs() <= 8.0 / steps as f64, "{steps} steps: {a}");
        }
    }

    /// A plane facing the eye whose centre pixel carries a normal tilted by θ (a normal map):
    /// every sample lies in the plane, horizon cosine 0 on both sides, so with n_φ at angle
    /// γ > 0 the plus side is open to π/2 and the minus side clamped to the tangent plane,
    /// γ − π/2; eq. 10 gives â(φ) = L(φ)(cos γ + ½ γ sin γ) (the same for γ < 0 by symmetry),
    /// L = |n_φ|. XeGTAO's lerp weights each slice by L + 0.05 (1 − L) instead of L.
    fn tilted_pixel(theta: f64) -> (GBuffer<f64>, (u32, u32), impl Fn(f64, f64) -> f64) {
        let camera = Pinhole::new(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO, 41);
        let mut g = camera.gbuffer(|o, d| {
            let t = -o.z / d.z;
            (t > 0.0).then(|| (o + t * d, DVec3::Z))
        });
        let (x, y) = camera.centre();
        let n = [0.0, theta.sin(), theta.cos()];
        g.samples[(y * g.width + x) as usize].as_mut().unwrap().normal = n;
        // The slice at φ turns about v = z from the image's x axis: axis = v × (cos φ, sin φ, 0).
        let slice = move |phi: f64, lerp: f64| {
            let axis = [-phi.sin(), phi.cos(), 0.0];
            let along_axis = n[0] * axis[0] + n[1] * axis[1];
            let projected = [n[0] - along_axis * axis[0], n[1] - along_axis * axis[1], n[2]];
            let l = dot(projected, projected).sqrt();
            let gamma = (projected[2] / l).acos();
            (l + lerp * (1.0 - l)) * (gamma.cos() + 0.5 * gamma * gamma.sin())
        };
        (g, (x, y), slice)
    }

    #[test]
    fn the_normal_lerp_matches_its_closed_form_on_a_tilted_normal() {
        let theta = 60f64.to_radians();
        let (g, (x, y), slice) = tilted_pixel(theta);
        for lerp in [0.0, Heuristics::XE.normal_lerp] {
            let expected = mean_over_half_turn(100_000, |phi| slice(phi, lerp));
            let got = pixel_visibility(&g, x, y, with(|h| h.normal_lerp = lerp, 1.0, 64, 8)).unwrap();
            // 64 midpoint slices of a smooth periodic integrand; measured 1e-6.
            assert!((got - expected).abs() < 1e-4, "lerp {lerp}: {got} against {expected}");
            assert!(expected < 0.95, "{expected}");
        }
        let gap = mean_over_half_turn(10_000, |phi| slice(phi, 0.05) - slice(phi, 0.0));
        assert!(gap > 0.005, "the lerp must show: {gap}");
    }

    /// N frames of one noisy slice each against the converged integral: frame f turns the
    /// slice to φ_f = π ξ_f (ξ_f the pixel's R2 slice offset in frame f), so the accumulated
    /// value is the mean of â(π ξ_f), and Koksma's inequality bounds its distance from
    /// (1/π) ∫ â by V(â) · D*_N, the total variation of â over the half turn times the star
    /// discrepancy of ξ₁ … ξ_N (for sorted ξ: 1/2N + max |ξ₍ᵢ₎ − (2i − 1)/2N|). On the tilted
    /// pixel every slice's value is exact whatever the steps, so the bound is all there is.
    #[test]
    fn accumulated_noise_meets_the_converged_integral_within_koksmas_bound() {
        let (g, (x, y), slice) = tilted_pixel(50f64.to_radians());
        let converged = mean_over_half_turn(100_000, |phi| slice(phi, 0.0));
        let fine: Vec<f64> = (0..=100_000).map(|i| slice(std::f64::consts::PI * i as f64 / 100_000.0, 0.0)).collect();
        let variation: f64 = fine.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
        let mut bounds = Vec::new();
        for frames in [1, 4, 16, 64] {
            let mut offsets: Vec<f64> = (0..frames).map(|f| noise::<f64>(x, y, f)[0]).collect();
            offsets.sort_by(f64::total_cmp);
            let n = frames as f64;
            let discrepancy = 1.0 / (2.0 * n)
                + offsets.iter().enumerate().map(|(i, &o)| (o - (2.0 * i as f64 + 1.0) / (2.0 * n)).abs()).fold(0.0, f64::max);
            let p = with(
                |h| {
                    h.noise = true;
                    h.frames = frames;
                },
                1.0,
                1,
                4,
            );
            let got = pixel_visibility(&g, x, y, p).unwrap();
            let bound = variation * discrepancy + 1e-9;
            eprintln!("{frames} frames: {got} against {converged} ± {bound}");
            assert!((got - converged).abs() <= bound, "{frames} frames: {got} against {converged} ± {bound}");
            bounds.push(bound);
        }
        // One frame's bound is at least V/2 (D*₁ ≥ ½); 64 frames' a tenth of it or less.
        assert!(bounds[3] < 0.1 * bounds[0] && bounds[3] < 0.03, "{bounds:?}");
    }

    /// Outside [min, max] pixels of screen radius: below the minimum the pixel is open; the
    /// maximum shortens the search (a wall beyond it in the image goes unseen).
    #[test]
    fn the_screen_radius_clamp_opens_small_radii_and_shortens_large_ones() {
        let d = 0.5;
        let scene = |o: DVec3, dir: DVec3| {
            let floor_hit = floor(o, dir, |q| q.x < d);
            let t = (d - o.x) / dir.x;
            let q = o + t * dir;
            let wall_hit = (t > 0.0 && q.y >= 0.0 && q.y <= 10.0 && q.z.abs() <= 10.0).then_some((t, q, -DVec3::X));
            [floor_hit, wall_hit].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, q, n)| (q, n))
        };
        let camera = Pinhole::new(DVec3::new(-2.0, 2.5, 0.3), DVec3::ZERO, 101);
        let g = camera.gbuffer(scene);
        let (x, y) = camera.centre();
        let depth = -g.samples[(y * g.width + x) as usize].unwrap().position[2];
        let radius_pixels = g.focal / depth;
        let plain = pixel_visibility(&g, x, y, Parameters::bare(1.0, 16, 64)).unwrap();
        assert!(plain < 0.9, "{plain}");
        let small = pixel_visibility(&g, x, y, with(|h| h.min_radius_pixels = radius_pixels * 1.01, 1.0, 16, 64)).unwrap();
        assert_eq!(small, 1.0);
        let kept = pixel_visibility(&g, x, y, with(|h| h.min_radius_pixels = radius_pixels * 0.99, 1.0, 16, 64)).unwrap();
        assert_eq!(kept, plain);
        // The wall's image lies farther than 2 px from the pixel in every direction.
        let short = pixel_visibility(&g, x, y, with(|h| h.max_radius_pixels = 2.0, 1.0, 16, 64)).unwrap();
        assert!((short - 1.0).abs() < 1e-3, "{short}");
        let unclamped = pixel_visibility(&g, x, y, with(|h| h.max_radius_pixels = radius_pixels * 1.5, 1.0, 16, 64)).unwrap();
        assert_eq!(unclamped, plain);
    }

    /// Clamping to the edge continues the edge texel's surface off the image at its depth.
    /// A plane facing the eye at depth 3 and, in front of it, a block facing the eye too
    /// (depth 2) over x ≥ 0.3, y ≥ 0.2 (from 26 px right of the centre and 17 px above it),
    /// cast over 201² pixels; its central 101² pixels (the same eye, focal length and
    /// centre) cut the block at the image's right edge, 50 px from the centre. From the
    /// centre pixel, with a search of 90 px (inside the 201² image), Algorithm 1's 16
    /// slices: the one at 16.9° up and right crosses the edge 15 px up, below the block,
    /// and meets the block only beyond it (from 60 px out). Unclamped, the small image loses
    /// that occluder; clamped, a sample there reads the edge texel of its own row (the block,
    /// depth 2) and stands at its own position at that depth, which is where the wide
    /// image's texel plane puts it (the block faces the eye). So the small image clamped
    /// equals the wide image exactly up to rounding, and unclamped it is lighter.
    #[test]
    fn clamping_to_the_edge_continues_the_edge_surface_at_its_depth() {
        let wide = Pinhole::new(DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO, 201);
        let g = wide.gbuffer(|o, d| {
            let block = (1.0 - o.z) / d.z;
            let p = o + block * d;
            let t = if p.x >= 0.3 && p.y >= 0.2 { block } else { -o.z / d.z };
            (t > 0.0).then(|| (o + t * d, DVec3::Z))
        });
        let (cut, size) = (50u32, 101u32);
        let small = GBuffer {
            width: size,
            height: size,
            focal: g.focal,
            samples: (0..size * size).map(|i| g.samples[((i / size + cut) * g.width + i % size + cut) as usize]).collect(),
        };
        // The search: 90 px at depth 3, from the centre (column 50 of 101) past column 100.
        let radius = 90.0 * 3.0 / g.focal;
        let (x, y) = (size / 2, size / 2);
        let clamped = with(|h| h.clamp_to_edge = true, radius, 16, 64);
        let wide_value = pixel_visibility(&g, x + cut, y + cut, clamped).unwrap();
        let small_clamped = pixel_visibility(&small, x, y, clamped).unwrap();
        let small_unclamped = pixel_visibility(&small, x, y, Parameters::bare(radius, 16, 64)).unwrap();
        assert!((small_clamped - wide_value).abs() < 1e-9, "{small_clamped} against {wide_value}");
        // One slice of 16 loses a side's horizon 45°–60° up (measured: 0.8995 against 0.8785).
        assert!(small_unclamped - wide_value > 0.01, "the edge must matter: {small_unclamped} against {wide_value}");
        // Inside the image clamping changes nothing: the wide image's own value.
        let wide_unclamped = pixel_visibility(&g, x + cut, y + cut, Parameters::bare(radius, 16, 64)).unwrap();
        assert_eq!(wide_unclamped, wide_value);
    }

    #[test]
    fn the_f32_twin_follows_the_f64_body() {
        let camera = Pinhole::new(DVec3::new(-2.0, 2.5, 0.3), DVec3::ZERO, 41);
        let g = camera.gbuffer(|o, d| {
            let wall = {
                let t = (0.4 - o.x) / d.x;
                let p = o + t * d;
                (t > 0.0 && p.y >= 0.0 && p.y <= 2.0).then_some((t, p, -DVec3::X))
            };
            [floor(o, d, |p| p.x < 0.4), wall].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, p, n)| (p, n))
        });
        let p = Parameters::bare(1.0, 4, 8);
        let wide = gtao(&g, p);
        let narrow = gtao(&g.narrowed(), p.narrowed());
        let mut largest = 0.0f64;
        for (a, b) in wide.iter().zip(&narrow) {
            assert_eq!(a.is_some(), b.is_some());
            if let (Some(a), Some(b)) = (a, b) {
                largest = largest.max((a - *b as f64).abs());
            }
        }
        // f32 rounding moves a sample to the neighbouring pixel only on a pixel boundary;
        // none does here. Measured 1.3e-6.
        assert!(largest < 1e-4, "{largest}");
        // XeGTAO High with 8 frames of noise: the noise's f32 index × R2 step (up to ~5 000,
        // ulp 5e-4) turns a slice by up to 1.6e-3 rad, and a sample crossing a pixel edge
        // reads another texel, so single pixels may differ more; the mean may not.
        // Measured: mean 1.3e-6, largest 7.9e-5 over 1681 pixels.
        let mut xe = Parameters { radius: 1.0, slices: 3, steps: 3, heuristics: Heuristics::XE };
        xe.heuristics.frames = 8;
        let wide = gtao(&g, xe);
        let narrow = gtao(&g.narrowed(), xe.narrowed());
        let differences: Vec<f64> = wide.iter().zip(&narrow).filter_map(|(a, b)| Some((a.as_ref()? - *b.as_ref()? as f64).abs())).collect();
        let mean = differences.iter().sum::<f64>() / differences.len() as f64;
        let largest = differences.iter().copied().fold(0.0, f64::max);
        eprintln!("xe-high, 8 frames: |f64 − f32| mean {mean:.2e}, largest {largest:.2e} over {} pixels", differences.len());
        assert!(mean < 1e-4 && largest < 1e-2, "{mean} {largest}");
    }
}
