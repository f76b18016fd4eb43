//! Scene errors that point into the file.

use super::{Invalid, MAX_FILE_BYTES};
use std::fmt;

/// A scene (or sweep) that cannot be loaded or used: which file, and what
/// kind of mistake ([`SceneErrorKind`]); displays as `FILE:LINE:COL: MESSAGE`
/// (or `FILE: MESSAGE`). An I/O error is its [`source`](std::error::Error::source).
///
/// ```
/// use e3d::scene::{Scene, SceneErrorKind};
///
/// let missing = Scene::load("no/such/scene.ron").unwrap_err();
/// assert!(matches!(missing.kind(), SceneErrorKind::Io(e) if e.kind() == std::io::ErrorKind::NotFound));
/// assert!(std::error::Error::source(&missing).is_some());
///
/// let typo = Scene::parse("Scene(name: \"x\", wrold: Grid(rows: 1))", "x.ron").unwrap_err();
/// assert!(matches!(typo.kind(), SceneErrorKind::Syntax { line: 1, col: 18, .. }));
/// assert_eq!(typo.position(), Some((1, 18)));
/// assert!(typo.to_string().starts_with("x.ron:1:18: unknown field `wrold`"));
/// ```
#[derive(Debug)]
pub struct SceneError {
    file: String,
    /// `scene` or `sweep`: the kind of file, for messages.
    what: &'static str,
    kind: SceneErrorKind,
}

/// What is wrong with a scene or sweep file, or with a scene built or
/// edited in code ([`SceneSpec::validate`](super::SceneSpec::validate)).
///
/// Positions are 1-based `(line, column)` in the file's text.
#[derive(Debug)]
#[non_exhaustive]
pub enum SceneErrorKind {
    /// The file could not be read (it does not exist, it may not be read,
    /// ...): the I/O error, also the error's source.
    Io(std::io::Error),
    /// The path is a directory.
    Directory,
    /// The path is not a regular file (a pipe, a device or a socket).
    NotRegularFile,
    /// The file holds more than [`MAX_FILE_BYTES`].
    TooLarge {
        /// Its size in bytes; `None` when it grew past the limit while it
        /// was read.
        bytes: Option<u64>,
    },
    /// The file's bytes are not UTF-8 text.
    NotUtf8 {
        /// Line of the first bad byte.
        line: usize,
        /// Column of the first bad byte.
        col: usize,
        /// The decoding error (also the error's source).
        error: std::str::Utf8Error,
    },
    /// The lines end with CR only (old Mac files), which RON reads as one
    /// line.
    CrLineEndings,
    /// The file holds nothing but white space.
    Empty,
    /// The text is not RON of the expected shape: a syntax error, an
    /// unknown or missing field, an unknown variant, a value of the wrong
    /// type.
    #[non_exhaustive]
    Syntax {
        /// Line of the mistake.
        line: usize,
        /// Column of the mistake.
        col: usize,
        /// What is wrong and what was expected.
        message: String,
        /// The field the mistake is about, where it names one: the
        /// unknown, missing or repeated field, or the one given a value of
        /// the wrong type or an unknown variant (see
        /// [`SceneError::field`]).
        field: Option<String>,
    },
    /// A value the format allows but the scene cannot hold (a range, a
    /// name that is not known, a symmetry the scene breaks, ...).
    Invalid {
        /// The field at fault (`mass`, `torque`, `slots`, ...).
        field: String,
        /// What was expected, and what was found.
        expected: String,
        /// `(line, col)` of the field in the file; `None` for a scene that
        /// has no text (built or edited in code), or when the field is not
        /// written in it.
        position: Option<(usize, usize)>,
    },
    /// [`Scene::resolve`](super::Scene::resolve): no such file, and no
    /// built-in scene of that name.
    NoSuchScene,
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            SceneErrorKind::Io(e) => Some(e),
            SceneErrorKind::NotUtf8 { error, .. } => Some(error),
            _ => None,
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position() {
            Some((l, c)) => write!(f, "{}:{l}:{c}: ", self.file)?,
            None => write!(f, "{}: ", self.file)?,
        }
        let what = self.what;
        match &self.kind {
            SceneErrorKind::Io(e) => write!(f, "cannot read the file: {e}"),
            SceneErrorKind::Directory => {
                write!(f, "this is a directory; expected a {what} file (.ron)")
            }
            SceneErrorKind::NotRegularFile => write!(
                f,
                "this is not a regular file (a pipe, a device or a socket); expected a {what} file (.ron)"
            ),
            SceneErrorKind::TooLarge { bytes } => {
                match bytes {
                    Some(n) => write!(f, "the file holds {n} bytes")?,
                    None => write!(f, "the file holds more than {MAX_FILE_BYTES} bytes")?,
                }
                write!(
                    f,
                    "; a {what} file may hold at most {MAX_FILE_BYTES} bytes (16 MiB)"
                )
            }
            SceneErrorKind::NotUtf8 { .. } => {
                write!(f, "the file is not valid UTF-8 text; expected a RON {what}")
            }
            SceneErrorKind::CrLineEndings => write!(
                f,
                "the file's lines end with CR only (old Mac line endings), which are not supported; expected a RON {what} with LF or CRLF line endings"
            ),
            SceneErrorKind::Empty => match what {
                "sweep" => write!(
                    f,
                    "the file is empty; expected `Sweep(scenes: [...], learners: [...], sessions: N, trials: T)`"
                ),
                _ => write!(
                    f,
                    "the file is empty; expected `Scene(name: ..., world: ..., command: ...)`"
                ),
            },
            SceneErrorKind::Syntax { message, .. } => f.write_str(message),
            SceneErrorKind::Invalid {
                field, expected, ..
            } => write!(f, "field `{field}`: expected {expected}"),
            SceneErrorKind::NoSuchScene => {
                let names: Vec<&str> = super::BUILTIN.iter().map(|(n, _)| *n).collect();
                write!(
                    f,
                    "no such file, and no built-in scene of that name{}; expected a path to a .ron scene or one of: {}",
                    did_you_mean(&stem(&self.file), &names),
                    names.join(", ")
                )
            }
        }
    }
}

