//! `fairfit surface`: a fair NURBS surface through section files, or through a mesh / point cloud sliced
//! into planar sections; writes the surface JSON and optionally a report of its measures.

use super::curve_args::OutliersArg;
use super::files::{check_outputs, commit, Inputs, Output};
use super::outputs::{check_output_formats, prepare_outputs, OutputArgs, OutputGeometry};
use super::{CliError, CmdResult};
use clap::{Args, ValueEnum};
use fairfit::fit::screening::OutlierMode;
use fairfit::io::mesh_read::read_mesh;
use fairfit::io::sections::{expand_section_inputs, read_section_file, SECTION_EXTENSIONS};
use fairfit::io::surface_to_json;
use fairfit::report::surface::{surface_report, SectionNotes};
use fairfit::surface::cad_skin::{skin_to_exact, ExactSection, ExactSkin};
use fairfit::surface::chain::Gap;
use fairfit::surface::orient::extent;
use fairfit::surface::slicing::{slice_mesh, SliceOptions};
use fairfit::surface::{
    reconstruct_surface_with_progress, Section, Stage, SurfaceOptions, SurfaceReconstruction,
    VParams,
};
use fairfit::{Tolerance, Vec3};
use std::path::PathBuf;

pub use fairfit::io::limits::DEFAULT_MAX_SECTIONS;

/// Axis perpendicular to the slicing planes.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Axis {
    /// Planes x = const.
    X,
    /// Planes y = const.
    Y,
    /// Planes z = const.
    Z,
}

/// Section parameterisation across the sections (v direction).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum VParam {
    /// Averaged chord lengths of the control columns.
    Chord,
    /// Averaged centripetal (square-root) lengths.
    Centripetal,
}

/// Order of section files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Order {
    /// By file name (folders are expanded in name order; listed files keep the order given).
    Name,
    /// By the position of each section's centroid along --axis (or --normal).
    Axis,
}

