//! [`LoadOptions`]: the loaders' memory budget and where a glTF file's buffers may come from;
//! [`Budget`], the running count of a load's bytes against it.

use std::cell::Cell;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

use crate::error::{Error, Result};

/// The default [`LoadOptions::max_bytes`]: 2 GiB, a mesh of a few million triangles, within the
/// memory of a desktop.
pub const DEFAULT_MAX_BYTES: u64 = 2 << 30;

/// Bytes the loaders charge for each vertex position they hold while welding: the position
/// (24) and, where the file has no normals, its computed normal (24).
pub(crate) const BYTES_PER_POSITION: u64 = 48;

/// Bytes the loaders charge for each triangle while welding: its three corners (3 × 40), its
/// three indices in the mesh (12), and per corner at most one new vertex of the mesh (position
/// and normal, 48; its source, 8; its entry in the welding map, 48): 444, rounded up.
pub(crate) const BYTES_PER_TRIANGLE: u64 = 448;

/// How a file is loaded ([`load_with`](crate::load_with), [`parse_with`](crate::parse_with),
/// [`load_animated_with`](crate::load_animated_with),
/// [`parse_animated_with`](crate::parse_animated_with)). `Default` is what [`load`](crate::load)
/// and the other entry points without options use.
///
/// ```
/// let mut options = smoothtri_io::LoadOptions::default();
/// options.max_bytes = 64 << 20;
/// assert!(!options.allow_outside_folder);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct LoadOptions {
    /// The budget of one load, in bytes (default [`DEFAULT_MAX_BYTES`]): the file itself, the
    /// glTF buffers it reads (external files, data URIs, the GLB's binary chunk), and what the
    /// loader decodes (accessors, vertices, triangles, animation keys; each charged at its size
    /// in memory before it is allocated). A load that would go past it stops with
    /// [`Error::Budget`] naming the file and the field. Every count, size and offset in a file
    /// is also checked against the bytes actually present, whatever the budget, so a small
    /// file cannot ask for much: the budget bounds what large, well-formed files and
    /// accessors without data (which decode to zeros) may take.
    pub max_bytes: u64,
    /// Whether a glTF buffer URI may name a file outside the asset's own folder (default
    /// `false`: absolute paths, `..` escapes, percent-encoded or not, and symlinks that leave
    /// the folder are [`Error::OutsideFolder`]). Set it for trusted pipelines only. Either way,
    /// a buffer must be a regular file (not a device, FIFO or folder) of at least its
    /// `byteLength`, of which only `byteLength` bytes are read. Images are never read.
    pub allow_outside_folder: bool,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            max_bytes: DEFAULT_MAX_BYTES,
            allow_outside_folder: false,
        }
    }
}

impl LoadOptions {
    /// These options with `max_bytes` set.
    pub fn with_max_bytes(mut self, max_bytes: u64) -> Self {
        self.max_bytes = max_bytes;
        self
    }

    /// These options with `allow_outside_folder` set.
    pub fn with_allow_outside_folder(mut self, allow: bool) -> Self {
        self.allow_outside_folder = allow;
        self
    }
}

/// The bytes one load has charged against its [`LoadOptions::max_bytes`].
///
/// Code that reports errors as strings charges with [`Budget::charge`], which returns the
/// message and keeps the typed error; whoever turns the message into an [`Error`] calls
/// [`Budget::typed`], which gives [`Error::Budget`] (with the full message as its field)
/// when the budget was what failed.
#[derive(Debug)]
pub(crate) struct Budget {
    path: String,
    max: u64,
    used: Cell<u64>,
    /// What the charge that failed needed.
    tripped: Cell<Option<u64>>,
}

impl Budget {
    /// A fresh budget of `options.max_bytes` for the file `path`.
    pub fn new(path: &str, options: &LoadOptions) -> Self {
        Budget {
            path: path.to_string(),
            max: options.max_bytes,
            used: Cell::new(0),
            tripped: Cell::new(None),
        }
    }

    /// A fresh budget of `options` for the file `path` whose `bytes` are already in memory,
    /// the bytes charged to it first ([`Error::Budget`] when they alone pass it).
    pub fn charged(path: &str, options: &LoadOptions, bytes: &[u8]) -> Result<Self> {
        let budget = Budget::new(path, options);
        budget.charge_typed("the file's size", bytes.len() as u64, 1)?;
        Ok(budget)
    }

    /// Charges `count` items of `size` bytes for `field`; past the budget, the error names the
    /// field and what was needed.
    pub fn charge_typed(&self, field: &str, count: u64, size: u64) -> Result<()> {
        self.charge(count, size)
            .map_err(|()| self.typed(Error::format(&self.path, field)))
    }

    /// Charges `count` items of `size` bytes; `Err` (the budget then marked as the cause, see
    /// [`Budget::typed`]) when that would pass the budget.
    pub fn charge(&self, count: u64, size: u64) -> std::result::Result<(), ()> {
        let needed = count.saturating_mul(size).saturating_add(self.used.get());
        if needed > self.max {
            self.tripped.set(Some(needed));
            return Err(());
        }
        self.used.set(needed);
        Ok(())
    }

