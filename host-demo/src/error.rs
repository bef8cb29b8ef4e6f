//! The demo's typed error: every failure on user input ends as one readable message.

use std::fmt;

/// Why a command failed. `main` prints it on stderr and exits with a non-zero code.
#[derive(Debug)]
pub enum DemoError {
    /// A file could not be read, parsed or written: a mesh (the loaders' and writers' error),
    /// a CSV file (a malformed line), an image. The message names the file, and the line where
    /// the format has lines.
    File(smoothtri_io::Error),
    /// The mesh has no triangles, or none that the core accepts.
    Empty {
        /// What is empty and why.
        msg: String,
    },
    /// An invalid option value.
    Usage(String),
    /// Writing an output (image, plot) failed.
    Output {
        /// The file.
        path: String,
        /// What went wrong.
        msg: String,
    },
}

impl fmt::Display for DemoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DemoError::File(e) => e.fmt(f),
            DemoError::Empty { msg } => f.write_str(msg),
            DemoError::Usage(msg) => f.write_str(msg),
            DemoError::Output { path, msg } => write!(f, "cannot write {path}: {msg}"),
        }
    }
}

impl std::error::Error for DemoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            DemoError::File(e) => e.source(),
            _ => None,
        }
    }
}

impl DemoError {
    /// An I/O error on `path`.
    pub fn io(path: &str, source: std::io::Error) -> Self {
        DemoError::File(smoothtri_io::Error::io(path, source))
    }
    /// A parse error at `path:line`.
    pub fn parse(path: &str, line: usize, msg: impl Into<String>) -> Self {
        DemoError::File(smoothtri_io::Error::parse(path, line, msg))
    }
    /// An output error on `path`.
    pub fn output(path: &str, msg: impl fmt::Display) -> Self {
        DemoError::Output {
            path: path.to_string(),
            msg: msg.to_string(),
        }
    }
}

impl From<smoothtri_io::Error> for DemoError {
    fn from(e: smoothtri_io::Error) -> Self {
        DemoError::File(e)
    }
}

/// Result with [`DemoError`].
pub type Result<T> = std::result::Result<T, DemoError>;
