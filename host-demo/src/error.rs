//! The demo's typed error: every failure on user input ends as one readable message.

use std::fmt;

/// Why a command failed. `main` prints it on stderr and exits with a non-zero code.
#[derive(Debug)]
pub enum DemoError {
    /// A file could not be read or written.
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// A malformed line in a text file (OBJ, CSV).
    Parse {
        /// The file.
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A malformed file in a format without line information (PLY, glTF), or an unknown format.
    Format {
        /// The file.
        path: String,
        /// What is wrong.
        msg: String,
    },
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
            DemoError::Io { path, source } => write!(f, "{path}: {source}"),
            DemoError::Parse { path, line, msg } => write!(f, "{path}:{line}: {msg}"),
            DemoError::Format { path, msg } => write!(f, "{path}: {msg}"),
            DemoError::Empty { msg } => f.write_str(msg),
            DemoError::Usage(msg) => f.write_str(msg),
            DemoError::Output { path, msg } => write!(f, "cannot write {path}: {msg}"),
        }
    }
}

impl std::error::Error for DemoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            DemoError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl DemoError {
    /// An I/O error on `path`.
    pub fn io(path: &str, source: std::io::Error) -> Self {
        DemoError::Io {
            path: path.to_string(),
            source,
        }
    }
    /// A parse error at `path:line`.
    pub fn parse(path: &str, line: usize, msg: impl Into<String>) -> Self {
        DemoError::Parse {
            path: path.to_string(),
            line,
            msg: msg.into(),
        }
    }
    /// A format error in `path`.
    pub fn format(path: &str, msg: impl Into<String>) -> Self {
        DemoError::Format {
            path: path.to_string(),
            msg: msg.into(),
        }
    }
    /// An output error on `path`.
    pub fn output(path: &str, msg: impl fmt::Display) -> Self {
        DemoError::Output {
            path: path.to_string(),
            msg: msg.to_string(),
        }
    }
}

/// Result with [`DemoError`].
pub type Result<T> = std::result::Result<T, DemoError>;
