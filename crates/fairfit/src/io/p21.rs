//! A tokenizer and parser for the clear-text encoding of STEP files (ISO 10303-21, "Part 21").
//!
//! Hand-written, like the writers: the Rust crates for Part 21 either pull a parser-combinator and
//! derive-macro tree with schema-generated code (`ruststep`, marked experimental by its authors, and its
//! successor `step-p21`) or are placeholders; fairfit needs only the instance syntax and a handful of
//! geometry and unit entities, which fit in two small files (this one and [`super::step_read`]).
//!
//! What is read: the header and data sections; simple instances `#12=NAME(...);` and complex instances
//! `#12=( A() B(1,2) ... );`; parameters: integers and reals (any exponent form: `1.E-03`, `2.5e7`,
//! `-.5`), strings `'it''s'` (the `''` escape; `\X\`-style control directives are kept as written),
//! enumerations `.UNSPECIFIED.` / `.T.`, references `#7`, `$` (unset), `*` (derived), lists, typed
//! parameters `LENGTH_MEASURE(1.)` and binaries `"0FF"` (kept as text). Comments `/* ... */` and line
//! breaks anywhere between tokens are skipped. Errors name the line.

use crate::errors::{Error, Result};
use std::collections::BTreeMap;

/// One parameter value of an instance.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// An integer or real number.
    Number(f64),
    /// A string (quotes removed, `''` unescaped).
    Str(String),
    /// An enumeration value without the dots (`UNSPECIFIED`, `T`, `F`).
    Enum(String),
    /// A reference to instance `#n`.
    Ref(u64),
    /// `$`: the value is not given.
    Unset,
    /// `*`: the value is derived (redeclared in a subtype).
    Derived,
    /// A list `( ... )`.
    List(Vec<Value>),
    /// A typed parameter `NAME(value)`, e.g. `LENGTH_MEASURE(1.)`.
    Typed(String, Box<Value>),
    /// A binary `"..."`, as written.
    Binary(String),
}

impl Value {
    /// The number, if this is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Number(x) => Some(*x),
            Value::Typed(_, v) => v.as_f64(),
            _ => None,
        }
    }
    /// The list items, if this is a list.
    pub fn as_list(&self) -> Option<&[Value]> {
        match self {
            Value::List(v) => Some(v),
            _ => None,
        }
    }
    /// The referenced instance, if this is a reference.
    pub fn as_ref_id(&self) -> Option<u64> {
        match self {
            Value::Ref(r) => Some(*r),
            _ => None,
        }
    }
}

/// One entity of an instance: its name (upper case) and parameters. A simple instance has one part, a
/// complex instance one per entity of its supertype chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Entity name, upper case.
    pub name: String,
    /// Parameters in file order.
    pub params: Vec<Value>,
}

/// A data-section instance.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The parts: one for a simple instance, several for a complex one.
    pub parts: Vec<Part>,
    /// Line of the `#n=` in the file.
    pub line: usize,
}

impl Instance {
    /// The part named `name`, if the instance has one.
    pub fn part(&self, name: &str) -> Option<&Part> {
        self.parts.iter().find(|p| p.name == name)
    }
    /// True for a complex instance (`( A() B() )`).
    pub fn is_complex(&self) -> bool {
        self.parts.len() > 1
    }
}

/// A parsed exchange structure: header entities and data instances by id.
#[derive(Clone, Debug, Default)]
pub struct Exchange {
    /// Header entities (`FILE_DESCRIPTION`, `FILE_NAME`, `FILE_SCHEMA`, ...).
    pub header: Vec<Part>,
    /// Data instances by their `#n` id, in id order.
    pub data: BTreeMap<u64, Instance>,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Keyword(String),
    Number(f64),
    Str(String),
    Enum(String),
    Ref(u64),
    Binary(String),
    Dollar,
    Star,
    Open,
    Close,
    Comma,
    Semi,
    Equals,
}

struct Lexer<'a> {
    s: &'a [u8],
    pos: usize,
    line: usize,
}

fn syntax(line: usize, msg: impl std::fmt::Display) -> Error {
    Error::Cad(format!("line {line}: {msg}"))
}

