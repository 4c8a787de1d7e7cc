//! The spectral mode of the f64 reference tracer: each pixel traced per wavelength, so
//! every bounce multiplies in F(λ) (exact Fresnel of the page's n(λ), k(λ)), refraction
//! bends each wavelength by its own n (dispersion), total internal reflection happens per
//! wavelength, and light inside a dielectric is attenuated by e^(−α(λ)d), α = 4πk(λ)/λ
//! (Beer–Lambert), d in metres (`effects.metres_per_unit`). The pixel is Σ_λ L(λ) w(λ) with
//! the weights of `colors` (`nklut_optics::color::spectral_weights`: CIE 1931 2°, D65,
//! XYZ → linear sRGB normalised to the integrated white; SPEC §4), so on the full 1 nm grid
//! one reflection of a surround of radiance 1 is `colors`' spectral reference colour.
//!
//! Wavelengths: a fixed grid of `count` contiguous bins of the 1 nm samples that carry weight
//! (360–780 nm, 421 samples; D65 ends at 780 nm), each bin weighted by the sum of its 1 nm
//! weights and its index read at its middle sample — the rectangle rule of the `colors`
//! sum at coarser spacing. `count` = 421 is `colors`' own sum; docs/effects.md records the
//! convergence as the count doubles.
//!
//! Geometry is shared across wavelengths wherever nothing disperses: a path carries a
//! bundle of wavelengths with their weights along one ray, and splits only at a refraction,
//! into runs of wavelengths with the same n (a flat or held index keeps one ray). Conductors
//! and mirror bounces never split a bundle. The rules per wavelength are the three-channel
//! reference's (`super::optics`): the side a ray arrives from by the triangle's plane; from
//! inside, where the wavelength refracts out at θₜ, F is its outside F at θₜ, else total
//! internal reflection with weight 1. So a flat spectrum (n, k constant; k = 0 in a
//! dielectric, whose α depends on λ) gives the three-channel reference to rounding.
//!
//! Diffuse surroundings: the albedo at the hit and the lights' summed RGB there are lifted
//! to spectra by `super::upsample` (Smits 1999, corrected to round-trip exactly) and
//! multiplied per wavelength: exact for grey lights, whose spectrum is D65's shape.

use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;

use super::geometry::Hit;
use super::optics::{facing, reflect, refract, Allowed};
use super::trace::{Camera, ObjectOptics, Stage, TracedFrame};
use super::upsample::Upsampler;
use crate::scene::lights::unshadowed;
use crate::scene::Depths;
use nklut_optics::color::spectral_weights;
use nklut_optics::fresnel::{sanitise, ExactTerms};
use nklut_optics::spectrum::{spectral_wavelength_nm, Index, Kind, SPECTRAL_SAMPLES};

/// What stops a spectral frame.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpectralError {
    #[error("a spectral frame needs 1..={max} wavelengths, not {count}")]
    WavelengthCount { count: usize, max: usize },
    #[error("object {object} has no spectrum (its material was not read with its page's data)")]
    NoSpectrum { object: usize },
    #[error("object {object}: its spectrum has {samples} samples, not the {expected} of the 1 nm grid")]
    SpectrumLength { object: usize, samples: usize, expected: usize },
}

/// The wavelengths of a spectral frame: each bin's centre as a (fractional) position on
/// the 1 nm grid, its wavelength and its colour weight (the sum of the bin's 1 nm weights).
#[derive(Clone, Debug, PartialEq)]
pub struct WavelengthGrid {
    pub centres: Vec<f64>,
    pub nm: Vec<f64>,
    pub weights: Vec<[f64; 3]>,
}

impl WavelengthGrid {
    /// The 1 nm samples that carry weight: `colors`' whole sum.
    pub fn full_count() -> usize {
        spectral_weights().active
    }

    /// `count` contiguous bins over the weighted 1 nm samples, as even as integers allow.
    pub fn new(count: usize) -> Result<WavelengthGrid, SpectralError> {
        let weights = spectral_weights();
        let active = weights.active;
        if !(1..=active).contains(&count) {
            return Err(SpectralError::WavelengthCount { count, max: active });
        }
        let mut grid =
            WavelengthGrid { centres: Vec::with_capacity(count), nm: Vec::with_capacity(count), weights: Vec::with_capacity(count) };
        for bin in 0..count {
            let (start, end) = (bin * active / count, (bin + 1) * active / count);
            // The bin's centre, between samples for an even run (a sample to one side
            // would bias every bin by half a nanometre, an error no count removes).
            let centre = (start + end - 1) as f64 / 2.0;
            grid.centres.push(centre);
            grid.nm.push(spectral_wavelength_nm(0) + centre);
            grid.weights.push(weights.rgb[start..end].iter().fold([0.0; 3], |s, w| [s[0] + w[0], s[1] + w[1], s[2] + w[2]]));
        }
        Ok(grid)
    }

    pub fn len(&self) -> usize {
        self.centres.len()
    }

    pub fn is_empty(&self) -> bool {
        self.centres.is_empty()
    }

