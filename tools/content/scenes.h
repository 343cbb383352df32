/* vergence content — the paper's scenes, each built into a glTF document. */
#pragma once
#include "gltf.h"

typedef struct content_scene {
    const char *name;        /* file stem: content/NAME.gltf */
    const char *description; /* one line, also written to scenes[0].extras */
    void (*build)(gltf *g);  /* failures are recorded in g and reported by gltf_write */
} content_scene;

void scene_balloon_build(gltf *g); /* paper Fig. 1 */
void scene_cubes_build(gltf *g);   /* paper Fig. 2 */
void scene_arena_build(gltf *g);   /* paper Fig. 6 */
void scene_bird_build(gltf *g);    /* like paper Fig. 8: skinned and morphed meshes, camera motion */

extern const content_scene content_scenes[];
extern const int content_scene_count;
