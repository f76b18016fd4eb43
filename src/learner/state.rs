//! Saving and loading a learner's whole state, bit for bit, in one
//! format for every learner (docs/robustness.md, "Saved learner states"):
//! the header [`STATE_HEADER`], the learner's [`KIND`](LearnerState::KIND)
//! and its serde fields in postcard's wire format (a float as its 8 bytes),
//! then the FNV-1a checksum of all before. Reading checks the checksum,
//! the kind, that no number is NaN, then the learner's own
//! [`validate`](LearnerState::validate); what is wrong is a
//! [`LearnerError::State`], never a panic. A learner read back proposes
//! and learns exactly as the saved one would.
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
use crate::hash::fnv1a64;
use serde::de::DeserializeOwned;
use serde::ser::{self, Serialize};
use tables::{no_table, StateTable};

pub mod tables;

/// The first bytes of every learner's saved state (the format's version
/// is the number).
pub const STATE_HEADER: &[u8] = b"E3D-LEARNER-STATE 3\n";

/// The bytes of a state past its header; the error of a state of another
/// version (named) or of bytes that are no state at all.
fn payload(bytes: &[u8]) -> Result<&[u8], LearnerError> {
    if let Some(rest) = bytes.strip_prefix(STATE_HEADER) {
        return Ok(rest);
    }
    let Some(v) = bytes.strip_prefix(b"E3D-LEARNER-STATE ") else {
        return Err(LearnerError::State(format!(
            "not a learner's state (it does not start with {:?})",
            String::from_utf8_lossy(STATE_HEADER)
        )));
    };
    let end = v.iter().position(|&b| b == b'\n').unwrap_or(v.len());
    let v = crate::text::echo(&String::from_utf8_lossy(&v[..end.min(20)]));
    let old = if v == "1" || v == "2" {
        " (written by an e3d from before its learner states went through serde)"
    } else {
        ""
    };
    Err(LearnerError::State(format!(
        "a learner's state of format version {v}{old}: this e3d reads version 3 only; \
         save the learner again from a run of this e3d"
    )))
}

/// Whether the last 8 bytes of `bytes` are the checksum of all before.
pub(crate) fn intact(bytes: &[u8]) -> bool {
    let Some(at) = bytes.len().checked_sub(8) else {
        return false;
    };
    bytes[at..] == fnv1a64(&bytes[..at]).to_le_bytes()
}

/// What a decoding error says of the bytes.
fn why(e: postcard::Error) -> String {
    match e {
        postcard::Error::DeserializeUnexpectedEnd => "the bytes end early".into(),
        e => format!("bytes that do not decode as its state ({e})"),
    }
}

/// The learner of kind `L` in a state's `payload`, and the length of its
/// bytes; `Err` says why not.
fn read<L: LearnerState>(payload: &[u8]) -> Result<(L, usize), String> {
    let (kind, rest): (String, _) = postcard::take_from_bytes(payload).map_err(why)?;
    if kind != L::KIND {
        return Err(format!("the bytes hold the state of a `{kind}` learner"));
    }
    let (l, rest) = postcard::take_from_bytes(rest).map_err(why)?;
    Ok((l, payload.len() - rest.len()))
}

/// A learner of kind `L` from the bytes of [`LearnerState::to_bytes`],
/// checked (see [the module](self)).
pub(crate) fn decode<L: LearnerState>(bytes: &[u8]) -> Result<L, LearnerError> {
    let rest = payload(bytes)?;
    let error =
        |what: String| LearnerError::State(format!("state of a `{}` learner: {what}", L::KIND));
    if rest.len() < 8 || !intact(bytes) {
        // a cut, bytes after a whole state, or damage
        let what = match read::<L>(rest) {
            Err(e) if e.ends_with("end early") => e,
            Ok((_, n)) if rest.len() < n + 8 => {
                "the bytes end early, in or before its checksum".into()
            }
            Ok((_, n)) if intact(&bytes[..bytes.len() - rest.len() + n + 8]) => {
                format!("{} bytes after the state", rest.len() - n - 8)
            }
            _ => {
                let (body, sum) = bytes.split_at(bytes.len().max(8) - 8);
                return Err(LearnerError::State(format!(
                    "a learner's state whose checksum does not match its bytes (damaged or edited: \
                     {:016x}, recorded {})",
                    fnv1a64(body),
                    sum.iter().rev().map(|b| format!("{b:02x}")).collect::<String>()
                )));
            }
        };
        return Err(error(what));
    }
    let (l, n) = read::<L>(&rest[..rest.len() - 8]).map_err(error)?;
    if n + 8 != rest.len() {
        return Err(error(format!(
            "{} bytes after the state",
            rest.len() - n - 8
        )));
    }
    if l.serialize(NanFinder).is_err() {
        return Err(error(
            "a number that is NaN (a learner's state holds none)".into(),
        ));
    }
    l.validate().map_err(error)?;
    Ok(l)
}

