/* vergence — capture.json (docs/formats.md), written last so that a folder
 * holding it is a complete capture: by `vergence capture` and by each run
 * of `vergence demo`, from the same sections. */
#pragma once
#include "capture_log.h"
#include "core/json.h"
#include "core/manifest.h"

/* The header every capture.json starts with: version, scene, size, frame
 * rate and keyframes, the frames recorded, the device and the display. */
void capture_json_header(vg_json *j, const char *scene_path, const scene *s, const frame_desc *fd, const gpu *g,
                         const capture_log *log);
/* The camera of every recorded frame. */
void capture_json_cameras(vg_json *j, const capture_log *log);
/* Per pass: median and mean ms over the frames; the frame's median wall ms. */
void capture_json_passes(vg_json *j, const capture_log *log);
/* The shadow map: its size, its texel in metres and in the screen pixels it
 * covers where it lands ("shadow"; capture_log_shadow). */
void capture_json_shadow(vg_json *j, const capture_log *log);
/* The stereo pair: how it was made, the cascade's stages, the warp's error,
 * holes and PSNR against the two-camera reference (m). */
void capture_json_stereo(vg_json *j, const frame_desc *fd, const warp_metrics *m);
/* The science metrics of h and f ("metrics"). */
void capture_json_metrics(vg_json *j, const frame_desc *fd, const frame_info *info, const science_metrics_result *r);
/* Ends the object with the files of the result (the manifest's list) and
 * the validation count, and writes it as the manifest m (atomically, last);
 * frees j. */
vg_status capture_json_finish(vg_json *j, const vg_manifest *m);
/* The names a capture writes into its folder (capture.json, frame_*, preview_{g,h,f}.png). */
bool capture_json_writes(const char *name);
