//! Text that crosses a boundary: what e3d prints to a terminal, writes
//! into SVG, HTML and CSV, and reads back from its own output files
//! (regular files only, of bounded size, never blocking on open).

use std::borrow::Cow;
use std::fmt::Write as _;
use std::io::{self, BufRead, Read};
use std::path::Path;

/// The most characters of a name, a command or a line an error message
/// shows; the rest is cut and its length said.
pub const MAX_ECHO_CHARS: usize = 80;

/// Whether a terminal may act on `c` or it changes how the text around it
/// shows: C0 (ESC, BEL, CR, ...), DEL and C1, the bidirectional controls
/// (U+202E shows `abc` as `cba`), the separators U+2028 and U+2029.
fn is_terminal_control(c: char) -> bool {
    c.is_control() || is_bidi_control(c) || matches!(c, '\u{2028}' | '\u{2029}')
}

/// The bidirectional formatting characters: marks (U+200E, U+200F,
/// U+061C), embeddings and overrides (U+202A to U+202E) and isolates
/// (U+2066 to U+2069).
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{200e}' | '\u{200f}' | '\u{061c}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// Whether `c` is a format character (Unicode category Cf: invisible, it
/// changes how the text around it shows or joins), a line or paragraph
/// separator, or a non-character: what a name may not hold besides the
/// control characters ([`check_name`]).
pub fn is_invisible_format(c: char) -> bool {
    is_bidi_control(c)
        || matches!(
            c,
            '\u{00ad}'
                | '\u{0600}'..='\u{0605}'
                | '\u{06dd}'
                | '\u{070f}'
                | '\u{0890}'..='\u{0891}'
                | '\u{08e2}'
                | '\u{180e}'
                | '\u{200b}'..='\u{200d}'
                | '\u{2028}'..='\u{2029}'
                | '\u{2060}'..='\u{2064}'
                | '\u{206a}'..='\u{206f}'
                | '\u{feff}'
                | '\u{fff9}'..='\u{fffb}'
                | '\u{fffe}'..='\u{ffff}'
                | '\u{110bd}'
                | '\u{110cd}'
                | '\u{13430}'..='\u{1343f}'
                | '\u{1bca0}'..='\u{1bca3}'
                | '\u{1d173}'..='\u{1d17a}'
                | '\u{e0001}'
                | '\u{e0020}'..='\u{e007f}'
        )
}

/// `s` with every control character except the line feed and the tab
/// written as `\xHH` (or `\u{HHHH}` past 0xFF): a message printed to a
/// terminal cannot run an escape sequence or ring its bell.
///
/// ```
/// use e3d::text::escape_controls;
/// assert_eq!(escape_controls("arm\x1b[31m\x07"), "arm\\x1b[31m\\x07");
/// assert_eq!(escape_controls("two\nlines"), "two\nlines");
/// ```
pub fn escape_controls(s: &str) -> Cow<'_, str> {
    escape_where(s, |c| is_terminal_control(c) && c != '\n' && c != '\t')
}

/// `s` with each character `escaped` picks written as by [`push_code`].
fn escape_where(s: &str, escaped: impl Fn(char) -> bool) -> Cow<'_, str> {
    if !s.chars().any(&escaped) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if escaped(c) {
            push_code(&mut out, c);
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// `c` written as `\xHH` (or `\u{HHHH}` past 0xFF).
fn push_code(out: &mut String, c: char) {
    let u = u32::from(c);
    if u <= 0xff {
        let _ = write!(out, "\\x{u:02x}");
    } else {
        let _ = write!(out, "\\u{{{u:04x}}}");
    }
}

/// `s` as an error message shows it: its control characters (line breaks
/// and tabs included) escaped as by [`escape_controls`], cut after
/// [`MAX_ECHO_CHARS`] characters with `…` and the whole length.
///
/// ```
/// use e3d::text::echo;
/// assert_eq!(echo("a\x1bb"), "a\\x1bb");
/// let long = "x".repeat(100_000);
/// assert_eq!(echo(&long), format!("{}… (100000 characters)", "x".repeat(80)));
/// ```
pub fn echo(s: &str) -> String {
    escape_where(&cut(s, MAX_ECHO_CHARS), is_terminal_control).into_owned()
}

/// `s` cut after `max` characters with `…` and its whole length in
/// characters; as is when shorter.
pub fn cut(s: &str, max: usize) -> Cow<'_, str> {
    match s.char_indices().nth(max) {
        None => Cow::Borrowed(s),
        Some((i, _)) => Cow::Owned(format!("{}… ({} characters)", &s[..i], s.chars().count())),
    }
}

