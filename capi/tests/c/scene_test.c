/*
 * What a C renderer does with smoothtri.h: builds a torus and a sphere from interleaved vertex
 * buffers (position, normal, uv) into memory it allocates, traces rays with st_intersect1,
 * st_occluded1, st_intersect8, st_intersect1M and st_patch_intersect over st_patch_bounds, in
 * float and in double, and checks the hits it can check alone (spheres are exact, t_error is
 * certified, every entry point agrees with st_intersect1). It prints every mesh, ray and hit
 * as bit patterns so that tests/c_api.rs compares each hit with the Rust API's.
 *
 * Usage: scene_test FLAGS ITERATIONS RAYS   (FLAGS: 0, 1 = ST_BUILD_SEAMS, 2, 3; RAYS a
 * multiple of 8)
 */
#include "smoothtri.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_common.h"

/* An interleaved vertex: position, normal, texture coordinates (32 bytes in float). */
typedef struct { float p[3], n[3], uv[2]; } vertex_f;
typedef struct { double p[3], n[3], uv[2]; } vertex_d;

typedef struct {
    size_t vertex_count, triangle_count;
    vertex_d *v;
    uint32_t *idx;
} mesh;

static mesh torus(unsigned nu, unsigned nv, double big_r, double r) {
    mesh m;
    unsigned i, j;
    m.vertex_count = (size_t)nu * nv;
    m.triangle_count = 2 * (size_t)nu * nv;
    m.v = (vertex_d *)calloc(m.vertex_count, sizeof(vertex_d));
    m.idx = (uint32_t *)calloc(3 * m.triangle_count, sizeof(uint32_t));
    for (i = 0; i < nu; i++) {
        for (j = 0; j < nv; j++) {
            double u = 2 * PI * i / nu, w = 2 * PI * j / nv;
            vertex_d *x = &m.v[i * nv + j];
            x->n[0] = cos(w) * cos(u);
            x->n[1] = cos(w) * sin(u);
            x->n[2] = sin(w);
            x->p[0] = (big_r + r * cos(w)) * cos(u);
            x->p[1] = (big_r + r * cos(w)) * sin(u);
            x->p[2] = r * sin(w);
            x->uv[0] = (double)i / nu;
            x->uv[1] = (double)j / nv;
        }
    }
    for (i = 0; i < nu; i++) {
        for (j = 0; j < nv; j++) {
            uint32_t a = i * nv + j, b = ((i + 1) % nu) * nv + j;
            uint32_t c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
            uint32_t *t = &m.idx[6 * (i * nv + j)];
            t[0] = a; t[1] = b; t[2] = c;
            t[3] = a; t[4] = c; t[5] = d;
        }
    }
    return m;
}

/* The unit sphere of test_common.h, radial normals: its patches are the sphere exactly. */
static mesh sphere(unsigned rings, unsigned segments) {
    mesh m;
    double *points;
    size_t i;
    unit_sphere(rings, segments, &m.vertex_count, &m.triangle_count, &points, &m.idx);
    m.v = (vertex_d *)calloc(m.vertex_count, sizeof(vertex_d));
    for (i = 0; i < m.vertex_count; i++) {
        memcpy(m.v[i].p, &points[3 * i], sizeof m.v[i].p);
        memcpy(m.v[i].n, &points[3 * i], sizeof m.v[i].n);
    }
    free(points);
    return m;
}

/* Whether two hits are the same, field by field (bit for bit; padding is not compared). */
static int same_hit(const st_rayhit *a, const st_rayhit *b) {
    const st_hit *x = &a->hit, *y = &b->hit;
    return memcmp(&a->ray.tfar, &b->ray.tfar, 4) == 0 && x->prim_id == y->prim_id &&
           x->geom_id == y->geom_id && memcmp(&x->ng_x, &y->ng_x, 5 * sizeof(float)) == 0 &&
           memcmp(&x->ns_x, &y->ns_x, 4 * sizeof(float)) == 0;
}

