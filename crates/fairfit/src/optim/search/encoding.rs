//! The decision vector of the knot search: interior knots encoded so that every particle is a valid
//! knot vector.
//!
//! A particle holds `k + 1` unconstrained coordinates `x_0..x_k` for the `k` interior knots of a
//! clamped knot vector on `[0, 1]`, optionally followed by one coordinate `log10 λ` (the smoothing
//! weight of the least-squares solve). The knot gaps are a softmax of `x` with a minimum spacing `δ`:
//!
//! `g_i = δ + (1 − (k+1) δ) · exp(x_i) / Σ_l exp(x_l)`, `t_j = Σ_{i<j} g_i`,
//!
//! so the gaps are positive, sum to 1, and the interior knots are strictly increasing whatever `x`
//! is. [`KnotEncoding::repair`] then enforces the Schoenberg–Whitney condition used by the
//! least-squares solve (every knot span holds at least one interior data parameter) by moving knots
//! to the midpoint between data parameters, and [`KnotEncoding::encode`] maps the repaired knots back
//! onto the particle, so the particle's position is the feasible point that was evaluated.

/// Encoding of `k` interior knots (plus an optional smoothing coordinate) as a particle position.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotEncoding {
    /// Number of interior knots.
    pub interior: usize,
    /// Minimum knot gap δ (as a fraction of the domain `[0, 1]`).
    pub min_gap: f64,
    /// Whether a `log10 λ` coordinate follows the knot coordinates.
    pub with_smoothing: bool,
}

/// Bounds of the log-gap coordinates: wide enough for gaps from ~1e-5 to ~1 of the domain.
pub(crate) const GAP_COORD_BOUND: f64 = 6.0;
/// Bounds of the `log10 λ` coordinate; values below [`LOG_LAMBDA_OFF`] mean no smoothing at all.
pub(crate) const LOG_LAMBDA_RANGE: (f64, f64) = (-20.0, -4.0);
/// `log10 λ` at or below which the smoothing term is switched off (λ = 0).
pub const LOG_LAMBDA_OFF: f64 = -19.0;

impl KnotEncoding {
    /// An encoding of `interior` knots with minimum gap `min_gap` (clamped so `(k+1) δ < 0.5`).
    pub fn new(interior: usize, min_gap: f64, with_smoothing: bool) -> Self {
        let cap = 0.5 / (interior as f64 + 1.0);
        KnotEncoding {
            interior,
            min_gap: min_gap.clamp(0.0, cap),
            with_smoothing,
        }
    }

    /// Length of the particle position.
    pub fn dim(&self) -> usize {
        self.interior + 1 + usize::from(self.with_smoothing)
    }

