//! Skinning compatible section curves into a tensor-product surface (NURBS Book §10.3): v parameters of
//! the sections by averaged chord or centripetal lengths over the control-point columns, v knots by
//! averaging (eq. 9.8), interpolation of every control column in homogeneous coordinates (weights must
//! stay positive); or, for many or noisy sections, least-squares approximation of the columns with a
//! bending (smoothing) term and fewer v control points. Optionally `∂S/∂v` along the first and last
//! sections is held parallel to given directions ([`super::skin_ends`]).

use super::linalg::{lu_solve, Dense};
use super::section_fit::lsq_control_points_held;
use super::skin_ends::{
    column_speed, doubled_ends, homogeneous_derivative, leg_factor, unit_direction,
};
use crate::errors::{Error, Result};
use crate::nurbs::basis::basis_funs_into;
use crate::nurbs::knots::{find_span, is_clamped};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};

/// How the sections' v parameters are chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum VParams {
    /// Averaged chord lengths of the control columns.
    ChordLength,
    /// Averaged square roots of the chord lengths (centripetal).
    Centripetal,
    /// Given parameters, one per section, increasing from 0 to 1.
    Given(Vec<f64>),
}

/// Options of [`skin`].
#[derive(Clone, Debug)]
pub struct SkinOptions {
    /// Degree in v; lowered to `sections - 1` when there are too few sections.
    pub degree_v: usize,
    /// Parameterisation of the sections in v.
    pub params: VParams,
    /// `None` interpolates every section; `Some(n)` approximates with `n` control points in v.
    pub approximate_with: Option<usize>,
    /// Bending weight of the approximation (relative to the data term); unused for interpolation.
    pub smoothing: f64,
    /// A direction (X, Y, Z, any non-zero length) for `∂S/∂v` along the whole first section (`v = 0`,
    /// pointing towards increasing v): `None` leaves the end free. The magnitude is the method's
    /// ([`super::skin_ends`]); interpolation gains one control point per column, approximation holds
    /// two and needs a degree in v of at least 2.
    pub start_tangent_v: Option<Vec3>,
    /// The same along the last section (`v = 1`).
    pub end_tangent_v: Option<Vec3>,
}

impl Default for SkinOptions {
    fn default() -> Self {
        SkinOptions {
            degree_v: 3,
            params: VParams::ChordLength,
            approximate_with: None,
            smoothing: 0.0,
            start_tangent_v: None,
            end_tangent_v: None,
        }
    }
}

/// A skinned surface and the v parameter of each section on it.
#[derive(Clone, Debug)]
pub struct Skin {
    /// The surface: u along the sections, v across them.
    pub surface: NurbsSurface,
    /// `S(u, v_params[k])` is section `k` (exactly when interpolating).
    pub v_params: Vec<f64>,
    /// With v end tangents: the magnitude of `∂S/∂v` at the constrained ends (the mean polygon length
    /// of the control columns, [`super::skin_ends`]); `None` without.
    pub v_tangent_speed: Option<f64>,
}

/// The asked v end tangents, as unit vectors, and the magnitude of the end derivatives.
struct Ends {
    start: Option<Vec3>,
    end: Option<Vec3>,
    speed: f64,
}

impl Ends {
    fn count(&self) -> usize {
        usize::from(self.start.is_some()) + usize::from(self.end.is_some())
    }

    /// End derivatives need a degree in v of at least 2 (at degree 1 the leg is the whole span).
    fn check_degree(&self, q: usize) -> Result<()> {
        if self.count() > 0 && q < 2 {
            return Err(Error::InvalidOption(format!(
                "v end tangents need a degree in v of at least 2, got {q}"
            )));
        }
        Ok(())
    }

