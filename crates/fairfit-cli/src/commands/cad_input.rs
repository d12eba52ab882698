//! STEP and IGES files as input: `--index` / `--entity` (flattened into `info`, `eval`, `plot`, `export`
//! and `curve`), the notes on what was read, and the points a CAD curve gives `fairfit curve`.
//!
//! A CAD file is recognised by its extension (`.step`, `.stp`, `.igs`, `.iges`); its coordinates are
//! read in millimetres (see `fairfit::io::cad_read`). When the file holds more than one entity of the
//! kind taken, or declares a unit other than mm, one `note:` line on stderr says which entity was taken
//! and how to choose another.

use super::CliError;
use clap::{Args, ValueEnum};
use fairfit::fit::sampling::{sample_chain_params, samples_per_span, ChainSample};
use fairfit::io::cad_chain::open_gaps;
use fairfit::io::cad_read::{
    curve_kind, read_cad, read_cad_chain, CadFormat, CadGeometry, CadKind, CadUnit,
};
use fairfit::io::cad_sections::read_cad_sections as read_sections;
use fairfit::io::{read_geometry, read_points, Geometry, PointSet};
use fairfit::surface::cad_skin::ExactSection;
use fairfit::surface::Section;
use std::path::{Path, PathBuf};

/// Which kind of entity to take from a CAD file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Default)]
pub enum EntityArg {
    /// A B-spline surface if the file holds one, else a B-spline curve.
    #[default]
    Auto,
    /// A B-spline curve (an edge).
    Curve,
    /// A B-spline surface (a face).
    Surface,
}

/// Choice of the entity read from a STEP or IGES input.
#[derive(Args, Debug, Clone, Default)]
pub struct CadInputArgs {
    /// STEP/IGES input: which B-spline entity of the chosen kind to read (0 = the first in the file).
    #[arg(long, value_name = "N")]
    pub index: Option<usize>,
    /// STEP/IGES input: the kind of entity to read.
    #[arg(long, value_enum, value_name = "KIND")]
    pub entity: Option<EntityArg>,
}

impl CadInputArgs {
    fn kind(&self, default: CadKind) -> CadKind {
        match self.entity {
            None => default,
            Some(EntityArg::Auto) => CadKind::Any,
            Some(EntityArg::Curve) => CadKind::Curve,
            Some(EntityArg::Surface) => CadKind::Surface,
        }
    }

    /// Refuses `--index` / `--entity` for an input that is no CAD file.
    pub(crate) fn check_not_cad(&self, path: &Path) -> Result<(), CliError> {
        if self.index.is_some() || self.entity.is_some() {
            return Err(CliError::usage(format!(
                "--index and --entity choose an entity of a STEP or IGES file, and {} is neither \
                 (.step, .stp, .igs, .iges)",
                path.display()
            )));
        }
        Ok(())
    }
}

/// What a read geometry is: `composite curve`, `circle`, `circular arc`, `ellipse`, `elliptical arc`,
/// `B-spline curve` or `B-spline surface`.
fn kind_of(g: &CadGeometry) -> &'static str {
    match g.geometry {
        Geometry::Curve(_) if g.segments > 1 => "composite curve",
        Geometry::Curve(_) => curve_kind(&g.source),
        Geometry::Surface(_) => "B-spline surface",
    }
}

/// Prints the note on what was read when there was a choice (`count > 1`) or a unit conversion.
fn note_read(path: &Path, what: &str, source: &str, index: usize, count: usize, unit: &CadUnit) {
    let unit = if unit.name != "mm" {
        format!("; coordinates converted from {} to mm", unit.name)
    } else {
        String::new()
    };
    if count > 1 || !unit.is_empty() {
        let choice = if count > 1 {
            format!(
                " ({} of {count}; choose with --index 0..{})",
                index + 1,
                count - 1
            )
        } else {
            String::new()
        };
        diag!(
            "note: {}: read {what} {source}{choice}{unit}",
            path.display()
        );
    }
}