    /// [`Budget::charge`] with the message `"{what}: {count} elements of {size} bytes"` for
    /// code that reports errors as strings.
    pub fn charge_msg(&self, what: &str, count: u64, size: u64) -> std::result::Result<(), String> {
        self.charge(count, size)
            .map_err(|()| format!("{what} ({count} elements of {size} bytes)"))
    }

    /// `err` as [`Error::Budget`] (its message as the field) when the last failed charge is
    /// what failed, else `err` unchanged.
    pub fn typed(&self, err: Error) -> Error {
        let Some(needed) = self.tripped.take() else {
            return err;
        };
        let field = match err {
            Error::Format { msg, .. } => msg,
            Error::Parse { line, msg, .. } => format!("line {line}: {msg}"),
            other => other.to_string(),
        };
        Error::Budget {
            path: self.path.clone(),
            field,
            needed,
            budget: self.max,
        }
    }
}

/// The bytes of the file `path` and the fresh budget of `options` they are charged to: a file
/// larger than the budget is [`Error::Budget`] (checked on its size before reading, and the
/// read bounded in case it grows); a file that is not a regular file is [`Error::Io`].
pub(crate) fn read_file(path: &str, options: &LoadOptions) -> Result<(Vec<u8>, Budget)> {
    let budget = Budget::new(path, options);
    // The kind first, without opening: opening a FIFO would wait for a writer.
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(Error::io(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a regular file"),
        ));
    }
    budget.charge_typed("the file's size", meta.len(), 1)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut out = Vec::new();
    // One byte past the charged size tells whether the file grew meanwhile.
    let limit = meta.len().saturating_add(1);
    file.take(limit)
        .read_to_end(&mut out)
        .map_err(|e| Error::io(path, e))?;
    if out.len() as u64 > meta.len() {
        return Err(Error::io(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidData, "the file grew while read"),
        ));
    }
    Ok((out, budget))
}

/// Decodes the `%XX` escapes of a URI reference (RFC 3986); `None` for a malformed escape or
/// bytes that are not UTF-8.
pub(crate) fn percent_decode(uri: &str) -> Option<String> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut k = 0;
    while k < b.len() {
        if b[k] == b'%' {
            let hex = b.get(k + 1..k + 3)?;
            let s = std::str::from_utf8(hex).ok()?;
            out.push(u8::from_str_radix(s, 16).ok()?);
            k += 3;
        } else {
            out.push(b[k]);
            k += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The external buffer `uri` of the glTF file `path`, `byte_length` bytes of it, confined as
/// `options` says (see [`LoadOptions::allow_outside_folder`]) and charged to `budget`.
pub(crate) fn read_buffer(
    path: &str,
    uri: &str,
    byte_length: usize,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<Vec<u8>> {
    let outside = || Error::OutsideFolder {
        path: path.to_string(),
        uri: uri.to_string(),
    };
    let not_file = |why: String| Error::Resource {
        path: path.to_string(),
        uri: uri.to_string(),
        why,
    };
    let decoded =
        percent_decode(uri).ok_or_else(|| not_file("malformed percent-encoding".into()))?;
    let rel = Path::new(&decoded);
    // A scheme (`file:`, `http:`) or a Windows drive is not a relative reference.
    let scheme = decoded
        .split_once(':')
        .is_some_and(|(s, _)| !s.is_empty() && !s.contains(['/', '\\']));
    let base = Path::new(path).parent().unwrap_or(Path::new(""));
    let base = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let joined: PathBuf = base.join(rel);
    let shown = joined.display().to_string();
    if !options.allow_outside_folder {
        let escapes = rel.is_absolute()
            || decoded.starts_with(['/', '\\'])
            || scheme
            || rel.components().any(|c| {
                matches!(
                    c,
                    Component::ParentDir | Component::RootDir | Component::Prefix(_)
                )
            });
        if escapes {
            return Err(outside());
        }
        // Symlinks: the file's real path must lie inside the folder's real path.
        let real_base = base
            .canonicalize()
            .map_err(|e| Error::io(&base.display().to_string(), e))?;
        let real = joined.canonicalize().map_err(|e| Error::io(&shown, e))?;
        if !real.starts_with(&real_base) {
            return Err(outside());
        }
    }
    // The kind first, without opening: opening a FIFO would wait for a writer.
    let meta = std::fs::metadata(&joined).map_err(|e| Error::io(&shown, e))?;
    if !meta.is_file() {
        return Err(not_file("not a regular file".into()));
    }
    if meta.len() < byte_length as u64 {
        return Err(not_file(format!(
            "the file has {} bytes, fewer than the buffer's byteLength {byte_length}",
            meta.len()
        )));
    }
    budget.charge(byte_length as u64, 1).map_err(|()| {
        budget.typed(Error::format(
            path,
            format!("buffer URI {uri:?} (byteLength {byte_length})"),
        ))
    })?;
    let file = std::fs::File::open(&joined).map_err(|e| Error::io(&shown, e))?;
    let mut out = Vec::with_capacity(byte_length);
    file.take(byte_length as u64)
        .read_to_end(&mut out)
        .map_err(|e| Error::io(&shown, e))?;
    Ok(out)
}
