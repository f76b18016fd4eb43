//! Commands: `n` slots, one symbol per slot.
//!
//! A [`CommandSpace`] says how many slots a command has and which symbols
//! each slot accepts (its *alphabet*). A [`Command`] is one symbol index per
//! slot. Commands print as their symbols, one character per slot
//! (`"ESSEENE"` on the grid, `"+0-0+00"` on the arm).
//!
//! A *continuous* command (the paper's first "future work") takes a value
//! per slot instead of a symbol: a [`ValueSpace`] gives each slot its range
//! `[min, max]`, and a command is one `f64` per slot, written as numbers
//! separated by commas (`"1.8, -0.3, 0, 0.75, 0, 0, 0.06"`).

use serde::{Deserialize, Serialize};
use std::fmt;

/// The largest number of symbols in one slot's alphabet.
pub const MAX_ALPHABET: usize = 64;
/// The largest number of slots in a command.
pub const MAX_SLOTS: usize = 64;

/// The longest command echoed whole in a message, in characters.
pub const ECHO_CHARS: usize = 80;

/// A command as echoed in messages: whole up to [`ECHO_CHARS`]
/// characters, else its start and `…` with its length.
pub fn echo(text: &str) -> String {
    let mut chars = text.char_indices();
    match chars.nth(ECHO_CHARS) {
        None => text.to_string(),
        Some((at, _)) => format!(
            "{}… ({} characters in all)",
            &text[..at],
            text.chars().count()
        ),
    }
}

/// An error about a command or a command space.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommandError {
    /// The text has a different number of symbols than the space has slots.
    #[error("command `{text}` has {found} symbols, expected {expected} (one per slot)")]
    WrongLength {
        /// The command as given.
        text: String,
        /// Its number of symbols.
        found: usize,
        /// The number of slots.
        expected: usize,
    },
    /// A symbol is not in its slot's alphabet.
    #[error("command `{text}`: symbol '{symbol}' at slot {slot} is not one of {alphabet}")]
    UnknownSymbol {
        /// The command as given.
        text: String,
        /// The offending symbol.
        symbol: char,
        /// Its slot (0-based).
        slot: usize,
        /// The slot's alphabet, as a string.
        alphabet: String,
    },
    /// The space itself is malformed.
    #[error("{0}")]
    Space(String),
    /// A continuous command has a different number of values than the
    /// space has slots.
    #[error("command `{text}` has {found} values, expected {expected} (one per slot)")]
    WrongCount {
        /// The command as given.
        text: String,
        /// Its number of values.
        found: usize,
        /// The number of slots.
        expected: usize,
    },
    /// A value of a continuous command is not a number.
    #[error("command `{text}`: `{part}` at slot {slot} is not a number")]
    NotANumber {
        /// The command as given.
        text: String,
        /// The part that is not a number.
        part: String,
        /// Its slot (0-based).
        slot: usize,
    },
    /// A value of a continuous command is outside its slot's range.
    #[error("command `{text}`: value {value} at slot {slot} is outside its range [{min}, {max}]")]
    OutOfRange {
        /// The command as given.
        text: String,
        /// The value.
        value: f64,
        /// Its slot (0-based).
        slot: usize,
        /// The slot's smallest value.
        min: f64,
        /// The slot's largest value.
        max: f64,
    },
}

/// Refuses a space of no slot or of more than [`MAX_SLOTS`].
fn check_slots(n: usize) -> Result<(), CommandError> {
    if n == 0 {
        return Err(CommandError::Space(
            "a command needs at least one slot".into(),
        ));
    }
    if n > MAX_SLOTS {
        return Err(CommandError::Space(format!(
            "{n} slots: at most {MAX_SLOTS} are supported"
        )));
    }
    Ok(())
}

/// The command space: `n` slots, each with its alphabet of symbols.
///
/// ```
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(7, &['E', 'S', 'W', 'N']).unwrap();
/// assert_eq!(space.num_commands(), Some(16384));
/// let c = space.parse("ESSEENE").unwrap();
/// assert_eq!(space.format(&c), "ESSEENE");
/// assert_eq!(space.command_at(space.index_of(&c)), c);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CommandSpace {
    alphabets: Vec<Vec<char>>,
}

