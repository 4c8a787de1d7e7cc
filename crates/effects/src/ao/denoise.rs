//! XeGTAO's edge-aware spatial denoiser (Intel 2021, `XeGTAO.hlsli`: `CalculateEdges`,
//! `PackEdges`/`UnpackEdges`, `XeGTAO_Denoise`), run over a GTAO image: a 3 × 3 weighted
//! mean per pixel whose weights fall to 0 across depth discontinuities.
//!
//! Edges. Per covered pixel and each of its four neighbours (left, right, top, bottom) the
//! neighbour's view-space depth minus the pixel's, d. Along each axis the pixel's own slope,
//! s = (d_right − d_left)/2 (resp. bottom − top), is taken out where it makes the difference
//! smaller: m = min(|d_left|, |d_left + s|), min(|d_right|, |d_right − s|), so that a plane
//! seen at a slant is not an edge. The edge weight is 1.25 − m / (0.011 · depth), clamped to
//! [0, 1] (1: same surface; 0: a jump of more than 1.25 % of the depth), stored in 2 bits:
//! ⌊2.9 w + ½⌋ / 3 ∈ {0, ⅓, ⅔, 1}. A neighbour beyond the image's edge is read clamped (the
//! pixel itself: d = 0) as the GPU's clamping sampler does; a neighbour with no surface has
//! weight 0 (XeGTAO's depth there is the far plane: a jump), and along its axis the slope is
//! not taken out.
//!
//! One pass, per covered pixel. Each of the four edge weights is multiplied by the
//! neighbour's weight back toward the pixel (the two ends agree); where their sum is under
//! 4 − 2.5 = 1.5 (three or four edges) each rises by min(1.5 − sum, 1)/1.5 × ½, clamped to
//! 1, so that a pixel in a corner still borrows a little ("leak"). A diagonal neighbour weighs
//! 0.425 × the sum of the two L-shaped paths to it (e.g. top-left: left edge × the left
//! neighbour's top edge + top edge × the top neighbour's left edge). The pixel weighs beta
//! (the last pass; beta / 5 in the passes before it). The result is the weighted mean of
//! the covered pixels among the nine, clamped to [0, 1] in the last pass.
//!
//! The edges depend on depth alone, so a pass is linear in the values: denoising every
//! accumulated frame and averaging (XeGTAO under TAA) equals denoising the average, to
//! rounding. Departures from XeGTAO: a neighbour with no surface adds nothing (XeGTAO would
//! blend in the background's value through the leak); the edges are computed in the
//! denoiser from the G-buffer, not stored by the main pass.
//!
//! One body over [`Real`]: f64 for the figures, f32 in the operation order of
//! `shaders/gtao.wgsl` (`gtao_edges`, `cs_denoise_*`), its twin.

use super::gtao::GBuffer;
use nklut_optics::fresnel::Real;

/// An edge's depth jump, relative to the pixel's depth, at which its weight is 1.25 − 1 =
/// ¼ below full (`CalculateEdges`: `centerZ * 0.011`).
pub const EDGE_DEPTH_FRACTION: f64 = 0.011;
/// The edge weight before the jump is taken off (`CalculateEdges`: 1.25).
pub const EDGE_OFFSET: f64 = 1.25;
/// An edge weight is stored as ⌊this × w + ½⌋ / 3: 2 bits (`PackEdges`: 2.9).
pub const EDGE_LEVELS: f64 = 2.9;
/// A diagonal neighbour's weight per L-shaped path (`XeGTAO_Denoise`: 0.85 × 0.5).
pub const DIAGONAL_WEIGHT: f64 = 0.425;
/// Below 4 − this sum of its four edge weights a pixel borrows from every neighbour
/// (`leak_threshold`).
pub const LEAK_THRESHOLD: f64 = 2.5;
/// How much a pixel with no edge weight at all borrows per neighbour (`leak_strength`).
pub const LEAK_STRENGTH: f64 = 0.5;
/// The centre's weight in the passes before the last is beta / this.
pub const EARLY_PASS_DIVISOR: f64 = 5.0;

/// Left, right, top, bottom: the order of a pixel's four edges and neighbours.
const LEFT: usize = 0;
const RIGHT: usize = 1;
const TOP: usize = 2;
const BOTTOM: usize = 3;
/// Each neighbour's offset, in the order of the edges.
const STEPS: [[i64; 2]; 4] = [[-1, 0], [1, 0], [0, -1], [0, 1]];

