//! [`Error`]: why a file could not be read, parsed or written, naming the file and, where the
//! format has them, the line (OBJ) or the element, node or accessor (PLY, glTF).

use std::fmt;

/// Why a mesh file could not be read, parsed or written. Every failure of this crate is one of
/// these, never a panic; its `Display` is one line that names the file (`path: …`,
/// `path:line: …`). Text readers of other files ([`obj::parse_f64`](crate::obj::parse_f64) in a
/// CSV reader, say) report with it too.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written (`path: <the OS error>`).
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// A malformed line in a text format (OBJ; `path:line: what`).
    Parse {
        /// The file.
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A malformed file in a format without line information (PLY, glTF: the message names the
    /// element, node, mesh, primitive or accessor), or an unknown extension (`path: what`).
    Format {
        /// The file.
        path: String,
        /// What is wrong.
        msg: String,
    },
    /// The file holds no triangle (`path: the mesh has no triangles`).
    NoTriangles {
        /// The file.
        path: String,
    },
    /// A mesh without positions or triangles given to the glTF writer, whose accessors need at
    /// least one element.
    EmptyGltf,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, source } => write!(f, "{path}: {source}"),
            Error::Parse { path, line, msg } => write!(f, "{path}:{line}: {msg}"),
            Error::Format { path, msg } => write!(f, "{path}: {msg}"),
            Error::NoTriangles { path } => write!(f, "{path}: the mesh has no triangles"),
            Error::EmptyGltf => f.write_str("cannot write an empty mesh as glTF"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: &str, source: std::io::Error) -> Self {
        Error::Io {
            path: path.to_string(),
            source,
        }
    }

    /// A parse error at `path:line`.
    pub fn parse(path: &str, line: usize, msg: impl Into<String>) -> Self {
        Error::Parse {
            path: path.to_string(),
            line,
            msg: msg.into(),
        }
    }

    /// A format error in `path`.
    pub fn format(path: &str, msg: impl Into<String>) -> Self {
        Error::Format {
            path: path.to_string(),
            msg: msg.into(),
        }
    }
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