/// Arguments of `fairfit surface`.
#[derive(Args, Debug)]
pub struct SurfaceArgs {
    /// Section files or folders (all .csv/.txt/.dat/.xyz files, sorted by name); or one STEP/IGES file
    /// (its B-spline curves in file order, or one B-spline surface to re-fair); with --slices, one mesh
    /// or point cloud (.ply, .stl, .obj, .xyz, .csv).
    #[arg(required = true)]
    pub input: Vec<PathBuf>,
    /// Absolute tolerance: largest allowed distance of a section point from the surface.
    #[arg(long, conflicts_with = "rel_tol", allow_hyphen_values = true,
          value_parser = super::finite_positive)]
    pub tol: Option<f64>,
    /// Relative tolerance: R times the largest bounding-box extent of the largest section [default: 1e-3].
    #[arg(long, allow_hyphen_values = true, value_parser = super::finite_positive)]
    pub rel_tol: Option<f64>,
    /// Output surface JSON.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Slice a mesh or point cloud into this many planar sections.
    #[arg(long, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub slices: Option<usize>,
    /// Axis perpendicular to the slicing planes (and the stacking axis for --order axis).
    #[arg(long, value_enum, default_value = "z")]
    pub axis: Axis,
    /// Order of section files: by name (a CAD file's curves: file order), or by position along --axis
    /// / --normal.
    #[arg(long, value_enum, default_value = "name")]
    pub order: Order,
    /// Slicing (or stacking) plane normal "nx,ny,nz" (overrides --axis).
    #[arg(long)]
    pub normal: Option<String>,
    /// Degree of the section curves (u).
    #[arg(long, default_value_t = 3, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub degree: usize,
    /// Degree across the sections (v); lowered to sections - 1 when there are few sections.
    #[arg(long, default_value_t = 3, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub degree_v: usize,
    /// Largest number of control points per section, at least --degree + 1 (the search stops at the
    /// fewest that meet the tolerance; 120 lets the sliced Stanford bunny meet 1e-3 of its extent).
    #[arg(long, default_value_t = 120, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub max_ctrl: usize,
    /// Most sections a surface is fitted through (section files, the curves of a STEP/IGES file, or
    /// --slices planes); more are refused with one line, since the fit's work grows with the count.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_SECTIONS, value_parser = super::whole_number)]
    pub max_sections: usize,
    /// Parameterisation of the sections across the surface.
    #[arg(long, value_enum, default_value = "chord")]
    pub v_params: VParam,
    /// Approximate across the sections with this many control points (for many or noisy sections)
    /// instead of interpolating every section.
    #[arg(long, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub approximate_v: Option<usize>,
    /// Smoothing weight of the approximation across the sections (relative to the data term).
    #[arg(long, default_value_t = 1e-3, allow_hyphen_values = true,
          value_parser = super::finite_non_negative)]
    pub smooth_v: f64,
    /// Direction X,Y,Z of the surface's derivative across the sections (∂S/∂v) along the whole first
    /// section, pointing towards the next one; only the direction counts (the magnitude is the mean
    /// length of the control columns). Interpolation gains one control point across the sections,
    /// --approximate-v holds two. Needs --degree-v 2 or more. The report's `v_end_tangents` gives the
    /// largest angle reached.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_direction, allow_hyphen_values = true)]
    pub start_tangent_v: Option<Vec3>,
    /// Direction X,Y,Z of ∂S/∂v along the whole last section (pointing away from the previous one), as
    /// --start-tangent-v.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_direction, allow_hyphen_values = true)]
    pub end_tangent_v: Option<Vec3>,
    /// Fit closed sections clamped, with a C0 edge at their aligned seam, even when they are smooth
    /// there (by default smooth closed sections are fitted and skinned periodically in u: no crease).
    #[arg(long)]
    pub clamped_seam: bool,
    /// Keep open sections open. By default a section file whose last point lies within the
    /// tolerance (and a few of its own spacings) of its first, and which continues smoothly through
    /// that gap, is fitted as a closed section, as `fairfit curve` closes such data (the report's
    /// per-section `closed_by_gap`).
    #[arg(long)]
    pub open_sections: bool,
    /// Turning angle (degrees) above which a section point is a corner, judged at the tolerance's
    /// scale (as `fairfit curve --corner-angle`): at a seam it keeps the seam C0; inside the
    /// sections, when every section has the same number of them, they are held as C0 knot lines
    /// shared by all sections (the report's `corners`).
    #[arg(long, value_name = "DEG", default_value_t = fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG,
          value_parser = super::corner_angle, allow_hyphen_values = true)]
    pub corner_angle: f64,
    /// Do not hold inner corners of the sections as C0 knot lines: they are smoothed over like any
    /// other point.
    #[arg(long)]
    pub no_corners: bool,
    /// Airfoil sections: pin every section's leading edge (the point farthest from the midpoint of its
    /// first and last points, the trailing edge) to the parameter 0.5 on its curve, as `fairfit curve
    /// --split-at-le` does, without a knot there: each section curve passes through its leading edge
    /// at u = 0.5 and the surface's iso-curve u = 0.5 is the leading edge (the report's
    /// `split_at_le`). A section whose leading edge is an end point is refused.
    #[arg(long)]
    pub split_at_le: bool,
    /// A chain edge longer than this many median spacings is reported as a gap (slicing). A point
    /// cloud's section is opened at its largest gap only when that gap is over 3 times the next
    /// longest edge; otherwise every gap is bridged and the section stays closed.
    #[arg(long, default_value_t = 5.0, allow_hyphen_values = true,
          value_parser = super::finite_positive)]
    pub gap_factor: f64,
    /// Spikes of dense sections (as `fairfit curve --outliers`): `auto` excludes isolated points
    /// farther than 4 tolerances (and 8 noise σ) from the curve of their neighbours on both sides and
    /// lists them per section in the report (`dense.sections[].outliers`); `off` keeps every point,
    /// and a surface that misses the tolerance names the spikes of each section that keep it out of
    /// reach. Sparse sections are never screened.
    #[arg(long, value_enum, default_value_t = OutliersArg::Auto)]
    pub outliers: OutliersArg,
    /// Worker threads (0 = all cores; capped at 4 per core; the output does not depend on it).
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub threads: usize,
    /// Write a JSON report of the measures here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// A STEP/IGES input: its B-spline curves are the sections (--entity curve), or the v-iso-curves of
    /// its B-spline surface are (--entity surface, --index; the default when it holds one).
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// CAD, mesh, plot and HTML outputs.
    #[command(flatten)]
    pub outputs: OutputArgs,
}

