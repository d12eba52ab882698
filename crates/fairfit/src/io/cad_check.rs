//! Structural checks of STEP and IGES text, without a CAD kernel: what fairfit's tests (and a careful
//! user) run on written files. STEP: header sections, one `#n=...;` instance per line, balanced
//! parentheses outside strings, every `#ref` defined. IGES: 80-column records, section letters in
//! order with consecutive sequence numbers, DE/PD pointers consistent both ways, Terminate counts.

use crate::errors::{Error, Result};
use std::collections::{BTreeMap, BTreeSet};

/// What a STEP check found.
#[derive(Debug, Clone, PartialEq)]
pub struct StepSummary {
    /// Entity names (first keyword of each instance, or `(` for complex instances) and counts.
    pub entities: BTreeMap<String, usize>,
}

fn bad(msg: String) -> Error {
    Error::InvalidData(msg)
}

/// Checks the structure of ISO 10303-21 text.
pub fn check_step(text: &str) -> Result<StepSummary> {
    let lines: Vec<&str> = text.lines().collect();
    let data_at = lines.iter().position(|l| *l == "DATA;");
    let ok_frame = lines.first() == Some(&"ISO-10303-21;")
        && lines.get(1) == Some(&"HEADER;")
        && lines.last() == Some(&"END-ISO-10303-21;")
        && data_at.is_some()
        && ["FILE_DESCRIPTION(", "FILE_NAME(", "FILE_SCHEMA("]
            .iter()
            .all(|k| lines.iter().any(|l| l.starts_with(k)));
    let data_at = match (ok_frame, data_at) {
        (true, Some(i)) => i,
        _ => return Err(bad("STEP: missing header or frame".into())),
    };
    let mut defined = BTreeSet::new();
    let mut used = BTreeSet::new();
    let mut entities = BTreeMap::new();
    for (n, line) in lines[data_at + 1..lines.len() - 2].iter().enumerate() {
        let (id, body) = line
            .strip_prefix('#')
            .and_then(|l| l.split_once('='))
            .ok_or_else(|| bad(format!("STEP data line {n}: not an instance: {line}")))?;
        let id: usize = id
            .parse()
            .map_err(|_| bad(format!("STEP: bad id in {line}")))?;
        if !defined.insert(id) {
            return Err(bad(format!("STEP: #{id} defined twice")));
        }
        let body = body
            .strip_suffix(';')
            .ok_or_else(|| bad(format!("STEP: #{id} does not end with ';'")))?;
        let (mut depth, mut in_str, mut num) = (0i64, false, None::<String>);
        for ch in body.chars().chain(std::iter::once(' ')) {
            if let Some(ref mut s) = num {
                if ch.is_ascii_digit() {
                    s.push(ch);
                    continue;
                }
                used.insert(s.parse::<usize>().unwrap_or(0));
                num = None;
            }
            match ch {
                '\'' => in_str = !in_str,
                '(' if !in_str => depth += 1,
                ')' if !in_str => depth -= 1,
                '#' if !in_str => num = Some(String::new()),
                _ => {}
            }
            if depth < 0 {
                return Err(bad(format!("STEP: #{id}: unbalanced ')'")));
            }
        }
        if depth != 0 || in_str {
            return Err(bad(format!(
                "STEP: #{id}: unbalanced parentheses or quotes"
            )));
        }
        let name: String = body
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let name = if name.is_empty() { "(".into() } else { name };
        *entities.entry(name).or_insert(0) += 1;
    }
    if lines[lines.len() - 2] != "ENDSEC;" {
        return Err(bad("STEP: DATA section not closed by ENDSEC;".into()));
    }
    if let Some(r) = used.difference(&defined).next() {
        return Err(bad(format!("STEP: #{r} is referenced but not defined")));
    }
    Ok(StepSummary { entities })
}

/// What an IGES check found.
#[derive(Debug, Clone, PartialEq)]
pub struct IgesSummary {
    /// Line counts of the S, G, D, P sections.
    pub counts: [usize; 4],
    /// Entity type numbers, in directory order.
    pub entity_types: Vec<u32>,
    /// The parameter data of each entity, joined across its lines (delimiters kept).
    pub parameters: Vec<String>,
}

/// Checks the structure of IGES 5.3 fixed-format text.
pub fn check_iges(text: &str) -> Result<IgesSummary> {
    let mut counts = [0usize; 5];
    let order = ['S', 'G', 'D', 'P', 'T'];
    let mut section = 0usize;
    let (mut de, mut pd) = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        if line.len() != 80 || !line.is_ascii() {
            return Err(bad(format!("IGES line {}: not 80 ASCII columns", n + 1)));
        }
        let letter = line.as_bytes()[72] as char;
        let seq: usize = line[73..]
            .trim()
            .parse()
            .map_err(|_| bad(format!("IGES line {}: bad sequence number", n + 1)))?;
        let s = order
            .iter()
            .position(|&c| c == letter)
            .ok_or_else(|| bad(format!("IGES line {}: unknown section {letter}", n + 1)))?;
        if s < section {
            return Err(bad(format!(
                "IGES line {}: section {letter} out of order",
                n + 1
            )));
        }
        section = s;
        counts[s] += 1;
        if seq != counts[s] {
            return Err(bad(format!(
                "IGES line {}: sequence {seq}, expected {}",
                n + 1,
                counts[s]
            )));
        }
        match letter {
            'D' => de.push(line.to_string()),
            'P' => pd.push(line.to_string()),
            _ => {}
        }
    }
    if counts[4] != 1 || de.len() % 2 != 0 {
        return Err(bad(
            "IGES: need exactly one T line and DE lines in pairs".into()
        ));
    }
    let t = text.lines().last().unwrap_or("");
    let want = format!(
        "S{:07}G{:07}D{:07}P{:07}",
        counts[0], counts[1], counts[2], counts[3]
    );
    if !t.starts_with(&want) {
        return Err(bad(format!(
            "IGES: terminate line {t:?} does not say {want}"
        )));
    }
    let field = |l: &str, k: usize| l[8 * k..8 * k + 8].trim().parse::<usize>().unwrap_or(0);
    let (mut types, mut params) = (Vec::new(), Vec::new());
    for pair in de.chunks(2) {
        let de_seq = types.len() * 2 + 1;
        let (ty, start, count) = (field(&pair[0], 0), field(&pair[0], 1), field(&pair[1], 3));
        if ty != field(&pair[1], 0) || start == 0 || count == 0 || start + count - 1 > pd.len() {
            return Err(bad(format!(
                "IGES: DE {de_seq} has inconsistent type or PD range"
            )));
        }
        let mut joined = String::new();
        for l in &pd[start - 1..start - 1 + count] {
            if field(l, 8) != de_seq {
                return Err(bad(format!(
                    "IGES: PD line does not point back to DE {de_seq}"
                )));
            }
            joined.push_str(l[..64].trim_end());
        }
        if !joined.starts_with(&format!("{ty},")) || !joined.ends_with(';') {
            return Err(bad(format!(
                "IGES: PD of DE {de_seq} must start with {ty}, end with ;"
            )));
        }
        types.push(ty as u32);
        params.push(joined);
    }
    let covered: usize = de.chunks(2).map(|p| field(&p[1], 3)).sum();
    if covered != pd.len() {
        return Err(bad(
            "IGES: PD lines not covered exactly by the DE ranges".into()
        ));
    }
    Ok(IgesSummary {
        counts: [counts[0], counts[1], counts[2], counts[3]],
        entity_types: types,
        parameters: params,
    })
}
