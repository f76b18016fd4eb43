//! The journal of a sweep: every finished session, one checksummed line
//! each, appended as sessions finish.
//!
//! ```text
//! # e3d sweep journal v1
//! # sweep=9b1f0c2a7d3e4f55 shard=1/1 total=600 per_cell=10 scenes=3c5e2a917b0d4f68@two_rooms version=0.1.0
//! # columns=scene,learner,use_reward,alpha,...
//! 5d8f2e0b9a7c6d41 17,two_rooms,e3d,false,0.3,1,0.03,0.01,,7,123456789,0.93,...
//! ```
//!
//! A data line is `CHECKSUM INDEX,ROW\n`: the 16 hex digits of
//! [`fnv1a64`] of `INDEX,ROW`, a space, the session's
//! canonical index and its `results.csv` row. Each line goes to the file in
//! one `write` as soon as its session ends (so it survives the process
//! being killed), and the file is synced to disk at least every half
//! second and at the end. On reading, the lines after the first one that
//! is torn (no line break) or fails its checksum are ignored, and
//! appending starts there again.

use super::{io_err, Shard, SweepError};
use crate::hash::fnv1a64;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const MAGIC: &str = "# e3d sweep journal v1";

/// The largest journal read (4 GiB): a line per session, a few hundred
/// bytes each, and a sweep holds at most
/// [`MAX_SESSIONS`](super::MAX_SESSIONS) sessions.
pub const MAX_JOURNAL_BYTES: u64 = 4 << 30;

/// The first lines of a journal: which sweep and which shard it belongs to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JournalHeader {
    /// FNV-1a of the sweep file's bytes.
    pub sweep_hash: u64,
    /// The shard this journal records.
    pub shard: Shard,
    /// The number of sessions of the whole sweep.
    pub total: usize,
    /// Sessions per cell.
    pub per_cell: usize,
    /// Each scene of the sweep, in its order: its name and
    /// [`OutcomeTable::key`](crate::OutcomeTable::key), a hash of its
    /// canonical content and the e3d version. A scene edited between
    /// shards, or before `--resume`, changes its key.
    pub scenes: Vec<(String, u64)>,
    /// The e3d version that wrote it.
    pub version: String,
    /// The header line of `results.csv`.
    pub columns: String,
}

impl JournalHeader {
    /// A short description, for messages.
    pub fn describe(&self) -> String {
        format!(
            "shard {} of sweep {:016x} with {} sessions, e3d {}",
            self.shard, self.sweep_hash, self.total, self.version
        )
    }

    fn text(&self) -> String {
        let scenes: Vec<String> = self
            .scenes
            .iter()
            .map(|(name, key)| format!("{key:016x}@{}", encode(name)))
            .collect();
        format!(
            "{MAGIC}\n# sweep={:016x} shard={} total={} per_cell={} scenes={} version={}\n# columns={}\n",
            self.sweep_hash,
            self.shard,
            self.total,
            self.per_cell,
            scenes.join(","),
            self.version,
            self.columns
        )
    }

    /// The first scene whose content differs between `self` and `other`
    /// (same sweep file): `(name, key here, key there)`.
    pub fn changed_scene(&self, other: &JournalHeader) -> Option<(String, u64, u64)> {
        if self.scenes.len() != other.scenes.len() {
            return None;
        }
        self.scenes
            .iter()
            .zip(&other.scenes)
            .find(|(a, b)| a.1 != b.1)
            .map(|(a, b)| (a.0.clone(), a.1, b.1))
    }
}

/// A scene name in the header line: whitespace, `%`, `,`, `=` and `@`
/// percent-encoded.
fn encode(name: &str) -> String {
    let encode = |c: char| match c.is_whitespace() || "%,=@".contains(c) {
        true => c.to_string().bytes().map(|b| format!("%{b:02X}")).collect(),
        false => c.to_string(),
    };
    name.chars().map(encode).collect()
}

fn decode(text: &str) -> Option<String> {
    let mut parts = text.split('%');
    let mut out = parts.next()?.as_bytes().to_vec();
    for part in parts {
        out.push(u8::from_str_radix(part.get(..2)?, 16).ok()?);
        out.extend_from_slice(&part.as_bytes()[2..]);
    }
    String::from_utf8(out).ok()
}

