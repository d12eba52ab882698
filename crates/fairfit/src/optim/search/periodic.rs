//! The per-candidate objectives of the knot search for a **closed** curve: a periodic knot vector
//! with the seam at the first data point, control points by periodic least squares (`C^(p−1)`
//! across the seam by construction), orthogonal deviation of every point (the first one included:
//! nothing is interpolated) and the fairness over the whole loop.
//!
//! A candidate is given by its `n_u − 1` interior breakpoints `0 < b_1 < … < b_{n_u−1} < 1` (the
//! seam `b_0 = 0 ≡ b_{n_u} = 1` is fixed at the first point): `n_u` knot spans and `n_u` distinct
//! control points. The knots are [`crate::fit::lsq::periodic_knots`], the solve is the
//! least-squares module's periodic [`LsqSolver`] with the scale-free smoothing `λ ∫|C'''|² du`.
//!
//! For measuring, the periodic curve is clamped at the seam ([`NurbsCurve::clamped`]: the same
//! geometry on `[0, 1]`) and measured by the open method's [`measure_current`] on the data with the
//! first point repeated at the end (parameter 1). So `F` sums the same `n_u` spans, the seam span
//! pair included: a curvature jump at the seam cannot happen (the periodic basis is `C^(p−1)` there),
//! and the fairness of the spans on both sides of it counts like any other. The first point, which
//! the open measure takes as interpolated, is projected here from both sides of the seam. A point
//! whose foot lies just across the seam is measured at the seam (an upper bound of its distance), so
//! the deviation reported is never below the true one.
//!
//! [`ClosedProblem`] is the knot search over these candidates as a [`SwarmProblem`], with the open
//! problem's encoding (softmax gaps: the breakpoints are a partition of the circle cut at the seam)
//! and its feasibility-first fitness.

use super::encoding::{KnotEncoding, LOG_LAMBDA_OFF};
use super::objective::{measure_current, CandidateEval, EvalWorkspace, FitData};
use super::prepare::Prepared;
use super::problem::{CountProblem, KnotProblem, KnotWorkspace};
use super::pso::{Fitness, SwarmProblem};
use crate::errors::{Error, Result};
use crate::fit::lsq::{periodic_knots, LsqOptions, LsqSolver, SmoothingOrder};
use crate::nurbs::{NurbsCurve, Vec3};

/// The normalised closed data.
#[derive(Clone, Debug)]
pub struct ClosedData {
    /// The `m` distinct points (the closing point is not repeated), normalised.
    pub points: Vec<Vec3>,
    /// Their centripetal parameters on the loop: `0 = u_0 < … < u_{m−1} < 1` (the closing chord
    /// counts, `u = 1` is the first point again).
    pub params: Vec<f64>,
    /// The points with the first repeated at the end and the parameters with 1 appended: what the
    /// open measure and the knot repair work on.
    pub measure: FitData,
    /// Parameter-correction passes per candidate.
    pub corrections: usize,
}

impl ClosedData {
    /// Closed data from the prepared (normalised) distinct points.
    pub fn new(prep: &Prepared) -> Result<ClosedData> {
        let d = &prep.data;
        let pts = &d.points;
        let m = pts.len();
        let p = d.degree;
        if m < p + 2 {
            return Err(Error::InvalidData(format!(
                "a closed curve of degree {p} needs at least {} distinct points, got {m}",
                p + 2
            )));
        }
        let closing = (pts[0] - pts[m - 1]).norm();
        if closing <= 1e-9 {
            return Err(Error::InvalidData(format!(
                "the last point (index {}) nearly repeats the first: remove it",
                m - 1
            )));
        }
        let mut params = Vec::with_capacity(m + 1);
        let mut acc = 0.0;
        params.push(0.0);
        for w in pts.windows(2) {
            acc += (w[1] - w[0]).norm().sqrt();
            params.push(acc);
        }
        let total = acc + closing.sqrt();
        for u in &mut params {
            *u /= total;
        }
        let mut ext = params.clone();
        ext.push(1.0);
        let mut mpts = pts.clone();
        mpts.push(pts[0]);
        Ok(ClosedData {
            points: pts.clone(),
            params,
            measure: FitData {
                points: mpts,
                params: ext,
                degree: p,
                planar: d.planar,
                corrections: 0,
                ends: Default::default(),
                bands: Default::default(),
            },
            corrections: d.corrections,
        })
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.measure.degree
    }
}

