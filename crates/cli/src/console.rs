//! Standard output and error without panics. `println!` panics when standard output cannot
//! be written (`c3dfix info FILE > /dev/full`); these macros return the failure as an error
//! instead, so the command ends with a message and exit code 2 — after `repair` and `batch`
//! have written their files, a lost summary is no reason to crash.

use std::fmt;
use std::io::Write;

/// Write formatted text to standard output; the error names standard output.
pub fn write_stdout(args: fmt::Arguments) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_fmt(args)
        .map_err(|e| anyhow::anyhow!("cannot write to standard output: {e}"))
}

/// Flush standard output (its last line may still be buffered).
pub fn flush_stdout() -> anyhow::Result<()> {
    std::io::stdout()
        .flush()
        .map_err(|e| anyhow::anyhow!("cannot write to standard output: {e}"))
}

/// Write formatted text to standard error. Failure is ignored: there is nowhere left to say
/// anything, and a message is never worth a crash.
pub fn write_stderr(args: fmt::Arguments) {
    let _ = std::io::stderr().lock().write_fmt(args);
}

/// `print!` that returns `anyhow::Result<()>` instead of panicking.
macro_rules! out {
    ($($t:tt)*) => {
        $crate::console::write_stdout(format_args!($($t)*))
    };
}

/// `println!` that returns `anyhow::Result<()>` instead of panicking.
macro_rules! outln {
    () => {
        $crate::console::write_stdout(format_args!("\n"))
    };
    ($($t:tt)*) => {
        $crate::console::write_stdout(format_args!("{}\n", format_args!($($t)*)))
    };
}

/// `eprintln!` that never panics.
macro_rules! errln {
    ($($t:tt)*) => {
        $crate::console::write_stderr(format_args!("{}\n", format_args!($($t)*)))
    };
}

pub(crate) use {errln, out, outln};

/// The error and its causes, each said once: a cause whose text its parent already includes
/// (the library's errors name their file, then say what is wrong, and keep that as their
/// source) is not repeated.
pub fn describe(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        // The library's kinds that name a setting are said with this tool's flags.
        let m = match cause.downcast_ref::<c3dfix::Error>() {
            Some(e) => crate::flags::phrase(e),
            None => match cause.downcast_ref::<show::Error>() {
                Some(show::Error::Library(e)) => crate::flags::phrase(e),
                _ => match cause.downcast_ref::<gait::Error>() {
                    Some(e) => crate::flags::markers_phrase(e),
                    None => cause.to_string(),
                },
            },
        };
        if out.contains(&m) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&m);
    }
    out
}
