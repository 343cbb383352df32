/* vergence — capture.json. */
#include "capture_json.h"

#include <math.h>
#include <string.h>

#include "core/io.h"
#include "shared.h"

void capture_json_header(vg_json *j, const char *scene_path, const scene *s, const frame_desc *fd, const gpu *g,
                         const capture_log *log)
{
    vg_json_object_begin(j, NULL);
    vg_json_str(j, "vergence", VERGENCE_VERSION);
    vg_json_str(j, "scene", scene_path);
    vg_json_object_begin(j, "scene_info");
    vg_json_int(j, "nodes", s->node_count);
    vg_json_int(j, "meshes", s->mesh_count);
    vg_json_int(j, "animations", s->animation_count);
    vg_json_int(j, "skins", s->skin_count);
    vg_json_int(j, "cameras", s->camera_count);
    vg_json_int(j, "materials", s->material_count);
    vg_json_int(j, "textures", s->texture_count);
    vg_json_int(j, "instances", s->instance_count);
    vg_json_int(j, "vertices", s->vertex_count);
    vg_json_int(j, "triangles", s->index_count / 3);
    vg_json_num(j, "duration", s->duration);
    vg_json_object_end(j);
    vg_json_array_begin(j, "size");
    vg_json_int(j, NULL, fd->width);
    vg_json_int(j, NULL, fd->height);
    vg_json_array_end(j);
    vg_json_num(j, "fps", fd->fps);
    vg_json_int(j, "keyframe_stride", fd->keyframe_stride);
    vg_json_int(j, "frames", log->frames);
    vg_json_int(j, "first_frame", log->frames ? log->times[0].index : 0);
    vg_json_object_begin(j, "device");
    vg_json_str(j, "name", g->props.deviceName);
    vg_json_str(j, "type", gpu_device_type_text(g->props.deviceType));
    vg_json_object_end(j);
    stereo_display_json(j, &fd->display);
}

