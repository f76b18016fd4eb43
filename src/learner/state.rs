//! Saving and loading a learner's whole state, bit for bit: one format
//! shared by every learner.
//!
//! A learner that implements [`LearnerState`] writes its fields, in a fixed
//! order, through a [`StateWriter`], and reads them back through a
//! [`StateReader`]; [`LearnerState::to_bytes`] and
//! [`LearnerState::from_bytes`] frame them. The bytes are:
//!
//! - the header `E3D-LEARNER-STATE 2\n` (the number is the format's version);
//! - the learner's kind ([`LearnerState::KIND`], e.g. `"e3d"`, `"count"`),
//!   as a string;
//! - its fields ([`StateField`]): a float is the 8 little-endian bytes of
//!   its bits (so every value, NaN payloads included, comes back exact), an
//!   integer 8 little-endian bytes (`u64`), a character its code point
//!   (4 bytes), a string or a sequence its length (8 bytes) then its items;
//! - the FNV-1a checksum (64 bits, little-endian) of every byte before it.
//!
//! A state is checked when it is read: its checksum (a state of version 1,
//! written before the checksum, still loads without it; any other version
//! is refused by its number), no NaN anywhere, and each learner's rates
//! and tables finite and in range (a NaN learning rate or a NaN `Q` made a
//! learner that proposed nonsense without a word).
//!
//! A learner read back proposes and learns exactly as the saved one would:
//! given the same generator, the same draws and the same bits of every
//! table. Bytes of another kind, cut short, with bytes left over or whose
//! tables do not fit together are refused with a [`LearnerError::State`]
//! saying what is wrong (never a panic).
//!
//! ```
//! use e3d::learner::CountBonus;
//! use e3d::{Learner, Outcome, Params, SessionRng};
//! use e3d::command::CommandSpace;
//! use e3d::learner::LearnerState;
//! use rand::SeedableRng;
//! let space = CommandSpace::repeat(3, &['a', 'b']).unwrap();
//! let mut l = CountBonus::new(&space, 4, &Params::TASK1);
//! let mut rng = SessionRng::seed_from_u64(1);
//! let mut c = space.first();
//! let o = Outcome { effect: 2, reward: 0.0, point: [0.0, 0.0] };
//! l.propose(&mut rng, &mut c);
//! l.learn(&c, &o);
//! let saved = l.to_bytes();
//! let back = CountBonus::from_bytes(&saved).unwrap();
//! assert_eq!(back.to_bytes(), saved);
//! assert!(e3d::learner::E3d::from_bytes(&saved).is_err()); // a count learner's state
//! ```

use super::LearnerError;
use crate::command::{CommandSpace, ValueSpace};
use crate::effect::EffectModel;
use tables::{no_table, StateTable};

pub mod tables;

/// The first bytes of every learner's saved state (the format's version
/// is the number).
pub const STATE_HEADER: &[u8] = b"E3D-LEARNER-STATE 2\n";

/// The header of the states written before the checksum (version 1):
/// read without one.
pub const STATE_HEADER_V1: &[u8] = b"E3D-LEARNER-STATE 1\n";

/// The bytes of a state past its header (of version 1 or 2), checksum
/// neither checked nor removed: enough to read the kind it starts with.
fn state_start(bytes: &[u8]) -> Result<&[u8], LearnerError> {
    if let Some(rest) = bytes
        .strip_prefix(STATE_HEADER)
        .or_else(|| bytes.strip_prefix(STATE_HEADER_V1))
    {
        return Ok(rest);
    }
    state_body(bytes)
}

