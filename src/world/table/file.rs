//! An outcome table's file: its format, the folder of tables keyed by the
//! scene's content, and partial files (a memo's outcomes).

use super::*;

/// The first bytes of an outcome-table file (version 2: whole or partial,
/// checksummed).
const MAGIC: &[u8; 8] = b"E3DTAB02";

/// The first bytes of the files of earlier versions (read as "old format").
const OLD_MAGIC: &[u8; 7] = b"E3DTAB0";

/// The bytes of one outcome in a table file: effect (u32), reward, x, y (f64).
const RECORD: usize = 28;

/// The header: magic, key, commands of the space, entries in the file.
const HEADER: usize = 32;

/// Refuses a table file's path that exists and is not a regular file (a
/// FIFO, a device, a socket, a folder; also through a symbolic link): a
/// table cache is a file e3d replaces, never a stream it writes through
/// (opening a FIFO to write blocked until a reader came, for ever).
pub(crate) fn refuse_non_regular(path: &Path) -> io::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{}: this is not a regular file (a folder, a pipe, a device or a socket); a table cache file must be one",
                path.display()
            ),
        )),
        _ => Ok(()),
    }
}

/// What a table file of a scene holds (see [`OutcomeTable::read_file`]).
#[derive(Debug, Clone)]
// a file is read once per run: the size of the whole table's variant costs
// nothing worth a box
#[allow(clippy::large_enum_variant)]
pub enum CachedOutcomes {
    /// Every command's outcome: a whole table.
    Full(OutcomeTable),
    /// Some commands' outcomes, in index order (an outcome memo saved by a
    /// run that did not enumerate the space).
    Partial(Vec<(u64, Outcome)>),
}

impl OutcomeTable {
    /// The key of a scene's table: a hash of the scene's content (its
    /// canonical RON form, so comments and layout do not matter) and of
    /// [`VERSION`](crate::world::VERSION), the crate's version with
    /// the fingerprint of the physics code it was built with, which
    /// changes whenever a simulation might.
    pub fn key(scene: &Scene) -> u64 {
        let canonical = ron::to_string(scene).unwrap_or_default();
        crate::hash::fnv1a64(format!("e3d {} {canonical}", crate::world::VERSION).as_bytes())
    }

    /// The file of a scene's table in the folder `dir`:
    /// `NAME-KEY.e3dtable`.
    pub fn cache_path(scene: &Scene, dir: &Path) -> PathBuf {
        dir.join(format!(
            "{}-{:016x}.e3dtable",
            file_safe(&scene.spec().name),
            Self::key(scene)
        ))
    }

    /// The table of `scene`: read from `dir` if a whole table with the
    /// scene's key is there, otherwise computed in parallel and written
    /// there (whole or not at all). The result is identical either way.
    pub fn cached(scene: &Scene, dir: &Path) -> Result<OutcomeTable, WorldError> {
        let path = Self::cache_path(scene, dir);
        crate::io::remove_stale_temps(dir);
        if let Ok(CachedOutcomes::Full(t)) = Self::read_file(&path, scene) {
            return Ok(t);
        }
        let table = Self::build_scene(scene)?;
        // a cache that cannot be written is not an error: it costs time only
        let _ = table.write_file(&path, scene);
        Ok(table)
    }

    /// Writes the table as the table file of `scene` at `path` (whole or
    /// not at all), creating its folder.
    pub fn write_file(&self, path: &Path, scene: &Scene) -> io::Result<()> {
        self.write_file_keyed(path, Self::key(scene))
    }

    /// [`write_file`](Self::write_file) with the key `key` in its header.
    pub(super) fn write_file_keyed(&self, path: &Path, key: u64) -> io::Result<()> {
        write_table(path, &self.to_bytes(key))
    }

    /// Writes `entries` (command index and outcome, in increasing index
    /// order) as a partial table file of `scene` at `path`, whole or not
    /// at all, creating its folder. Entries covering every command make a
    /// whole table.
    pub fn write_partial(path: &Path, scene: &Scene, entries: &[(u64, Outcome)]) -> io::Result<()> {
        let n = scene.command_space().num_commands().ok_or_else(|| {
            io::Error::new(io::ErrorKind::InvalidInput, "more than 2^64 commands")
        })?;
        let entries = entries.iter().map(|(i, o)| (*i, o));
        write_table(path, &encode(Self::key(scene), n, entries))
    }

