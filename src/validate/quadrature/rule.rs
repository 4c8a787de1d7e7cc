//! Panel rules of the adaptive path: Kronrod-7 with its embedded Gauss-3 and plain
//! Gauss-3, each with both panel ends as interpolation nodes, and what is built on the
//! interpolant of the node values — its sign changes (regula falsi, Illinois) and the
//! exact integral of its magnitude. Abscissae and weights: QUADPACK (Piessens et al.
//! 1983).

/// A panel rule on [−1, 1]: M nodes, increasing, the first and last at the ends (shared
/// with the neighbouring panels), the weights of the rule, its error estimate (see
/// [`Estimate`]), and the monomial coefficients of the Lagrange basis of the nodes
/// (L_i(t) = Σ_k lagrange[i][k] t^k), so that p(t) = Σ_i g_i L_i(t) interpolates node
/// values g.
pub struct Rule<const M: usize> {
    pub(super) nodes: [f64; M],
    weights: [f64; M],
    estimate: Estimate<M>,
    lagrange: [[f64; M]; M],
}

/// How a rule estimates its error on a panel.
pub enum Estimate<const M: usize> {
    /// Against an embedded lower-degree rule with these weights, scaled as QUADPACK does.
    Embedded([f64; M]),
    /// From the highest coefficient c of the interpolant of the smooth function under the
    /// integral (g for the relative error, F_m − F_e for the squared one): the rule is
    /// exact to a degree above the interpolant's, so its error comes from higher terms,
    /// taken as no larger than |c| times this factor (the rule's error on t^(M+1)).
    Tail(f64),
}

impl<const M: usize> Rule<M> {
    const fn new(nodes: [f64; M], weights: [f64; M], estimate: Estimate<M>) -> Self {
        // Multiply out Π_{m≠i} (t − t_m)/(t_i − t_m), lowest power first.
        let mut lagrange = [[0.0; M]; M];
        let mut i = 0;
        while i < M {
            let mut poly = [0.0; M];
            poly[0] = 1.0;
            let mut degree = 0;
            let mut m = 0;
            while m < M {
                if m != i {
                    let scale = 1.0 / (nodes[i] - nodes[m]);
                    let mut power = degree + 1;
                    while power > 0 {
                        poly[power] = (poly[power - 1] - nodes[m] * poly[power]) * scale;
                        power -= 1;
                    }
                    poly[0] = -nodes[m] * poly[0] * scale;
                    degree += 1;
                }
                m += 1;
            }
            lagrange[i] = poly;
            i += 1;
        }
        Self { nodes, weights, estimate, lagrange }
    }

    /// The rule and the embedded rule (0 for a [`Estimate::Tail`] rule) applied to node
    /// values.
    #[cfg(test)]
    fn sums(&self, values: &[f64; M]) -> (f64, f64) {
        let embedded_weights = match &self.estimate {
            Estimate::Embedded(weights) => weights,
            Estimate::Tail(_) => &[0.0; M],
        };
        let mut main = 0.0;
        let mut embedded = 0.0;
        for i in 0..M {
            main += self.weights[i] * values[i];
            embedded += embedded_weights[i] * values[i];
        }
        (main, embedded)
    }

    /// The rule's value on [−1, 1] and its error estimate, for node values of the
    /// integrand. `tail` gives, for [`Estimate::Tail`], the size of the interpolant's
    /// highest coefficient as it bears on the integral: |c_top| of the smooth function
    /// under the integral, times 2·max|s| when the integrand is its square s²
    /// (∫(s + ε)² − ∫s² ≈ 2∫sε).
    ///
    /// [`Estimate::Embedded`]: QUADPACK's (Piessens et al. 1983, qk15) scaling of
    /// E = |main − embedded| by the integrand's variation V = Σ w_i |f_i − main/2|:
    /// E·min(1, (200 E/V)^1.5). E is the error of the embedded (lower-degree) rule; the
    /// main rule's error falls much faster with the panel width, which the power models.
    pub(super) fn estimate(&self, values: &[f64; M], tail: impl FnOnce() -> f64) -> (f64, f64) {
        let main = self.integral(values);
        let error = match &self.estimate {
            Estimate::Embedded(weights) => {
                let embedded: f64 = (0..M).map(|i| weights[i] * values[i]).sum();
                let mean = 0.5 * main;
                let variation: f64 = (0..M).map(|i| self.weights[i] * (values[i] - mean).abs()).sum();
                let difference = (main - embedded).abs();
                if variation > 0.0 && difference > 0.0 {
                    let ratio = (200.0 * difference / variation).min(1.0);
                    difference * ratio * ratio.sqrt()
                } else {
                    difference
                }
            }
            Estimate::Tail(factor) => factor * tail(),
        };
        (main, error)
    }