/// The bytes of a state past its header, checksum checked and removed
/// (version 2), as they are (version 1); the error of bytes of another
/// version (named) or not a state at all.
fn state_body(bytes: &[u8]) -> Result<&[u8], LearnerError> {
    if let Some(rest) = bytes.strip_prefix(STATE_HEADER_V1) {
        return Ok(rest);
    }
    let Some(rest) = bytes.strip_prefix(STATE_HEADER) else {
        let prefix = b"E3D-LEARNER-STATE ";
        if let Some(v) = bytes.strip_prefix(&prefix[..]) {
            let end = v
                .iter()
                .position(|&b| b == b'\n')
                .unwrap_or(v.len())
                .min(20);
            return Err(LearnerError::State(format!(
                "a learner's state of version {}, which this e3d cannot read (it reads versions 1 and 2)",
                crate::text::echo(&String::from_utf8_lossy(&v[..end]))
            )));
        }
        return Err(no_header());
    };
    if rest.len() < 8 {
        return Err(LearnerError::State(
            "a learner's state (version 2) cut before its checksum".into(),
        ));
    }
    let (body, sum) = rest.split_at(rest.len() - 8);
    let want = u64::from_le_bytes(sum.try_into().expect("8 bytes"));
    let got = crate::hash::fnv1a64(&bytes[..bytes.len() - 8]);
    if want != got {
        // a whole state followed by more bytes: the first place where the
        // 8 bytes are the checksum of all before them (one pass)
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for (p, &b) in bytes.iter().enumerate() {
            if p >= STATE_HEADER.len() && p + 8 < bytes.len() {
                let at = u64::from_le_bytes(bytes[p..p + 8].try_into().expect("8 bytes"));
                if at == h {
                    let kind = state_kind(bytes).unwrap_or_else(|_| "?".into());
                    return Err(LearnerError::State(format!(
                        "state of a `{kind}` learner: {} bytes after the state",
                        bytes.len() - p - 8
                    )));
                }
            }
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        return Err(LearnerError::State(format!(
            "a learner's state whose checksum does not match its bytes (damaged or edited: {got:016x}, recorded {want:016x})"
        )));
    }
    Ok(body)
}

/// The bytes of a state being written.
#[derive(Debug, Default)]
pub struct StateWriter {
    out: Vec<u8>,
}

impl StateWriter {
    /// Writes `value`.
    pub fn put<T: StateField>(&mut self, value: &T) -> &mut Self {
        value.put(self);
        self
    }

    /// Writes raw bytes (the fields' own encodings use this).
    pub fn bytes(&mut self, b: &[u8]) {
        self.out.extend_from_slice(b);
    }
}

/// The bytes of a state being read, with the kind of learner they are for
/// (to name it in errors).
#[derive(Debug)]
pub struct StateReader<'a> {
    rest: &'a [u8],
    kind: &'static str,
}

impl<'a> StateReader<'a> {
    /// Reads a `T`.
    pub fn get<T: StateField>(&mut self) -> Result<T, LearnerError> {
        T::get(self)
    }

    /// The next `n` raw bytes, or an error if the state ends before.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], LearnerError> {
        if self.rest.len() < n {
            return Err(self.error("the bytes end early"));
        }
        let (a, b) = self.rest.split_at(n);
        self.rest = b;
        Ok(a)
    }

    /// A length of a sequence whose items take at least `min_item` bytes
    /// each, checked against the bytes left (so that bad bytes cannot ask
    /// for a huge allocation).
    pub fn len(&mut self, min_item: usize) -> Result<usize, LearnerError> {
        let n: u64 = self.get()?;
        if n.saturating_mul(min_item as u64) > self.rest.len() as u64 {
            return Err(self.error(&format!("a sequence of {n} items: the bytes end early")));
        }
        Ok(n as usize)
    }

    /// A [`LearnerError::State`] saying that this kind's state is wrong
    /// and why.
    pub fn error(&self, what: &str) -> LearnerError {
        LearnerError::State(format!("state of a `{}` learner: {what}", self.kind))
    }

    /// Checks `ok`, else the error [`error`](Self::error)`(what)`.
    pub fn check(&self, ok: bool, what: impl FnOnce() -> String) -> Result<(), LearnerError> {
        if ok {
            Ok(())
        } else {
            Err(self.error(&what()))
        }
    }
}

/// A value in a learner's saved state: how it is written and read back.
pub trait StateField: Sized {
    /// Writes the value.
    fn put(&self, w: &mut StateWriter);
    /// Reads a value written by [`put`](Self::put), checked.
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError>;
}

