//! Freestanding `no_std`, `no_main` binary that calls **every public function and type** of the
//! core on opaque inputs, in `f32`, `f64` and `FastF32` (feature `micromath`), plus dual
//! numbers over them.
//!
//! Its panic handler calls `smoothtri_panic_path_survived`, a symbol defined nowhere: if any
//! panic path of the core survives optimisation, the handler is referenced and the link fails
//! with "undefined reference to `smoothtri_panic_path_survived`". A successful link proves the
//! called code cannot panic.
//!
//! Coverage is by construction: [`exercise`] is generic over the precision and is instantiated
//! for each; when a public item is added to the core, add its call here (the list at the top of
//! each function mirrors the core's modules).
#![no_std]
#![no_main]

use core::fmt::Write;
use core::hint::black_box;

use smoothtri::dual::Dual;
use smoothtri::sphere::{curvature, nearest_root};
use smoothtri::vec::V3;
use smoothtri::{
    Aabb, Bvh, BvhError, BvhNode, DEFAULT_SAMPLES, FastF32, Float, Hit, KernelStats, LineField,
    Patch, PatchError, Ray, Real, Seam, SharedEdge, MeshError, VertexClamp, clamp_vertex_normals,
    close_cracks, fit_seams, flat_hit, moller_trumbore,
};

unsafe extern "C" {
    fn smoothtri_panic_path_survived() -> !;
    fn exit(code: i32) -> !;
}

#[panic_handler]
fn on_panic(_: &core::panic::PanicInfo) -> ! {
    // SAFETY: never executed when the link succeeds; the symbol does not exist.
    unsafe { smoothtri_panic_path_survived() }
}

/// A fixed-size `fmt::Write` sink (the `Display` impls are public functions too).
struct Sink {
    buf: [u8; 128],
    len: usize,
}

impl Write for Sink {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for (slot, b) in self.buf.iter_mut().skip(self.len).zip(s.bytes()) {
            *slot = b;
        }
        self.len = (self.len + s.len()).min(self.buf.len());
        Ok(())
    }
}

fn display_len(x: &dyn core::fmt::Display) -> u32 {
    let mut sink = Sink {
        buf: [0; 128],
        len: 0,
    };
    let _ = write!(sink, "{x}");
    black_box(sink.buf);
    sink.len as u32
}

/// A world vector from `f64` components, opaque to the optimiser.
fn v<F: Float>(x: f64, y: f64, z: f64) -> F::Vec3 {
    black_box(F::to_glam(V3::new(
        F::from_f64(x),
        F::from_f64(y),
        F::from_f64(z),
    )))
}

fn c<F: Float>(x: f64) -> F {
    black_box(F::from_f64(x))
}