fn parse_scenes(v: &str) -> Option<Vec<(String, u64)>> {
    if v.is_empty() {
        return Some(Vec::new());
    }
    v.split(',')
        .map(|item| {
            let (key, name) = item.split_once('@')?;
            Some((decode(name)?, u64::from_str_radix(key, 16).ok()?))
        })
        .collect()
}

/// A journal read back.
#[derive(Debug, Clone)]
pub struct JournalRead {
    /// Its header.
    pub header: JournalHeader,
    /// The rows of the finished sessions, by canonical index.
    pub rows: BTreeMap<usize, String>,
    /// The length in bytes of the valid part (header and whole, correct
    /// lines); anything after it is ignored.
    pub valid_len: u64,
}

fn corrupt(path: &Path, what: &str) -> SweepError {
    SweepError::Output(format!(
        "{}: not an e3d sweep journal ({what}); choose another --out",
        path.display()
    ))
}

/// The longest journal line read: 64 MiB. A session's line holds a
/// checksum, numbers and names of at most 200 characters, and the header's
/// scene list is bounded by the sweep file (16 MiB, names encoded at most
/// threefold). A longer data line is not one e3d wrote: it ends the valid
/// part, as a line that fails its checksum does (a tail of zeros left by
/// a crash is one), without being read further.
pub const MAX_LINE_BYTES: usize = 64 << 20;

/// Reads the next line of a journal into `buf`, its line feed kept (a
/// line without one is torn), holding at most [`MAX_LINE_BYTES`] + 1
/// bytes: the bytes read, or `None` at the end. A line longer than the cap
/// comes back cut, without its line feed, as a torn line does.
fn next_line(
    input: &mut impl BufRead,
    buf: &mut Vec<u8>,
    path: &Path,
) -> Result<Option<usize>, SweepError> {
    buf.clear();
    let got = (&mut *input)
        .take(MAX_LINE_BYTES as u64 + 1)
        .read_until(b'\n', buf)
        .map_err(io_err(path))?;
    Ok((got > 0).then_some(got))
}

/// Reads a journal, keeping the whole, correct lines before the first bad
/// one. The file is streamed, a line at a time: memory holds one line and
/// the rows kept, and the work is linear in the file's length.
pub fn read(path: &Path) -> Result<JournalRead, SweepError> {
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(SweepError::Output(format!(
            "{}: is a symbolic link; refused (e3d reads and appends only to a journal it made); choose another --out",
            path.display()
        )));
    }
    let own_err =
        |e: crate::text::ReadError| SweepError::Output(format!("{e}; choose another --out"));
    let (file, _) =
        crate::text::open_own(path, MAX_JOURNAL_BYTES, "sweep journal").map_err(own_err)?;
    let mut input = BufReader::new(file.take(MAX_JOURNAL_BYTES + 1));
    let mut buf = Vec::new();
    let (header, header_len) = read_header(&mut input, &mut buf, path)?;
    let mut valid_len = header_len;
    let mut rows = BTreeMap::new();
    let check = RowCheck::new(&header);
    let mut n = 3;
    let mut total = header_len;
    loop {
        n += 1;
        let Some(got) = next_line(&mut input, &mut buf, path)? else {
            break;
        };
        total += got as u64;
        let Some((index, row)) = parse_line(&buf) else {
            break;
        };
        check.row(path, n, index, &row)?;
        if let Some(old) = rows.get(&index) {
            if *old != row {
                return Err(corrupt(
                    path,
                    &format!("session {index} appears twice with different results"),
                ));
            }
        }
        rows.insert(index, row);
        valid_len += got as u64;
    }
    // the file's length was checked when it was opened; one that grew past
    // the cap while it was read is refused (what follows a bad line is not
    // read)
    if total > MAX_JOURNAL_BYTES {
        let e = crate::text::too_large(path, MAX_JOURNAL_BYTES, "sweep journal");
        return Err(own_err(e));
    }
    Ok(JournalRead {
        header,
        rows,
        valid_len,
    })
}