    /// The table as the bytes of a whole table file: magic `E3DTAB02`,
    /// key, commands, entries (u64 each), then per command in index order
    /// its effect (u32), reward, x and y (f64), then the FNV-1a checksum
    /// (u64) of every byte before it; all little-endian. A partial file
    /// ([`write_partial`](Self::write_partial)) has fewer entries, each
    /// preceded by its command index (u64).
    pub fn to_bytes(&self, key: u64) -> Vec<u8> {
        let entries = self.outcomes.iter().enumerate();
        encode(key, self.len() as u64, entries.map(|(i, o)| (i as u64, o)))
    }

    /// Reads the whole table written for `scene` at `path`; refuses a
    /// partial table, a file of another scene or version, and a damaged
    /// one.
    pub fn load(path: &Path, scene: &Scene) -> io::Result<OutcomeTable> {
        match Self::read_file(path, scene)? {
            CachedOutcomes::Full(t) => Ok(t),
            CachedOutcomes::Partial(e) => Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "{}: a partial table ({} commands of {})",
                    path.display(),
                    e.len(),
                    scene.command_space().num_commands().unwrap_or(u64::MAX)
                ),
            )),
        }
    }

    /// Reads a table file (whole or partial) written for `scene`. The error
    /// says why a file cannot be used: missing, of an older format, of
    /// another scene or e3d version, damaged (its checksum), truncated.
    ///
    /// The file must be a regular file (a FIFO or a link to `/dev/zero` is
    /// refused, never read) no larger than the scene's whole table with
    /// indices; every outcome must agree with the scene: its effect inside
    /// the grid, its reward the scene's reward for that effect (bit for
    /// bit), its point finite. A file resealed after an edit (the checksum
    /// is easy to recompute) is refused as not matching the scene.
    pub fn read_file(path: &Path, scene: &Scene) -> io::Result<CachedOutcomes> {
        Self::read_file_keyed(path, scene, Self::key(scene))
    }

    /// [`read_file`](Self::read_file) of a file whose header holds `key`.
    pub(super) fn read_file_keyed(
        path: &Path,
        scene: &Scene,
        key: u64,
    ) -> io::Result<CachedOutcomes> {
        let most = scene
            .command_space()
            .num_commands()
            .unwrap_or(u64::MAX)
            .min(MAX_TABLE_COMMANDS)
            .saturating_mul((RECORD + 8) as u64)
            .saturating_add((HEADER + 8) as u64);
        let bytes =
            crate::text::read_own_bytes(path, most, "e3d table file").map_err(|e| match e {
                crate::text::ReadError::Io { error, .. } => error,
                other => io::Error::new(io::ErrorKind::InvalidData, other.to_string()),
            })?;
        let r = TableBytes {
            bytes: &bytes,
            path,
            rewards: scene.reward_table(),
            num_effects: scene.num_effects(),
        };
        let space = scene.command_space();
        let n = space
            .num_commands()
            .ok_or_else(|| r.bad("command space too large"))?;
        let entries = r.check_header(key, n)?;
        if entries == n {
            let outcomes = (0..n as usize)
                .map(|k| r.record(HEADER + k * RECORD))
                .collect::<io::Result<Vec<_>>>()?;
            return Ok(CachedOutcomes::Full(OutcomeTable::new(
                space,
                r.num_effects,
                outcomes,
            )));
        }
        let mut out = Vec::with_capacity(entries as usize);
        for k in 0..entries as usize {
            let at = HEADER + k * (RECORD + 8);
            let i = r.u64_at(at);
            if i >= n || out.last().is_some_and(|&(p, _)| p >= i) {
                return Err(r.bad("command indices out of order"));
            }
            out.push((i, r.record(at + 8)?));
        }
        Ok(CachedOutcomes::Partial(out))
    }
}

