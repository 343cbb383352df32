/* vergence — faults injected by tests, and the features they pretend are
 * missing (docs/architecture.md "Validation and leak tests"):
 *
 *   VERGENCE_FAULT=NAME:N[,NAME:N...]
 *     device-lost:N  queue submission N and every later one fail as a lost device
 *     enospc:N       file writes fail with ENOSPC ("no space left") once N bytes
 *                    were written in all (a disk that fills up mid-write)
 *     kill:N         the process kills itself (SIGKILL, as kill -9) right after
 *                    its N-th finished file (a study: its N-th line, a new
 *                    file's header included)
 *     present-ms:N   each frame of a hit-study flight is presented N ms late
 *                    (a display that cannot hold 60 Hz: game/play/flight.h)
 *   VERGENCE_DISABLE=tessellation,multiview,timestamps,indirect
 *     and any requirement the requirements query names: dynamicRendering,
 *     synchronization2, maintenance4, hostQueryReset, scalarBlockLayout,
 *     shaderStorageImageWriteWithoutFormat, drawIndirectFirstInstance,
 *     VK_KHR_push_descriptor, VK_KHR_swapchain (gpu_missing_features)
 *
 * A name these lists do not hold is an error (vg_fault_check), not a fault
 * silently not injected. */
#pragma once
#include <stdbool.h>
#include <stddef.h>

#include "status.h"

/* Checks both variables; one error line and VG_ERR_ARG for a bad entry. */
vg_status vg_fault_check(void);
/* N of fault `name`, -1 when it is not injected. */
long vg_fault(const char *name);
/* Whether VERGENCE_DISABLE names `feature`. */
bool vg_fault_disabled(const char *feature);

/* The file-write faults, for the writers of core/io.h and the study logs:
 * how many of `n` bytes may still be written (all of them without enospc)... */
size_t vg_fault_write_allowance(size_t n);
/* ... and a file was finished (kill:N counts these). */
void vg_fault_file_done(void);
