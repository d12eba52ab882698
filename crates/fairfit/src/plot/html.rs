//! One self-contained HTML report per run: inputs, parameters, a metrics table and the plots as inline
//! SVG (no scripts, no external files).

use super::svg::escape;
use std::fmt::Write as _;

/// The content of a report.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Page title.
    pub title: String,
    /// Inputs (file names, point counts, ...) as label/value rows.
    pub inputs: Vec<(String, String)>,
    /// Parameters of the run as label/value rows.
    pub parameters: Vec<(String, String)>,
    /// Metrics as label/value rows.
    pub metrics: Vec<(String, String)>,
    /// Plots: caption and SVG text.
    pub plots: Vec<(String, String)>,
}

/// Label/value rows from a JSON value: object members flattened with dotted keys, arrays of numbers
/// shown inline (long ones shortened).
pub(crate) fn rows_from_json(v: &serde_json::Value) -> Vec<(String, String)> {
    fn walk(prefix: &str, v: &serde_json::Value, out: &mut Vec<(String, String)>) {
        match v {
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    let key = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    walk(&key, x, out);
                }
            }
            serde_json::Value::Array(a) if a.len() > 12 => {
                out.push((prefix.to_string(), format!("[{} values]", a.len())));
            }
            serde_json::Value::String(s) => out.push((prefix.to_string(), s.clone())),
            other => {
                let mut other = other.clone();
                crate::io::numbers::clear_negative_zeros(&mut other);
                out.push((prefix.to_string(), other.to_string()))
            }
        }
    }
    let mut out = Vec::new();
    walk("", v, &mut out);
    out
}

fn table(out: &mut String, heading: &str, rows: &[(String, String)]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(out, "<h2>{}</h2>\n<table>", escape(heading));
    for (k, v) in rows {
        let _ = writeln!(out, "<tr><th>{}</th><td>{}</td></tr>", escape(k), escape(v));
    }
    out.push_str("</table>\n");
}

/// The HTML text of a report.
///
/// ```
/// use fairfit::plot::html::{html_report, Report};
/// let r = Report { title: "fit".into(), metrics: vec![("max error".into(), "1e-3".into())], ..Default::default() };
/// let page = html_report(&r);
/// assert!(page.contains("<td>1e-3</td>") && page.starts_with("<!DOCTYPE html>"));
/// ```
pub fn html_report(r: &Report) -> String {
    let mut out =
        String::from("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    let _ = writeln!(out, "<title>{}</title>", escape(&r.title));
    out.push_str(
        "<style>body{font-family:DejaVu Sans,Arial,sans-serif;margin:2em;max-width:1000px}\
         table{border-collapse:collapse;margin-bottom:1em}th,td{border:1px solid #ccc;padding:4px 10px;\
         text-align:left;font-variant-numeric:tabular-nums}th{background:#f3f3f3}\
         figure{margin:1.5em 0}svg{max-width:100%;height:auto}</style>\n</head>\n<body>\n",
    );
    let _ = writeln!(out, "<h1>{}</h1>", escape(&r.title));
    table(&mut out, "Inputs", &r.inputs);
    table(&mut out, "Parameters", &r.parameters);
    table(&mut out, "Metrics", &r.metrics);
    for (caption, svg) in &r.plots {
        let _ = writeln!(
            out,
            "<figure>\n{}<figcaption>{}</figcaption>\n</figure>",
            svg,
            escape(caption)
        );
    }
    let _ = writeln!(
        out,
        "<footer><small>fairfit {}</small></footer>\n</body>\n</html>",
        env!("CARGO_PKG_VERSION")
    );
    out
}
