//! Outputs that lose nothing. Every file a command writes is checked before any work
//! ([`check`]: its extension names its format, its folder exists, it is none of the command's
//! inputs and no other output) and then written whole or not at all ([`write`]: a temporary
//! file in the same folder, synced, then renamed over the target), so a failure leaves the old
//! file as it was and no temporary file behind.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{DemoError, Result};

/// The formats the commands write, each with the extensions it accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// A PNG image (`render --out`, `view --screenshot`, `precision --strip`,
    /// `tessellate --picture`): `.png`.
    Png,
    /// A plain PBM mask (`render --mask`, `view --mask`): `.pbm`.
    Pbm,
    /// An SVG plot (`precision --plot`): `.svg`.
    Svg,
    /// A CSV table (`precision --csv`): `.csv`.
    Csv,
    /// A mesh (`tessellate --out`, written by [`smoothtri_io::encode`]): `.obj`, `.ply` or
    /// `.glb`.
    Mesh,
}

impl Format {
    /// The extensions (lower case, without the dot) a file of this format may have; a path's
    /// extension is compared case-insensitively.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Format::Png => &["png"],
            Format::Pbm => &["pbm"],
            Format::Svg => &["svg"],
            Format::Csv => &["csv"],
            Format::Mesh => &["obj", "ply", "glb"],
        }
    }

    /// What the format is, for messages: `"a PNG image"`.
    pub fn name(self) -> &'static str {
        match self {
            Format::Png => "a PNG image",
            Format::Pbm => "a PBM mask",
            Format::Svg => "an SVG plot",
            Format::Csv => "a CSV table",
            Format::Mesh => "a mesh",
        }
    }

    /// The accepted extensions as a message lists them: `".obj, .ply or .glb"`.
    pub fn expected(self) -> String {
        let e: Vec<String> = self.extensions().iter().map(|e| format!(".{e}")).collect();
        match e.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => e.concat(),
        }
    }
}

/// A file a command reads: the option that names it (`"--mesh"`) and its path (`-`: stdin,
/// never a file).
#[derive(Clone, Copy, Debug)]
pub struct Input<'a> {
    /// The option, for messages.
    pub flag: &'static str,
    /// The path as given.
    pub path: &'a str,
}

/// A file a command writes: the option that names it (`"--out"`), its path (`-`: stdout,
/// accepted as is) and its format.
#[derive(Clone, Copy, Debug)]
pub struct Output<'a> {
    /// The option, for messages.
    pub flag: &'static str,
    /// The path as given.
    pub path: &'a str,
    /// What is written there.
    pub format: Format,
}

/// The inputs of the options that are set: `(flag, path)` pairs with `None` left out.
pub fn inputs<'a>(given: &[(&'static str, Option<&'a str>)]) -> Vec<Input<'a>> {
    given
        .iter()
        .filter_map(|&(flag, path)| path.map(|path| Input { flag, path }))
        .collect()
}

/// The outputs of the options that are set: `(flag, path, format)` triples with `None` left
/// out.
pub fn outputs<'a>(given: &[(&'static str, Option<&'a str>, Format)]) -> Vec<Output<'a>> {
    given
        .iter()
        .filter_map(|&(flag, path, format)| path.map(|path| Output { flag, path, format }))
        .collect()
}

