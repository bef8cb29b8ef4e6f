/*
 * Bad input through smoothtri.h: every documented status, outputs untouched on failure, no
 * crash on NULL pointers, and the structs laid out as Embree's. Exits non-zero on a failed
 * check.
 */
#include "smoothtri.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

#define EXPECT(call, status)                                                               \
    do {                                                                                   \
        st_status got_ = (call);                                                           \
        if (got_ != (status)) {                                                            \
            fprintf(stderr, "%s:%d: %s gave %s, expected %s\n", __FILE__, __LINE__, #call,  \
                    st_status_str(got_), st_status_str(status));                            \
            failures++;                                                                    \
        }                                                                                  \
    } while (0)

/* The upper half of an octahedron, packed positions and radial normals. */
static const float P[15] = {1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1};
static const uint32_t I[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};

int main(void) {
    size_t bytes = 0, sentinel_bytes = 777;
    void *memory;
    st_scene *scene = NULL, *const sentinel = (st_scene *)(void *)&bytes;
    st_scene_info info;
    float pos[15], bad[15], box[6] = {42, 42, 42, 42, 42, 42};
    uint32_t idx[12];
    st_rayhit rh;
    st_ray ray;

    /* Layouts: st_ray is Embree's RTCRay; the SoA packet is 32-byte aligned. */
    CHECK(sizeof(st_ray) == 48 && offsetof(st_ray, tnear) == 12 && offsetof(st_ray, tfar) == 32);
    CHECK(offsetof(st_ray, mask) == 36 && offsetof(st_ray, flags) == 44);
    CHECK(offsetof(st_hit, prim_id) == 20 && offsetof(st_hit, geom_id) == 24);
    CHECK(offsetof(st_hit, ns_x) == 28 && offsetof(st_hit, t_error) == 40);
    CHECK(sizeof(st_rayhit) == 96 && offsetof(st_rayhit, hit) == 48);
    CHECK(sizeof(st_rayhit8) == 736 && offsetof(st_rayhit8, hit) == 384);
    CHECK(offsetof(st_ray8, tfar) == 8 * 32 && offsetof(st_hit8, prim_id) == 5 * 32);

    memcpy(pos, P, sizeof pos);
    memcpy(idx, I, sizeof idx);
    CHECK(strcmp(st_status_str(ST_OK), "ST_OK") == 0);
    CHECK(strcmp(st_status_str(ST_ERROR_NON_FINITE), "ST_ERROR_NON_FINITE") == 0);
    CHECK(strcmp(st_status_str(ST_ERROR_NOT_UPDATABLE), "ST_ERROR_NOT_UPDATABLE") == 0);
    /* The kernels' instruction set: a known name (which one, `tests/c_api.rs` checks). */
    {
        const char *isa = st_get_isa();
        CHECK(isa != NULL && (strcmp(isa, "sse2") == 0 || strcmp(isa, "avx2") == 0 ||
                              strcmp(isa, "avx512") == 0 || strcmp(isa, "neon") == 0));
    }
    CHECK(strcmp(st_status_str(12345), "ST_ERROR_UNKNOWN") == 0);

    /* Sizes. */
    EXPECT(st_scene_required_bytes(5, 4, 0, NULL), ST_ERROR_NULL_ARGUMENT);
    EXPECT(st_scene_required_bytes(5, 4, 1u << 7, &sentinel_bytes), ST_ERROR_INVALID_ARGUMENT);
    CHECK(sentinel_bytes == 777);
    EXPECT(st_scene_required_bytes((size_t)-1, (size_t)-1, 0, &sentinel_bytes), ST_ERROR_TOO_LARGE);
    CHECK(sentinel_bytes == 777);
    EXPECT(st_scene_required_bytes(5, 4, ST_BUILD_SEAMS | ST_BUILD_SHARED_FIELD, &bytes), ST_OK);
    memory = malloc(bytes + 1);

#define BUILD(mem, n, p, ps, nrm, ns, vc, ix, tc, fl, it)                                  \
    st_scene_build((mem), (n), (p), (ps), (nrm), (ns), (vc), (ix), (tc), (fl), (it), &scene)

    /* NULL pointers. */
    scene = sentinel;
    EXPECT(BUILD(NULL, bytes, pos, 0, pos, 0, 5, idx, 4, 0, 8), ST_ERROR_NULL_ARGUMENT);
    EXPECT(BUILD(memory, bytes, NULL, 0, pos, 0, 5, idx, 4, 0, 8), ST_ERROR_NULL_ARGUMENT);
    EXPECT(BUILD(memory, bytes, pos, 0, NULL, 0, 5, idx, 4, 0, 8), ST_ERROR_NULL_ARGUMENT);
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, NULL, 4, 0, 8), ST_ERROR_NULL_ARGUMENT);
    EXPECT(st_scene_build(memory, bytes, pos, 0, pos, 0, 5, idx, 4, 0, 8, NULL),
           ST_ERROR_NULL_ARGUMENT);
    /* Bad arguments. */
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, idx, 4, 0, ST_MAX_ITERATIONS + 1),
           ST_ERROR_INVALID_ARGUMENT);
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, idx, 4, 0, UINT32_MAX), ST_ERROR_INVALID_ARGUMENT);
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, idx, 4, 8, 8), ST_ERROR_INVALID_ARGUMENT);
    EXPECT(BUILD(memory, bytes, pos, 8, pos, 0, 5, idx, 4, 0, 8), ST_ERROR_INVALID_ARGUMENT);
    EXPECT(BUILD(memory, bytes, pos, 13, pos, 0, 5, idx, 4, 0, 8), ST_ERROR_INVALID_ARGUMENT);
    EXPECT(BUILD(memory, bytes, (const float *)(const void *)((const char *)pos + 1), 0, pos, 0,
                 4, idx, 4, 0, 8),
           ST_ERROR_INVALID_ARGUMENT);
    /* Short memory: one byte short of what st_scene_required_bytes said. */
    EXPECT(BUILD(memory, bytes - 1, pos, 0, pos, 0, 5, idx, 4, ST_BUILD_SEAMS | ST_BUILD_SHARED_FIELD, 8),
           ST_ERROR_BUFFER_TOO_SMALL);
    /* Indices out of range, no triangles. */
    idx[7] = 5;
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, idx, 4, 0, 8), ST_ERROR_INDEX_OUT_OF_RANGE);
    idx[7] = I[7];
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, idx, 0, 0, 8), ST_ERROR_NO_USABLE_TRIANGLES);
    EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 0, idx, 4, 0, 8), ST_ERROR_INDEX_OUT_OF_RANGE);
    /* NaN positions everywhere: nothing usable, and the first reason is non-finite. */
    {
        size_t i;
        for (i = 0; i < 15; i++) bad[i] = NAN;
        EXPECT(BUILD(memory, bytes, bad, 0, pos, 0, 5, idx, 4, 0, 8), ST_ERROR_NON_FINITE);
    }
    /* Only degenerate triangles (all corners equal). */
    {
        uint32_t same[6] = {0, 0, 0, 1, 1, 1};
        EXPECT(BUILD(memory, bytes, pos, 0, pos, 0, 5, same, 2, 0, 8), ST_ERROR_NO_USABLE_TRIANGLES);
    }
    /* Nothing above wrote the output. */
    CHECK(scene == sentinel);

    /* One NaN vertex among good ones: its two triangles are skipped and counted. */
    memcpy(bad, P, sizeof bad);
    bad[3] = NAN;
    EXPECT(BUILD(memory, bytes, bad, 0, pos, 0, 5, idx, 4, 0, 8), ST_OK);
    EXPECT(st_scene_get_info(scene, &info), ST_OK);
    CHECK(info.patch_count == 2 && info.rejected_count == 2 && info.rejected_non_finite == 2);
    CHECK(info.first_rejected == 0);

    /* A good build, any alignment of the memory. */
    EXPECT(BUILD((char *)memory + 1, bytes, pos, 0, pos, 0, 5, idx, 4, ST_BUILD_SEAMS | ST_BUILD_SHARED_FIELD, 8),
           ST_OK);
    EXPECT(st_scene_get_info(scene, &info), ST_OK);
    CHECK(info.patch_count == 4 && info.rejected_count == 0 && info.first_rejected == ST_INVALID_ID);
    CHECK(info.seam_edge_count == 4);

    /* Queries with bad pointers: errors, misses, no crash, outputs untouched. */
    EXPECT(st_scene_get_info(NULL, &info), ST_ERROR_NULL_ARGUMENT);
    EXPECT(st_scene_get_info(scene, NULL), ST_ERROR_NULL_ARGUMENT);
    EXPECT(st_scene_get_info((const st_scene *)(const void *)pos, &info), ST_ERROR_WRONG_SCENE);
    EXPECT(st_patch_bounds(scene, 4, box), ST_ERROR_INDEX_OUT_OF_RANGE);
    EXPECT(st_patch_bounds(NULL, 0, box), ST_ERROR_NULL_ARGUMENT);
    EXPECT(st_patch_bounds(scene, 0, NULL), ST_ERROR_NULL_ARGUMENT);
    CHECK(box[0] == 42 && box[5] == 42);
    EXPECT(st_patch_bounds(scene, 3, box), ST_OK);

    memset(&rh, 0, sizeof rh);
    rh.ray.org_z = 3; rh.ray.dir_z = -1; rh.ray.org_x = 0.25f; rh.ray.org_y = 0.125f;
    rh.ray.tfar = INFINITY;
    st_intersect1(NULL, &rh);
    CHECK(rh.hit.prim_id == ST_INVALID_ID && isinf(rh.ray.tfar));
    st_intersect1(scene, NULL);
    st_occluded1(NULL, &rh.ray);
    CHECK(isinf(rh.ray.tfar) && rh.ray.tfar > 0);
    st_occluded1(scene, NULL);
    st_intersect8(NULL, scene, NULL);
    st_intersect1M(scene, NULL, 10, 0);
    st_intersect1M(scene, &rh, 1, 8); /* stride below sizeof(st_rayhit): nothing traced */
    CHECK(rh.hit.prim_id == ST_INVALID_ID);
    CHECK(!st_patch_intersect(NULL, 0, &rh) && !st_patch_intersect(scene, 9, &rh));
    CHECK(!st_patch_intersect(scene, 0, NULL));

    /* And the good query: the unit sphere, exactly. */
    st_intersect1(scene, &rh);
    CHECK(rh.hit.prim_id < 4 && rh.hit.geom_id == 0);
    CHECK(fabsf(rh.ray.tfar - (3.0f - sqrtf(1.0f - 0.25f * 0.25f - 0.125f * 0.125f))) < 1e-5f);
    /* A ray starting past the hit misses; a ray with a NaN direction misses. */
    ray = rh.ray;
    ray.tfar = INFINITY;
    st_occluded1(scene, &ray);
    CHECK(ray.tfar == -INFINITY);
    ray.tfar = INFINITY;
    ray.tnear = 10;
    st_occluded1(scene, &ray);
    CHECK(ray.tfar == INFINITY);
    ray.tnear = 0;
    ray.dir_x = NAN;
    st_occluded1(scene, &ray);
    CHECK(ray.tfar == INFINITY);

    free(memory);
    return check_exit_status("errors_test: all checks passed");
}
