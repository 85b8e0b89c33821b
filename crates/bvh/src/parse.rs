//! Lexer and parser for BVH text.
//!
//! Tolerates what real exporters write: CRLF or CR line ends, blank lines, tabs, `Frames:<TAB>n`
//! or `Frames:n`, `.0083333` and scientific notation, joint names with spaces, `{` on the joint's
//! line, leaf joints without End Site, several roots, and frame values split across lines.
//! Every error carries the line and column where it was noticed.

use crate::skeleton::{Bvh, Channel, Joint, Motion, Skeleton, Vec3};

/// Hierarchies nested deeper than this are refused (real skeletons are a few dozen deep); the
/// limit keeps hostile input from exhausting the stack.
pub const MAX_DEPTH: usize = 1000;

/// What went wrong while parsing.
///
/// More kinds may come in later versions, so matches need a `_` arm.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParseErrorKind {
    #[error("the file is empty")]
    Empty,
    #[error("unexpected end of file: expected {expected}")]
    UnexpectedEof { expected: String },
    #[error("expected {expected}, found `{found}`")]
    Unexpected { expected: String, found: String },
    #[error("`{0}` is not a finite number")]
    NotANumber(String),
    #[error("`{0}` is not a frame count")]
    BadCount(String),
    #[error("`{0}` is not a channel count")]
    BadChannelCount(String),
    #[error("unknown channel `{0}`")]
    UnknownChannel(String),
    #[error("joint without a name")]
    MissingName,
    #[error("hierarchy nested deeper than {MAX_DEPTH} joints")]
    TooDeep,
    #[error(
        "the file declares {frames} frames but the data ends after {found} of {expected} values"
    )]
    TooFewValues {
        frames: usize,
        expected: usize,
        found: usize,
    },
    #[error("extra value `{found}` after the {expected} values that Frames: announces")]
    TooManyValues { expected: usize, found: String },
    #[error("{frames} frames of {channels} channels is too large")]
    TooLarge { frames: usize, channels: usize },
}

/// A parse failure and where it happened (1-based line and column; columns count characters).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}, column {column}: {kind}")]
pub struct ParseError {
    pub line: usize,
    pub column: usize,
    pub kind: ParseErrorKind,
}

#[derive(Debug, Clone, Copy)]
struct Token<'a> {
    text: &'a str,
    line: usize,
    column: usize,
}

/// Splits on whitespace; `{` and `}` are tokens of their own even when glued to a name.
struct Lexer<'a> {
    src: &'a str,
    pos: usize,
    line: usize,
    column: usize,
    peeked: Option<Option<Token<'a>>>,
}

impl<'a> Lexer<'a> {
    fn new(src: &'a str) -> Self {
        Lexer {
            src,
            pos: 0,
            line: 1,
            column: 1,
            peeked: None,
        }
    }

    fn scan(&mut self) -> Option<Token<'a>> {
        let bytes = self.src.as_bytes();
        // Skip whitespace, counting lines: CRLF is one line end, a lone CR is one too.
        while self.pos < bytes.len() {
            match bytes[self.pos] {
                b'\n' => {
                    self.line += 1;
                    self.column = 1;
                    self.pos += 1;
                }
                b'\r' => {
                    self.line += 1;
                    self.column = 1;
                    self.pos += 1;
                    if bytes.get(self.pos) == Some(&b'\n') {
                        self.pos += 1;
                    }
                }
                b' ' | b'\t' | b'\x0b' | b'\x0c' => {
                    self.pos += 1;
                    self.column += 1;
                }
                _ => break,
            }
        }
        if self.pos >= bytes.len() {
            return None;
        }
        let start = self.pos;
        let (line, column) = (self.line, self.column);
        if matches!(bytes[start], b'{' | b'}') {
            self.pos += 1;
            self.column += 1;
        } else {
            while self.pos < bytes.len()
                && !matches!(
                    bytes[self.pos],
                    b' ' | b'\t' | b'\n' | b'\r' | b'\x0b' | b'\x0c' | b'{' | b'}'
                )
            {
                // Count characters, not bytes, for the column of later tokens.
                if bytes[self.pos] & 0xC0 != 0x80 {
                    self.column += 1;
                }
                self.pos += 1;
            }
        }
        // Token boundaries fall on ASCII bytes, so the slice is valid UTF-8.
        let text = self.src.get(start..self.pos).unwrap_or("");
        Some(Token { text, line, column })
    }

    fn next(&mut self) -> Option<Token<'a>> {
        match self.peeked.take() {
            Some(t) => t,
            None => self.scan(),
        }
    }

    fn peek(&mut self) -> Option<Token<'a>> {
        if self.peeked.is_none() {
            let t = self.scan();
            self.peeked = Some(t);
        }
        self.peeked.flatten()
    }

    fn eof_error(&self, expected: &str) -> ParseError {
        ParseError {
            line: self.line,
            column: self.column,
            kind: ParseErrorKind::UnexpectedEof {
                expected: expected.to_string(),
            },
        }
    }

    fn expect_any(&mut self, expected: &str) -> Result<Token<'a>, ParseError> {
        self.next().ok_or_else(|| self.eof_error(expected))
    }

    fn expect(&mut self, word: &str) -> Result<Token<'a>, ParseError> {
        let t = self.expect_any(&format!("`{word}`"))?;
        if t.text.eq_ignore_ascii_case(word) {
            Ok(t)
        } else {
            Err(unexpected(t, &format!("`{word}`")))
        }
    }

    fn number(&mut self, expected: &str) -> Result<f64, ParseError> {
        let t = self.expect_any(expected)?;
        number(t)
    }
}

