//! The node rules of the fairing stages: a node is a parameter inside one knot span with its
//! basis derivatives 0..=3 precomputed, so that `C', C'', C'''` at the node cost `3 (p + 1)`
//! multiply-adds of the control points. Band fairing's fairness integral (Gauss nodes) and the
//! curvature-extrema count ([`super::extrema`]) are both rules of such nodes.
//!
//! Invariant: a node's derivatives are those of the span's own polynomial (nodes sit strictly
//! inside a span, never at a knot, where `C'''` jumps).

use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::Vec3;
use crate::optim::search::objective::{GL_W, GL_X, MAX_DEGREE};

/// A Gauss node of the fairness integral: its knot span, weight and basis derivatives 1..=3.
pub(crate) struct Node {
    pub(crate) span: usize,
    pub(crate) weight: f64,
    /// `ders[o * (p + 1) + j]`: the `o`-th derivative of `N_{span−p+j}` (o = 0..=3).
    pub(crate) ders: [f64; NDERS],
}

/// Basis derivatives 0..=3 of a degree up to [`MAX_DEGREE`].
pub(crate) const NDERS: usize = 4 * (MAX_DEGREE + 1);

/// Basis functions and derivatives up to `nd` (at most 3) at `u` in knot span `span` (degree `p`
/// at most [`MAX_DEGREE`]), laid out as [`Node::ders`]; no allocation.
pub(crate) fn basis_ders(knots: &[f64], p: usize, span: usize, u: f64, nd: usize) -> [f64; NDERS] {
    const P1: usize = MAX_DEGREE + 1;
    let p1 = p + 1;
    let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
    let (mut ndu, mut a) = ([0.0; P1 * P1], [0.0; 2 * P1]);
    let mut ders = [0.0; NDERS];
    ders_basis_funs_into(
        span,
        u,
        p,
        nd,
        knots,
        &mut left[..p1],
        &mut right[..p1],
        &mut ndu[..p1 * p1],
        &mut a[..2 * p1],
        &mut ders[..(nd + 1) * p1],
    );
    ders
}

/// `[C, C', C'', C''']` at a node from the control points (`C` itself is left zero).
#[inline]
pub(crate) fn node_derivatives(node: &Node, ctrl: &[Vec3], p: usize) -> [Vec3; 4] {
    if p == 3 {
        // the usual cubic: the same loops with a constant degree, unrolled by the compiler
        node_derivatives_any(node, ctrl, 3)
    } else {
        node_derivatives_any(node, ctrl, p)
    }
}

/// [`node_derivatives`] for any degree (always inlined so a constant `p` unrolls the loops).
#[inline(always)]
fn node_derivatives_any(node: &Node, ctrl: &[Vec3], p: usize) -> [Vec3; 4] {
    let mut d = [Vec3::ZERO; 4];
    for (o, out) in d.iter_mut().enumerate().skip(1).take(3.min(p)) {
        for j in 0..=p {
            *out += ctrl[node.span - p + j] * node.ders[o * (p + 1) + j];
        }
    }
    d
}

/// Sign changes of `dκ/ds` (values `dkds`, scaled by `l2 = L²`) with the hysteresis floor
/// `1e-6 max|dκ/ds| L² + 1e-9`.
pub(crate) fn sign_changes(dkds: &[f64], l2: f64) -> usize {
    let peak = dkds.iter().fold(0.0f64, |a, v| a.max((v * l2).abs()));
    let floor = 1e-6 * peak + 1e-9;
    let (mut state, mut extrema) = (0i8, 0usize);
    for v in dkds {
        let v = v * l2;
        let s = if v >= floor {
            1
        } else if v <= -floor {
            -1
        } else {
            continue;
        };
        if state != 0 && s != state {
            extrema += 1;
        }
        state = s;
    }
    extrema
}

/// Every knot span is integrated in this many equal parts (8 Gauss nodes each): a long span can
/// hold curvature detail that 8 nodes alone miss, and the optimisation would exploit that.
const SUBDIVISIONS: usize = 4;

/// The Gauss nodes of every non-empty knot span (as the optimiser's fairness measure).
pub(crate) fn gauss_nodes(knots: &[f64], p: usize, n: usize) -> Vec<Node> {
    let mut nodes = Vec::new();
    for s in p..n {
        let (a0, b0) = (knots[s], knots[s + 1]);
        if b0 <= a0 {
            continue;
        }
        for q in 0..SUBDIVISIONS {
            let a = a0 + (b0 - a0) * q as f64 / SUBDIVISIONS as f64;
            let b = a0 + (b0 - a0) * (q + 1) as f64 / SUBDIVISIONS as f64;
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for i in 0..8 {
                // in increasing parameter order (the extrema count walks the nodes in order)
                let (t, w) = if i < 4 {
                    (-GL_X[3 - i], GL_W[3 - i])
                } else {
                    (GL_X[i - 4], GL_W[i - 4])
                };
                let u = mid + half * t;
                nodes.push(Node {
                    span: s,
                    weight: w * half,
                    ders: basis_ders(knots, p, s, u, 3.min(p)),
                });
            }
        }
    }
    nodes
}
