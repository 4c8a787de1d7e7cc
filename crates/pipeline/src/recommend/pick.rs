//! The pure core of `nklut recommend`: per page × device, the cheapest way to shade the page
//! whose error against its spectral reference curve stays within a bound, the runner-up,
//! and why every other way loses. Plain rows in ([`Candidate`], [`Timing`]), plain rows
//! out ([`Recommendation`]); no files, no flags.
//!
//! Rules (docs/SPEC.md, "Recommendations"):
//! - A candidate passes when its largest CIEDE2000 over θ (`de2000_max`, the quadrature
//!   nodes of the colour module) is ≤ `bound.de2000` and, when a relative bound is set,
//!   its worst channel's mean relative error over θ (`rel_error_max`) is ≤ `bound.rel`.
//! - Its cost on a device is the device's time for the candidate's shader `method` (for a
//!   LUT the time of that size and encoding where the device has one, else the device's one
//!   `lut` time); a candidate without a time on the device cannot be ranked there.
//! - Ranking among the passing candidates: lower cost; then fewer texture bytes; then lower
//!   `de2000_max`; then lower `de2000_mean`; then the earlier in the candidate list (the
//!   caller's fixed order). The first is the pick; the runner-up is the first passing
//!   candidate of another shader method.

use std::collections::BTreeMap;

/// A LUT's size and encoding: what a timing or a candidate names when it is one LUT.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LutSize {
    /// Texels per row (N).
    pub texels: usize,
    /// The texel encoding's name (`unorm8-srgb`, `f16`, …).
    pub encoding: String,
}

impl LutSize {
    pub fn new(texels: usize, encoding: impl Into<String>) -> Self {
        Self { texels, encoding: encoding.into() }
    }
}

/// One way of shading one page, with its error against the page's spectral reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub page: String,
    /// `conductor` or `dielectric`.
    pub kind: String,
    /// The shader function a device times (`exact`, `schlick`, `lut`, …).
    pub method: String,
    /// Where its parameters come from (`three-channel (n, k)`, `spectral F0`, `spectral curve`, …).
    pub parameters_from: String,
    /// The candidate's name in the tables: method, its parameters' origin, a LUT's size and encoding.
    pub name: String,
    /// A LUT's texels per row and encoding; `None` for a closed form.
    pub lut: Option<LutSize>,
    pub texture_bytes: usize,
    pub de2000_mean: f64,
    pub de2000_max: f64,
    /// Mean over the channels of the mean relative error over θ.
    pub rel_error_mean: f64,
    /// The worst channel's mean relative error over θ.
    pub rel_error_max: f64,
    /// What to put in the shader: the values, or the LUT file.
    pub parameters: String,
    /// The table the error figures are the row of.
    pub error_table: String,
}

/// One shader method's time on one device (`CPU`: ns per evaluation; a GPU: the median
/// pass time in ms over the materials it timed).
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    pub device: String,
    pub method: String,
    /// A LUT's size and encoding where the time is that LUT's alone.
    pub lut: Option<LutSize>,
    pub value: f64,
    pub unit: TimeUnit,
    /// ms per 10⁶ pixels (GPU passes of a known resolution).
    pub ms_per_mpixel: Option<f64>,
    /// The table and row the time comes from.
    pub source: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeUnit {
    NsPerEvaluation,
    MsPerPass,
}

/// The bound a pick must stay within.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Largest CIEDE2000 over θ against the spectral reference.
    pub de2000: f64,
    /// Largest worst-channel mean relative error, when set.
    pub rel: Option<f64>,
}

impl Default for Bound {
    /// ΔE2000 ≤ 1 (about the smallest difference a viewer sees side by side); no relative bound.
    fn default() -> Self {
        Self { de2000: 1.0, rel: None }
    }
}

impl Bound {
    pub fn passes(&self, c: &Candidate) -> bool {
        c.de2000_max <= self.de2000 && self.rel.is_none_or(|r| c.rel_error_max <= r)
    }

    pub fn describe(&self) -> String {
        match self.rel {
            Some(r) => format!("max ΔE2000 over θ ≤ {} and worst-channel mean relative error ≤ {}", self.de2000, r),
            None => format!("max ΔE2000 over θ ≤ {}", self.de2000),
        }
    }
}

