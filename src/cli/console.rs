//! The command line's standard output and standard error, written through
//! [`outln!`] and [`errln!`]: every write is checked where it is made (a
//! failed one ends e3d, [`fail`]), and control characters are escaped so
//! that a name echoed in a message cannot drive the terminal.

use std::io::Write;

/// Writes `args` to `stream` (`stdout` or `stderr`), its control
/// characters escaped, or ends e3d ([`fail`]).
pub fn write(stream: &str, args: std::fmt::Arguments<'_>) {
    let text = args.to_string();
    let bytes = e3d::text::escape_controls(&text);
    let written = match stream {
        "stdout" => std::io::stdout().lock().write_all(bytes.as_bytes()),
        _ => std::io::stderr().lock().write_all(bytes.as_bytes()),
    };
    if let Err(e) = written {
        fail(stream, &e)
    }
}

/// Writes `text` to standard output and flushes it, as a CLI error
/// ([`stdout_error`]).
pub fn write_stdout(text: &[u8]) -> Result<(), super::CliError> {
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(text)
        .and_then(|()| stdout.flush())
        .map_err(stdout_error)
}

/// The error of a failed write to standard output: a closed pipe ends e3d
/// quietly ([`fail`]), anything else is an output error.
pub fn stdout_error(e: std::io::Error) -> super::CliError {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        fail("stdout", &e)
    }
    super::CliError::output(format!("standard output: {e}"))
}

/// Ends e3d after the write to `stream` failed with `e`: quietly for a
/// broken pipe, else with `error: cannot write to STREAM: E`; exit code 3
/// ([`exit::OUTPUT`](super::exit::OUTPUT)) either way.
pub fn fail(stream: &str, e: &std::io::Error) -> ! {
    // the temporary files of unfinished outputs go first: `> /dev/full`
    // must not leave a hidden `.trials.csv.tmp-*` in `run --out`'s folder
    e3d::io::remove_temps();
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        // end of the closed pipe's signal, as other Unix tools do
        #[cfg(unix)]
        // SAFETY: restores SIGPIPE's default action and raises it
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
            libc::raise(libc::SIGPIPE);
        }
    } else {
        // standard error may be the one that fails: then nothing can be said
        let _ = writeln!(std::io::stderr(), "error: cannot write to {stream}: {e}");
    }
    std::process::exit(i32::from(super::exit::OUTPUT))
}

/// [`println!`] whose write is checked ([`write`]).
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::cli::console::write("stdout", format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// [`eprintln!`] whose write is checked ([`write`]).
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::cli::console::write("stderr", format_args!("{}\n", format_args!($($arg)*)))
    };
}

pub(crate) use {errln, outln};
