//! The docs contract, checked on every file of the repository (the README's test command and
//! CI run it):
//! - every repository path a file cites exists (from the repository's root, the citing file's
//!   crate or its folder); `CHANGELOG.md` is history and exempt;
//! - every section a file cites by title (`README, "Limits"`, `docs/METHOD.md "The shell"`)
//!   or by anchor (`docs/MEASUREMENTS.md#…`) is a heading or a bold lead-in of that document;
//! - every name a comment cites beside a source file (`gpu/src/shader.rs` `PATCH_VEC4`,
//!   `core/src/surface/field.rs SECTION_NEWTON_STEPS`, in Rust, WGSL, C and Markdown alike) is
//!   in that file;
//! - the core's comments carry no "before → after" figures and no dates: those belong in
//!   `docs/MEASUREMENTS.md` and the CHANGELOG;
//! - the README is a guide of at most [`README_MAX_LINES`] lines.

use std::path::{Path, PathBuf};

/// The README's length limit (the full tables live in `docs/MEASUREMENTS.md`).
const README_MAX_LINES: usize = 350;

/// Folders never read (build outputs, fuzzing state, version control).
const SKIP_DIRS: &[&str] = &[
    "target",
    ".git",
    "node_modules",
    "corpus",
    "artifacts",
    ".venv",
];

/// Cited paths that name what a command creates, not a file of the repository.
const GENERATED: &[&str] = &[
    "fuzz/artifacts",
    "fuzz/corpus",
    "fuzz/target",
    "no-panic-check/target",
];

/// Files whose paths are history by design.
const HISTORY: &[&str] = &["CHANGELOG.md"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every text file of the repository: sources, docs, manifests, scripts.
fn files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = e.file_name().to_string_lossy().into_owned();
            if p.is_dir() {
                if !SKIP_DIRS.contains(&name.as_str()) {
                    walk(&p, out);
                }
                continue;
            }
            let text = matches!(
                p.extension().and_then(|x| x.to_str()),
                Some("rs" | "md" | "toml" | "wgsl" | "h" | "c" | "cpp" | "py" | "pyi" | "sh")
            ) || name == "run";
            if text {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&root(), &mut out);
    out.sort();
    out
}

/// The files whose citations are checked, each with its path from the root and its text:
/// every readable file of [`files`] but the [`HISTORY`] ones and those named in `skip`.
fn cited_from(skip: &'static [&'static str]) -> impl Iterator<Item = (PathBuf, String, String)> {
    files().into_iter().filter_map(move |f| {
        let name = rel(&f);
        if HISTORY.contains(&name.as_str()) || skip.contains(&name.as_str()) {
            return None;
        }
        let text = std::fs::read_to_string(&f).ok()?;
        Some((f, name, text))
    })
}

/// The repository's top-level folders: a cited path starts with one of them.
fn top_dirs() -> Vec<String> {
    let mut dirs: Vec<String> = std::fs::read_dir(root())
        .expect("the repository root is readable")
        .flatten()
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !SKIP_DIRS.contains(&n.as_str()) && (!n.starts_with('.') || n == ".ci"))
        .collect();
    dirs.sort();
    dirs
}

fn path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-')
}

/// The repository paths cited in `text`: a top-level folder, a slash and path characters,
/// not preceded by a path character (so `../x` and URLs' paths are not read as ours).
fn cited_paths(text: &str, tops: &[String]) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let chars: Vec<(usize, char)> = line.char_indices().collect();
        for (k, &(i, c)) in chars.iter().enumerate() {
            if k > 0 && path_char(chars[k - 1].1) || !(c.is_ascii_alphanumeric() || c == '.') {
                continue;
            }
            let Some(top) = tops
                .iter()
                .find(|t| line[i..].starts_with(&format!("{t}/")))
            else {
                continue;
            };
            let end = line[i..]
                .char_indices()
                .find(|&(_, c)| !path_char(c))
                .map_or(line.len(), |(j, _)| i + j);
            let p = line[i..end].trim_end_matches(['.', '/', '-']);
            if p.len() > top.len() + 1 && !p.contains("..") {
                out.push((n + 1, p.to_owned()));
            }
        }
    }
    out
}

/// The folder of the crate that holds `file` (the nearest folder with a `Cargo.toml`).
fn crate_dir(file: &Path) -> Option<PathBuf> {
    let mut d = file.parent()?;
    loop {
        if d.join("Cargo.toml").exists() {
            return Some(d.to_path_buf());
        }
        d = d.parent()?;
    }
}