impl SceneError {
    /// `what`: `scene` or `sweep`, the kind of file, for messages.
    pub(crate) fn new(file: &str, what: &'static str, kind: SceneErrorKind) -> Self {
        SceneError {
            file: file.to_string(),
            what,
            kind,
        }
    }

    /// The field at fault, where the mistake is about one (an invalid value,
    /// or an unknown, missing, repeated or mistyped field); `None` otherwise.
    ///
    /// ```
    /// use e3d::Scene;
    /// let e = Scene::parse("Scene(name: 3)", "x.ron").unwrap_err();
    /// assert_eq!(e.field(), Some("name"));
    /// assert_eq!(e.to_string(), "x.ron:1:12: field `name`: expected string");
    /// ```
    pub fn field(&self) -> Option<&str> {
        match &self.kind {
            SceneErrorKind::Invalid { field, .. } => Some(field),
            SceneErrorKind::Syntax { field, .. } => field.as_deref(),
            _ => None,
        }
    }

    /// The file (or `<builtin NAME>` for a shipped scene, `<scene NAME>`
    /// for one validated in code, or the name that was not found).
    pub fn file(&self) -> &str {
        &self.file
    }

    /// What kind of mistake this is.
    pub fn kind(&self) -> &SceneErrorKind {
        &self.kind
    }

    /// The kind, by value (to take the I/O error out).
    pub fn into_kind(self) -> SceneErrorKind {
        self.kind
    }

    /// 1-based `(line, column)` of the mistake in the file, where it has
    /// one.
    pub fn position(&self) -> Option<(usize, usize)> {
        match self.kind {
            SceneErrorKind::NotUtf8 { line, col, .. }
            | SceneErrorKind::Syntax { line, col, .. } => Some((line, col)),
            SceneErrorKind::Invalid { position, .. } => position,
            _ => None,
        }
    }