/// A learner whose whole state can be saved as bytes and read back bit for
/// bit (see [the module](self) for the format).
pub trait LearnerState: StateField {
    /// The learner's kind, written in its state (`"e3d"`, `"count"`, ...).
    const KIND: &'static str;

    /// What the learner was made for: check it before running a loaded
    /// learner on a scene ([`StateShape::fits`]).
    fn shape(&self) -> StateShape;

    /// The learner's tables by name (Q, the policy, the effect model,
    /// the target, counts, ... as the learner has them; see
    /// [`tables`](mod@tables) for their shapes): none by default.
    fn tables(&self) -> Vec<StateTable> {
        Vec::new()
    }

    /// Replaces the table `name` by `values` (row-major, of the shape
    /// [`tables`](Self::tables) gives it), checked: an error says what is
    /// wrong and leaves the learner unchanged. By default no table can be
    /// written.
    fn set_table(&mut self, name: &str, values: &[f64]) -> Result<(), LearnerError> {
        let _ = values;
        Err(no_table(Self::KIND, name, &self.tables()))
    }

    /// The learner's whole state as bytes.
    fn to_bytes(&self) -> Vec<u8> {
        let mut w = StateWriter::default();
        w.bytes(STATE_HEADER);
        w.put(&Self::KIND.to_string());
        self.put(&mut w);
        let sum = crate::hash::fnv1a64(&w.out);
        w.bytes(&sum.to_le_bytes());
        w.out
    }

    /// A learner from the bytes of [`to_bytes`](Self::to_bytes); an error
    /// saying what is wrong if they are not such bytes.
    fn from_bytes(bytes: &[u8]) -> Result<Self, LearnerError> {
        let read = |rest: &[u8]| -> Result<Self, LearnerError> {
            let mut r = StateReader {
                rest,
                kind: Self::KIND,
            };
            let kind: String = r.get()?;
            r.check(kind == Self::KIND, || {
                format!("the bytes hold the state of a `{kind}` learner")
            })?;
            let l = Self::get(&mut r)?;
            r.check(r.rest.is_empty(), || {
                format!("{} bytes after the state", r.rest.len())
            })?;
            Ok(l)
        };
        match state_body(bytes) {
            Ok(rest) => read(rest),
            // a state cut short fails its checksum too: say where it ends
            Err(e) => {
                let Some(rest) = bytes.strip_prefix(STATE_HEADER) else {
                    return Err(e);
                };
                match read(rest) {
                    Err(cut) if cut.to_string().contains("end early") => Err(cut),
                    // the whole state, then part of its checksum or none
                    _ if (0..8)
                        .any(|k| rest.len() >= k && read(&rest[..rest.len() - k]).is_ok()) =>
                    {
                        Err(LearnerError::State(format!(
                            "state of a `{}` learner: the bytes end early, in or before its checksum",
                            Self::KIND
                        )))
                    }
                    _ => Err(e),
                }
            }
        }
    }
}

/// What a learner was made for: its slots, its effects and its contexts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateShape {
    /// The alphabet size of each slot (0 for a slot of continuous values).
    pub sizes: Vec<usize>,
    /// The number of effects, if the learner keeps a table over them.
    pub effects: Option<usize>,
    /// The number of contexts, if the learner is contextual.
    pub contexts: Option<usize>,
}

impl StateShape {
    /// Whether a learner of this shape can run on slots of alphabet sizes
    /// `sizes` (0 for values) with `effects` effects and `contexts`
    /// contexts (`None`: not contextual); `Err` says why not.
    pub fn fits(
        &self,
        sizes: &[usize],
        effects: usize,
        contexts: Option<usize>,
    ) -> Result<(), String> {
        if self.sizes != sizes {
            return Err(format!(
                "the learner's slots have alphabet sizes {:?} (0: values), the scene's {sizes:?}",
                self.sizes
            ));
        }
        if let Some(e) = self.effects.filter(|&e| e != effects) {
            return Err(format!("the learner has {e} effects, the scene {effects}"));
        }
        if self.contexts != contexts {
            let says =
                |c: Option<usize>| c.map_or("no contexts".into(), |c| format!("{c} contexts"));
            return Err(format!(
                "the learner has {}, the run {}",
                says(self.contexts),
                says(contexts)
            ));
        }
        Ok(())
    }