    /// The rule applied to node values (the integral over [−1, 1]).
    #[inline]
    pub(super) fn integral(&self, values: &[f64; M]) -> f64 {
        (0..M).map(|i| self.weights[i] * values[i]).sum()
    }

    /// The highest (t^(M−1)) coefficient of the interpolant of node values: the
    /// (M−1)-th divided difference.
    #[inline]
    pub(super) fn top_coefficient(&self, values: &[f64; M]) -> f64 {
        (0..M).map(|i| self.lagrange[i][M - 1] * values[i]).sum()
    }

    /// The interpolating polynomial of node values `g` (monomials in t, lowest first).
    pub(super) fn interpolate(&self, g: &[f64; M]) -> [f64; M] {
        let mut coefficients = [0.0; M];
        for (value, basis) in g.iter().zip(self.lagrange.iter()) {
            for (c, b) in coefficients.iter_mut().zip(basis) {
                *c += value * b;
            }
        }
        coefficients
    }

    /// The sign changes of the interpolant p of `g` on [−1, 1], increasing, into
    /// `roots`; returns how many. Between nodes of opposite sign there is a root. Between
    /// nodes of the same sign p can still dip through zero (twice): a root r in (lo, hi)
    /// needs |p(lo)| + |p(hi)| ≤ max|p'|·(hi − lo), with max|p'| ≤ Σ k|c_k| x^(k−1) on
    /// [lo, hi], x = max(|lo|, |hi|); intervals that pass this test are halved and tested
    /// again, down to 1/32 of the gap between nodes. A dip narrower than that is missed,
    /// and with it an area below max|p'|·(gap/32)².
    #[cfg(test)]
    pub(super) fn sign_change_roots(&self, g: &[f64; M], coefficients: &[f64; M], roots: &mut [f64; MAX_ROOTS]) -> usize {
        let mut brackets = Vec::new();
        let count = self.sign_change_brackets(g, coefficients, 0, &mut brackets);
        for (r, b) in roots.iter_mut().zip(&brackets) {
            *r = root(coefficients, b.lo, b.hi, b.scale);
        }
        count
    }

    /// The brackets of the sign changes that [`sign_change_roots`](Self::sign_change_roots)
    /// resolves, in increasing order, appended to `brackets`; returns how many (at most
    /// [`MAX_ROOTS`]), each naming the interpolant as `polynomial`. Each root is then
    /// [`root`] of its bracket ([`roots_of`]).
    pub(super) fn sign_change_brackets(&self, g: &[f64; M], coefficients: &[f64; M], polynomial: usize, brackets: &mut Vec<Bracket>) -> usize {
        let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return 0;
        }
        // The bound on [−1, 1], to rule out most gaps before the finer one on a gap.
        let slope_bound: f64 = coefficients.iter().enumerate().skip(1).map(|(k, c)| k as f64 * c.abs()).sum();
        let mut found = Brackets { coefficients, polynomial, scale, brackets, count: 0 };
        for i in 0..M - 1 {
            let (lo, hi) = (self.nodes[i], self.nodes[i + 1]);
            if g[i] * g[i + 1] < 0.0 {
                found.push(lo, hi);
            } else if g[i].abs() + g[i + 1].abs() <= slope_bound * (hi - lo) {
                found.dips(Knot { t: lo, value: g[i] }, Knot { t: hi, value: g[i + 1] }, 5);
            }
        }
        found.count
    }
}

