//! The binary glTF (GLB) container, split and checked here before any byte of it reaches the
//! `gltf` crate (whose own GLB reader panicked on some truncated headers).
//!
//! Layout, from the glTF 2.0 specification ("GLB File Format Specification"), all integers
//! little-endian `u32`:
//!
//! - a 12-byte header: `magic` = `glTF`, `version` = 2, `length` = the total length of the GLB
//!   in bytes, header and all chunks included (here: the file's size);
//! - then chunks, each an 8-byte chunk header, `chunkLength` (bytes of chunk data) and
//!   `chunkType`, followed by `chunkLength` bytes of data. The start and the end of every chunk
//!   are aligned to 4-byte boundaries, so `chunkLength` is a multiple of 4;
//! - the first chunk is the JSON chunk (`JSON`, exactly one); a binary buffer chunk (`BIN\0`),
//!   if there is one, is the second; chunks of other types are ignored.

use std::fmt;

/// `magic` of the GLB header.
pub const MAGIC: [u8; 4] = *b"glTF";
/// The only container version this reader accepts.
pub const VERSION: u32 = 2;
/// Size of the GLB header in bytes.
pub const HEADER_LEN: usize = 12;
/// Size of a chunk header in bytes.
pub const CHUNK_HEADER_LEN: usize = 8;
/// `chunkType` of the JSON chunk.
pub const CHUNK_JSON: [u8; 4] = *b"JSON";
/// `chunkType` of the binary buffer chunk.
pub const CHUNK_BIN: [u8; 4] = *b"BIN\0";

/// The chunks of a well-formed GLB, borrowed from the file's bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Glb<'a> {
    /// Data of the JSON chunk (the glTF document, padded with spaces).
    pub json: &'a [u8],
    /// Data of the BIN chunk, if there is one (padding included).
    pub bin: Option<&'a [u8]>,
}

/// What is wrong with a GLB container. Chunks are numbered from 0 (the JSON chunk).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GlbError {
    /// The file is shorter than the 12-byte header.
    TruncatedHeader {
        /// File size in bytes.
        len: usize,
    },
    /// The first four bytes are not `glTF`.
    Magic([u8; 4]),
    /// The container version is not 2.
    Version(u32),
    /// The header's total length differs from the file's size.
    Length {
        /// `length` from the header.
        declared: u32,
        /// File size in bytes.
        actual: usize,
    },
    /// Fewer than 8 bytes are left where a chunk header should start.
    TruncatedChunkHeader {
        /// Chunk number.
        index: usize,
        /// Bytes left in the file.
        remaining: usize,
    },
    /// A chunk declares more data than the file has left.
    ChunkPastEnd {
        /// Chunk number.
        index: usize,
        /// `chunkType`.
        ty: [u8; 4],
        /// `chunkLength`.
        declared: u32,
        /// Bytes left after the chunk header.
        remaining: usize,
    },
    /// A chunk's length is not a multiple of 4.
    ChunkUnaligned {
        /// Chunk number.
        index: usize,
        /// `chunkType`.
        ty: [u8; 4],
        /// `chunkLength`.
        declared: u32,
    },
    /// The header is not followed by any chunk.
    NoChunks,
    /// The first chunk is not the JSON chunk.
    FirstNotJson([u8; 4]),
    /// A JSON chunk other than the first.
    ExtraJson {
        /// Chunk number.
        index: usize,
    },
    /// A BIN chunk other than the second.
    MisplacedBin {
        /// Chunk number.
        index: usize,
    },
}

/// A chunk type for messages: `JSON`, `BIN`, or the quoted bytes.
struct ChunkType([u8; 4]);

impl fmt::Display for ChunkType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            CHUNK_JSON => f.write_str("JSON"),
            CHUNK_BIN => f.write_str("BIN"),
            ty => write!(f, "type \"{}\"", ty.escape_ascii()),
        }
    }
}

