/*
 * The one pattern of concurrent use smoothtri.h allows, from C with POSIX threads: many
 * threads trace one scene at once (st_intersect1, st_occluded1, st_intersect8 and
 * st_patch_intersect take a const scene), they are joined, then st_scene_update moves the
 * scene with no tracer running, and the threads trace it again. Checked, for every frame:
 *   - every thread's answers equal, byte for byte, those of one thread tracing alone;
 *   - after each update, every patch answers each ray exactly as the same patch of a fresh
 *     st_scene_build of the new pose (patch by patch, st_patch_intersect: bit for bit);
 *   - the scene's closest hits equal the fresh build's bit for bit when the update built the
 *     tree anew, and otherwise hit the same rays with t within the larger t_error (the
 *     documented contract of st_scene_update: a refitted tree may order the patch tests
 *     differently).
 * Frames: the rest pose, a small wobble (the tree is refitted), and a scramble of every
 * vertex (the tree is built anew). Prints one line per frame and "all checks passed".
 * Usage: threads_test [RAYS] (default and most 256; fewer under valgrind, which is slow).
 */
#define _POSIX_C_SOURCE 200809L
#include "smoothtri.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_common.h"

#define RINGS 8
#define SEGMENTS 16
#define RAYS 256 /* at most; the first argument may ask for fewer (a multiple of 8) */
#define THREADS 4
#define PATCH_EVERY 8 /* every eighth ray is also tested patch by patch */

typedef struct { float p[3], n[3]; } vertex;

static size_t vertex_count, triangle_count;
static unsigned rays = RAYS;
static double *rest; /* the unit sphere's points (test_common.h), also its normals */
static uint32_t *idx;

/* Pose f: 0 the rest pose, 1 a small wobble of each vertex along its normal, 2 every vertex
 * moved far from its place (a fixed pseudo-random scramble). */
static void pose(int f, vertex *out) {
    size_t i;
    unsigned k, seed = 12345;
    for (i = 0; i < vertex_count; i++) {
        double s = 1.0;
        if (f == 1) s = 1.0 + 0.03 * sin(3.0 * (double)i);
        for (k = 0; k < 3; k++) {
            out[i].p[k] = (float)(s * rest[3 * i + k]);
            out[i].n[k] = (float)rest[3 * i + k];
        }
        if (f == 2) {
            for (k = 0; k < 3; k++) {
                seed = seed * 1103515245u + 12345u;
                out[i].p[k] += (float)(8.0 * ((seed >> 8) % 1000) / 1000.0 - 4.0);
            }
        }
    }
}

/* Ray k: from a point at distance 4 from the origin, aimed near it. */
static void ray_k(unsigned k, st_rayhit *rh) {
    double a = 2 * PI * k / rays * 5.0, b = acos(1 - 2 * (k + 0.5) / rays);
    memset(rh, 0, sizeof *rh);
    rh->ray.org_x = (float)(4 * sin(b) * cos(a));
    rh->ray.org_y = (float)(4 * sin(b) * sin(a));
    rh->ray.org_z = (float)(4 * cos(b));
    rh->ray.dir_x = (float)(0.3 * sin(1.7 * k)) - rh->ray.org_x;
    rh->ray.dir_y = (float)(0.3 * cos(2.3 * k)) - rh->ray.org_y;
    rh->ray.dir_z = -rh->ray.org_z;
    rh->ray.tnear = 0;
    rh->ray.tfar = INFINITY;
    rh->ray.mask = 0xFFFFFFFFu;
    rh->hit.prim_id = ST_INVALID_ID;
    rh->hit.geom_id = ST_INVALID_ID;
}

/* What one tracer answers for every ray: closest hits, shadow rays, and packets of eight. */
typedef struct {
    st_rayhit hits[RAYS];
    st_ray shadows[RAYS];
    st_rayhit8 packets[RAYS / 8];
} answers;

typedef struct {
    const st_scene *scene;
    answers *out;
} job;

static void trace_all(const st_scene *scene, answers *out) {
    unsigned k, l;
    memset(out, 0, sizeof *out);
    for (k = 0; k < rays; k++) {
        ray_k(k, &out->hits[k]);
        out->shadows[k] = out->hits[k].ray;
        st_intersect1(scene, &out->hits[k]);
        st_occluded1(scene, &out->shadows[k]);
    }
    for (k = 0; k < rays / 8; k++) {
        int valid[8];
        st_rayhit8 *p = &out->packets[k];
        for (l = 0; l < 8; l++) {
            st_rayhit rh;
            ray_k(8 * k + l, &rh);
            valid[l] = -1;
            p->ray.org_x[l] = rh.ray.org_x; p->ray.org_y[l] = rh.ray.org_y;
            p->ray.org_z[l] = rh.ray.org_z; p->ray.dir_x[l] = rh.ray.dir_x;
            p->ray.dir_y[l] = rh.ray.dir_y; p->ray.dir_z[l] = rh.ray.dir_z;
            p->ray.tnear[l] = 0; p->ray.tfar[l] = INFINITY;
            p->hit.prim_id[l] = ST_INVALID_ID; p->hit.geom_id[l] = ST_INVALID_ID;
        }
        st_intersect8(valid, scene, p);
    }
}