    /// The held leading and trailing control points of a column for approximation: the end points,
    /// and the leg points of the asked tangents on the knots `kv` of degree `q`.
    #[allow(clippy::type_complexity)]
    fn held(&self, col: &[[f64; 4]], kv: &[f64], q: usize) -> (Vec<[f64; 4]>, Vec<[f64; 4]>) {
        let (first, last) = (col[0], col[col.len() - 1]);
        let leg = |end: &[f64; 4], d: Vec3, at_start: bool, sign: f64| {
            let f = sign * leg_factor(kv, q, at_start);
            let dv = homogeneous_derivative(end, self.speed, d);
            [
                end[0] + f * dv[0],
                end[1] + f * dv[1],
                end[2] + f * dv[2],
                end[3] + f * dv[3],
            ]
        };
        let mut front = vec![first];
        front.extend(self.start.map(|d| leg(&first, d, true, 1.0)));
        let mut back: Vec<[f64; 4]> = self
            .end
            .map(|d| leg(&last, d, false, -1.0))
            .into_iter()
            .collect();
        back.push(last);
        (front, back)
    }
}

fn averaged_params(cols: &[Vec<[f64; 4]>], centripetal: bool) -> Result<Vec<f64>> {
    let k1 = cols[0].len();
    let mut v = vec![0.0; k1];
    let mut used = 0usize;
    for col in cols {
        let d: Vec<f64> = col
            .windows(2)
            .map(|w| {
                let a = Vec3::new(w[0][0] / w[0][3], w[0][1] / w[0][3], w[0][2] / w[0][3]);
                let b = Vec3::new(w[1][0] / w[1][3], w[1][1] / w[1][3], w[1][2] / w[1][3]);
                let l = a.distance(b);
                if centripetal {
                    l.sqrt()
                } else {
                    l
                }
            })
            .collect();
        let total: f64 = d.iter().sum();
        if total.is_nan() || total <= 0.0 || !total.is_finite() {
            continue;
        }
        used += 1;
        let mut acc = 0.0;
        for (k, dk) in d.iter().enumerate() {
            acc += dk;
            v[k + 1] += acc / total;
        }
    }
    if used == 0 {
        return Err(Error::InvalidData(
            "all sections coincide: no distance between them to parameterise".into(),
        ));
    }
    for x in v.iter_mut() {
        *x /= used as f64;
    }
    v[k1 - 1] = 1.0;
    Ok(v)
}

/// The number of trailing control columns that repeat the leading ones of a periodic u knot vector
/// (`p` when the knots are unclamped and the columns wrap, else 0).
fn periodic_copies(knots: &[f64], p: usize, cols: &[Vec<[f64; 4]>]) -> usize {
    let n = cols.len();
    if is_clamped(knots, p) || n < 2 * p + 1 || (0..p).any(|i| cols[i] != cols[n - p + i]) {
        0
    } else {
        p
    }
}

/// Knot vector by averaging the parameters (NURBS Book eq. 9.8), for interpolation.
pub fn averaging_knots(params: &[f64], degree: usize) -> Vec<f64> {
    let n = params.len() - 1;
    let mut k = vec![0.0; degree + 1];
    for j in 1..=n.saturating_sub(degree) {
        let s: f64 = params[j..j + degree].iter().sum();
        k.push(s / degree as f64);
    }
    k.extend(std::iter::repeat_n(1.0, degree + 1));
    k
}

/// Knot vector for least-squares approximation with `n_ctrl` control points (NURBS Book eq. 9.69).
pub(crate) fn approximation_knots(params: &[f64], degree: usize, n_ctrl: usize) -> Vec<f64> {
    let m = params.len() - 1;
    let n = n_ctrl - 1;
    let d = (m + 1) as f64 / (n - degree + 1) as f64;
    let mut k = vec![0.0; degree + 1];
    for j in 1..=n - degree {
        let i = (j as f64 * d).floor() as usize;
        let a = j as f64 * d - i as f64;
        let i = i.clamp(1, m);
        k.push((1.0 - a) * params[i - 1] + a * params[i]);
    }
    k.extend(std::iter::repeat_n(1.0, degree + 1));
    k
}

