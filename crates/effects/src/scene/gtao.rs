//! The settings of screen-space GTAO a scene names: the heuristics engines add to the
//! paper's Algorithm 1 (Jimenez et al. 2016), each a number with its source (XeGTAO,
//! Intel 2021; HDRP), and the named presets. Plain data; `ao::gtao` runs them.

/// The heuristics engines add to Algorithm 1, each a number with its source (XeGTAO's
/// `XeGTAO.h` defaults and `vaGTAO.hlsl` quality levels, Intel 2021; HDRP's screen-radius
/// clamp). [`Heuristics::BARE`] turns every one off: the paper's Algorithm 1 as
/// `ao::gtao::pixel_visibility` ran it before they existed, to the last bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heuristics<T> {
    /// The search radius is `radius` × this (XeGTAO `RadiusMultiplier`, 1.457: "to counter
    /// inherent screen space biases").
    pub radius_multiplier: T,
    /// The fraction of the (multiplied) radius over which a sample's weight falls linearly
    /// from 1 to 0 at the radius; 0 is the hard cut of §4.3 (XeGTAO `FalloffRange`, 0.615).
    /// A sample's horizon cosine is lerped toward the tangent plane's by 1 − weight.
    pub falloff_range: T,
    /// Sample k of `steps` (k = 0 …) lies at ((k + ξ)/steps)^power of the screen radius
    /// (XeGTAO `SampleDistributionPower`, 2: "small crevices more important").
    pub distribution_power: T,
    /// Pixels added to every sample's distance, so that none reads the centre pixel (XeGTAO
    /// `pixelTooCloseThreshold`, 1.3).
    pub start_pixels: T,
    /// A sample's distance for the falloff and the cut takes its view-space depth offset ×
    /// (1 + this): occluders far in front of or behind the pixel fall off sooner (XeGTAO
    /// `ThinOccluderCompensation`, default 0, range 0–0.7).
    pub thin_occluder: T,
    /// A sample below the slice side's horizon so far pulls the horizon down toward it by
    /// this squared (the horizon cosine c becomes c − b²(c − sample)): an occluder seen
    /// before open ground behind it counts as a thin one, not a wall to infinity. 0: the
    /// horizon is the highest sample (Algorithm 1). Unreal's `r.GTAO.ThicknessBlend`
    /// (default 0.5, uploaded as the lerp factor 1 − b²; "bigger values lead to reduced
    /// occlusion").
    pub thickness_blend: T,
    /// The accessibility is raised to this power (XeGTAO `FinalValuePower`, 2.2).
    pub final_power: T,
    /// The projected normal's length is lerped toward 1 by this before weighting a slice
    /// (XeGTAO's fudge against over-darkening on slopes, 0.05).
    pub normal_lerp: T,
    /// Below this screen radius (pixels) the pixel is taken as open, 1 (XeGTAO's early-out at
    /// `pixelTooCloseThreshold`, disabled there: 0).
    pub min_radius_pixels: T,
    /// The screen radius (pixels) is clamped to this (HDRP's "Maximum Radius In Pixels";
    /// XeGTAO has none: ∞).
    pub max_radius_pixels: T,
    /// Per-pixel slice rotation and step offsets from XeGTAO's Hilbert-curve-driven R2
    /// sequence (`ao::gtao::noise`), a new value each frame; off: slices at the midpoints of their
    /// sectors and samples at the ends of their steps (Algorithm 1).
    pub noise: bool,
    /// Frames accumulated (their mean, what temporal accumulation converges to): XeGTAO's
    /// noise repeats every 64 frames (`NoiseIndex = frameIndex % 64`).
    pub frames: u32,
    /// A sample beyond the image's edge reads the nearest edge texel's view-space depth and
    /// stands at its own image position at that depth, as XeGTAO's depth reads do (a point
    /// sampler with clamp addressing, `vaGTAO.hlsl`; `XeGTAO_ComputeViewspacePosition` of
    /// the unclamped position): the surface at the edge continues off screen at the edge's
    /// depth. Off: such a sample is skipped (Algorithm 1 here).
    pub clamp_to_edge: bool,
    /// Passes of XeGTAO's edge-aware 3 × 3 spatial denoiser over the image (`ao::denoise`):
    /// 0 off, XeGTAO's default 1 ("sharp"; 2 medium, 3 soft).
    pub denoise_passes: u32,
    /// The centre pixel's weight in the denoiser's last pass (each earlier pass: this / 5);
    /// a neighbour weighs its edge weight, at most 1 (XeGTAO `DenoiseBlurBeta`, 1.2).
    pub denoise_beta: T,
}

impl Heuristics<f64> {
    /// Algorithm 1 of the paper: no heuristic.
    pub const BARE: Heuristics<f64> = Heuristics {
        radius_multiplier: 1.0,
        falloff_range: 0.0,
        distribution_power: 1.0,
        start_pixels: 0.0,
        thin_occluder: 0.0,
        thickness_blend: 0.0,
        final_power: 1.0,
        normal_lerp: 0.0,
        min_radius_pixels: 0.0,
        max_radius_pixels: f64::INFINITY,
        noise: false,
        frames: 1,
        clamp_to_edge: false,
        denoise_passes: 0,
        denoise_beta: 1.2,
    };

