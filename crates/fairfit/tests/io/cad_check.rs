//! STEP and IGES files checked without a CAD kernel: structure (cad_check) and the numbers they hold
//! (read back from the text and compared bit for bit with the geometry written).

use fairfit::io::cad_check::{check_iges, check_step};
use fairfit::io::iges::{curve_to_iges, surface_to_iges, IgesOptions};
use fairfit::io::step::{curve_to_step, surface_to_step, StepOptions};
use fairfit::io::LengthUnit;
use fairfit::{NurbsCurve, NurbsSurface, Vec3};

fn rational_curve() -> NurbsCurve {
    // Quarter circle (exact rational quadratic) followed by a cubic-ish tail, degree 2, 5 points.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let pts = vec![
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.5),
        Vec3::new(-1.0, 0.0, 1.0),
    ];
    let knots = vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0];
    NurbsCurve::new(2, knots, pts, Some(vec![1.0, s, 1.0, 0.8, 1.0])).unwrap()
}

fn bicubic() -> NurbsSurface {
    let ku = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
    let kv = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let net = (0..5)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64 * 10.0, j as f64 * 7.0);
                    Vec3::new(x, y, 0.01 * x * y - 0.02 * x * x / 3.0)
                })
                .collect()
        })
        .collect();
    let w = (0..5)
        .map(|i| (0..4).map(|j| 1.0 + 0.25 * ((i * j) % 3) as f64).collect())
        .collect();
    NurbsSurface::new(3, 3, ku, kv, net, Some(w)).unwrap()
}

#[test]
fn step_curve_file_is_well_formed_and_holds_the_curve() {
    let c = rational_curve();
    let text = curve_to_step(&c, &StepOptions::default()).unwrap();
    let summary = check_step(&text).unwrap();
    assert_eq!(summary.entities.get("GEOMETRIC_CURVE_SET"), Some(&1));
    assert_eq!(summary.entities.get("PRODUCT_DEFINITION"), Some(&1));
    assert!(text.contains("SI_UNIT(.MILLI.,.METRE.)"));
    assert!(text.contains("B_SPLINE_CURVE_WITH_KNOTS((3,2,3),(0.,0.5,1.),.UNSPECIFIED.)"));
    assert!(text.contains("RATIONAL_B_SPLINE_CURVE((1.,0.7071067811865476,1.,0.8,1.))"));
    assert!(text.contains("CARTESIAN_POINT('',(-1.,1.,0.5))"));
    let metres = StepOptions {
        unit: LengthUnit::Metre,
        ..StepOptions::default()
    };
    assert!(curve_to_step(&c, &metres)
        .unwrap()
        .contains("SI_UNIT($,.METRE.)"));
}

#[test]
fn step_surface_file_is_one_bounded_face() {
    let s = bicubic();
    let text = surface_to_step(&s, &StepOptions::default()).unwrap();
    let e = check_step(&text).unwrap().entities;
    assert_eq!(e.get("ADVANCED_FACE"), Some(&1));
    assert_eq!(e.get("EDGE_CURVE"), Some(&4));
    assert_eq!(e.get("VERTEX_POINT"), Some(&4));
    assert_eq!(e.get("MANIFOLD_SURFACE_SHAPE_REPRESENTATION"), Some(&1));
    assert!(text
        .contains("B_SPLINE_SURFACE_WITH_KNOTS((4,1,4),(4,4),(0.,0.4,1.),(0.,1.),.UNSPECIFIED.)"));
}

#[test]
fn step_checker_catches_broken_files() {
    let text = curve_to_step(&rational_curve(), &StepOptions::default()).unwrap();
    assert!(check_step(&text.replacen("(#", "(#999", 1)).is_err());
    assert!(check_step(&text.replacen("B_SPLINE_CURVE(2,(", "B_SPLINE_CURVE(2,", 1)).is_err());
    assert!(check_step(&text.replace("ENDSEC;\nEND", "END")).is_err());
}

fn numbers(params: &str) -> Vec<f64> {
    params
        .trim_end_matches(';')
        .split(',')
        .filter(|t| !t.contains('H'))
        .map(|t| t.parse::<f64>().unwrap())
        .collect()
}

