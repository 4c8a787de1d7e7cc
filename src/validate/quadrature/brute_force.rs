//! The reference integration of the error figures: the θ-midpoint rule with
//! M = 10⁶ points, θ_j = (j + ½)·(π/2)/M (SPEC §6).

use std::f64::consts::FRAC_PI_2;

use rayon::prelude::*;

use super::{figures, Integral, Maximum, Sample, Sums};
use crate::fresnel::Precision;

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
/// `evaluate(θ, out)` fills one [`Sample`] per member.
pub fn brute_force(evaluate: &(impl Fn(f64, &mut [Sample]) + Sync), members: usize, samples: usize) -> Vec<Integral> {
    const CHUNK: usize = 8192;
    let step = FRAC_PI_2 / samples as f64;
    let total = (0..samples.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut partial = Partial::empty(members);
            let mut out = vec![Sample::default(); members];
            for j in chunk * CHUNK..((chunk + 1) * CHUNK).min(samples) {
                let theta = (j as f64 + 0.5) * step;
                evaluate(theta, &mut out);
                let included = out.first().is_some_and(|s| s.exact > 0.0);
                partial.excluded += u64::from(!included);
                for (m, sample) in out.iter().enumerate() {
                    for precision in Precision::ALL {
                        let difference = sample.difference(precision);
                        partial.sums[m].squared[precision] += difference * difference;
                        if included {
                            partial.sums[m].relative[precision] += difference.abs() / sample.exact;
                        }
                    }
                    partial.maxima[m].see(theta, sample);
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
