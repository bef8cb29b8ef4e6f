//! Fuzz target: the GLB container check of `smoothtri-io` (`smoothtri_io::glb::parse`) and the
//! glTF loader behind it, in memory. Any panic is a bug; an accepted container's chunks must be
//! slices of the input that follow the specification's layout.
#![no_main]

use smoothtri_io::{glb, gltf};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(g) = glb::parse(data) {
        assert!(data.starts_with(&glb::MAGIC) && data.len() >= glb::HEADER_LEN + 8);
        assert_eq!(g.json.len() % 4, 0, "unaligned JSON chunk accepted");
        assert!(
            g.bin.is_none_or(|b| b.len() % 4 == 0),
            "unaligned BIN chunk accepted"
        );
        let within = |s: &[u8]| {
            let (lo, hi) = (data.as_ptr() as usize, data.as_ptr() as usize + data.len());
            s.as_ptr() as usize >= lo && s.as_ptr() as usize + s.len() <= hi
        };
        assert!(within(g.json) && g.bin.is_none_or(within));
    }
    // External buffer URIs resolve against a directory that does not exist: I/O errors only.
    let _ = gltf::parse(data, "/nonexistent-smoothtri-fuzz/input.glb");
});