fn parse_normal(s: &str) -> Result<Vec3, CliError> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            CliError::usage(format!(
                "--normal must be three numbers \"nx,ny,nz\", got `{s}`"
            ))
        })?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(CliError::usage(format!(
            "--normal must be three numbers \"nx,ny,nz\", got `{s}`"
        )));
    }
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// clap value parser: a direction `X,Y,Z`, three finite numbers not all zero.
fn parse_direction(s: &str) -> Result<Vec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected three numbers X,Y,Z: {e}"))?;
    let [x, y, z] = v[..] else {
        return Err(format!(
            "expected three numbers X,Y,Z, got {} values",
            v.len()
        ));
    };
    let d = Vec3::new(x, y, z);
    if !d.is_finite() {
        return Err("expected finite numbers X,Y,Z".into());
    }
    if d.norm() <= 0.0 {
        return Err("the direction must be a non-zero vector".into());
    }
    Ok(d)
}

/// Refuses counts no surface can have (before any file is read): fewer control points per section
/// than a degree-p section needs (p + 1; the fit had lifted such a --max-ctrl silently), fewer than 2
/// control points across the sections (2 plus one per v end tangent with `--approximate-v`), v end
/// tangents with `--degree-v` below 2, fewer than 2 slicing planes.
fn check_counts(args: &SurfaceArgs) -> Result<(), CliError> {
    let need = args.degree.saturating_add(1);
    if args.degree >= 1 && args.max_ctrl < need {
        return Err(CliError::usage(format!(
            "--max-ctrl {} is below the {need} control points a degree-{} section needs; give --max-ctrl {need} or more",
            args.max_ctrl, args.degree
        )));
    }
    if let Some(n) = args.approximate_v.filter(|&n| n < 2) {
        return Err(CliError::usage(format!(
            "--approximate-v {n}: approximation across the sections needs at least 2 control points"
        )));
    }
    let tangents =
        usize::from(args.start_tangent_v.is_some()) + usize::from(args.end_tangent_v.is_some());
    if tangents > 0 && args.degree_v < 2 {
        return Err(CliError::usage(format!(
            "--start-tangent-v / --end-tangent-v need --degree-v 2 or more, got {}",
            args.degree_v
        )));
    }
    if let Some(n) = args
        .approximate_v
        .filter(|&n| tangents > 0 && n < 2 + tangents)
    {
        return Err(CliError::usage(format!(
            "--approximate-v {n}: with {tangents} v end tangent(s) it needs at least {} control points",
            2 + tangents
        )));
    }
    if args.slices.is_some_and(|n| n < 2) {
        return Err(CliError::usage(format!(
            "--slices {}: a surface needs at least 2 slices (slicing planes)",
            args.slices.unwrap_or(0)
        )));
    }
    if let Some(n) = args.slices.filter(|&n| n > args.max_sections) {
        return Err(CliError::usage(format!(
            "--slices {n} is above the limit of {} sections; raise it with --max-sections",
            args.max_sections
        )));
    }
    Ok(())
}

/// Refuses more sections than `--max-sections` (read from files, a CAD file's curves or slices).
fn check_section_count(args: &SurfaceArgs, sections: &[Section]) -> Result<(), CliError> {
    if sections.len() > args.max_sections {
        return Err(CliError::new(format!(
            "{} sections are above the limit of {}; raise it with --max-sections",
            sections.len(),
            args.max_sections
        )));
    }
    Ok(())
}

fn is_mesh(p: &std::path::Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "ply" | "stl" | "obj"))
}

