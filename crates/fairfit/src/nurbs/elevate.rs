//! Degree elevation (NURBS Book A5.9) on homogeneous control points: Bézier decomposition, elevation
//! of each segment, and removal of the knots the decomposition added. Unclamped curves are clamped first.

use super::clamp::clamp_hom;
use super::curve::NurbsCurve;
use super::insert::{lerp, Hom};
use super::surface::binom;
use crate::errors::{Error, Result};

// the highest degree elevation produces is the limit of every curve and surface (binomial weights stay
// exact well beyond it)
use super::knots::MAX_DEGREE;

/// Raises the degree `p` of the homogeneous curve `(knots, cw)` by `t` (NURBS Book A5.9).
///
/// A line-by-line transcription of the book's index arithmetic, kept recognisable on purpose, in its
/// steps: the multiplicity check, the Bézier coefficients, and per segment the insertion to Bézier
/// form ([`insert_to_bezier`]), the elevation ([`elevate_segment`]) and the removal of the knots the
/// decomposition added ([`remove_knots`]).
#[allow(clippy::needless_range_loop, clippy::explicit_counter_loop)]
pub(crate) fn elevate_degree_hom(
    p: usize,
    knots: &[f64],
    cw: &[Hom],
    t: usize,
) -> Result<(Vec<f64>, Vec<Hom>)> {
    if t == 0 {
        return Ok((knots.to_vec(), cw.to_vec()));
    }
    if t > MAX_DEGREE.saturating_sub(p) {
        return Err(Error::KnotOperation(format!(
            "degree {p} raised by {t} exceeds the supported maximum degree {MAX_DEGREE}"
        )));
    }
    let (knots, pw) = clamp_hom(p, knots, cw)?;
    let m = knots.len() - 1;
    check_multiplicities(p, &knots)?;
    let u = &knots[..];
    let ph = p + t;
    let bezalfs = bezier_elevation_coefficients(p, t);
    let segments = 1 + (p + 1..m - p).filter(|&i| u[i] != u[i - 1]).count();
    let mut qw: Vec<Hom> = vec![[0.0; 4]; pw.len() + segments * t + 1];
    let mut uh: Vec<f64> = vec![0.0; qw.len() + ph + 2];
    let mut bpts: Vec<Hom> = pw[..=p].to_vec();
    let mut ebpts: Vec<Hom> = vec![[0.0; 4]; ph + 1];
    let mut next_bpts: Vec<Hom> = vec![[0.0; 4]; p.saturating_sub(1).max(1)];
    let mut alfs = vec![0.0; p.saturating_sub(1).max(1)];
    let mut mh = ph;
    let mut kind = ph + 1;
    let mut r: isize = -1;
    let mut a = p;
    let mut b = p + 1;
    let mut cind = 1;
    let mut ua = u[0];
    qw[0] = pw[0];
    uh[..=ph].fill(ua);
    while b < m {
        let i0 = b;
        while b < m && u[b] == u[b + 1] {
            b += 1;
        }
        let mul = b - i0 + 1;
        mh += mul + t;
        let ub = u[b];
        let oldr = r;
        r = p as isize - mul as isize;
        let lbz = if oldr > 0 { (oldr as usize + 2) / 2 } else { 1 };
        let rbz = if r > 0 {
            ph - (r as usize).div_ceil(2)
        } else {
            ph
        };
        if r > 0 {
            let span = Span { a, mul, ua, ub };
            insert_to_bezier(p, u, span, r as usize, &mut alfs, &mut bpts, &mut next_bpts);
        }
        elevate_segment(&bezalfs, p, t, lbz, &bpts, &mut ebpts);
        if oldr > 1 {
            let at = Removal {
                oldr: oldr as usize,
                kind,
                cind,
                lbz,
                ph,
                ua,
                ub,
            };
            remove_knots(at, &uh, &mut qw, &mut ebpts);
        }
        if a != p {
            let load = ph - oldr.max(0) as usize;
            uh[kind..kind + load].fill(ua);
            kind += load;
        }
        for e in &ebpts[lbz..=rbz] {
            qw[cind] = *e;
            cind += 1;
        }
        if b < m {
            let ru = r.max(0) as usize;
            bpts[..ru].copy_from_slice(&next_bpts[..ru]);
            for j in ru..=p {
                bpts[j] = pw[b - p + j];
            }
            a = b;
            b += 1;
            ua = ub;
        } else {
            uh[kind..=kind + ph].fill(ub);
        }
    }
    let nh = mh - ph - 1;
    qw.truncate(nh + 1);
    uh.truncate(nh + ph + 2);
    Ok((uh, qw))
}

/// Interior multiplicity `p + 1` (a break) is outside what A5.9 handles.
fn check_multiplicities(p: usize, knots: &[f64]) -> Result<()> {
    let m = knots.len() - 1;
    let mut i = p + 1;
    while i < m - p {
        let mult = knots[i..].iter().take_while(|&&k| k == knots[i]).count();
        if mult > p && i + mult <= m - p {
            return Err(Error::KnotOperation(format!(
                "degree elevation needs interior multiplicities <= degree {p}; knot {} has {mult}",
                knots[i]
            )));
        }
        i += mult;
    }
    Ok(())
}

