//! The second-order cone's Jordan algebra and Nesterov–Todd scaling for [`super::cone_ipm`], on
//! cones of a fixed dimension `D` (`[f64; D]`: `u₀` the scalar part, `u₁` the rest), and a small
//! dense Cholesky factorisation.
//!
//! The cone is `Q = {u : u₀ ≥ ‖u₁‖}`, its identity `e = (1, 0, …)`, `J = diag(1, −1, …)`. For
//! interior `s`, `z` the NT scaling is `W = η (2 v vᵀ − J)` with `W z = W⁻¹ s` (Vandenberghe,
//! "The CVXOPT linear and quadratic cone program solvers", 2010, §4).

#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[inline]
pub(crate) fn arr<const D: usize>(s: &[f64]) -> &[f64; D] {
    s.try_into().expect("a cone block")
}

#[inline]
pub(crate) fn arr_mut<const D: usize>(s: &mut [f64]) -> &mut [f64; D] {
    s.try_into().expect("a cone block")
}

/// `s₀² − ‖s₁‖²`.
#[inline]
pub(crate) fn jnorm2<const D: usize>(s: &[f64; D]) -> f64 {
    let mut t = 0.0;
    for i in 1..D {
        t += s[i] * s[i];
    }
    s[0] * s[0] - t
}

/// `W⁻¹ x` (`INV`) or `W x` for the NT scaling `W = η (2 v vᵀ − J)` of one cone.
#[inline]
pub(crate) fn scale_cone<const D: usize, const INV: bool>(
    eta: f64,
    v: &[f64; D],
    x: &[f64; D],
    out: &mut [f64; D],
) {
    if INV {
        let mut a = v[0] * x[0];
        for i in 1..D {
            a -= v[i] * x[i];
        }
        let e = 1.0 / eta;
        out[0] = (2.0 * v[0] * a - x[0]) * e;
        for i in 1..D {
            out[i] = (x[i] - 2.0 * v[i] * a) * e;
        }
    } else {
        let mut a = 0.0;
        for i in 0..D {
            a += v[i] * x[i];
        }
        out[0] = eta * (2.0 * v[0] * a - x[0]);
        for i in 1..D {
            out[i] = eta * (2.0 * v[i] * a + x[i]);
        }
    }
}

/// The NT scaling of one cone at interior `s`, `z`: `η`, and `v` into `v`; `None` when not
/// interior.
pub(crate) fn nt_scaling<const D: usize>(
    s: &[f64; D],
    z: &[f64; D],
    v: &mut [f64; D],
) -> Option<f64> {
    let (a, b) = (jnorm2(s), jnorm2(z));
    if !(a > 0.0 && b > 0.0 && s[0] > 0.0 && z[0] > 0.0) {
        return None;
    }
    let (a, b) = (a.sqrt(), b.sqrt());
    let mut sz = 0.0;
    for i in 0..D {
        sz += s[i] * z[i];
    }
    let gamma = ((1.0 + sz / (a * b)) / 2.0).sqrt();
    let w0 = (s[0] / a + z[0] / b) / (2.0 * gamma);
    let c = (2.0 * (w0 + 1.0)).sqrt();
    v[0] = (w0 + 1.0) / c;
    for i in 1..D {
        v[i] = (s[i] / a - z[i] / b) / (2.0 * gamma * c);
    }
    Some((a / b).sqrt())
}

/// Jordan product `u ∘ w` of one cone.
#[inline]
pub(crate) fn jprod<const D: usize>(u: &[f64; D], w: &[f64; D], out: &mut [f64; D]) {
    let mut t = 0.0;
    for i in 0..D {
        t += u[i] * w[i];
    }
    out[0] = t;
    for i in 1..D {
        out[i] = u[0] * w[i] + w[0] * u[i];
    }
}

/// `x` with `l ∘ x = d` (one cone, `l` interior).
#[inline]
pub(crate) fn jdiv<const D: usize>(l: &[f64; D], d: &[f64; D], out: &mut [f64; D]) {
    let mut t = l[0] * d[0];
    for i in 1..D {
        t -= l[i] * d[i];
    }
    let x0 = t / jnorm2(l);
    out[0] = x0;
    for i in 1..D {
        out[i] = (d[i] - x0 * l[i]) / l[0];
    }
}

/// Largest `α` (possibly `∞`) with `u + α du` in the cone (`u` interior).
pub(crate) fn cone_step<const D: usize>(u: &[f64; D], du: &[f64; D]) -> f64 {
    let c = jnorm2(u);
    let mut b = u[0] * du[0];
    for i in 1..D {
        b -= u[i] * du[i];
    }
    let a = jnorm2(du);
    let mut best = f64::INFINITY;
    if du[0] < 0.0 {
        best = -u[0] / du[0];
    }
    // roots of a α² + 2 b α + c
    if a == 0.0 {
        if b < 0.0 {
            best = best.min(-c / (2.0 * b));
        }
    } else {
        let disc = b * b - a * c;
        if disc >= 0.0 {
            let qq = if b >= 0.0 {
                -(b + disc.sqrt())
            } else {
                -b + disc.sqrt()
            };
            for r in [qq / a, if qq != 0.0 { c / qq } else { f64::INFINITY }] {
                if r > 0.0 {
                    best = best.min(r);
                }
            }
        }
    }
    best
}

/// In-place Cholesky factor (lower, row-major) of the symmetric `n × n` matrix `a`; `false`
/// when it is not positive definite. `first[i]` receives the first non-zero column of row `i`
/// (its envelope; `i` for an empty row): the factor has the same envelope, entries left of it
/// stay the zeros of `a`, and only the envelope is computed. The values are those of the plain
/// dense algorithm: the products it adds left of the envelope are zeros (a zero entry times a
/// finite one), and adding them to a sum of zeros before the first non-zero product changes
/// nothing but possibly the sign of an all-zero sum.
pub(crate) fn cholesky(a: &mut [f64], n: usize, first: &mut Vec<usize>) -> bool {
    first.clear();
    first.extend((0..n).map(|i| {
        a[i * n..i * n + i]
            .iter()
            .position(|&v| v != 0.0)
            .unwrap_or(i)
    }));
    for j in 0..n {
        let fj = first[j];
        let rj = &a[j * n + fj..j * n + j];
        let d = a[j * n + j] - dot(rj, rj);
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let fi = first[i];
            if fi > j {
                continue;
            }
            let k0 = fi.max(fj);
            let (lo, hi) = a.split_at_mut(i * n);
            let rj = &lo[j * n + k0..j * n + j];
            let ri = &mut hi[..=j];
            ri[j] = (ri[j] - dot(&ri[k0..j], rj)) / d;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place (`l` and its envelope `first` from [`cholesky`]).
pub(crate) fn chol_solve(l: &[f64], n: usize, first: &[usize], x: &mut [f64]) {
    for i in 0..n {
        let fi = first[i];
        let v = x[i] - dot(&l[i * n + fi..i * n + i], &x[fi..i]);
        x[i] = v / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut v = x[i];
        for k in i + 1..n {
            if first[k] <= i {
                v -= l[k * n + i] * x[k];
            }
        }
        x[i] = v / l[i * n + i];
    }
}
