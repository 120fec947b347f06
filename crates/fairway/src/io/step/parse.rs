//! ISO 10303-21 (Part 21) clear-text exchange structure: a tokenizer and a
//! parser into entity instances, independent of any schema.
//!
//! Read: the header section's records, then every data section's instances
//! `#n = NAME(params);` (simple) and `#n = (A(..) B(..) ..);` (complex),
//! with parameters that are integers, reals, strings (`''` and the `\X2\`,
//! `\X\`, `\\` escapes decoded), enumerations `.T.`, references `#n`, `$`,
//! `*`, binaries, nested lists and typed parameters `LENGTH_MEASURE(1.)`.
//! Comments `/* */` and whitespace may stand between any two tokens;
//! keywords are matched without regard to case.
//!
//! A malformed instance is skipped up to its `;` and reported in
//! [`Exchange::errors`]; only a file that is not Part 21 at all is an
//! error. Everything allocated grows with the tokens actually read (never
//! from a count in the file), and nesting is limited to `MAX_DEPTH` so a
//! hostile file cannot exhaust the stack.

use std::collections::HashMap;

/// The deepest nesting of lists and typed parameters accepted.
pub(crate) const MAX_DEPTH: usize = 64;

/// One parameter of a record.
#[derive(Debug, Clone, PartialEq)]
pub enum Param {
    /// An integer (no decimal point).
    Int(i64),
    /// A real.
    Real(f64),
    /// A string, escapes decoded.
    Str(String),
    /// An enumeration or logical value, without its dots (`T`, `UNSPECIFIED`).
    Enum(String),
    /// A reference to an instance, `#n`.
    Ref(u64),
    /// `$`: unset.
    Null,
    /// `*`: derived.
    Derived,
    /// A binary `"..."` (kept as text).
    Binary(String),
    /// A list `(a, b, ...)`.
    List(Vec<Param>),
    /// A typed parameter `NAME(value)`.
    Typed(String, Box<Param>),
}

impl Param {
    /// The number, if this is an integer or a real (possibly typed).
    pub fn real(&self) -> Option<f64> {
        match self {
            Param::Int(i) => Some(*i as f64),
            Param::Real(x) => Some(*x),
            Param::Typed(_, p) => p.real(),
            _ => None,
        }
    }

    /// The list, if this is one.
    pub fn list(&self) -> Option<&[Param]> {
        match self {
            Param::List(v) => Some(v),
            _ => None,
        }
    }
}

/// A record: an entity name (upper case) and its parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Entity name, upper case.
    pub name: String,
    /// Parameters.
    pub params: Vec<Param>,
}

/// An entity instance of the data section.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// The instance number `n` of `#n`.
    pub id: u64,
    /// One record (simple instance) or several (complex instance).
    pub records: Vec<Record>,
    /// Whether the instance was written in the complex form `(A() B())`.
    pub complex: bool,
    /// The line it starts on (1-based).
    pub line: usize,
}

impl Instance {
    /// The record of this name, if the instance has one.
    pub fn record(&self, name: &str) -> Option<&Record> {
        self.records.iter().find(|r| r.name == name)
    }
}

/// A parsed exchange file.
#[derive(Debug, Clone, Default)]
pub struct Exchange {
    /// Header section records (`FILE_DESCRIPTION`, `FILE_NAME`, `FILE_SCHEMA`, ...).
    pub header: Vec<Record>,
    /// Data section instances, in file order.
    pub instances: Vec<Instance>,
    /// Instance number → index in `instances`.
    pub index: HashMap<u64, usize>,
    /// What could not be read, one message each (`line 12: #34: ...`).
    pub errors: Vec<String>,
}

impl Exchange {
    /// The instance `#id`, if the file has it.
    pub fn get(&self, id: u64) -> Option<&Instance> {
        self.index.get(&id).map(|&k| &self.instances[k])
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Keyword(String),
    Int(i64),
    Real(f64),
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
    Eof,
    /// Bytes the lexer could not read, with the reason: an error when the parser reaches it, so a bad
    /// byte costs only the instance it is in.
    Bad(String),
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Keyword(k) => format!("the word {k}"),
        Tok::Int(_) | Tok::Real(_) => "a number".into(),
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
        Tok::Eof => "the end of the file".into(),
        Tok::Bad(why) => why.clone(),
    }
}