/// What the note calls a curve of `kind` (a conic's source names its kind: `read exact conic #16
/// (circular arc, trimmed #17)`).
fn described(kind: &str) -> String {
    match kind {
        "B-spline curve" | "B-spline surface" => kind.to_string(),
        "composite curve" => "composite curve (joined into one B-spline)".to_string(),
        _ => "exact conic".to_string(),
    }
}

/// Reads the CAD file and prints a note when there was a choice or a unit conversion.
fn read_noted(path: &Path, kind: CadKind, args: &CadInputArgs) -> Result<CadGeometry, CliError> {
    let g = read_cad(path, kind, args.index.unwrap_or(0))?;
    note_read(
        path,
        &described(kind_of(&g)),
        &g.source,
        g.index,
        g.count,
        &g.unit,
    );
    Ok(g)
}

/// The geometry of a JSON, STEP or IGES file (for `info`, `eval`, `plot`, `export`).
pub fn read_input(path: &Path, args: &CadInputArgs) -> Result<Geometry, CliError> {
    Ok(read_input_with_source(path, args)?.0)
}

/// The geometry of a JSON, STEP or IGES file, and for a CAD file what was read (`info`'s `source`):
/// `{"format", "entity", "kind", "segments", "index", "count", "unit", "unit_declared", "mm_per_unit"}`,
/// where `mm_per_unit` is the factor the coordinates were multiplied by (1 for millimetres).
pub fn read_input_with_source(
    path: &Path,
    args: &CadInputArgs,
) -> Result<(Geometry, Option<serde_json::Value>), CliError> {
    let Some(format) = CadFormat::from_path(path) else {
        args.check_not_cad(path)?;
        return Ok((read_geometry(path)?, None));
    };
    let g = read_noted(path, args.kind(CadKind::Any), args)?;
    let kind = kind_of(&g);
    let source = serde_json::json!({
        "format": match format {
            CadFormat::Step => "STEP",
            CadFormat::Iges => "IGES",
        },
        "entity": g.source,
        "kind": kind,
        "segments": g.segments,
        "index": g.index,
        "count": g.count,
        "unit": g.unit.name,
        "unit_declared": g.unit.declared,
        "mm_per_unit": g.unit.mm_per_unit,
    });
    Ok((g.geometry, Some(source)))
}

/// A CAD curve `fairfit curve` re-fits: the exact segments (in mm) and their dense samples.
pub struct CadCurve {
    /// The segments of the chain (one for a single curve), oriented along it.
    pub segments: Vec<fairfit::NurbsCurve>,
    /// The samples, with their segments and parameters (`fairfit::fit::cad_fit`).
    pub samples: Vec<ChainSample>,
}

/// The points `fairfit curve` fits: a point file as it is, or a B-spline curve of a STEP or IGES file
/// sampled densely (`fairfit::fit::sampling::sample_chain_params`), so that re-fitting it fairs it; for
/// a CAD file also the exact curve, which the fit is checked against.
pub fn read_curve_points(
    path: &Path,
    args: &CadInputArgs,
) -> Result<(PointSet, Option<CadCurve>), CliError> {
    if CadFormat::from_path(path).is_none() {
        args.check_not_cad(path)?;
        return Ok((read_points(path)?, None));
    }
    if args.entity == Some(EntityArg::Surface) {
        return Err(CliError::usage(
            "fairfit curve re-fits a curve: --entity surface is not possible here",
        ));
    }
    // the file is read and parsed once: a single curve is the chain's one segment
    let chain = read_cad_chain(path, args.index.unwrap_or(0))?;
    if let [c] = chain.segments.as_slice() {
        let kind = curve_kind(&chain.source);
        note_read(
            path,
            &described(kind),
            &chain.source,
            chain.index,
            chain.count,
            &chain.unit,
        );
        let samples = sample_chain_params(&chain.segments);
        diag!(
            "note: {}: fitting {} points sampled on {} (degree {}, {} control points; {} per knot span)",
            path.display(),
            samples.len(),
            chain.source,
            c.degree(),
            c.n_control_points(),
            samples_per_span(c.degree())
        );
        return Ok(cad_points(samples, chain.segments, chain.source));
    }
    let samples = sample_chain_params(&chain.segments);
    let degrees: Vec<String> = chain
        .segments
        .iter()
        .map(|c| c.degree().to_string())
        .collect();
    let choice = if chain.count > 1 {
        format!(
            " ({} of {} curves; choose with --index 0..{})",
            chain.index + 1,
            chain.count,
            chain.count - 1
        )
    } else {
        String::new()
    };
    let unit = if chain.unit.name != "mm" {
        format!("; coordinates converted from {} to mm", chain.unit.name)
    } else {
        String::new()
    };
    let gaps: Vec<String> = open_gaps(&chain.segments)
        .into_iter()
        .map(|(k, g)| format!("{g:.3e} mm between segments {} and {}", k + 1, k + 2))
        .collect();
    let gaps = if gaps.is_empty() {
        String::new()
    } else {
        format!("; not joined where they are apart: {}", gaps.join(", "))
    };
    diag!(
        "note: {}: fitting {} points sampled on the composite curve {}{choice}, segments of degree {} joined in order{unit}{gaps}",
        path.display(),
        samples.len(),
        chain.source,
        degrees.join(", "),
    );
    Ok(cad_points(samples, chain.segments, chain.source))
}