/// Buffers of one closed candidate evaluation.
#[derive(Clone, Debug, Default)]
pub struct ClosedWorkspace {
    /// The clamped form of the last candidate (and its measurement state).
    pub eval: EvalWorkspace,
    /// Periodic knots of the last candidate.
    pub knots: Vec<f64>,
    /// Periodic control points (`n_u + p`, the last `p` repeating the first).
    pub ctrl: Vec<Vec3>,
    solver: Option<LsqSolver>,
    breaks: Vec<f64>,
    params: Vec<f64>,
    start: Vec<f64>,
}

/// The periodic knot vector for the interior breakpoints `interior` (seam at 0 ≡ 1).
pub(crate) fn closed_knots(degree: usize, interior: &[f64], breaks: &mut Vec<f64>) -> Vec<f64> {
    breaks.clear();
    breaks.push(0.0);
    breaks.extend_from_slice(interior);
    breaks.push(1.0);
    periodic_knots(breaks, degree)
}

/// Fits and measures the closed candidate with interior breakpoints `interior` and smoothing
/// `log10 λ`; the periodic curve is left in `ws.knots`/`ws.ctrl`, its clamped form in `ws.eval`.
pub fn evaluate_closed(
    data: &ClosedData,
    interior: &[f64],
    log_lambda: f64,
    ws: &mut ClosedWorkspace,
) -> CandidateEval {
    let p = data.degree();
    let mut breaks = std::mem::take(&mut ws.breaks);
    ws.knots = closed_knots(p, interior, &mut breaks);
    ws.breaks = breaks;
    let mut params = std::mem::take(&mut ws.params);
    params.clear();
    params.extend_from_slice(&data.params);
    let mut best = solve_and_measure(data, &params, log_lambda, ws);
    for _ in 0..data.corrections {
        if !best.solved {
            break;
        }
        // refit at the foot points of this fit; keep it only when the deviation shrinks
        let kept_ctrl = ws.ctrl.clone();
        let kept_params = params.clone();
        let m = params.len();
        params[1..].copy_from_slice(&ws.eval.foot_params[1..m]);
        let e = solve_and_measure(data, &params, log_lambda, ws);
        if e.solved && e.max_deviation <= best.max_deviation {
            best = e;
            continue;
        }
        params = kept_params;
        ws.ctrl = kept_ctrl;
        best = measure_periodic(data, &params, ws);
        break;
    }
    ws.params = params;
    best
}

fn solve_and_measure(
    data: &ClosedData,
    params: &[f64],
    log_lambda: f64,
    ws: &mut ClosedWorkspace,
) -> CandidateEval {
    let p = data.degree();
    let solver = ws.solver.get_or_insert_with(|| LsqSolver::new(p));
    let opts = LsqOptions {
        smoothing: if log_lambda > LOG_LAMBDA_OFF {
            10f64.powf(log_lambda)
        } else {
            0.0
        },
        smoothing_order: SmoothingOrder::Third,
        end_tangents: None,
        closed: true,
    };
    if solver
        .solve(&data.points, params, &ws.knots, None, &opts, &mut ws.ctrl)
        .is_err()
        || ws.ctrl.iter().any(|c| !c.is_finite())
    {
        return CandidateEval::failed();
    }
    measure_periodic(data, params, ws)
}