    /// From a RON parse error: its position, and a sentence with a "did you
    /// mean" for misspelt fields and variants.
    pub(crate) fn from_ron(file: &str, text: &str, e: ron::error::SpannedError) -> Self {
        use ron::error::Error as E;
        // " in `Outer`": the struct (or enum) the mistake is in
        let within = |word: &str, outer: &Option<String>| {
            outer
                .as_ref()
                .map_or(String::new(), |o| format!(" {word} `{o}`"))
        };
        let unknown = |what: &str, found: &str, expected: &[&str], within: String| {
            format!(
                "unknown {what} `{found}`{within}{}; expected one of: {}",
                did_you_mean(found, expected),
                expected.join(", ")
            )
        };
        // the message, and the field the mistake is about if it names one
        let (message, at) = match &e.code {
            E::NoSuchStructField {
                expected,
                found,
                outer,
            } => (
                unknown("field", found, expected, within("in", outer)),
                Some(found.to_string()),
            ),
            E::NoSuchEnumVariant {
                expected,
                found,
                outer,
            } => (
                unknown("variant", found, expected, within("for", outer)),
                field_before(text, e.span.start.line, e.span.start.col),
            ),
            E::MissingStructField { field, outer } => (
                format!("missing field `{field}`{}", within("in", outer)),
                Some(field.to_string()),
            ),
            E::DuplicateStructField { field, outer } => (
                format!("field `{field}` given twice{}", within("in", outer)),
                Some(field.to_string()),
            ),
            other => other_message(other, text, &e),
        };
        SceneError::new(
            file,
            "scene",
            SceneErrorKind::Syntax {
                line: e.span.start.line,
                col: e.span.start.col,
                message,
                field: at,
            },
        )
    }

    /// A validation failure placed in the file's `text`: the field it
    /// names, found there.
    pub(crate) fn from_validation(file: &str, text: &str, v: Invalid) -> Self {
        let position = match v.within {
            Some((list, k)) => locate_within(text, list, k, &v.field),
            None => locate(text, &v.field, v.anchor.as_deref(), v.nth),
        };
        SceneError::invalid(file, v, position)
    }

    /// A validation failure at `position` (`None`: a scene without text).
    pub(crate) fn invalid(file: &str, v: Invalid, position: Option<(usize, usize)>) -> Self {
        SceneError::new(
            file,
            "scene",
            SceneErrorKind::Invalid {
                field: v.field,
                expected: v.expected,
                position,
            },
        )
    }
}

/// The message of a RON error `other` than an unknown or missing field or
/// variant: std's, lowercased, naming the field a value of the wrong type
/// was given to (and what was written, for a count out of bounds); and
/// that field.
fn other_message(
    other: &ron::error::Error,
    text: &str,
    e: &ron::error::SpannedError,
) -> (String, Option<String>) {
    let mut m = other.to_string();
    if let Some(c) = m.get(..1) {
        m.replace_range(..1, &c.to_lowercase());
    }
    // a value of the wrong type: name the field it was given to
    let about_a_value = m.starts_with("expected")
        || ["integer", "digit", "out of bounds", "float"]
            .iter()
            .any(|w| m.contains(w));
    if m.contains("out of bounds") {
        // say what was written, and what a count takes
        let token = token_at(text, e.span.start.line, e.span.start.col);
        if token.starts_with('-') {
            m = format!("{m}: expected a whole number >= 0, found {token}");
        } else if !token.is_empty() {
            m = format!("{m}: {token} is too large for this field");
        }
    }
    match field_before(text, e.span.start.line, e.span.start.col) {
        Some(f) if about_a_value => (format!("field `{f}`: {m}"), Some(f)),
        _ => (m, None),
    }
}

/// The name of `file` without its folders and extension (`puck_room` of
/// `scenes/puck_room.ron`), to compare with the built-in scenes' names.
fn stem(file: &str) -> String {
    std::path::Path::new(file)
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned())
}