impl fmt::Display for GlbError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GlbError::TruncatedHeader { len } => write!(
                f,
                "the file has {len} bytes, fewer than the {HEADER_LEN}-byte GLB header"
            ),
            GlbError::Magic(m) => write!(
                f,
                "the file starts with \"{}\", not the GLB magic \"glTF\"",
                m.escape_ascii()
            ),
            GlbError::Version(v) => {
                if *v == 1 {
                    write!(
                        f,
                        "GLB version 1 (glTF 1.0) is not supported (only glTF 2.0; convert the \
                         file to 2.0 first)"
                    )
                } else {
                    write!(f, "GLB version {v} is not supported (expected {VERSION})")
                }
            }
            GlbError::Length { declared, actual } => write!(
                f,
                "the GLB header declares a length of {declared} bytes but the file has {actual}"
            ),
            GlbError::TruncatedChunkHeader { index, remaining } => write!(
                f,
                "GLB chunk {index}: only {remaining} bytes remain for its {CHUNK_HEADER_LEN}-byte \
                 chunk header"
            ),
            GlbError::ChunkPastEnd {
                index,
                ty,
                declared,
                remaining,
            } => write!(
                f,
                "GLB chunk {index} ({}) declares {declared} bytes but only {remaining} remain",
                ChunkType(*ty)
            ),
            GlbError::ChunkUnaligned {
                index,
                ty,
                declared,
            } => write!(
                f,
                "GLB chunk {index} ({}) declares {declared} bytes, not a multiple of 4",
                ChunkType(*ty)
            ),
            GlbError::NoChunks => f.write_str("GLB has no chunks (a JSON chunk is required)"),
            GlbError::FirstNotJson(ty) => write!(
                f,
                "the first GLB chunk is {}, expected the JSON chunk",
                ChunkType(*ty)
            ),
            GlbError::ExtraJson { index } => {
                write!(f, "GLB chunk {index} is a second JSON chunk")
            }
            GlbError::MisplacedBin { index } => write!(
                f,
                "GLB chunk {index} is a BIN chunk, but only chunk 1 (right after the JSON \
                 chunk) may be"
            ),
        }
    }
}

impl std::error::Error for GlbError {}