/// The tokenizer: one token at a time, with its line.
struct Lexer<'a> {
    s: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lexer<'a> {
    fn skip_blanks(&mut self) -> Result<(), String> {
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
                            None => return Err(format!("a comment opened on line {start} is never closed")),
                            Some(b'*') if self.s.get(self.pos + 1) == Some(&b'/') => {
                                self.pos += 2;
                                break;
                            }
                            Some(c) => {
                                self.line += usize::from(*c == b'\n');
                                self.pos += 1;
                            }
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn take_while(&mut self, f: impl Fn(u8) -> bool) -> &'a [u8] {
        let start = self.pos;
        while self.s.get(self.pos).is_some_and(|&c| f(c)) {
            self.pos += 1;
        }
        &self.s[start..self.pos]
    }

    /// The next token; what cannot be read comes as [`Tok::Bad`] (always past at least one byte, so
    /// reading on never loops).
    fn next(&mut self) -> Tok {
        self.token().unwrap_or_else(Tok::Bad)
    }

    fn token(&mut self) -> Result<Tok, String> {
        self.skip_blanks()?;
        let Some(&c) = self.s.get(self.pos) else {
            return Ok(Tok::Eof);
        };
        let single = match c {
            b'(' => Some(Tok::Open),
            b')' => Some(Tok::Close),
            b',' => Some(Tok::Comma),
            b';' => Some(Tok::Semi),
            b'=' => Some(Tok::Equals),
            b'$' => Some(Tok::Dollar),
            b'*' => Some(Tok::Star),
            _ => None,
        };
        if let Some(t) = single {
            self.pos += 1;
            return Ok(t);
        }
        match c {
            b'\'' => self.string(),
            b'"' => {
                self.pos += 1;
                let b = self.take_while(|c| c != b'"');
                if self.s.get(self.pos) != Some(&b'"') {
                    return Err("a binary value is never closed".into());
                }
                self.pos += 1;
                Ok(Tok::Binary(String::from_utf8_lossy(b).into_owned()))
            }
            b'#' => {
                self.pos += 1;
                let d = self.take_while(|c| c.is_ascii_digit());
                let n = std::str::from_utf8(d).ok().and_then(|d| d.parse::<u64>().ok());
                n.map(Tok::Ref)
                    .ok_or_else(|| "'#' is not followed by an instance number".into())
            }
            b'.' if self
                .s
                .get(self.pos + 1)
                .is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_') =>
            {
                self.pos += 1;
                let e = self.take_while(|c| c.is_ascii_alphanumeric() || c == b'_');
                let e = String::from_utf8_lossy(e).to_ascii_uppercase();
                if self.s.get(self.pos) != Some(&b'.') {
                    return Err(format!("the enumeration .{e} has no closing '.'"));
                }
                self.pos += 1;
                Ok(Tok::Enum(e))
            }
            b'+' | b'-' | b'0'..=b'9' | b'.' => self.number(),
            c if c.is_ascii_alphabetic() || c == b'!' => {
                let k = self.take_while(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'-' || c == b'!');
                Ok(Tok::Keyword(String::from_utf8_lossy(k).to_ascii_uppercase()))
            }
            c => {
                self.pos += 1;
                Err(format!("unexpected character {:?}", char::from(c)))
            }
        }
    }

    fn number(&mut self) -> Result<Tok, String> {
        let t = self.take_while(|c| c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.' | b'E' | b'e'));
        let t = std::str::from_utf8(t).unwrap_or("");
        if !t.bytes().any(|c| c.is_ascii_digit()) {
            return Err(format!("{t:?} is not a number"));
        }
        if !t.contains(['.', 'E', 'e'])
            && let Ok(i) = t.parse::<i64>()
        {
            return Ok(Tok::Int(i));
        }
        t.parse::<f64>()
            .map(Tok::Real)
            .map_err(|_| format!("{t:?} is not a number"))
    }

    fn string(&mut self) -> Result<Tok, String> {
        let start = self.line;
        self.pos += 1;
        let mut raw = Vec::new();
        loop {
            match self.s.get(self.pos) {
                None => return Err(format!("a string opened on line {start} is never closed")),
                Some(b'\'') if self.s.get(self.pos + 1) == Some(&b'\'') => {
                    raw.push(b'\'');
                    self.pos += 2;
                }
                Some(b'\'') => {
                    self.pos += 1;
                    return Ok(Tok::Str(decode_string(&raw)));
                }
                Some(&c) => {
                    self.line += usize::from(c == b'\n');
                    if c != b'\n' && c != b'\r' {
                        raw.push(c);
                    }
                    self.pos += 1;
                }
            }
        }
    }
}