    /// The index at a bin's centre: the 1 nm samples linearly interpolated (a whole
    /// position is the sample itself, so the full grid reads exactly `colors`' indices).
    pub fn index_at(spectrum: &[Index], centre: f64) -> Index {
        let low = centre.floor() as usize;
        let t = centre - low as f64;
        if t == 0.0 || low + 1 >= spectrum.len() {
            return spectrum[low.min(spectrum.len() - 1)];
        }
        let (a, b) = (spectrum[low], spectrum[low + 1]);
        Index::new(a.n + t * (b.n - a.n), a.k + t * (b.k - a.k))
    }

    /// Σ_λ L(λ) w(λ): the linear sRGB of a spectrum on this grid.
    pub fn colour(&self, spectrum: &[f64]) -> [f64; 3] {
        spectrum.iter().zip(&self.weights).fold([0.0; 3], |rgb, (s, w)| [rgb[0] + s * w[0], rgb[1] + s * w[1], rgb[2] + s * w[2]])
    }
}

/// One wavelength of a specular material: exact Fresnel's terms of its index from
/// outside, its n (Snell) and its attenuation per scene unit.
#[derive(Clone, Copy, Debug)]
struct Lane {
    terms: ExactTerms,
    n: f64,
    attenuation: f64,
}

/// A specular material on a grid.
#[derive(Clone, Debug)]
struct SpectralOptics {
    kind: Kind,
    lanes: Vec<Lane>,
    absorbing: bool,
}

impl SpectralOptics {
    fn new(spectrum: &[Index], kind: Kind, grid: &WavelengthGrid, metres_per_unit: f64) -> SpectralOptics {
        let lanes: Vec<Lane> = grid
            .centres
            .iter()
            .zip(&grid.nm)
            .map(|(&centre, &nm)| {
                let index = sanitise(WavelengthGrid::index_at(spectrum, centre));
                let attenuation = match kind {
                    Kind::Dielectric => super::optics::attenuation_per_unit(index.k, nm, metres_per_unit),
                    Kind::Conductor => 0.0,
                };
                Lane { terms: ExactTerms::new(index), n: index.n, attenuation }
            })
            .collect();
        SpectralOptics { kind, absorbing: lanes.iter().any(|l| l.attenuation > 0.0), lanes }
    }
}

/// A spectral frame: the colours (and which specular object each pixel shows), the rays
/// traced, the wavelength-rays (one ray at one wavelength; a ray carrying a bundle counts
/// each of its wavelengths) and the total internal reflections (per wavelength).
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralFrame {
    pub frame: TracedFrame,
    pub wavelength_rays: u64,
    pub total_internal_reflections: u64,
}

#[derive(Clone, Copy, Default)]
struct Counts {
    rays: u64,
    wavelength_rays: u64,
    total_internal_reflections: u64,
}

struct Context<'a> {
    stage: &'a Stage,
    optics: Vec<Option<SpectralOptics>>,
    upsampler: Upsampler,
    depths: Depths,
}

/// Where a pixel's light goes, per wavelength (lane) of the grid: what returns to the
/// camera, and what is still in flight when the depths run out (a bounce the depths do not
/// allow). Absorption (Beer–Lambert, a conductor's 1 − F) and rays leaving the scene are
/// neither. In a closed white furnace of lossless dielectrics every interface splits a
/// weight into F and 1 − F (weight 1 at a total internal reflection), so the two sum to 1
/// at every wavelength, whatever the mesh: the depth-truncation share is the whole loss.
struct Sums<'a> {
    radiance: &'a mut [f64],
    truncated: &'a mut [f64],
}

impl Sums<'_> {
    fn cut(&mut self, lane: u16, weight: f64) {
        self.truncated[lane as usize] += weight;
    }
}

/// A bundle's lanes and weights, inline up to four (past a dispersive refraction most
/// bundles carry one wavelength).
type Lanes = SmallVec<[u16; 4]>;
type Weights = SmallVec<[f64; 4]>;

/// A bundle: the wavelengths (lanes of the grid) a ray carries and their weights.
struct Bundle {
    lanes: Lanes,
    weights: Weights,
}

