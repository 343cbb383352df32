#include "status.h"

const char *vg_status_text(vg_status s)
{
    switch (s) {
#define VG_STATUS_TEXT(name, code, text) case VG_##name: return text;
        VG_STATUS_LIST(VG_STATUS_TEXT)
#undef VG_STATUS_TEXT
    }
    return "unknown status";
}

int vg_status_exit_code(vg_status s)
{
    return (int)s;
}