/// An interval (lo, hi) of [−1, 1] where an interpolant p (named by an index, `polynomial`)
/// changes sign, and the largest |g| at its panel's nodes (the scale of [`root`]'s
/// tolerance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Bracket {
    pub polynomial: usize,
    pub lo: f64,
    pub hi: f64,
    pub scale: f64,
}

/// The sign changes found so far on a panel, in increasing order.
struct Brackets<'a, const M: usize> {
    coefficients: &'a [f64; M],
    polynomial: usize,
    scale: f64,
    brackets: &'a mut Vec<Bracket>,
    count: usize,
}

impl<const M: usize> Brackets<'_, M> {
    fn push(&mut self, lo: f64, hi: f64) {
        if self.count < MAX_ROOTS {
            self.brackets.push(Bracket { polynomial: self.polynomial, lo, hi, scale: self.scale });
            self.count += 1;
        }
    }

    /// Sign changes of p in (lo, hi) where p(lo), p(hi) have the same sign, by bisection
    /// while the slope bound cannot exclude a root, `depth` levels deep.
    fn dips(&mut self, lo: Knot, hi: Knot, depth: u32) {
        let coefficients = self.coefficients;
        if lo.value * hi.value < 0.0 {
            self.push(lo.t, hi.t);
            return;
        }
        if depth == 0 || lo.value == 0.0 || hi.value == 0.0 {
            return;
        }
        let x = lo.t.abs().max(hi.t.abs());
        let slope_bound = coefficients.iter().enumerate().skip(1).rev().fold(0.0, |acc, (k, c)| acc * x + k as f64 * c.abs());
        if lo.value.abs() + hi.value.abs() > slope_bound * (hi.t - lo.t) {
            return;
        }
        let middle = Knot { t: 0.5 * (lo.t + hi.t), value: 0.0 };
        let middle = Knot { value: horner(coefficients, middle.t), ..middle };
        self.dips(lo, middle, depth - 1);
        self.dips(middle, hi, depth - 1);
    }
}

/// A point t of [−1, 1] with the interpolant's value there.
#[derive(Clone, Copy, Debug)]
struct Knot {
    t: f64,
    value: f64,
}

/// The 7-point Kronrod rule (exact to degree 11) with its embedded 3-point Gauss rule
/// (degree 5), plus the two ends as interpolation nodes (weight 0); QUADPACK's qk7
/// abscissae and weights. For panels wide enough that the integrand's curvature matters.
pub const KRONROD7: Rule<9> = Rule::new(
    [
        -1.0,
        -0.960_491_268_708_020_3,
        -0.774_596_669_241_483_4,
        -0.434_243_749_346_802_6,
        0.0,
        0.434_243_749_346_802_6,
        0.774_596_669_241_483_4,
        0.960_491_268_708_020_3,
        1.0,
    ],
    [
        0.0,
        0.104_656_226_026_467_27,
        0.268_488_089_868_333_44,
        0.401_397_414_775_962_2,
        0.450_916_538_658_474_14,
        0.401_397_414_775_962_2,
        0.268_488_089_868_333_44,
        0.104_656_226_026_467_27,
        0.0,
    ],
    Estimate::Embedded([0.0, 0.0, 5.0 / 9.0, 0.0, 8.0 / 9.0, 0.0, 5.0 / 9.0, 0.0, 0.0]),
);

/// The 3-point Gauss rule (nodes ±√(3/5), 0; weights 5/9, 8/9, 5/9; exact to degree 5)
/// plus the two ends as interpolation nodes (weight 0): three new evaluations per panel,
/// a degree-4 interpolant for the roots, and a [`Estimate::Tail`] error estimate (G3's
/// error on t⁶ is 2/7 − 2·(5/9)·(3/5)³ = 0.0457). For the narrow panels between LUT
/// texel centres, where F_m − F_e is nearly quadratic and Kronrod's seven nodes would
/// be wasted; an embedded rule cannot judge it (any 5-node rule below degree 5 sees the
/// genuine t⁴ of (F_m − F_e)² as error).
pub const GAUSS3: Rule<5> = Rule::new(
    [-1.0, -0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4, 1.0],
    [0.0, 5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0, 0.0],
    Estimate::Tail(0.0457),
);