/// Skins compatible `sections` (same degree and knot vector) into a surface.
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::surface::{skin, SkinOptions};
/// let knots = vec![0.0, 0.0, 1.0, 1.0];
/// let sec = |z: f64, s: f64| NurbsCurve::bspline(1, knots.clone(),
///     vec![Vec3::new(0.0, 0.0, z), Vec3::new(s, 0.0, z)]).unwrap();
/// let sections = vec![sec(0.0, 1.0), sec(1.0, 2.0), sec(2.0, 1.5)];
/// let sk = skin(&sections, &SkinOptions::default()).unwrap();
/// // the surface passes through every section at its v parameter
/// let p = sk.surface.point(1.0, sk.v_params[1]);
/// assert!((p - Vec3::new(2.0, 0.0, 1.0)).norm() < 1e-12);
/// ```
pub fn skin(sections: &[NurbsCurve], opts: &SkinOptions) -> Result<Skin> {
    let k1 = sections.len();
    if k1 < 2 {
        return Err(Error::InvalidData(format!(
            "skinning needs at least 2 sections, got {k1}"
        )));
    }
    let first = &sections[0];
    for (k, s) in sections.iter().enumerate() {
        if s.degree() != first.degree() || s.knots() != first.knots() {
            return Err(Error::InvalidData(format!(
                "section {k} is not compatible with section 0 (degree or knot vector differ)"
            )));
        }
    }
    if opts.degree_v == 0 {
        return Err(Error::InvalidOption(
            "degree in v must be at least 1".into(),
        ));
    }
    if !(opts.smoothing.is_finite() && opts.smoothing >= 0.0) {
        return Err(Error::InvalidOption(format!(
            "the smoothing across the sections must be finite and >= 0, got {}",
            opts.smoothing
        )));
    }
    let n_u = first.n_control_points();
    // columns: cols[i][k] = homogeneous control point i of section k
    let cols: Vec<Vec<[f64; 4]>> = (0..n_u)
        .map(|i| sections.iter().map(|s| s.homogeneous_points()[i]).collect())
        .collect();
    // periodic sections: the last p columns repeat the first; each distinct column counts once and
    // the copies are copied, so the surface stays periodic (C^(p−1)) across the u seam
    let copies = periodic_copies(first.knots(), first.degree(), &cols);
    let distinct = &cols[..n_u - copies];
    let v_params = match &opts.params {
        VParams::ChordLength => averaged_params(distinct, false)?,
        VParams::Centripetal => averaged_params(distinct, true)?,
        VParams::Given(v) => {
            if v.len() != k1 {
                return Err(Error::InvalidOption(format!(
                    "{} v parameters given for {k1} sections",
                    v.len()
                )));
            }
            v.clone()
        }
    };
    if v_params.windows(2).any(|w| w[1].is_nan() || w[1] <= w[0])
        || v_params[0] != 0.0
        || v_params[k1 - 1] != 1.0
    {
        return Err(Error::InvalidData(
            "section v parameters must increase strictly from 0 to 1 (two sections coincide?)"
                .into(),
        ));
    }
    let start = opts
        .start_tangent_v
        .map(|d| unit_direction(d, "the v tangent at the first section"))
        .transpose()?;
    let end = opts
        .end_tangent_v
        .map(|d| unit_direction(d, "the v tangent at the last section"))
        .transpose()?;
    // the magnitude is only measured (and can only fail) when a tangent is asked
    let speed = if start.is_some() || end.is_some() {
        column_speed(distinct)?
    } else {
        0.0
    };
    let ends = Ends { start, end, speed };
    let (q, knots_v, net_cw) = match opts.approximate_with {
        Some(n_v) if n_v < k1 => approximate(distinct, &v_params, opts, n_v, &ends)?,
        _ => interpolate(distinct, &v_params, opts.degree_v, &ends)?,
    };
    let mut net_cw = net_cw;
    for i in 0..copies {
        net_cw.push(net_cw[i].clone());
    }
    let mut pts = Vec::with_capacity(n_u);
    let mut wts = Vec::with_capacity(n_u);
    let mut rational = false;
    for row in &net_cw {
        let mut pr = Vec::with_capacity(row.len());
        let mut wr = Vec::with_capacity(row.len());
        for c in row {
            let w = c[3];
            if w.is_nan() || w <= 0.0 || !w.is_finite() {
                return Err(Error::Fit(format!(
                    "skinning produced a non-positive weight {w}: the sections' weights vary too much"
                )));
            }
            if (w - 1.0).abs() > 1e-14 {
                rational = true;
            }
            pr.push(Vec3::new(c[0] / w, c[1] / w, c[2] / w));
            wr.push(w);
        }
        pts.push(pr);
        wts.push(wr);
    }
    let surface = NurbsSurface::new(
        first.degree(),
        q,
        first.knots().to_vec(),
        knots_v,
        pts,
        if rational { Some(wts) } else { None },
    )?;
    Ok(Skin {
        surface,
        v_params,
        v_tangent_speed: (ends.count() > 0).then_some(ends.speed),
    })
}

