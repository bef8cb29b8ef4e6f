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
    /// Loading the file would take more than its budget
    /// ([`LoadOptions::max_bytes`](crate::LoadOptions::max_bytes); `path: field needs N bytes,
    /// over the load budget of M bytes`).
    Budget {
        /// The file.
        path: String,
        /// What asked for the bytes (the file's size, a buffer, an accessor, an element, with
        /// where it is: node, mesh, primitive, animation, line).
        field: String,
        /// The bytes the load would have held with it.
        needed: u64,
        /// The budget.
        budget: u64,
    },
    /// A glTF buffer URI that resolves outside the asset's own folder (an absolute path, a
    /// `..` escape, a symlink leaving the folder, another scheme), refused without
    /// [`LoadOptions::allow_outside_folder`](crate::LoadOptions::allow_outside_folder).
    OutsideFolder {
        /// The glTF file.
        path: String,
        /// The URI as the file writes it.
        uri: String,
    },
    /// A glTF buffer URI that cannot be read as a buffer: not a regular file (a device, a
    /// FIFO, a folder), shorter than its `byteLength`, or a malformed URI.
    Resource {
        /// The glTF file.
        path: String,
        /// The URI as the file writes it.
        uri: String,
        /// What is wrong.
        why: String,
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
            Error::Budget {
                path,
                field,
                needed,
                budget,
            } => write!(
                f,
                "{path}: {field} needs {needed} bytes, over the load budget of {budget} bytes"
            ),
            Error::OutsideFolder { path, uri } => write!(
                f,
                "{path}: buffer URI {uri:?} resolves outside the file's folder (refused; \
                 allow_outside_folder / --allow-outside-folder permits it)"
            ),
            Error::Resource { path, uri, why } => {
                write!(f, "{path}: buffer URI {uri:?}: {why}")
            }
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