/// A learner whose whole state can be saved as bytes and read back bit for
/// bit (see [the module](self) for the format): derive `Serialize` and
/// `Deserialize` for its fields, name its kind and its shape.
pub trait LearnerState: Serialize + DeserializeOwned {
    /// The learner's kind, written in its state (`"e3d"`, `"count"`, ...).
    const KIND: &'static str;

    /// What the learner was made for: check it before running a loaded
    /// learner on a scene ([`StateShape::fits`]).
    fn shape(&self) -> StateShape;

    /// Checks a learner just read from bytes (after the checksum, its kind
    /// and the absence of NaN): what its constructor would have refused,
    /// such as rates out of range or tables that do not fit together;
    /// `Err` says what is wrong. Nothing by default.
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

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
        let mut out = postcard::to_extend(&(Self::KIND, self), STATE_HEADER.to_vec())
            .expect("a learner's fields serialise");
        out.extend_from_slice(&fnv1a64(&out).to_le_bytes());
        out
    }

    /// A learner from the bytes of [`to_bytes`](Self::to_bytes); an error
    /// saying what is wrong if they are not such bytes.
    fn from_bytes(bytes: &[u8]) -> Result<Self, LearnerError> {
        decode(bytes)
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

/// The kind of learner whose state `bytes` hold (`"e3d"`, `"count"`, ...),
/// or why they are not a learner's state.
pub fn state_kind(bytes: &[u8]) -> Result<String, LearnerError> {
    postcard::take_from_bytes(payload(bytes)?)
        .map(|(kind, _)| kind)
        .map_err(|_| LearnerError::State("a learner's state cut before its kind".into()))
}

/// The kind of the learners of a `per_context` state (`"e3d"`,
/// `"count"`, ...: the kind written after `"per_context"`), or why
/// `bytes` are not such a state.
pub fn per_context_kind(bytes: &[u8]) -> Result<String, LearnerError> {
    let error =
        |what: String| LearnerError::State(format!("state of a `per_context` learner: {what}"));
    let ((kind, inner), _): ((String, String), _) =
        postcard::take_from_bytes(payload(bytes)?).map_err(|e| error(why(e)))?;
    if kind != "per_context" {
        return Err(error(format!(
            "the bytes hold the state of a `{kind}` learner"
        )));
    }
    Ok(inner)
}

/// `Ok` if `ok`, else `Err(what())`.
pub(crate) fn ensure(ok: bool, what: impl FnOnce() -> String) -> Result<(), String> {
    ok.then_some(()).ok_or_else(what)
}

/// Checks rates read from a state: finite (`rates` named as the
/// learner's fields), the inverse temperature `beta` > 0.
pub(crate) fn check_rates(rates: &[(&str, f64)], beta: f64) -> Result<(), String> {
    if let Some((name, v)) = rates.iter().find(|(_, v)| !v.is_finite()) {
        return Err(format!("rate `{name}`: a finite number, found {v}"));
    }
    ensure(beta.is_finite() && beta > 0.0, || {
        format!("`beta`: a finite number > 0, found {beta}")
    })
}

/// Checks that every value of table `name` read from a state is finite.
pub(crate) fn check_finite(name: &str, values: &[f64]) -> Result<(), String> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(format!(
            "table `{name}`: finite values, found {} at entry {i}",
            values[i]
        )),
    }
}

/// Checks an effect model read from a state (as
/// [`EffectModel::from_raw`]) and that `log_target` has one value per
/// effect.
pub(crate) fn check_model(model: &EffectModel, log_target: &[f64]) -> Result<(), String> {
    let (q, scale, eta) = model.raw();
    EffectModel::from_raw(q.to_vec(), scale, eta).map_err(|e| format!("effect model: {e}"))?;
    ensure(log_target.len() == model.num_effects(), || {
        format!(
            "a target of {} effects for an effect model of {}",
            log_target.len(),
            model.num_effects()
        )
    })
}

