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
/// A line-by-line transcription of the book's index arithmetic, kept recognisable on purpose.
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
    // interior multiplicity p + 1 (a break) is outside what A5.9 handles
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
    let u = &knots[..];
    let ph = p + t;
    let ph2 = ph / 2;
    // Bézier degree elevation coefficients bezalfs[i][j]
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
            let ru = r as usize;
            let numer = ub - ua;
            for k in (mul + 1..=p).rev() {
                alfs[k - mul - 1] = numer / (u[a + k] - ua);
            }
            for j in 1..=ru {
                let save = ru - j;
                let s = mul + j;
                for k in (s..=p).rev() {
                    let al = alfs[k - s];
                    bpts[k] = lerp(al, &bpts[k], 1.0 - al, &bpts[k - 1]);
                }
                next_bpts[save] = bpts[p];
            }
        }
        for (i, e) in ebpts.iter_mut().enumerate().skip(lbz) {
            let mut acc = [0.0; 4];
            for j in i.saturating_sub(t)..=p.min(i) {
                acc = lerp(1.0, &acc, bezalfs[i][j], &bpts[j]);
            }
            *e = acc;
        }
        if oldr > 1 {
            let oldr = oldr as usize;
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
