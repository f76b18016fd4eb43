//! Output files written whole or not at all.

#[cfg(unix)]
use libc::{O_NOFOLLOW, O_NONBLOCK};
use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
#[cfg(not(unix))]
const O_NOFOLLOW: i32 = 0;
#[cfg(not(unix))]
const O_NONBLOCK: i32 = 0;

/// Temporary files made by this process so far (part of their names).
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// [`create_temp_beside`] in `dir`, retried under a new name if one exists.
fn create_temp(dir: &Path, name: &str) -> io::Result<(PathBuf, File)> {
    let mut last = None;
    for _ in 0..100 {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let t = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let tmp = dir.join(format!(".{name}.tmp-{}-{n}-{t:x}", std::process::id()));
        // created and registered under the lock, which a fatal signal's
        // cleanup holds until the process ends: no file escapes it
        let mut temps = TEMPS.lock().unwrap_or_else(|e| e.into_inner());
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => {
                temps.push(absolute(&tmp));
                return Ok((tmp, f));
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| io::Error::other("no free temporary name")))
}

/// Creates a new temporary file `.NAME.tmp-PID-N-T` beside `path`,
/// exclusively (never an existing file nor a link planted under that
/// name); the caller writes it, then renames it over `path` or removes it.
pub fn create_temp_beside(path: &Path) -> io::Result<(PathBuf, File)> {
    let (dir, name) = folder_and_name(path)?;
    create_temp(dir, &name)
}

/// The folder `path` sits in (`.` for a bare name) and its file name.
fn folder_and_name(path: &Path) -> io::Result<(&Path, String)> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file path"))?;
    Ok((dir, name.to_string_lossy().into_owned()))
}

/// Whether `path` (or what a link there leads to) is a character device or
/// a FIFO (`/dev/stdout`, a named pipe): a stream to write through, since
/// renaming a file over it would put a regular file in the device's place.
pub fn is_stream(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        fs::metadata(path).is_ok_and(|m| m.file_type().is_char_device() || m.file_type().is_fifo())
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

/// Where the output for `path` is written: a temporary file beside it
/// (`Some` of its path, [`create_temp_beside`]), or `path` itself when it
/// is a stream ([`is_stream`]; `None`).
pub fn create_output(path: &Path) -> io::Result<(Option<PathBuf>, File)> {
    if is_stream(path) {
        return Ok((None, OpenOptions::new().write(true).open(path)?));
    }
    let (tmp, f) = create_temp_beside(path)?;
    Ok((Some(tmp), f))
}

/// Whether `name` is the name of a temporary file of [`write_atomic`]
/// (`.NAME.tmp-...`), left behind by a process killed while writing.
pub fn is_temporary(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp-")
}

/// Writes `path` atomically: a temporary file ([`create_temp_beside`]),
/// synced, then renamed over `path` (a link there is replaced, not
/// followed); a crash or a full disk leaves the old file or the new one,
/// never half of one. A stream ([`is_stream`]) is written through.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let (tmp, mut f) = create_output(path)?;
    let written = f.write_all(bytes).and_then(|()| match tmp {
        Some(_) => f.sync_all(),
        None => f.flush(),
    });
    drop(f);
    finish_output(tmp, path, written, |e| e)
}

/// Ends an output of [`create_output`] once written and closed: a
/// temporary file is renamed over `path`, or removed if `written` (or the
/// renaming, made an `E` by `io_err`) failed. Returns the first error.
pub fn finish_output<E>(
    tmp: Option<PathBuf>,
    path: &Path,
    written: Result<(), E>,
    io_err: impl FnOnce(io::Error) -> E,
) -> Result<(), E> {
    let Some(tmp) = tmp else {
        return written;
    };
    let result = written.and_then(|()| fs::rename(&tmp, path).map_err(io_err));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    forget_temp(&tmp);
    result
}

