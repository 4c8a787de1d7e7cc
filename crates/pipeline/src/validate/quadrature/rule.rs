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
    #[inline(always)]
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
    #[inline(always)]
    pub(super) fn integral(&self, values: &[f64; M]) -> f64 {
        (0..M).map(|i| self.weights[i] * values[i]).sum()
    }

    /// The highest (t^(M−1)) coefficient of the interpolant of node values: the
    /// (M−1)-th divided difference.
    #[inline(always)]
    pub(super) fn top_coefficient(&self, values: &[f64; M]) -> f64 {
        (0..M).map(|i| self.lagrange[i][M - 1] * values[i]).sum()
    }

    /// The interpolating polynomial of node values `g` (monomials in t, lowest first).
    #[inline(always)]
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
    #[inline(always)]
    pub(super) fn sign_change_roots(&self, g: &[f64; M], coefficients: &[f64; M], roots: &mut [f64; MAX_ROOTS]) -> usize {
        let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return 0;
        }
        // The bound on [−1, 1], to rule out most gaps before the finer one on a gap.
        let slope_bound: f64 = coefficients.iter().enumerate().skip(1).map(|(k, c)| k as f64 * c.abs()).sum();
        let mut found = Roots { roots, count: 0 };
        for i in 0..M - 1 {
            let (lo, hi) = (self.nodes[i], self.nodes[i + 1]);
            if g[i] * g[i + 1] < 0.0 {
                found.push(root(coefficients, lo, hi, scale));
            } else if g[i].abs() + g[i + 1].abs() <= slope_bound * (hi - lo) {
                found.dips(coefficients, scale, Knot { t: lo, value: g[i] }, Knot { t: hi, value: g[i + 1] }, 5);
            }
        }
        found.count
    }
}

/// Roots found so far on a panel, in increasing order.
struct Roots<'a> {
    roots: &'a mut [f64; MAX_ROOTS],
    count: usize,
}

impl Roots<'_> {
    fn push(&mut self, r: f64) {
        if self.count < MAX_ROOTS {
            self.roots[self.count] = r;
            self.count += 1;
        }
    }

    /// Sign changes of p in (lo, hi) where p(lo), p(hi) have the same sign, by bisection
    /// while the slope bound cannot exclude a root, `depth` levels deep.
    fn dips<const M: usize>(&mut self, coefficients: &[f64; M], scale: f64, lo: Knot, hi: Knot, depth: u32) {
        if lo.value * hi.value < 0.0 {
            self.push(root(coefficients, lo.t, hi.t, scale));
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
        self.dips(coefficients, scale, lo, middle, depth - 1);
        self.dips(coefficients, scale, middle, hi, depth - 1);
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
#[inline(always)]
fn horner<const M: usize>(coefficients: &[f64; M], t: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, c| acc * t + c)
}

/// ∫₀ᵗ p by Horner's rule on the antiderivative.
#[inline(always)]
fn antiderivative<const M: usize>(coefficients: &[f64; M], t: f64) -> f64 {
    let mut acc = 0.0;
    for (power, c) in coefficients.iter().enumerate().rev() {
        acc = acc * t + c / (power + 1) as f64;
    }
    acc * t
}

/// A root of p in (lo, hi) where p(lo) and p(hi) differ in sign: Illinois regula falsi
/// until the bracket is below 1e-4 or |p| below 1e-5 of `scale` (the largest |g| on the
/// panel). A root off by δ changes ∫|p| by about |p'|δ², below 1e-8 of the panel's
/// integral.
#[inline(always)]
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

/// At most this many sign changes of p are resolved per panel.
pub(super) const MAX_ROOTS: usize = 32;

/// ∫_{−1}^{1} |p| given p's sign changes at `roots` (increasing).
#[inline(always)]
pub(super) fn absolute_integral<const M: usize>(coefficients: &[f64; M], roots: &[f64]) -> f64 {
    let mut total = 0.0;
    let mut from = antiderivative(coefficients, -1.0);
    for &t in roots.iter().chain(std::iter::once(&1.0)) {
        let to = antiderivative(coefficients, t);
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
        type Sums<'a> = &'a dyn Fn(i32) -> (f64, f64);
        let cases: [(i32, i32, Sums); 2] = [(11, 5, &kronrod), (5, 5, &gauss)];
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