/// `s` safe in XML text and attribute values (SVG, HTML): `&`, `<`, `>`,
/// `"` and `'` as entities; the control characters XML 1.0 does not allow
/// (all of C0 but tab, line feed and carriage return) written as `\xHH`,
/// since not even an entity may stand for them.
///
/// ```
/// use e3d::text::xml_escape;
/// assert_eq!(xml_escape("a<b & \"c\"\x1b"), "a&lt;b &amp; &quot;c&quot;\\x1b");
/// ```
pub fn xml_escape(s: &str) -> Cow<'_, str> {
    let unsafe_char =
        |c: char| matches!(c, '&' | '<' | '>' | '"' | '\'') || xml_forbidden(c) || c == '\u{7f}';
    if !s.chars().any(unsafe_char) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 16);
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c if xml_forbidden(c) || c == '\u{7f}' => push_code(&mut out, c),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// `xml` (a whole SVG or HTML document) with the characters XML 1.0
/// forbids written as `\xHH` text: for documents drawn by a library that
/// escapes `<` and `&` but passes control characters through (plotters),
/// which would make the document ill-formed.
pub fn xml_forbidden_escaped(xml: String) -> String {
    escape_where(&xml, xml_forbidden).into_owned()
}

/// Characters XML 1.0 forbids in a document (C0 controls but tab, line
/// feed and carriage return; the two non-characters U+FFFE and U+FFFF).
fn xml_forbidden(c: char) -> bool {
    (c < ' ' && !matches!(c, '\t' | '\n' | '\r')) || c == '\u{fffe}' || c == '\u{ffff}'
}

/// The most characters a name (of a scene, a body, a joint, a start
/// context) may hold.
pub const MAX_NAME_CHARS: usize = 200;

/// Checks a name (of a scene, a body, a joint, a start context), which e3d
/// prints to terminals and writes into CSV files: not blank; no control or
/// format character ([`is_invisible_format`]), no `,` or `"`; at most
/// [`MAX_NAME_CHARS`] characters. The error says what is expected and
/// what was found (escaped, cut).
///
/// ```
/// use e3d::text::check_name;
/// assert!(check_name("room_a").is_ok());
/// assert!(check_name("a,b").unwrap_err().contains("U+002C"));
/// assert!(check_name("evil\u{202e}txt").unwrap_err().contains("U+202E"));
/// assert!(check_name(" ").is_err());
/// ```
pub fn check_name(name: &str) -> Result<(), String> {
    if name.trim().is_empty() {
        return Err(format!("a non-empty name, found `{}`", echo(name)));
    }
    let bad = |c: char| c.is_control() || c == ',' || c == '"' || is_invisible_format(c);
    if let Some(c) = name.chars().find(|&c| bad(c)) {
        let (code, name) = (u32::from(c), echo(name));
        return Err(format!("a name without control or format characters, ',' or '\"' (it is printed and written into CSV files), found U+{code:04X} in `{name}`"));
    }
    let n = name.chars().count();
    if n > MAX_NAME_CHARS {
        return Err(format!(
            "a name of at most {MAX_NAME_CHARS} characters, found {n}"
        ));
    }
    Ok(())
}

/// A number for messages: as written for ordinary magnitudes, else in
/// scientific notation (`1e39`, not 39 digits).
///
/// ```
/// use e3d::text::show_number;
/// assert_eq!(show_number(1e300), "1e300");
/// assert_eq!(show_number(0.9), "0.9");
/// assert_eq!(show_number(-1.7e308), "-1.7e308");
/// ```
pub fn show_number(v: f64) -> String {
    let s = if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    };
    if s.len() <= 12 {
        return s;
    }
    // a computed value: 5 significant digits
    let s = if (1e-4..1e6).contains(&v.abs()) {
        format!(
            "{v:.*}",
            (4 - v.abs().log10().floor() as i64).max(0) as usize
        )
    } else {
        format!("{v:.4e}")
    };
    let (m, e) = s
        .split_once('e')
        .map_or((s.as_str(), None), |(m, e)| (m, Some(e)));
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.')
    } else {
        m
    };
    match e {
        Some(e) => format!("{m}e{e}"),
        None => m.to_string(),
    }
}

/// Why one of e3d's own files could not be read (see [`read_own_file`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// Missing, unreadable, a failed read.
    #[error("{file}: {error}")]
    Io {
        /// The file.
        file: String,
        /// What the system said.
        #[source]
        error: io::Error,
    },
    /// A pipe, a device, a socket, a folder.
    #[error("{file}: this is not a regular file (a folder, a pipe, a device or a socket); expected the {what} e3d wrote")]
    NotRegularFile {
        /// The file.
        file: String,
        /// What was expected there (`sweep journal`, `summary.csv`, ...).
        what: String,
    },
    /// Larger than the cap.
    #[error("{file}: holds more than {max} bytes, the most a {what} may hold here; expected the {what} e3d wrote")]
    TooLarge {
        /// The file.
        file: String,
        /// What was expected there.
        what: String,
        /// The cap.
        max: u64,
    },
    /// Bytes that are not UTF-8 text.
    #[error("{file}:{line}:{col}: not UTF-8 text; expected the {what} e3d wrote")]
    NotUtf8 {
        /// The file.
        file: String,
        /// What was expected there.
        what: String,
        /// 1-based line of the first bad byte.
        line: usize,
        /// 1-based column (in characters) of the first bad byte.
        col: usize,
    },
}