/// The bytes of a table file of `commands` commands holding `entries`
/// (command index and outcome, in index order): the header, each record
/// (preceded by its index unless the file is whole), the checksum of
/// everything before it.
fn encode<'a>(
    key: u64,
    commands: u64,
    entries: impl ExactSizeIterator<Item = (u64, &'a Outcome)>,
) -> Vec<u8> {
    let len = entries.len();
    let full = len as u64 == commands;
    let mut b = Vec::with_capacity(HEADER + len * (RECORD + if full { 0 } else { 8 }) + 8);
    b.extend_from_slice(MAGIC);
    for v in [key, commands, len as u64] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for (i, o) in entries {
        if !full {
            b.extend_from_slice(&i.to_le_bytes());
        }
        b.extend_from_slice(&(o.effect as u32).to_le_bytes());
        for v in [o.reward, o.point[0], o.point[1]] {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    let sum = crate::hash::fnv1a64(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// Writes the bytes of a table file at `path` (whole or not at all),
/// creating its folder.
fn write_table(path: &Path, bytes: &[u8]) -> io::Result<()> {
    refuse_non_regular(path)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    crate::io::write_atomic(path, bytes)
}

/// `name` with every character but ASCII letters, digits, `_` and `-`
/// made `_` (a file name's part).
pub(super) fn file_safe(name: &str) -> String {
    name.replace(
        |c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'),
        "_",
    )
}

/// The bytes of a table file being read, and what its outcomes must agree
/// with (see [`OutcomeTable::read_file`]).
struct TableBytes<'a> {
    bytes: &'a [u8],
    path: &'a Path,
    rewards: Vec<f64>,
    num_effects: usize,
}

impl TableBytes<'_> {
    /// Why the file cannot be used, naming it.
    fn bad(&self, m: &str) -> io::Error {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{}: {m}", self.path.display()),
        )
    }

    fn u64_at(&self, i: usize) -> u64 {
        u64::from_le_bytes(self.bytes[i..i + 8].try_into().expect("8 bytes"))
    }

    /// Checks the magic, the key, the number of commands `n`, the length
    /// and the checksum; returns the number of entries (`n`: a whole
    /// table).
    fn check_header(&self, key: u64, n: u64) -> io::Result<u64> {
        let bytes = self.bytes;
        if bytes.len() < HEADER + 8 || &bytes[..8] != MAGIC {
            return Err(self.bad(if bytes.starts_with(OLD_MAGIC) {
                "a table of an older e3d format"
            } else {
                "not an e3d table file"
            }));
        }
        if self.u64_at(8) != key || self.u64_at(16) != n {
            return Err(self.bad("the table belongs to another scene or e3d version"));
        }
        let entries = self.u64_at(24);
        let each = RECORD + if entries == n { 0 } else { 8 };
        if entries > n || (bytes.len() - HEADER - 8) as u64 != entries.saturating_mul(each as u64) {
            return Err(self.bad("truncated or of the wrong length"));
        }
        let body = bytes.len() - 8;
        if self.u64_at(body) != crate::hash::fnv1a64(&bytes[..body]) {
            return Err(self.bad("damaged (its checksum does not match)"));
        }
        Ok(entries)
    }

    /// The outcome recorded at `at`, checked against the scene.
    fn record(&self, at: usize) -> io::Result<Outcome> {
        let bytes = self.bytes;
        let effect = u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as usize;
        if effect >= self.num_effects {
            return Err(self.bad("an effect out of range"));
        }
        let f = |i: usize| f64::from_le_bytes(bytes[i..i + 8].try_into().expect("8 bytes"));
        let (reward, point) = (f(at + 4), [f(at + 12), f(at + 20)]);
        if reward.to_bits() != self.rewards[effect].to_bits() {
            return Err(self.bad(&format!(
                "a reward that is not the scene's: {reward} for effect {effect}, where the scene gives {}",
                self.rewards[effect]
            )));
        }
        if !point.iter().all(|v| v.is_finite()) {
            return Err(self.bad("a terminal point that is not finite"));
        }
        Ok(Outcome {
            effect,
            reward,
            point,
        })
    }
}
