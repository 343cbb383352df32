/* scene_probe FILE [--time T]: loads a glTF, evaluates it at T
 * and prints counts and a few evaluated values as JSON on stdout.
 *
 * The exit code is the load status (vg_status_exit_code), so scripts can
 * tell I/O (3), format (4) and unsupported (10) failures apart; the one
 * error line is the loader's own. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/json.h"
#include "core/log.h"
#include "scene/scene.h"

int main(int argc, char **argv)
{
    const char *path = NULL;
    double t = 0.0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--time") && i + 1 < argc)
            t = atof(argv[++i]);
        else if (!path && argv[i][0] != '-')
            path = argv[i];
        else {
            fprintf(stderr, "usage: scene_probe FILE [--time T]\n");
            return 2;
        }
    }
    if (!path) {
        fprintf(stderr, "usage: scene_probe FILE [--time T]\n");
        return 2;
    }
    scene *s = NULL;
    vg_status st = scene_load(path, &s);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    scene_state ev;
    if (scene_state_init(s, &ev) != VG_OK) {
        scene_destroy(s);
        return vg_status_exit_code(VG_ERR_NOMEM);
    }
    scene_evaluate(s, (float)t, &ev);
    vg_camera cam;
    scene_camera_resolve(s, &ev, 0, 16.0f / 9.0f, &cam);

    vg_json j = {0};
    vg_json_object_begin(&j, NULL);
    vg_json_str(&j, "path", s->path);
    vg_json_int(&j, "max_textures", SCENE_MAX_TEXTURES);
    vg_json_int(&j, "nodes", s->node_count);
    vg_json_int(&j, "meshes", s->mesh_count);
    vg_json_int(&j, "primitives", s->primitive_count);
    vg_json_int(&j, "materials", s->material_count);
    vg_json_int(&j, "textures", s->texture_count);
    vg_json_int(&j, "cameras", s->camera_count);
    vg_json_int(&j, "skins", s->skin_count);
    vg_json_int(&j, "animations", s->animation_count);
    vg_json_int(&j, "channels", s->channel_count);
    vg_json_int(&j, "samplers", s->sampler_count);
    vg_json_int(&j, "roots", s->root_count);
    vg_json_int(&j, "instances", s->instance_count);
    vg_json_int(&j, "vertices", s->vertex_count);
    vg_json_int(&j, "indices", s->index_count);
    vg_json_num(&j, "duration", s->duration);
    vg_json_bool(&j, "animated", s->animated);
    vg_json_nums(&j, "bounds_min", s->bounds_min, 3);
    vg_json_nums(&j, "bounds_max", s->bounds_max, 3);
    vg_json_num(&j, "time", ev.t);
    vg_json_nums(&j, "state_bounds_min", ev.bounds_min, 3);
    vg_json_nums(&j, "state_bounds_max", ev.bounds_max, 3);
    if (s->vertex_count) {
        vg_json_nums(&j, "first_position", ev.positions, 3);
        vg_json_nums(&j, "first_normal", ev.normals, 3);
    }
    vg_json_array_begin(&j, "textures_wh");
    for (int i = 0; i < s->texture_count; i++) {
        float wh[2] = {(float)s->textures[i].width, (float)s->textures[i].height};
        vg_json_nums(&j, NULL, wh, 2);
    }
    vg_json_array_end(&j);
    vg_json_object_begin(&j, "camera");
    vg_json_int(&j, "source_node", cam.source_node);
    vg_json_bool(&j, "orthographic", cam.orthographic);
    vg_json_nums(&j, "position", cam.position, 3);
    vg_json_nums(&j, "forward", cam.forward, 3);
    vg_json_num(&j, "yfov", cam.yfov);
    vg_json_num(&j, "znear", cam.znear);
    vg_json_num(&j, "zfar", cam.zfar);
    vg_json_object_end(&j);
    vg_json_object_end(&j);
    if (j.buf)
        fwrite(j.buf, 1, j.len, stdout);
    fputc('\n', stdout);
    vg_json_free(&j);
    scene_state_free(&ev);
    scene_destroy(s);
    return 0;
}