/// The three header lines of a journal and their length in bytes.
fn read_header(
    input: &mut impl BufRead,
    buf: &mut Vec<u8>,
    path: &Path,
) -> Result<(JournalHeader, u64), SweepError> {
    let mut len = 0u64;
    let mut header_line = |n: usize| -> Result<String, SweepError> {
        match next_line(input, buf, path)? {
            Some(got) if buf.ends_with(b"\n") => {
                len += got as u64;
                String::from_utf8(buf[..got - 1].to_vec())
                    .map_err(|_| corrupt(path, &format!("line {n} is not UTF-8")))
            }
            _ => Err(corrupt(path, "its header is incomplete")),
        }
    };
    let magic = header_line(1)?;
    if magic != MAGIC {
        return Err(corrupt(path, "line 1 is not the journal's title"));
    }
    let meta = header_line(2)?;
    let columns = header_line(3)?;
    let columns = columns
        .strip_prefix("# columns=")
        .ok_or_else(|| corrupt(path, "line 3 lacks `# columns=`"))?
        .to_string();
    let mut fields: BTreeMap<&str, &str> = BTreeMap::new();
    for kv in meta.trim_start_matches('#').split_whitespace() {
        if let Some((k, v)) = kv.split_once('=') {
            fields.insert(k, v);
        }
    }
    let get = |k: &str| {
        fields
            .get(k)
            .copied()
            .ok_or_else(|| corrupt(path, &format!("line 2 lacks `{k}=`")))
    };
    let bad_num = |k: &str| corrupt(path, &format!("line 2: `{k}` is not a number"));
    let header = JournalHeader {
        sweep_hash: u64::from_str_radix(get("sweep")?, 16).map_err(|_| bad_num("sweep"))?,
        shard: get("shard")?.parse().map_err(|_| bad_num("shard"))?,
        total: get("total")?.parse().map_err(|_| bad_num("total"))?,
        per_cell: get("per_cell")?.parse().map_err(|_| bad_num("per_cell"))?,
        // journals written before scenes were part of the identity have
        // none: they match no run, and are refused as another run's
        scenes: match fields.get("scenes") {
            None => Vec::new(),
            Some(v) => parse_scenes(v)
                .ok_or_else(|| corrupt(path, "line 2: `scenes` is not a list of KEY@NAME"))?,
        },
        version: get("version")?.to_string(),
        columns,
    };
    Ok((header, len))
}

/// What a session's row must hold: as many fields as the header's
/// columns, its metrics finite numbers or empty.
struct RowCheck<'h> {
    names: Vec<&'h str>,
    metrics: std::ops::Range<usize>,
}

impl<'h> RowCheck<'h> {
    fn new(header: &'h JournalHeader) -> Self {
        let names: Vec<&str> = header.columns.split(',').collect();
        let keys = super::summary::cell_columns(&names).map_or(super::KEY_COLUMNS.len(), |n| n + 2);
        let metrics = keys..names.len().saturating_sub(1);
        RowCheck { names, metrics }
    }

    /// Checks the row of line `n`. A line that passes its checksum was
    /// written whole; its values must still be what e3d writes (a resealed
    /// line with `inf` would end as an infinite summary).
    fn row(&self, path: &Path, n: usize, index: usize, row: &str) -> Result<(), SweepError> {
        let width = self.names.len();
        let fields = row.split(',').count();
        if fields != width {
            return Err(corrupt(
                path,
                &format!("line {n}: {fields} fields, expected {width} (`# columns=`)"),
            ));
        }
        // the column of the row's first field in the line: checksum,
        // space, index, comma
        let mut col = 16 + 1 + index.to_string().len() + 1 + 1;
        for (j, v) in row.split(',').enumerate() {
            if self.metrics.contains(&j) && !v.is_empty() {
                crate::text::parse_finite(v, &path.display().to_string(), n, col, self.names[j])
                    .map_err(|e| {
                        SweepError::Output(format!(
                            "{e}; the journal was edited: choose another --out"
                        ))
                    })?;
            }
            col += v.chars().count() + 1;
        }
        Ok(())
    }
}

/// `CHECKSUM INDEX,ROW\n` -> `(INDEX, ROW)`, or `None` if torn or wrong.
fn parse_line(line: &[u8]) -> Option<(usize, String)> {
    let body = line.strip_suffix(b"\n")?;
    let text = std::str::from_utf8(body).ok()?;
    let (sum, payload) = text.split_once(' ')?;
    if sum.len() != 16 || u64::from_str_radix(sum, 16).ok()? != fnv1a64(payload.as_bytes()) {
        return None;
    }
    let (index, row) = payload.split_once(',')?;
    Some((index.parse().ok()?, row.to_string()))
}

