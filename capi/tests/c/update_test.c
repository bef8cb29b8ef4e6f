/*
 * What a C renderer with an animated mesh does with smoothtri.h: builds an updatable scene
 * (ST_BUILD_UPDATABLE) once, then moves its vertices every frame with st_scene_update, in
 * float and in double, and checks each frame alone:
 *   - the mesh is a unit sphere's, moved each frame by a scale and a translation, so every hit
 *     lies on the frame's analytic sphere within its t_error;
 *   - every hit equals that of a fresh st_scene_build of the same vertices within t_error (bit
 *     for bit when the update built the tree anew);
 *   - a frame that collapses every vertex to one point succeeds with a scene that every ray
 *     misses, and the next frame hits again;
 *   - bad updates (NULL, a fixed scene, another vertex count, a NaN, a bad stride) return their
 *     status and leave the scene as it was: the same hits bit for bit.
 * Prints "all checks passed" when every check held.
 */
#include "smoothtri.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_common.h"

#define RINGS 12
#define SEGMENTS 24
#define RAYS 64
#define FRAMES 12
/* The rounding of the rays and vertices, relative to t, beyond a hit's certified t_error. */
#define F32_ROUNDING 1e-5
#define F64_ROUNDING 1e-12

typedef struct { float p[3], n[3]; } vertex_f;
typedef struct { double p[3], n[3]; } vertex_d;

static size_t vertex_count, triangle_count;
static double *rest; /* the unit sphere's points (test_common.h), also its normals */
static uint32_t *idx;

/* Frame f's sphere: radius and centre (frame -1: every vertex at one point). */
static void frame_sphere(int f, double *radius, double c[3]) {
    if (f < 0) {
        *radius = 0;
    } else {
        *radius = 0.5 + 0.1 * f;
    }
    c[0] = 0.3 * sin(0.7 * f);
    c[1] = 0.2 * cos(1.3 * f);
    c[2] = 0.1 * f - 0.5;
}

static void pose_d(int f, vertex_d *out) {
    double r, c[3];
    size_t i;
    unsigned k;
    frame_sphere(f, &r, c);
    for (i = 0; i < vertex_count; i++) {
        for (k = 0; k < 3; k++) {
            out[i].p[k] = c[k] + r * rest[3 * i + k];
            out[i].n[k] = rest[3 * i + k];
        }
    }
}

static void pose_f(int f, vertex_f *out, vertex_d *scratch) {
    size_t i;
    unsigned k;
    pose_d(f, scratch);
    for (i = 0; i < vertex_count; i++) {
        for (k = 0; k < 3; k++) {
            out[i].p[k] = (float)scratch[i].p[k];
            out[i].n[k] = (float)scratch[i].n[k];
        }
    }
}

/* Ray k toward frame f's sphere: from a point at distance 5 from its centre, aimed near it. */
static void ray_k(int f, unsigned k, double o[3], double d[3]) {
    double r, c[3];
    double a = 2 * PI * k / RAYS * 5.0, b = acos(1 - 2 * (k + 0.5) / RAYS);
    frame_sphere(f < 0 ? 0 : f, &r, c);
    o[0] = c[0] + 5 * sin(b) * cos(a);
    o[1] = c[1] + 5 * sin(b) * sin(a);
    o[2] = c[2] + 5 * cos(b);
    d[0] = c[0] + 0.4 * sin(1.7 * k) - o[0];
    d[1] = c[1] + 0.4 * cos(2.3 * k) - o[1];
    d[2] = c[2] + 0.2 * sin(0.7 * k) - o[2];
}

/* The ray's first crossing with the sphere (radius r, centre c), or -1. */
static double sphere_t(const double o[3], const double d[3], double r, const double c[3]) {
    double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
    double disc = b * b - a * cc;
    if (disc < 0) return -1;
    return (-b - sqrt(disc)) / a;
}

/* A hit as the checks read it, in double (exact for a float hit); `hit` 0 on a miss. */
typedef struct {
    int hit;
    uint32_t prim_id;
    double t, t_error;
} seen;

static seen seen_of(uint32_t geom_id, uint32_t prim_id, double t, double t_error) {
    seen x;
    x.hit = geom_id != ST_INVALID_ID;
    x.prim_id = prim_id;
    x.t = t;
    x.t_error = t_error;
    return x;
}

/* The same answer, bit for bit (a miss's t is infinite). */
static int same(const seen *a, const seen *b) {
    return a->hit == b->hit && a->prim_id == b->prim_id && a->t == b->t &&
           a->t_error == b->t_error;
}

