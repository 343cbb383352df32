/* vergence — frame file patterns in the printf style ffmpeg uses for image
 * sequences: exactly one integer conversion %d, %4d or %04d; %% is a literal
 * percent sign. "in/g_%04d.pfm" names in/g_0007.pfm for frame 7. */
#pragma once
#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

typedef struct disp_pattern {
    const char *text; /* the pattern as given */
    int conv_begin;   /* offset of the '%' of the conversion */
    int conv_end;     /* offset just past its 'd' */
    int width;        /* minimum digits, 0 = none */
    bool zero_pad;
} disp_pattern;

/* Checks the pattern; option names the flag in the error ("--g"). */
vg_status disp_pattern_parse(const char *text, const char *option, disp_pattern *out);
/* The file name of a frame (>= 0); VG_ERR_ARG when it does not fit in cap. */
vg_status disp_pattern_format(const disp_pattern *p, int frame, char *out, size_t cap);