/// The answer for one page on one device.
#[derive(Clone, Debug, PartialEq)]
pub struct Recommendation {
    pub page: String,
    pub kind: String,
    pub device: String,
    /// The pick; `None` when no candidate with a time on the device passes.
    pub pick: Option<Pick>,
    pub runner_up: Option<Pick>,
    /// Candidates that pass and have a time on this device.
    pub passing: usize,
    pub bound: Bound,
    /// Why the pick won, in words with its figures.
    pub reason: String,
    /// Per other shader method and parameter origin, why it lost (its best candidate).
    pub others: String,
}

/// A ranked candidate with its cost on the device.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    pub candidate: Candidate,
    pub timing: Timing,
    /// The cost relative to `exact` on the same device; `None` where the device has no
    /// `exact` time.
    pub x_exact: Option<f64>,
}

/// The devices of `timings`, in order of first appearance.
fn devices(timings: &[Timing]) -> Vec<&str> {
    let mut seen: Vec<&str> = Vec::new();
    for t in timings {
        if !seen.contains(&t.device.as_str()) {
            seen.push(&t.device);
        }
    }
    seen
}

/// The time of `candidate` on `device`: the exact (method, LUT) row, else the method's row without a LUT.
pub fn timing_of<'a>(timings: &'a [Timing], device: &str, candidate: &Candidate) -> Option<&'a Timing> {
    let on = |lut: Option<&LutSize>| timings.iter().find(|t| t.device == device && t.method == candidate.method && t.lut.as_ref() == lut);
    candidate.lut.as_ref().and_then(|l| on(Some(l))).or_else(|| on(None))
}

/// The figure a reader compares: ×exact where the device timed exact, else the raw value.
fn shown_cost(pick: &Pick) -> String {
    match pick.x_exact {
        Some(x) => format!("{}× exact", fmt(x)),
        None => format!("{} {}", fmt(pick.timing.value), fmt_unit(pick.timing.unit)),
    }
}

pub fn fmt_unit(u: TimeUnit) -> &'static str {
    match u {
        TimeUnit::NsPerEvaluation => "ns/eval",
        TimeUnit::MsPerPass => "ms/pass",
    }
}

pub use crate::report::findings::sig3 as fmt;

/// Ranking order of two passing picks (see the module's rules).
fn rank(a: &(usize, Pick), b: &(usize, Pick)) -> std::cmp::Ordering {
    let (ia, pa) = a;
    let (ib, pb) = b;
    pa.timing
        .value
        .total_cmp(&pb.timing.value)
        .then(pa.candidate.texture_bytes.cmp(&pb.candidate.texture_bytes))
        .then(pa.candidate.de2000_max.total_cmp(&pb.candidate.de2000_max))
        .then(pa.candidate.de2000_mean.total_cmp(&pb.candidate.de2000_mean))
        .then(ia.cmp(ib))
}

/// Every page × device answer: pages in the order of `candidates`, devices in the order of
/// `timings`.
pub fn recommend(candidates: &[Candidate], timings: &[Timing], bound: Bound) -> Vec<Recommendation> {
    let mut pages: Vec<&str> = Vec::new();
    let mut by_page: BTreeMap<&str, Vec<(usize, &Candidate)>> = BTreeMap::new();
    for (i, c) in candidates.iter().enumerate() {
        if !by_page.contains_key(c.page.as_str()) {
            pages.push(&c.page);
        }
        by_page.entry(&c.page).or_default().push((i, c));
    }
    let mut out = Vec::new();
    for page in pages {
        let own = &by_page[page];
        for device in devices(timings) {
            out.push(recommend_one(own, timings, device, bound));
        }
    }
    out
}

