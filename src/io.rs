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
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file path"))?;
    let (tmp, mut f) = create_temp(dir, &name.to_string_lossy())?;
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