/// The temporary files this process made and may not have renamed or
/// removed yet ([`remove_temps`], [`remove_temps_on_signals`]).
static TEMPS: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

fn register_temp(path: &Path) {
    TEMPS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(absolute(path));
}

/// Says that the temporary file `path` (of [`create_temp_beside`]) was
/// renamed into place or removed: [`remove_temps`] leaves it alone.
pub fn forget_temp(path: &Path) {
    let mut t = TEMPS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(i) = t.iter().rposition(|p| p.ends_with(path)) {
        t.swap_remove(i);
    }
}

/// Removes every temporary file this process made and has not renamed
/// into place nor forgotten; returns how many.
pub fn remove_temps() -> usize {
    remove_held(&mut TEMPS.lock().unwrap_or_else(|e| e.into_inner()))
}

fn remove_held(temps: &mut Vec<PathBuf>) -> usize {
    temps
        .drain(..)
        .filter(|p| fs::remove_file(p).is_ok())
        .count()
}

/// The signals on which [`remove_temps_on_signals`] removes the
/// temporary files: every one whose default action ends the process and
/// that can be caught (after SIGKILL, [`remove_stale_temps`] cleans up).
#[cfg(unix)]
pub const CLEANUP_SIGNALS: [libc::c_int; 10] = [
    libc::SIGINT,
    libc::SIGTERM,
    libc::SIGHUP,
    libc::SIGQUIT,
    libc::SIGPIPE,
    libc::SIGXFSZ,
    libc::SIGXCPU,
    libc::SIGALRM,
    libc::SIGUSR1,
    libc::SIGUSR2,
];

/// On the signals that end a process ([`CLEANUP_SIGNALS`]), removes this
/// process's temporary files ([`remove_temps`]), then dies of the signal
/// as it would have; an ignored signal (`nohup`) stays ignored. The
/// handler only writes to a pipe (what is safe there); a thread does the
/// rest. Unix only; call once, early.
pub fn remove_temps_on_signals() {
    #[cfg(unix)]
    {
        use std::sync::atomic::AtomicI32;
        static PIPE_WRITE: AtomicI32 = AtomicI32::new(-1);
        extern "C" fn on_signal(sig: libc::c_int) {
            let fd = PIPE_WRITE.load(Ordering::Relaxed);
            let b = sig as u8;
            // SAFETY: write(2) is async-signal-safe; the byte is on the stack
            unsafe {
                libc::write(fd, (&b as *const u8).cast(), 1);
            }
        }
        if PIPE_WRITE.load(Ordering::Relaxed) >= 0 {
            return;
        }
        let mut fds = [0 as libc::c_int; 2];
        // SAFETY: pipe fills the two descriptors of a valid array
        if unsafe { libc::pipe(fds.as_mut_ptr()) } != 0 {
            return;
        }
        PIPE_WRITE.store(fds[1], Ordering::Relaxed);
        let read_fd = fds[0];
        let spawned = std::thread::Builder::new()
            .name("e3d-signals".into())
            .spawn(move || loop {
                let mut b = 0u8;
                // SAFETY: reads one byte into a valid buffer
                let n = unsafe { libc::read(read_fd, (&mut b as *mut u8).cast(), 1) };
                if n == 1 {
                    // the lock is kept until the process ends of the signal
                    let mut temps = TEMPS.lock().unwrap_or_else(|e| e.into_inner());
                    remove_held(&mut temps);
                    let sig = libc::c_int::from(b);
                    // SAFETY: restores the default action and raises the
                    // signal again, so that the process ends of it
                    unsafe {
                        libc::signal(sig, libc::SIG_DFL);
                        libc::raise(sig);
                    }
                } else if n == 0 {
                    return;
                }
            });
        if spawned.is_err() {
            return;
        }
        for sig in CLEANUP_SIGNALS {
            // SAFETY: installs a handler that only calls write(2); a
            // signal found ignored is set back to ignored at once
            unsafe {
                let before = libc::signal(
                    sig,
                    on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t,
                );
                if before == libc::SIG_IGN {
                    libc::signal(sig, libc::SIG_IGN);
                }
            }
        }
    }
}

