//! Brent's one-dimensional minimisation (Brent 1973, "Algorithms for Minimization without
//! Derivatives", ch. 5; the form of Numerical Recipes' `brent`): parabolic steps through
//! the three best points seen, golden-section steps where the parabola is not trusted.

/// (3 − √5)/2: the golden-section fraction.
const GOLDEN: f64 = 0.381_966_011_250_105_1;

/// The minimum of `f` in [a, b], starting from `start` = (x, f(x)) inside the bracket.
/// `tolerance(x)` is the absolute precision wanted at x; the search stops when the bracket
/// around the best point is within twice it, or after `max_evaluations`. Returns the best
/// point and its value. A parabola step that is not finite falls back to golden section.
pub fn brent(
    mut f: impl FnMut(f64) -> f64,
    bracket: (f64, f64),
    start: (f64, f64),
    tolerance: impl Fn(f64) -> f64,
    max_evaluations: usize,
) -> (f64, f64) {
    let (mut a, mut b) = bracket;
    let (mut x, mut fx) = start;
    let (mut w, mut fw, mut v, mut fv) = (x, fx, x, fx);
    let (mut step, mut previous_step) = (0.0f64, 0.0f64);
    for _ in 0..max_evaluations {
        let middle = 0.5 * (a + b);
        let tol1 = tolerance(x);
        let tol2 = 2.0 * tol1;
        if (x - middle).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if previous_step.abs() > tol1 {
            // Parabola through x, w, v.
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let older = previous_step;
            previous_step = step;
            if p.abs() < (0.5 * q * older).abs() && p > q * (a - x) && p < q * (b - x) {
                step = p / q;
                let u = x + step;
                if u - a < tol2 || b - u < tol2 {
                    step = tol1.copysign(middle - x);
                }
                golden = false;
            }
        }
        if golden {
            previous_step = if x >= middle { a - x } else { b - x };
            step = GOLDEN * previous_step;
        }
        let u = if step.abs() >= tol1 { x + step } else { x + tol1.copysign(step) };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_smooth_minimum_in_few_evaluations() {
        // cos has its minimum at π in [2, 4].
        let mut evaluations = 0;
        let (x, fx) = brent(
            |t| {
                evaluations += 1;
                t.cos()
            },
            (2.0, 4.0),
            (3.0, 3f64.cos()),
            |x| 1e-9 * x.abs() + 1e-15,
            100,
        );
        assert!((x - std::f64::consts::PI).abs() < 1e-7 && (fx + 1.0).abs() < 1e-14, "{x}");
        assert!(evaluations < 20, "{evaluations}");
    }

    #[test]
    fn stops_after_the_evaluation_budget_and_survives_infinite_costs() {
        let mut evaluations = 0;
        brent(
            |t| {
                evaluations += 1;
                t * t
            },
            (-1.0, 1.0),
            (0.9, 0.81),
            |_| 0.0,
            5,
        );
        assert_eq!(evaluations, 5);
        let (x, _) = brent(|t| if t > 0.5 { f64::INFINITY } else { (t - 0.2).powi(2) }, (0.0, 1.0), (0.4, 0.04), |_| 1e-9, 200);
        assert!((x - 0.2).abs() < 1e-6, "{x}");
    }
}