impl ReadError {
    /// Whether the file does not exist.
    pub fn is_not_found(&self) -> bool {
        matches!(self, ReadError::Io { error, .. } if error.kind() == io::ErrorKind::NotFound)
    }
}

/// Opens `path` for reading if it is a regular file
/// ([`io::open_regular`](crate::io::open_regular)), as a [`ReadError`].
fn open_regular(path: &Path, what: &str) -> Result<std::fs::File, ReadError> {
    let file = path.display().to_string();
    match crate::io::open_regular(path) {
        Ok(f) => Ok(f),
        Err(error) if error.kind() == io::ErrorKind::InvalidInput => {
            Err(ReadError::NotRegularFile {
                file,
                what: what.to_string(),
            })
        }
        Err(error) => Err(ReadError::Io { file, error }),
    }
}

/// Reads one of e3d's own files whole, as bytes: a regular file only
/// (never a FIFO, a device or a folder; a symbolic link to one is refused
/// too), of at most `max` bytes (read up to `max + 1` even if it grows
/// meanwhile). `what` names what was expected, for the messages.
pub fn read_own_bytes(path: &Path, max: u64, what: &str) -> Result<Vec<u8>, ReadError> {
    let (f, len) = open_own(path, max, what)?;
    let mut bytes = Vec::with_capacity(len as usize);
    f.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|error| ReadError::Io {
            file: path.display().to_string(),
            error,
        })?;
    if bytes.len() as u64 > max {
        return Err(too_large(path, max, what));
    }
    Ok(bytes)
}

/// Opens one of e3d's own files for a streamed read, with the checks of
/// [`read_own_bytes`] that come before reading: a regular file only, of at
/// most `max` bytes now. Returns the file and its length; the reader
/// must still stop after `max + 1` bytes (the file may grow) and refuse
/// with [`too_large`] if it gets them.
pub fn open_own(path: &Path, max: u64, what: &str) -> Result<(std::fs::File, u64), ReadError> {
    let f = open_regular(path, what)?;
    let len = f.metadata().map(|m| m.len()).unwrap_or(0);
    if len > max {
        return Err(too_large(path, max, what));
    }
    Ok((f, len))
}

/// The [`ReadError::TooLarge`] of `path`.
pub fn too_large(path: &Path, max: u64, what: &str) -> ReadError {
    ReadError::TooLarge {
        file: path.display().to_string(),
        what: what.to_string(),
        max,
    }
}

/// [`read_own_bytes`] as UTF-8 text; bytes that are not are refused with
/// the line and column where they start.
pub fn read_own_file(path: &Path, max: u64, what: &str) -> Result<String, ReadError> {
    let bytes = read_own_bytes(path, max, what)?;
    String::from_utf8(bytes).map_err(|e| {
        let upto = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = upto.iter().filter(|&&b| b == b'\n').count() + 1;
        let start = upto.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let col = String::from_utf8_lossy(&upto[start..]).chars().count() + 1;
        ReadError::NotUtf8 {
            file: path.display().to_string(),
            what: what.to_string(),
            line,
            col,
        }
    })
}

/// The longest line e3d reads from standard input (`scene exec -`): 64
/// KiB, far more than a command of 64 slots.
pub const MAX_LINE_BYTES: usize = 64 << 10;

/// What [`read_line_bounded`] read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Line {
    /// A line (without its line feed), at most the cap long.
    Line(String),
    /// A line longer than the cap: its first bytes (up to the cap). The
    /// reading stopped there, in the middle of the line (a stream like
    /// `/dev/zero` has no end to wait for); `.1` is how many bytes of it
    /// were read (more than the cap).
    TooLong(String, u64),
    /// The end of the stream.
    End,
}

/// Reads one line of `input`, reading at most `max` + 2 bytes whatever
/// the stream holds (`/dev/zero` has no line feed): a longer line is
/// [`Line::TooLong`], with its start, as soon as the cap is passed; bytes
/// that are not UTF-8 are replaced by U+FFFD.
pub fn read_line_bounded(input: &mut impl BufRead, max: usize) -> io::Result<Line> {
    let mut line = Vec::new();
    // the cap, a carriage return and one byte more: a longer line stops there
    input.take(max as u64 + 2).read_until(b'\n', &mut line)?;
    if line.is_empty() {
        return Ok(Line::End);
    }
    if line.last() == Some(&b'\n') {
        line.pop();
    }
    if line.len() <= max && line.last() == Some(&b'\r') {
        line.pop();
    }
    let total = line.len() as u64;
    line.truncate(max);
    let text = String::from_utf8_lossy(&line).into_owned();
    Ok(match total > max as u64 {
        true => Line::TooLong(text, total),
        false => Line::Line(text),
    })
}

