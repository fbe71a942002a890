//! pbrt-v4's statements: a directive name, its positional arguments (numbers, strings
//! or a bare word, as each directive defines them) and a parameter list of
//! `"type name" value` pairs (a value is one token or a bracketed list). Only syntax
//! is checked here; what the directives and parameters mean is the builder's.

use super::lexer::{tokenize, Kind, Token};

/// Every directive of pbrt-v4's format (and pbrt-v3's `TransformBegin`/`End`).
pub const DIRECTIVES: &[&str] = &[
    "Accelerator",
    "ActiveTransform",
    "AreaLightSource",
    "Attribute",
    "AttributeBegin",
    "AttributeEnd",
    "Camera",
    "ColorSpace",
    "ConcatTransform",
    "CoordinateSystem",
    "CoordSysTransform",
    "Film",
    "Identity",
    "Import",
    "Include",
    "Integrator",
    "LightSource",
    "LookAt",
    "MakeNamedMaterial",
    "MakeNamedMedium",
    "Material",
    "MediumInterface",
    "NamedMaterial",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Option",
    "PixelFilter",
    "ReverseOrientation",
    "Rotate",
    "Sampler",
    "Scale",
    "Shape",
    "Texture",
    "Transform",
    "TransformBegin",
    "TransformEnd",
    "TransformTimes",
    "Translate",
    "WorldBegin",
    "WorldEnd",
];

/// A positional argument.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    Num(f64),
    Str(String),
}

/// One value of a parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum PVal {
    Num(f64),
    Str(String),
    Bool(bool),
}

/// `"type name" values`.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub ty: String,
    pub name: String,
    /// Offset of the declaration string.
    pub pos: usize,
    pub values: Vec<PVal>,
    /// Offset of each value.
    pub value_pos: Vec<usize>,
}

/// One statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Directive {
    pub name: String,
    pub pos: usize,
    pub args: Vec<(Arg, usize)>,
    pub params: Vec<Param>,
}

/// A syntax error at a byte offset.
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    pub pos: usize,
    pub message: String,
}

/// What a directive takes before its parameter list.
enum Shape {
    None,
    Numbers(usize),
    Word,
    Strings(usize),
    /// One string, and a second one when the next token is a string.
    OneOrTwoStrings,
    StringsThenParams(usize),
    Params,
}

fn shape_of(name: &str) -> Option<Shape> {
    Some(match name {
        "AttributeBegin" | "AttributeEnd" | "TransformBegin" | "TransformEnd" | "WorldBegin"
        | "WorldEnd" | "ObjectEnd" | "ReverseOrientation" | "Identity" => Shape::None,
        "Translate" | "Scale" => Shape::Numbers(3),
        "Rotate" => Shape::Numbers(4),
        "LookAt" => Shape::Numbers(9),
        "Transform" | "ConcatTransform" => Shape::Numbers(16),
        "TransformTimes" => Shape::Numbers(2),
        "ActiveTransform" => Shape::Word,
        "CoordinateSystem" | "CoordSysTransform" | "ObjectBegin" | "ObjectInstance" | "Include"
        | "Import" | "NamedMaterial" | "ColorSpace" => Shape::Strings(1),
        "MediumInterface" => Shape::OneOrTwoStrings,
        "Camera" | "Sampler" | "Film" | "Integrator" | "PixelFilter" | "Accelerator" | "Shape"
        | "Material" | "LightSource" | "AreaLightSource" | "MakeNamedMaterial"
        | "MakeNamedMedium" | "Attribute" => Shape::StringsThenParams(1),
        "Texture" => Shape::StringsThenParams(3),
        "Option" => Shape::Params,
        _ => return None,
    })
}

/// Parses a whole file into its directives.
pub fn parse(text: &str) -> Result<Vec<Directive>, SyntaxError> {
    let tokens = tokenize(text).map_err(|e| SyntaxError {
        pos: e.pos,
        message: e.message,
    })?;
    let mut p = Parser {
        tokens: &tokens,
        i: 0,
        end: text.len(),
    };
    let mut out = Vec::new();
    while p.i < tokens.len() {
        out.push(p.directive()?);
    }
    Ok(out)
}

struct Parser<'t> {
    tokens: &'t [Token],
    i: usize,
    end: usize,
}