fn recommend_one(own: &[(usize, &Candidate)], timings: &[Timing], device: &str, bound: Bound) -> Recommendation {
    let exact = timings.iter().find(|t| t.device == device && t.method == "exact" && t.lut.is_none()).map(|t| t.value);
    let priced = |c: &Candidate| {
        timing_of(timings, device, c).map(|t| Pick {
            candidate: c.clone(),
            timing: t.clone(),
            x_exact: exact.filter(|e| *e > 0.0).map(|e| t.value / e),
        })
    };
    let mut ranked: Vec<(usize, Pick)> =
        own.iter().filter(|(_, c)| bound.passes(c)).filter_map(|(i, c)| priced(c).map(|p| (*i, p))).collect();
    ranked.sort_by(rank);
    let pick = ranked.first().map(|(_, p)| p.clone());
    let runner_up =
        pick.as_ref().and_then(|p| ranked.iter().find(|(_, r)| r.candidate.method != p.candidate.method)).map(|(_, r)| r.clone());
    let (page, kind) = (own[0].1.page.clone(), own[0].1.kind.clone());
    let reason = match &pick {
        Some(p) => {
            let mut r = format!(
                "cheapest of {} candidates within {}: {} at {} (ΔE2000 max {})",
                ranked.len(),
                bound.describe(),
                p.candidate.name,
                shown_cost(p),
                fmt(p.candidate.de2000_max)
            );
            if let Some((_, tied)) = ranked.get(1).filter(|(_, s)| s.timing.value == p.timing.value) {
                r.push_str(&format!(
                    "; tied on cost with {}, won on {}",
                    tied.candidate.name,
                    if tied.candidate.texture_bytes != p.candidate.texture_bytes {
                        "fewer texture bytes"
                    } else if tied.candidate.de2000_max != p.candidate.de2000_max {
                        "the lower ΔE2000 max"
                    } else if tied.candidate.de2000_mean != p.candidate.de2000_mean {
                        "the lower ΔE2000 mean"
                    } else {
                        "the candidate order"
                    }
                ));
            }
            r
        }
        None => {
            let best = own.iter().map(|(_, c)| c).min_by(|a, b| a.de2000_max.total_cmp(&b.de2000_max));
            format!(
                "no candidate with a time on {device} stays within {}{}",
                bound.describe(),
                best.map(|c| format!("; the smallest ΔE2000 max is {} ({})", fmt(c.de2000_max), c.name)).unwrap_or_default()
            )
        }
    };
    let others = others(own, &pick, &priced, bound, device);
    Recommendation { page, kind, device: device.to_string(), passing: ranked.len(), pick, runner_up, bound, reason, others }
}

/// One clause per other (method, parameter origin): why its best candidate lost.
fn others(
    own: &[(usize, &Candidate)],
    pick: &Option<Pick>,
    priced: &dyn Fn(&Candidate) -> Option<Pick>,
    bound: Bound,
    device: &str,
) -> String {
    let mut groups: Vec<(String, Vec<&Candidate>)> = Vec::new();
    for (_, c) in own {
        let key = format!("{} ({})", c.method, c.parameters_from);
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push(c),
            None => groups.push((key, vec![c])),
        }
    }
    let mut clauses = Vec::new();
    for (key, members) in groups {
        if let Some(p) = pick {
            if members.iter().any(|c| c.name == p.candidate.name) {
                continue;
            }
        }
        let passing: Vec<&&Candidate> = members.iter().filter(|c| bound.passes(c)).collect();
        let clause = if passing.is_empty() {
            let best = members.iter().min_by(|a, b| a.de2000_max.total_cmp(&b.de2000_max)).expect("a group has members");
            if best.de2000_max > bound.de2000 {
                format!("{key}: ΔE2000 max {} > {}", fmt(best.de2000_max), bound.de2000)
            } else {
                format!("{key}: relative error {} > {}", fmt(best.rel_error_max), bound.rel.unwrap_or(f64::INFINITY))
            }
        } else {
            let timed: Vec<Pick> = passing.iter().filter_map(|c| priced(c)).collect();
            match (timed.iter().min_by(|a, b| a.timing.value.total_cmp(&b.timing.value)), pick) {
                (None, _) => format!("{key}: no time on {device}"),
                (Some(t), Some(p)) if t.timing.value > p.timing.value => {
                    format!("{key}: slower, {} vs {}", shown_cost(t), shown_cost(p))
                }
                (Some(t), Some(_)) => format!("{key}: same cost ({}), loses the tie-break", shown_cost(t)),
                (Some(_), None) => format!("{key}: no pick"),
            }
        };
        clauses.push(clause);
    }
    clauses.join("; ")
}
