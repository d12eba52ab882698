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
    if let Some(sm) = std::env::args().nth(2) {
        opts.sections.smoothing = sm.parse()?;
    }
    let t0 = std::time::Instant::now();
    let r = reconstruct_surface(sections, &opts)?;
    let dt = t0.elapsed().as_secs_f64();
    let (nu, nv) = r.surface.net_size();
    println!(
        "tol {tol}: net {nu} x {nv}, time {dt:.3} s, candidates {}",
        r.compatible.candidates_tried
    );
    println!(
        "section deviations {:?}",
        r.section_deviation
            .iter()
            .map(|d| format!("{d:.2e}"))
            .collect::<Vec<_>>()
    );
    println!(
        "surface deviation max {:.3e} rms {:.3e} over {} points",
        r.deviation.max, r.deviation.rms, r.deviation.points
    );
    println!(
        "closed {:?}",
        r.sections.iter().map(|s| s.closed).collect::<Vec<_>>()
    );
    println!("alignment {:?}", r.alignment);
    println!(
        "max span F of sections {:.3e}",
        r.compatible.max_span_fairness
    );
    println!("iso fairness {:?}", r.fairness);
    println!("knots {:?}", r.compatible.knots);
    if std::env::var("DEBUG_SEC").is_ok() {
        let c = &r.compatible.fits[0].curve;
        println!("cp {:?}", &c.control_points()[..5]);
        for u in [0.0, 0.001, 0.003, 0.005, 0.01, 0.02] {
            let d = fairfit::diffgeo::differentials(c, u);
            println!(
                "u {u} p {:?} speed {:.3e} k {:.3e} dk {:.3e}",
                d.point, d.speed, d.curvature, d.dkappa_ds
            );
        }
    }
    for f in &r.compatible.fits {
        let cf = fairfit::surface::span_fairness(&f.curve, 1);
        println!(
            "  F {:.3e} max span {:.3e} at {:?}",
            cf.total,
            cf.max_span(),
            cf.per_span.iter().position(|&x| x == cf.max_span())
        );
    }
    Ok(())
}