struct Input {
    sections: Vec<Section>,
    names: Vec<String>,
    gaps: Vec<Gap>,
    empty_planes: Vec<f64>,
    dropped_chains: Vec<usize>,
    /// A CAD input's exact section curves, in the order of `sections`.
    exact: Option<Vec<ExactSection>>,
}

/// The slicing / stacking direction from --normal or --axis.
fn stacking_normal(args: &SurfaceArgs) -> Result<Vec3, CliError> {
    Ok(match &args.normal {
        Some(s) => parse_normal(s)?,
        None => match args.axis {
            Axis::X => Vec3::new(1.0, 0.0, 0.0),
            Axis::Y => Vec3::new(0.0, 1.0, 0.0),
            Axis::Z => Vec3::new(0.0, 0.0, 1.0),
        },
    })
}

fn read_input(args: &SurfaceArgs) -> Result<Input, CliError> {
    if let Some(n) = args.slices {
        if args.input.len() != 1 {
            return Err(CliError::usage(
                "--slices takes exactly one mesh or point-cloud file",
            ));
        }
        args.cad.check_not_cad(&args.input[0])?;
        let normal = stacking_normal(args)?;
        let mesh = read_mesh(&args.input[0])?;
        let opts = SliceOptions {
            slices: n,
            normal,
            gap_factor: args.gap_factor,
            tolerance: Some(match (args.tol, args.rel_tol) {
                (Some(t), _) => Tolerance::Absolute(t),
                (None, r) => Tolerance::Relative(r.unwrap_or(1e-3)),
            }),
            ..Default::default()
        };
        let s = slice_mesh(&mesh, &opts)?;
        if s.sections.len() < 2 {
            return Err(CliError::new(format!(
                "slicing gave {} usable section(s) from {n} planes ({} empty); a surface needs at least 2",
                s.sections.len(),
                s.empty_planes.len()
            )));
        }
        return Ok(Input {
            names: s
                .offsets
                .iter()
                .map(|h| format!("plane at {h:.6}"))
                .collect(),
            sections: s.sections,
            gaps: s.gaps,
            empty_planes: s.empty_planes,
            dropped_chains: s.dropped_chains,
            exact: None,
        });
    }
    if args.input.len() == 1 && is_mesh(&args.input[0]) {
        return Err(CliError::usage(format!(
            "{} is a mesh: give --slices N to cut it into sections",
            args.input[0].display()
        )));
    }
    let (mut sections, mut names, mut exact) =
        match super::cad_input::read_cad_sections(&args.input, &args.cad)? {
            Some((s, n, e)) => (s, n, Some(e)),
            None => {
                let (s, n) = read_section_files(&args.input)?;
                (s, n, None)
            }
        };
    if args.order == Order::Axis {
        let n = stacking_normal(args)?;
        if n.norm() <= 0.0 {
            return Err(CliError::usage("--normal must be a non-zero vector"));
        }
        let mut keyed: Vec<(f64, usize)> = sections
            .iter()
            .enumerate()
            .map(|(k, s)| (s.centroid().dot(n), k))
            .collect();
        // stable: sections at the same position keep their name order
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
        let order: Vec<usize> = keyed.into_iter().map(|(_, k)| k).collect();
        sections = order.iter().map(|&k| sections[k].clone()).collect();
        names = order.iter().map(|&k| names[k].clone()).collect();
        exact = exact.map(|e| order.iter().map(|&k| e[k].clone()).collect());
    }
    if sections.len() < 2 {
        return Err(CliError::new(format!(
            "a surface needs at least 2 sections, got {}",
            sections.len()
        )));
    }
    Ok(Input {
        names,
        dropped_chains: vec![0; sections.len()],
        sections,
        gaps: Vec::new(),
        empty_planes: Vec::new(),
        exact,
    })
}