#[test]
fn iges_curve_file_is_well_formed_and_holds_the_curve() {
    let c = rational_curve();
    let text = curve_to_iges(&c, &IgesOptions::default()).unwrap();
    let summary = check_iges(&text).unwrap();
    assert_eq!(summary.entity_types, vec![126]);
    let v = numbers(&summary.parameters[0]);
    // 126, K=4, M=2, planar=0, closed=0, polynomial=0, periodic=0, then 8 knots, 5 weights, 15 coords.
    assert_eq!(&v[..7], &[126.0, 4.0, 2.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(&v[7..15], c.knots());
    assert_eq!(&v[15..20], c.weights());
    assert_eq!(&v[20..23], &c.control_points()[0].0);
    assert_eq!(&v[32..35], &c.control_points()[4].0);
    assert_eq!(&v[35..37], &[0.0, 1.0]);
    assert_eq!(v.len(), 40);
    let global: String = text
        .lines()
        .filter(|l| &l[72..73] == "G")
        .map(|l| &l[..72])
        .collect();
    assert!(global.starts_with("1H,,1H;,"), "{global}");
    assert!(global.contains(",2,2HMM,"), "unit flag mm: {global}");
}

#[test]
fn iges_surface_orders_the_net_u_fastest() {
    let s = bicubic();
    let text = surface_to_iges(&s, &IgesOptions::default()).unwrap();
    let summary = check_iges(&text).unwrap();
    assert_eq!(summary.entity_types, vec![128]);
    assert!(summary.counts[3] > 5, "multi-line parameter data");
    let v = numbers(&summary.parameters[0]);
    assert_eq!(
        &v[..10],
        &[128.0, 4.0, 3.0, 3.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    );
    let (nk_u, nk_v) = (s.knots_u().len(), s.knots_v().len());
    let w0 = 10 + nk_u + nk_v;
    assert_eq!(v[w0 + 1], s.weight(1, 0));
    assert_eq!(v[w0 + 5], s.weight(0, 1));
    let p0 = w0 + 20;
    assert_eq!(&v[p0 + 3..p0 + 6], &s.control_point(1, 0).0);
    assert_eq!(&v[p0 + 15..p0 + 18], &s.control_point(0, 1).0);
    assert_eq!(v.len(), p0 + 60 + 4);
}

#[test]
fn iges_checker_catches_broken_files() {
    let text = curve_to_iges(&rational_curve(), &IgesOptions::default()).unwrap();
    let short: String = text.lines().map(|l| format!("{}\n", &l[..79])).collect();
    assert!(check_iges(&short).is_err());
    let no_term: String = text
        .lines()
        .filter(|l| !l.ends_with("T      1"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(check_iges(&no_term).is_err());
}

#[test]
fn bad_geometry_is_refused_before_writing() {
    let dir = tempfile_dir("bad");
    let path = dir.join("c.step");
    let pts = (0..4).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
    // A full-multiplicity interior knot: a valid (discontinuous) B-spline, but not exportable.
    let c = NurbsCurve::bspline(1, vec![0.0, 0.0, 0.5, 0.5, 1.0, 1.0], pts).unwrap();
    let e = fairfit::io::step::write_curve_step(&path, &c, &StepOptions::default()).unwrap_err();
    assert!(e.to_string().contains("multiplicity 2"), "{e}");
    assert!(!path.exists());
    let unwritable = dir.join("missing").join("c.igs");
    let e = fairfit::io::iges::write_curve_iges(
        &unwritable,
        &rational_curve(),
        &IgesOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("c.igs"), "{e}");
    assert!(!unwritable.exists());
    let _ = std::fs::remove_dir_all(dir);
}

fn tempfile_dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("fairfit-cad-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn long_and_non_ascii_names_keep_the_files_valid() {
    let name = format!("{}é'\\.igs", "very_long_file_name_".repeat(10));
    let iges = curve_to_iges(
        &rational_curve(),
        &IgesOptions {
            name: name.clone(),
            ..IgesOptions::default()
        },
    )
    .unwrap();
    check_iges(&iges).unwrap();
    let step = surface_to_step(
        &bicubic(),
        &StepOptions {
            name,
            ..StepOptions::default()
        },
    )
    .unwrap();
    check_step(&step).unwrap();
    assert!(step.is_ascii());
}

/// A periodic bicubic ring (8 distinct rows, the last 3 of 11 repeating the first), linear in v.
fn periodic_ring() -> NurbsSurface {
    let breaks: Vec<f64> = (0..=8).map(|i| i as f64 / 8.0).collect();
    let ku = fairfit::fit::lsq::periodic_knots(&breaks, 3);
    let net = (0..11)
        .map(|i| {
            let t = std::f64::consts::TAU * (i % 8) as f64 / 8.0;
            (0..2)
                .map(|j| Vec3::new(3.0 * t.cos(), 2.0 * t.sin(), 5.0 * j as f64))
                .collect()
        })
        .collect();
    NurbsSurface::new(3, 1, ku, vec![0.0, 0.0, 1.0, 1.0], net, None).unwrap()
}

#[test]
fn closed_and_periodic_surfaces_are_flagged() {
    let s = periodic_ring();
    assert!(s.is_periodic_u() && !s.is_periodic_v());
    assert!(!bicubic().is_periodic_u());
    // IGES 128: PROP1 closed in u, PROP2 closed in v, PROP3 polynomial, PROP4 / PROP5 periodic
    let summary = check_iges(&surface_to_iges(&s, &IgesOptions::default()).unwrap()).unwrap();
    let v = numbers(&summary.parameters[0]);
    assert_eq!(
        &v[..10],
        &[128.0, 10.0, 1.0, 3.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0]
    );
    // STEP: u_closed .T., one seam edge shared by both u ends (3 edges, 2 vertices)
    let text = surface_to_step(&s, &StepOptions::default()).unwrap();
    let e = check_step(&text).unwrap().entities;
    assert_eq!(e.get("EDGE_CURVE"), Some(&3));
    assert_eq!(e.get("VERTEX_POINT"), Some(&2));
    assert!(text.contains(",.UNSPECIFIED.,.T.,.F.,.F.,"), "{text}");
    let open = surface_to_step(&bicubic(), &StepOptions::default()).unwrap();
    assert!(open.contains(",.UNSPECIFIED.,.F.,.F.,.F.)"));
}