/// The pixel (`x`, `y`) clamped into the image, as an index.
fn clamped(width: u32, height: u32, x: i64, y: i64) -> usize {
    let x = x.clamp(0, width as i64 - 1) as usize;
    let y = y.clamp(0, height as i64 - 1) as usize;
    y * width as usize + x
}

fn depth<T: Real>(g: &GBuffer<T>, x: i64, y: i64) -> Option<T> {
    g.samples[clamped(g.width, g.height, x, y)].map(|s| -s.position[2])
}

/// An edge weight in [0, 1] as its 2 bits store it.
fn quantised<T: Real>(weight: T) -> T {
    (weight.clamp(T::ZERO, T::ONE) * T::of(EDGE_LEVELS) + T::of(0.5)).floor() / T::of(3.0)
}

/// Pixel (`x`, `y`)'s edge weights toward its left, right, top and bottom neighbours (all 0
/// where no surface is). The twin of `gtao_edges` in `shaders/gtao.wgsl`.
pub fn edges<T: Real>(g: &GBuffer<T>, x: u32, y: u32) -> [T; 4] {
    let (x, y) = (x as i64, y as i64);
    let Some(z) = depth(g, x, y) else { return [T::ZERO; 4] };
    let d = STEPS.map(|[dx, dy]| depth(g, x + dx, y + dy).map(|n| n - z));
    let mut jump: [Option<T>; 4] = d.map(|d| d.map(T::abs));
    for (low, high) in [(LEFT, RIGHT), (TOP, BOTTOM)] {
        if let (Some(a), Some(b)) = (d[low], d[high]) {
            let slope = (b - a) * T::of(0.5);
            jump[low] = Some(a.abs().min((a + slope).abs()));
            jump[high] = Some(b.abs().min((b - slope).abs()));
        }
    }
    let scale = z * T::of(EDGE_DEPTH_FRACTION);
    jump.map(|m| m.map_or(T::ZERO, |m| quantised(T::of(EDGE_OFFSET) - m / scale)))
}

/// Every pixel's edges (row-major).
pub fn edge_image<T: Real>(g: &GBuffer<T>) -> Vec<[T; 4]> {
    (0..g.width * g.height).map(|i| edges(g, i % g.width, i / g.width)).collect()
}

/// The centre pixel's weight in a pass: `beta` in the last, `beta` / [`EARLY_PASS_DIVISOR`]
/// before it (the GPU pass's uniform takes it from here, in f32).
pub fn centre_weight<T: Real>(beta: T, last: bool) -> T {
    if last {
        beta
    } else {
        beta / T::of(EARLY_PASS_DIVISOR)
    }
}

/// One pass at covered pixel (`x`, `y`) of `values` (row-major, `None` where no surface
/// is) with the centre weighing `beta`; `last`: clamp to [0, 1]. The twin of
/// `denoised_value` in `shaders/gtao.wgsl`.
pub fn denoised<T: Real>(g: &GBuffer<T>, edges: &[[T; 4]], values: &[Option<T>], x: u32, y: u32, beta: T, last: bool) -> Option<T> {
    let (w, h) = (g.width, g.height);
    let (x, y) = (x as i64, y as i64);
    let here = clamped(w, h, x, y);
    let centre = values[here]?;
    let around = STEPS.map(|[dx, dy]| clamped(w, h, x + dx, y + dy));
    let own = edges[here];
    let back = [RIGHT, LEFT, BOTTOM, TOP];
    let mut e: [T; 4] = std::array::from_fn(|k| own[k] * edges[around[k]][back[k]]);
    let sum = e[LEFT] + e[RIGHT] + e[TOP] + e[BOTTOM];
    let threshold = T::of(LEAK_THRESHOLD);
    let open = T::of(4.0) - threshold;
    let leak = (open - sum).clamp(T::ZERO, T::ONE) / open * T::of(LEAK_STRENGTH);
    e = e.map(|e| (e + leak).clamp(T::ZERO, T::ONE));
    let [l, r, t, b] = around.map(|i| edges[i]);
    let diagonal = T::of(DIAGONAL_WEIGHT);
    let corner = |first: usize, second: usize, first_edges: [T; 4], second_edges: [T; 4]| {
        diagonal * (e[first] * first_edges[second] + e[second] * second_edges[first])
    };
    let weighted = [
        (around[LEFT], e[LEFT]),
        (around[RIGHT], e[RIGHT]),
        (around[TOP], e[TOP]),
        (around[BOTTOM], e[BOTTOM]),
        (clamped(w, h, x - 1, y - 1), corner(LEFT, TOP, l, t)),
        (clamped(w, h, x + 1, y - 1), corner(TOP, RIGHT, t, r)),
        (clamped(w, h, x - 1, y + 1), corner(BOTTOM, LEFT, b, l)),
        (clamped(w, h, x + 1, y + 1), corner(RIGHT, BOTTOM, r, b)),
    ];
    let (mut total, mut weight) = (beta * centre, beta);
    for (index, w) in weighted {
        if let Some(v) = values[index] {
            total = total + w * v;
            weight = weight + w;
        }
    }
    let mean = total / weight;
    Some(if last { mean.clamp(T::ZERO, T::ONE) } else { mean })
}