/// p(t) by Horner's rule.
#[inline]
fn horner<const M: usize>(coefficients: &[f64; M], t: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, c| acc * t + c)
}

/// The antiderivative of p divided by t: c_k/(k + 1) for the monomial coefficients c_k
/// of p, lowest power first.
#[inline]
fn antiderivative_coefficients<const M: usize>(coefficients: &[f64; M]) -> [f64; M] {
    std::array::from_fn(|power| coefficients[power] / (power + 1) as f64)
}

/// ∫₀ᵗ p by Horner's rule on the antiderivative, from [`antiderivative_coefficients`].
#[inline]
fn antiderivative<const M: usize>(quotients: &[f64; M], t: f64) -> f64 {
    let mut acc = 0.0;
    for q in quotients.iter().rev() {
        acc = acc * t + q;
    }
    acc * t
}

/// A root of p in (lo, hi) where p(lo) and p(hi) differ in sign: Illinois regula falsi
/// until the bracket is below 1e-4 or |p| below 1e-5 of `scale` (the largest |g| on the
/// panel). A root off by δ changes ∫|p| by about |p'|δ², below 1e-8 of the panel's
/// integral.
fn root<const M: usize>(coefficients: &[f64; M], mut lo: f64, mut hi: f64, scale: f64) -> f64 {
    let (mut f_lo, mut f_hi) = (horner(coefficients, lo), horner(coefficients, hi));
    if f_lo == 0.0 {
        return lo;
    }
    if f_hi == 0.0 || f_lo * f_hi > 0.0 {
        return hi;
    }
    let small = 1e-5 * scale;
    let mut side = 0i8;
    for _ in 0..60 {
        let x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        let x = if x > lo && x < hi { x } else { 0.5 * (lo + hi) };
        let f = horner(coefficients, x);
        if f.abs() <= small || hi - lo < 1e-4 {
            return x;
        }
        if (f > 0.0) == (f_lo > 0.0) {
            lo = x;
            f_lo = f;
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            hi = x;
            f_hi = f;
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (lo + hi)
}

/// How many brackets [`roots_of`] resolves at once: one AVX-512 register of f64.
const ROOT_LANES: usize = 8;

/// [`root`] of each bracket into `roots` (the shorter decides how many), the bracket's
/// polynomial being `polynomials(bracket.polynomial)`: [`ROOT_LANES`] brackets at a time in
/// vector lanes, each lane with the operations of [`root`] in its order (the same bits).
/// The vector width is chosen at run time (AVX-512, AVX2, or what the baseline target
/// allows).
pub(super) fn roots_of<'a, const M: usize>(brackets: &[Bracket], polynomials: &impl Fn(usize) -> &'a [f64; M], roots: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has just been found to support AVX-512F.
            return unsafe { roots_avx512(brackets, polynomials, roots) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            return unsafe { roots_avx2(brackets, polynomials, roots) };
        }
    }
    roots_in_lanes(brackets, polynomials, roots)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn roots_avx512<'a, const M: usize>(brackets: &[Bracket], polynomials: &impl Fn(usize) -> &'a [f64; M], roots: &mut [f64]) {
    roots_in_lanes(brackets, polynomials, roots)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn roots_avx2<'a, const M: usize>(brackets: &[Bracket], polynomials: &impl Fn(usize) -> &'a [f64; M], roots: &mut [f64]) {
    roots_in_lanes(brackets, polynomials, roots)
}

