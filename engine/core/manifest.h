/* vergence — the manifest of a result (docs/formats.md "Results").
 *
 * A command that writes a result into a folder writes one file last and
 * atomically, its manifest (capture.json, metrics.json, index.html), which
 * lists exactly the files of the result: "files": [{"name", "bytes"}, ...],
 * names relative to the folder. A folder with a manifest holds a complete
 * result; one without does not. A run into a folder that holds an earlier
 * result first removes that manifest, then every file it listed, before it
 * writes anything: nothing of the old result can pass for the new one, and
 * a run that fails or is killed leaves no manifest. A file of the manifest's
 * name that vergence did not write is left alone and the run refused. */
#pragma once
#include "io.h"
#include "json.h"

/* An HTML manifest carries the list in
 * <script type="application/json" id="vergence-files">{"files": [...]}</script>. */
#define VG_MANIFEST_HTML_OPEN "<script type=\"application/json\" id=\"vergence-files\">"
#define VG_MANIFEST_HTML_CLOSE "</script>"

typedef struct vg_manifest {
    char dir[1024];
    char name[256];              /* the manifest's file name in dir */
    vg_write_watch watch;        /* every file written under dir from begin on */
} vg_manifest;

/* Prepares dir (created if missing) for a result whose manifest is
 * dir/name: removes an earlier manifest and the files it listed, then
 * records every file written under dir. */
vg_status vg_manifest_begin(vg_manifest *m, const char *dir, const char *name);
/* The files written under dir so far (the manifest itself excepted), as the
 * member "files" of the object j is writing. VG_ERR_NOMEM when one went
 * unrecorded: a manifest is exact or not written. */
vg_status vg_manifest_files(const vg_manifest *m, vg_json *j);
/* Stops recording. */
void vg_manifest_end(vg_manifest *m);

/* Removes the manifest dir/name and then the files it lists (names with
 * ".." or a leading '/' are skipped: a manifest cannot reach out of its
 * folder); nothing when there is none. VG_ERR_ARG, removing nothing, when
 * dir/name is not vergence's (no list, no "vergence" member, no vergence
 * title). */
vg_status vg_manifest_clear(const char *dir, const char *name);

/* ------------------------------------------------------------------------- */
/* Inputs against outputs                                                    */
/* ------------------------------------------------------------------------- */

/* A command's inputs (paths with the flag that named them), against which
 * every output is checked before any work: an output that is an input
 * (after links; by inode when both exist) is refused with one line, exit 2. */
typedef struct vg_inputs {
    struct vg_input {
        char path[1024];         /* canonical */
        char given[1024];        /* as given */
        char label[64];          /* "--scene", "--g", ... */
    } *items;
    int count, cap;
} vg_inputs;

vg_status vg_inputs_add(vg_inputs *in, const char *label, const char *path);
/* Output file `path` (named by `label`) is not an input. */
vg_status vg_inputs_check(const vg_inputs *in, const char *label, const char *path);
/* No input lies in the output folder dir under a name the command writes
 * there (writes(name relative to dir)), nor among the files an earlier
 * result's manifest dir/manifest lists (they would be removed; manifest NULL:
 * the command writes none). */
vg_status vg_inputs_check_dir(const vg_inputs *in, const char *label, const char *dir, const char *manifest,
                              bool (*writes)(const char *name));
void vg_inputs_free(vg_inputs *in);