impl CommandSpace {
    /// A space whose slots have the given alphabets (slot `i` takes a symbol
    /// of `alphabets[i]`). Symbols within a slot must be distinct.
    pub fn new(alphabets: Vec<Vec<char>>) -> Result<Self, CommandError> {
        check_slots(alphabets.len())?;
        for (i, a) in alphabets.iter().enumerate() {
            if a.is_empty() {
                return Err(CommandError::Space(format!(
                    "slot {i} has an empty alphabet"
                )));
            }
            if a.len() > MAX_ALPHABET {
                return Err(CommandError::Space(format!(
                    "slot {i} has {} symbols: at most {MAX_ALPHABET} are supported",
                    a.len()
                )));
            }
            for (j, s) in a.iter().enumerate() {
                if a[..j].contains(s) {
                    return Err(CommandError::Space(format!(
                        "slot {i}: symbol '{s}' appears twice"
                    )));
                }
            }
        }
        Ok(CommandSpace { alphabets })
    }

    /// `n` slots sharing one alphabet.
    pub fn repeat(n: usize, alphabet: &[char]) -> Result<Self, CommandError> {
        Self::new(vec![alphabet.to_vec(); n])
    }

    /// The number of slots `n`.
    pub fn num_slots(&self) -> usize {
        self.alphabets.len()
    }

    /// The alphabet of slot `slot`.
    pub fn alphabet(&self, slot: usize) -> &[char] {
        &self.alphabets[slot]
    }

    /// The alphabet sizes, slot by slot.
    pub fn sizes(&self) -> impl DoubleEndedIterator<Item = usize> + ExactSizeIterator + '_ {
        self.alphabets.iter().map(Vec::len)
    }

    /// The number of distinct commands, or `None` if it exceeds `u64`.
    pub fn num_commands(&self) -> Option<u64> {
        self.sizes()
            .try_fold(1u64, |acc, k| acc.checked_mul(k as u64))
    }

    /// The number of commands written out exactly, in decimal, even when
    /// it does not fit a `u64` (4^64 is
    /// 340282366920938463463374607431768211456, not 18446744073709551615).
    pub fn num_commands_text(&self) -> String {
        // base 10^9 digits, least significant first
        let mut digits: Vec<u64> = vec![1];
        for k in self.sizes() {
            let mut carry = 0u64;
            for d in digits.iter_mut() {
                let v = *d * k as u64 + carry;
                *d = v % 1_000_000_000;
                carry = v / 1_000_000_000;
            }
            while carry > 0 {
                digits.push(carry % 1_000_000_000);
                carry /= 1_000_000_000;
            }
        }
        let mut out = digits.last().map_or(String::new(), |d| d.to_string());
        for d in digits.iter().rev().skip(1) {
            out.push_str(&format!("{d:09}"));
        }
        out
    }

    /// A command of all first symbols (index 0 in every slot).
    pub fn first(&self) -> Command {
        Command {
            symbols: vec![0; self.num_slots()],
        }
    }

    /// The command written as symbols, one character per slot. A symbol
    /// index outside its slot's alphabet (a command of another space) is
    /// written `?`, and slots beyond this space's are left out: formatting
    /// never panics, so that errors can always show the command.
    pub fn format(&self, command: &Command) -> String {
        command
            .symbols
            .iter()
            .zip(&self.alphabets)
            .map(|(&s, a)| a.get(s as usize).copied().unwrap_or('?'))
            .collect()
    }

    /// Parses a command written as symbols, one character per slot.
    pub fn parse(&self, text: &str) -> Result<Command, CommandError> {
        let chars: Vec<char> = text.trim().chars().collect();
        if chars.len() != self.num_slots() {
            return Err(CommandError::WrongLength {
                text: echo(text),
                found: chars.len(),
                expected: self.num_slots(),
            });
        }
        let mut symbols = Vec::with_capacity(chars.len());
        for (slot, (c, a)) in chars.iter().zip(&self.alphabets).enumerate() {
            match a.iter().position(|s| s == c) {
                Some(k) => symbols.push(k as u8),
                None => {
                    return Err(CommandError::UnknownSymbol {
                        text: echo(text),
                        symbol: *c,
                        slot,
                        alphabet: a.iter().collect(),
                    })
                }
            }
        }
        Ok(Command { symbols })
    }

    /// The index of a command in `0..num_commands()`, mixed radix with slot 0
    /// the most significant digit (so the order is lexicographic).
    pub fn index_of(&self, command: &Command) -> u64 {
        command
            .symbols
            .iter()
            .zip(self.sizes())
            .fold(0u64, |acc, (&s, k)| acc * k as u64 + s as u64)
    }

    /// The command with the given index (the inverse of [`index_of`](Self::index_of)).
    pub fn command_at(&self, index: u64) -> Command {
        let mut c = self.first();
        self.write_command_at(index, &mut c);
        c
    }

    /// Writes the command with the given index into `command` (no allocation).
    pub fn write_command_at(&self, mut index: u64, command: &mut Command) {
        command.symbols.resize(self.num_slots(), 0);
        for (slot, k) in self.sizes().enumerate().rev() {
            command.symbols[slot] = (index % k as u64) as u8;
            index /= k as u64;
        }
    }

    /// Every command, in index order. Only sensible for small spaces.
    pub fn iter(&self) -> impl Iterator<Item = Command> + '_ {
        (0..self.num_commands().unwrap_or(u64::MAX)).map(move |i| self.command_at(i))
    }
}