static unsigned bits_f(float x) { uint32_t u; memcpy(&u, &x, 4); return u; }
static unsigned long long bits_d(double x) { uint64_t u; memcpy(&u, &x, 8); return (unsigned long long)u; }

/* Deterministic rays toward the mesh: origins on a sphere of radius 4, aimed at points near
 * the centre, so most hit and some miss. */
static void ray_k(unsigned k, unsigned count, double o[3], double d[3]) {
    double a = 2 * PI * k / count * 7.0, b = acos(1 - 2 * (k + 0.5) / count);
    double tx = 0.9 * sin(1.7 * k), ty = 0.9 * cos(2.3 * k), tz = 0.3 * sin(0.7 * k);
    o[0] = 4 * sin(b) * cos(a);
    o[1] = 4 * sin(b) * sin(a);
    o[2] = 4 * cos(b);
    d[0] = tx - o[0];
    d[1] = ty - o[1];
    d[2] = tz - o[2];
}

static unsigned RAYS = 192;

static void print_mesh(const char *name, const mesh *m) {
    size_t i;
    printf("mesh %s %zu %zu\n", name, m->vertex_count, m->triangle_count);
    for (i = 0; i < m->vertex_count; i++) {
        const vertex_d *x = &m->v[i];
        printf("v %016llx %016llx %016llx %016llx %016llx %016llx\n", bits_d(x->p[0]),
               bits_d(x->p[1]), bits_d(x->p[2]), bits_d(x->n[0]), bits_d(x->n[1]),
               bits_d(x->n[2]));
    }
    for (i = 0; i < m->triangle_count; i++)
        printf("f %u %u %u\n", m->idx[3 * i], m->idx[3 * i + 1], m->idx[3 * i + 2]);
}

