/* vergence-content — writes the paper's scenes as glTF 2.0 into a folder.
 *
 * The output is reproducible byte for byte (no timestamps, fixed number
 * formatting, integer-hash noise, fixed PNG settings), so the committed files
 * in content/ can be checked against a fresh run (test content.reproducible). */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/io.h"
#include "core/log.h"
#include "core/status.h"
#include "scenes.h"

const content_scene content_scenes[] = {
    {"balloon", "Paper Fig. 1: a red balloon flies from 25 m to 3 m between a house and a tree.",
     scene_balloon_build},
    {"cubes", "Paper Fig. 2: a small cube flies from 3 m to 25 m past static cubes at 8-12.5 m.",
     scene_cubes_build},
    {"arena", "Paper Fig. 6: hit-prediction field; the game moves node 'ball' (default: a 2 s ballistic throw).",
     scene_arena_build},
    {"bird", "Like paper Fig. 8: a skinned bird flies from 40 m to 4 m past a windmill; a morphing flag, a moving camera.",
     scene_bird_build},
};
const int content_scene_count = (int)(sizeof content_scenes / sizeof content_scenes[0]);

static void print_help(FILE *out)
{
    fprintf(out,
            "usage: vergence-content --out DIR [--scene NAME]...\n"
            "\n"
            "Writes the paper's scenes as glTF 2.0 (NAME.gltf + NAME.bin, textures\n"
            "embedded as PNG) into DIR. Without --scene, writes every scene. The output\n"
            "is byte-for-byte reproducible; the build target 'content' regenerates the\n"
            "committed files in content/.\n"
            "\n"
            "options:\n"
            "  --out DIR      output folder (created when missing)\n"
            "  --scene NAME   scene to write; repeatable\n"
            "  --list         print the scene names and descriptions, then exit\n"
            "  -h, --help     print this help\n"
            "\n"
            "scenes:\n");
    for (int i = 0; i < content_scene_count; i++)
        fprintf(out, "  %-9s %s\n", content_scenes[i].name, content_scenes[i].description);
}

static int find_scene(const char *name)
{
    for (int i = 0; i < content_scene_count; i++)
        if (!strcmp(content_scenes[i].name, name))
            return i;
    return -1;
}

typedef struct args {
    const char *out;
    bool selected[sizeof content_scenes / sizeof content_scenes[0]];
    bool any_selected, help, list;
} args;

static vg_status parse_args(int argc, char **argv, args *a)
{
    for (int i = 1; i < argc; i++) {
        const char *opt = argv[i];
        if (!strcmp(opt, "-h") || !strcmp(opt, "--help")) {
            a->help = true;
        } else if (!strcmp(opt, "--list")) {
            a->list = true;
        } else if (!strcmp(opt, "--out") || !strcmp(opt, "--scene")) {
            if (i + 1 >= argc || !argv[i + 1][0]) {
                vg_error("content: %s needs a value (see 'vergence-content --help')", opt);
                return VG_ERR_ARG;
            }
            const char *val = argv[++i];
            if (!strcmp(opt, "--out")) {
                a->out = val;
                continue;
            }
            int s = find_scene(val);
            if (s < 0) {
                char known[256] = "";
                for (int k = 0; k < content_scene_count; k++)
                    snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", k ? ", " : "",
                             content_scenes[k].name);
                vg_error("content: --scene: unknown scene '%s' (known: %s)", val, known);
                return VG_ERR_ARG;
            }
            a->selected[s] = a->any_selected = true;
        } else {
            vg_error("content: unknown option '%s' (see 'vergence-content --help')", opt);
            return VG_ERR_ARG;
        }
    }
    return VG_OK;
}

static vg_status write_scene(const content_scene *cs, const char *dir)
{
    gltf *g = gltf_create(cs->name, cs->description);
    if (!g) {
        vg_error("%s: out of memory", cs->name);
        return VG_ERR_NOMEM;
    }
    cs->build(g);
    size_t gltf_bytes = 0, bin_bytes = 0;
    vg_status st = gltf_write(g, dir, &gltf_bytes, &bin_bytes);
    if (st == VG_OK)
        printf("%-8s %6u triangles  %s.gltf %7zu bytes  %s.bin %8zu bytes\n", cs->name, gltf_triangles(g),
               cs->name, gltf_bytes, cs->name, bin_bytes);
    else
        vg_error("%s: not written: %s", cs->name, vg_status_text(st));
    gltf_destroy(g);
    return st;
}

int main(int argc, char **argv)
{
    args a = {0};
    vg_status st = parse_args(argc, argv, &a);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    if (a.help || a.list) {
        if (a.help)
            print_help(stdout);
        else
            for (int i = 0; i < content_scene_count; i++)
                printf("%s\t%s\n", content_scenes[i].name, content_scenes[i].description);
        return 0;
    }
    if (!a.out) {
        vg_error("content: --out is required (see 'vergence-content --help')");
        return vg_status_exit_code(VG_ERR_ARG);
    }
    st = vg_dir_prepare(a.out);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    for (int i = 0; i < content_scene_count && st == VG_OK; i++)
        if (!a.any_selected || a.selected[i])
            st = write_scene(&content_scenes[i], a.out);
    return vg_status_exit_code(st);
}