/// Measures the periodic curve in `ws.knots`/`ws.ctrl` (data parameters `params` as projection
/// starts).
fn measure_periodic(data: &ClosedData, params: &[f64], ws: &mut ClosedWorkspace) -> CandidateEval {
    let p = data.degree();
    let Ok(curve) = NurbsCurve::bspline(p, ws.knots.clone(), ws.ctrl.clone()) else {
        return CandidateEval::failed();
    };
    let Ok(clamped) = curve.clamped() else {
        return CandidateEval::failed();
    };
    ws.eval.knots.clear();
    ws.eval.knots.extend_from_slice(clamped.knots());
    ws.eval.ctrl.clear();
    ws.eval.ctrl.extend_from_slice(clamped.control_points());
    let m = data.points.len();
    ws.start.clear();
    ws.start.push(0.0);
    // projection starts inside [0, 1] (a corrected parameter may lie just across the seam)
    ws.start
        .extend(params[1..].iter().map(|&u| u.rem_euclid(1.0)));
    ws.start.push(1.0);
    let start = std::mem::take(&mut ws.start);
    let e = measure_current(&data.measure, &start, &mut ws.eval);
    ws.start = start;
    if !e.solved {
        return e;
    }
    let (d0, u0) = seam_foot(&clamped, data.points[0]);
    ws.eval.foot_params[0] = u0;
    ws.eval.foot_params[m] = u0;
    // the open measure averages over m + 1 points with zeros at both ends
    let sum2 = e.rms_deviation * e.rms_deviation * (m + 1) as f64 + d0 * d0;
    CandidateEval {
        max_deviation: e.max_deviation.max(d0),
        rms_deviation: (sum2 / m as f64).sqrt(),
        ..e
    }
}

/// Orthogonal distance of `q` from the clamped closed curve near its seam, and the foot parameter
/// (in `[0, 1)`): Newton from both ends of the domain, the nearer foot wins.
pub fn seam_foot(curve: &NurbsCurve, q: Vec3) -> (f64, f64) {
    let mut d = [Vec3::ZERO; 3];
    seam_foot_by(
        (curve.point(0.0) - q).norm(),
        q,
        |u| {
            curve.derivatives_into(u, 2, &mut d);
            d
        },
        |u| curve.point(u),
    )
}

/// [`seam_foot`] on any evaluator of a clamped closed curve on `[0, 1]`: `ders(u)` gives the point and
/// its first two derivatives, `point(u)` the point; `start` is the distance of `q` from the curve's
/// start (the answer when neither Newton run gets nearer).
pub fn seam_foot_by(
    start: f64,
    q: Vec3,
    mut ders: impl FnMut(f64) -> [Vec3; 3],
    mut point: impl FnMut(f64) -> Vec3,
) -> (f64, f64) {
    let mut best = (start, 0.0);
    for (u0, lo, hi) in [(0.0, 0.0, 0.5), (1.0, 0.5, 1.0)] {
        let mut u: f64 = u0;
        for _ in 0..20 {
            let d = ders(u);
            let diff = d[0] - q;
            let f = d[1].dot(diff);
            let fp = d[2].dot(diff) + d[1].norm_squared();
            if fp.is_nan() || fp <= 0.0 {
                break;
            }
            let next = (u - f / fp).clamp(lo, hi);
            let done = (next - u).abs() < 1e-14;
            u = next;
            if done {
                break;
            }
        }
        let dist = (point(u) - q).norm();
        if dist < best.0 {
            best = (dist, u.rem_euclid(1.0));
        }
    }
    best
}

/// The closed knot search for one number of distinct control points, as a swarm problem.
#[derive(Clone, Debug)]
pub struct ClosedProblem<'a> {
    /// The open problem on the measure data: encoding, repair, tolerance and fitness.
    pub base: KnotProblem<'a>,
    /// The closed data.
    pub data: &'a ClosedData,
}

impl<'a> ClosedProblem<'a> {
    /// The problem for `n_u` distinct control points (`n_u − 1` interior breakpoints).
    pub fn new(
        data: &'a ClosedData,
        n_u: usize,
        min_gap: f64,
        with_smoothing: bool,
        tolerance: f64,
        span_target: Option<f64>,
    ) -> Self {
        ClosedProblem {
            base: KnotProblem {
                data: &data.measure,
                encoding: KnotEncoding::new(n_u - 1, min_gap, with_smoothing),
                tolerance,
                span_target,
                fairness_cutoff: f64::INFINITY,
            },
            data,
        }
    }
}