/* Single precision: build from the interleaved float buffer, trace every entry point. */
static void trace_f32(const char *name, const mesh *m, uint32_t flags, uint32_t iterations,
                      int exact_sphere) {
    vertex_f *vb = (vertex_f *)calloc(m->vertex_count, sizeof(vertex_f));
    size_t i, bytes = 0;
    unsigned k, lane, prim;
    void *memory;
    st_scene *scene = NULL;
    st_scene_info info;
    st_rayhit *stream;
    for (i = 0; i < m->vertex_count; i++) {
        for (k = 0; k < 3; k++) {
            vb[i].p[k] = (float)m->v[i].p[k];
            vb[i].n[k] = (float)m->v[i].n[k];
        }
        vb[i].uv[0] = (float)m->v[i].uv[0];
        vb[i].uv[1] = (float)m->v[i].uv[1];
    }
    CHECK(st_scene_required_bytes(m->vertex_count, m->triangle_count, flags, &bytes) == ST_OK);
    memory = malloc(bytes);
    CHECK(st_scene_build(memory, bytes, vb[0].p, sizeof(vertex_f), vb[0].n, sizeof(vertex_f),
                         m->vertex_count, m->idx, m->triangle_count, flags, iterations,
                         &scene) == ST_OK);
    CHECK(scene != NULL);
    CHECK(st_scene_get_info(scene, &info) == ST_OK);
    CHECK(info.triangle_count == m->triangle_count);
    CHECK(info.patch_count + info.rejected_count == m->triangle_count);
    CHECK(info.bytes_used > 0 && info.bytes_used <= bytes);
    CHECK(info.iterations == iterations && info.flags == flags);
    CHECK(((flags & ST_BUILD_SEAMS) != 0) == (info.seam_edge_count > 0));
    /* The vertex buffer is no longer needed: the scene copied what it keeps. */
    memset(vb, 0xff, m->vertex_count * sizeof(vertex_f));
    free(vb);
    printf("build %s f32 %zu %zu %zu %zu\n", name, info.patch_count, info.rejected_count,
           info.remedied_count, info.seam_edge_count);

    stream = (st_rayhit *)calloc(RAYS, sizeof(st_rayhit));
    for (k = 0; k < RAYS; k++) {
        double o[3], d[3];
        st_rayhit rh;
        st_ray shadow;
        ray_k(k, RAYS, o, d);
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = (float)o[0]; rh.ray.org_y = (float)o[1]; rh.ray.org_z = (float)o[2];
        rh.ray.dir_x = (float)d[0]; rh.ray.dir_y = (float)d[1]; rh.ray.dir_z = (float)d[2];
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = INFINITY;
        rh.ray.mask = 0xffffffffu;
        rh.hit.geom_id = ST_INVALID_ID;
        rh.hit.prim_id = ST_INVALID_ID;
        stream[k] = rh;
        shadow = rh.ray;
        st_intersect1(scene, &rh);
        printf("r %08x %08x %08x %08x %08x %08x\n", bits_f(rh.ray.org_x), bits_f(rh.ray.org_y),
               bits_f(rh.ray.org_z), bits_f(rh.ray.dir_x), bits_f(rh.ray.dir_y),
               bits_f(rh.ray.dir_z));
        if (rh.hit.prim_id == ST_INVALID_ID) {
            printf("miss\n");
            CHECK(rh.hit.geom_id == ST_INVALID_ID && isinf(rh.ray.tfar));
        } else {
            float px = rh.ray.org_x + rh.ray.tfar * rh.ray.dir_x;
            float py = rh.ray.org_y + rh.ray.tfar * rh.ray.dir_y;
            float pz = rh.ray.org_z + rh.ray.tfar * rh.ray.dir_z;
            float nn = rh.hit.ns_x * rh.hit.ns_x + rh.hit.ns_y * rh.hit.ns_y + rh.hit.ns_z * rh.hit.ns_z;
            printf("hit %u %08x %08x %08x %08x %08x %08x %08x %08x %08x %08x\n", rh.hit.prim_id,
                   bits_f(rh.ray.tfar), bits_f(rh.hit.u), bits_f(rh.hit.v), bits_f(rh.hit.ng_x),
                   bits_f(rh.hit.ng_y), bits_f(rh.hit.ng_z), bits_f(rh.hit.ns_x),
                   bits_f(rh.hit.ns_y), bits_f(rh.hit.ns_z), bits_f(rh.hit.t_error));
            CHECK(rh.hit.geom_id == 0 && rh.hit.prim_id < m->triangle_count);
            CHECK(rh.hit.u >= -1e-4f && rh.hit.v >= -1e-4f && rh.hit.u + rh.hit.v <= 1.0001f);
            CHECK(rh.hit.t_error >= 0.0f);
            CHECK(fabsf(nn - 1.0f) < 1e-5f);
            /* From N = 8 the hits are at rounding (N = 0 only brackets). */
            if (iterations >= 8) CHECK(rh.hit.t_error < 1e-3f);
            if (exact_sphere && iterations >= 8) {
                /* Radial normals: the patches are the unit sphere. */
                CHECK(fabsf(sqrtf(px * px + py * py + pz * pz) - 1.0f) < 2e-6f);
                CHECK(rh.hit.ns_x * px + rh.hit.ns_y * py + rh.hit.ns_z * pz > 0.99999f);
            }
        }
        /* Shadow ray over the same interval: occluded exactly when there is a hit. */
        st_occluded1(scene, &shadow);
        CHECK((shadow.tfar == -INFINITY) == (rh.hit.prim_id != ST_INVALID_ID));

        /* The user's own traversal (every 4th ray): every patch in turn, keeping the closest
         * hit, as a BVH of the user's over st_patch_bounds would. */
        if (k % 4 == 0) {
            st_rayhit own = stream[k];
            float b[6];
            for (prim = 0; prim < info.patch_count; prim++) {
                CHECK(st_patch_bounds(scene, (uint32_t)prim, b) == ST_OK);
                CHECK(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5]);
                (void)st_patch_intersect(scene, (uint32_t)prim, &own);
            }
            CHECK(own.hit.prim_id == rh.hit.prim_id);
            CHECK(st_patch_bounds(scene, (uint32_t)info.patch_count, b) == ST_ERROR_INDEX_OUT_OF_RANGE);
            if (rh.hit.prim_id != ST_INVALID_ID) {
                float px = own.ray.org_x + own.ray.tfar * own.ray.dir_x;
                float py = own.ray.org_y + own.ray.tfar * own.ray.dir_y;
                float pz = own.ray.org_z + own.ray.tfar * own.ray.dir_z;
                CHECK(same_hit(&own, &rh));
                /* No triangle is rejected here, so patch = triangle: the hit lies in its box. */
                CHECK(info.rejected_count == 0);
                CHECK(st_patch_bounds(scene, rh.hit.prim_id, b) == ST_OK);
                CHECK(px >= b[0] - 1e-5f && py >= b[1] - 1e-5f && pz >= b[2] - 1e-5f);
                CHECK(px <= b[3] + 1e-5f && py <= b[4] + 1e-5f && pz <= b[5] + 1e-5f);
            }
        }
    }
    /* Eight at a time (SoA; every other lane of the last packet inactive) and as a stream: the
     * same bits as one at a time. */
    for (k = 0; k < RAYS; k += 8) {
        st_rayhit8 p8;
        int32_t valid[8];
        memset(&p8, 0, sizeof p8);
        for (lane = 0; lane < 8; lane++) {
            const st_rayhit *r = &stream[k + lane];
            valid[lane] = (k + 8 < RAYS || lane % 2 == 0) ? -1 : 0;
            p8.ray.org_x[lane] = r->ray.org_x; p8.ray.org_y[lane] = r->ray.org_y;
            p8.ray.org_z[lane] = r->ray.org_z; p8.ray.dir_x[lane] = r->ray.dir_x;
            p8.ray.dir_y[lane] = r->ray.dir_y; p8.ray.dir_z[lane] = r->ray.dir_z;
            p8.ray.tnear[lane] = 0.0f; p8.ray.tfar[lane] = INFINITY;
            p8.hit.geom_id[lane] = ST_INVALID_ID;
            p8.hit.prim_id[lane] = 12345;
        }
        st_intersect8(valid, scene, &p8);
        for (lane = 0; lane < 8; lane++) {
            st_rayhit one = stream[k + lane];
            st_intersect1(scene, &one);
            if (!valid[lane]) {
                CHECK(p8.hit.prim_id[lane] == 12345 && isinf(p8.ray.tfar[lane]));
                continue;
            }
            CHECK(p8.hit.prim_id[lane] == one.hit.prim_id);
            CHECK(p8.ray.tfar[lane] == one.ray.tfar);
            if (one.hit.prim_id != ST_INVALID_ID) {
                CHECK(p8.hit.u[lane] == one.hit.u && p8.hit.v[lane] == one.hit.v);
                CHECK(p8.hit.ns_x[lane] == one.hit.ns_x && p8.hit.ng_z[lane] == one.hit.ng_z);
                CHECK(p8.hit.t_error[lane] == one.hit.t_error);
            }
        }
    }
    {
        /* A stream with a stride of two ray-hits: every other slot is traced. */
        st_rayhit *wide = (st_rayhit *)calloc(2 * RAYS, sizeof(st_rayhit));
        for (k = 0; k < RAYS; k++) {
            wide[2 * k] = stream[k];
            wide[2 * k + 1] = stream[k];
        }
        st_intersect1M(scene, wide, RAYS, 2 * sizeof(st_rayhit));
        for (k = 0; k < RAYS; k++) {
            st_rayhit one = stream[k];
            st_intersect1(scene, &one);
            CHECK(same_hit(&wide[2 * k], &one));
            CHECK(same_hit(&wide[2 * k + 1], &stream[k]));
        }
        free(wide);
    }
    free(stream);
    free(memory);
}