fn err<T>(pos: usize, message: impl Into<String>) -> Result<T, SyntaxError> {
    Err(SyntaxError {
        pos,
        message: message.into(),
    })
}

fn describe(k: &Kind) -> String {
    match k {
        Kind::Word(w) => format!("`{w}`"),
        Kind::Str(s) => format!("the string \"{s}\""),
        Kind::Open => "`[`".into(),
        Kind::Close => "`]`".into(),
    }
}

impl<'t> Parser<'t> {
    fn peek(&self) -> Option<&'t Token> {
        self.tokens.get(self.i)
    }

    fn next_pos(&self) -> usize {
        self.peek().map_or(self.end, |t| t.pos)
    }

    fn directive(&mut self) -> Result<Directive, SyntaxError> {
        let t = &self.tokens[self.i];
        let Kind::Word(name) = &t.kind else {
            return err(
                t.pos,
                format!("expected a directive name, found {}", describe(&t.kind)),
            );
        };
        let Some(shape) = shape_of(name) else {
            let msg = match crate::pbrt::closest(name, DIRECTIVES) {
                Some(c) => format!("unknown directive `{name}`; did you mean `{c}`?"),
                None => format!("unknown directive `{name}`"),
            };
            return err(t.pos, msg);
        };
        let mut d = Directive {
            name: name.clone(),
            pos: t.pos,
            args: Vec::new(),
            params: Vec::new(),
        };
        self.i += 1;
        match shape {
            Shape::None => {}
            Shape::Numbers(n) => self.numbers(&mut d, n)?,
            Shape::Word => match self.peek() {
                Some(Token {
                    kind: Kind::Word(w),
                    pos,
                }) => {
                    d.args.push((Arg::Str(w.clone()), *pos));
                    self.i += 1;
                }
                _ => {
                    return err(
                        self.next_pos(),
                        format!("{} needs a bare word (StartTime, EndTime or All)", d.name),
                    )
                }
            },
            Shape::Strings(n) => self.strings(&mut d, n)?,
            Shape::OneOrTwoStrings => {
                self.strings(&mut d, 1)?;
                if matches!(
                    self.peek(),
                    Some(Token {
                        kind: Kind::Str(_),
                        ..
                    })
                ) {
                    self.strings(&mut d, 1)?;
                }
            }
            Shape::StringsThenParams(n) => {
                self.strings(&mut d, n)?;
                self.params(&mut d)?;
            }
            Shape::Params => self.params(&mut d)?,
        }
        Ok(d)
    }

    fn numbers(&mut self, d: &mut Directive, n: usize) -> Result<(), SyntaxError> {
        let bracketed = matches!(
            self.peek(),
            Some(Token {
                kind: Kind::Open,
                ..
            })
        );
        if bracketed {
            self.i += 1;
        }
        for k in 0..n {
            match self.peek() {
                Some(Token {
                    kind: Kind::Word(w),
                    pos,
                }) => match parse_number(w) {
                    Some(x) => {
                        d.args.push((Arg::Num(x), *pos));
                        self.i += 1;
                    }
                    None => {
                        return err(
                            *pos,
                            format!("{} expects {n} numbers; `{w}` is not a number", d.name),
                        )
                    }
                },
                other => {
                    let found =
                        other.map_or("the end of the file".to_string(), |t| describe(&t.kind));
                    return err(
                        self.next_pos(),
                        format!("{} expects {n} numbers, found {k} and then {found}", d.name),
                    );
                }
            }
        }
        if bracketed {
            match self.peek() {
                Some(Token {
                    kind: Kind::Close, ..
                }) => self.i += 1,
                _ => {
                    return err(
                        self.next_pos(),
                        format!("{} expects exactly {n} numbers and a closing `]`", d.name),
                    )
                }
            }
        }
        Ok(())
    }

    fn strings(&mut self, d: &mut Directive, n: usize) -> Result<(), SyntaxError> {
        for _ in 0..n {
            match self.peek() {
                Some(Token {
                    kind: Kind::Str(s),
                    pos,
                }) => {
                    d.args.push((Arg::Str(s.clone()), *pos));
                    self.i += 1;
                }
                other => {
                    let found =
                        other.map_or("the end of the file".to_string(), |t| describe(&t.kind));
                    return err(
                        self.next_pos(),
                        format!("{} expects a quoted string here, found {found}", d.name),
                    );
                }
            }
        }
        Ok(())
    }

    fn params(&mut self, d: &mut Directive) -> Result<(), SyntaxError> {
        while let Some(Token {
            kind: Kind::Str(decl),
            pos,
        }) = self.peek().cloned()
        {
            let words: Vec<&str> = decl.split_whitespace().collect();
            if words.len() != 2 {
                return err(
                    pos,
                    format!("bad parameter declaration \"{decl}\": expected \"type name\""),
                );
            }
            let (ty, name) = (words[0].to_string(), words[1].to_string());
            self.i += 1;
            let mut values = Vec::new();
            let mut value_pos = Vec::new();
            match self.peek() {
                Some(Token {
                    kind: Kind::Open, ..
                }) => {
                    self.i += 1;
                    loop {
                        match self.peek() {
                            Some(Token {
                                kind: Kind::Close, ..
                            }) => {
                                self.i += 1;
                                break;
                            }
                            Some(t) => {
                                values.push(value(t)?);
                                value_pos.push(t.pos);
                                self.i += 1;
                            }
                            None => {
                                return err(
                                    pos,
                                    format!("the values of \"{decl}\" have no closing `]`"),
                                )
                            }
                        }
                    }
                }
                Some(
                    t @ Token {
                        kind: Kind::Str(_) | Kind::Word(_),
                        ..
                    },
                ) => {
                    // A bare word that is a directive name ends the list: the value
                    // is missing.
                    if let Kind::Word(w) = &t.kind {
                        if shape_of(w).is_some() {
                            return err(t.pos, format!("parameter \"{decl}\" has no value"));
                        }
                    }
                    values.push(value(t)?);
                    value_pos.push(t.pos);
                    self.i += 1;
                }
                _ => {
                    return err(
                        self.next_pos(),
                        format!("parameter \"{decl}\" has no value"),
                    )
                }
            }
            d.params.push(Param {
                ty,
                name,
                pos,
                values,
                value_pos,
            });
        }
        Ok(())
    }
}

