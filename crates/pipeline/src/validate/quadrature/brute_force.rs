//! The reference integration of the error figures: the θ-midpoint rule with
//! M = 10⁶ points, θ_j = (j + ½)·(π/2)/M (SPEC §6).

use std::f64::consts::FRAC_PI_2;

use rayon::prelude::*;

use super::{figures, Integral, Integrand, Maximum, Sample, Sums};
use nklut_optics::fresnel::Precision;

/// The number of midpoints of the reference brute force.
pub const BRUTE_FORCE_SAMPLES: usize = 1_000_000;

/// Sums over a run of midpoints, per member.
struct Partial {
    sums: Vec<Sums>,
    maxima: Vec<Maximum>,
    excluded: u64,
}

impl Partial {
    fn empty(members: usize) -> Self {
        Self { sums: vec![Sums::default(); members], maxima: vec![Maximum::default(); members], excluded: 0 }
    }

    fn merge(mut self, other: Partial) -> Partial {
        for (m, (sums, maximum)) in other.sums.iter().zip(&other.maxima).enumerate() {
            self.sums[m].add(sums);
            self.maxima[m] = self.maxima[m].merge(maximum);
        }
        self.excluded += other.excluded;
        self
    }
}

/// Brute force over `samples` θ-midpoints θ_j = (j + ½)·(π/2)/M, in parallel (rayon);
/// `integrand` fills one [`Sample`] per member at each θ, [`BATCH`] midpoints at a time.
pub fn brute_force<I: Integrand + Sync + ?Sized>(integrand: &I, members: usize, samples: usize) -> Vec<Integral> {
    const CHUNK: usize = 8192;
    let step = FRAC_PI_2 / samples as f64;
    let total = (0..samples.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut partial = Partial::empty(members);
            let mut thetas = Vec::with_capacity(BATCH);
            let mut batch = vec![Sample::default(); BATCH * members];
            let (first, last) = (chunk * CHUNK, ((chunk + 1) * CHUNK).min(samples));
            for start in (first..last).step_by(BATCH) {
                thetas.clear();
                thetas.extend((start..(start + BATCH).min(last)).map(|j| (j as f64 + 0.5) * step));
                let batch = &mut batch[..thetas.len() * members];
                integrand.evaluate(&thetas, batch);
                for (j, &theta) in thetas.iter().enumerate() {
                    partial.see(theta, &batch[j * members..(j + 1) * members]);
                }
            }
            partial
        })
        .reduce(|| Partial::empty(members), Partial::merge);
    // Midpoint sums: the means need only the counts.
    let included = (samples as u64 - total.excluded) as f64;
    (0..members)
        .map(|m| Integral {
            figures: figures(&total.sums[m], included, samples as f64, &total.maxima[m]),
            excluded_samples: total.excluded,
            evaluations: samples as u64,
        })
        .collect()
}

/// Midpoints evaluated per call of the integrand.
const BATCH: usize = 64;

impl Partial {
    /// Add the family's samples at one midpoint θ.
    fn see(&mut self, theta: f64, out: &[Sample]) {
        let included = out.first().is_some_and(|s| s.exact > 0.0);
        self.excluded += u64::from(!included);
        for (m, sample) in out.iter().enumerate() {
            for precision in Precision::ALL {
                let difference = sample.difference(precision);
                self.sums[m].squared[precision] += difference * difference;
                if included {
                    self.sums[m].relative[precision] += difference.abs() / sample.exact;
                }
            }
            self.maxima[m].see(theta, sample);
        }
    }
}