/// The sections of section files and folders, with the file names.
fn read_section_files(input: &[PathBuf]) -> Result<(Vec<Section>, Vec<String>), CliError> {
    let files = expand_section_inputs(input)?;
    let mut sections = Vec::with_capacity(files.len());
    for f in &files {
        let pts = read_section_file(f)?;
        if pts.len() < 3 {
            return Err(CliError::new(format!(
                "{}: a section needs at least 3 points, got {}",
                f.display(),
                pts.len()
            )));
        }
        sections.push(Section::from_points(pts));
    }
    Ok((
        sections,
        files.iter().map(|f| f.display().to_string()).collect(),
    ))
}

/// Runs `fairfit surface`: the arguments and outputs checked before any file is read, the input read
/// into sections, the tolerance and options set, the surface reconstructed, its files written all or
/// none, and the one-line summary.
pub fn run(args: SurfaceArgs) -> CmdResult {
    let outputs = checked_outputs(&args)?;
    check_arguments(&args)?;
    let Input {
        sections,
        names,
        gaps,
        empty_planes,
        dropped_chains,
        exact,
    } = read_input(&args)?;
    check_section_count(&args, &sections)?;
    if args.split_at_le {
        check_leading_edges(&sections, &names)?;
    }
    let tol = tolerance(&args, &sections)?;
    let opts = surface_options(&args, tol);
    let spikes = spike_notes(&args, &sections, tol);
    let (r, exact) = reconstruct(&args, sections, exact, &opts)?;
    check_measures(&r)?;
    if let Some(e) = &exact {
        note_exact(&args.input[0], e);
    }
    let notes = SectionNotes {
        names,
        gaps,
        empty_planes,
        dropped_chains,
    };
    let gap_count = notes.gaps.len();
    let files = output_files(&args, &r, tol, notes, exact.as_ref())?;
    let summary_on_stdout = !outputs.iter().any(|(_, p)| super::files::is_stdout(p));
    commit(files)?;
    if let Some(w) = r.dense.as_ref().and_then(|d| d.noise_warning(tol)) {
        diag!("{w}");
    }
    let tol = r.tolerance_used(tol);
    let within = r.deviation.max <= tol && exact.as_ref().is_none_or(|e| e.met);
    if !within {
        for note in &spikes {
            diag!("warning: {note}");
        }
    }
    summarise(&r, tol, within, gap_count, summary_on_stdout)
}

/// `--split-at-le`: every section has a leading edge (the point farthest from the midpoint of its
/// first and last points is not an end point; orientation and seam alignment do not change that for
/// an open section, and a closed one always has one), else a one-line error naming its file.
fn check_leading_edges(sections: &[Section], names: &[String]) -> CmdResult {
    for (k, s) in sections.iter().enumerate() {
        if fairfit::fit::airfoil::leading_edge(&s.points).is_none() {
            let name = names
                .get(k)
                .map_or_else(|| format!("section {k}"), Clone::clone);
            return Err(CliError::new(format!(
                "{name} (section {k}): no leading edge to split at: the point farthest from the \
                 trailing edge (the midpoint of its first and last points) is an end point"
            )));
        }
    }
    Ok(())
}

/// With `--outliers off`: per section, the isolated spikes that would keep tolerance `tol` out of
/// reach, as sentences naming the section (by its input order) and the option that excludes them;
/// none with `auto` (the fit excludes them itself).
fn spike_notes(args: &SurfaceArgs, sections: &[Section], tol: f64) -> Vec<String> {
    if args.outliers != OutliersArg::Off {
        return Vec::new();
    }
    sections
        .iter()
        .enumerate()
        .filter_map(|(k, s)| {
            fairfit::fit::screening::spikes_note(&s.points, tol)
                .map(|n| format!("section {k}: {n}; --outliers auto excludes them"))
        })
        .collect()
}