fn unexpected(t: Token, expected: &str) -> ParseError {
    ParseError {
        line: t.line,
        column: t.column,
        kind: ParseErrorKind::Unexpected {
            expected: expected.to_string(),
            found: t.text.to_string(),
        },
    }
}

fn number(t: Token) -> Result<f64, ParseError> {
    match t.text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(ParseError {
            line: t.line,
            column: t.column,
            kind: ParseErrorKind::NotANumber(t.text.to_string()),
        }),
    }
}

/// Parse BVH text.
pub fn parse(src: &str) -> Result<Bvh, ParseError> {
    let mut lx = Lexer::new(src);
    let first = lx.next().ok_or(ParseError {
        line: 1,
        column: 1,
        kind: ParseErrorKind::Empty,
    })?;
    if !first.text.eq_ignore_ascii_case("HIERARCHY") {
        return Err(unexpected(first, "`HIERARCHY`"));
    }
    let mut joints: Vec<Joint> = Vec::new();
    let mut channels = 0usize;
    loop {
        let t = lx.expect_any("`ROOT` or `MOTION`")?;
        if t.text.eq_ignore_ascii_case("ROOT") {
            parse_joint(&mut lx, t, None, 0, &mut joints, &mut channels)?;
        } else if t.text.eq_ignore_ascii_case("MOTION") {
            if joints.is_empty() {
                return Err(unexpected(t, "`ROOT`"));
            }
            break;
        } else {
            return Err(unexpected(t, "`ROOT` or `MOTION`"));
        }
    }
    let (frames, frame_time) = parse_motion_header(&mut lx)?;
    let total = frames.checked_mul(channels).ok_or(ParseError {
        line: lx.line,
        column: lx.column,
        kind: ParseErrorKind::TooLarge { frames, channels },
    })?;
    // Every value takes at least two bytes (a digit and a separator), so the remaining input
    // bounds what is worth reserving: a lying `Frames:` cannot force a huge allocation.
    let remaining = src.len().saturating_sub(lx.pos);
    let mut values = Vec::with_capacity(total.min(remaining / 2 + 1));
    while values.len() < total {
        match lx.next() {
            Some(t) => values.push(number(t)?),
            None => {
                return Err(ParseError {
                    line: lx.line,
                    column: lx.column,
                    kind: ParseErrorKind::TooFewValues {
                        frames,
                        expected: total,
                        found: values.len(),
                    },
                })
            }
        }
    }
    if let Some(t) = lx.next() {
        return Err(ParseError {
            line: t.line,
            column: t.column,
            kind: ParseErrorKind::TooManyValues {
                expected: total,
                found: t.text.to_string(),
            },
        });
    }
    Ok(Bvh {
        skeleton: Skeleton { joints },
        motion: Motion {
            frame_time,
            frames,
            channels,
            values,
        },
    })
}

/// `text` without an ASCII `prefix` (compared case-insensitively), when something follows it.
fn strip_prefix_ci<'a>(text: &'a str, prefix: &str) -> Option<&'a str> {
    let head = text.get(..prefix.len())?;
    let rest = text.get(prefix.len()..)?;
    (head.eq_ignore_ascii_case(prefix) && !rest.is_empty()).then_some(rest)
}

