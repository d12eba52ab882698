//! Times `fit_to_tolerance` on point files (in-process, many repetitions): `cargo run --release
//! --example fit_timing -- FILE... [--rel-tol R]
//! [--correction-rounds N] [--smoothing L] [--reps N]`. Prints control points, solves, microseconds per
//! fit and a digest of the result's bits (control points, knots, deviation), to check that a change
//! keeps the fits bit for bit.

use fairfit::prelude::{fit_to_tolerance, FitOptions, Tolerance};
use std::time::Instant;

fn main() {
    let mut rel = 1e-3;
    let mut rounds = 0;
    let mut smoothing = 0.0;
    let mut reps = 50;
    let mut files = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--rel-tol" {
            rel = args.next().and_then(|s| s.parse().ok()).unwrap_or(rel);
        } else if a == "--correction-rounds" {
            rounds = args.next().and_then(|s| s.parse().ok()).unwrap_or(rounds);
        } else if a == "--smoothing" {
            smoothing = args
                .next()
                .and_then(|s| s.parse().ok())
                .unwrap_or(smoothing);
        } else if a == "--reps" {
            reps = args.next().and_then(|s| s.parse().ok()).unwrap_or(reps);
        } else {
            files.push(a);
        }
    }
    let opts = FitOptions {
        tolerance: Tolerance::Relative(rel),
        correction_rounds: rounds,
        smoothing,
        ..Default::default()
    };
    let mut total = 0.0;
    for f in &files {
        let pts = match fairfit::io::read_points(f) {
            Ok(p) => p.points,
            Err(e) => {
                println!("{f}: {e}");
                continue;
            }
        };
        let t0 = Instant::now();
        let mut last = None;
        for _ in 0..reps {
            last = Some(fit_to_tolerance(&pts, &opts));
        }
        let us = t0.elapsed().as_secs_f64() * 1e6 / reps as f64;
        total += us;
        let name = std::path::Path::new(f)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        match last {
            Some(Ok(r)) => println!(
                "{name:24} {:4} pts {:3} cp {:.3} tol {:5} solves {:8.1} us  {:016x}",
                pts.len(),
                r.n_control_points,
                r.deviation.max / r.tolerance,
                r.solves,
                us,
                digest(&r)
            ),
            Some(Err(e)) => println!("{name:24} {e}"),
            None => {}
        }
    }
    println!("total {total:.1} us");
}

/// FNV-1a over the bits of the control points, the knots and the deviation.
fn digest(r: &fairfit::fit::FitResult) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: f64| {
        for b in x.to_bits().to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for c in r.curve.control_points() {
        c.0.iter().for_each(|&v| eat(v));
    }
    r.curve.knots().iter().for_each(|&k| eat(k));
    r.deviation.per_point.iter().for_each(|&d| eat(d));
    r.deviation.params.iter().for_each(|&u| eat(u));
    h
}