/// Every output named (`-o`, `--report`, CAD/mesh/plot/HTML), refused when it names an input or
/// another output, or has a format it cannot be written in.
fn checked_outputs(args: &SurfaceArgs) -> Result<Vec<(&'static str, &std::path::Path)>, CliError> {
    let mut outputs = vec![("-o", args.output.as_path())];
    outputs.extend(args.report.as_deref().map(|p| ("--report", p)));
    outputs.extend(args.outputs.named());
    let inputs = Inputs {
        paths: args.input.iter().map(|p| p.as_path()).collect(),
        folder_reads: &SECTION_EXTENSIONS,
    };
    check_outputs(&outputs, &[], &inputs)?;
    check_output_formats(&outputs)?;
    Ok(outputs)
}

/// The usage errors found before any file is read: `--slices` on a CAD file, a zero `--normal`, and
/// counts no surface can have ([`check_counts`]).
fn check_arguments(args: &SurfaceArgs) -> Result<(), CliError> {
    if args.slices.is_some() {
        if let Some(p) = args
            .input
            .iter()
            .find(|p| fairfit::io::cad_read::CadFormat::from_path(p).is_some())
        {
            return Err(CliError::usage(format!(
                "--slices takes a mesh or point cloud (.ply, .stl, .obj, .xyz, .csv), and {} is a \
                 STEP/IGES file; drop --slices to take its curves as sections",
                p.display()
            )));
        }
    }
    if stacking_normal(args)?.norm() <= 0.0 {
        return Err(CliError::usage("--normal must be a non-zero vector"));
    }
    check_counts(args)
}

/// The absolute tolerance: `--tol`, or `--rel-tol` (default 1e-3) times the largest section's extent.
fn tolerance(args: &SurfaceArgs, sections: &[Section]) -> Result<f64, CliError> {
    let largest = sections
        .iter()
        .map(|s| extent(&s.points))
        .fold(0.0, f64::max);
    let tol = match (args.tol, args.rel_tol) {
        (Some(t), _) => t,
        (None, r) => r.unwrap_or(1e-3) * largest,
    };
    if !tol.is_finite() || tol <= 0.0 {
        return Err(CliError::usage(format!(
            "the tolerance must be positive, got {tol}"
        )));
    }
    Ok(tol)
}

/// The library's surface options from the arguments and the tolerance.
fn surface_options(args: &SurfaceArgs, tol: f64) -> SurfaceOptions {
    let mut opts = SurfaceOptions::default();
    opts.sections.degree = args.degree;
    opts.sections.tolerance = tol;
    opts.sections.max_control_points = args.max_ctrl;
    opts.sections.periodic_closed = !args.clamped_seam;
    opts.sections.corner_angle_deg = args.corner_angle;
    opts.sections.hold_corners = !args.no_corners;
    opts.sections.split_at_le = args.split_at_le;
    opts.open_sections = args.open_sections;
    opts.skin.degree_v = args.degree_v;
    opts.skin.params = match args.v_params {
        VParam::Chord => VParams::ChordLength,
        VParam::Centripetal => VParams::Centripetal,
    };
    opts.skin.approximate_with = args.approximate_v;
    opts.skin.smoothing = args.smooth_v;
    opts.skin.start_tangent_v = args.start_tangent_v;
    opts.skin.end_tangent_v = args.end_tangent_v;
    opts.iso_curves = fairfit::fair::DEFAULT_ISO_CURVES;
    opts.dense.outliers = match args.outliers {
        OutliersArg::Off => OutlierMode::Off,
        OutliersArg::Auto => OutlierMode::Auto,
    };
    opts
}

/// The surface through the sections (held to the exact curves of a CAD input), on `--threads`
/// workers, with a progress bar.
fn reconstruct(
    args: &SurfaceArgs,
    sections: Vec<Section>,
    exact: Option<Vec<ExactSection>>,
    opts: &SurfaceOptions,
) -> Result<(SurfaceReconstruction, Option<ExactSkin>), CliError> {
    let pb = crate::progress::bar(3, "surface");
    pb.set_message("fitting sections");
    let threads = super::threads::pool_threads(args.threads);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::new(format!("cannot start {threads} worker threads: {e}")))?;
    let mut progress = |st: Stage| match st {
        Stage::Compatible(n) => pb.set_message(format!("knot vectors {n}")),
        Stage::Skinned => {
            pb.inc(1);
            pb.set_message("measuring");
        }
        Stage::Measured => pb.inc(1),
    };
    let result = pool.install(|| match exact {
        Some(exact) => {
            skin_to_exact(exact, opts, &mut progress).map(|e| (e.reconstruction.clone(), Some(e)))
        }
        None => reconstruct_surface_with_progress(sections, opts, &mut progress).map(|r| (r, None)),
    });
    pb.finish_and_clear();
    Ok(result?)
}