fn line(index: usize, row: &str) -> String {
    let payload = format!("{index},{row}");
    format!("{:016x} {payload}\n", fnv1a64(payload.as_bytes()))
}

/// A journal open for appending.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: File,
    last_sync: Instant,
}

/// How often appended lines are synced to disk.
const SYNC_EVERY: Duration = Duration::from_millis(500);

impl Journal {
    /// Creates a journal with `header` and no session (atomically), then
    /// opens it for appending.
    pub fn create(path: &Path, header: &JournalHeader) -> Result<Journal, SweepError> {
        crate::io::write_atomic(path, header.text().as_bytes()).map_err(io_err(path))?;
        Journal::append(path, header.text().len() as u64)
    }

    /// Opens a journal for appending after its first `valid_len` bytes
    /// (dropping a torn or corrupt tail).
    pub fn append(path: &Path, valid_len: u64) -> Result<Journal, SweepError> {
        // O_APPEND: every line lands at the end of the file, whole;
        // O_NOFOLLOW: a symbolic link in its place is refused, not
        // truncated and appended to
        let file = crate::io::open_append_nofollow(path).map_err(io_err(path))?;
        file.set_len(valid_len).map_err(io_err(path))?;
        file.sync_all().map_err(io_err(path))?;
        Ok(Journal {
            path: path.to_path_buf(),
            file,
            last_sync: Instant::now(),
        })
    }

    /// Appends the row of session `index` (one `write`), syncing to disk
    /// when the last sync is older than half a second.
    pub fn push(&mut self, index: usize, row: &str) -> Result<(), SweepError> {
        self.file
            .write_all(line(index, row).as_bytes())
            .map_err(io_err(&self.path))?;
        if self.last_sync.elapsed() >= SYNC_EVERY {
            self.sync()?;
        }
        Ok(())
    }

    /// Syncs the journal to disk.
    pub fn sync(&mut self) -> Result<(), SweepError> {
        self.file.sync_data().map_err(io_err(&self.path))?;
        self.last_sync = Instant::now();
        Ok(())
    }
}

/// Writes a whole journal (header and `rows` in index order) atomically.
pub fn write_whole(
    path: &Path,
    header: &JournalHeader,
    rows: &BTreeMap<usize, String>,
) -> Result<(), SweepError> {
    let mut text = header.text();
    for (i, r) in rows {
        text.push_str(&line(*i, r));
    }
    crate::io::write_atomic(path, text.as_bytes()).map_err(io_err(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> JournalHeader {
        JournalHeader {
            sweep_hash: 0xabc,
            shard: Shard { k: 2, n: 3 },
            total: 10,
            per_cell: 2,
            scenes: vec![("two rooms, 100%".into(), 0xfe), ("b".into(), 1)],
            version: "0.1.0".into(),
            columns: "scene,learner,x".into(),
        }
    }

    #[test]
    fn torn_and_corrupt_tails_are_dropped_then_overwritten() {
        let dir = std::env::temp_dir().join(format!("e3d-journal-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("journal.txt");
        let mut j = Journal::create(&p, &header()).unwrap();
        j.push(1, "a,b,1").unwrap();
        j.push(4, "a,b,2").unwrap();
        drop(j);
        let good_len = std::fs::metadata(&p).unwrap().len();
        // a torn line: no line break
        let mut f = std::fs::OpenOptions::new().append(true).open(&p).unwrap();
        f.write_all(b"0123456789abcdef 7,a,b").unwrap();
        drop(f);
        let r = read(&p).unwrap();
        assert_eq!(r.header, header());
        assert_eq!(r.rows.len(), 2);
        assert_eq!(r.rows[&4], "a,b,2");
        assert_eq!(r.valid_len, good_len);
        // appending starts at the valid end
        let mut j = Journal::append(&p, r.valid_len).unwrap();
        j.push(7, "a,b,3").unwrap();
        drop(j);
        let r = read(&p).unwrap();
        assert_eq!(r.rows.keys().copied().collect::<Vec<_>>(), vec![1, 4, 7]);
        // a flipped byte fails the checksum: that line and the rest go
        let mut bytes = std::fs::read(&p).unwrap();
        let at = bytes.len() - 3;
        bytes[at] = b'9';
        std::fs::write(&p, &bytes).unwrap();
        let r = read(&p).unwrap();
        assert_eq!(r.rows.keys().copied().collect::<Vec<_>>(), vec![1, 4]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