/// A GLB of a JSON document and an optional binary buffer: the header, the JSON chunk padded
/// with spaces and the BIN chunk padded with zeros to 4-byte boundaries, as the
/// specification requires. (The inverse of [`parse`]; no checks: a JSON or BIN of 4 GiB or more
/// does not fit the format's `u32` lengths and is the caller's to avoid.)
pub fn build(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |n: usize| n.div_ceil(4) * 4;
    let jl = pad(json.len());
    let bl = bin.map(|b| pad(b.len()));
    let total = HEADER_LEN + CHUNK_HEADER_LEN + jl + bl.map_or(0, |l| CHUNK_HEADER_LEN + l);
    let mut out = Vec::with_capacity(total);
    out.extend(MAGIC);
    out.extend(VERSION.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((jl as u32).to_le_bytes());
    out.extend(CHUNK_JSON);
    out.extend(json);
    out.resize(out.len() + jl - json.len(), b' ');
    if let (Some(b), Some(l)) = (bin, bl) {
        out.extend((l as u32).to_le_bytes());
        out.extend(CHUNK_BIN);
        out.extend(b);
        out.resize(out.len() + l - b.len(), 0);
    }
    out
}

/// Little-endian `u32` at `at`; the caller has checked that four bytes are there.
fn u32_at(bytes: &[u8], at: usize) -> u32 {
    let mut b = [0u8; 4];
    b.copy_from_slice(&bytes[at..at + 4]);
    u32::from_le_bytes(b)
}

/// Four bytes at `at` as a tag; the caller has checked that they are there.
fn tag_at(bytes: &[u8], at: usize) -> [u8; 4] {
    let mut b = [0u8; 4];
    b.copy_from_slice(&bytes[at..at + 4]);
    b
}

/// Checks a whole GLB file and returns its JSON and BIN chunks (see the module documentation
/// for the rules). Never panics, whatever the bytes.
pub fn parse(bytes: &[u8]) -> Result<Glb<'_>, GlbError> {
    if bytes.len() >= 4 && bytes[..4] != MAGIC {
        return Err(GlbError::Magic(tag_at(bytes, 0)));
    }
    if bytes.len() < HEADER_LEN {
        return Err(GlbError::TruncatedHeader { len: bytes.len() });
    }
    let version = u32_at(bytes, 4);
    if version != VERSION {
        return Err(GlbError::Version(version));
    }
    let declared = u32_at(bytes, 8);
    if usize::try_from(declared).ok() != Some(bytes.len()) {
        return Err(GlbError::Length {
            declared,
            actual: bytes.len(),
        });
    }
    let mut json = None;
    let mut bin = None;
    let mut at = HEADER_LEN;
    let mut index = 0usize;
    while at < bytes.len() {
        let remaining = bytes.len() - at;
        if remaining < CHUNK_HEADER_LEN {
            return Err(GlbError::TruncatedChunkHeader { index, remaining });
        }
        let len = u32_at(bytes, at);
        let ty = tag_at(bytes, at + 4);
        at += CHUNK_HEADER_LEN;
        let remaining = bytes.len() - at;
        let data_len = match usize::try_from(len) {
            Ok(n) if n <= remaining => n,
            _ => {
                return Err(GlbError::ChunkPastEnd {
                    index,
                    ty,
                    declared: len,
                    remaining,
                });
            }
        };
        if data_len % 4 != 0 {
            return Err(GlbError::ChunkUnaligned {
                index,
                ty,
                declared: len,
            });
        }
        let data = &bytes[at..at + data_len];
        match (index, ty) {
            (0, CHUNK_JSON) => json = Some(data),
            (0, other) => return Err(GlbError::FirstNotJson(other)),
            (_, CHUNK_JSON) => return Err(GlbError::ExtraJson { index }),
            (1, CHUNK_BIN) => bin = Some(data),
            (_, CHUNK_BIN) => return Err(GlbError::MisplacedBin { index }),
            // Chunks of unknown types are skipped, as the specification requires.
            _ => {}
        }
        at += data_len;
        index += 1;
    }
    let json = json.ok_or(GlbError::NoChunks)?;
    Ok(Glb { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A GLB with the given chunks, the header's length set to the total.
    fn glb(chunks: &[(&[u8; 4], &[u8])]) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend(MAGIC);
        out.extend(VERSION.to_le_bytes());
        out.extend(0u32.to_le_bytes());
        for (ty, data) in chunks {
            out.extend((data.len() as u32).to_le_bytes());
            out.extend(*ty);
            out.extend(*data);
        }
        let n = out.len() as u32;
        out[8..12].copy_from_slice(&n.to_le_bytes());
        out
    }

    #[test]
    fn build_pads_and_parse_reads_back() {
        let bytes = build(b"{}", Some(&[1, 2, 3, 4, 5]));
        assert_eq!(bytes.len(), 12 + 8 + 4 + 8 + 8);
        let g = parse(&bytes).unwrap();
        assert_eq!(g.json, b"{}  ");
        assert_eq!(g.bin, Some(&[1u8, 2, 3, 4, 5, 0, 0, 0][..]));
        assert_eq!(parse(&build(b"{}", None)).unwrap().bin, None);
    }

    #[test]
    fn well_formed_chunks_are_returned() {
        let bytes = glb(&[(b"JSON", b"{}  "), (b"BIN\0", &[1, 2, 3, 4])]);
        let g = parse(&bytes).unwrap();
        assert_eq!(g.json, b"{}  ");
        assert_eq!(g.bin, Some(&[1u8, 2, 3, 4][..]));
        let bytes = glb(&[(b"JSON", b"{}  ")]);
        assert_eq!(parse(&bytes).unwrap().bin, None);
        // Unknown chunk types are skipped.
        let bytes = glb(&[(b"JSON", b"{}  "), (b"BIN\0", b""), (b"XTRA", b"abcd")]);
        assert_eq!(parse(&bytes).unwrap().bin, Some(&[][..]));
    }

    #[test]
    fn every_malformation_is_a_typed_error() {
        assert_eq!(
            parse(b"glTF\x02\0\0"),
            Err(GlbError::TruncatedHeader { len: 7 })
        );
        assert_eq!(parse(b"gl"), Err(GlbError::TruncatedHeader { len: 2 }));
        assert_eq!(parse(b"{\"asset\":{}}"), Err(GlbError::Magic(*b"{\"as")));
        // The 13-byte input the `gltf` fuzz target found (the crate panicked on it).
        let fuzz = [
            0x67, 0x6c, 0x54, 0x46, 0x01, 0x00, 0x00, 0x45, 0x00, 0x00, 0x00, 0x00, 0x0a,
        ];
        assert_eq!(parse(&fuzz), Err(GlbError::Version(0x4500_0001)));
        let mut short = glb(&[(b"JSON", b"{}  ")]);
        short[8] = 0;
        assert_eq!(
            parse(&short),
            Err(GlbError::Length {
                declared: 0,
                actual: 24
            })
        );
        let mut past = glb(&[(b"JSON", b"{}  "), (b"BIN\0", &[0; 12])]);
        past[24..28].copy_from_slice(&4000u32.to_le_bytes());
        assert_eq!(
            parse(&past),
            Err(GlbError::ChunkPastEnd {
                index: 1,
                ty: CHUNK_BIN,
                declared: 4000,
                remaining: 12
            })
        );
        assert_eq!(
            parse(&glb(&[(b"JSON", b"{} ")])),
            Err(GlbError::ChunkUnaligned {
                index: 0,
                ty: CHUNK_JSON,
                declared: 3
            })
        );
        assert_eq!(parse(&glb(&[])), Err(GlbError::NoChunks));
        assert_eq!(
            parse(&glb(&[(b"BIN\0", b"")])),
            Err(GlbError::FirstNotJson(CHUNK_BIN))
        );
        assert_eq!(
            parse(&glb(&[(b"JSON", b"{}  "), (b"JSON", b"{}  ")])),
            Err(GlbError::ExtraJson { index: 1 })
        );
        assert_eq!(
            parse(&glb(&[(b"JSON", b"{}  "), (b"XTRA", b""), (b"BIN\0", b"")])),
            Err(GlbError::MisplacedBin { index: 2 })
        );
        let mut stray = glb(&[(b"JSON", b"{}  ")]);
        stray.extend([0, 0, 0, 0]);
        stray[8] = 28;
        assert_eq!(
            parse(&stray),
            Err(GlbError::TruncatedChunkHeader {
                index: 1,
                remaining: 4
            })
        );
    }

    #[test]
    fn messages_name_the_problem() {
        let e = GlbError::ChunkPastEnd {
            index: 1,
            ty: CHUNK_BIN,
            declared: 4000,
            remaining: 12,
        };
        assert_eq!(
            e.to_string(),
            "GLB chunk 1 (BIN) declares 4000 bytes but only 12 remain"
        );
        assert_eq!(
            GlbError::Magic(*b"\x7fELF").to_string(),
            "the file starts with \"\\x7fELF\", not the GLB magic \"glTF\""
        );
    }

    /// Every prefix of a valid GLB, and every single-byte corruption of its header and chunk
    /// headers, is an error or a valid split, never a panic.
    #[test]
    fn truncations_and_corruptions_never_panic() {
        let bytes = glb(&[(b"JSON", b"{}  "), (b"BIN\0", &[7; 8])]);
        for n in 0..bytes.len() {
            assert!(parse(&bytes[..n]).is_err(), "prefix {n} accepted");
        }
        for at in 0..36 {
            for v in [0u8, 1, 3, 0x7f, 0xff] {
                let mut b = bytes.clone();
                b[at] = v;
                let _ = parse(&b);
            }
        }
    }
}
