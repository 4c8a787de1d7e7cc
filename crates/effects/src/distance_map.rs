//! Layered distance maps on the CPU: the GPU algorithm of Umenhoffer, Patow and
//! Szirmay-Kalos (GPU Gems 3 ch. 17, "Robust Multiple Specular Reflections and
//! Refractions") in f64, so its geometric error can be measured against the exact tracer
//! and the shaders tested against it.
//!
//! **Maps.** Each specular object gets a cube map around a reference point (the centre of
//! its bounding box): per texel, what a ray from that point through the texel's centre
//! direction sees — distance, unit normal and surface (a specular object, or a diffuse
//! surface's lit colour, which is the same from every viewpoint). Layers keep what one map
//! would hide: the first `layers − 1` layers hold the 1st, 2nd, … specular surfaces along
//! the texel's ray (depth peeling: an object's front and back faces land in their own
//! layers), the last layer the first diffuse surface, specular objects ignored. Faces and
//! texel directions follow the cube-map convention of Vulkan and WebGPU (faces +x, −x, +y,
//! −y, +z, −z; [`face_coordinates`]); lookups take the nearest texel.
//!
//! **Search.** A ray x + R·d (x relative to the reference point) is parametrised so that
//! equal steps sweep equal chords of direction from x̂ to R̂: d(t) = |x|·t/(1 − t), t ∈ [0,
//! 1], t = 1 being the ray's point at infinity. Against one layer, g(t) = 1 − D(p̂)/|p| with
//! p = x + R·d(t) and D the stored distance is negative in front of the stored surface and
//! non-negative behind it (g(1) = 1). `linear` equal steps in t find the first step from
//! front to behind; `secant` steps refine it between the last front and first behind
//! points, the last estimate being the hit. Each layer is searched; the hit nearest along
//! the ray wins. A texel with no surface is neither in front nor behind, so a ray passing
//! from an empty region behind a surface finds nothing there. A ray starting on a surface
//! that a layer holds (|g(0)| within [`start_tolerance`]) is neither in front of it nor
//! behind it until it leaves that band, so it cannot hit the surface it leaves — nor, at a
//! grazing angle, the nearest-texel steps of that surface beside its start.

use glam::DVec3;
use rayon::prelude::*;

use super::trace::{Stage, Surface, SurfaceHit, Tracer};
use crate::scene::{Depths, SearchSteps};

/// One texel of one layer: the distance from the reference point to the surface seen
/// through the texel's centre, its unit normal and what it is; `None` where nothing is seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    pub distance: f64,
    pub normal: DVec3,
    pub surface: Surface,
}

/// The layered distance map of one specular object.
#[derive(Clone, Debug)]
pub struct DistanceMap {
    pub centre: DVec3,
    /// Texels per face edge.
    pub size: u32,
    /// `layers[l][face·size² + row·size + column]`.
    pub layers: Vec<Vec<Option<Texel>>>,
}

/// Cube face and texel coordinates (s, t) ∈ [0, 1]² of a direction: the major axis picks
/// the face, then s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2 with (sc, tc) per face as in
/// the Vulkan specification's cube-map face selection table (t grows downwards).
pub fn face_coordinates(d: DVec3) -> (usize, f64, f64) {
    let a = d.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 {
            (0, -d.z, -d.y, a.x)
        } else {
            (1, d.z, -d.y, a.x)
        }
    } else if a.y >= a.z {
        if d.y > 0.0 {
            (2, d.x, d.z, a.y)
        } else {
            (3, d.x, -d.z, a.y)
        }
    } else if d.z > 0.0 {
        (4, d.x, -d.y, a.z)
    } else {
        (5, -d.x, -d.y, a.z)
    };
    (face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
}

/// The unit direction through face coordinates (s, t): the inverse of [`face_coordinates`].
pub fn face_direction(face: usize, s: f64, t: f64) -> DVec3 {
    let (sc, tc) = (2.0 * s - 1.0, 2.0 * t - 1.0);
    let d = match face {
        0 => DVec3::new(1.0, -tc, -sc),
        1 => DVec3::new(-1.0, -tc, sc),
        2 => DVec3::new(sc, 1.0, tc),
        3 => DVec3::new(sc, -1.0, -tc),
        4 => DVec3::new(sc, -tc, 1.0),
        _ => DVec3::new(-sc, -tc, -1.0),
    };
    d.normalize()
}