impl CountProblem for ClosedProblem<'_> {
    fn position(&self, knots: &[f64]) -> Vec<f64> {
        self.base.position(knots)
    }

    fn decode(&self, x: &[f64]) -> Option<Vec<f64>> {
        self.base.decode(x)
    }

    fn smoothing_coord(&self) -> Option<usize> {
        self.base.smoothing_coord()
    }

    fn log_lambda(&self, x: &[f64]) -> f64 {
        self.base.encoding.log_lambda(x)
    }
}

/// Buffers of one particle of a [`ClosedProblem`].
#[derive(Clone, Debug, Default)]
pub struct ClosedParticle {
    knots: KnotWorkspace,
    eval: ClosedWorkspace,
}

impl SwarmProblem for ClosedProblem<'_> {
    type Workspace = ClosedParticle;
    type Output = CandidateEval;

    fn dim(&self) -> usize {
        self.base.dim()
    }

    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.base.bounds()
    }

    fn workspace(&self) -> ClosedParticle {
        ClosedParticle::default()
    }

    fn repair(&self, x: &mut [f64], ws: &mut ClosedParticle) {
        self.base.repair(x, &mut ws.knots);
    }

    fn evaluate(&self, x: &[f64], ws: &mut ClosedParticle) -> CandidateEval {
        if !self.base.decode_into(x, &mut ws.knots) {
            return CandidateEval::failed();
        }
        evaluate_closed(
            self.data,
            &ws.knots.interior,
            self.base.encoding.log_lambda(x),
            &mut ws.eval,
        )
    }

    fn fitness(&self, e: &CandidateEval) -> Fitness {
        self.base.fitness(e)
    }
}

#[cfg(test)]
mod tests {
    use super::{evaluate_closed, ClosedData, ClosedWorkspace};
    use crate::nurbs::{NurbsCurve, Vec3};
    use crate::optim::search::prepare::prepare;

    /// The largest distance from a point to the nearest of 40 001 curve samples equally spaced over
    /// the domain: an upper bound of the orthogonal distance, independent of the projection code.
    fn brute_force_deviation(curve: &NurbsCurve, points: &[Vec3]) -> f64 {
        let (a, b) = curve.domain();
        let n = 40_000;
        let samples: Vec<Vec3> = (0..=n)
            .map(|i| curve.point(a + (b - a) * i as f64 / n as f64))
            .collect();
        points
            .iter()
            .map(|q| {
                samples
                    .iter()
                    .map(|s| (*s - *q).norm())
                    .fold(f64::MAX, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn periodic_candidate_of_a_circle_is_close_and_fair_and_its_deviation_is_exact() {
        // 8 equal spans on a 100-point circle: the periodic cubic deviates by ~1e-5 of the diameter,
        // F ≈ 0 (a circle has dκ/ds = 0); the evaluation's deviation agrees with dense sampling
        let pts: Vec<Vec3> = (0..100)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 100.0;
                Vec3([3.0 + t.cos(), -2.0 + t.sin(), 0.0])
            })
            .collect();
        let prep = prepare(&pts, 3).unwrap();
        let d = ClosedData::new(&prep).unwrap();
        for (k, u) in d.params.iter().enumerate() {
            assert!(
                (u - k as f64 / 100.0).abs() < 1e-9,
                "equal chords, equal steps"
            );
        }
        let interior: Vec<f64> = (1..16).map(|j| j as f64 / 16.0).collect();
        let mut ws = ClosedWorkspace::default();
        let e = evaluate_closed(&d, &interior, f64::NEG_INFINITY, &mut ws);
        assert!(e.solved);
        // 16 equal spans: deviation ~2e-5 of the diameter, F ~ 21 (F of the circle is 0)
        assert!(e.max_deviation < 3e-5 && e.max_deviation > 1e-7, "{e:?}");
        assert!(e.fairness < 30.0, "{e:?}");
        assert_eq!(ws.ctrl.len(), 16 + 3);
        let c = NurbsCurve::bspline(3, ws.knots.clone(), ws.ctrl.clone()).unwrap();
        let dense = brute_force_deviation(&c, &d.points);
        assert!(dense <= e.max_deviation * 1.01, "{dense} vs {e:?}");
        assert!(dense >= e.max_deviation * 0.95, "{dense} vs {e:?}");
    }
}
