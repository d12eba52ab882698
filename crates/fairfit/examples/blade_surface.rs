//! Skins the IEA 15 MW blade sections (examples/data/iea15mw_sections) at a given tolerance and prints
//! the measures: `cargo run --release -p fairfit --example blade_surface [-- TOL]`.

use fairfit::io::sections::{expand_section_inputs, read_section_file};
use fairfit::surface::{reconstruct_surface, Section, SurfaceOptions};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let tol: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(0.0057);
    let dir =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/iea15mw_sections");
    let files = expand_section_inputs(&[dir])?;
    let sections: Vec<Section> = files
        .iter()
        .map(|f| read_section_file(f).map(Section::from_points))
        .collect::<Result<_, _>>()?;
    let mut opts = SurfaceOptions::default();
    opts.sections.tolerance = tol;
    opts.iso_curves = 11;
    let t0 = std::time::Instant::now();
    let r = reconstruct_surface(sections, &opts)?;
    let dt = t0.elapsed().as_secs_f64();
    let (nu, nv) = r.surface.net_size();
    println!(
        "tol {tol}: net {nu} x {nv}, {dt:.3} s, {} candidate knot vectors, within tolerance: {}",
        r.compatible.candidates_tried, r.compatible.within_tolerance
    );
    println!(
        "surface deviation max {:.3e} rms {:.3e} over {} points",
        r.deviation.max, r.deviation.rms, r.deviation.points
    );
    println!(
        "iso-curve F across sections (u_iso): max {:.3e} mean {:.3e}; along sections (v_iso): max {:.3e}",
        r.fairness.max_fairness_u, r.fairness.mean_fairness_u, r.fairness.max_fairness_v
    );
    for (k, f) in r.compatible.fits.iter().enumerate() {
        let cf = fairfit::fair::curve_fairness(&f.curve);
        println!(
            "  section {k}: closed {} deviation {:.3e} F {:.3e} max F_j {:.3e}",
            r.sections[k].closed, f.max_deviation, cf.fairness, cf.max_span_fairness
        );
    }
    println!("knots {:?}", r.compatible.knots);
    Ok(())
}