/// How close to a stored surface, in g = 1 − D/|p|, a ray's start counts as on it: four
/// texel widths (2/size each) of angle, which covers the distance a nearest-texel lookup
/// can be off for surfaces up to ~60° from facing the reference point.
pub fn start_tolerance(size: u32) -> f64 {
    8.0 / size as f64
}

impl DistanceMap {
    /// Render the map of `object` by ray casting from its bounding-box centre.
    pub fn render(stage: &Stage, object: usize, size: u32, layers: u32) -> DistanceMap {
        let centre = stage.geometry.object_centre(object);
        let specular_layers = layers as usize - 1;
        let texels_per_face = (size * size) as usize;
        let texels: Vec<Vec<Option<Texel>>> = (0..6 * texels_per_face)
            .into_par_iter()
            .map(|index| {
                let face = index / texels_per_face;
                let (row, column) = ((index % texels_per_face) / size as usize, index % size as usize);
                let direction = face_direction(face, (column as f64 + 0.5) / size as f64, (row as f64 + 0.5) / size as f64);
                let is_specular = |o: usize| stage.is_specular(o);
                let texel = |hit: &super::geometry::Hit| Texel {
                    distance: hit.t,
                    normal: hit.normal,
                    surface: stage.surface(hit.object, hit.point, hit.normal),
                };
                let peeled = stage.geometry.all_hits(centre, direction, is_specular);
                let mut column_of_layers: Vec<Option<Texel>> = (0..specular_layers).map(|l| peeled.get(l).map(texel)).collect();
                column_of_layers.push(stage.geometry.nearest(centre, direction, None, |o| !is_specular(o)).as_ref().map(texel));
                column_of_layers
            })
            .collect();
        let mut layers_out = vec![Vec::with_capacity(6 * texels_per_face); layers as usize];
        for column in texels {
            for (layer, texel) in column.into_iter().enumerate() {
                layers_out[layer].push(texel);
            }
        }
        DistanceMap { centre, size, layers: layers_out }
    }

    /// Index within a layer of the texel whose solid angle holds `direction` (nearest
    /// texel): face·size² + row·size + column.
    pub fn texel_index(&self, direction: DVec3) -> usize {
        let (face, s, t) = face_coordinates(direction);
        let n = self.size as f64;
        let column = ((s * n) as usize).min(self.size as usize - 1);
        let row = ((t * n) as usize).min(self.size as usize - 1);
        face * (self.size * self.size) as usize + row * self.size as usize + column
    }

    /// The texel of `layer` whose solid angle holds `direction` (nearest texel).
    pub fn lookup(&self, layer: usize, direction: DVec3) -> Option<Texel> {
        self.layers[layer][self.texel_index(direction)]
    }