impl<'a> Lexer<'a> {
    fn skip_space(&mut self) -> Result<()> {
        loop {
            match self.s.get(self.pos) {
                Some(b'\n') => {
                    self.line += 1;
                    self.pos += 1;
                }
                Some(c) if c.is_ascii_whitespace() => self.pos += 1,
                Some(b'/') if self.s.get(self.pos + 1) == Some(&b'*') => {
                    let start = self.line;
                    self.pos += 2;
                    loop {
                        match self.s.get(self.pos) {
                            None => return Err(syntax(start, "comment /* is never closed")),
                            Some(b'*') if self.s.get(self.pos + 1) == Some(&b'/') => {
                                self.pos += 2;
                                break;
                            }
                            Some(b'\n') => {
                                self.line += 1;
                                self.pos += 1;
                            }
                            Some(_) => self.pos += 1,
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn take_while(&mut self, f: impl Fn(u8) -> bool) -> &'a str {
        let start = self.pos;
        while self.s.get(self.pos).is_some_and(|&c| f(c)) {
            self.pos += 1;
        }
        // only ASCII bytes are ever accepted by the callers' predicates
        std::str::from_utf8(&self.s[start..self.pos]).unwrap_or("")
    }

    /// The next token and its line, or `None` at the end of the text.
    fn next(&mut self) -> Result<Option<(Tok, usize)>> {
        self.skip_space()?;
        let line = self.line;
        let Some(&c) = self.s.get(self.pos) else {
            return Ok(None);
        };
        let tok = match c {
            b'(' | b')' | b',' | b';' | b'=' | b'$' | b'*' => {
                self.pos += 1;
                match c {
                    b'(' => Tok::Open,
                    b')' => Tok::Close,
                    b',' => Tok::Comma,
                    b';' => Tok::Semi,
                    b'=' => Tok::Equals,
                    b'$' => Tok::Dollar,
                    _ => Tok::Star,
                }
            }
            b'#' => {
                self.pos += 1;
                let digits = self.take_while(|c| c.is_ascii_digit());
                let id = digits
                    .parse()
                    .map_err(|_| syntax(line, "'#' must be followed by an instance number"))?;
                Tok::Ref(id)
            }
            b'\'' => Tok::Str(self.string(line)?),
            b'"' => {
                self.pos += 1;
                let text = self.take_while(|c| c != b'"').to_string();
                if self.s.get(self.pos) != Some(&b'"') {
                    return Err(syntax(line, "binary \"... is never closed"));
                }
                self.pos += 1;
                Tok::Binary(text)
            }
            b'.' if self
                .s
                .get(self.pos + 1)
                .is_some_and(|c| c.is_ascii_alphabetic()) =>
            {
                self.pos += 1;
                let name = self.take_while(|c| c.is_ascii_alphanumeric() || c == b'_');
                if self.s.get(self.pos) != Some(&b'.') {
                    return Err(syntax(
                        line,
                        format!("enumeration .{name} lacks its closing '.'"),
                    ));
                }
                self.pos += 1;
                Tok::Enum(name.to_ascii_uppercase())
            }
            b'+' | b'-' | b'.' | b'0'..=b'9' => {
                let text = self.number_text();
                let x: f64 = text
                    .parse()
                    .map_err(|_| syntax(line, format!("'{text}' is not a number")))?;
                Tok::Number(x)
            }
            c if c.is_ascii_alphabetic() || c == b'!' || c == b'_' => {
                let name = self.take_while(|c| {
                    c.is_ascii_alphanumeric() || c == b'_' || c == b'-' || c == b'!'
                });
                Tok::Keyword(name.to_ascii_uppercase())
            }
            other => {
                return Err(syntax(
                    line,
                    format!(
                        "unexpected character '{}'",
                        char::from(other).escape_default()
                    ),
                ))
            }
        };
        Ok(Some((tok, line)))
    }

    /// A number: sign, digits, optional fraction, optional exponent (`E`/`e`); `1.E-03` included.
    fn number_text(&mut self) -> String {
        let start = self.pos;
        if matches!(self.s.get(self.pos), Some(b'+' | b'-')) {
            self.pos += 1;
        }
        self.take_while(|c| c.is_ascii_digit());
        if self.s.get(self.pos) == Some(&b'.') {
            self.pos += 1;
            self.take_while(|c| c.is_ascii_digit());
        }
        if matches!(self.s.get(self.pos), Some(b'E' | b'e' | b'D' | b'd')) {
            let save = self.pos;
            self.pos += 1;
            if matches!(self.s.get(self.pos), Some(b'+' | b'-')) {
                self.pos += 1;
            }
            if self.take_while(|c| c.is_ascii_digit()).is_empty() {
                self.pos = save;
            }
        }
        let text = String::from_utf8_lossy(&self.s[start..self.pos]);
        // Rust's parser wants a digit after a trailing '.' before an exponent ("1.E-3" -> "1.0E-3")
        let mut t = text.replace(['D', 'd'], "E");
        if let Some(i) = t.find(".E").or_else(|| t.find(".e")) {
            t.insert(i + 1, '0');
        }
        if t.ends_with('.') {
            t.push('0');
        }
        t
    }

    fn string(&mut self, line: usize) -> Result<String> {
        self.pos += 1;
        let mut out = Vec::new();
        loop {
            match self.s.get(self.pos) {
                None => return Err(syntax(line, "string '... is never closed")),
                Some(b'\'') if self.s.get(self.pos + 1) == Some(&b'\'') => {
                    out.push(b'\'');
                    self.pos += 2;
                }
                Some(b'\'') => {
                    self.pos += 1;
                    return Ok(String::from_utf8_lossy(&out).into_owned());
                }
                Some(&c) => {
                    if c == b'\n' {
                        self.line += 1;
                    }
                    if c != b'\n' && c != b'\r' {
                        out.push(c);
                    }
                    self.pos += 1;
                }
            }
        }
    }
}

/// A token stream with one token of look-ahead.
struct Parser<'a> {
    lex: Lexer<'a>,
    peeked: Option<(Tok, usize)>,
    last_line: usize,
    /// Nesting depth of the value being read (lists, typed parameters).
    depth: usize,
}

/// Deepest nesting of lists accepted (B-spline surfaces need 3; a hostile file must not exhaust the stack).
const MAX_DEPTH: usize = 64;

impl<'a> Parser<'a> {
    fn peek(&mut self) -> Result<Option<&Tok>> {
        if self.peeked.is_none() {
            self.peeked = self.lex.next()?;
        }
        Ok(self.peeked.as_ref().map(|(t, _)| t))
    }

    fn bump(&mut self, context: &str) -> Result<Tok> {
        self.peek()?;
        match self.peeked.take() {
            Some((t, line)) => {
                self.last_line = line;
                Ok(t)
            }
            None => Err(syntax(
                self.lex.line,
                format!("the file ends inside {context} (truncated?)"),
            )),
        }
    }

    fn expect(&mut self, want: Tok, context: &str) -> Result<()> {
        let t = self.bump(context)?;
        if t == want {
            Ok(())
        } else {
            Err(syntax(
                self.last_line,
                format!("expected {} in {context}, found {}", show(&want), show(&t)),
            ))
        }
    }

    /// `NAME(params)` after the name was read.
    fn part(&mut self, name: String, context: &str) -> Result<Part> {
        self.expect(Tok::Open, context)?;
        let params = self.params_until_close(context)?;
        Ok(Part { name, params })
    }

    /// Comma-separated values up to and including `)`.
    fn params_until_close(&mut self, context: &str) -> Result<Vec<Value>> {
        let mut out = Vec::new();
        if self.peek()? == Some(&Tok::Close) {
            self.bump(context)?;
            return Ok(out);
        }
        loop {
            out.push(self.value(context)?);
            match self.bump(context)? {
                Tok::Comma => continue,
                Tok::Close => return Ok(out),
                t => {
                    return Err(syntax(
                        self.last_line,
                        format!("expected ',' or ')' in {context}, found {}", show(&t)),
                    ))
                }
            }
        }
    }

    fn value(&mut self, context: &str) -> Result<Value> {
        if self.depth >= MAX_DEPTH {
            return Err(syntax(
                self.lex.line,
                format!("lists nested deeper than {MAX_DEPTH} in {context}"),
            ));
        }
        self.depth += 1;
        let v = self.value_inner(context);
        self.depth -= 1;
        v
    }

    fn value_inner(&mut self, context: &str) -> Result<Value> {
        Ok(match self.bump(context)? {
            Tok::Number(x) => Value::Number(x),
            Tok::Str(s) => Value::Str(s),
            Tok::Enum(e) => Value::Enum(e),
            Tok::Ref(r) => Value::Ref(r),
            Tok::Binary(b) => Value::Binary(b),
            Tok::Dollar => Value::Unset,
            Tok::Star => Value::Derived,
            Tok::Open => Value::List(self.params_until_close(context)?),
            Tok::Keyword(name) => {
                self.expect(Tok::Open, context)?;
                let mut inner = self.params_until_close(context)?;
                let v = if inner.len() == 1 {
                    inner.pop().unwrap_or(Value::Unset)
                } else {
                    Value::List(inner)
                };
                Value::Typed(name, Box::new(v))
            }
            t => {
                return Err(syntax(
                    self.last_line,
                    format!("expected a value in {context}, found {}", show(&t)),
                ))
            }
        })
    }
}

fn show(t: &Tok) -> String {
    match t {
        Tok::Keyword(k) => k.clone(),
        Tok::Number(x) => format!("number {x}"),
        Tok::Str(_) => "a string".into(),
        Tok::Enum(e) => format!(".{e}."),
        Tok::Ref(r) => format!("#{r}"),
        Tok::Binary(_) => "a binary".into(),
        Tok::Dollar => "'$'".into(),
        Tok::Star => "'*'".into(),
        Tok::Open => "'('".into(),
        Tok::Close => "')'".into(),
        Tok::Comma => "','".into(),
        Tok::Semi => "';'".into(),
        Tok::Equals => "'='".into(),
    }
}

/// Parses a Part 21 text. Errors ([`Error::Cad`]) name the line: not a STEP file, a syntax error, a
/// truncated file (no `END-ISO-10303-21;`, or the text ends inside an instance), a duplicate id.
///
/// ```
/// let text = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(1.E-03,2.,-3.5e1));\n\
///             #2=( A() B(#1,.T.,$,*) );\nENDSEC;\nEND-ISO-10303-21;\n";
/// let x = fairfit::io::p21::parse(text).unwrap();
/// assert_eq!(x.data.len(), 2);
/// assert!(x.data[&2].is_complex());
/// ```
pub fn parse(text: &str) -> Result<Exchange> {
    let mut p = Parser {
        lex: Lexer {
            s: text.as_bytes(),
            pos: 0,
            line: 1,
        },
        peeked: None,
        last_line: 1,
        depth: 0,
    };
    match p.peek().ok().flatten() {
        Some(Tok::Keyword(k)) if k == "ISO-10303-21" => {
            p.bump("the file start")?;
            p.expect(Tok::Semi, "the file start")?;
        }
        _ => {
            return Err(Error::Cad(
                "not a STEP file (it does not start with ISO-10303-21;)".into(),
            ))
        }
    }
    let mut x = Exchange::default();
    loop {
        let t = match p.peek()? {
            None => {
                return Err(syntax(
                    p.lex.line,
                    "the file ends without END-ISO-10303-21; (truncated?)",
                ))
            }
            Some(t) => t.clone(),
        };
        p.bump("the file")?;
        match t {
            Tok::Keyword(k) if k == "END-ISO-10303-21" => return Ok(x),
            Tok::Keyword(k) if k == "HEADER" => {
                p.expect(Tok::Semi, "HEADER")?;
                section(&mut p, |p, t| match t {
                    Tok::Keyword(name) => {
                        let part = p.part(name.clone(), &name)?;
                        p.expect(Tok::Semi, &name)?;
                        x.header.push(part);
                        Ok(())
                    }
                    t => Err(syntax(
                        p.last_line,
                        format!("unexpected {} in HEADER", show(&t)),
                    )),
                })?;
            }
            Tok::Keyword(k) if k == "DATA" => {
                // DATA; or, in edition 3, DATA('name',(schema));
                if p.peek()? == Some(&Tok::Open) {
                    p.bump("DATA")?;
                    p.params_until_close("DATA")?;
                }
                p.expect(Tok::Semi, "DATA")?;
                section(&mut p, |p, t| {
                    let line = p.last_line;
                    let Tok::Ref(id) = t else {
                        return Err(syntax(
                            line,
                            format!("expected #n= in DATA, found {}", show(&t)),
                        ));
                    };
                    let context = format!("instance #{id}");
                    p.expect(Tok::Equals, &context)?;
                    let parts = match p.bump(&context)? {
                        Tok::Keyword(name) => vec![p.part(name, &context)?],
                        Tok::Open => {
                            let mut parts = Vec::new();
                            loop {
                                match p.bump(&context)? {
                                    Tok::Keyword(name) => parts.push(p.part(name, &context)?),
                                    Tok::Close if !parts.is_empty() => break,
                                    t => {
                                        return Err(syntax(
                                            p.last_line,
                                            format!(
                                                "expected an entity name in {context}, found {}",
                                                show(&t)
                                            ),
                                        ))
                                    }
                                }
                            }
                            parts
                        }
                        t => {
                            return Err(syntax(
                                p.last_line,
                                format!("expected an entity name in {context}, found {}", show(&t)),
                            ))
                        }
                    };
                    p.expect(Tok::Semi, &context)?;
                    if x.data.insert(id, Instance { parts, line }).is_some() {
                        return Err(syntax(line, format!("instance #{id} is defined twice")));
                    }
                    Ok(())
                })?;
            }
            Tok::Keyword(k) if k == "ANCHOR" || k == "REFERENCE" || k == "SIGNATURE" => {
                // edition 3 sections fairfit does not need: skip to their ENDSEC
                skip_to_endsec(&mut p, &k)?;
            }
            t => {
                return Err(syntax(
                    p.last_line,
                    format!(
                        "expected HEADER, DATA or END-ISO-10303-21, found {}",
                        show(&t)
                    ),
                ))
            }
        }
    }
}

/// Runs `item` on every statement of a section up to its `ENDSEC;`.
fn section(
    p: &mut Parser<'_>,
    mut item: impl FnMut(&mut Parser<'_>, Tok) -> Result<()>,
) -> Result<()> {
    loop {
        let t = p.bump("a section (no ENDSEC;)")?;
        if matches!(&t, Tok::Keyword(k) if k == "ENDSEC") {
            return p.expect(Tok::Semi, "ENDSEC");
        }
        item(p, t)?;
    }
}

fn skip_to_endsec(p: &mut Parser<'_>, name: &str) -> Result<()> {
    loop {
        let t = p.bump(name)?;
        if matches!(&t, Tok::Keyword(k) if k == "ENDSEC") {
            return p.expect(Tok::Semi, "ENDSEC");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wrap(data: &str) -> String {
        format!("ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('X'));\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n")
    }

    #[test]
    fn values_of_every_kind() {
        let x = parse(&wrap(
            "#1 = FOO ( 'it''s' , .UNSPECIFIED., #22, $, *, (1, 2.5E-3, -1.E+02), \n\
             LENGTH_MEASURE(1.E-03), \"0FF\", .5, 3.D2 ) ; /* comment ; #2=BAR(); */",
        ))
        .unwrap();
        let p = &x.data[&1].parts[0];
        assert_eq!(p.name, "FOO");
        assert_eq!(p.params[0], Value::Str("it's".into()));
        assert_eq!(p.params[1], Value::Enum("UNSPECIFIED".into()));
        assert_eq!(p.params[2], Value::Ref(22));
        assert_eq!(p.params[3], Value::Unset);
        assert_eq!(p.params[4], Value::Derived);
        assert_eq!(
            p.params[5],
            Value::List(vec![
                Value::Number(1.0),
                Value::Number(2.5e-3),
                Value::Number(-100.0)
            ])
        );
        assert_eq!(p.params[6].as_f64(), Some(1e-3));
        assert_eq!(p.params[7], Value::Binary("0FF".into()));
        assert_eq!(p.params[8], Value::Number(0.5));
        assert_eq!(p.params[9], Value::Number(300.0));
        assert_eq!(x.data.len(), 1);
    }

    #[test]
    fn complex_instances_keep_their_parts() {
        let x = parse(&wrap(
            "#5=( BOUNDED_CURVE() B_SPLINE_CURVE(1,(#1,#2),.UNSPECIFIED.,.F.,.F.)\n\
             B_SPLINE_CURVE_WITH_KNOTS((2,2),(0.,1.),.UNSPECIFIED.) CURVE() );",
        ))
        .unwrap();
        let i = &x.data[&5];
        assert!(i.is_complex());
        assert_eq!(i.parts.len(), 4);
        assert_eq!(
            i.part("B_SPLINE_CURVE").unwrap().params[0],
            Value::Number(1.0)
        );
        assert!(i.part("BOUNDED_CURVE").unwrap().params.is_empty());
    }

    #[test]
    fn broken_files_give_one_line_errors_with_the_line() {
        let e = parse("hello").unwrap_err().to_string();
        assert!(e.contains("not a STEP file"), "{e}");
        let full = wrap("#1=FOO(1,2);\n#2=BAR((3,4),'x');");
        let cut = &full[..full.find("'x'").unwrap()];
        let e = parse(cut).unwrap_err().to_string();
        assert!(e.contains("line 7") && e.contains("truncated"), "{e}");
        let e = parse(&full.replace("END-ISO-10303-21;", ""))
            .unwrap_err()
            .to_string();
        assert!(e.contains("truncated"), "{e}");
        let e = parse(&wrap("#1=FOO(1,,2);")).unwrap_err().to_string();
        assert!(
            e.contains("line 6") && e.contains("expected a value"),
            "{e}"
        );
        let deep = format!("#1=FOO({}1{});", "(".repeat(100_000), ")".repeat(100_000));
        let e = parse(&wrap(&deep)).unwrap_err().to_string();
        assert!(e.contains("nested deeper than 64"), "{e}");
        let e = parse(&wrap("#1=FOO(1);\n#1=FOO(2);"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("defined twice"), "{e}");
        assert!(!e.contains('\n'));
    }
}