#[inline(always)]
fn roots_in_lanes<'a, const M: usize>(brackets: &[Bracket], polynomials: &impl Fn(usize) -> &'a [f64; M], roots: &mut [f64]) {
    for (chunk, out) in brackets.chunks(ROOT_LANES).zip(roots.chunks_mut(ROOT_LANES)) {
        if let ([b], [r]) = (chunk, &mut *out) {
            *r = root(polynomials(b.polynomial), b.lo, b.hi, b.scale);
            continue;
        }
        // Unused lanes repeat the first bracket.
        let lane = |l: usize| chunk.get(l).unwrap_or(&chunk[0]);
        let lanes: RootLanes<M> = RootLanes {
            coefficients: std::array::from_fn(|k| std::array::from_fn(|l| polynomials(lane(l).polynomial)[k])),
            lo: std::array::from_fn(|l| lane(l).lo),
            hi: std::array::from_fn(|l| lane(l).hi),
            scale: std::array::from_fn(|l| lane(l).scale),
        };
        let found = lanes.solve();
        let used = chunk.len().min(out.len());
        out[..used].copy_from_slice(&found[..used]);
    }
}

/// [`ROOT_LANES`] brackets, structure of arrays: coefficient k of every lane together.
struct RootLanes<const M: usize> {
    coefficients: [[f64; ROOT_LANES]; M],
    lo: [f64; ROOT_LANES],
    hi: [f64; ROOT_LANES],
    scale: [f64; ROOT_LANES],
}

impl<const M: usize> RootLanes<M> {
    /// p of each lane at its t by Horner's rule ([`horner`] lane by lane).
    #[inline(always)]
    fn horner(&self, t: &[f64; ROOT_LANES]) -> [f64; ROOT_LANES] {
        let mut acc = [0.0; ROOT_LANES];
        for c in self.coefficients.iter().rev() {
            for l in 0..ROOT_LANES {
                acc[l] = acc[l] * t[l] + c[l];
            }
        }
        acc
    }

    /// [`root`] in every lane: the Illinois steps as selects, a lane left alone once it
    /// has its root, until every lane has one or the 60 steps are spent.
    #[inline(always)]
    fn solve(&self) -> [f64; ROOT_LANES] {
        let (mut lo, mut hi) = (self.lo, self.hi);
        let (mut f_lo, mut f_hi) = (self.horner(&lo), self.horner(&hi));
        let mut found = [0.0; ROOT_LANES];
        let mut active = [false; ROOT_LANES];
        for l in 0..ROOT_LANES {
            if f_lo[l] == 0.0 {
                found[l] = lo[l];
            } else if f_hi[l] == 0.0 || f_lo[l] * f_hi[l] > 0.0 {
                found[l] = hi[l];
            } else {
                active[l] = true;
            }
        }
        let small: [f64; ROOT_LANES] = std::array::from_fn(|l| 1e-5 * self.scale[l]);
        // −1: the last step moved lo, +1: hi, 0: none yet.
        let mut side = [0.0f64; ROOT_LANES];
        for _ in 0..60 {
            if !active.iter().any(|&a| a) {
                return found;
            }
            let mut x = [0.0; ROOT_LANES];
            for l in 0..ROOT_LANES {
                let step = (lo[l] * f_hi[l] - hi[l] * f_lo[l]) / (f_hi[l] - f_lo[l]);
                x[l] = if step > lo[l] && step < hi[l] { step } else { 0.5 * (lo[l] + hi[l]) };
            }
            let f = self.horner(&x);
            for l in 0..ROOT_LANES {
                let done = active[l] && (f[l].abs() <= small[l] || hi[l] - lo[l] < 1e-4);
                found[l] = if done { x[l] } else { found[l] };
                let go = active[l] && !done;
                let same = (f[l] > 0.0) == (f_lo[l] > 0.0);
                let (move_lo, move_hi) = (go && same, go && !same);
                let new_f_lo = if move_lo { f[l] } else if move_hi && side[l] == 1.0 { f_lo[l] * 0.5 } else { f_lo[l] };
                let new_f_hi = if move_hi { f[l] } else if move_lo && side[l] == -1.0 { f_hi[l] * 0.5 } else { f_hi[l] };
                lo[l] = if move_lo { x[l] } else { lo[l] };
                hi[l] = if move_hi { x[l] } else { hi[l] };
                f_lo[l] = new_f_lo;
                f_hi[l] = new_f_hi;
                side[l] = if move_lo { -1.0 } else if move_hi { 1.0 } else { side[l] };
                active[l] = go;
            }
        }
        for l in 0..ROOT_LANES {
            if active[l] {
                found[l] = 0.5 * (lo[l] + hi[l]);
            }
        }
        found
    }
}