/// Checks a command's outputs before it does any work. Each output other than `-` (stdout)
///
/// - has an extension of its format ([`Format::extensions`]);
/// - lies in a folder that exists;
/// - is not one of `inputs`, compared as canonical paths (so `./m.glb`, `dir/../m.glb` and a
///   symbolic link to the input count as the input; on Unix also the same file under another
///   name, a hard link); an output that does not exist yet is no input;
/// - is not the same file as another output.
///
/// Returns `Ok(())` when all hold. Errors: [`DemoError::Usage`] naming the option, the path and
/// the expected extensions, or the input it would overwrite, or the two options naming one
/// file; [`DemoError::Output`] naming the output whose folder does not exist.
pub fn check(inputs: &[Input<'_>], outputs: &[Output<'_>]) -> Result<()> {
    let mut seen: Vec<(&Output<'_>, Identity)> = Vec::new();
    for o in outputs.iter().filter(|o| o.path != "-") {
        let ext = smoothtri_io::extension(o.path);
        if !ext.is_some_and(|e| o.format.extensions().contains(&e.as_str())) {
            return Err(DemoError::Usage(format!(
                "{} {}: the output is {}, so its name must end in {}",
                o.flag,
                o.path,
                o.format.name(),
                o.format.expected()
            )));
        }
        let folder = folder_of(Path::new(o.path));
        if !folder.is_dir() {
            return Err(DemoError::output(
                o.path,
                format!("its folder {} does not exist", folder.display()),
            ));
        }
        let Some(id) = Identity::of_output(Path::new(o.path)) else {
            continue;
        };
        for i in inputs.iter().filter(|i| i.path != "-") {
            if Identity::of_existing(Path::new(i.path)).is_some_and(|j| j.same(&id)) {
                return Err(DemoError::Usage(format!(
                    "{} {} is the input {} {}: refusing to overwrite an input, name another file",
                    o.flag, o.path, i.flag, i.path
                )));
            }
        }
        if let Some((p, _)) = seen.iter().find(|(_, j)| j.same(&id)) {
            return Err(DemoError::Usage(format!(
                "{} {} and {} {} name the same file: name two files",
                p.flag, p.path, o.flag, o.path
            )));
        }
        seen.push((o, id));
    }
    Ok(())
}

/// Writes `bytes` to `path` whole or not at all, or to stdout for `-`.
///
/// The bytes go to a temporary file in the target's folder (the folder of the file a symbolic
/// link names, so the link stays and names the new contents), which is flushed, synced
/// to the disk and renamed over the target; the new file takes the old one's permissions (a new
/// file: read and write for all, less the umask). Any failure (the folder read-only, the disk
/// or a size limit full, the target a folder) leaves the target as it was and removes the
/// temporary file.
///
/// Returns `Ok(())` once the file is in place. Errors: [`DemoError::File`] with the I/O error,
/// naming `path`.
pub fn write(path: &str, bytes: &[u8]) -> Result<()> {
    if path == "-" {
        let mut out = std::io::stdout().lock();
        return out
            .write_all(bytes)
            .and_then(|_| out.flush())
            .map_err(|e| DemoError::io(path, e));
    }
    write_file(Path::new(path), bytes).map_err(|e| DemoError::io(path, e))
}

/// [`write`] to a file.
fn write_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let target = resolve(path)?;
    let name = target
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let old = fs::metadata(&target).ok().filter(|m| m.is_file());
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    let new_file = {
        use std::os::unix::fs::PermissionsExt as _;
        fs::Permissions::from_mode(0o666)
    };
    #[cfg(unix)]
    builder.permissions(new_file);
    let dir = folder_of(&target);
    let mut tmp = builder.tempfile_in(&dir)?;
    if let Some(old) = old {
        tmp.as_file().set_permissions(old.permissions())?;
    }
    tmp.write_all(bytes)?;
    tmp.flush()?;
    tmp.as_file().sync_all()?;
    tmp.persist(&target).map_err(|e| e.error)?;
    // The rename itself reaches the disk with the folder's entry; a folder that cannot be
    // opened or synced (some file systems refuse) leaves the file written and in place, so this
    // last step is best effort.
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The most symbolic links [`resolve`] follows in a row (Linux's limit).
const MAX_LINKS: usize = 40;

/// `path` with its symbolic links followed to the file they name, which need not exist yet (a
/// link that dangles names the file it would create). Errors: a loop of links, or a link that
/// cannot be read.
fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = fs::read_link(&p)?;
                p = folder_of(&p).join(to);
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links in a row"
    )))
}

/// The folder a path lies in (`.` for a bare file name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// What makes two paths one file: the canonical path and, on Unix, the device and inode of an
/// existing file.
struct Identity {
    path: PathBuf,
    inode: Option<(u64, u64)>,
}

impl Identity {
    /// An existing file's identity; `None` when it does not exist (or cannot be resolved).
    fn of_existing(path: &Path) -> Option<Identity> {
        let meta = fs::metadata(path).ok()?;
        Some(Identity {
            path: fs::canonicalize(path).ok()?,
            inode: inode(&meta),
        })
    }

    /// An output's identity: the existing file's, or the canonical folder with the name for a
    /// file still to be made; `None` when the folder cannot be resolved.
    fn of_output(path: &Path) -> Option<Identity> {
        Identity::of_existing(path).or_else(|| {
            // A file still to be made, or a dangling link to one: where it will be.
            let path = resolve(path).ok()?;
            let dir = fs::canonicalize(folder_of(&path)).ok()?;
            Some(Identity {
                path: dir.join(path.file_name()?),
                inode: None,
            })
        })
    }

    fn same(&self, other: &Identity) -> bool {
        self.path == other.path || (self.inode.is_some() && self.inode == other.inode)
    }
}

#[cfg(unix)]
fn inode(meta: &fs::Metadata) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt as _;
    Some((meta.dev(), meta.ino()))
}

#[cfg(not(unix))]
fn inode(_: &fs::Metadata) -> Option<(u64, u64)> {
    None
}