/// A Part 21 string's escapes decoded: `\\`, `\X\hh` (ISO 8859-1), `\X2\hhhh..\X0\` (UTF-16) and
/// `\X4\hhhhhhhh..\X0\`; other bytes as UTF-8 where valid. Malformed escapes are kept as written.
fn decode_string(raw: &[u8]) -> String {
    let text = String::from_utf8_lossy(raw);
    let mut out = String::new();
    let mut rest: &str = &text;
    while let Some(k) = rest.find('\\') {
        out.push_str(&rest[..k]);
        rest = &rest[k..];
        if let Some(r) = rest.strip_prefix("\\\\") {
            out.push('\\');
            rest = r;
        } else if let Some((decoded, r)) = wide_escape(rest) {
            out.push_str(&decoded);
            rest = r;
        } else if let Some(h) = rest.strip_prefix("\\X\\").and_then(|r| r.get(..2))
            && let Ok(b) = u8::from_str_radix(h, 16)
        {
            out.push(char::from(b));
            rest = &rest[5..];
        } else {
            out.push('\\');
            rest = &rest[1..];
        }
    }
    out.push_str(rest);
    out
}

/// `\X2\...\X0\` or `\X4\...\X0\` at the start of `s`: the decoded text and the rest.
fn wide_escape(s: &str) -> Option<(String, &str)> {
    let (width, body) = if let Some(b) = s.strip_prefix("\\X2\\") {
        (4, b)
    } else {
        (8, s.strip_prefix("\\X4\\")?)
    };
    let end = body.find("\\X0\\")?;
    let hex = &body[..end];
    if hex.len() % width != 0 {
        return None;
    }
    let mut units = Vec::new();
    for k in (0..hex.len()).step_by(width) {
        units.push(u32::from_str_radix(hex.get(k..k + width)?, 16).ok()?);
    }
    let text = if width == 4 {
        let u16s: Vec<u16> = units.iter().map(|&u| u as u16).collect();
        String::from_utf16_lossy(&u16s)
    } else {
        units.iter().map(|&u| char::from_u32(u).unwrap_or('\u{fffd}')).collect()
    };
    Some((text, &body[end + 4..]))
}

/// The parser: a lexer with one token of look-ahead.
struct Parser<'a> {
    lex: Lexer<'a>,
    tok: Tok,
    line: usize,
}

impl<'a> Parser<'a> {
    fn new(s: &'a [u8]) -> Self {
        let mut lex = Lexer { s, pos: 0, line: 1 };
        let tok = lex.next();
        let line = lex.line;
        Self { lex, tok, line }
    }

    /// Take the current token and read the next; a [`Tok::Bad`] taken is its error.
    fn bump(&mut self) -> Result<Tok, String> {
        let next = self.lex.next();
        self.line = self.lex.line;
        match std::mem::replace(&mut self.tok, next) {
            Tok::Bad(why) => Err(why),
            t => Ok(t),
        }
    }

    fn expect(&mut self, t: Tok) -> Result<(), String> {
        if self.tok == t {
            self.bump()?;
            Ok(())
        } else if let Tok::Bad(why) = &self.tok {
            Err(why.clone())
        } else {
            Err(format!("expected {} but found {}", describe(&t), describe(&self.tok)))
        }
    }

    fn keyword(&mut self) -> Result<String, String> {
        match self.bump()? {
            Tok::Keyword(k) => Ok(k),
            t => Err(format!("expected an entity name but found {}", describe(&t))),
        }
    }

    /// `(p, p, ...)` after the opening parenthesis was seen.
    fn params(&mut self, depth: usize) -> Result<Vec<Param>, String> {
        if depth > MAX_DEPTH {
            return Err(format!("lists nested more than {MAX_DEPTH} deep"));
        }
        self.expect(Tok::Open)?;
        let mut v = Vec::new();
        if self.tok == Tok::Close {
            self.bump()?;
            return Ok(v);
        }
        loop {
            v.push(self.param(depth)?);
            match self.bump()? {
                Tok::Comma => continue,
                Tok::Close => return Ok(v),
                t => return Err(format!("expected ',' or ')' in a list but found {}", describe(&t))),
            }
        }
    }

