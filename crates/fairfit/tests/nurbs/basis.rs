//! Properties of the B-spline basis (NURBS Book A2.2/A2.3) on random knot vectors, degrees 1..6:
//! partition of unity, non-negativity, derivative rows summing to zero, and A2.3 row 0 equal to A2.2.

use fairfit::nurbs::basis::{basis_funs, ders_basis_funs, BasisWorkspace};
use fairfit::nurbs::knots::{find_span, validate_knots};
use proptest::prelude::*;

/// Degree, sorted knot vector (random multiplicities, clamped or not) and a parameter in the domain.
fn knot_case() -> impl Strategy<Value = (usize, Vec<f64>, f64)> {
    (1usize..=6, 0usize..12, any::<bool>(), 0.0f64..=1.0).prop_flat_map(|(p, extra, clamped, t)| {
        let n = p + 1 + extra;
        let m = n + p + 1;
        let interior = if clamped { m - 2 * (p + 1) } else { m };
        (
            Just(p),
            prop::collection::vec((-3.0f64..3.0, 1usize..=3), interior.max(1)),
            Just(clamped),
            Just(n),
            Just(t),
        )
            .prop_map(move |(p, vals, clamped, n, t)| {
                let m = n + p + 1;
                let mut k: Vec<f64> = Vec::with_capacity(m);
                // repeat some values to get multiple knots
                for (v, mult) in vals {
                    for _ in 0..mult.min(p) {
                        k.push(v);
                    }
                }
                k.sort_by(f64::total_cmp);
                let need = if clamped { m - 2 * (p + 1) } else { m };
                k.truncate(need);
                while k.len() < need {
                    k.push(k.last().copied().unwrap_or(0.0) + 0.5);
                }
                if clamped {
                    let lo = k.first().copied().unwrap_or(0.0) - 1.0;
                    let hi = k.last().copied().unwrap_or(0.0) + 1.0;
                    let mut full = vec![lo; p + 1];
                    full.extend(k);
                    full.extend(std::iter::repeat_n(hi, p + 1));
                    k = full;
                }
                let (a, b) = (k[p], k[n]);
                (p, k, a + t * (b - a))
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, rng_seed: proptest::test_runner::RngSeed::Fixed(0x00FA_1AF1), ..ProptestConfig::default() })]

    #[test]
    fn partition_of_unity_and_nonnegativity((p, knots, u) in knot_case()) {
        let n = knots.len() - p - 1;
        prop_assume!(validate_knots(&knots, p, n, "test").is_ok());
        let span = find_span(n - 1, p, u, &knots);
        prop_assert!(knots[span] <= u && knots[span] < knots[span + 1]);
        let mut ws = BasisWorkspace::new(p);
        let mut basis = vec![0.0; p + 1];
        basis_funs(span, u, &knots, &mut ws, &mut basis);
        let sum: f64 = basis.iter().sum();
        prop_assert!((sum - 1.0).abs() < 1e-13, "sum {} basis {:?}", sum, basis);
        prop_assert!(basis.iter().all(|&b| b >= 0.0), "{:?}", basis);

        let nd = p + 1;
        let mut ders = vec![0.0; (nd + 1) * (p + 1)];
        ders_basis_funs(span, u, nd, &knots, &mut ws, &mut ders);
        for j in 0..=p {
            prop_assert!((ders[j] - basis[j]).abs() < 1e-14);
        }
        for k in 1..=nd {
            let row = &ders[k * (p + 1)..(k + 1) * (p + 1)];
            let size: f64 = row.iter().map(|x| x.abs()).sum();
            let s: f64 = row.iter().sum();
            prop_assert!(s.abs() <= 1e-12 * size.max(1.0), "k={} row {:?}", k, row);
            if k > p {
                prop_assert!(row.iter().all(|&x| x == 0.0));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, rng_seed: proptest::test_runner::RngSeed::Fixed(0x00FA_1AF1), ..ProptestConfig::default() })]

    /// The rational basis sums to one too: a NURBS curve whose control points all equal `q` is the
    /// point `q` everywhere, whatever its (positive) weights, degree and knots.
    #[test]
    fn rational_basis_is_a_partition_of_unity(
        (p, knots, u) in knot_case(),
        q in (-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3),
        weights in prop::collection::vec(0.05f64..20.0, 20),
    ) {
        let n = knots.len() - p - 1;
        prop_assume!(validate_knots(&knots, p, n, "test").is_ok());
        let q = fairfit::nurbs::Vec3::new(q.0, q.1, q.2);
        let w: Vec<f64> = (0..n).map(|i| weights[i % weights.len()]).collect();
        let c = fairfit::nurbs::NurbsCurve::new(p, knots, vec![q; n], Some(w)).unwrap();
        let size = q.max_abs().max(1.0);
        prop_assert!((c.point(u) - q).max_abs() <= 1e-13 * size, "{:?} vs {:?}", c.point(u), q);
    }
}
