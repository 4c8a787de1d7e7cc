//! Accessibility — the unoccluded fraction of a surfel's cosine-weighted hemisphere — in
//! passes, and bent normals (Bunnell, GPU Gems 2 ch. 14):
//!
//! ```text
//! pass 1:  a₁(i) = clamp(1 − Σⱼ S(j → i), 0, 1)
//! pass k:  a_k(i) = clamp(1 − Σⱼ S(j → i) · a_{k−1}(j), 0, 1)
//! bent normal:  b(i) = normalise(n_i − Σⱼ S(j → i) · w(j) · v_ij)
//! ```
//!
//! S from [`super::shadow`], v_ij the unit direction from receiver i to emitter j and w(j)
//! the weight of emitter j in the last pass (1 in pass 1, a_{k−1}(j) after). One pass
//! over-darkens (an emitter that is itself in shadow still casts its whole shadow); pass k
//! lets shadowed emitters cast less, and the passes alternate about the converged value.
//! The bent normal is the normal turned away from what hides the hemisphere, the mean
//! unoccluded direction to first order.
//!
//! Who the emitters of a receiver are is an [`Emitters`]: every other surfel
//! ([`BruteForce`], O(n²)) or a tree's cut (`super::hierarchy`, toward O(n log n)).

use glam::DVec3;
use rayon::prelude::*;

use super::shadow::{transfer, ShadowForm};
use super::surfel::Surfel;

/// What the emitters of one receiver hide: Σ w·S, Σ w·S·v, and how many emitters were
/// evaluated (the cost).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Occlusion {
    pub shadow: f64,
    pub direction: DVec3,
    pub interactions: u64,
}

impl Occlusion {
    /// Add the shadow of `emitter` weighted by `weight`.
    #[inline]
    pub fn add(&mut self, form: ShadowForm, emitter: &Surfel, weight: f64, receiver: &Surfel) {
        let (s, v) = transfer(form, emitter, receiver.centre, receiver.normal);
        self.shadow += weight * s;
        self.direction += (weight * s) * v;
        self.interactions += 1;
    }
}

/// The emitters a receiver gathers shadow from.
pub trait Emitters: Sync {
    /// The surfels (receivers), in vertex order.
    fn surfels(&self) -> &[Surfel];
    /// Per-emitter weights for a pass from the receivers' accessibility of the last pass.
    fn weights(&self, accessibility: &[f64]) -> Vec<f64>;
    /// The occlusion of `receiver` with those weights.
    fn gather(&self, receiver: usize, weights: &[f64]) -> Occlusion;
}

/// Every other surfel is an emitter of every receiver.
pub struct BruteForce<'a> {
    pub surfels: &'a [Surfel],
    pub form: ShadowForm,
}

impl Emitters for BruteForce<'_> {
    fn surfels(&self) -> &[Surfel] {
        self.surfels
    }

    fn weights(&self, accessibility: &[f64]) -> Vec<f64> {
        accessibility.to_vec()
    }

    fn gather(&self, receiver: usize, weights: &[f64]) -> Occlusion {
        let me = &self.surfels[receiver];
        let mut occlusion = Occlusion::default();
        for (j, (emitter, &w)) in self.surfels.iter().zip(weights).enumerate() {
            if j != receiver {
                occlusion.add(self.form, emitter, w, me);
            }
        }
        occlusion
    }
}

/// Per-surfel accessibility after the last pass, bent normals and the cost.
#[derive(Clone, Debug)]
pub struct Accessibility {
    /// a(i) in [0, 1], one per surfel.
    pub values: Vec<f64>,
    /// Unit bent normals (the normal itself where nothing hides the hemisphere).
    pub bent_normals: Vec<DVec3>,
    /// Passes run.
    pub passes: u32,
    /// Emitter evaluations over all passes so far.
    pub interactions: u64,
    /// Wall time of all passes so far, in ms (a measurement, not a result: two runs differ).
    pub elapsed_ms: f64,
}

/// Accessibility after `passes` passes (0 passes: everything fully accessible).
pub fn accessibility(emitters: &dyn Emitters, passes: u32) -> Accessibility {
    accessibility_by_pass(emitters, passes).pop().expect("pass 0 is always there")
}

/// The accessibility after each of 0, 1, …, `passes` passes (each pass's cost counted
/// alone), computed in one sweep.
pub fn accessibility_by_pass(emitters: &dyn Emitters, passes: u32) -> Vec<Accessibility> {
    let surfels = emitters.surfels();
    let unoccluded = Accessibility {
        values: vec![1.0; surfels.len()],
        bent_normals: surfels.iter().map(|s| s.normal).collect(),
        passes: 0,
        interactions: 0,
        elapsed_ms: 0.0,
    };
    let start = std::time::Instant::now();
    let mut history = vec![unoccluded];
    for pass in 1..=passes {
        let previous = history.last().expect("pass 0 is always there");
        let weights = emitters.weights(&previous.values);
        let gathered: Vec<Occlusion> = (0..surfels.len()).into_par_iter().map(|i| emitters.gather(i, &weights)).collect();
        let interactions = previous.interactions + gathered.iter().map(|o| o.interactions).sum::<u64>();
        let values = gathered.iter().map(|o| (1.0 - o.shadow).clamp(0.0, 1.0)).collect();
        let bent_normals =
            surfels.iter().zip(&gathered).map(|(s, o)| (s.normal - o.direction).try_normalize().unwrap_or(s.normal)).collect();
        history.push(Accessibility { values, bent_normals, passes: pass, interactions, elapsed_ms: start.elapsed().as_secs_f64() * 1e3 });
    }
    history
}