    fn param(&mut self, depth: usize) -> Result<Param, String> {
        if self.tok == Tok::Open {
            return Ok(Param::List(self.params(depth + 1)?));
        }
        if let Tok::Keyword(k) = &self.tok {
            let name = k.clone();
            self.bump()?;
            let mut inner = self.params(depth + 1)?;
            if inner.len() != 1 {
                return Err(format!(
                    "the typed value {name}(..) holds {} values, not one",
                    inner.len()
                ));
            }
            return Ok(Param::Typed(name, Box::new(inner.remove(0))));
        }
        Ok(match self.bump()? {
            Tok::Int(i) => Param::Int(i),
            Tok::Real(x) => Param::Real(x),
            Tok::Str(s) => Param::Str(s),
            Tok::Enum(e) => Param::Enum(e),
            Tok::Ref(r) => Param::Ref(r),
            Tok::Binary(b) => Param::Binary(b),
            Tok::Dollar => Param::Null,
            Tok::Star => Param::Derived,
            t => return Err(format!("expected a value but found {}", describe(&t))),
        })
    }

    fn record(&mut self) -> Result<Record, String> {
        let name = self.keyword()?;
        let params = self.params(0)?;
        Ok(Record { name, params })
    }

    /// `#n = ...;` after `#n` was taken.
    fn instance(&mut self, id: u64, line: usize) -> Result<Instance, String> {
        self.expect(Tok::Equals)?;
        let (records, complex) = if self.tok == Tok::Open {
            self.bump()?;
            let mut v = Vec::new();
            while self.tok != Tok::Close {
                v.push(self.record()?);
            }
            self.bump()?;
            if v.is_empty() {
                return Err("an empty complex instance ()".into());
            }
            (v, true)
        } else {
            (vec![self.record()?], false)
        };
        self.expect(Tok::Semi)?;
        Ok(Instance {
            id,
            records,
            complex,
            line,
        })
    }

    /// Skip to just past the next `;` (or to the end).
    fn recover(&mut self) {
        while !matches!(self.bump(), Ok(Tok::Semi) | Ok(Tok::Eof)) {}
    }
}

/// Parse an exchange file. `Err` only when it is not Part 21 (no `ISO-10303-21;` at its start).
pub fn parse(bytes: &[u8]) -> Result<Exchange, String> {
    let not_step = |why: String| format!("not a STEP (ISO 10303-21) file: {why}");
    let mut p = Parser::new(bytes);
    match p.bump().map_err(not_step)? {
        Tok::Keyword(k) if k == "ISO-10303-21" => {}
        t => return Err(not_step(format!("it begins with {}, not ISO-10303-21;", describe(&t)))),
    }
    p.expect(Tok::Semi).map_err(not_step)?;
    let mut ex = Exchange::default();
    let mut ended = false;
    while p.tok != Tok::Eof {
        let line = p.line;
        let step = match &p.tok {
            Tok::Keyword(k) if k == "END-ISO-10303-21" => {
                ended = true;
                break;
            }
            Tok::Keyword(k) if k == "HEADER" => section_start(&mut p, false),
            Tok::Keyword(k) if k == "DATA" => section_start(&mut p, true),
            Tok::Keyword(k) if k == "ENDSEC" => p.bump().and_then(|_| p.expect(Tok::Semi)),
            Tok::Ref(_) => data_instance(&mut p, &mut ex, line),
            Tok::Keyword(_) => p.record().and_then(|r| {
                ex.header.push(r);
                p.expect(Tok::Semi)
            }),
            Tok::Bad(why) => {
                // between instances: report the bad bytes and go on with the next token
                ex.errors.push(format!("line {line}: {why}"));
                let _ = p.bump();
                continue;
            }
            t => Err(format!("unexpected {}", describe(t))),
        };
        if let Err(e) = step {
            ex.errors.push(format!("line {line}: {e}"));
            p.recover();
        }
    }
    if !ended {
        ex.errors.push(format!(
            "line {}: the file ends without END-ISO-10303-21; (truncated?): read up to there",
            p.line
        ));
    }
    Ok(ex)
}

/// `HEADER;` or `DATA;` / `DATA(...);` (Part 21 edition 3 names its data sections).
fn section_start(p: &mut Parser<'_>, data: bool) -> Result<(), String> {
    p.bump()?;
    if data && p.tok == Tok::Open {
        p.params(0)?;
    }
    p.expect(Tok::Semi)
}