    /// A context-free learner's shape: `sizes`, `effects`.
    pub(crate) fn of(sizes: Vec<usize>, effects: Option<usize>) -> StateShape {
        StateShape {
            sizes,
            effects,
            contexts: None,
        }
    }
}

/// The alphabet sizes of slots laid out at `offsets`.
pub(crate) fn sizes_of(offsets: &[usize]) -> Vec<usize> {
    offsets.windows(2).map(|w| w[1] - w[0]).collect()
}

/// The error of bytes that do not start with [`STATE_HEADER`].
fn no_header() -> LearnerError {
    LearnerError::State(format!(
        "not a learner's state (it does not start with {:?})",
        String::from_utf8_lossy(STATE_HEADER)
    ))
}

/// The kind of learner whose state `bytes` hold (`"e3d"`, `"count"`, ...),
/// or why they are not a learner's state.
pub fn state_kind(bytes: &[u8]) -> Result<String, LearnerError> {
    let rest = state_start(bytes)?;
    let mut r = StateReader { rest, kind: "?" };
    r.get()
        .map_err(|_| LearnerError::State("a learner's state cut before its kind".into()))
}

/// The kind of the learners of a `per_context` state (`"e3d"`,
/// `"count"`, ...: the kind written after `"per_context"`), or why
/// `bytes` are not such a state.
pub fn per_context_kind(bytes: &[u8]) -> Result<String, LearnerError> {
    let rest = state_start(bytes)?;
    let mut r = StateReader {
        rest,
        kind: "per_context",
    };
    let kind: String = r.get()?;
    r.check(kind == "per_context", || {
        format!("the bytes hold the state of a `{kind}` learner")
    })?;
    r.get()
}

impl StateField for f64 {
    fn put(&self, w: &mut StateWriter) {
        w.bytes(&self.to_bits().to_le_bytes());
    }
    /// A number, never NaN: no learner keeps one, and a NaN rate or
    /// table entry would make every proposal and update NaN.
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let b = r.take(8)?;
        let v = f64::from_bits(u64::from_le_bytes(b.try_into().expect("8 bytes")));
        if v.is_nan() {
            return Err(r.error("a number that is NaN (a learner's state holds none)"));
        }
        Ok(v)
    }
}

impl StateField for u64 {
    fn put(&self, w: &mut StateWriter) {
        w.bytes(&self.to_le_bytes());
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let b = r.take(8)?;
        Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
}

impl StateField for usize {
    fn put(&self, w: &mut StateWriter) {
        w.put(&(*self as u64));
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let v: u64 = r.get()?;
        usize::try_from(v).map_err(|_| r.error(&format!("{v} does not fit a usize")))
    }
}

impl StateField for char {
    fn put(&self, w: &mut StateWriter) {
        w.bytes(&u32::from(*self).to_le_bytes());
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let v = u32::from_le_bytes(r.take(4)?.try_into().expect("4 bytes"));
        char::from_u32(v).ok_or_else(|| r.error(&format!("{v:#x} is not a character")))
    }
}

impl StateField for String {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self.len());
        w.bytes(self.as_bytes());
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let n = r.len(1)?;
        let b = r.take(n)?;
        String::from_utf8(b.to_vec()).map_err(|_| r.error("a string that is not UTF-8"))
    }
}

/// A sequence: its length, then each item.
fn put_seq<'a, T: StateField + 'a>(
    w: &mut StateWriter,
    items: impl ExactSizeIterator<Item = &'a T>,
) {
    w.put(&items.len());
    for v in items {
        v.put(w);
    }
}

/// A sequence [`put_seq`] wrote, collected.
fn get_seq<T: StateField, C: FromIterator<T>>(r: &mut StateReader<'_>) -> Result<C, LearnerError> {
    let n = r.len(1)?;
    (0..n).map(|_| T::get(r)).collect()
}