/// One command: a symbol index per slot (`symbols[i]` indexes slot `i`'s
/// alphabet).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub struct Command {
    /// The symbol index of each slot.
    pub symbols: Vec<u8>,
}

impl Command {
    /// A command from symbol indices.
    pub fn new(symbols: Vec<u8>) -> Self {
        Command { symbols }
    }

    /// The number of slots.
    pub fn len(&self) -> usize {
        self.symbols.len()
    }

    /// Whether the command has no slot.
    pub fn is_empty(&self) -> bool {
        self.symbols.is_empty()
    }
}

impl AsRef<[u8]> for Command {
    fn as_ref(&self) -> &[u8] {
        &self.symbols
    }
}

impl fmt::Display for Command {
    /// Writes the symbol indices, e.g. `[0, 1, 1, 0]`; use
    /// [`CommandSpace::format`] for the symbols themselves.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.symbols)
    }
}

/// The command space of a scene whose slots take values: slot `i` takes a
/// number in `[min_i, max_i]` (a torque in N·m, a target angle, an impulse
/// direction: the scene says which).
///
/// ```
/// use e3d::command::ValueSpace;
/// let space = ValueSpace::new(vec![(-1.8, 1.8), (0.0, 3.0)]).unwrap();
/// let v = space.parse("1.5, 0.25").unwrap();
/// assert_eq!(v, [1.5, 0.25]);
/// assert_eq!(space.format(&v), "1.5,0.25");
/// let e = space.parse("1.5, 4").unwrap_err();
/// assert_eq!(e.to_string(), "command `1.5, 4`: value 4 at slot 1 is outside its range [0, 3]");
/// // the unit cube [-1, 1]^n maps onto the ranges
/// assert_eq!(space.from_unit(0, 1.0), 1.8);
/// assert_eq!(space.from_unit(1, -1.0), 0.0);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValueSpace {
    ranges: Vec<(f64, f64)>,
}