fn data_instance(p: &mut Parser<'_>, ex: &mut Exchange, line: usize) -> Result<(), String> {
    let Tok::Ref(id) = p.bump()? else {
        return Err("expected an instance number".into());
    };
    let inst = p.instance(id, line).map_err(|e| format!("#{id}: {e}"))?;
    if ex.index.contains_key(&id) {
        // the instance was read to its end: nothing to recover
        ex.errors.push(format!(
            "line {line}: #{id} is defined twice: the second definition is ignored"
        ));
        return Ok(());
    }
    ex.index.insert(id, ex.instances.len());
    ex.instances.push(inst);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(s: &str) -> Exchange {
        parse(s.as_bytes()).unwrap()
    }

    #[test]
    fn simple_and_complex_instances_with_all_kinds_of_parameters() {
        let ex = parse_ok(
            "ISO-10303-21;\nHEADER;FILE_NAME('a''b',$);ENDSEC;\nDATA;\n\
             #1 = cartesian_point ( 'p\\X2\\00E9\\X0\\' , ( 1. , -2.5E-3 , 4 ) ) ;\n\
             /* a comment; with ; inside */\n\
             #2=(A()B(#1,.T.,$,*,\"0F\")C(LENGTH_MEASURE(1.E2),((1,2),(3,4))));\n\
             ENDSEC;\nEND-ISO-10303-21;\n",
        );
        assert!(ex.errors.is_empty(), "{:?}", ex.errors);
        assert_eq!(ex.header[0].params[0], Param::Str("a'b".into()));
        let p = ex.get(1).unwrap();
        assert_eq!(p.records[0].name, "CARTESIAN_POINT");
        assert_eq!(p.records[0].params[0], Param::Str("pé".into()));
        assert_eq!(
            p.records[0].params[1],
            Param::List(vec![Param::Real(1.0), Param::Real(-2.5e-3), Param::Int(4)])
        );
        let c = ex.get(2).unwrap();
        assert!(c.complex);
        let names: Vec<_> = c.records.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["A", "B", "C"]);
        assert_eq!(
            c.record("B").unwrap().params,
            vec![
                Param::Ref(1),
                Param::Enum("T".into()),
                Param::Null,
                Param::Derived,
                Param::Binary("0F".into())
            ]
        );
        assert_eq!(c.record("C").unwrap().params[0].real(), Some(100.0));
        assert_eq!(c.line, 6);
    }

    #[test]
    fn a_bad_instance_is_skipped_and_reported_and_the_rest_is_read() {
        let ex = parse_ok("ISO-10303-21;\nDATA;\n#1=A(1,,2);\n#2=B('x;y');\n#2=C();\n#3=D(%);\n#4=E(1);\n");
        assert_eq!(ex.instances.iter().map(|i| i.id).collect::<Vec<_>>(), [2, 4]);
        assert_eq!(ex.errors.len(), 4, "{:?}", ex.errors);
        assert!(
            ex.errors[0].starts_with("line 3: #1: expected a value but found ','"),
            "{:?}",
            ex.errors
        );
        assert!(ex.errors[1].contains("#2 is defined twice"));
        assert!(ex.errors[2].contains("unexpected character '%'"));
        assert!(ex.errors[3].contains("ends without END-ISO-10303-21"));
    }

    #[test]
    fn a_bad_byte_between_instances_costs_no_instance() {
        let ex = parse_ok("ISO-10303-21;DATA;#1=A(1);%#2=B(2);\n@ #3=C(3);ENDSEC;END-ISO-10303-21;");
        assert_eq!(ex.instances.iter().map(|i| i.id).collect::<Vec<_>>(), [1, 2, 3]);
        assert_eq!(
            ex.errors,
            ["line 1: unexpected character '%'", "line 2: unexpected character '@'"]
        );
        // an unclosed string or comment runs to the end: what came before is kept
        for tail in ["#3=C('open);", "/* #3=C(3);"] {
            let ex = parse_ok(&format!("ISO-10303-21;DATA;#1=A(1);#2=B(2);{tail}"));
            assert_eq!(ex.instances.len(), 2, "{tail}");
            assert!(ex.errors[0].contains("never closed"), "{:?}", ex.errors);
        }
    }

    #[test]
    fn not_part_21_and_deep_nesting_are_refused_cleanly() {
        let e = parse(b"hello").unwrap_err();
        assert!(e.starts_with("not a STEP (ISO 10303-21) file"), "{e}");
        let deep = format!(
            "ISO-10303-21;DATA;#1=A({}1{});ENDSEC;END-ISO-10303-21;",
            "(".repeat(10_000),
            ")".repeat(10_000)
        );
        let ex = parse_ok(&deep);
        assert!(ex.instances.is_empty());
        assert!(ex.errors[0].contains("nested more than 64 deep"), "{:?}", ex.errors);
    }
}