static void *tracer(void *arg) {
    job *j = (job *)arg;
    trace_all(j->scene, j->out);
    return NULL;
}

/* A scene of the vertices `v` in memory of its own (freed by the caller). */
static st_scene *build(const vertex *v, uint32_t flags, void **memory) {
    return build_f(v[0].p, v[0].n, sizeof(vertex), vertex_count, idx, triangle_count, flags, 8,
                   memory, NULL);
}

int main(int argc, char **argv) {
    static answers alone, per_thread[THREADS], fresh_answers;
    pthread_t threads[THREADS];
    job jobs[THREADS];
    vertex *v;
    void *memory;
    st_scene *scene = NULL;
    const unsigned flags = ST_BUILD_SEAMS | ST_BUILD_UPDATABLE;
    int f, t, seen_refit = 0, seen_rebuild = 0;
    unsigned k;

    if (argc > 1) rays = (unsigned)strtoul(argv[1], NULL, 10);
    if (rays < 8 || rays > RAYS || rays % 8 != 0) {
        fprintf(stderr, "usage: threads_test [RAYS: a multiple of 8 from 8 to %d]\n", RAYS);
        return 2;
    }
    unit_sphere(RINGS, SEGMENTS, &vertex_count, &triangle_count, &rest, &idx);
    v = (vertex *)calloc(vertex_count, sizeof(vertex));
    pose(0, v);
    scene = build(v, flags, &memory);
    if (failures) return 1;

    for (f = 0; f < 3; f++) {
        st_scene_info info, fresh_info;
        void *fresh_memory;
        st_scene *fresh;
        unsigned hits = 0;
        if (f > 0) {
            /* Between frames, with no tracer running: the one time the scene may change. */
            pose(f, v);
            CHECK(st_scene_update(scene, v[0].p, sizeof(vertex), v[0].n, sizeof(vertex),
                                  vertex_count) == ST_OK);
        }
        CHECK(st_scene_get_info(scene, &info) == ST_OK);

        /* One thread alone, then THREADS at once on the same scene. */
        trace_all(scene, &alone);
        for (t = 0; t < THREADS; t++) {
            jobs[t].scene = scene;
            jobs[t].out = &per_thread[t];
            CHECK(pthread_create(&threads[t], NULL, tracer, &jobs[t]) == 0);
        }
        for (t = 0; t < THREADS; t++) CHECK(pthread_join(threads[t], NULL) == 0);
        for (t = 0; t < THREADS; t++) {
            CHECK(memcmp(&per_thread[t], &alone, sizeof alone) == 0);
        }

        /* The same pose built afresh. */
        fresh = build(v, ST_BUILD_SEAMS, &fresh_memory);
        CHECK(st_scene_get_info(fresh, &fresh_info) == ST_OK);
        CHECK(info.patch_count == fresh_info.patch_count);
        CHECK(info.rejected_count == fresh_info.rejected_count);
        CHECK(info.seam_edge_count == fresh_info.seam_edge_count);
        trace_all(fresh, &fresh_answers);
        if (f > 0) {
            if (info.bvh_refitted) seen_refit = 1; else seen_rebuild = 1;
        }
        for (k = 0; k < rays; k++) {
            const st_rayhit *a = &alone.hits[k], *b = &fresh_answers.hits[k];
            hits += a->hit.prim_id != ST_INVALID_ID;
            if (f == 0 || !info.bvh_refitted) {
                CHECK(memcmp(a, b, sizeof *a) == 0);
                CHECK(memcmp(&alone.shadows[k], &fresh_answers.shadows[k], sizeof(st_ray)) == 0);
            } else {
                float tol = a->hit.t_error > b->hit.t_error ? a->hit.t_error : b->hit.t_error;
                CHECK((a->hit.prim_id == ST_INVALID_ID) == (b->hit.prim_id == ST_INVALID_ID));
                CHECK(a->hit.prim_id == ST_INVALID_ID || fabsf(a->ray.tfar - b->ray.tfar) <= tol);
                CHECK((alone.shadows[k].tfar < 0) == (fresh_answers.shadows[k].tfar < 0));
            }
        }
        if (f == 0 || !info.bvh_refitted) {
            CHECK(memcmp(alone.packets, fresh_answers.packets, sizeof alone.packets) == 0);
        }
        /* Patch by patch, the updated scene's patches are the fresh build's, bit for bit. */
        for (k = 0; k < rays / PATCH_EVERY; k++) {
            uint32_t p;
            for (p = 0; p < info.patch_count; p++) {
                st_rayhit a, b;
                bool ha, hb;
                ray_k(k * PATCH_EVERY, &a);
                b = a;
                ha = st_patch_intersect(scene, p, &a);
                hb = st_patch_intersect(fresh, p, &b);
                CHECK(ha == hb);
                CHECK(memcmp(&a, &b, sizeof a) == 0);
            }
        }
        printf("frame %d: %s, %u of %u rays hit, %u patches\n", f,
               f == 0 ? "built" : info.bvh_refitted ? "refitted" : "rebuilt", hits, rays,
               (unsigned)info.patch_count);
        CHECK(hits > rays / 4);
        free(fresh_memory);
    }
    CHECK(seen_refit && seen_rebuild);

    free(memory);
    free(v);
    free(rest);
    free(idx);
    return check_exit_status("all checks passed");
}