/// Removes (and returns) the temporary files in `dir` of e3d processes
/// that no longer run (by their PID, on this machine: a running one may be
/// writing there). Errors are ignored.
pub fn remove_stale_temps(dir: &Path) -> Vec<PathBuf> {
    let mut removed = Vec::new();
    let Ok(entries) = fs::read_dir(dir) else {
        return removed;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if !is_temporary(&name) {
            continue;
        }
        let pid = name
            .rsplit_once(".tmp-")
            .and_then(|(_, rest)| rest.split('-').next())
            .and_then(|p| p.parse::<u32>().ok());
        let Some(pid) = pid else { continue };
        if pid == std::process::id() || process_alive(pid) {
            continue;
        }
        // only a regular file or a link: never a folder
        if e.file_type().is_ok_and(|t| !t.is_dir()) && fs::remove_file(e.path()).is_ok() {
            removed.push(e.path());
        }
    }
    removed
}

/// Whether process `pid` runs on this machine (unix: `kill(pid, 0)`;
/// elsewhere assumed).
fn process_alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(p) = libc::pid_t::try_from(pid) else {
            return false;
        };
        // SAFETY: signal 0 only checks that the process exists
        let r = unsafe { libc::kill(p, 0) };
        r == 0 || io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// An exclusive lock tied to a file: `flock` on `.NAME.lock` beside it,
/// held until dropped, so that writers that read, add to and write back a
/// file (outcome memos) lose none of another's additions. The lock file
/// stays (removing it would let two processes lock two different files).
#[derive(Debug)]
pub struct FileLock {
    #[allow(dead_code)]
    file: File,
}

impl FileLock {
    /// Waits for and takes the lock of `path`.
    pub fn exclusive(path: &Path) -> io::Result<FileLock> {
        let (dir, name) = folder_and_name(path)?;
        let lock = dir.join(format!(".{name}.lock"));
        let file = open_lock(&lock)?;
        if !file.metadata()?.is_file() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{}: not a regular file", lock.display()),
            ));
        }
        #[cfg(unix)]
        flock(&file, libc::LOCK_EX)?;
        Ok(FileLock { file })
    }
}

/// `flock(2)` of `file` with `op`, retried when a signal interrupts it.
#[cfg(unix)]
fn flock(file: &File, op: libc::c_int) -> io::Result<()> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a descriptor we own
    while unsafe { libc::flock(file.as_raw_fd(), op) } != 0 {
        let e = io::Error::last_os_error();
        if e.kind() != io::ErrorKind::Interrupted {
            return Err(e);
        }
    }
    Ok(())
}

/// `o` with the open(2) `flags` on unix (ignored elsewhere).
fn unix_flags(o: &mut OpenOptions, flags: i32) -> &mut OpenOptions {
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(o, flags);
    let _ = flags;
    o
}

/// Opens (or creates) the lock file `path` for reading and writing, never
/// through a symbolic link, without blocking on a FIFO.
fn open_lock(path: &Path) -> io::Result<File> {
    let mut o = OpenOptions::new();
    o.read(true).write(true).create(true).truncate(false);
    unix_flags(&mut o, O_NOFOLLOW | O_NONBLOCK).open(path)
}

/// Opens `path` for reading only if it (or what a link leads to) is a
/// regular file, checked before and after a non-blocking open (a FIFO
/// would block, `/dev/zero` never ends); anything else is `InvalidInput`.
pub fn open_regular(path: &Path) -> io::Result<File> {
    let not_regular = || io::Error::new(io::ErrorKind::InvalidInput, "not a regular file");
    if !fs::metadata(path)?.is_file() {
        return Err(not_regular());
    }
    let f = unix_flags(OpenOptions::new().read(true), O_NONBLOCK).open(path)?;
    if !f.metadata()?.is_file() {
        return Err(not_regular());
    }
    Ok(f)
}