impl ValueSpace {
    /// A space whose slot `i` takes a value in `ranges[i] = (min, max)`,
    /// finite with `min < max`.
    pub fn new(ranges: Vec<(f64, f64)>) -> Result<Self, CommandError> {
        check_slots(ranges.len())?;
        for (i, &(lo, hi)) in ranges.iter().enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(CommandError::Space(format!(
                    "slot {i}: the range [{lo}, {hi}] needs finite bounds with min < max"
                )));
            }
        }
        Ok(ValueSpace { ranges })
    }

    /// The number of slots `n`.
    pub fn num_slots(&self) -> usize {
        self.ranges.len()
    }

    /// The range `(min, max)` of slot `slot`.
    pub fn range(&self, slot: usize) -> (f64, f64) {
        self.ranges[slot]
    }

    /// Every slot's range.
    pub fn ranges(&self) -> &[(f64, f64)] {
        &self.ranges
    }

    /// The value of slot `slot` at `u` in `[-1, 1]` (`-1` is the slot's
    /// min, `1` its max, linearly between; `u` outside is clamped).
    pub fn from_unit(&self, slot: usize, u: f64) -> f64 {
        let (lo, hi) = self.ranges[slot];
        let u = u.clamp(-1.0, 1.0);
        if u == 1.0 {
            return hi;
        }
        lo + (u + 1.0) * 0.5 * (hi - lo)
    }

    /// `Ok` if `values` has one value per slot, each finite and within
    /// its slot's range.
    pub fn check(&self, values: &[f64]) -> Result<(), CommandError> {
        let text = || echo(&self.format(values));
        if values.len() != self.num_slots() {
            return Err(CommandError::WrongCount {
                text: text(),
                found: values.len(),
                expected: self.num_slots(),
            });
        }
        for (slot, &v) in values.iter().enumerate() {
            self.check_value(slot, v, text)?;
        }
        Ok(())
    }

    /// `Ok` if `v` is within `slot`'s range, else the
    /// [`CommandError::OutOfRange`] of the command `text()`.
    fn check_value(
        &self,
        slot: usize,
        v: f64,
        text: impl FnOnce() -> String,
    ) -> Result<(), CommandError> {
        let (lo, hi) = self.ranges[slot];
        if v >= lo && v <= hi {
            return Ok(());
        }
        Err(CommandError::OutOfRange {
            text: text(),
            value: v,
            slot,
            min: lo,
            max: hi,
        })
    }

    /// The values written as numbers separated by commas, each in the
    /// shortest form that reads back to the same `f64`.
    pub fn format(&self, values: &[f64]) -> String {
        let parts: Vec<String> = values.iter().map(|v| format!("{v}")).collect();
        parts.join(",")
    }

    /// Parses numbers separated by commas (spaces allowed), one per slot,
    /// each within its slot's range.
    pub fn parse(&self, text: &str) -> Result<Vec<f64>, CommandError> {
        let parts: Vec<&str> = text.trim().split(',').map(str::trim).collect();
        if parts.len() != self.num_slots() {
            return Err(CommandError::WrongCount {
                text: echo(text.trim()),
                found: parts.len(),
                expected: self.num_slots(),
            });
        }
        let mut values = Vec::with_capacity(parts.len());
        for (slot, part) in parts.iter().enumerate() {
            let v: f64 = part.parse().map_err(|_| CommandError::NotANumber {
                text: echo(text.trim()),
                part: echo(part),
                slot,
            })?;
            self.check_value(slot, v, || echo(text.trim()))?;
            values.push(v);
        }
        Ok(values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_command_of_another_space_formats_without_panicking() {
        let s = CommandSpace::new(vec![vec!['a', 'b'], vec!['x', 'y']]).unwrap();
        assert_eq!(s.format(&Command::new(vec![1, 7])), "b?");
        assert_eq!(s.format(&Command::new(vec![0, 1, 2])), "ay");
    }

    #[test]
    fn index_round_trip_over_mixed_radix() {
        let s = CommandSpace::new(vec![vec!['a', 'b'], vec!['x', 'y', 'z'], vec!['0']]).unwrap();
        assert_eq!(s.num_commands(), Some(6));
        let all: Vec<String> = s.iter().map(|c| s.format(&c)).collect();
        assert_eq!(all, ["ax0", "ay0", "az0", "bx0", "by0", "bz0"]);
        for i in 0..6 {
            assert_eq!(s.index_of(&s.command_at(i)), i);
        }
    }

    #[test]
    fn long_commands_are_echoed_shortened() {
        let space = CommandSpace::new(vec![vec!['E', 'S']; 7]).unwrap();
        let long = "E".repeat(1_000_000);
        let e = space.parse(&long).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "command `{}… (1000000 characters in all)` has 1000000 symbols, expected 7 (one per slot)",
                "E".repeat(80)
            )
        );
        assert_eq!(echo("ééé"), "ééé");
    }

    #[test]
    fn huge_counts_are_written_exactly() {
        let space = CommandSpace::new(vec![vec!['a', 'b', 'c', 'd']; 64]).unwrap();
        assert_eq!(space.num_commands(), None);
        assert_eq!(
            space.num_commands_text(),
            "340282366920938463463374607431768211456"
        );
        let small = CommandSpace::new(vec![vec!['a', 'b', 'c']; 7]).unwrap();
        assert_eq!(small.num_commands_text(), "2187");
    }

    #[test]
    fn parse_reports_the_bad_symbol_and_slot() {
        let s = CommandSpace::repeat(3, &['E', 'S']).unwrap();
        let e = s.parse("ESX").unwrap_err();
        assert_eq!(
            e.to_string(),
            "command `ESX`: symbol 'X' at slot 2 is not one of ES"
        );
        assert!(matches!(
            s.parse("ES"),
            Err(CommandError::WrongLength { found: 2, .. })
        ));
    }

    #[test]
    fn malformed_spaces_are_refused() {
        assert!(CommandSpace::new(vec![]).is_err());
        assert!(CommandSpace::new(vec![vec![]]).is_err());
        assert!(CommandSpace::new(vec![vec!['a', 'a']]).is_err());
        assert_eq!(
            CommandSpace::repeat(64, &['a', 'b', 'c'])
                .unwrap()
                .num_commands(),
            None
        );
    }
}