/// A known name close to `found`, as `" (did you mean `x`?)"`, or "".
pub fn did_you_mean(found: &str, known: &[&str]) -> String {
    // a suggestion is within a few edits; names past 64 characters get
    // none, so that the edit distance (quadratic) stays cheap on a
    // 200,000-character name
    const LONGEST: usize = 64;
    if found.chars().nth(LONGEST).is_some() {
        return String::new();
    }
    let best = known
        .iter()
        .filter(|k| k.chars().nth(LONGEST).is_none())
        .map(|k| (edit_distance(&found.to_lowercase(), &k.to_lowercase()), *k))
        .min();
    match best {
        Some((d, k)) if d <= 2.max(found.len() / 3) && d < found.len() => {
            format!(" (did you mean `{k}`?)")
        }
        _ => String::new(),
    }
}

fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut cur = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The name of the field whose value starts at or before the 1-based
/// `(line, col)`: the last `ident:` before it on that line or the one above.
fn field_before(text: &str, line: usize, col: usize) -> Option<String> {
    let code = blank_comments(text);
    let lines: Vec<&str> = code.lines().collect();
    let this = lines.get(line.checked_sub(1)?)?;
    let upto: String = this.chars().take(col.saturating_sub(1)).collect();
    let prev = line
        .checked_sub(2)
        .and_then(|l| lines.get(l))
        .copied()
        .unwrap_or("");
    for chunk in [upto.as_str(), prev] {
        let mut best = None;
        for (i, _) in chunk.match_indices(':') {
            let before = chunk[..i].trim_end();
            let word = before.trim_end_matches(|c: char| c.is_alphanumeric() || c == '_');
            let name = &before[word.len()..];
            if !name.is_empty() && !name.starts_with(|c: char| c.is_ascii_digit()) {
                best = Some(name.to_string());
            }
        }
        if best.is_some() {
            return best;
        }
    }
    None
}

/// The number-like word at or just before the 1-based `(line, col)`.
fn token_at(text: &str, line: usize, col: usize) -> String {
    let Some(l) = line.checked_sub(1).and_then(|i| text.lines().nth(i)) else {
        return String::new();
    };
    let chars: Vec<char> = l.chars().collect();
    let is_num = |c: char| c.is_ascii_alphanumeric() || "-+._".contains(c);
    let mut at = col.saturating_sub(1).min(chars.len());
    // RON reports the end of the number: step back to its start
    while at > 0 && is_num(chars[at - 1]) {
        at -= 1;
    }
    chars[at..]
        .iter()
        .take_while(|&&c| is_num(c))
        .take(40)
        .collect()
}

/// 1-based (line, column) of byte offset `at` in `text`.
pub(crate) fn position_at(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before[before.rfind('\n').map_or(0, |i| i + 1)..]
        .chars()
        .count()
        + 1;
    (line, col)
}

/// Where a validation failure sits: the `nth` occurrence of `anchor` if
/// given, else the `nth` occurrence of `field` used as a field name
/// (`field:`), skipping comments.
fn locate(text: &str, field: &str, anchor: Option<&str>, nth: usize) -> Option<(usize, usize)> {
    let code = blank_comments(text);
    let fields = |from: usize, to: usize| -> Vec<usize> {
        code[from..to]
            .match_indices(field)
            .map(|(i, _)| from + i)
            .filter(|&i| {
                let before_ok = code[..i]
                    .chars()
                    .next_back()
                    .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
                let after = code[i + field.len()..].trim_start();
                before_ok && (after.starts_with(':') || after.starts_with('('))
            })
            .collect()
    };
    let hits: Vec<usize> = match anchor {
        Some(a) => code.match_indices(a).map(|(i, _)| i).collect(),
        None => fields(0, code.len()),
    };
    let at = *hits.get(nth).or_else(|| hits.first())?;
    // an anchor (a body's name, a symbol): the field itself, when it is
    // written inside the same parentheses
    let at = match anchor {
        Some(_) => {
            let (_, end) = top_level(code.as_bytes(), at);
            fields(at, end).first().copied().unwrap_or(at)
        }
        None => at,
    };
    Some(position_at(text, at))
}