/// `Frames: n` and `Frame Time: t`, with or without a space after the colon.
fn parse_motion_header(lx: &mut Lexer) -> Result<(usize, f64), ParseError> {
    let t = lx.expect_any("`Frames:`")?;
    let count_tok = if t.text.eq_ignore_ascii_case("Frames:") {
        lx.expect_any("the frame count")?
    } else if let Some(rest) = strip_prefix_ci(t.text, "Frames:") {
        Token {
            text: rest,
            line: t.line,
            column: t.column + 7,
        }
    } else {
        return Err(unexpected(t, "`Frames:`"));
    };
    let frames = count_tok.text.parse::<usize>().map_err(|_| ParseError {
        line: count_tok.line,
        column: count_tok.column,
        kind: ParseErrorKind::BadCount(count_tok.text.to_string()),
    })?;
    lx.expect("Frame")?;
    let t = lx.expect_any("`Time:`")?;
    let frame_time = if t.text.eq_ignore_ascii_case("Time:") {
        lx.number("the frame time")?
    } else if let Some(rest) = strip_prefix_ci(t.text, "Time:") {
        number(Token {
            text: rest,
            line: t.line,
            column: t.column + 5,
        })?
    } else {
        return Err(unexpected(t, "`Time:`"));
    };
    Ok((frames, frame_time))
}

/// Parse one ROOT or JOINT block; `kw` is its keyword token. Pushes the joint, then its
/// descendants, so joints stay in depth-first order.
fn parse_joint(
    lx: &mut Lexer,
    kw: Token,
    parent: Option<usize>,
    depth: usize,
    joints: &mut Vec<Joint>,
    channels: &mut usize,
) -> Result<(), ParseError> {
    if depth >= MAX_DEPTH {
        return Err(ParseError {
            line: kw.line,
            column: kw.column,
            kind: ParseErrorKind::TooDeep,
        });
    }
    // The name is every word on the keyword's line, up to an optional `{`.
    let mut words = Vec::new();
    let mut brace_seen = false;
    while let Some(t) = lx.peek() {
        if t.line != kw.line {
            break;
        }
        lx.next();
        if t.text == "{" {
            brace_seen = true;
            break;
        }
        words.push(t.text);
    }
    if words.is_empty() {
        return Err(ParseError {
            line: kw.line,
            column: kw.column,
            kind: ParseErrorKind::MissingName,
        });
    }
    if !brace_seen {
        lx.expect("{")?;
    }
    let index = joints.len();
    joints.push(Joint {
        name: words.join(" "),
        parent,
        offset: [0.0; 3],
        channels: Vec::new(),
        first_channel: *channels,
        end_site: None,
    });
    loop {
        let t = lx.expect_any("`}`")?;
        let word = t.text;
        if word.eq_ignore_ascii_case("OFFSET") {
            joints[index].offset = offset(lx)?;
        } else if word.eq_ignore_ascii_case("CHANNELS") {
            if !joints[index].channels.is_empty() || joints.len() != index + 1 {
                return Err(unexpected(t, "CHANNELS once, before child joints"));
            }
            let n_tok = lx.expect_any("the channel count")?;
            let n = n_tok.text.parse::<usize>().map_err(|_| ParseError {
                line: n_tok.line,
                column: n_tok.column,
                kind: ParseErrorKind::BadChannelCount(n_tok.text.to_string()),
            })?;
            let mut list = Vec::new();
            for _ in 0..n {
                let c = lx.expect_any("a channel name")?;
                list.push(Channel::from_name(c.text).ok_or_else(|| ParseError {
                    line: c.line,
                    column: c.column,
                    kind: ParseErrorKind::UnknownChannel(c.text.to_string()),
                })?);
            }
            *channels += list.len();
            joints[index].channels = list;
        } else if word.eq_ignore_ascii_case("JOINT") {
            parse_joint(lx, t, Some(index), depth + 1, joints, channels)?;
        } else if word.eq_ignore_ascii_case("End") {
            lx.expect("Site")?;
            lx.expect("{")?;
            lx.expect("OFFSET")?;
            let o = offset(lx)?;
            lx.expect("}")?;
            joints[index].end_site = Some(o);
        } else if word == "}" {
            return Ok(());
        } else {
            return Err(unexpected(t, "OFFSET, CHANNELS, JOINT, End Site or `}`"));
        }
    }
}

fn offset(lx: &mut Lexer) -> Result<Vec3, ParseError> {
    Ok([
        lx.number("an OFFSET value")?,
        lx.number("an OFFSET value")?,
        lx.number("an OFFSET value")?,
    ])
}