    /// Lower and upper bounds of every coordinate.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lo = vec![-GAP_COORD_BOUND; self.interior + 1];
        let mut hi = vec![GAP_COORD_BOUND; self.interior + 1];
        if self.with_smoothing {
            lo.push(LOG_LAMBDA_RANGE.0);
            hi.push(LOG_LAMBDA_RANGE.1);
        }
        (lo, hi)
    }

    /// The interior knots of position `x`, written into `knots` (length `interior`).
    pub fn decode(&self, x: &[f64], knots: &mut [f64]) {
        let k = self.interior;
        let g = &x[..=k];
        let mx = g.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let sum: f64 = g.iter().map(|&v| (v - mx).exp()).sum();
        let free = 1.0 - (k as f64 + 1.0) * self.min_gap;
        let mut t = 0.0;
        for j in 0..k {
            t += self.min_gap + free * (g[j] - mx).exp() / sum;
            knots[j] = t;
        }
    }

    /// The `log10 λ` coordinate of `x` (the lower bound, i.e. almost no smoothing, when absent).
    pub fn log_lambda(&self, x: &[f64]) -> f64 {
        if self.with_smoothing {
            x[self.interior + 1]
        } else {
            f64::NEG_INFINITY
        }
    }

    /// Writes the position of strictly increasing interior knots in `(0, 1)` into `x[..=k]`
    /// (the smoothing coordinate is left alone). Gaps below the minimum map to the lower bound.
    pub fn encode(&self, knots: &[f64], x: &mut [f64]) {
        let k = self.interior;
        let free = 1.0 - (k as f64 + 1.0) * self.min_gap;
        let mut prev = 0.0;
        let mut mean = 0.0;
        for j in 0..=k {
            let next = if j < k { knots[j] } else { 1.0 };
            let share = ((next - prev - self.min_gap) / free).max(1e-12);
            x[j] = share.ln();
            mean += x[j];
            prev = next;
        }
        // softmax is shift invariant: centre the coordinates so they stay inside the bounds
        mean /= k as f64 + 1.0;
        for v in &mut x[..=k] {
            *v = (*v - mean).clamp(-GAP_COORD_BOUND, GAP_COORD_BOUND);
        }
    }

    /// Moves interior knots so every span `[t_j, t_{j+1})` of `0 = t_0 < t_1 < .. < t_k < t_{k+1} = 1`
    /// holds at least one of the interior data parameters `params[1..m]` (sorted, in `(0, 1)`).
    ///
    /// Returns false when there are fewer interior parameters than spans (no repair possible).
    pub fn repair(&self, knots: &mut [f64], params: &[f64]) -> bool {
        let k = self.interior;
        if params.len() < 2 {
            return k == 0;
        }
        let inner = &params[1..params.len() - 1];
        if inner.len() < k + 1 {
            return false;
        }
        let n_in = inner.len();
        let mut lower = 0.0;
        let mut idx = 0usize;
        for j in 0..k {
            // first parameter of span j
            while idx + 1 < n_in && inner[idx] < lower {
                idx += 1;
            }
            // span j must hold inner[idx]
            if knots[j] <= inner[idx] {
                knots[j] = 0.5 * (inner[idx] + inner[idx + 1]);
            }
            // spans j+1..=k need k - j parameters at or above the knot
            let up = n_in - (k - j);
            if knots[j] > inner[up] {
                knots[j] = 0.5 * (inner[up - 1] + inner[up]);
            }
            lower = knots[j];
        }
        knots.windows(2).all(|w| w[0] < w[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count_per_span(knots: &[f64], params: &[f64]) -> Vec<usize> {
        let inner = &params[1..params.len() - 1];
        let mut edges = vec![0.0];
        edges.extend_from_slice(knots);
        edges.push(1.0 + 1e-15);
        edges
            .windows(2)
            .map(|w| inner.iter().filter(|&&u| u >= w[0] && u < w[1]).count())
            .collect()
    }

    #[test]
    fn decode_encode_round_trip_and_monotone() {
        let enc = KnotEncoding::new(5, 1e-3, false);
        let knots = [0.1, 0.15, 0.4, 0.41, 0.9];
        let mut x = vec![0.0; enc.dim()];
        enc.encode(&knots, &mut x);
        let mut back = [0.0; 5];
        enc.decode(&x, &mut back);
        for (a, b) in knots.iter().zip(&back) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
        // any position decodes to strictly increasing knots with gaps >= δ
        let x = [5.9, -6.0, -6.0, 3.0, -6.0, 0.0];
        enc.decode(&x, &mut back);
        let mut prev = 0.0;
        for &t in back.iter().chain([1.0].iter()) {
            assert!(t - prev >= 1e-3 - 1e-15, "gap {}", t - prev);
            prev = t;
        }
    }

    #[test]
    fn repair_gives_every_span_a_parameter() {
        // clustered parameters: 30 uniform in (0,1) plus dense ends
        let mut params: Vec<f64> = (0..=30).map(|i| i as f64 / 30.0).collect();
        params.sort_by(f64::total_cmp);
        let enc = KnotEncoding::new(8, 1e-4, false);
        // all knots crammed into one data interval
        let mut knots: Vec<f64> = (0..8).map(|i| 0.5 + 1e-4 * i as f64).collect();
        assert!(enc.repair(&mut knots, &params));
        let counts = count_per_span(&knots, &params);
        assert!(counts.iter().all(|&c| c >= 1), "{counts:?} {knots:?}");
        assert!(knots.windows(2).all(|w| w[0] < w[1]));
        // knots at the far end
        let mut knots: Vec<f64> = (0..8).map(|i| 0.99 + 1e-3 * i as f64).collect();
        assert!(enc.repair(&mut knots, &params));
        let counts = count_per_span(&knots, &params);
        assert!(counts.iter().all(|&c| c >= 1), "{counts:?} {knots:?}");
        // too many knots for the data
        let enc = KnotEncoding::new(40, 1e-4, false);
        let mut knots: Vec<f64> = (0..40).map(|i| (i + 1) as f64 / 41.0).collect();
        assert!(!enc.repair(&mut knots, &params));
    }
}