/* Frame f's ray k traced in a float scene. */
static seen hit_f(const st_scene *s, int f, unsigned k) {
    double o[3], d[3];
    st_rayhit rh;
    memset(&rh, 0, sizeof rh);
    ray_k(f, k, o, d);
    rh.ray.org_x = (float)o[0]; rh.ray.org_y = (float)o[1]; rh.ray.org_z = (float)o[2];
    rh.ray.dir_x = (float)d[0]; rh.ray.dir_y = (float)d[1]; rh.ray.dir_z = (float)d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = INFINITY;
    st_intersect1(s, &rh);
    return seen_of(rh.hit.geom_id, rh.hit.prim_id, rh.ray.tfar, rh.hit.t_error);
}

static seen hit_d(const st_scene_f64 *s, int f, unsigned k) {
    double o[3], d[3];
    st_rayhit_f64 rh;
    memset(&rh, 0, sizeof rh);
    ray_k(f, k, o, d);
    rh.ray.org_x = o[0]; rh.ray.org_y = o[1]; rh.ray.org_z = o[2];
    rh.ray.dir_x = d[0]; rh.ray.dir_y = d[1]; rh.ray.dir_z = d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = INFINITY;
    st_intersect1_f64(s, &rh);
    return seen_of(rh.hit.geom_id, rh.hit.prim_id, rh.ray.tfar, rh.hit.t_error);
}

/* The hits of frame f's rays in a float scene. */
static void trace_f(const st_scene *s, int f, seen *out) {
    unsigned k;
    for (k = 0; k < RAYS; k++) out[k] = hit_f(s, f, k);
}

static void trace_d(const st_scene_f64 *s, int f, seen *out) {
    unsigned k;
    for (k = 0; k < RAYS; k++) out[k] = hit_d(s, f, k);
}

/* Checks frame f's hits against its analytic sphere (within t_error plus `rounding` times t) and
 * a fresh build's hits. */
static void check_frame(int f, const seen *got, const seen *fresh, int refitted,
                        double rounding) {
    unsigned k, hits = 0;
    double r, c[3];
    frame_sphere(f, &r, c);
    for (k = 0; k < RAYS; k++) {
        double o[3], d[3], t;
        const seen *h = &got[k];
        ray_k(f, k, o, d);
        t = sphere_t(o, d, r, c);
        if (f < 0) {
            CHECK(!h->hit);
            continue;
        }
        /* Rays graze the sphere only at tangency; the mesh's edge rings meet it exactly. */
        if (t > 0 && h->hit) {
            hits++;
            CHECK(fabs(h->t - t) <= h->t_error + rounding * (1 + t));
        }
        CHECK(h->hit == fresh[k].hit);
        if (h->hit && fresh[k].hit) {
            CHECK(fabs(h->t - fresh[k].t) <= h->t_error + fresh[k].t_error);
            if (!refitted) CHECK(same(h, &fresh[k]));
        }
    }
    if (f >= 0) CHECK(hits > RAYS / 4);
}

/* A fresh build of frame f's float vertices (flags without ST_BUILD_UPDATABLE). */
static st_scene *fresh_f(const vertex_f *v, uint32_t flags, void **memory) {
    return build_f(v[0].p, v[0].n, sizeof(vertex_f), vertex_count, idx, triangle_count, flags, 8,
                   memory, NULL);
}