impl Context<'_> {
    /// The radiance spectrum of a diffuse surface, albedo spectrum × the lights' spectrum,
    /// added into `out` at the bundle's wavelengths only.
    fn diffuse(&self, hit: &Hit, bundle: &Bundle, out: &mut Sums) {
        let ObjectOptics::Diffuse(d) = &self.stage.objects[hit.object] else { unreachable!("called for diffuse objects") };
        let (p, n) = (hit.point.to_array(), hit.normal.to_array());
        let albedo = self.upsampler.lift(d.albedo_at(p, n));
        let light = self.upsampler.lift(unshadowed(&self.stage.lights, [1.0; 3], p, n));
        for (&lane, w) in bundle.lanes.iter().zip(&bundle.weights) {
            let lane = lane as usize;
            out.radiance[lane] += w * (self.upsampler.value(&albedo, lane) * self.upsampler.value(&light, lane));
        }
    }

    fn shade(&self, hit: &Hit, incoming: DVec3, bounces: u32, bundle: Bundle, out: &mut Sums, counts: &mut Counts) {
        match &self.optics[hit.object] {
            None => self.diffuse(hit, &bundle, out),
            Some(optics) => self.specular(optics, hit, incoming, bounces, bundle, out, counts),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn follow(
        &self,
        from: &Hit,
        direction: DVec3,
        inside: Option<&SpectralOptics>,
        bounces: u32,
        bundle: Bundle,
        out: &mut Sums,
        counts: &mut Counts,
    ) {
        let next = self.stage.geometry.nearest(from.point, direction, Some(from.triangle), |_| true);
        self.arrive(from, next, direction, inside, bounces, bundle, out, counts);
    }

    /// The bundle that left `from` along `direction` arrives at `next` (`None`: it leaves
    /// the scene): attenuated on the way through `inside`, then shaded there.
    #[allow(clippy::too_many_arguments)]
    fn arrive(
        &self,
        from: &Hit,
        next: Option<Hit>,
        direction: DVec3,
        inside: Option<&SpectralOptics>,
        bounces: u32,
        mut bundle: Bundle,
        out: &mut Sums,
        counts: &mut Counts,
    ) {
        counts.rays += 1;
        counts.wavelength_rays += bundle.lanes.len() as u64;
        let Some(next) = next else { return };
        if let Some(medium) = inside.filter(|m| m.absorbing) {
            let distance = next.point.distance(from.point);
            for (&lane, w) in bundle.lanes.iter().zip(bundle.weights.iter_mut()) {
                let alpha = medium.lanes[lane as usize].attenuation;
                if alpha > 0.0 {
                    *w *= (-alpha * distance).exp();
                }
            }
        }
        self.shade(&next, direction, bounces + 1, bundle, out, counts);
    }

    #[allow(clippy::too_many_arguments)]
    fn specular(
        &self,
        optics: &SpectralOptics,
        hit: &Hit,
        incoming: DVec3,
        bounces: u32,
        bundle: Bundle,
        out: &mut Sums,
        counts: &mut Counts,
    ) {
        let allowed = Allowed { reflection: bounces < self.depths.reflection, refraction: bounces < self.depths.refraction };
        let (from_inside, facing, cos_i) = facing(incoming, hit.normal, hit.geometric);
        let mirror = reflect(incoming, facing);
        if optics.kind == Kind::Conductor {
            let weights: Weights =
                bundle.lanes.iter().zip(&bundle.weights).map(|(&l, w)| w * optics.lanes[l as usize].terms.reflectance(cos_i)).collect();
            if allowed.reflection {
                self.follow(hit, mirror, None, bounces, Bundle { lanes: bundle.lanes, weights }, out, counts);
            } else {
                bundle.lanes.iter().zip(weights).for_each(|(&l, w)| out.cut(l, w));
            }
            return;
        }
        let mut mirrored = Bundle { lanes: Lanes::new(), weights: Weights::new() };
        // Each run's refracted ray; all leave this point, so they are traced together.
        let mut refracted: SmallVec<[(DVec3, Bundle); 1]> = SmallVec::new();
        let mut start = 0;
        while start < bundle.lanes.len() {
            // A run of wavelengths with one n shares its refracted ray.
            let n = optics.lanes[bundle.lanes[start] as usize].n;
            let end = start + bundle.lanes[start..].iter().take_while(|&&l| optics.lanes[l as usize].n == n).count();
            let (lanes, weights) = (&bundle.lanes[start..end], &bundle.weights[start..end]);
            let eta = if from_inside { n } else { 1.0 / n };
            match refract(incoming, facing, eta) {
                Some(direction) => {
                    let cos_f = if from_inside { direction.dot(-facing).clamp(0.0, 1.0) } else { cos_i };
                    let f: Weights = lanes.iter().map(|&l| optics.lanes[l as usize].terms.reflectance(cos_f)).collect();
                    let reflected = weights.iter().zip(&f).map(|(w, f)| w * f);
                    if allowed.reflection {
                        mirrored.lanes.extend_from_slice(lanes);
                        mirrored.weights.extend(reflected);
                    } else {
                        lanes.iter().zip(reflected).for_each(|(&l, w)| out.cut(l, w));
                    }
                    let transmitted = weights.iter().zip(&f).map(|(w, f)| w * (1.0 - f));
                    if allowed.refraction {
                        refracted.push((direction, Bundle { lanes: Lanes::from_slice(lanes), weights: transmitted.collect() }));
                    } else {
                        lanes.iter().zip(transmitted).for_each(|(&l, w)| out.cut(l, w));
                    }
                }
                None if allowed.refraction || allowed.reflection => {
                    if allowed.refraction {
                        counts.total_internal_reflections += lanes.len() as u64;
                    }
                    mirrored.lanes.extend_from_slice(lanes);
                    mirrored.weights.extend_from_slice(weights);
                }
                None => lanes.iter().zip(weights).for_each(|(&l, &w)| out.cut(l, w)),
            }
            start = end;
        }
        let inside = (!from_inside).then_some(optics);
        if refracted.len() == 1 {
            let (direction, bundle) = refracted.pop().expect("one refracted ray");
            self.follow(hit, direction, inside, bounces, bundle, out, counts);
        } else if !refracted.is_empty() {
            let directions: Vec<DVec3> = refracted.iter().map(|(d, _)| *d).collect();
            let hits = self.stage.geometry.nearest_rays(hit.point, &directions, Some(hit.triangle));
            for ((direction, bundle), next) in refracted.into_iter().zip(hits) {
                self.arrive(hit, next, direction, inside, bounces, bundle, out, counts);
            }
        }
        if !mirrored.lanes.is_empty() {
            let inside = from_inside.then_some(optics);
            self.follow(hit, mirror, inside, bounces, mirrored, out, counts);
        }
    }
}

impl<'a> Context<'a> {
    fn new(stage: &'a Stage, depths: Depths, grid: &WavelengthGrid) -> Result<Context<'a>, SpectralError> {
        let mut optics = Vec::with_capacity(stage.objects.len());
        for (object, o) in stage.objects.iter().enumerate() {
            optics.push(match o {
                ObjectOptics::Diffuse(_) => None,
                ObjectOptics::Specular(m) => {
                    let spectrum = stage.spectra.get(object).and_then(|s| s.as_ref()).ok_or(SpectralError::NoSpectrum { object })?;
                    if spectrum.len() != SPECTRAL_SAMPLES {
                        return Err(SpectralError::SpectrumLength { object, samples: spectrum.len(), expected: SPECTRAL_SAMPLES });
                    }
                    Some(SpectralOptics::new(spectrum, m.kind, grid, stage.metres_per_unit))
                }
            });
        }
        Ok(Context { stage, optics, upsampler: Upsampler::new(&grid.nm, &grid.weights), depths })
    }

    /// The radiance spectrum (per lane of the grid) along the camera ray `direction`, and
    /// the object it shows first; `None`: the ray meets nothing.
    fn primary(&self, eye: DVec3, direction: DVec3, out: &mut Sums, counts: &mut Counts) -> Option<usize> {
        let lanes = out.radiance.len();
        counts.rays += 1;
        counts.wavelength_rays += lanes as u64;
        out.radiance.iter_mut().chain(out.truncated.iter_mut()).for_each(|s| *s = 0.0);
        let hit = self.stage.geometry.nearest(eye, direction, None, |_| true)?;
        let bundle = Bundle { lanes: (0..lanes as u16).collect(), weights: Weights::from_elem(1.0, lanes) };
        self.shade(&hit, direction, 0, bundle, out, counts);
        Some(hit.object)
    }
}

/// One pixel on a grid's wavelengths: its radiance spectrum L(λ) (relative to D65), the
/// share of each wavelength still in flight when the depths ran out (see [`Sums`]) and the
/// total internal reflections along its paths.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralPixel {
    pub radiance: Vec<f64>,
    pub truncated: Vec<f64>,
    pub total_internal_reflections: u64,
}

/// Pixel (`x`, `y`) of the spectral reference on `grid`'s wavelengths.
pub fn spectral_pixel(
    stage: &Stage,
    camera: &Camera,
    (x, y): (u32, u32),
    depths: Depths,
    grid: &WavelengthGrid,
) -> Result<SpectralPixel, SpectralError> {
    let context = Context::new(stage, depths, grid)?;
    let (mut radiance, mut truncated) = (vec![0.0; grid.len()], vec![0.0; grid.len()]);
    let mut counts = Counts::default();
    context.primary(camera.eye, camera.ray(x, y), &mut Sums { radiance: &mut radiance, truncated: &mut truncated }, &mut counts);
    Ok(SpectralPixel { radiance, truncated, total_internal_reflections: counts.total_internal_reflections })
}

/// The spectral reference frame of `stage` through `camera` at `depths` on `grid`: every
/// specular object needs its spectrum on the 1 nm grid ([`Stage::spectra`]).
pub fn spectral_reference(stage: &Stage, camera: &Camera, depths: Depths, grid: &WavelengthGrid) -> Result<SpectralFrame, SpectralError> {
    let context = Context::new(stage, depths, grid)?;
    let rows: Vec<(TracedFrame, Counts)> = (0..camera.height)
        .into_par_iter()
        .map(|y| {
            let mut counts = Counts::default();
            let (mut radiance, mut seen) = (Vec::with_capacity(camera.width as usize), Vec::with_capacity(camera.width as usize));
            let (mut spectrum, mut truncated) = (vec![0.0; grid.len()], vec![0.0; grid.len()]);
            for x in 0..camera.width {
                let mut sums = Sums { radiance: &mut spectrum, truncated: &mut truncated };
                match context.primary(camera.eye, camera.ray(x, y), &mut sums, &mut counts) {
                    None => {
                        radiance.push([0.0; 3]);
                        seen.push(None);
                    }
                    Some(object) => {
                        radiance.push(grid.colour(&spectrum));
                        seen.push(context.optics[object].is_some().then_some(object));
                    }
                }
            }
            (TracedFrame { width: camera.width, height: 1, radiance, seen, rays: counts.rays }, counts)
        })
        .collect();
    let (rows, counts): (Vec<TracedFrame>, Vec<Counts>) = rows.into_iter().unzip();
    let wavelength_rays = counts.iter().map(|c| c.wavelength_rays).sum();
    let total_internal_reflections = counts.iter().map(|c| c.total_internal_reflections).sum();
    Ok(SpectralFrame { frame: TracedFrame::stack(camera.width, rows), wavelength_rays, total_internal_reflections })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Scene, SceneMaterial};
    use crate::trace::{reference, stage_from_table};
    use nklut_optics::fresnel::exact;
    use std::path::Path;

    /// A material whose index on the 1 nm grid is `index(λ)`, with its three channels at
    /// 685/535/475 nm.
    fn spectral_material(page: &str, kind: Kind, index: impl Fn(f64) -> Index) -> SceneMaterial {
        let spectrum: Vec<Index> = (0..SPECTRAL_SAMPLES).map(|i| index(spectral_wavelength_nm(i))).collect();
        SceneMaterial::new(page, [685.0, 535.0, 475.0].map(&index), kind).with_spectrum(spectrum)
    }

    fn staged(text: &str, table: &[SceneMaterial]) -> (Scene, Stage) {
        let scene = Scene::parse(text, Path::new("t.yaml")).unwrap();
        let stage = stage_from_table(&scene, table).unwrap();
        (scene, stage)
    }

    #[test]
    fn the_grid_bins_the_colors_sum_and_refuses_counts_outside_it() {
        let full = WavelengthGrid::new(WavelengthGrid::full_count()).unwrap();
        assert_eq!((full.len(), full.nm[0], full.nm[420]), (421, 360.0, 780.0));
        assert_eq!(full.weights, spectral_weights().rgb[..421].to_vec());
        for count in [1, 7, 48, 200] {
            let grid = WavelengthGrid::new(count).unwrap();
            let white = grid.colour(&vec![1.0; count]);
            assert!(white.iter().all(|v| (v - 1.0).abs() < 1e-13), "{count}: {white:?}");
        }
        // Three bins of 421: 0..140 (centre 69.5), 140..280 (209.5), 280..421 (350).
        assert_eq!(WavelengthGrid::new(3).unwrap().centres, vec![69.5, 209.5, 350.0]);
        let line = [Index::new(1.0, 0.5), Index::new(2.0, 0.0)];
        assert_eq!(WavelengthGrid::index_at(&line, 0.25), Index::new(1.25, 0.375));
        assert_eq!(WavelengthGrid::index_at(&line, 1.0), line[1]);
        assert_eq!(WavelengthGrid::new(0), Err(SpectralError::WavelengthCount { count: 0, max: 421 }));
        assert!(WavelengthGrid::new(422).is_err());
    }

    #[test]
    fn a_flat_spectrum_gives_the_three_channel_reference_at_every_depth() {
        // Flat glass (k = 0: a dielectric's α depends on λ even for a flat k) and a flat
        // conductor in a coloured checker room under grey light: every wavelength takes the
        // one geometry of the three channels with the same F, and the surround's spectra
        // round-trip their RGB, so the frames agree to rounding.
        let table = vec![
            spectral_material("t/glass/flat", Kind::Dielectric, |_| Index::new(1.5, 0.0)),
            spectral_material("t/metals/flat", Kind::Conductor, |_| Index::new(0.4, 2.8)),
        ];
        let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0.3], distance: 2.2, fov_y_degrees: 50}\neffects: {reflection: {max_depth: 4}, refraction: {max_depth: 4}}\nlight: {direction: [-0.3, -1, -0.5], colour: [0.7, 0.7, 0.7], ambient: [0.3, 0.3, 0.3]}\nobjects:\n  - {mesh: sphere, scale: 0.45, position: [-0.5, 0, 0], material: t/glass/flat, method: exact}\n  - {mesh: cube, scale: 0.45, position: [0.5, 0, 0], material: t/metals/flat, method: exact}\n  - {mesh: room, scale: 3, diffuse: [0.85, 0.85, 0.8], pattern: {kind: checker, size: 0.5, albedo: [0.15, 0.2, 0.45]}}\n";
        let (scene, stage) = staged(text, &table);
        let camera = Camera::new(&scene.camera, 0, 16, 12);
        let grid = WavelengthGrid::new(23).unwrap();
        for depth in 1..=4 {
            let depths = Depths { reflection: depth, refraction: depth };
            let three = reference(&stage, &camera, depths);
            let spectral = spectral_reference(&stage, &camera, depths, &grid).unwrap();
            assert_eq!(spectral.frame.seen, three.seen);
            let worst = three
                .radiance
                .iter()
                .zip(&spectral.frame.radiance)
                .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs() / a[c].abs().max(1e-3)))
                .fold(0.0f64, f64::max);
            assert!(worst < 1e-12, "depth {depth}: {worst:e}");
            assert!(spectral.wavelength_rays >= spectral.frame.rays);
        }
    }

    #[test]
    fn an_absorbing_slab_attenuates_each_wavelength_as_beer_lambert_says() {
        // Face on through a cube of glass (n = 1.5, k = 2·10⁻⁵ at every λ; the scene unit a
        // centimetre), refraction only: Σ_λ w(λ)(1 − F0)² e^(−4πk d/λ)·0.8 on the 1 nm grid.
        let k = 2e-5;
        let table = vec![spectral_material("t/glass/tinted", Kind::Dielectric, |_| Index::new(1.5, k))];
        let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0], distance: 2.0, fov_y_degrees: 30}\neffects: {refraction: {max_depth: 2}, metres_per_unit: 0.01}\nlight: {colour: [0, 0, 0], ambient: [1, 1, 1]}\nobjects:\n  - {mesh: cube, scale: 0.5, material: t/glass/tinted, method: exact}\n  - {mesh: room, scale: 3, diffuse: [0.8, 0.8, 0.8]}\n";
        let (scene, stage) = staged(text, &table);
        let camera = Camera::new(&scene.camera, 0, 9, 9);
        let grid = WavelengthGrid::new(WavelengthGrid::full_count()).unwrap();
        let frame = spectral_reference(&stage, &camera, Depths { reflection: 0, refraction: 2 }, &grid).unwrap();
        let z: Vec<f64> = stage.meshes[0].positions.iter().map(|p| f64::from(p[2])).collect();
        let d = z.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - z.iter().cloned().fold(f64::INFINITY, f64::min);
        let f0 = exact(1.5, k, 1.0);
        let transmitted: Vec<f64> = grid
            .nm
            .iter()
            .map(|nm| (1.0 - f0) * (1.0 - f0) * (-4.0 * std::f64::consts::PI * k / (nm * 1e-9) * 0.01 * d).exp() * 0.8)
            .collect();
        let expected = grid.colour(&transmitted);
        let pixel = frame.frame.radiance[40];
        eprintln!("slab of k = 2e-5, d = {d:.5} cm: {pixel:?}, expected {expected:?}");
        assert!((0..3).all(|c| (pixel[c] / expected[c] - 1.0).abs() < 1e-9), "{pixel:?} vs {expected:?}");
        // Blue is attenuated more than red (α ∝ 1/λ): the glass looks warm.
        assert!(pixel[0] > pixel[2]);
    }

    /// Cauchy's n(λ) = A + B/λ² (λ in nm), k = 0.
    fn cauchy(a: f64, b: f64) -> impl Fn(f64) -> Index {
        move |nm| Index::new(a + b / (nm * nm), 0.0)
    }

    #[test]
    fn lossless_dispersive_spheres_in_a_white_furnace_lose_only_the_truncated_share() {
        // Per wavelength the three-channel argument holds: on a perfect sphere every inner
        // hit is at that wavelength's refraction angle, where its F is its outside F at θᵢ,
        // so depths 8/8 return 1 − (1 − F)F⁷ per wavelength; the pixel is its weighted sum.
        // Cauchy fits of water, BK7 and diamond (A, B in nm²).
        let materials = [("water", 1.3199, 6878.0), ("bk7", 1.5046, 4200.0), ("diamond", 2.3818, 12070.0)];
        for (name, a, b) in materials {
            let page = format!("t/glass/{name}");
            let table = vec![spectral_material(&page, Kind::Dielectric, cauchy(a, b))];
            let text = format!("measurements: [image_error]\ncamera: {{axis: [0, 1, 0], distance: 1.2, fov_y_degrees: 52}}\neffects: {{reflection: {{max_depth: 8}}, refraction: {{max_depth: 8}}}}\nlight: {{colour: [0, 0, 0], ambient: [1, 1, 1]}}\nobjects:\n  - {{mesh: sphere, scale: 0.5, material: {page}, method: exact}}\n  - {{mesh: room, scale: 3, diffuse: [1, 1, 1]}}\n");
            let (scene, stage) = staged(&text, &table);
            let camera = Camera::new(&scene.camera, 0, 24, 24);
            let grid = WavelengthGrid::new(12).unwrap();
            let frame = spectral_reference(&stage, &camera, Depths { reflection: 8, refraction: 8 }, &grid).unwrap();
            let (mut rendered, mut analytic, mut pixels) = ([0.0; 3], [0.0; 3], 0);
            for y in 0..24 {
                for x in 0..24 {
                    let i = (y * 24 + x) as usize;
                    let value = frame.frame.radiance[i];
                    // Every wavelength returns at most 1; a channel can exceed 1 (the red
                    // weight is negative over 462–552 nm), the luminance (ȳ ≥ 0) cannot.
                    let to_xyz = &spectral_weights().rgb_to_xyz;
                    let luminance = (0..3).map(|c| to_xyz[1][c] * value[c]).sum::<f64>();
                    assert!(luminance <= 1.0 + 1e-12, "{name} ({x}, {y}): {value:?}");
                    if frame.frame.seen[i] != Some(0) {
                        continue;
                    }
                    let d = camera.ray(x, y);
                    let along = -camera.eye.dot(d);
                    let miss2 = camera.eye.length_squared() - along * along;
                    if miss2 >= 0.25 {
                        continue;
                    }
                    let cos = (1.0 - miss2 / 0.25).sqrt();
                    let kept: Vec<f64> = grid
                        .nm
                        .iter()
                        .map(|&nm| {
                            let f = exact(cauchy(a, b)(nm).n, 0.0, cos);
                            1.0 - (1.0 - f) * f.powi(7)
                        })
                        .collect();
                    let expected = grid.colour(&kept);
                    pixels += 1;
                    for c in 0..3 {
                        rendered[c] += value[c];
                        analytic[c] += expected[c];
                    }
                }
            }
            let rendered = rendered.map(|v| v / pixels as f64);
            let analytic = analytic.map(|v| v / pixels as f64);
            eprintln!(
                "white furnace, {name}: rendered {rendered:?}, perfect sphere {analytic:?}, {} TIR",
                frame.total_internal_reflections
            );
            // Measured ≤ 1.1·10⁻⁵ (the 64×32 tessellation; 10⁻³ before rays through the
            // room's edges stopped escaping, geometry.rs).
            assert!((0..3).all(|c| (rendered[c] - analytic[c]).abs() < 1e-4), "{name}: {rendered:?} vs {analytic:?}");
        }
    }

    #[test]
    fn each_wavelength_leaves_a_prism_at_the_angle_snell_gives_by_hand() {
        // The camera turned 20° about y looks through the prism near minimum deviation
        // (about 49° in at the entry face, whose exit face is 60° on). Refraction only, one pixel, every 1 nm wavelength: the light lands on the room's wall
        // z = 3, whose grey albedo ramps linearly in x under ambient light 1, so the
        // radiance at λ, divided by the two transmissions (1 − F) taken by hand, says where
        // it landed, and so the angle it left at. By hand: Snell at both faces (2D, the
        // faces' lines through the mesh's own f32 corners), then the line to the wall.
        let bk7 = cauchy(1.5046, 4200.0);
        let table = vec![spectral_material("t/glass/bk7", Kind::Dielectric, &bk7)];
        let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0], distance: 2.0, degrees_per_frame: 20}\neffects: {refraction: {max_depth: 2}}\nlight: {colour: [0, 0, 0], ambient: [1, 1, 1]}\nobjects:\n  - {mesh: prism, material: t/glass/bk7, method: exact}\n  - {mesh: room, scale: 3, diffuse: [0.2, 0.2, 0.2], pattern: {kind: gradient, axis: [0.3333333333333333, 0, 0], albedo: [0.8, 0.8, 0.8]}}\n";
        let (scene, stage) = staged(text, &table);
        let camera = Camera::new(&scene.camera, 1, 1, 1);
        let (eye, ray) = (camera.eye, camera.ray(0, 0));
        assert!(eye.y.abs() < 1e-15 && ray.y.abs() < 1e-15);
        let grid = WavelengthGrid::new(WavelengthGrid::full_count()).unwrap();
        let pixel = spectral_pixel(&stage, &camera, (0, 0), Depths { reflection: 0, refraction: 2 }, &grid).unwrap();
        let spectrum = pixel.radiance;
        assert_eq!(pixel.total_internal_reflections, 0);
        // The section's corners as placed (x, z): at 0°, 120°, 240°.
        let corner = |degrees: f64| {
            let p = stage.meshes[0]
                .positions
                .iter()
                .find(|p| p[1] > 0.0 && (f64::from(p[2]).atan2(f64::from(p[0])).to_degrees().rem_euclid(360.0) - degrees).abs() < 1e-3)
                .unwrap();
            glam::DVec2::new(f64::from(p[0]), f64::from(p[2]))
        };
        let (a0, a120, a240) = (corner(0.0), corner(120.0), corner(240.0));
        let outward = |p: glam::DVec2, q: glam::DVec2| {
            let n = glam::DVec2::new(q.y - p.y, p.x - q.x).normalize();
            if n.dot((p + q) * 0.5) > 0.0 {
                n
            } else {
                -n
            }
        };
        let snell = |d: glam::DVec2, facing: glam::DVec2, eta: f64| {
            let cos_i = -d.dot(facing);
            let cos_t2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
            (cos_t2 >= 0.0).then(|| (d * eta + facing * (eta * cos_i - cos_t2.sqrt())).normalize())
        };
        let meet = |p: glam::DVec2, d: glam::DVec2, a: glam::DVec2, n: glam::DVec2| p + d * ((a - p).dot(n) / d.dot(n));
        // The faces' normals as the mesh states them (f32, normalised in f64 as the tracer
        // interpolates them): the plane through the f32 corners differs by ~10⁻⁷ rad.
        let stated = |plane: glam::DVec2| {
            let n = stage.meshes[0]
                .normals
                .iter()
                .map(|n| DVec3::new(f64::from(n[0]), f64::from(n[1]), f64::from(n[2])))
                .find(|n| n.y == 0.0 && glam::DVec2::new(n.x, n.z).dot(plane) > 0.999)
                .unwrap()
                .normalize();
            glam::DVec2::new(n.x, n.z)
        };
        let (n_in, n_out) = (stated(outward(a240, a0)), stated(outward(a0, a120)));
        let d0 = glam::DVec2::new(ray.x, ray.z);
        let incidence = (-d0.dot(n_in)).acos().to_degrees();
        assert!((45.0..55.0).contains(&incidence), "{incidence}° at the entry face");
        let entry = meet(glam::DVec2::new(eye.x, eye.z), d0, a0, outward(a240, a0));
        // The wall as placed (the room's f32 corners: 3 to f32 rounding).
        let wall = stage.meshes[1].positions.iter().map(|p| f64::from(p[2])).fold(f64::NEG_INFINITY, f64::max);
        assert!((wall - 3.0).abs() < 1e-6);
        let mut worst: f64 = 0.0;
        for (lane, &nm) in grid.nm.iter().enumerate() {
            let n = bk7(nm).n;
            let inside = snell(d0, n_in, 1.0 / n).unwrap();
            let exit_point = meet(entry, inside, a0, outward(a0, a120));
            let out = snell(inside, -n_out, n).expect("BK7 leaves near minimum deviation");
            let (f_in, f_out) = (exact(n, 0.0, -d0.dot(n_in)), exact(n, 0.0, out.dot(n_out)));
            // The landing point on z = 3 by hand, and the one the radiance says.
            let by_hand = meet(exit_point, out, glam::DVec2::new(0.0, wall), glam::DVec2::new(0.0, 1.0));
            let albedo = spectrum[lane] / ((1.0 - f_in) * (1.0 - f_out));
            let x = ((albedo - 0.2) / 0.6 * 2.0 - 1.0) * 3.0;
            let angle_by_hand = (by_hand.x - exit_point.x).atan2(by_hand.y - exit_point.y);
            let angle_rendered = (x - exit_point.x).atan2(by_hand.y - exit_point.y);
            worst = worst.max((angle_rendered - angle_by_hand).abs());
        }
        // Dispersion: blue leaves at a larger deviation than red.
        let deviation = |nm: f64| {
            let n = bk7(nm).n;
            let inside = snell(d0, n_in, 1.0 / n).unwrap();
            snell(inside, -n_out, n).unwrap().x
        };
        eprintln!(
            "prism: largest |exit angle − Snell by hand| over 421 wavelengths {worst:.2e} rad; exit x-direction 400 nm {:.6}, 700 nm {:.6}",
            deviation(400.0),
            deviation(700.0)
        );
        // Measured 6.7·10⁻¹⁶ rad (f64 rounding through three intersections and two
        // refractions); asked: 10⁻⁹.
        assert!(worst < 1e-12, "{worst:e}");
        assert!(deviation(400.0) != deviation(700.0));
    }

    #[test]
    fn total_internal_reflection_happens_per_wavelength_in_a_diamond_prism() {
        // Diamond (n ≈ 2.42) refracts the ray entering at 30° to ≈ 12°, so it meets the exit
        // face at ≈ 48°, past the critical angle asin(1/n) ≈ 24.4°: every wavelength is
        // totally reflected there (and counted), none reaches the wall through that face.
        let diamond = cauchy(2.3818, 12070.0);
        let table = vec![spectral_material("t/crystals/diamond", Kind::Dielectric, diamond)];
        let text = "measurements: [image_error]\ncamera: {axis: [0, 1, 0], distance: 2.0}\neffects: {refraction: {max_depth: 2}}\nlight: {colour: [0, 0, 0], ambient: [1, 1, 1]}\nobjects:\n  - {mesh: prism, material: t/crystals/diamond, method: exact}\n  - {mesh: room, scale: 3, diffuse: [0.5, 0.5, 0.5]}\n";
        let (scene, stage) = staged(text, &table);
        let camera = Camera::new(&scene.camera, 0, 1, 1);
        let grid = WavelengthGrid::new(40).unwrap();
        let pixel = spectral_pixel(&stage, &camera, (0, 0), Depths { reflection: 0, refraction: 2 }, &grid).unwrap();
        let (spectrum, tir) = (pixel.radiance, pixel.total_internal_reflections);
        // Refraction depth 2: in, then total internal reflection (the second bounce), then no
        // bounce left: black at every wavelength, 40 reflections counted.
        assert_eq!(tir, 40);
        assert!(spectrum.iter().all(|&l| l == 0.0), "{spectrum:?}");
        // With more depth the reflected light leaves through the third face.
        let pixel = spectral_pixel(&stage, &camera, (0, 0), Depths { reflection: 0, refraction: 4 }, &grid).unwrap();
        let (deeper, tir) = (pixel.radiance, pixel.total_internal_reflections);
        assert!(tir >= 40 && deeper.iter().all(|&l| l > 0.0), "{tir} {deeper:?}");
    }
}