/// Refuses a surface whose measures are not finite (the message names the measure).
fn check_measures(r: &SurfaceReconstruction) -> CmdResult {
    for (what, x) in [
        ("surface's largest deviation", r.deviation.max),
        ("surface's rms deviation", r.deviation.rms),
        (
            "largest iso-curve fairness along u",
            r.fairness.max_fairness_v,
        ),
        (
            "largest iso-curve fairness along v",
            r.fairness.max_fairness_u,
        ),
    ] {
        super::finite(what, x)?;
    }
    Ok(())
}

/// The files to write: the surface JSON, the report and the CAD/mesh/plot/HTML outputs.
fn output_files(
    args: &SurfaceArgs,
    r: &SurfaceReconstruction,
    tol: f64,
    notes: SectionNotes,
    exact: Option<&ExactSkin>,
) -> Result<Vec<Output>, CliError> {
    let mut files = vec![Output::geometry(
        &args.output,
        surface_to_json(&r.surface).into_bytes(),
    )];
    let all_points: Vec<Vec3> = r
        .sections
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .collect();
    let rep = if args.report.is_some() || args.outputs.html.is_some() {
        Some(surface_report(r, tol, &notes, exact))
    } else {
        None
    };
    if let (Some(path), Some(rep)) = (&args.report, &rep) {
        let text = super::json_pretty(rep)?;
        files.push(Output::new(path, text.into_bytes()));
    }
    if args.outputs.any() {
        let made = prepare_outputs(
            OutputGeometry::Surface(&r.surface),
            Some(&all_points),
            rep.as_ref(),
            &args.outputs,
        )?;
        files.extend(made.into_iter().map(|(p, b)| Output::new(p, b)));
    }
    Ok(files)
}

/// The one-line summary (on stdout, or as a note when an output goes to stdout), and the warning when
/// the tolerance is not met.
fn summarise(
    r: &SurfaceReconstruction,
    tol: f64,
    within: bool,
    gaps: usize,
    on_stdout: bool,
) -> CmdResult {
    let (nu, nv) = r.surface.net_size();
    let summary = format!(
        "surface: net {nu} x {nv}, max deviation {:.3e} (rms {:.3e}) over {} points, tolerance {:.3e}{}; iso-curve F max: along u (the sections) {:.3e}, along v (across them) {:.3e}; {} gap(s) reported",
        r.deviation.max,
        r.deviation.rms,
        r.deviation.points,
        tol,
        if within { "" } else { " NOT MET" },
        r.fairness.max_fairness_v,
        r.fairness.max_fairness_u,
        gaps
    );
    if on_stdout {
        super::print_stdout(&summary)?;
    } else {
        diag!("note: {summary}");
    }
    if r.deviation.max > tol {
        diag!(
            "warning: the tolerance {tol:.3e} is not met (max deviation {:.3e}); raise --max-ctrl or the tolerance",
            r.deviation.max
        );
    }
    Ok(())
}

/// The note on how far the exact CAD sections are from the surface (and the warning when beyond the
/// tolerance).
fn note_exact(path: &std::path::Path, e: &ExactSkin) {
    super::note_exact_deviation(
        path,
        "the exact sections",
        true,
        "surface",
        "the surface's iso-curves",
        &super::ExactDeviation {
            max_deviation: e.max_deviation,
            tolerance: e.tolerance,
            met: e.met,
            checked: e.checked,
            refits: e.refits,
            added: e.added,
            first_max_deviation: e.first_max_deviation,
            fit_tolerance: e.fit_tolerance,
        },
    );
}