/// At most this many sign changes of p are resolved per panel.
pub(super) const MAX_ROOTS: usize = 32;

/// ∫_{−1}^{1} |p| given p's sign changes at `roots` (increasing).
pub(super) fn absolute_integral<const M: usize>(coefficients: &[f64; M], roots: &[f64]) -> f64 {
    let quotients = antiderivative_coefficients(coefficients);
    let mut total = 0.0;
    let mut from = antiderivative(&quotients, -1.0);
    for &t in roots.iter().chain(std::iter::once(&1.0)) {
        let to = antiderivative(&quotients, t);
        total += (to - from).abs();
        from = to;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫_{−1}^{1} t^power.
    fn monomial_integral(power: i32) -> f64 {
        if power % 2 == 0 {
            2.0 / (power + 1) as f64
        } else {
            0.0
        }
    }

    #[test]
    fn rules_are_exact_to_their_degree() {
        let kronrod = |power: i32| KRONROD7.sums(&KRONROD7.nodes.map(|t| t.powi(power)));
        let gauss = |power: i32| {
            let (main, _) = GAUSS3.sums(&GAUSS3.nodes.map(|t| t.powi(power)));
            (main, main)
        };
        let cases: [(i32, i32, &dyn Fn(i32) -> (f64, f64)); 2] = [(11, 5, &kronrod), (5, 5, &gauss)];
        for (rule_main, rule_embedded, sums) in cases {
            for power in 0..=rule_main {
                let (main, embedded) = sums(power);
                let exact = monomial_integral(power);
                assert!((main - exact).abs() < 1e-15, "x^{power}: {main} vs {exact}");
                if power <= rule_embedded {
                    assert!((embedded - exact).abs() < 1e-15, "embedded x^{power}: {embedded} vs {exact}");
                }
            }
            // One degree more is not exact (the rule is what it claims, no more).
            let (main, _) = sums(rule_main + 1);
            assert!((main - monomial_integral(rule_main + 1)).abs() > 1e-6);
        }
    }

    fn check_interpolant<const M: usize>(rule: &Rule<M>) {
        // p(t) = (t − 0.3)(t + 0.55)(t − 0.9) = t³ − 0.65 t² − 0.39 t + 0.1485 (degree 3 < M).
        let p = |t: f64| (t - 0.3) * (t + 0.55) * (t - 0.9);
        let g = rule.nodes.map(p);
        let coefficients = rule.interpolate(&g);
        let expected = [0.1485, -0.39, -0.65, 1.0];
        for (k, c) in coefficients.iter().enumerate() {
            assert!((c - expected.get(k).copied().unwrap_or(0.0)).abs() < 1e-13, "{coefficients:?}");
        }
        let mut roots = [0.0; MAX_ROOTS];
        let count = rule.sign_change_roots(&g, &coefficients, &mut roots);
        assert_eq!(count, 3, "{:?}", &roots[..count]);
        // Roots are found to |p| ≤ 1e-5 of the largest |g| (see `root`).
        for (r, expected) in roots[..3].iter().zip([-0.55, 0.3, 0.9]) {
            assert!((r - expected).abs() < 1e-4, "{roots:?}");
        }
        // ∫|p| over [−1, 1], by the antiderivative P(t) = t⁴/4 − 0.65t³/3 − 0.195t² + 0.1485t.
        let big_p = |t: f64| t.powi(4) / 4.0 - 0.65 * t.powi(3) / 3.0 - 0.195 * t * t + 0.1485 * t;
        let knots = [-1.0, -0.55, 0.3, 0.9, 1.0];
        let expected: f64 = knots.windows(2).map(|w| (big_p(w[1]) - big_p(w[0])).abs()).sum();
        // A root off by δ moves ∫|p| by about |p'|δ²: ≤ 1e-8 of it.
        assert!((absolute_integral(&coefficients, &roots[..3]) - expected).abs() < 1e-8 * expected);
    }

    #[test]
    fn interpolant_reproduces_polynomials_roots_and_absolute_integrals() {
        check_interpolant(&KRONROD7);
        check_interpolant(&GAUSS3);
    }

    /// The roots in vector lanes are the bits of [`root`] one bracket at a time: sign
    /// changes of random quartics and octics (p from random roots, so brackets close in),
    /// a root at an end, ends of one sign, a zero polynomial, a zero scale (only the
    /// bracket width stops), and batches of 1, 3, 8 and 19 brackets (partly filled lanes).
    #[test]
    fn roots_in_lanes_give_the_bits_of_one_at_a_time() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        fn check<const M: usize>((polynomials, brackets): &(Vec<[f64; M]>, Vec<Bracket>)) {
            let mut lanes = vec![f64::NAN; brackets.len()];
            roots_of(brackets, &|p| &polynomials[p], &mut lanes);
            for (b, got) in brackets.iter().zip(&lanes) {
                let expected = root(&polynomials[b.polynomial], b.lo, b.hi, b.scale);
                assert_eq!(got.to_bits(), expected.to_bits(), "{b:?}: {got} vs {expected}");
            }
        }
        fn brackets_of<const M: usize>(uniform: &mut impl FnMut() -> f64, count: usize) -> (Vec<[f64; M]>, Vec<Bracket>) {
            (0..count)
                .map(|i| {
                    // p(t) = s·Π(t − r_j) with M − 1 random roots, bracket around one of them.
                    let roots: Vec<f64> = (0..M - 1).map(|_| uniform()).collect();
                    let mut coefficients = [0.0; M];
                    coefficients[0] = 1e-3 * (1.0 + uniform().abs());
                    for (degree, r) in roots.iter().enumerate() {
                        for k in (0..=degree + 1).rev() {
                            let lower = if k > 0 { coefficients[k - 1] } else { 0.0 };
                            coefficients[k] = lower - r * coefficients[k];
                        }
                    }
                    let target = roots[i % roots.len()];
                    let (lo, hi) = match i % 7 {
                        // One end exactly at a root of p, or both ends on one side.
                        5 => (target, target + 0.3),
                        6 => (-1.0, -0.99),
                        _ => (target - 0.05 * (1.0 + uniform().abs()), target + 0.07 * (1.0 + uniform().abs())),
                    };
                    let scale = if i % 11 == 3 { 0.0 } else { coefficients.iter().map(|c| c.abs()).sum() };
                    (coefficients, Bracket { polynomial: i, lo, hi, scale })
                })
                .unzip()
        }
        for count in [1, 3, 8, 19] {
            check::<5>(&brackets_of::<5>(&mut uniform, count));
            check::<9>(&brackets_of::<9>(&mut uniform, count));
        }
        check::<5>(&(
            vec![[0.0; 5], [0.3, -1.0, 0.0, 0.0, 0.0]],
            vec![Bracket { polynomial: 0, lo: -0.5, hi: 0.5, scale: 1.0 }, Bracket { polynomial: 1, lo: 0.0, hi: 1.0, scale: 1.0 }],
        ));
    }

    #[test]
    fn a_dip_through_zero_between_nodes_is_found() {
        // g(t) = (t − 0.15)(t − 0.35) − 0.001: both roots lie between the Kronrod nodes
        // 0 and 0.434, where g is positive at both nodes.
        let g_of = |t: f64| (t - 0.15) * (t - 0.35);
        let g = KRONROD7.nodes.map(g_of);
        assert!(g[4] > 0.0 && g[5] > 0.0);
        let coefficients = KRONROD7.interpolate(&g);
        let mut roots = [0.0; MAX_ROOTS];
        let count = KRONROD7.sign_change_roots(&g, &coefficients, &mut roots);
        assert_eq!(&roots[..count].iter().map(|r| (r * 1e3).round() / 1e3).collect::<Vec<_>>(), &[0.15, 0.35]);
    }
}
