//! What reaches stderr, one line at a time: the `warning:` and `note:` lines of a run are queued
//! ([`diagnostic`], the `diag!` macro) and printed when the run succeeds; a failed run prints ONE
//! line, its error with the warnings folded in ([`failure_line`]), the notes dropped. Every line is
//! made safe to print by [`one_line`]: control characters (a newline in a file name) escaped, echoed
//! input (a token or a line of a file) cut to about 80 characters.

use std::sync::Mutex;

/// The longest quoted piece of echoed input kept whole (in characters).
const MAX_QUOTED: usize = 80;
/// The longest run of characters without a space kept whole (a token without quotes; paths are
/// shorter).
const MAX_WORD: usize = 240;
/// How many characters of a cut piece are kept.
const KEPT: usize = 60;

static QUEUE: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Queues a `warning: ...` or `note: ...` line for stderr.
pub fn diagnostic(line: String) {
    QUEUE.lock().unwrap_or_else(|e| e.into_inner()).push(line);
}

fn take() -> Vec<String> {
    std::mem::take(&mut *QUEUE.lock().unwrap_or_else(|e| e.into_inner()))
}

/// Prints the queued lines (a run that succeeded).
pub fn flush() {
    for line in take() {
        eprintln!("{}", one_line(&line));
    }
}

/// The one line of a failed run: `error: MESSAGE`, with the queued warnings folded in
/// (`...; earlier warning: ...`) and the notes dropped.
pub fn failure_line(message: &str) -> String {
    let warnings: Vec<String> = take()
        .into_iter()
        .filter_map(|l| l.strip_prefix("warning: ").map(str::to_string))
        .collect();
    let mut line = format!("error: {message}");
    for w in warnings {
        line.push_str("; earlier warning: ");
        line.push_str(&w);
    }
    one_line(&line)
}

/// Whether `c` opens a quoted piece of echoed input, and its closing quote.
fn closing_quote(c: char) -> Option<char> {
    match c {
        '\'' => Some('\''),
        '`' => Some('`'),
        '"' => Some('"'),
        _ => None,
    }
}

/// `piece` cut to its first [`KEPT`] characters with the count of the rest, when it is longer than
/// `max`.
fn cut(piece: &str, max: usize) -> String {
    let n = piece.chars().count();
    if n <= max {
        return piece.to_string();
    }
    let head: String = piece.chars().take(KEPT).collect();
    format!("{head}... ({} more characters)", n - KEPT)
}

/// `text` as one printable line: control characters escaped (`\n`, `\t`, `\u{1b}`), every quoted
/// piece longer than [`MAX_QUOTED`] characters and every run without spaces longer than
/// [`MAX_WORD`] cut (see [`cut`]).
pub fn one_line(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len().min(4096));
    for c in text.chars() {
        match c {
            '\n' => escaped.push_str("\\n"),
            '\r' => escaped.push_str("\\r"),
            '\t' => escaped.push_str("\\t"),
            c if c.is_control() => escaped.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => escaped.push(c),
        }
    }
    // quoted pieces: an opening quote after no letter or digit (not the `'` of "curve's"), its
    // closing quote before none
    let mut out = String::with_capacity(escaped.len().min(4096));
    let mut rest = escaped.as_str();
    let mut prev_alnum = false;
    loop {
        let open = rest.char_indices().find(|&(k, c)| {
            let before = if k == 0 {
                prev_alnum
            } else {
                rest[..k]
                    .chars()
                    .next_back()
                    .is_some_and(char::is_alphanumeric)
            };
            closing_quote(c).is_some() && !before
        });
        let Some((k, c)) = open else { break };
        let close = closing_quote(c).unwrap_or(c);
        out.push_str(&rest[..k + 1]);
        let after = &rest[k + 1..];
        let end = after.char_indices().find(|&(e, d)| {
            d == close
                && !after[e + d.len_utf8()..]
                    .chars()
                    .next()
                    .is_some_and(char::is_alphanumeric)
        });
        match end {
            Some((e, _)) => {
                out.push_str(&cut(&after[..e], MAX_QUOTED));
                out.push(close);
                rest = &after[e + close.len_utf8()..];
                prev_alnum = false;
            }
            None => {
                rest = after;
                prev_alnum = false;
                continue;
            }
        }
    }
    out.push_str(rest);
    // long runs without spaces
    out.split(' ')
        .map(|w| cut(w, MAX_WORD))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped() {
        assert_eq!(one_line("a\nb\tc\u{1b}[31m"), "a\\nb\\tc\\u{1b}[31m");
    }

    #[test]
    fn long_echoes_are_cut_and_short_ones_kept() {
        let long = "x".repeat(10_000);
        let line = one_line(&format!("error: bad token '{long}' in f.csv"));
        assert!(line.len() < 200, "{line}");
        assert!(line.starts_with(&format!("error: bad token '{}...", "x".repeat(KEPT))));
        assert!(line.ends_with("(9940 more characters)' in f.csv"), "{line}");
        let spaced = format!("got `{}`", "1 2 ".repeat(1000));
        assert!(one_line(&spaced).len() < 200);
        let bare = format!("error: {}", "y".repeat(5000));
        assert!(one_line(&bare).len() < 400);
        let ok = "error: f.csv: expected 2 or 3 numbers, got 'a b' on line 3";
        assert_eq!(one_line(ok), ok);
        let apostrophes = format!(
            "error: the curve's {} see 'fairfit curve --help'",
            "word ".repeat(40)
        );
        assert_eq!(one_line(&apostrophes), apostrophes);
    }

    #[test]
    fn warnings_fold_into_the_failure_and_notes_drop() {
        diagnostic("note: read entity 2".into());
        diagnostic("warning: p.csv: dropped 198 consecutive duplicate point(s)".into());
        let line = failure_line("2 points are too few");
        assert_eq!(
            line,
            "error: 2 points are too few; earlier warning: p.csv: dropped 198 consecutive duplicate point(s)"
        );
        assert_eq!(failure_line("x"), "error: x");
    }
}