/// The scalar layer: `Real`, `Float`, `V3`, `Dual`, and the sphere functions on plain and dual
/// numbers.
fn scalars<F: Float>() -> u32 {
    let x = c::<F>(2.0);
    let y = c::<F>(-0.5);
    // Real (provided and required methods), on F and on nested duals over F.
    let r = x.sqrt0() + y.abs() + y.max0() + F::lit(0.25) + F::cst(x.re()) + F::zero() + F::one();
    let s = x.sign1() + y.sign1();
    let d = Dual::var(x) * Dual::constant(y) + Dual::var(y) / Dual::var(x) - Dual::constant(x);
    let mut dd = -d;
    dd += Dual::var(x);
    dd -= Dual::constant(y);
    dd *= Dual::var(y);
    let dd = dd.sqrt0() + dd.abs() + dd.max0();
    let nested: Dual<Dual<F>> = Dual::var(Dual::var(x)) * Dual::var(Dual::constant(y));
    let fin = r.all_finite() as u32
        + dd.all_finite() as u32
        + nested.sqrt0().all_finite() as u32
        + (d.sign1() > F::ZERO) as u32
        + (d == dd) as u32
        + (d < dd) as u32;
    // Float.
    let f = x.sqrt() + x.min(y) + x.max(y) + F::from_f64(F::EPSILON.to_f64()) - F::MIN_POSITIVE
        + F::MAX * F::ZERO
        + F::MIN * F::ZERO
        + F::ONE;
    let flags = f.is_fin() as u32 + f.is_nan() as u32;
    // V3.
    let a = V3::new(x, y, F::ONE);
    let b = V3::<F>::zero() + F::from_glam(v::<F>(0.3, 0.2, 0.1));
    let m = a
        .cross(b)
        .try_normalize()
        .unwrap_or(V3::new(F::ZERO, F::ZERO, F::ONE));
    let w = a.lerp(b, y) - m * x;
    let lifted: V3<Dual<F>> = V3::lift(w);
    let vv = (-lifted).re();
    let vec_ok = vv.all_finite() as u32 + (a.dot(b) + w.length() + w.length2() > F::ZERO) as u32;
    // Spheres, on F and on duals.
    let k = curvature(a, m, b);
    let root = nearest_root(b, a, w, m, k);
    let kd = curvature(lifted, V3::lift(m), V3::lift(b));
    let rd = nearest_root(V3::lift(b), lifted, V3::lift(a), V3::lift(m), kd);
    let sph = (k + root + s).is_fin() as u32 + rd.all_finite() as u32;
    fin + flags + vec_ok + sph
}

/// Everything above the scalar layer, in precision `F`.
/// Every method of the lane type of `F` (the kernel's eight-wide evaluation) and the work bound.
fn lanes<F: Float>() -> u32 {
    use smoothtri::lanes::{LANES, Lane, LaneOps};
    let a = F::L8::from_array(core::array::from_fn(|i| c::<F>(i as f64 - 3.5)));
    let b = black_box(F::L8::splat(c::<F>(0.5)));
    let x = ((a + b) * b - a / b).abs().sqrt() + (-a);
    let m = F::L8::and(a.lt(b), F::L8::not(a.eq(b)));
    let m = F::L8::or(m, F::L8::and(a.le(b), a.gt(b)));
    let m = F::L8::and(m, x.finite());
    let y = F::L8::select(m, x, b).to_array();
    let mut acc = F::L8::any(m) as u32 + F::L8::mask_array(m).iter().filter(|&&q| q).count() as u32;
    acc += y.iter().filter(|q| q.is_fin()).count() as u32;
    acc += (smoothtri::kernel::max_lane_calls(black_box(DEFAULT_SAMPLES), black_box(8)) + LANES)
        as u32;
    acc
}