fn value(t: &Token) -> Result<PVal, SyntaxError> {
    Ok(match &t.kind {
        Kind::Str(s) => PVal::Str(s.clone()),
        Kind::Word(w) if w == "true" => PVal::Bool(true),
        Kind::Word(w) if w == "false" => PVal::Bool(false),
        Kind::Word(w) => match parse_number(w) {
            Some(x) => PVal::Num(x),
            None => return err(t.pos, format!("`{w}` is not a number")),
        },
        Kind::Open => return err(t.pos, "a `[` inside a parameter's values"),
        Kind::Close => unreachable!("handled by the caller"),
    })
}

/// A finite decimal number (pbrt's reader rejects NaN and infinity too).
pub fn parse_number(w: &str) -> Option<f64> {
    let first = w.as_bytes().first()?;
    if !(first.is_ascii_digit() || matches!(first, b'-' | b'+' | b'.')) {
        return None;
    }
    w.parse::<f64>().ok().filter(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statements() {
        let d = parse(
            "LookAt 0 0 5  0 0 0  0 1 0\nShape \"sphere\" \"float radius\" 2 \"rgb c\" [1 2 3]\nTexture \"t\" \"spectrum\" \"checkerboard\"\nWorldBegin",
        )
        .unwrap();
        assert_eq!(d.len(), 4);
        assert_eq!(d[0].args.len(), 9);
        assert_eq!(d[1].params[0].values, vec![PVal::Num(2.0)]);
        assert_eq!(d[1].params[1].values.len(), 3);
        assert_eq!(d[2].args.len(), 3);
    }

    #[test]
    fn bracketed_matrix() {
        let d = parse("Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]").unwrap();
        assert_eq!(d[0].args.len(), 16);
    }

    #[test]
    fn errors_have_places() {
        assert_eq!(parse("Shap \"sphere\"").unwrap_err().pos, 0);
        assert!(parse("Shap").unwrap_err().message.contains("Shape"));
        assert_eq!(parse("Translate 1 x 2").unwrap_err().pos, 12);
        assert_eq!(parse("Shape \"s\" \"float\" 1").unwrap_err().pos, 10);
        assert!(parse("Shape \"s\" \"float r\" [1").is_err());
        assert!(parse("Shape \"s\" \"float r\" WorldBegin").is_err());
        assert!(parse("Translate 1 2").is_err());
    }
}