/// Checks a command space read from a state (as [`CommandSpace::new`]).
pub(crate) fn check_space(space: &CommandSpace) -> Result<(), String> {
    let alphabets = (0..space.num_slots()).map(|s| space.alphabet(s).to_vec());
    CommandSpace::new(alphabets.collect()).map_err(|e| format!("command space: {e}"))?;
    Ok(())
}

/// Checks a value space read from a state (as [`ValueSpace::new`]).
pub(crate) fn check_values(space: &ValueSpace) -> Result<(), String> {
    ValueSpace::new(space.ranges().to_vec()).map_err(|e| format!("value space: {e}"))?;
    Ok(())
}

/// A `serde` serializer that writes nothing and fails at the first NaN:
/// `value.serialize(NanFinder).is_err()` when `value` holds one.
struct NanFinder;

/// What [`NanFinder`] found.
#[derive(Debug)]
struct FoundNan;

impl std::fmt::Display for FoundNan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a NaN")
    }
}

impl std::error::Error for FoundNan {}

impl ser::Error for FoundNan {
    fn custom<T: std::fmt::Display>(_: T) -> Self {
        FoundNan
    }
}

/// `NanFinder`'s methods: `leaf`s hold no float, `open` a compound value
/// (its parts come next), `inner` a value around another.
macro_rules! nan_finder {
    (leaf $($l:ident($($lt:ty),*))*; open $($o:ident($($ot:ty),*))*; inner $($i:ident($($it:ty),*))*) => {
        $(fn $l(self, $(_: $lt),*) -> Result<(), FoundNan> { Ok(()) })*
        $(fn $o(self, $(_: $ot),*) -> Result<Self, FoundNan> { Ok(self) })*
        $(fn $i<T: Serialize + ?Sized>(self, $(_: $it,)* v: &T) -> Result<(), FoundNan> { v.serialize(self) })*
    };
}

/// The parts of compound values, each looked through.
macro_rules! parts {
    ($($tr:ident { $($m:ident($($k:ty)?))* })*) => {$(
        impl ser::$tr for NanFinder {
            type Ok = ();
            type Error = FoundNan;
            $(fn $m<T: Serialize + ?Sized>(&mut self, $(_: $k,)? v: &T) -> Result<(), FoundNan> { v.serialize(NanFinder) })*
            fn end(self) -> Result<(), FoundNan> { Ok(()) }
        }
    )*};
}

parts! {
    SerializeSeq { serialize_element() } SerializeTuple { serialize_element() }
    SerializeTupleStruct { serialize_field() } SerializeTupleVariant { serialize_field() }
    SerializeMap { serialize_key() serialize_value() }
    SerializeStruct { serialize_field(&'static str) }
    SerializeStructVariant { serialize_field(&'static str) }
}

impl ser::Serializer for NanFinder {
    type Ok = ();
    type Error = FoundNan;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Self;
    type SerializeTupleVariant = Self;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Self;
    fn serialize_f64(self, v: f64) -> Result<(), FoundNan> {
        (!v.is_nan()).then_some(()).ok_or(FoundNan)
    }
    fn serialize_f32(self, v: f32) -> Result<(), FoundNan> {
        self.serialize_f64(v.into())
    }
    nan_finder! {
        leaf serialize_bool(bool) serialize_i8(i8) serialize_i16(i16) serialize_i32(i32)
        serialize_i64(i64) serialize_u8(u8) serialize_u16(u16) serialize_u32(u32)
        serialize_u64(u64) serialize_char(char) serialize_str(&str) serialize_bytes(&[u8])
        serialize_none() serialize_unit() serialize_unit_struct(&'static str)
        serialize_unit_variant(&'static str, u32, &'static str);
        open serialize_seq(Option<usize>) serialize_tuple(usize) serialize_map(Option<usize>)
        serialize_tuple_struct(&'static str, usize) serialize_struct(&'static str, usize)
        serialize_tuple_variant(&'static str, u32, &'static str, usize)
        serialize_struct_variant(&'static str, u32, &'static str, usize);
        inner serialize_some() serialize_newtype_struct(&'static str)
        serialize_newtype_variant(&'static str, u32, &'static str)
    }
}