fn exercise<F: Float>() -> u32 {
    let mut acc = scalars::<F>();
    let p = [
        v::<F>(1.0, 0.0, 0.0),
        v::<F>(0.0, 1.0, 0.0),
        v::<F>(0.0, 0.0, 1.0),
    ];
    let n = black_box(p);
    // Construction: both constructors and every error's Display.
    let steep = [v::<F>(1.0, 0.0, -0.2), n[1], n[2]];
    for r in [
        Patch::<F>::new(p, n),
        Patch::<F>::new(p, steep),
        Patch::<F>::new_or_tilted(p, steep),
    ] {
        match r {
            Ok(patch) => acc += patch.normal_clamp().is_some() as u32,
            Err(e) => acc += display_len(&e),
        }
    }
    acc += display_len(&black_box(PatchError::ZeroNormal { vertex: 1 }));
    // The shared line field: a patch with tilted sections (normals at unequal angles to the
    // face), its evaluation and its kernel (the section's Newton steps, the ruled walls).
    let uneven = [v::<F>(0.3, 0.3, 0.9), n[1], n[2]];
    for field in [LineField::Face, black_box(LineField::Vertex)] {
        for r in [
            Patch::<F>::with_field(p, uneven, field),
            Patch::<F>::new_or_tilted_with(p, steep, field),
        ] {
            if let Ok(q) = r {
                let ray = Ray::<F>::new(v::<F>(2.0, 2.0, 2.0), v::<F>(-1.0, -1.0, -1.0));
                let h = q.intersect::<4>(&ray, c::<F>(0.0), c::<F>(f64::INFINITY));
                acc += h.map_or(0, |h| h.t.is_fin() as u32);
                acc += F::from_glam(q.point(c::<F>(0.1), c::<F>(0.7))).all_finite() as u32;
            }
        }
    }
    let Ok(patch) = Patch::<F>::new_or_tilted(p, n) else {
        return acc;
    };
    // Evaluation.
    let (w1, w2) = (c::<F>(0.2), c::<F>(0.3));
    let x = patch.point(w1, w2);
    let h = patch.height(w1, w2);
    let (xn, nn) = patch.point_normal(w1, w2);
    let (d1, d2) = patch.derivatives(w1, w2);
    let (ce, cn) = patch.edge_point_normal(black_box(4), w1);
    let [v0, _, _] = patch.vertices();
    let [n0, _, _] = patch.normals();
    let nf = patch.face_normal();
    let (lo, hi) = patch.height_range();
    acc += patch.roots_certified() as u32;
    let vs = [x, xn, nn, d1, d2, ce, cn, v0, n0, nf];
    acc += vs.iter().filter(|q| F::from_glam(**q).all_finite()).count() as u32;
    acc += (h + lo + hi).is_fin() as u32;
    // Boxes.
    let b = patch.bounds();
    let u = b.union(&Aabb::new(b.min(), b.max())).union(&Aabb::EMPTY);
    let e = Aabb::<F>::default();
    acc += F::from_glam(u.max()).all_finite() as u32 + (e == Aabb::EMPTY) as u32;
    let data = patch.data();
    acc += (data.sigma[1].is_fin() && data == black_box(patch).data()) as u32;
    // Rays and the per-patch kernels.
    let ray = Ray::<F>::new(v::<F>(2.0, 2.0, 2.0), v::<F>(-1.0, -1.0, -1.0));
    let at = ray.at(c::<F>(0.5));
    acc += F::from_glam(at).all_finite() as u32;
    let (t0, t1) = (c::<F>(0.0), c::<F>(f64::INFINITY));
    let hit: Option<Hit<F>> = patch.intersect::<8>(&ray, t0, t1);
    let (hit2, stats): (_, KernelStats) = patch.intersect_stats::<DEFAULT_SAMPLES, 5>(&ray, t0, t1);
    let (hit3, _) = patch.intersect_stats::<0, 0>(&ray, t0, t1);
    let verts = patch.vertices();
    let mt = moller_trumbore(&verts, &ray, t0, t1);
    let flat = flat_hit(&verts, None, &ray, t0, t1);
    let phong = flat_hit(&verts, Some(&patch.normals()), &ray, t0, t1);
    acc += hit.map_or(0, |h| {
        h.patch + h.front_face as u32 + h.t_error.is_fin() as u32
    });
    acc += hit2.is_some() as u32 + hit3.is_some() as u32 + mt.is_some() as u32;
    acc += flat.is_some() as u32 + phong.is_some() as u32;
    acc += stats.height_evals + stats.normal_evals;
    // BVH over a few copies, in caller-provided storage, every query.
    const COUNT: usize = 8;
    let patches = [patch; COUNT];
    let mut nodes = [BvhNode::<F>::default(); 2 * COUNT - 1];
    let mut order = [0u32; COUNT];
    match Bvh::build(black_box(&patches), &mut nodes, &mut order) {
        Ok(bvh) => {
            acc += bvh.node_count() as u32 + bvh.memory_bytes() as u32;
            acc += bvh.patches().len() as u32;
            let root = bvh.nodes().first().copied().unwrap_or_default();
            acc += root.first() + root.count() + bvh.order().len() as u32;
            acc += F::from_glam(root.bounds().min()).all_finite() as u32;
            if let Ok(Some(h)) = bvh.closest_hit::<8>(&ray, t0, t1) {
                acc += h.patch;
            }
            let rays = [ray; smoothtri::lanes::LANES];
            if let Ok(hs) = bvh.closest_hit_packet::<4>(black_box(&rays), t0, t1) {
                acc += hs.iter().flatten().count() as u32;
            }
            if let Ok(true) = bvh.any_hit::<4>(&ray, t0, t1) {
                acc += 1;
            }
            let with = bvh.closest_with(&ray, t0, t1, |p, a, b| {
                flat_hit(&p.vertices(), Some(&p.normals()), &ray, a, b)
            });
            if let Err(e) = with {
                acc += display_len(&e);
            }
        }
        Err(e) => acc += display_len(&e),
    }
    // Storage not made by `build`: typed errors, never a panic.
    let junk = [BvhNode::<F>::default(); 3];
    let raw = Bvh::from_parts(black_box(&patches), black_box(&junk), black_box(&order));
    if let Err(e) = raw.closest_hit::<2>(&ray, t0, t1) {
        acc += display_len(&e);
    }
    let mut few = [BvhNode::<F>::default(); 1];
    if let Err(e) = Bvh::build(black_box(&patches), &mut few, &mut order) {
        acc += display_len(&e);
    }
    acc += display_len(&black_box(BvhError::Internal));
    acc += seams(&patches, &ray);
    acc
}