/// Whether the path `p` cited in `file` names a file or folder of the repository.
fn resolves(file: &Path, p: &str) -> bool {
    let bases = [
        Some(root()),
        crate_dir(file),
        file.parent().map(Path::to_path_buf),
    ];
    bases.into_iter().flatten().any(|b| b.join(p).exists())
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

/// The verdict of a scan of the cited `what`: more than `min` found (else the scan is broken),
/// and none of them bad (`bad`: one line each, listed under `heading`).
fn check_scan(min: usize, cited: usize, what: &str, heading: &str, bad: &[String]) {
    assert!(
        cited > min,
        "only {cited} cited {what} found: is the scan broken?"
    );
    assert!(
        bad.is_empty(),
        "{} {heading}:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn every_cited_path_exists() {
    let tops = top_dirs();
    let mut bad = Vec::new();
    let mut cited = 0;
    for (f, name, text) in cited_from(&[]) {
        for (line, p) in cited_paths(&text, &tops) {
            cited += 1;
            if GENERATED.iter().any(|g| p.starts_with(g)) || resolves(&f, &p) {
                continue;
            }
            bad.push(format!("{name}:{line}: `{p}` does not exist"));
        }
    }
    check_scan(100, cited, "paths", "missing paths", &bad);
}

/// `text` with the comment markers of each line removed and the lines joined, so that a
/// reference broken across comment lines reads as one.
fn flatten(text: &str) -> String {
    text.lines()
        .map(|l| {
            let t = l.trim_start();
            ["//!", "///", "//", "#", "*", "-"]
                .iter()
                .find_map(|m| t.strip_prefix(m))
                .unwrap_or(t)
                .trim()
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The headings and bold lead-ins (`**Title.**`) of a Markdown document, without their
/// numbering marks and trailing punctuation.
fn titles(md: &str) -> Vec<String> {
    // "§9 Seamless shading normals" → "Seamless shading normals".
    let clean = |s: &str| {
        s.trim()
            .trim_start_matches(['§', '#'])
            .trim_start_matches(|c: char| c.is_ascii_digit() || c == '.' || c == ' ')
            .trim_end_matches(['.', ':'])
            .to_owned()
    };
    let mut out = Vec::new();
    for l in md.lines() {
        if l.starts_with('#') {
            out.push(clean(l.trim_start_matches('#')));
        }
        let mut rest = l;
        while let Some(i) = rest.find("**") {
            let after = &rest[i + 2..];
            let Some(j) = after.find("**") else { break };
            out.push(clean(&after[..j]));
            rest = &after[j + 2..];
        }
    }
    out
}

/// GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens.
fn slug(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The document a reference names (`README`, `README.md`, `docs/METHOD.md`, `METHOD.md`).
fn document(file: &Path, name: &str) -> Option<PathBuf> {
    let name = if name == "README" { "README.md" } else { name };
    let bases = [
        Some(root()),
        Some(root().join("docs")),
        file.parent().map(Path::to_path_buf),
    ];
    bases
        .into_iter()
        .flatten()
        .map(|b| b.join(name))
        .find(|p| p.is_file())
}

/// The cited sections of `text`: `(document, title or anchor, is_anchor)`.
fn cited_sections(text: &str) -> Vec<(String, String, bool)> {
    let flat = flatten(text);
    let mut out = Vec::new();
    let bytes = flat.as_bytes();
    let mut i = 0;
    while i < flat.len() {
        let rest = &flat[i..];
        // A document name: README or a *.md word.
        let name_end = rest
            .char_indices()
            .find(|&(_, c)| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-')))
            .map_or(rest.len(), |(j, _)| j);
        let name = &rest[..name_end];
        let boundary = i == 0 || !path_char(bytes[i - 1] as char);
        let is_doc = boundary && (name == "README" || name.ends_with(".md"));
        if is_doc {
            let after = &rest[name_end..];
            if let Some(anchor) = after.strip_prefix('#') {
                let a: String = anchor
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || matches!(c, '-' | '_'))
                    .collect();
                if !a.is_empty() {
                    out.push((name.to_owned(), a, true));
                }
            } else {
                let skipped = after.trim_start_matches([',', ':', ' ', '(', '\'', 's']);
                let skipped = skipped
                    .strip_prefix("section")
                    .unwrap_or(skipped)
                    .trim_start();
                // A title: a capital letter first, prose after (not code that names a file).
                if let Some(q) = skipped.strip_prefix('"')
                    && let Some(j) = q.find('"')
                    && j <= 80
                    && q.starts_with(|c: char| c.is_uppercase())
                    && !q[..j].contains(['(', ')', '{', '}', ';', '=', '!', '&', '<', '>'])
                {
                    out.push((name.to_owned(), q[..j].to_owned(), false));
                }
            }
        }
        i += name_end.max(1);
        while i < flat.len() && !flat.is_char_boundary(i) {
            i += 1;
        }
    }
    out
}

#[test]
fn every_cited_section_exists() {
    let mut bad = Vec::new();
    let mut cited = 0;
    for (f, name, text) in cited_from(&[]) {
        for (doc, title, anchor) in cited_sections(&text) {
            let Some(path) = document(&f, &doc) else {
                continue; // a document outside the repository (a crate's README, say)
            };
            cited += 1;
            let heads = titles(&std::fs::read_to_string(&path).unwrap_or_default());
            let found = if anchor {
                let md = std::fs::read_to_string(&path).unwrap_or_default();
                md.lines()
                    .filter(|l| l.starts_with('#'))
                    .any(|l| slug(l.trim_start_matches('#').trim()) == title)
            } else {
                heads
                    .iter()
                    .any(|h| h.starts_with(title.trim_end_matches(['.', ':'])))
            };
            if !found {
                bad.push(format!("{name}: {doc} has no section \"{title}\""));
            }
        }
    }
    check_scan(5, cited, "sections", "missing sections", &bad);
}

/// The names cited right after a source file's path in `text` (flattened: a citation may break
/// across comment lines): a backticked name (`` `GpuScene::closest_hit` ``, `` `traverse` ``)
/// or a bare constant (`SECTION_NEWTON_STEPS`), each as the identifier to look for (the last
/// segment of a path or method call) with the cited file.
fn cited_names(text: &str, tops: &[String]) -> Vec<(String, String)> {
    let flat = flatten(text);
    let mut out = Vec::new();
    for (_, p) in cited_paths(&flat, tops) {
        if !(p.ends_with(".rs") || p.ends_with(".wgsl")) {
            continue;
        }
        let mut from = 0;
        while let Some(at) = flat[from..].find(p.as_str()) {
            let start = from + at + p.len();
            from = start;
            let rest = &flat[start..];
            let after = rest.trim_start_matches(['`', ' ', '(', ',']);
            let skipped = &rest[..rest.len() - after.len()];
            let token: String = after
                .chars()
                .take_while(|&c| c.is_ascii_alphanumeric() || matches!(c, '_' | ':' | '.' | '/'))
                .collect();
            let token = token.trim_end_matches([':', '.']);
            let last = token.rsplit([':', '.']).next().unwrap_or("");
            let file_like = token.contains('/')
                || ["rs", "wgsl", "md", "h", "c", "py", "toml", "json"].contains(&last);
            let backticked = skipped.ends_with('`');
            let constant = last.len() > 3
                && last.contains('_')
                && last
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_');
            if !file_like
                && last.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
                && (backticked || constant && !skipped.contains(','))
            {
                out.push((p.clone(), last.to_owned()));
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// Whether `word` occurs in `text` as a whole identifier.
fn has_word(text: &str, word: &str) -> bool {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.match_indices(word).any(|(i, _)| {
        !text[..i].chars().next_back().is_some_and(ident)
            && !text[i + word.len()..].chars().next().is_some_and(ident)
    })
}

#[test]
fn every_cited_name_is_in_its_file() {
    let tops = top_dirs();
    let mut bad = Vec::new();
    let mut cited = 0;
    for (f, name, text) in cited_from(&["docs/MEASUREMENTS.md"]) {
        for (p, word) in cited_names(&text, &tops) {
            let bases = [
                Some(root()),
                crate_dir(&f),
                f.parent().map(Path::to_path_buf),
            ];
            let Some(target) = bases
                .into_iter()
                .flatten()
                .map(|b| b.join(&p))
                .find(|t| t.is_file())
            else {
                continue;
            };
            cited += 1;
            let body = std::fs::read_to_string(&target).unwrap_or_default();
            // A name ending in `_` is a prefix (`scene_tilted_sphere_*`).
            let found = if word.ends_with('_') {
                body.contains(&word)
            } else {
                has_word(&body, &word)
            };
            if !found {
                bad.push(format!("{name}: `{p}` has no `{word}`"));
            }
        }
    }
    check_scan(20, cited, "names", "names not in the file cited", &bad);
}

#[test]
fn core_comments_carry_no_history() {
    let mut bad = Vec::new();
    for f in files() {
        let name = rel(&f);
        if !name.starts_with("core/src/") {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap_or_default();
        for (n, line) in text.lines().enumerate() {
            let Some(at) = line.find("//") else { continue };
            let comment = &line[at..];
            let chars: Vec<char> = comment.chars().collect();
            // "<digit> → <digit>" (or ->), digits grouped by spaces, commas or points.
            let arrow = chars.iter().enumerate().any(|(k, &c)| {
                let (a, b) = match c {
                    '→' => (k, k + 1),
                    '-' if chars.get(k + 1) == Some(&'>') => (k, k + 2),
                    _ => return false,
                };
                let before = chars[..a].iter().rev().find(|c| **c != ' ');
                let after = chars[b..].iter().find(|c| **c != ' ');
                before.is_some_and(|c| c.is_ascii_digit() || *c == '%')
                    && after.is_some_and(|c| c.is_ascii_digit())
            });
            // A date: 20YY-MM.
            let date = comment.as_bytes().windows(7).any(|w| {
                w[0] == b'2'
                    && w[1] == b'0'
                    && w[2..4].iter().all(u8::is_ascii_digit)
                    && w[4] == b'-'
                    && w[5..7].iter().all(u8::is_ascii_digit)
            });
            if arrow || date {
                bad.push(format!("{name}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "figures before → after and dates belong in docs/MEASUREMENTS.md and the CHANGELOG:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_readme_is_a_guide() {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let lines = readme.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines (at most {README_MAX_LINES}: full tables go to docs/)"
    );
}