/// The Bézier degree-elevation coefficients `bezalfs[i][j]` from degree `p` to `p + t`.
#[allow(clippy::needless_range_loop)] // the book's index arithmetic, as in `elevate_degree_hom`
fn bezier_elevation_coefficients(p: usize, t: usize) -> Vec<Vec<f64>> {
    let ph = p + t;
    let ph2 = ph / 2;
    let mut bezalfs = vec![vec![0.0; p + 1]; ph + 1];
    bezalfs[0][0] = 1.0;
    bezalfs[ph][p] = 1.0;
    for i in 1..=ph2 {
        let inv = 1.0 / binom(ph, i);
        for j in i.saturating_sub(t)..=p.min(i) {
            bezalfs[i][j] = inv * binom(p, j) * binom(t, i - j);
        }
    }
    for i in ph2 + 1..ph {
        for j in i.saturating_sub(t)..=p.min(i) {
            bezalfs[i][j] = bezalfs[ph - i][p - j];
        }
    }
    bezalfs
}

/// The knot span `[ua, ub]` of the segment being decomposed: `a` the index of `ua`, `mul` the
/// multiplicity of `ub`.
#[derive(Clone, Copy)]
struct Span {
    a: usize,
    mul: usize,
    ua: f64,
    ub: f64,
}

/// Inserts `ub` `r` times into the segment's control points `bpts` to make it a Bézier segment; the
/// leftover points of the next segment go to `next_bpts`.
fn insert_to_bezier(
    p: usize,
    u: &[f64],
    span: Span,
    r: usize,
    alfs: &mut [f64],
    bpts: &mut [Hom],
    next_bpts: &mut [Hom],
) {
    let Span { a, mul, ua, ub } = span;
    let numer = ub - ua;
    for k in (mul + 1..=p).rev() {
        alfs[k - mul - 1] = numer / (u[a + k] - ua);
    }
    for j in 1..=r {
        let save = r - j;
        let s = mul + j;
        for k in (s..=p).rev() {
            let al = alfs[k - s];
            bpts[k] = lerp(al, &bpts[k], 1.0 - al, &bpts[k - 1]);
        }
        next_bpts[save] = bpts[p];
    }
}

/// Degree-elevates the Bézier segment `bpts` by `t` into `ebpts` (from index `lbz` on).
fn elevate_segment(
    bezalfs: &[Vec<f64>],
    p: usize,
    t: usize,
    lbz: usize,
    bpts: &[Hom],
    ebpts: &mut [Hom],
) {
    for (i, e) in ebpts.iter_mut().enumerate().skip(lbz) {
        let mut acc = [0.0; 4];
        for j in i.saturating_sub(t)..=p.min(i) {
            acc = lerp(1.0, &acc, bezalfs[i][j], &bpts[j]);
        }
        *e = acc;
    }
}

/// Where the knot `ua` is removed `oldr − 1` times after the elevation: the positions `kind` (in
/// the new knots `uh`) and `cind` (in the new control points), the first elevated point kept
/// (`lbz`), the new degree `ph` and the span `[ua, ub]`.
#[derive(Clone, Copy)]
struct Removal {
    oldr: usize,
    kind: usize,
    cind: usize,
    lbz: usize,
    ph: usize,
    ua: f64,
    ub: f64,
}

/// Removes the knot `ua` that the Bézier decomposition inserted (NURBS Book A5.9, the knot-removal
/// part), updating the control points `qw` written so far and the elevated segment `ebpts`.
#[allow(clippy::explicit_counter_loop)] // the book's index arithmetic, as in `elevate_degree_hom`
fn remove_knots(at: Removal, uh: &[f64], qw: &mut [Hom], ebpts: &mut [Hom]) {
    let Removal {
        oldr,
        kind,
        cind,
        lbz,
        ph,
        ua,
        ub,
    } = at;
    let mut first = kind - 2;
    let mut last = kind;
    let den = ub - ua;
    let bet = (ub - uh[kind - 1]) / den;
    for tr in 1..oldr {
        let (mut i, mut j) = (first, last);
        let mut kj = j - kind + 1;
        while j - i > tr {
            if i < cind {
                let alf = (ub - uh[i]) / (ua - uh[i]);
                qw[i] = lerp(alf, &qw[i], 1.0 - alf, &qw[i - 1]);
            }
            if j >= lbz {
                if j - tr <= kind - ph + oldr {
                    let gam = (ub - uh[j - tr]) / den;
                    ebpts[kj] = lerp(gam, &ebpts[kj], 1.0 - gam, &ebpts[kj + 1]);
                } else {
                    ebpts[kj] = lerp(bet, &ebpts[kj], 1.0 - bet, &ebpts[kj + 1]);
                }
            }
            i += 1;
            j -= 1;
            kj = kj.wrapping_sub(1);
        }
        first -= 1;
        last += 1;
    }
}

impl NurbsCurve {
    /// The same curve with its degree raised by `t` (NURBS Book A5.9); the geometry is unchanged,
    /// rational curves included. Unclamped curves are clamped first; interior knots of multiplicity
    /// `p + 1` (breaks) are rejected.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let c = NurbsCurve::circle(Vec3::ZERO, 1.5).unwrap();
    /// let cubic = c.elevate_degree(1).unwrap();
    /// assert_eq!(cubic.degree(), 3);
    /// for i in 0..=20 {
    ///     let u = i as f64 / 20.0;
    ///     assert!((cubic.point(u).norm() - 1.5).abs() < 1e-13);
    /// }
    /// ```
    pub fn elevate_degree(&self, t: usize) -> Result<NurbsCurve> {
        let (knots, cw) =
            elevate_degree_hom(self.degree(), self.knots(), self.homogeneous_points(), t)?;
        super::insert::try_from_hom_parts(self.degree() + t, knots, &cw, self.is_rational())
    }
}