/// The lines of `input` (without line feeds), each read by
/// [`read_line_bounded`]: a line longer than `max` bytes is an error of
/// kind `InvalidData` that says its start, and ends the lines.
pub fn bounded_lines<R: BufRead>(
    mut input: R,
    max: usize,
) -> impl Iterator<Item = io::Result<String>> {
    let mut over = false;
    std::iter::from_fn(move || {
        if over {
            return None;
        }
        match read_line_bounded(&mut input, max) {
            Ok(Line::End) => None,
            Ok(Line::Line(l)) => Some(Ok(l)),
            Ok(Line::TooLong(start, _)) => {
                over = true;
                Some(Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "a line of more than {max} bytes; expected a command, found `{}`",
                        echo(&start)
                    ),
                )))
            }
            Err(e) => Some(Err(e)),
        }
    })
}

/// A number read from one of e3d's own files at `file:line:col`, which
/// must be a finite number: `inf`, `NaN` and what does not parse are
/// refused with the place, the text (cut by [`echo`]) and `what` was
/// expected.
///
/// ```
/// use e3d::text::parse_finite;
/// assert_eq!(parse_finite("0.5", "s.csv", 2, 7, "beta"), Ok(0.5));
/// let e = parse_finite("inf", "s.csv", 2, 7, "beta").unwrap_err();
/// assert_eq!(e, "s.csv:2:7: column `beta`: expected a finite number, found `inf`");
/// ```
pub fn parse_finite(
    text: &str,
    file: &str,
    line: usize,
    col: usize,
    what: &str,
) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!(
            "{file}:{line}:{col}: column `{what}`: expected a finite number, found `{}`",
            echo(text)
        )),
    }
}

/// The fields of a CSV line with the 1-based column (in characters) each
/// starts at; fields between double quotes may hold commas and doubled
/// quotes (RFC 4180; a line break inside quotes is not supported: e3d
/// never writes one). Linear in the line's length.
pub fn csv_fields(line: &str) -> Vec<(Cow<'_, str>, usize)> {
    let mut col = 1;
    let mut out: Vec<(Cow<'_, str>, usize)> = Vec::new();
    if !line.contains('"') {
        for f in line.split(',') {
            out.push((Cow::Borrowed(f), col));
            col += f.chars().count() + 1;
        }
        return out;
    }
    // a field opening with a quote runs to the closing quote not doubled;
    // anything after it, up to the next comma, belongs to the field
    let (mut value, mut start, mut at_start, mut quoted) = (String::new(), 1, true, false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if at_start => quoted = true,
            '"' if quoted && chars.next_if_eq(&'"').is_some() => {
                col += 1;
                value.push('"');
            }
            '"' if quoted => quoted = false,
            ',' if !quoted => {
                out.push((Cow::Owned(std::mem::take(&mut value)), start));
                start = col + 1;
            }
            c => value.push(c),
        }
        at_start = c == ',' && !quoted;
        col += 1;
    }
    out.push((Cow::Owned(value), start));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_round_trip_quoted_fields() {
        let f: Vec<(String, usize)> = csv_fields("\"a\"\"b,c\",d,x")
            .into_iter()
            .map(|(s, c)| (s.into_owned(), c))
            .collect();
        assert_eq!(
            f,
            vec![("a\"b,c".into(), 1), ("d".into(), 10), ("x".into(), 12)]
        );
        assert_eq!(csv_fields("").len(), 1);
        assert_eq!(csv_fields("a,,b").len(), 3);
    }

    #[test]
    fn bounded_lines_keep_at_most_the_cap() {
        let data = vec![b'x'; 100_000];
        let mut r = io::BufReader::with_capacity(64, &data[..]);
        match read_line_bounded(&mut r, 10).unwrap() {
            // stopped within a buffer of the cap
            Line::TooLong(s, n) => assert!(s.len() == 10 && n > 11 && n <= 11 + 64, "{n}"),
            l => panic!("{l:?}"),
        }
        let mut r = io::BufReader::new(&b"ab\r\ncd\n\nef"[..]);
        for line in ["ab", "cd", "", "ef"] {
            assert_eq!(
                read_line_bounded(&mut r, 10).unwrap(),
                Line::Line(line.into())
            );
        }
        assert_eq!(read_line_bounded(&mut r, 10).unwrap(), Line::End);
    }
}
