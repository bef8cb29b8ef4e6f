//! The crafted hostile files of `crafted/` fail within a bounded peak allocation: a counting
//! global allocator tracks the bytes live at once while each is loaded.
//!
//! The bound, per file of `n` bytes: the loader holds the file (`n`), its parsed JSON document
//! or PLY header (serde's and the `gltf` crate's structures: well under 64 bytes per byte of
//! JSON for these small documents, whose every member is a short number or name), the buffers
//! it decodes from data URIs (`3n/4`), and fixed-size state (the PLY reader's line buffer,
//! hash maps' first allocations: under 1 MiB). So `64 n + 1 MiB`. Before the budget, the
//! sparse file alone asked for 96 GB.

mod crafted;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Peak;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

impl Peak {
    fn add(n: usize) {
        let now = LIVE.fetch_add(n, Ordering::Relaxed) + n;
        PEAK.fetch_max(now, Ordering::Relaxed);
    }
}

// SAFETY: every call is forwarded to the system allocator unchanged; the counters are only
// read.
unsafe impl GlobalAlloc for Peak {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is passed on unchanged.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            Peak::add(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            Peak::add(new_size);
        }
        p
    }
}

#[global_allocator]
static GLOBAL: Peak = Peak;

/// The peak of live bytes above the start while `f` runs. The only test of this binary, so
/// no other test allocates meanwhile.
fn peak_of(f: impl FnOnce()) -> usize {
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    f();
    PEAK.load(Ordering::Relaxed) - base
}

#[test]
fn crafted_files_fail_in_bounded_memory() {
    for (name, bytes, animated) in crafted::all() {
        let bound = 64 * bytes.len() + (1 << 20);
        let mut failed = false;
        let peak = peak_of(|| {
            failed = if animated {
                smoothtri_io::parse_animated(&bytes, name).is_err()
            } else {
                smoothtri_io::parse(&bytes, name).is_err()
            };
        });
        assert!(failed, "{name} loaded");
        assert!(
            peak <= bound,
            "{name}: peak {peak} bytes, over the bound {bound} ({} bytes of file)",
            bytes.len()
        );
    }
    // A budget holds a well-formed file's decoding: the triangle's sparse accessor of four
    // billion zeros, as POSITION, under a budget of 1 MiB, peaks within the budget plus the
    // bound above.
    let json = crafted::triangle_gltf(
        &crafted::embedded_buffer(),
        &crafted::sparse_viewless("VEC3"),
        "",
    )
    .replacen(r#""POSITION":0"#, r#""POSITION":1"#, 1)
    .replacen("4000000000", "1000000", 1)
    .replacen(
        r#""type":"VEC3","sparse""#,
        r#""type":"VEC3","min":[0,0,0],"max":[0,0,0],"sparse""#,
        1,
    );
    let options = smoothtri_io::LoadOptions::default().with_max_bytes(1 << 20);
    let mut err = None;
    let peak = peak_of(|| {
        err = smoothtri_io::parse_with(json.as_bytes(), "m.gltf", &options).err();
    });
    assert!(
        matches!(&err, Some(smoothtri_io::Error::Budget { .. })),
        "{err:?}"
    );
    let bound = (1 << 20) + 64 * json.len() + (1 << 20);
    assert!(peak <= bound, "peak {peak}, over {bound}");
}