/// Where a failure in entry `k` of the list field `list` (`chains: [...]`)
/// sits: its field `field` if written in that entry, else the entry's
/// start; the list field itself when the entry is not found.
fn locate_within(text: &str, list: &str, k: usize, field: &str) -> Option<(usize, usize)> {
    let code = blank_comments(text);
    let b = code.as_bytes();
    let is_word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    // on bytes: `i` need not be a character boundary (text in strings)
    let name_at = |i: usize, name: &str| {
        b[i..].starts_with(name.as_bytes())
            && (i == 0 || !is_word(b[i - 1]))
            && b[i + name.len()..]
                .iter()
                .find(|c| !c.is_ascii_whitespace())
                == Some(&b':')
    };
    let mut in_str = false;
    let start = (0..b.len()).find(|&i| {
        if b[i] == b'"' && (i == 0 || b[i - 1] != b'\\') {
            in_str = !in_str;
        }
        !in_str && name_at(i, list)
    })?;
    let open = start + code[start..].find('[')?;
    // the entries: the groups at depth 1 inside the brackets
    let (inside, _) = top_level(b, open + 1);
    let mut entries = inside.into_iter().filter(|&i| matches!(b[i], b'(' | b'['));
    let Some(i) = entries.nth(k) else {
        return Some(position_at(text, start));
    };
    let (fields, _) = top_level(b, i + 1);
    let at = fields.into_iter().find(|&j| name_at(j, field));
    Some(position_at(text, at.unwrap_or(i)))
}

/// The byte offsets from `from` on that lie in no string and at the depth
/// of `from` (the opening brackets of the groups there included), and the
/// offset of the `)` or `]` that closes that depth (the end of the text if
/// none).
fn top_level(b: &[u8], from: usize) -> (Vec<usize>, usize) {
    let (mut depth, mut in_str, mut out) = (0usize, false, Vec::new());
    let mut i = from;
    while i < b.len() {
        match b[i] {
            b'\\' if in_str => i += 1,
            b'"' => in_str = !in_str,
            b'(' | b'[' if !in_str => {
                if depth == 0 {
                    out.push(i);
                }
                depth += 1;
            }
            b')' | b']' if !in_str => {
                if depth == 0 {
                    return (out, i);
                }
                depth -= 1;
            }
            _ if !in_str && depth == 0 => out.push(i),
            _ => {}
        }
        i += 1;
    }
    (out, b.len())
}

/// The text with `//` and `/* */` comments (outside strings) replaced by
/// spaces, so that byte offsets stay the same.
fn blank_comments(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = b.to_vec();
    let (mut i, mut in_str) = (0, false);
    while i < b.len() {
        let rest = &b[i..];
        if in_str && b[i] == b'\\' {
            i += 2;
            continue;
        }
        if b[i] == b'"' {
            in_str = !in_str;
        } else if !in_str && (rest.starts_with(b"//") || rest.starts_with(b"/*")) {
            // to the end of the line, or past the `*/` (the text's end if none)
            let end = match rest[1] {
                b'/' => rest.iter().position(|&c| c == b'\n'),
                _ => rest.windows(2).position(|w| w == b"*/").map(|e| e + 2),
            };
            let end = i + end.unwrap_or(rest.len());
            out[i..end]
                .iter_mut()
                .filter(|c| **c != b'\n')
                .for_each(|c| *c = b' ');
            i = end;
            continue;
        }
        i += 1;
    }
    // Only ASCII bytes were replaced by ASCII spaces, within comments that
    // start and end on ASCII delimiters; multi-byte characters inside a
    // comment are blanked byte by byte, which keeps valid UTF-8.
    String::from_utf8(out).unwrap_or_else(|_| text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names_only() {
        assert_eq!(
            did_you_mean("colz", &["rows", "cols"]),
            " (did you mean `cols`?)"
        );
        assert_eq!(did_you_mean("zzzzzz", &["rows", "cols"]), "");
    }

    #[test]
    fn locates_fields_outside_comments() {
        let text = "// rows: no\n(\n  rows: 3,\n)";
        assert_eq!(locate(text, "rows", None, 0), Some((3, 3)));
    }
}