/// Seamless shading normals: the fit over an opaque index buffer (shared, boundary and
/// non-manifold edges, and every error), both normal functions, with fitted and opaque
/// coefficients.
fn seams<F: Float>(patches: &[Patch<F>], ray: &Ray<F>) -> u32 {
    const COUNT: usize = 8;
    let mut acc = 0;
    let tris: [[u32; 3]; COUNT] = black_box([
        [0, 1, 2],
        [2, 1, 3],
        [1, 2, 4],
        [3, 4, 5],
        [5, 4, 3],
        [0, 2, 5],
        [6, 7, 8],
        [8, 7, 6],
    ]);
    let mut scratch = [SharedEdge::default(); 3 * COUNT];
    let mut out = [Seam::<F>::default(); COUNT];
    let Some(ps) = patches.get(..COUNT) else {
        return acc;
    };
    match fit_seams(ps, &tris, black_box(9), &mut scratch, &mut out) {
        Ok(n) => acc += n as u32,
        Err(e) => acc += display_len(&e),
    }
    for bad in [
        fit_seams(ps, &tris, black_box(3), &mut scratch, &mut out),
        fit_seams(ps, &tris, 9, &mut scratch[..5], &mut out),
        fit_seams(ps, &tris[..2], 9, &mut scratch, &mut out),
    ] {
        if let Err(e) = bad {
            acc += display_len(&e);
        }
    }
    acc += display_len(&black_box(MeshError::TooManyTriangles));
    // Crack closing on a copy (it widens the patches' walls and boxes), and its errors.
    let mut sealed = [ps[0]; COUNT];
    sealed.copy_from_slice(ps);
    match close_cracks(&mut sealed, &tris, black_box(9), &mut scratch) {
        Ok(r) => {
            acc += r.shared_edges as u32 + r.open_edges as u32 + (r.widest_gap > 0.0) as u32;
            if let Some(h) = sealed[1].intersect::<4>(ray, c::<F>(0.0), c::<F>(f64::INFINITY)) {
                acc += h.t.is_fin() as u32;
            }
            acc += sealed[2].data().reach.iter().filter(|r| r.is_fin()).count() as u32;
        }
        Err(e) => acc += display_len(&e),
    }
    for bad in [
        close_cracks(&mut sealed, &tris, black_box(3), &mut scratch),
        close_cracks(&mut sealed, &tris, 9, &mut scratch[..5]),
        close_cracks(&mut sealed, &tris[..2], 9, &mut scratch),
    ] {
        if let Err(e) = bad {
            acc += display_len(&e);
        }
    }
    let mut wild = black_box(out[0]);
    wild.common[1][3] = c::<F>(f64::NAN);
    wild.common_along[0][5] = c::<F>(-1e30);
    wild.own[2][0] = c::<F>(1e30);
    let (w1, w2) = (c::<F>(0.25), c::<F>(0.5));
    for (seam, patch) in out.iter().chain([&wild]).zip(ps.iter().cycle()) {
        let n = seam.shading_normal(patch, w1, w2);
        let g = patch.point_normal(w1, w2).1;
        let m = seam.correct(patch, w1, w2, g);
        acc += F::from_glam(n).all_finite() as u32 + F::from_glam(m).all_finite() as u32;
        acc += seam.is_zero() as u32 + (seam == &wild) as u32;
    }
    if let Some(p) = ps.first() {
        if let Some(h) = p.intersect::<4>(ray, c::<F>(0.0), c::<F>(f64::INFINITY)) {
            let n = wild.correct(p, h.w1, h.w2, h.normal);
            acc += F::from_glam(n).all_finite() as u32;
        }
    }
    acc
}