/// Homogeneous control columns with their degree and knots: `(q, knots_v, columns)`.
type Columns = (usize, Vec<f64>, Vec<Vec<[f64; 4]>>);

/// Least-squares approximation of every column with `n_v` control points (knots by eq. 9.69), the end
/// points held, and with v end tangents the leg points too.
fn approximate(
    distinct: &[Vec<[f64; 4]>],
    v_params: &[f64],
    opts: &SkinOptions,
    n_v: usize,
    ends: &Ends,
) -> Result<Columns> {
    let q = opts.degree_v.min(n_v.saturating_sub(1)).max(1);
    if n_v < 2 {
        return Err(Error::InvalidOption(
            "approximation in v needs at least 2 control points".into(),
        ));
    }
    ends.check_degree(q)?;
    if n_v < 2 + ends.count() {
        return Err(Error::InvalidOption(format!(
            "approximation in v with {} v end tangent(s) needs at least {} control points, got {n_v}",
            ends.count(),
            2 + ends.count()
        )));
    }
    let kv = approximation_knots(v_params, q, n_v);
    let mut net = Vec::with_capacity(distinct.len());
    for col in distinct {
        let (front, back) = ends.held(col, &kv, q);
        net.push(lsq_control_points_held(
            col,
            v_params,
            q,
            &kv,
            opts.smoothing,
            &front,
            &back,
        )?);
    }
    Ok((q, kv, net))
}

/// Interpolation of every column through its sections (NURBS Book eq. 9.8 knots), with one more
/// control point and equation per asked v end tangent (eq. 9.21; knots by eq. 9.8 of the parameters
/// with the constrained ends doubled, eq. 9.22).
fn interpolate(
    distinct: &[Vec<[f64; 4]>],
    v_params: &[f64],
    degree_v: usize,
    ends: &Ends,
) -> Result<Columns> {
    let k1 = v_params.len();
    let (s, e) = (ends.start.is_some(), ends.end.is_some());
    let n = k1 + ends.count();
    let q = degree_v.min(n - 1);
    ends.check_degree(q)?;
    let kv = averaging_knots(&doubled_ends(v_params, s, e), q);
    // rows: section 0, start leg, inner sections, end leg, last section (eq. 9.21)
    let row_of = |k: usize| k + usize::from(s && k > 0) + usize::from(e && k + 1 == k1);
    let mut a = Dense::zeros(n);
    let (mut left, mut right, mut nb) = (vec![0.0; q + 1], vec![0.0; q + 1], vec![0.0; q + 1]);
    for (k, &v) in v_params.iter().enumerate() {
        let span = find_span(n - 1, q, v, &kv);
        basis_funs_into(span, v, q, &kv, &mut left, &mut right, &mut nb);
        for (j, &b) in nb.iter().enumerate() {
            *a.at(row_of(k), span - q + j) = b;
        }
    }
    if s {
        *a.at(1, 0) = -1.0;
        *a.at(1, 1) = 1.0;
    }
    if e {
        *a.at(n - 2, n - 2) = -1.0;
        *a.at(n - 2, n - 1) = 1.0;
    }
    let mut net = Vec::with_capacity(distinct.len());
    for col in distinct {
        let mut m = a.clone();
        let mut b = vec![[0.0; 4]; n];
        for (k, c) in col.iter().enumerate() {
            b[row_of(k)] = *c;
        }
        if let Some(d) = ends.start {
            let f = leg_factor(&kv, q, true);
            b[1] = homogeneous_derivative(&col[0], ends.speed, d).map(|x| f * x);
        }
        if let Some(d) = ends.end {
            let f = leg_factor(&kv, q, false);
            b[n - 2] = homogeneous_derivative(&col[k1 - 1], ends.speed, d).map(|x| f * x);
        }
        lu_solve(&mut m, &mut b)?;
        net.push(b);
    }
    Ok((q, kv, net))
}
