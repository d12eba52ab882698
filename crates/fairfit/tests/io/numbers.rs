//! Every geometry writer of `fairfit::io` (STEP, IGES, JSON, samples, OBJ, PLY, STL) and the SVG plots
//! write a coordinate that is exactly `-0.0` as `0`: no `-0.`, `-0.0` or `-0.00` in any file.

use fairfit::io::iges::{curve_to_iges, surface_to_iges, IgesOptions};
use fairfit::io::mesh_write::{to_obj, to_ply, to_stl};
use fairfit::io::samples::{curve_samples_json, surface_samples_json};
use fairfit::io::step::{curve_to_step, surface_to_step, StepOptions};
use fairfit::io::tessellate::{tessellate_curve, tessellate_surface, TessellationOptions};
use fairfit::io::{curve_to_json, surface_to_json};
use fairfit::plot::curve_plots::curve_comb_svg;
use fairfit::plot::surface_plots::{iso_curvature_svg, IsoDirection};
use fairfit::plot::PlotSize;
use fairfit::{NurbsCurve, NurbsSurface, Vec3};

/// The numbers in `text` that are a negative zero (`-0`, `-0.`, `-0.0`, `-0.00`, `-0.0E0`, ...).
fn negative_zeros(text: &str) -> Vec<String> {
    text.split(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c)))
        .filter(|t| t.starts_with('-'))
        .filter(|t| t.parse::<f64>().is_ok_and(|x| x == 0.0))
        .map(str::to_string)
        .collect()
}

/// A planar quadratic in the plane z = -0.0, starting at (-0.0, -0.0, -0.0), knots from -0.0.
fn curve() -> NurbsCurve {
    NurbsCurve::bspline(
        2,
        vec![-0.0, -0.0, -0.0, 0.5, 1.0, 1.0, 1.0],
        vec![
            Vec3::new(-0.0, -0.0, -0.0),
            Vec3::new(1.0, -0.0, -0.0),
            Vec3::new(2.0, 1.0, -0.0),
            Vec3::new(3.0, -0.0, -0.0),
        ],
    )
    .unwrap()
}

/// A flat bilinear patch in z = -0.0 over [-0.0, 1]^2, one corner at (-0.0, -0.0, -0.0).
fn surface() -> NurbsSurface {
    let net = vec![
        vec![Vec3::new(-0.0, -0.0, -0.0), Vec3::new(-0.0, 1.0, -0.0)],
        vec![Vec3::new(1.0, -0.0, -0.0), Vec3::new(1.0, 1.0, -0.0)],
    ];
    let k = vec![-0.0, -0.0, 1.0, 1.0];
    NurbsSurface::new(1, 1, k.clone(), k, net, None).unwrap()
}

#[test]
fn the_helper_finds_negative_zeros_in_every_spelling() {
    let text = "(-0.,1.,-0.0) -0.00 -0.0E0 -0 0.0 -1.0 -0.5 1e-0";
    assert_eq!(
        negative_zeros(text),
        ["-0.", "-0.0", "-0.00", "-0.0E0", "-0"].map(String::from)
    );
}

#[test]
fn step_and_iges_write_zero_for_negative_zero() {
    let (c, s) = (curve(), surface());
    let step = curve_to_step(&c, &StepOptions::default()).unwrap();
    assert_eq!(negative_zeros(&step), Vec::<String>::new());
    assert!(step.contains("CARTESIAN_POINT('',(0.,0.,0.))"), "{step}");
    assert!(step.contains("CARTESIAN_POINT('',(3.,0.,0.))"), "{step}");
    assert!(
        step.contains("(0.,0.5,1.)"),
        "distinct knots from 0: {step}"
    );
    let step = surface_to_step(&s, &StepOptions::default()).unwrap();
    assert_eq!(negative_zeros(&step), Vec::<String>::new());
    assert!(step.contains("CARTESIAN_POINT('',(0.,1.,0.))"), "{step}");

    let iges = curve_to_iges(&c, &IgesOptions::default()).unwrap();
    assert_eq!(negative_zeros(&iges), Vec::<String>::new());
    // the parameter data: counts, knots, weights, control points, domain, plane normal
    let pd: String = iges
        .lines()
        .filter(|l| l.as_bytes().get(72) == Some(&b'P'))
        .map(|l| l[..64].trim_end())
        .collect();
    assert_eq!(
        pd,
        "126,3,2,1,0,1,0,0.,0.,0.,0.5,1.,1.,1.,1.,1.,1.,1.,0.,0.,0.,1.,0.,0.,2.,1.,0.,3.,0.,0.,0.,1.,0.,0.,1.;"
    );
    let iges = surface_to_iges(&s, &IgesOptions::default()).unwrap();
    assert_eq!(negative_zeros(&iges), Vec::<String>::new());
}

#[test]
fn json_and_sample_files_write_zero_for_negative_zero() {
    let (c, s) = (curve(), surface());
    for text in [
        curve_to_json(&c),
        surface_to_json(&s),
        curve_samples_json(&c, 6),
        surface_samples_json(&s, 3, 2),
    ] {
        assert_eq!(negative_zeros(&text), Vec::<String>::new(), "{text}");
    }
    let v: serde_json::Value = serde_json::from_str(&curve_to_json(&c)).unwrap();
    assert_eq!(
        v["knots"][0].as_f64().map(f64::is_sign_positive),
        Some(true)
    );
    assert_eq!(v["control_points"][0], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(v["control_points"][3], serde_json::json!([3.0, 0.0, 0.0]));
    let v: serde_json::Value = serde_json::from_str(&curve_samples_json(&c, 6)).unwrap();
    assert_eq!(v["params"][0], serde_json::json!([0.0]));
    assert_eq!(v["points"][0], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(v["points"][6], serde_json::json!([3.0, 0.0, 0.0]));
}

#[test]
fn meshes_write_zero_for_negative_zero() {
    let opts = TessellationOptions::default();
    let surface_mesh = tessellate_surface(&surface(), &opts).unwrap();
    let curve_mesh = tessellate_curve(&curve(), &opts).unwrap();
    for mesh in [&surface_mesh, &curve_mesh] {
        for text in [to_obj(mesh), to_ply(mesh)] {
            assert_eq!(negative_zeros(&text), Vec::<String>::new(), "{text}");
        }
    }
    let obj = to_obj(&surface_mesh);
    assert!(obj.contains("\nv 0.0 0.0 0.0\n"), "{obj}");
    assert!(obj.contains("\nvn 0.0 0.0 1.0\n"), "{obj}");
    // STL: every f32 written (normals and corners) has its sign bit clear or is nonzero
    let stl = to_stl(&surface_mesh).unwrap();
    let floats: Vec<f32> = stl[84..]
        .chunks(50)
        .flat_map(|f| {
            f[..48]
                .chunks(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        })
        .collect();
    assert_eq!(floats.len(), 12 * surface_mesh.triangles.len());
    assert!(floats.iter().all(|&x| x != 0.0 || x.is_sign_positive()));
}

#[test]
fn svg_plots_write_zero_for_negative_zero() {
    let size = PlotSize::new(600, 400).unwrap();
    let comb = curve_comb_svg(&curve(), None, size).unwrap();
    assert_eq!(negative_zeros(&comb), Vec::<String>::new());
    // the first iso-curve is at u = -0.0, the start of the domain
    let iso = iso_curvature_svg(&surface(), IsoDirection::FixedU, 3, size).unwrap();
    assert_eq!(negative_zeros(&iso), Vec::<String>::new());
    assert!(iso.contains(">u = 0.000<"), "{iso}");
}