/// The remedy per vertex: a square pyramid whose apex normal is steep for every face, its
/// report, and its three error paths.
fn vertex_clamps<F: Float>() -> u32 {
    let pos = [
        v::<F>(0.0, 0.0, 0.0),
        v::<F>(1.0, 0.0, 0.0),
        v::<F>(1.0, 1.0, 0.0),
        v::<F>(0.0, 1.0, 0.0),
        v::<F>(0.5, 0.5, 0.2),
    ];
    let nrm = [
        v::<F>(-1.0, -1.0, 1.0),
        v::<F>(1.0, -1.0, 1.0),
        v::<F>(1.0, 1.0, 1.0),
        v::<F>(-1.0, 1.0, 1.0),
        black_box(v::<F>(1.0, 0.0, 0.05)),
    ];
    let tris = [[0u32, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    let mut out = nrm;
    let mut scratch = [VertexClamp::<F>::default(); 5];
    let mut acc = 0;
    match clamp_vertex_normals(&pos, &nrm, &tris, &mut out, &mut scratch) {
        Ok(r) => {
            acc += (r.clamped + r.unresolved) as u32 + F::from_glam(out[4]).all_finite() as u32
        }
        Err(e) => acc += display_len(&e),
    }
    for r in [
        clamp_vertex_normals(&pos, &nrm, &[[0, 1, 9]], &mut out, &mut scratch),
        clamp_vertex_normals(&pos, &nrm, &tris, &mut out, &mut scratch[..2]),
        clamp_vertex_normals(&pos, &nrm[..2], &tris, &mut out, &mut scratch),
    ] {
        if let Err(e) = r {
            acc += display_len(&e);
        }
    }
    acc
}

/// Entry point: aligns the stack as the C ABI expects, then calls [`main`].
#[cfg(target_arch = "x86_64")]
#[unsafe(naked)]
#[unsafe(no_mangle)]
pub extern "C" fn _start() -> ! {
    core::arch::naked_asm!("xor ebp, ebp", "and rsp, -16", "call {main}", "ud2", main = sym main)
}

extern "C" fn main() -> ! {
    let r = exercise::<f32>() + exercise::<f64>() + exercise::<FastF32>();
    let r = r + lanes::<f32>() + lanes::<f64>() + lanes::<FastF32>();
    let r = r + vertex_clamps::<f32>() + vertex_clamps::<f64>() + vertex_clamps::<FastF32>();
    // SAFETY: libc's exit, linked from the C library (only the start files are left out).
    unsafe { exit(if black_box(r) >= 3 { 0 } else { 1 }) }
}
