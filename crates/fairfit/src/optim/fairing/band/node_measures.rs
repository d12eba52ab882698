//! The per-node measures band fairing is built from: the Gauss–Newton residual of `F` at one node
//! and its gradient, the nodes' fairness and signals, the edge sign nodes, sign violations, the
//! data points' distances and local frames. Free functions of one curve, no subproblem state
//! ([`super::model`] assembles them into a subproblem).

use super::super::control_map::ControlMap;
use super::super::nodes::{basis_ders, node_derivatives, sign_changes, Node};

use crate::nurbs::knots::find_span;
use crate::nurbs::Vec3;
use crate::optim::search::objective::speed_and_dkappa_du;

/// Offset of the edge sign nodes from their knot, relative to the span ([`super::options::BandOptions::edge_signs`]):
/// the span's own polynomial next to the knot, never the third derivative at the knot itself.
const EDGE_OFFSET: f64 = 1e-6;

/// The edge sign nodes of [`super::options::BandOptions::edge_signs`]: two per knot span, with the weight (for the
/// residual's scale only; they are not part of `F`) and the target of the span's first and last
/// Gauss node. Empty without targets.
pub(super) fn edge_nodes(
    nodes: &[Node],
    targets: &[i8],
    knots: &[f64],
    p: usize,
) -> (Vec<Node>, Vec<i8>) {
    let (mut out, mut signs) = (Vec::new(), Vec::new());
    if targets.is_empty() {
        return (out, signs);
    }
    let mut g = 0;
    while g < nodes.len() {
        let s = nodes[g].span;
        let end = g + nodes[g..].iter().take_while(|nd| nd.span == s).count();
        let (a, b) = (knots[s], knots[s + 1]);
        for (u, k) in [
            (a + EDGE_OFFSET * (b - a), g),
            (b - EDGE_OFFSET * (b - a), end - 1),
        ] {
            if targets[k] != 0 {
                out.push(Node {
                    span: s,
                    weight: nodes[k].weight,
                    ders: basis_ders(knots, p, s, u, 3.min(p)),
                });
                signs.push(targets[k]);
            }
        }
        g = end;
    }
    (out, signs)
}

/// `(F, max_j F_j, curvature extrema)` of the curve with control points `ctrl` by the rule of
/// `nodes`; the extrema are the sign changes of `dκ/ds` at the nodes with a hysteresis floor of
/// `1e-6 max|dκ/ds| L² + 1e-9` (as the benchmark's measurer counts them on its samples).
pub(super) fn node_fairness(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
) -> (f64, f64, usize) {
    let (mut length, mut total, mut fmax) = (0.0, 0.0, 0.0f64);
    let (mut span, mut part) = (usize::MAX, 0.0);
    let mut dkds = Vec::with_capacity(nodes.len());
    for nd in nodes {
        if nd.span != span {
            fmax = fmax.max(part);
            (span, part) = (nd.span, 0.0);
        }
        let d = node_derivatives(nd, ctrl, p);
        let (v, dk) = speed_and_dkappa_du(&d, planar);
        length += nd.weight * v;
        dkds.push(if v > 0.0 { dk / v } else { 0.0 });
        if v > 0.0 {
            let e = nd.weight * dk * dk / v;
            total += e;
            part += e;
        }
    }
    fmax = fmax.max(part);
    let l3 = length * length * length;
    let f = l3 * total;
    let extrema = sign_changes(&dkds, length * length);
    if f.is_finite() {
        (f, l3 * fmax, extrema)
    } else {
        (f64::INFINITY, f64::INFINITY, usize::MAX)
    }
}

/// `(F, max_j F_j)` of [`node_fairness`] (the same sums) without the extrema count, and, when
/// `res` is not empty, the residuals of [`node_residuals`] (scale `c`) into it, from the same
/// node derivatives: the line search's measure of a trial step.
pub(super) fn node_fairness_residuals(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
    c: f64,
    res: &mut [f64],
) -> (f64, f64) {
    let (mut length, mut total, mut fmax) = (0.0, 0.0, 0.0f64);
    let (mut span, mut part) = (usize::MAX, 0.0);
    let with_res = !res.is_empty();
    for (g, nd) in nodes.iter().enumerate() {
        if nd.span != span {
            fmax = fmax.max(part);
            (span, part) = (nd.span, 0.0);
        }
        let d = node_derivatives(nd, ctrl, p);
        let (v, dk) = speed_and_dkappa_du(&d, planar);
        length += nd.weight * v;
        if v > 0.0 {
            let e = nd.weight * dk * dk / v;
            total += e;
            part += e;
        }
        if with_res {
            // as `residual` with `c_w = c w_g`
            res[g] = if v > 0.0 {
                (c * nd.weight / v).sqrt() * dk
            } else {
                0.0
            };
        }
    }
    fmax = fmax.max(part);
    let l3 = length * length * length;
    let f = l3 * total;
    if f.is_finite() {
        (f, l3 * fmax)
    } else {
        (f64::INFINITY, f64::INFINITY)
    }
}