    /// XeGTAO's defaults (`XeGTAO.h`, version 1.20): radius multiplier 1.457, falloff range
    /// 0.615, sample distribution power 2, thin-occluder compensation 0, final power 2.2;
    /// `XeGTAO.hlsli`: samples start 1.3 px out, |n_φ| lerped 5 % toward 1; `vaGTAO.hlsl`:
    /// noise from the Hilbert-R2 sequence, its index advancing each frame (mod 64) under TAA,
    /// depth read through a clamping sampler; `XeGTAO.h` `GTAOSettings`: one denoiser pass,
    /// blur beta 1.2.
    pub const XE: Heuristics<f64> = Heuristics {
        radius_multiplier: 1.457,
        falloff_range: 0.615,
        distribution_power: 2.0,
        start_pixels: 1.3,
        thin_occluder: 0.0,
        thickness_blend: 0.0,
        final_power: 2.2,
        normal_lerp: 0.05,
        min_radius_pixels: 0.0,
        max_radius_pixels: f64::INFINITY,
        noise: true,
        frames: 64,
        clamp_to_edge: true,
        denoise_passes: 1,
        denoise_beta: 1.2,
    };

    /// Unreal Engine's GTAO where its `r.GTAO.*` defaults differ from XeGTAO's: the search
    /// radius as given (no multiplier), the falloff over the outer half of it
    /// (`r.GTAO.FalloffStartRatio` 0.5), samples evenly spaced from one pixel out (its
    /// taps lie at max(step × (i + offset), i + 1) px), the thickness blend 0.5
    /// (`r.GTAO.ThicknessBlend`), no final power and no |n_φ| lerp, the screen radius
    /// clamped to 256 px (`GTAO_MAX_PIXEL_SCREEN_RADIUS`). Unreal's own per-pixel noise
    /// (interleaved gradient noise turned each frame) and 5 × 5 spatial filter are not
    /// reproduced: XeGTAO's noise, 64 frames and one pass of its denoiser stand in, so
    /// the preset measures Unreal's horizon search, not its filters.
    pub const UNREAL: Heuristics<f64> = Heuristics {
        radius_multiplier: 1.0,
        falloff_range: 0.5,
        distribution_power: 1.0,
        start_pixels: 1.0,
        thin_occluder: 0.0,
        thickness_blend: 0.5,
        final_power: 1.0,
        normal_lerp: 0.0,
        min_radius_pixels: 0.0,
        max_radius_pixels: 256.0,
        noise: true,
        frames: 64,
        clamp_to_edge: true,
        denoise_passes: 1,
        denoise_beta: 1.2,
    };

    pub fn narrowed(self) -> Heuristics<f32> {
        Heuristics {
            radius_multiplier: self.radius_multiplier as f32,
            falloff_range: self.falloff_range as f32,
            distribution_power: self.distribution_power as f32,
            start_pixels: self.start_pixels as f32,
            thin_occluder: self.thin_occluder as f32,
            thickness_blend: self.thickness_blend as f32,
            final_power: self.final_power as f32,
            normal_lerp: self.normal_lerp as f32,
            min_radius_pixels: self.min_radius_pixels as f32,
            max_radius_pixels: self.max_radius_pixels as f32,
            noise: self.noise,
            frames: self.frames,
            clamp_to_edge: self.clamp_to_edge,
            denoise_passes: self.denoise_passes,
            denoise_beta: self.denoise_beta as f32,
        }
    }

    /// Whether this is Algorithm 1 with no heuristic (what `shaders/gtao.wgsl` runs).
    pub fn is_bare(&self) -> bool {
        *self == Heuristics::BARE
    }
}

/// A named GTAO configuration: Algorithm 1 as the paper gives it, XeGTAO's quality levels
/// (`vaGTAO.hlsl`: Low 1 slice × 2 steps, Medium 2 × 2, High 3 × 3, Ultra 9 × 3 per side) with
/// its default heuristics ([`Heuristics::XE`]), or Unreal's defaults ([`Heuristics::UNREAL`]:
/// `r.GTAO.NumAngles` 2 slices, 8 taps per side, the middle of the 4, 6, 8, 12, 20 of its
/// shader quality levels). A scene names one and may override any number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    Bare,
    XeLow,
    XeMedium,
    XeHigh,
    XeUltra,
    Unreal,
}

impl Preset {
    pub const ALL: [Preset; 6] = [Preset::Bare, Preset::XeLow, Preset::XeMedium, Preset::XeHigh, Preset::XeUltra, Preset::Unreal];

    /// The name scenes and tables use.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Bare => "bare",
            Preset::XeLow => "xe-low",
            Preset::XeMedium => "xe-medium",
            Preset::XeHigh => "xe-high",
            Preset::XeUltra => "xe-ultra",
            Preset::Unreal => "unreal",
        }
    }

    pub fn named(name: &str) -> Option<Preset> {
        Preset::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Slices per pixel and steps per side of a slice (bare: the scenes' defaults, 4 × 8).
    pub fn slices_steps(self) -> [u32; 2] {
        match self {
            Preset::Bare => [4, 8],
            Preset::XeLow => [1, 2],
            Preset::XeMedium => [2, 2],
            Preset::XeHigh => [3, 3],
            Preset::XeUltra => [9, 3],
            Preset::Unreal => [2, 8],
        }
    }

    pub fn heuristics(self) -> Heuristics<f64> {
        match self {
            Preset::Bare => Heuristics::BARE,
            Preset::XeLow | Preset::XeMedium | Preset::XeHigh | Preset::XeUltra => Heuristics::XE,
            Preset::Unreal => Heuristics::UNREAL,
        }
    }
}
