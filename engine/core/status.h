/* vergence — status codes shared by every module.
 *
 * One X-macro table names every failure class; tests assert on the code,
 * never on message text. Library functions return a vg_status and log one
 * line naming the cause; only the CLI turns a status into an exit code. */
#pragma once

#define VG_STATUS_LIST(X)                                                   \
    X(OK,         0, "ok")                                                  \
    X(ERR_ARG,    2, "bad command-line argument")                           \
    X(ERR_IO,     3, "file could not be read or written")                   \
    X(ERR_FORMAT, 4, "malformed input file")                                \
    X(ERR_NOMEM,  5, "out of memory")                                       \
    X(ERR_VULKAN, 6, "Vulkan call failed")                                  \
    X(ERR_DEVICE, 7, "device lacks a required feature")                     \
    X(ERR_GRAPH,  8, "frame graph is invalid")                              \
    X(ERR_VALIDATION, 9, "Vulkan validation reported messages")             \
    X(ERR_UNSUPPORTED, 10, "unsupported input")

typedef enum vg_status {
#define VG_STATUS_ENUM(name, code, text) VG_##name = code,
    VG_STATUS_LIST(VG_STATUS_ENUM)
#undef VG_STATUS_ENUM
} vg_status;

/* Human text of a status ("malformed input file"). */
const char *vg_status_text(vg_status s);

/* Process exit code of a status: 0 for OK, 2..10 otherwise (never >= 128). */
int vg_status_exit_code(vg_status s);