void capture_json_cameras(vg_json *j, const capture_log *log)
{
    if (!log->frames)
        return;
    const vg_camera *c0 = &log->cameras[0];
    vg_json_object_begin(j, "camera");
    vg_json_int(j, "node", c0->source_node);
    vg_json_num(j, "yfov", c0->yfov);
    vg_json_num(j, "aspect", c0->aspect);
    vg_json_num(j, "znear", c0->znear);
    vg_json_num(j, "zfar", c0->zfar);
    vg_json_array_begin(j, "frames");
    for (int i = 0; i < log->frames; i++) {
        const vg_camera *c = &log->cameras[i];
        const frame_times *t = &log->times[i];
        vg_json_object_begin(j, NULL);
        vg_json_int(j, "frame", t->index);
        vg_json_num(j, "time", t->t);
        vg_json_int(j, "prev_keyframe", t->prev_key);
        vg_json_int(j, "next_keyframe", t->next_key);
        vg_json_nums(j, "position", c->position, 3);
        vg_json_nums(j, "forward", c->forward, 3);
        vg_json_nums(j, "view", c->view, 16);
        vg_json_nums(j, "proj", c->proj, 16);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    vg_json_object_end(j);
}

void capture_json_passes(vg_json *j, const capture_log *log)
{
    /* Timings differ from run to run; everything else does not. */
    vg_json_array_begin(j, "passes");
    for (uint32_t p = 0; p < log->pass_count; p++) {
        double sum = 0;
        int n = 0;
        for (int i = 0; i < log->frames; i++) {
            double ms = log->pass_ms[(size_t)i * RG_MAX_PASSES + p];
            if (isfinite(ms))
                sum += ms, n++;
        }
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", log->pass_names[p]);
        vg_json_num(j, "ms_median", capture_log_pass_median(log, p));
        vg_json_num(j, "ms_mean", n ? sum / n : NAN);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    vg_json_num(j, "frame_ms_median", capture_log_frame_median(log));
}

void capture_json_shadow(vg_json *j, const capture_log *log)
{
    double m[2], split, px;
    capture_log_shadow(log, m, &split, &px);
    vg_json_object_begin(j, "shadow");
    vg_json_int(j, "map_px", log->shadow_map_px);
    vg_json_num(j, "texel_m", m[0]);
    vg_json_num(j, "near_texel_m", m[1]);
    vg_json_num(j, "split_m", split);
    vg_json_num(j, "texel_px_median", px);
    vg_json_object_end(j);
}

void capture_json_stereo(vg_json *j, const frame_desc *fd, const warp_metrics *m)
{
    bool cameras = fd->stereo == FRAME_STEREO_CAMERAS; /* the reference itself */
    vg_json_object_begin(j, "stereo");
    vg_json_str(j, "render", frame_stereo_names[fd->stereo]);
    vg_json_str(j, "mode", frame_mode_names[fd->mode]);
    vg_json_str(j, "output", frame_compose_names[fd->compose]);
    vg_json_str(j, "operator", disp_operator_kind_name(fd->op));
    vg_json_bool(j, "swap_eyes", fd->swap_eyes);
    vg_json_num(j, "tess_px", fd->tess_px);
    vg_json_num(j, "tess_error", fd->tess_px > 0 ? 0 : fd->tess_error);
    vg_json_num(j, "interaxial_m", fd->rig.interaxial_m);
    vg_json_num(j, "convergence_m", fd->rig.convergence_m);
    vg_json_object_end(j);
    static const char *const stages[5] = {"none", "direct", "neighborhood", "halton", "curve"};
    vg_json_object_begin(j, "cascade");
    for (int s = 1; s <= VGX_STAGE_CURVE; s++)
        vg_json_num(j, stages[s], m->stage_fraction[s]);
    vg_json_object_end(j);
    vg_json_object_begin(j, "warp_error_px");
    vg_json_num(j, "median", m->error_median);
    vg_json_num(j, "p99", m->error_p99);
    vg_json_num(j, "p99_curve", m->error_p99_curve);
    vg_json_object_end(j);
    vg_json_num(j, "hole_fraction", cameras ? 0.0 : m->hole_fraction);
    vg_json_object_begin(j, "cracks");
    vg_json_int(j, "pixels", (long long)m->crack_pixels);
    vg_json_num(j, "fraction", m->crack_fraction);
    vg_json_int(j, "frame_max", (long long)m->crack_frame_max);
    vg_json_object_end(j);
    vg_json_object_begin(j, "speckles");
    vg_json_int(j, "pixels", (long long)m->speckle_pixels);
    vg_json_num(j, "fraction", m->speckle_fraction);
    vg_json_object_end(j);
    /* The reference shows g: against h or f silhouettes rightly move. */
    vg_json_num(j, "silhouette_mismatch",
                cameras ? 0.0 : fd->mode == FRAME_MODE_ORIGINAL ? m->silhouette_mismatch : NAN);
    vg_json_object_begin(j, "psnr_db");
    vg_json_num(j, "left", cameras ? INFINITY : m->psnr[0]);
    vg_json_num(j, "right", cameras ? INFINITY : m->psnr[1]);
    vg_json_object_end(j);
}

static void json_field_metrics(vg_json *j, const char *key, const disp_metrics *m, double violation,
                               const science_second_difference *d2)
{
    vg_json_object_begin(j, key);
    disp_metrics_write_json(j, m, violation);
    vg_json_object_begin(j, "second_difference");
    vg_json_num(j, "at_keyframe_boundaries", d2->boundary);
    vg_json_num(j, "between_keyframes", d2->between);
    vg_json_object_end(j);
    vg_json_object_end(j);
}

void capture_json_metrics(vg_json *j, const frame_desc *fd, const frame_info *info, const science_metrics_result *r)
{
    /* Shaped as `vergence optimize`'s metrics.json. */
    vg_json_object_begin(j, "metrics");
    json_field_metrics(j, "h", &r->h, r->h_range_violation, &r->h_d2);
    json_field_metrics(j, "f", &r->f, r->f_range_violation, &r->f_d2);
    /* The correction f - h (what the pipeline adds): a kink of the
     * upsampling in time shows at the keyframes themselves. */
    vg_json_object_begin(j, "correction_second_difference");
    vg_json_num(j, "at_keyframe_boundaries", r->c_d2.boundary);
    vg_json_num(j, "between_keyframes", r->c_d2.between);
    vg_json_num(j, "at_keyframes", r->c_d2.at_key);
    vg_json_num(j, "next_to_keyframes", r->c_d2.next_to_key);
    vg_json_object_end(j);
    vg_json_num(j, "mid_reduction",
                r->h.mid_distortion_jnd > 0 ? 1.0 - r->f.mid_distortion_jnd / r->h.mid_distortion_jnd : 0.0);
    /* f's MID distortion as a share of h's (null when h has none). */
    vg_json_num(j, "mid_ratio", r->h.mid_distortion_jnd > 0 ? r->f.mid_distortion_jnd / r->h.mid_distortion_jnd : NAN);
    vg_json_str(j, "operator", disp_operator_kind_name(fd->op));
    vg_json_str(j, "temporal_occlusion", fd->temporal_depth_only ? "depth" : "links");
    vg_json_str(j, "look_ahead", frame_look_ahead_names[fd->look_ahead]);
    vg_json_str(j, "saliency", info->saliency_computed ? "computed" : "authored");
    vg_json_num(j, "range_lo", r->range_lo);
    vg_json_num(j, "range_hi", r->range_hi);
    vg_json_int(j, "keyframes", r->keyframes);
    vg_json_num(j, "window_seconds", fd->window_seconds);
    vg_json_int(j, "coarse_stride", (long)info->grid_stride);
    vg_json_object_end(j);
}

vg_status capture_json_finish(vg_json *j, const vg_manifest *m)
{
    vg_status st = vg_manifest_files(m, j);
    vg_json_int(j, "validation_messages", gpu_validation_messages());
    vg_json_object_end(j);
    char path[4096];
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, m->dir, m->name);
    if (st == VG_OK)
        st = vg_json_write_file(j, path);
    vg_json_free(j);
    return st;
}

bool capture_json_writes(const char *name)
{
    return !strncmp(name, "frame_", 6) || !strcmp(name, "capture.json") || !strcmp(name, "preview_g.png") ||
           !strcmp(name, "preview_h.png") || !strcmp(name, "preview_f.png");
}