/// `passes` passes over `values` (row-major, `None` where no surface is; 0 passes: the
/// values as they are), the last with the centre weighing `beta`, the ones before `beta`/5.
pub fn denoise<T: Real + Send + Sync>(g: &GBuffer<T>, values: &[Option<T>], passes: u32, beta: T) -> Vec<Option<T>> {
    use rayon::prelude::*;
    let mut values = values.to_vec();
    if passes == 0 {
        return values;
    }
    let edges = edge_image(g);
    for pass in 0..passes {
        let last = pass + 1 == passes;
        let centre = centre_weight(beta, last);
        values =
            (0..g.width * g.height).into_par_iter().map(|i| denoised(g, &edges, &values, i % g.width, i / g.width, centre, last)).collect();
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ao::gtao::ViewSample;

    /// A `width` × `height` G-buffer facing the eye with `depth(x, y)` per pixel (`None`: no
    /// surface), focal length 100.
    fn frame(width: u32, height: u32, depth: impl Fn(u32, u32) -> Option<f64>) -> GBuffer<f64> {
        let samples = (0..width * height)
            .map(|i| depth(i % width, i / width).map(|z| ViewSample { position: [0.0, 0.0, -z], normal: [0.0, 0.0, 1.0] }))
            .collect();
        GBuffer { width, height, focal: 100.0, samples }
    }

    #[test]
    fn edges_are_whole_on_a_plane_at_a_slant_and_zero_across_a_jump() {
        // A plane whose depth grows by 0.1 per pixel to the right: d_left = −0.1, d_right =
        // 0.1, s = 0.1, so both differences vanish once the slope is out: weight 1.25 → 1.
        let slant = frame(5, 5, |x, _| Some(3.0 + 0.1 * x as f64));
        assert_eq!(edges(&slant, 2, 2), [1.0; 4]);
        // A step of 0.1 at depth 3 between columns 2 and 3: at column 2, d_right = 0.1,
        // d_left = 0, s = 0.05, m_right = min(0.1, 0.05) = 0.05; 1.25 − 0.05/0.033 = −0.27 → 0.
        // m_left = min(0, 0.05) = 0 → 1.
        let step = frame(5, 5, |x, _| Some(if x <= 2 { 3.0 } else { 3.1 }));
        assert_eq!(edges(&step, 2, 2), [1.0, 0.0, 1.0, 1.0]);
        // A small step, 0.02 at depth 3: m = 0.01, 1.25 − 0.01/0.033 = 0.947 → ⌊2.9·0.947 + ½⌋/3
        // = ⌊3.25⌋/3 = 1; 0.04: m = 0.02, 0.644 → ⌊2.37⌋/3 = ⅔.
        let small = |jump: f64| frame(5, 5, move |x, _| Some(if x <= 2 { 3.0 } else { 3.0 + jump }));
        assert_eq!(edges(&small(0.02), 2, 2)[RIGHT], 1.0);
        assert_eq!(edges(&small(0.04), 2, 2)[RIGHT], 2.0 / 3.0);
        // A neighbour with no surface is an edge; beyond the image the pixel reads itself.
        let hole = frame(5, 5, |x, y| (x != 3 || y != 2).then_some(3.0));
        assert_eq!(edges(&hole, 2, 2), [1.0, 0.0, 1.0, 1.0]);
        assert_eq!(edges(&hole, 0, 0), [1.0; 4]);
    }

    #[test]
    fn a_pass_keeps_a_constant_and_weighs_neighbours_as_derived() {
        // A constant image on one surface stays constant (a weighted mean of equal values).
        let plane = frame(6, 4, |_, _| Some(2.0));
        let constant = vec![Some(0.6); 24];
        for passes in 1..=3 {
            for v in denoise(&plane, &constant, passes, 1.2) {
                assert!((v.unwrap() - 0.6).abs() < 1e-15);
            }
        }
        // One bright pixel (1) among zeros, all edges whole: four neighbours weigh 1 and each
        // diagonal 0.425 × 2 = 0.85, so the centre keeps 1.2 / (1.2 + 4 + 4 × 0.85) = 1.2/8.6,
        // a side neighbour 1/8.6 (the bright pixel is one of its eight, weight 1) and a
        // diagonal one 0.85/8.6.
        let mut spike = vec![Some(0.0); 25];
        spike[12] = Some(1.0);
        let plane = frame(5, 5, |_, _| Some(2.0));
        let out = denoise(&plane, &spike, 1, 1.2);
        assert!((out[12].unwrap() - 1.2 / 8.6).abs() < 1e-15);
        assert!((out[11].unwrap() - 1.0 / 8.6).abs() < 1e-15);
        assert!((out[6].unwrap() - 0.85 / 8.6).abs() < 1e-15);
        // Mass is kept where nothing reaches the border: 1.2/8.6 + 4/8.6 + 4 × 0.85/8.6 = 1.
        let total: f64 = out.iter().map(|v| v.unwrap()).sum();
        assert!((total - 1.0).abs() < 1e-14, "{total}");
    }

    #[test]
    fn nothing_crosses_a_depth_jump_but_the_leak_of_a_cornered_pixel() {
        // Two surfaces, depth 2 (columns 0–2) and 3 (columns 3–5), values 0 and 1: across the
        // jump every edge weight is 0. A pixel with three whole edges (sum 3 ≥ 1.5) does not
        // leak: column 2 stays exactly 0, column 3 exactly 1.
        let g = frame(6, 5, |x, _| Some(if x <= 2 { 2.0 } else { 3.0 }));
        let values: Vec<Option<f64>> = (0..30).map(|i| Some(if i % 6 <= 2 { 0.0 } else { 1.0 })).collect();
        let out = denoise(&g, &values, 3, 1.2);
        for (i, v) in out.iter().enumerate() {
            assert_eq!(v.unwrap(), values[i].unwrap(), "pixel {i}");
        }
        // A lone pixel of another depth (all four edges 0, sum 0) borrows min(1.5, 1)/1.5 × ½
        // = ⅓ from each side neighbour, and from each diagonal 0.425 × (⅓ × 1 + ⅓ × 1) (its
        // side neighbours' edges toward the diagonal one are whole): with the neighbours at 0,
        // 1.2 / (1.2 + 4 × ⅓ + 4 × 0.85 × ⅓).
        let island = frame(5, 5, |x, y| Some(if (x, y) == (2, 2) { 3.0 } else { 2.0 }));
        let mut lone = vec![Some(0.0); 25];
        lone[12] = Some(1.0);
        let out = denoise(&island, &lone, 1, 1.2);
        let leak = 1.0 / 1.5 * 0.5;
        let expected = 1.2 / (1.2 + 4.0 * leak + 4.0 * 0.85 * leak);
        assert!((out[12].unwrap() - expected).abs() < 1e-15, "{:?} against {expected}", out[12]);
        // Its neighbours do not take from it: their edge toward it is 0 and three whole
        // edges (sum 3) leave them no leak.
        assert_eq!(out[11], Some(0.0));
        // A pixel with no surface stays without one and adds nothing to its neighbours.
        let holed = frame(3, 3, |x, _| (x != 1).then_some(2.0));
        let values: Vec<Option<f64>> = holed.samples.iter().map(|s| s.map(|_| 0.5)).collect();
        let out = denoise(&holed, &values, 1, 1.2);
        assert_eq!((out[4], out[3]), (None, Some(0.5)));
    }

    #[test]
    fn the_f32_twin_follows_the_f64_body() {
        let g = frame(9, 7, |x, y| (x + y != 7).then_some(2.0 + 0.05 * x as f64 + if y > 3 { 0.5 } else { 0.0 }));
        let values: Vec<Option<f64>> = (0..63).map(|i| g.samples[i].map(|_| ((i * 37) % 11) as f64 / 10.0)).collect();
        let narrow = g.narrowed();
        let narrow_values: Vec<Option<f32>> = values.iter().map(|v| v.map(|v| v as f32)).collect();
        let wide = denoise(&g, &values, 2, 1.2);
        let twin = denoise(&narrow, &narrow_values, 2, 1.2);
        for (a, b) in wide.iter().zip(&twin) {
            assert_eq!(a.is_some(), b.is_some());
            if let (Some(a), Some(b)) = (a, b) {
                assert!((a - *b as f64).abs() < 1e-6, "{a} against {b}");
            }
        }
    }
}