/* Double precision: the same mesh from the double buffer. */
static void trace_f64(const char *name, const mesh *m, uint32_t flags, uint32_t iterations,
                      int exact_sphere) {
    size_t bytes = 0;
    unsigned k;
    void *memory;
    st_scene_f64 *scene = NULL;
    st_scene_info info;
    CHECK(st_scene_required_bytes_f64(m->vertex_count, m->triangle_count, flags, &bytes) == ST_OK);
    memory = malloc(bytes);
    CHECK(st_scene_build_f64(memory, bytes, m->v[0].p, sizeof(vertex_d), m->v[0].n,
                             sizeof(vertex_d), m->vertex_count, m->idx, m->triangle_count,
                             flags, iterations, &scene) == ST_OK);
    CHECK(st_scene_get_info_f64(scene, &info) == ST_OK);
    /* A double scene is not a float scene. */
    CHECK(st_scene_get_info((const st_scene *)(const void *)scene, &info) == ST_ERROR_WRONG_SCENE);
    printf("build %s f64 %zu %zu %zu %zu\n", name, info.patch_count, info.rejected_count,
           info.remedied_count, info.seam_edge_count);
    for (k = 0; k < RAYS; k++) {
        double o[3], d[3];
        st_rayhit_f64 rh;
        ray_k(k, RAYS, o, d);
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = o[0]; rh.ray.org_y = o[1]; rh.ray.org_z = o[2];
        rh.ray.dir_x = d[0]; rh.ray.dir_y = d[1]; rh.ray.dir_z = d[2];
        rh.ray.tfar = INFINITY;
        st_intersect1_f64(scene, &rh);
        printf("r %016llx %016llx %016llx %016llx %016llx %016llx\n", bits_d(o[0]), bits_d(o[1]),
               bits_d(o[2]), bits_d(d[0]), bits_d(d[1]), bits_d(d[2]));
        if (rh.hit.prim_id == ST_INVALID_ID) {
            printf("miss\n");
        } else {
            double px = o[0] + rh.ray.tfar * d[0], py = o[1] + rh.ray.tfar * d[1],
                   pz = o[2] + rh.ray.tfar * d[2];
            printf("hit %u %016llx %016llx %016llx %016llx %016llx %016llx %016llx %016llx "
                   "%016llx %016llx\n",
                   rh.hit.prim_id, bits_d(rh.ray.tfar), bits_d(rh.hit.u), bits_d(rh.hit.v),
                   bits_d(rh.hit.ng_x), bits_d(rh.hit.ng_y), bits_d(rh.hit.ng_z),
                   bits_d(rh.hit.ns_x), bits_d(rh.hit.ns_y), bits_d(rh.hit.ns_z),
                   bits_d(rh.hit.t_error));
            CHECK(rh.hit.t_error >= 0.0);
            if (iterations >= 8) CHECK(rh.hit.t_error < 1e-6);
            if (exact_sphere && iterations >= 8)
                CHECK(fabs(sqrt(px * px + py * py + pz * pz) - 1.0) < 1e-12);
        }
    }
    free(memory);
}

int main(int argc, char **argv) {
    uint32_t flags = argc > 1 ? (uint32_t)atoi(argv[1]) : 0;
    uint32_t iterations = argc > 2 ? (uint32_t)atoi(argv[2]) : 8;
    if (argc > 3) RAYS = (unsigned)atoi(argv[3]);
    mesh t = torus(8, 8, 1.0, 0.4), s = sphere(6, 8);
    print_mesh("torus", &t);
    trace_f32("torus", &t, flags, iterations, 0);
    trace_f64("torus", &t, flags, iterations, 0);
    print_mesh("sphere", &s);
    trace_f32("sphere", &s, flags, iterations, 1);
    trace_f64("sphere", &s, flags, iterations, 1);
    free(t.v); free(t.idx); free(s.v); free(s.idx);
    /* Nothing more on stdout: tests/c_api.rs reads every line of it. */
    return check_exit_status(NULL);
}
