//! The library crates' errors as Python exceptions, with the message the
//! command line prints after `error: ` (the error and its causes, joined by
//! `: ` as anyhow's alternate form writes them).

use std::error::Error;

use pyo3::PyErr;
use pyo3::exceptions::PyOSError;

use crate::ImuthermError;

/// The message and, when the root cause is the operating system's, its
/// error number.
fn message(err: &(dyn Error + 'static)) -> (String, Option<i32>) {
    let mut text = err.to_string();
    let mut errno = None;
    let mut cause: Option<&(dyn Error + 'static)> = Some(err);
    while let Some(e) = cause {
        // imu's reading error keeps its cause as a field, not as a source.
        let read = e.downcast_ref::<imu::ReadError>().or_else(|| {
            match e.downcast_ref::<analysis::AnalysisError>() {
                Some(analysis::AnalysisError::Read(r)) => Some(r),
                _ => None,
            }
        });
        let io = e
            .downcast_ref::<std::io::Error>()
            .or(match read.map(|r| &r.kind) {
                Some(imu::ReadErrorKind::Io(io)) => Some(io),
                _ => None,
            });
        if let Some(io) = io {
            // An I/O error with no OS code (a truncated file) is still one.
            errno = errno.or(Some(io.raw_os_error().unwrap_or(0)));
        }
        if let Some(imu::ReadErrorKind::IsDirectory) = read.map(|r| &r.kind) {
            // Python's IsADirectoryError is OSError with EISDIR: 21 on Linux,
            // macOS, the BSDs and in the Windows C runtime.
            errno = errno.or(Some(21));
        }
        cause = e.source();
        if let Some(next) = cause {
            text = format!("{text}: {next}");
        }
    }
    (text, errno)
}

/// An error of a reader or an analysis: `OSError` (its `FileNotFoundError`,
/// `PermissionError`, … subclass by the error number) when the file could
/// not be read, [`ImuthermError`] (a `ValueError`) otherwise.
pub(crate) fn to_py(err: &(dyn Error + 'static)) -> PyErr {
    match message(err) {
        (text, Some(errno)) if errno > 0 => PyOSError::new_err((errno, text)),
        (text, Some(_)) => PyOSError::new_err(text),
        (text, None) => ImuthermError::new_err(text),
    }
}

pub(crate) fn analysis_err(err: analysis::AnalysisError) -> PyErr {
    to_py(&err)
}

/// An error under a context, as anyhow's `with_context` shows it.
pub(crate) fn in_context(context: &str, err: &(dyn Error + 'static)) -> PyErr {
    let (text, _) = message(err);
    ImuthermError::new_err(format!("{context}: {text}"))
}

/// A refusal with the command line's message.
pub(crate) fn refused(text: impl Into<String>) -> PyErr {
    ImuthermError::new_err(text.into())
}
