//! Commands: `n` slots, one symbol per slot.
//!
//! A [`CommandSpace`] says how many slots a command has and which symbols
//! each slot accepts (its *alphabet*). A [`Command`] is one symbol index per
//! slot. Commands print as their symbols, one character per slot
//! (`"ESSEENE"` on the grid, `"+0-0+00"` on the arm).

use serde::{Deserialize, Serialize};
use std::fmt;

/// The largest number of symbols in one slot's alphabet.
pub const MAX_ALPHABET: usize = 64;
/// The largest number of slots in a command.
pub const MAX_SLOTS: usize = 64;

/// The longest command echoed whole in a message, in characters.
pub const ECHO_CHARS: usize = 80;

/// A command as echoed in messages: whole up to [`ECHO_CHARS`]
/// characters, else its start and `…` with its length (a 50 MB line was
/// printed whole).
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
}

/// The command space: `n` slots, each with its alphabet of symbols.
///
/// ```
/// use e3d::CommandSpace;
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
        if alphabets.is_empty() {
            return Err(CommandError::Space(
                "a command needs at least one slot".into(),
            ));
        }
        if alphabets.len() > MAX_SLOTS {
            return Err(CommandError::Space(format!(
                "{} slots: at most {MAX_SLOTS} are supported",
                alphabets.len()
            )));
        }
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

    /// The largest alphabet size over all slots.
    pub fn max_alphabet(&self) -> usize {
        self.sizes().max().unwrap_or(0)
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

impl fmt::Display for Command {
    /// Writes the symbol indices, e.g. `[0, 1, 1, 0]`; use
    /// [`CommandSpace::format`] for the symbols themselves.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.symbols)
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