fn cad_points(
    samples: Vec<ChainSample>,
    segments: Vec<fairfit::NurbsCurve>,
    source: String,
) -> (PointSet, Option<CadCurve>) {
    let set = PointSet {
        points: samples.iter().map(|s| s.point).collect(),
        dropped_duplicates: 0,
        columns: 3,
        name: Some(source),
        lednicer: false,
    };
    (set, Some(CadCurve { segments, samples }))
}

/// Sections with their names (`#12`, `DE 7`, `#30 at v = 0.25`) and their exact curves, in the same
/// order.
pub type NamedSections = (Vec<Section>, Vec<String>, Vec<ExactSection>);

/// The sections `fairfit surface` skins from one STEP or IGES file (`fairfit::io::cad_sections`), with
/// their names and exact curves (which the surface is held to, `fairfit::surface::cad_skin`), or `None` when
/// the input is no CAD file. One `note:` line says what was taken.
pub fn read_cad_sections(
    input: &[PathBuf],
    args: &CadInputArgs,
) -> Result<Option<NamedSections>, CliError> {
    let Some(path) = input.iter().find(|p| CadFormat::from_path(p).is_some()) else {
        if let Some(first) = input.first() {
            args.check_not_cad(first)?;
        }
        return Ok(None);
    };
    if input.len() != 1 {
        return Err(CliError::usage(format!(
            "{} is a STEP/IGES file: its curves are all the sections, so give it as the only input",
            path.display()
        )));
    }
    let s = read_sections(path, args.kind(CadKind::Any), args.index)?;
    let unit = if s.unit.name != "mm" {
        format!("; coordinates converted from {} to mm", s.unit.name)
    } else {
        String::new()
    };
    let what = match &s.surface {
        Some((src, i, n)) => {
            let choice = if *n > 1 {
                format!(" ({} of {n}; choose with --index 0..{})", i + 1, n - 1)
            } else {
                String::new()
            };
            format!(
                "re-fairing B-spline surface {src}{choice} through {} of its v-iso-curves (--entity curve takes the file's curves instead)",
                s.sections.len()
            )
        }
        None => format!(
            "{} sections from its B-spline curves in file order",
            s.sections.len()
        ),
    };
    diag!("note: {}: {what}{unit}", path.display());
    let mut sections = Vec::with_capacity(s.sections.len());
    let mut names = Vec::with_capacity(s.sections.len());
    for (name, pts) in s.sections {
        if pts.len() < 3 {
            return Err(CliError::new(format!(
                "{}: the curve {name} is a single point, not a section",
                path.display()
            )));
        }
        sections.push(Section::from_points(pts));
        names.push(name);
    }
    Ok(Some((sections, names, s.exact)))
}