impl<T: StateField> StateField for Vec<T> {
    fn put(&self, w: &mut StateWriter) {
        put_seq(w, self.iter());
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        get_seq(r)
    }
}

impl StateField for u8 {
    fn put(&self, w: &mut StateWriter) {
        w.bytes(&[*self]);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        Ok(r.take(1)?[0])
    }
}

/// `None` is the byte 0; `Some(v)` the byte 1, then `v`.
impl<T: StateField> StateField for Option<T> {
    fn put(&self, w: &mut StateWriter) {
        match self {
            None => w.bytes(&[0]),
            Some(v) => {
                w.bytes(&[1]);
                v.put(w);
            }
        }
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        match r.take(1)?[0] {
            0 => Ok(None),
            1 => Ok(Some(T::get(r)?)),
            b => Err(r.error(&format!("an option tagged {b} (expected 0 or 1)"))),
        }
    }
}

impl StateField for [f64; 2] {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self[0]).put(&self[1]);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        Ok([r.get()?, r.get()?])
    }
}

impl<T: StateField> StateField for std::collections::VecDeque<T> {
    fn put(&self, w: &mut StateWriter) {
        put_seq(w, self.iter());
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        get_seq(r)
    }
}

impl<A: StateField, B: StateField> StateField for (A, B) {
    fn put(&self, w: &mut StateWriter) {
        self.0.put(w);
        self.1.put(w);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        Ok((A::get(r)?, B::get(r)?))
    }
}

impl StateField for EffectModel {
    fn put(&self, w: &mut StateWriter) {
        let (q, scale, eta) = self.raw();
        w.put(&q.to_vec()).put(&scale).put(&eta);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let (q, scale, eta) = (r.get()?, r.get()?, r.get()?);
        EffectModel::from_raw(q, scale, eta).map_err(|e| r.error(&format!("effect model: {e}")))
    }
}

impl StateField for CommandSpace {
    fn put(&self, w: &mut StateWriter) {
        let alphabets: Vec<Vec<char>> = (0..self.num_slots())
            .map(|s| self.alphabet(s).to_vec())
            .collect();
        w.put(&alphabets);
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let alphabets: Vec<Vec<char>> = r.get()?;
        CommandSpace::new(alphabets).map_err(|e| r.error(&format!("command space: {e}")))
    }
}

impl StateField for ValueSpace {
    fn put(&self, w: &mut StateWriter) {
        w.put(&self.ranges().to_vec());
    }
    fn get(r: &mut StateReader<'_>) -> Result<Self, LearnerError> {
        let ranges: Vec<(f64, f64)> = r.get()?;
        ValueSpace::new(ranges).map_err(|e| r.error(&format!("value space: {e}")))
    }
}

/// Checks that the rates and the `Q` tables read from a state are
/// finite, the inverse temperature `beta` > 0 (`rates` named as the
/// learner's fields).
pub(crate) fn check_rates(
    r: &StateReader<'_>,
    rates: &[(&str, f64)],
    beta: f64,
) -> Result<(), LearnerError> {
    if let Some((name, v)) = rates.iter().find(|(_, v)| !v.is_finite()) {
        return Err(r.error(&format!("rate `{name}`: a finite number, found {v}")));
    }
    r.check(beta.is_finite() && beta > 0.0, || {
        format!("`beta`: a finite number > 0, found {beta}")
    })
}

/// Checks that every value of table `name` read from a state is finite.
pub(crate) fn check_finite(
    r: &StateReader<'_>,
    name: &str,
    values: &[f64],
) -> Result<(), LearnerError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(r.error(&format!(
            "table `{name}`: finite values, found {} at entry {i}",
            values[i]
        ))),
    }
}

/// Checks that `log_target` (read from a state) has one value per effect
/// of `model`.
pub(crate) fn check_target(
    r: &StateReader<'_>,
    log_target: &[f64],
    model: &EffectModel,
) -> Result<(), LearnerError> {
    r.check(log_target.len() == model.num_effects(), || {
        format!(
            "a target of {} effects for an effect model of {}",
            log_target.len(),
            model.num_effects()
        )
    })
}