/// Opens an existing file for appending without following a symbolic link
/// (`O_NOFOLLOW` on unix): a link in its place is an error, so that a
/// planted link cannot make e3d append to, or truncate, another file.
pub fn open_append_nofollow(path: &Path) -> io::Result<File> {
    let mut o = OpenOptions::new();
    unix_flags(o.append(true), O_NOFOLLOW)
        .open(path)
        .map_err(|e| {
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

    /// A new empty folder `e3d-io-NAME-PID` in the system's temporary folder.
    fn fresh_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("e3d-io-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[cfg(unix)]
    #[test]
    fn a_stream_is_written_through_never_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = fresh_dir("stream");
        let fifo = dir.join("out.svg");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // no mkfifo here
        }
        assert!(is_stream(&fifo) && !is_stream(&dir) && !is_stream(&dir.join("none")));
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || fs::read(&fifo).unwrap())
        };
        write_atomic(&fifo, b"<svg/>").unwrap();
        assert_eq!(reader.join().unwrap(), b"<svg/>");
        // still the named pipe, and nothing left beside it
        assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        // a link to a stream is written through too; a regular file is replaced
        let link = dir.join("link.svg");
        std::os::unix::fs::symlink("/dev/null", &link).unwrap();
        write_atomic(&link, b"x").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        let plain = dir.join("plain.svg");
        write_atomic(&plain, b"a").unwrap();
        write_atomic(&plain, b"b").unwrap();
        assert_eq!(fs::read(&plain).unwrap(), b"b");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn temporary_files_never_follow_a_planted_link() {
        let dir = fresh_dir("test");
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
/// when the lock is dropped, and on the signals that end the process
/// ([`remove_temps_on_signals`]).
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

/// The error of a lock file `path` that cannot be opened: a symbolic link
/// or anything but a regular file in its place is named as such (the
/// system said only "Too many levels of symbolic links"); other errors as
/// they are, with the file.
fn lock_file_error(path: &Path, e: io::Error) -> io::Error {
    let p = path.display();
    let what = match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => "a symbolic link",
        Ok(m) if !m.is_file() => "not a regular file (a folder, a pipe, a device or a socket)",
        _ => return io::Error::new(e.kind(), format!("{p}: {e}")),
    };
    let why = format!("{p}: the lock file is {what}; e3d makes it as a regular file and never follows a link there (remove it, then run again)");
    io::Error::new(io::ErrorKind::InvalidInput, why)
}

impl DirLock {
    /// Takes the lock of folder `dir` (which must exist), or says who holds
    /// it: `Err` of kind `WouldBlock` whose message is the holder.
    pub fn acquire(dir: &Path) -> io::Result<DirLock> {
        let path = dir.join(LOCK_FILE);
        loop {
            let mut file = open_lock(&path).map_err(|e| lock_file_error(&path, e))?;
            if !file.metadata()?.is_file() {
                return Err(lock_file_error(
                    &path,
                    io::Error::new(io::ErrorKind::InvalidInput, "not a regular file"),
                ));
            }
            #[cfg(unix)]
            {
                use std::os::unix::fs::MetadataExt;
                if let Err(e) = flock(&file, libc::LOCK_EX | libc::LOCK_NB) {
                    if e.kind() != io::ErrorKind::WouldBlock {
                        return Err(e);
                    }
                    let mut who = String::new();
                    let _ = io::Read::read_to_string(&mut file, &mut who);
                    let who = match who.trim() {
                        "" => "another e3d".to_string(),
                        w => format!("e3d {w}"),
                    };
                    return Err(io::Error::new(io::ErrorKind::WouldBlock, who));
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
            // removed on the signals that end the process, as temporary
            // files are
            register_temp(&path);
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
        forget_temp(&self.path);
        let _ = fs::remove_file(&self.path);
    }
}
