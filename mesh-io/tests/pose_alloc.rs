//! `AnimatedMesh::pose` allocates nothing: a counting allocator over the posing of both
//! animated files of `assimp-testmodels` (skinned without normals, morphed with normals), after
//! the first pose. The only test of its binary, so no other test allocates meanwhile; only
//! the allocations of this test's thread are counted.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::DVec3;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

// SAFETY: every call is forwarded to the system allocator unchanged; the counter is only read.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn posing_allocates_nothing() {
    let Some(root) = smoothtri_testkit::assimp_models().unwrap() else {
        return;
    };
    for rel in [
        "glTF2/simple_skin/simple_skin.gltf",
        "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
    ] {
        let path = root.join(rel);
        let mut anim = smoothtri_io::load_animated(path.to_str().unwrap()).unwrap();
        let n = anim.mesh().positions.len();
        let (mut p, mut q) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        let d = anim.clips()[0].duration;
        anim.pose(0, 0.0, &mut p, &mut q).unwrap();
        ALLOCATIONS.store(0, Ordering::Relaxed);
        COUNTING.with(|c| c.set(true));
        for k in 0..200 {
            anim.pose(0, d * k as f64 / 199.0, &mut p, &mut q).unwrap();
        }
        anim.pose_rest(&mut p, &mut q).unwrap();
        COUNTING.with(|c| c.set(false));
        assert_eq!(ALLOCATIONS.load(Ordering::Relaxed), 0, "{rel}");
    }
}