/// Per node, `dκ/ds` (any positive scaling: here `dκ/du / |C'|`) and the curvature change
/// `w_g dκ/du` it carries: the inputs of [`super::super::curvature_signs::target_signs`].
pub(super) fn node_signals(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
) -> (Vec<f64>, Vec<f64>) {
    nodes
        .iter()
        .map(|nd| {
            let (v, dk) = speed_and_dkappa_du(&node_derivatives(nd, ctrl, p), planar);
            (if v > 0.0 { dk / v } else { 0.0 }, nd.weight * dk)
        })
        .unzip()
}

/// The Gauss–Newton residuals `r_g` (scale `c = L³ / F` of the current linearisation) into `out`.
pub(super) fn node_residuals(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
    c: f64,
    out: &mut [f64],
) {
    for (r, nd) in out.iter_mut().zip(nodes) {
        *r = residual(&node_derivatives(nd, ctrl, p), c * nd.weight, planar);
    }
}

/// `Σ max(0, m − s_g r_g)` over the nodes with a sign target.
pub(super) fn violation(res: &[f64], targets: &[i8], margin: f64) -> f64 {
    res.iter()
        .zip(targets)
        .filter(|(_, &t)| t != 0)
        .map(|(&r, &t)| (margin - f64::from(t) * r).max(0.0))
        .sum()
}

/// `∂r/∂C^(o)_k` of a node's [`residual`] by central differences in its derivatives `d` (orders
/// `1..=min(p, 3)`, coordinates `0..dims`; the other entries stay 0).
pub(super) fn residual_gradient(
    d: &[Vec3; 4],
    c_w: f64,
    planar: bool,
    p: usize,
    dims: usize,
) -> [[f64; 3]; 4] {
    let mut grad = [[0.0; 3]; 4];
    for o in 1..=3.min(p) {
        let h = 1e-6 * (d[o].norm() + 1e-3 * d[1].norm()).max(1e-300);
        for k in 0..dims {
            let mut dp = *d;
            dp[o][k] += h;
            let rp = residual(&dp, c_w, planar);
            dp[o][k] -= 2.0 * h;
            let rm = residual(&dp, c_w, planar);
            grad[o][k] = (rp - rm) / (2.0 * h);
        }
    }
    grad
}

/// Adds `scale ·` the node's residual gradient with respect to the free variables to `row`: the
/// chain rule from `grad` ([`residual_gradient`], by derivative order and coordinate) through the
/// node's basis derivatives and the control map (variable `z`, coordinate `k` at `z · dims + k`).
pub(super) fn add_node_row(
    nd: &Node,
    grad: &[[f64; 3]; 4],
    p: usize,
    dims: usize,
    map: &ControlMap,
    scale: f64,
    row: &mut [f64],
) {
    for j in 0..=p {
        let cj = nd.span - p + j;
        for k in 0..dims {
            let mut v = 0.0;
            for o in 1..=3.min(p) {
                v += grad[o][k] * nd.ders[o * (p + 1) + j];
            }
            for &(z, c) in map.row(cj) {
                row[z * dims + k] += scale * c * v;
            }
        }
    }
}

/// The residual `sqrt(c w / |C'|) dκ/du` of a node with derivatives `d`.
pub(super) fn residual(d: &[Vec3; 4], c_w: f64, planar: bool) -> f64 {
    let (v, dk) = speed_and_dkappa_du(d, planar);
    if v > 0.0 {
        (c_w / v).sqrt() * dk
    } else {
        0.0
    }
}

/// `‖C(u) − q‖` for the B-spline (`knots`, `ctrl`, degree `p`).
pub(super) fn distance_at(knots: &[f64], ctrl: &[Vec3], p: usize, u: f64, q: Vec3) -> f64 {
    let s = find_span(ctrl.len() - 1, p, u, knots);
    let basis = basis_ders(knots, p, s, u, 0);
    let mut c = -q;
    for j in 0..=p {
        c += ctrl[s - p + j] * basis[j];
    }
    c.norm()
}

/// The rows measuring a deviation `e` at a foot with tangent `tan`: the normal directions, then the
/// tangent scaled by `tangent_weight` (1: the full distance; a unit tangent of zero length falls
/// back to the coordinate axes).
pub(super) fn local_frame(tan: Vec3, planar: bool, tangent_weight: f64) -> [Vec3; 3] {
    let len = tan.norm();
    if !(len > 0.0 && len.is_finite()) {
        return [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
    }
    let t = tan / len;
    if planar {
        return [Vec3::new(-t[1], t[0], 0.0), t * tangent_weight, Vec3::ZERO];
    }
    // the coordinate axis least aligned with t, made orthogonal to it
    let mut k = 0;
    for i in 1..3 {
        if t[i].abs() < t[k].abs() {
            k = i;
        }
    }
    let mut a = Vec3::ZERO;
    a[k] = 1.0;
    let n1 = a - t * t.dot(a);
    let n1 = n1 / n1.norm();
    let n2 = t.cross(n1);
    [n1, n2, t * tangent_weight]
}
