//! CSV input and output of `trace` and `eval`: reading a file or stdin, checking the header,
//! splitting rows, parsing numbers in the target precision (errors name `file:line`), printing
//! vectors shortest-round-trip.

use std::io::Read;

use crate::error::{DemoError, Result};
use crate::tracer::Prec;

/// Reads a whole text file, or stdin for `-`.
pub fn read_text(path: &str) -> Result<String> {
    if path == "-" {
        let mut s = String::new();
        std::io::stdin()
            .read_to_string(&mut s)
            .map_err(|e| DemoError::io("<stdin>", e))?;
        Ok(s)
    } else {
        std::fs::read_to_string(path).map_err(|e| DemoError::io(path, e))
    }
}

/// The name of an input in messages (`<stdin>` for `-`).
pub(crate) fn display_name(path: &str) -> &str {
    if path == "-" { "<stdin>" } else { path }
}

/// Data rows of a CSV text with the given header: `(line number, fields)`. Blank lines are
/// skipped; the header is compared case-insensitively.
pub(crate) fn rows<'a>(
    text: &'a str,
    path: &str,
    header: &[&str],
) -> Result<Vec<(usize, Vec<&'a str>)>> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let want = header.join(",");
    let Some((hl, h)) = lines.next() else {
        return Err(DemoError::parse(
            path,
            1,
            format!("empty file, expected header '{want}'"),
        ));
    };
    let got: Vec<String> = h
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    if got != header {
        return Err(DemoError::parse(
            path,
            hl + 1,
            format!("expected header '{want}', found '{}'", h.trim()),
        ));
    }
    let mut out = Vec::new();
    for (i, l) in lines {
        let f: Vec<&str> = l.split(',').map(str::trim).collect();
        if f.len() != header.len() {
            return Err(DemoError::parse(
                path,
                i + 1,
                format!("expected {} fields, found {}", header.len(), f.len()),
            ));
        }
        out.push((i + 1, f));
    }
    Ok(out)
}

/// A finite number in precision `F`, parsed in that precision directly so that printed values
/// read back exactly.
pub(crate) fn num<F: Prec>(tok: &str, path: &str, line: usize) -> Result<F> {
    let v = smoothtri_io::obj::parse_f64(tok, path, line)?;
    Ok(F::parse(tok).unwrap_or_else(|| F::from_f64(v)))
}

/// `x,y,z` of a vector, each shortest-round-trip.
pub(crate) fn vec3<F: Prec>(v: F::Vec3) -> String {
    let [x, y, z] = F::to_array3(v);
    format!("{x},{y},{z}")
}