    /// The hit of ray x + R·d (x relative to the centre) in one layer.
    fn search_layer(&self, layer: usize, x: DVec3, r: DVec3, steps: SearchSteps) -> Option<MapHit> {
        let scale = x.length().max(1e-9);
        let point = |t: f64| if t < 1.0 { Some(x + r * (scale * t / (1.0 - t))) } else { None };
        // g(t) and the texel it read; `None` where the layer is empty.
        let probe = |t: f64| -> Option<(f64, usize)> {
            match point(t) {
                Some(p) => {
                    let index = self.texel_index(p);
                    let texel = self.layers[layer][index]?;
                    Some((1.0 - texel.distance / p.length(), index))
                }
                None => {
                    let index = self.texel_index(r);
                    self.layers[layer][index].map(|_| (1.0, index))
                }
            }
        };
        // A ray starting on this layer's surface stays "on" it, neither in front nor behind,
        // until it leaves the band |g| ≤ tolerance.
        let tolerance = start_tolerance(self.size);
        let mut on_surface = probe(0.0).is_some_and(|(g, _)| g.abs() <= tolerance);
        let mut front = probe(0.0).filter(|(g, _)| *g < -tolerance).map(|(g, _)| (0.0, g));
        let mut bracket = None;
        for k in 1..=steps.linear {
            let t = k as f64 / steps.linear as f64;
            let sample = probe(t);
            on_surface &= sample.is_some_and(|(g, _)| g.abs() <= tolerance);
            match sample {
                _ if on_surface => {}
                None => front = None,
                Some((g, _)) if g < 0.0 => front = Some((t, g)),
                Some((g, texel)) => {
                    if let Some(last_front) = front {
                        bracket = Some((last_front, (t, g, texel)));
                        break;
                    }
                }
            }
        }
        let ((mut ta, mut ga), (mut tb, mut gb, texel_b)) = bracket?;
        let (mut hit_t, mut hit_texel) = (tb, texel_b);
        for i in 0..steps.secant {
            let tm = ta + (tb - ta) * ga / (ga - gb);
            let Some((gm, texel)) = probe(tm) else { break };
            (hit_t, hit_texel) = (tm, texel);
            if i + 1 == steps.secant {
                break;
            }
            if gm < 0.0 {
                (ta, ga) = (tm, gm);
            } else {
                (tb, gb) = (tm, gm);
            }
        }
        let texel = self.layers[layer][hit_texel].expect("probes return only texels with a surface");
        let point = point(hit_t).unwrap_or_else(|| r * texel.distance);
        Some(MapHit { t: hit_t, point, layer, index: hit_texel, texel })
    }

    /// The nearest hit over all layers of ray x + R·d (x relative to the centre).
    pub fn search(&self, x: DVec3, r: DVec3, steps: SearchSteps) -> Option<MapHit> {
        (0..self.layers.len()).filter_map(|layer| self.search_layer(layer, x, r, steps)).min_by(|a, b| a.t.total_cmp(&b.t))
    }
}

/// Where a search ended: the ray parameter t, the point (relative to the map's centre),
/// the layer and texel index read there, and that texel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapHit {
    pub t: f64,
    pub point: DVec3,
    pub layer: usize,
    pub index: usize,
    pub texel: Texel,
}

/// Tracing through one object's distance map with a search configuration.
pub struct DistanceMapTracer<'a> {
    pub map: &'a DistanceMap,
    pub steps: SearchSteps,
}

impl Tracer for DistanceMapTracer<'_> {
    fn trace(&self, origin: DVec3, direction: DVec3, _from: &SurfaceHit) -> Option<SurfaceHit> {
        let hit = self.map.search(origin - self.map.centre, direction, self.steps)?;
        Some(SurfaceHit {
            point: hit.point + self.map.centre,
            normal: hit.texel.normal,
            geometric: hit.texel.normal,
            surface: hit.texel.surface,
            triangle: None,
        })
    }
}

/// What a row of the effects' tables measured: the depths and the distance maps' search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Configuration {
    pub depths: Depths,
    pub steps: SearchSteps,
    pub map_size: u32,
    pub layers: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_coordinates_invert_face_direction_on_every_face() {
        for face in 0..6 {
            for (s, t) in [(0.5, 0.5), (0.1, 0.9), (0.8, 0.3), (0.99, 0.01)] {
                let d = face_direction(face, s, t);
                let (f, s2, t2) = face_coordinates(d);
                assert_eq!(f, face);
                assert!((s - s2).abs() < 1e-12 && (t - t2).abs() < 1e-12, "face {face}: ({s}, {t}) → ({s2}, {t2})");
            }
        }
        // The centres of the faces are the axes, in the order +x, −x, +y, −y, +z, −z.
        let axes = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
        for (face, axis) in axes.into_iter().enumerate() {
            assert!((face_direction(face, 0.5, 0.5) - axis).length() < 1e-15);
        }
        // Vulkan's table: +x face, s grows towards −z and t towards −y.
        let (_, s, t) = face_coordinates(DVec3::new(1.0, -0.5, -0.5));
        assert_eq!((s, t), (0.75, 0.75));
    }
}
