#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "smoothtri.h"

/* An interleaved vertex buffer, as engines keep them: position, normal, uv. */
typedef struct { float p[3], n[3], uv[2]; } vertex;

int main(void) {
    /* The upper half of an octahedron with radial normals: its patches are the unit sphere. */
    vertex v[5] = {{{1, 0, 0}, {1, 0, 0}, {0, 0}}, {{0, 1, 0}, {0, 1, 0}, {0, 0}},
                   {{-1, 0, 0}, {-1, 0, 0}, {0, 0}}, {{0, -1, 0}, {0, -1, 0}, {0, 0}},
                   {{0, 0, 1}, {0, 0, 1}, {0, 0}}};
    uint32_t idx[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    size_t bytes;
    st_scene *scene;
    st_rayhit rh;
    st_status s = st_scene_required_bytes(5, 4, ST_BUILD_SEAMS, &bytes);
    void *memory = malloc(bytes); /* any allocator, any alignment; the scene lives here */
    if (s == ST_OK)
        s = st_scene_build(memory, bytes, v[0].p, sizeof(vertex), v[0].n, sizeof(vertex), 5,
                           idx, 4, ST_BUILD_SEAMS, 8 /* N */, &scene);
    if (s != ST_OK) {
        fprintf(stderr, "smoothtri: %s\n", st_status_str(s));
        return 1;
    }
    memset(&rh, 0, sizeof rh);
    rh.ray.org_x = 0.3f; rh.ray.org_y = 0.2f; rh.ray.org_z = 3.0f;
    rh.ray.dir_z = -1.0f;
    rh.ray.tfar = INFINITY;
    st_intersect1(scene, &rh); /* thread-safe; the scene is immutable */
    if (rh.hit.prim_id == ST_INVALID_ID) return 1;
    printf("t = %.6f ± %.1e, triangle %u, shading normal (%.3f, %.3f, %.3f)\n", rh.ray.tfar,
           rh.hit.t_error, rh.hit.prim_id, rh.hit.ns_x, rh.hit.ns_y, rh.hit.ns_z);
    free(memory); /* no destroy call: the scene is gone with its memory */
    return 0;
}
