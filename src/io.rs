//! Output files written whole or not at all.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Temporary files made by this process so far (part of their names).
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Creates a new temporary file next to `path`, named
/// `.NAME.tmp-PID-N-T`: created exclusively (`O_EXCL`, which also refuses
/// to follow a symbolic link planted under that name), retried under a new
/// name if one exists.
fn create_temp(dir: &Path, name: &str) -> io::Result<(PathBuf, File)> {
    let mut last = None;
    for _ in 0..100 {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let t = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let tmp = dir.join(format!(".{name}.tmp-{}-{n}-{t:x}", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| io::Error::other("no free temporary name")))
}

/// Creates a new temporary file beside `path` (in its folder, named
/// `.NAME.tmp-PID-N-T` after its file name): created exclusively, so that
/// it is never an existing file nor the target of a symbolic link planted
/// under that name. The caller writes it, then renames it over `path` or
/// removes it.
pub fn create_temp_beside(path: &Path) -> io::Result<(PathBuf, File)> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file path"))?;
    create_temp(dir, &name.to_string_lossy())
}

/// Whether `name` is the name of a temporary file of [`write_atomic`]
/// (`.NAME.tmp-...`), left behind by a process killed while writing.
pub fn is_temporary(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp-")
}

/// Writes `path` atomically: the bytes go to a new temporary file in the
/// same folder (created exclusively, under a unique name: never an
/// existing file nor the target of a symbolic link), which is synced and
/// then renamed over `path`. A crash or a full disk leaves either the old
/// file or the new one, never half of one. If `path` is a symbolic link,
/// the link itself is replaced, not the file it points to.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let (tmp, mut f) = create_temp_beside(path)?;
    let result = (|| {
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Opens an existing file for appending without following a symbolic link
/// (`O_NOFOLLOW` on unix): a link in its place is an error, so that a
/// planted link cannot make e3d append to, or truncate, another file.
pub fn open_append_nofollow(path: &Path) -> io::Result<File> {
    let mut o = OpenOptions::new();
    o.append(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(libc::O_NOFOLLOW);
    }
    o.open(path).map_err(|e| {
        if fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
            io::Error::new(
                io::ErrorKind::InvalidInput,
                "is a symbolic link; refused (e3d appends only to a file it made)",
            )
        } else {
            e
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn temporary_files_never_follow_a_planted_link() {
        let dir = std::env::temp_dir().join(format!("e3d-io-test-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let victim = dir.join("victim.txt");
        fs::write(&victim, "keep me").unwrap();
        // the old, predictable temporary names of the next files, planted
        let pid = std::process::id();
        for n in 0..8 {
            let _ = std::os::unix::fs::symlink(&victim, dir.join(format!(".out.txt.tmp-{pid}")));
            let _ =
                std::os::unix::fs::symlink(&victim, dir.join(format!(".out.txt.tmp-{pid}-{n}")));
        }
        write_atomic(&dir.join("out.txt"), b"new").unwrap();
        assert_eq!(fs::read_to_string(&victim).unwrap(), "keep me");
        assert_eq!(fs::read_to_string(dir.join("out.txt")).unwrap(), "new");
        // a link as the file to append to is refused
        let link = dir.join("journal.txt");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let e = open_append_nofollow(&link).unwrap_err().to_string();
        assert!(e.contains("symbolic link"), "{e}");
        assert_eq!(fs::read_to_string(&victim).unwrap(), "keep me");
        fs::remove_dir_all(&dir).unwrap();
    }
}

/// The name of the lock file of an output folder.
pub const LOCK_FILE: &str = ".lock";

/// An exclusive lock on an output folder: `DIR/.lock`, held with
/// `flock` (unix) and holding `pid=P host=H` for messages. The kernel
/// releases it when its process ends, however it ends; the file is removed
/// when the lock is dropped.
#[derive(Debug)]
pub struct DirLock {
    path: PathBuf,
    #[allow(dead_code)]
    file: File,
    /// The holder that left the file behind (killed before it could remove
    /// it), whose lock was taken over.
    pub previous: Option<String>,
}

/// `pid=P host=H`, this process.
fn holder() -> String {
    let mut host = String::from("?");
    #[cfg(unix)]
    {
        let mut buf = [0u8; 256];
        // SAFETY: the buffer is writable for its length
        if unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) } == 0 {
            let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
            host = String::from_utf8_lossy(&buf[..end]).into_owned();
        }
    }
    format!("pid={} host={host}", std::process::id())
}

impl DirLock {
    /// Takes the lock of folder `dir` (which must exist), or says who holds
    /// it: `Err` of kind `WouldBlock` whose message is the holder.
    pub fn acquire(dir: &Path) -> io::Result<DirLock> {
        let path = dir.join(LOCK_FILE);
        loop {
            let mut o = OpenOptions::new();
            o.read(true).write(true).create(true).truncate(false);
            #[cfg(unix)]
            {
                use std::os::unix::fs::OpenOptionsExt;
                o.custom_flags(libc::O_NOFOLLOW);
            }
            let mut file = o.open(&path)?;
            #[cfg(unix)]
            {
                use std::os::unix::fs::MetadataExt;
                use std::os::unix::io::AsRawFd;
                // SAFETY: flock on a descriptor we own
                if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } != 0 {
                    let e = io::Error::last_os_error();
                    if e.kind() != io::ErrorKind::WouldBlock {
                        return Err(e);
                    }
                    let mut who = String::new();
                    let _ = io::Read::read_to_string(&mut file, &mut who);
                    let who = who.trim();
                    return Err(io::Error::new(
                        io::ErrorKind::WouldBlock,
                        if who.is_empty() {
                            "another e3d".to_string()
                        } else {
                            format!("e3d {who}")
                        },
                    ));
                }
                // the holder before us may have removed the file meanwhile:
                // then our lock is on a file nobody else will open
                let same = fs::symlink_metadata(&path)
                    .is_ok_and(|m| m.ino() == file.metadata().map_or(0, |f| f.ino()));
                if !same {
                    continue;
                }
            }
            let mut old = String::new();
            let _ = io::Read::read_to_string(&mut file, &mut old);
            file.set_len(0)?;
            io::Seek::seek(&mut file, io::SeekFrom::Start(0))?;
            file.write_all(format!("{}\n", holder()).as_bytes())?;
            let old = old.trim().to_string();
            return Ok(DirLock {
                path,
                file,
                previous: (!old.is_empty()).then_some(old),
            });
        }
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        // removed while still held: a process that opened it meanwhile
        // sees the change of file and opens it again
        let _ = fs::remove_file(&self.path);
    }
}