static void run_f(uint32_t flags) {
    size_t bytes = 0;
    void *memory;
    st_scene *s = NULL;
    st_scene_info info;
    vertex_f *v = (vertex_f *)calloc(vertex_count, sizeof(vertex_f));
    vertex_d *scratch = (vertex_d *)calloc(vertex_count, sizeof(vertex_d));
    seen got[RAYS], fresh[RAYS], again[RAYS];
    int f;

    pose_f(0, v, scratch);
    s = build_f(v[0].p, v[0].n, sizeof(vertex_f), vertex_count, idx, triangle_count,
                flags | ST_BUILD_UPDATABLE, 8, &memory, &bytes);
    CHECK(st_scene_get_info(s, &info) == ST_OK);
    CHECK(info.bytes_used <= bytes && info.update_count == 0);
    for (f = 1; f <= FRAMES; f++) {
        void *fm;
        st_scene *fs;
        int pose = f == FRAMES / 2 ? -1 : f;
        pose_f(pose, v, scratch);
        CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                              vertex_count) == ST_OK);
        CHECK(st_scene_get_info(s, &info) == ST_OK);
        CHECK(info.update_count == (uint32_t)f);
        CHECK(info.triangle_count == triangle_count);
        trace_f(s, pose, got);
        if (pose < 0) {
            CHECK(info.rejected_count == triangle_count);
            check_frame(pose, got, got, 1, F32_ROUNDING);
            continue;
        }
        CHECK(info.rejected_count == 0);
        fs = fresh_f(v, flags, &fm);
        trace_f(fs, pose, fresh);
        check_frame(pose, got, fresh, (int)info.bvh_refitted, F32_ROUNDING);
        free(fm);
    }

    /* Bad updates leave the scene as it was. */
    trace_f(s, FRAMES, got);
    CHECK(st_scene_update(NULL, v[0].p, 0, v[0].n, 0, vertex_count) == ST_ERROR_NULL_ARGUMENT);
    CHECK(st_scene_update(s, NULL, 0, v[0].n, 0, vertex_count) == ST_ERROR_NULL_ARGUMENT);
    CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                          vertex_count - 1) == ST_ERROR_INVALID_ARGUMENT);
    CHECK(st_scene_update(s, v[0].p, 8, v[0].n, sizeof(vertex_f), vertex_count) ==
          ST_ERROR_INVALID_ARGUMENT);
    pose_f(3, v, scratch);
    v[vertex_count / 2].p[1] = NAN;
    CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                          vertex_count) == ST_ERROR_NON_FINITE);
    v[vertex_count / 2].p[1] = 0;
    v[3].n[0] = INFINITY;
    CHECK(st_scene_update(s, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                          vertex_count) == ST_ERROR_NON_FINITE);
    CHECK(st_scene_update_f64((st_scene_f64 *)(void *)s, scratch[0].p, sizeof(vertex_d),
                              scratch[0].n, sizeof(vertex_d), vertex_count) ==
          ST_ERROR_WRONG_SCENE);
    CHECK(st_scene_get_info(s, &info) == ST_OK);
    CHECK(info.update_count == FRAMES);
    trace_f(s, FRAMES, again);
    {
        unsigned k;
        for (k = 0; k < RAYS; k++) CHECK(same(&got[k], &again[k]));
    }

    /* A scene built without the flag cannot be updated. */
    {
        void *fm;
        st_scene *fs;
        pose_f(1, v, scratch);
        fs = fresh_f(v, flags, &fm);
        CHECK(st_scene_update(fs, v[0].p, sizeof(vertex_f), v[0].n, sizeof(vertex_f),
                              vertex_count) == ST_ERROR_NOT_UPDATABLE);
        free(fm);
    }
    free(memory);
    free(v);
    free(scratch);
}

static void run_d(uint32_t flags) {
    size_t bytes = 0, fbytes = 0;
    void *memory, *fm;
    st_scene_f64 *s = NULL, *fs = NULL;
    st_scene_info info;
    vertex_d *v = (vertex_d *)calloc(vertex_count, sizeof(vertex_d));
    seen got[RAYS], fresh[RAYS];
    int f;

    pose_d(0, v);
    CHECK(st_scene_required_bytes_f64(vertex_count, triangle_count, flags | ST_BUILD_UPDATABLE,
                                      &bytes) == ST_OK);
    memory = malloc(bytes);
    CHECK(st_scene_build_f64(memory, bytes, v[0].p, sizeof(vertex_d), v[0].n,
                             sizeof(vertex_d), vertex_count, idx, triangle_count,
                             flags | ST_BUILD_UPDATABLE, 8, &s) == ST_OK);
    CHECK(st_scene_required_bytes_f64(vertex_count, triangle_count, flags, &fbytes) == ST_OK);
    fm = malloc(fbytes);
    for (f = 1; f <= FRAMES; f++) {
        pose_d(f, v);
        CHECK(st_scene_update_f64(s, v[0].p, sizeof(vertex_d), v[0].n, sizeof(vertex_d),
                                  vertex_count) == ST_OK);
        CHECK(st_scene_get_info_f64(s, &info) == ST_OK);
        CHECK(info.update_count == (uint32_t)f);
        CHECK(st_scene_build_f64(fm, fbytes, v[0].p, sizeof(vertex_d), v[0].n,
                                 sizeof(vertex_d), vertex_count, idx, triangle_count, flags, 8,
                                 &fs) == ST_OK);
        trace_d(s, f, got);
        trace_d(fs, f, fresh);
        check_frame(f, got, fresh, (int)info.bvh_refitted, F64_ROUNDING);
    }
    CHECK(st_scene_update_f64(fs, v[0].p, 0, v[0].n, 0, vertex_count) ==
          ST_ERROR_NOT_UPDATABLE);
    free(fm);
    free(memory);
    free(v);
}

int main(void) {
    uint32_t flags;
    unit_sphere(RINGS, SEGMENTS, &vertex_count, &triangle_count, &rest, &idx);
    for (flags = 0; flags < 4; flags++) {
        run_f(flags);
        run_d(flags);
    }
    free(rest);
    free(idx);
    return check_exit_status("all checks passed");
}
