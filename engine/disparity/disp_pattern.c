#include "disp_pattern.h"

#include <stdio.h>
#include <string.h>

#include "core/log.h"

vg_status disp_pattern_parse(const char *text, const char *option, disp_pattern *out)
{
    *out = (disp_pattern){.text = text, .conv_begin = -1};
    int count = 0;
    for (int i = 0; text[i]; i++) {
        if (text[i] != '%')
            continue;
        if (text[i + 1] == '%') {
            i++;
            continue;
        }
        int j = i + 1, width = 0;
        bool zero = text[j] == '0';
        if (zero)
            j++;
        while (text[j] >= '0' && text[j] <= '9' && width < 100)
            width = width * 10 + (text[j++] - '0');
        if (text[j] != 'd') {
            vg_error("%s '%s': only %%d, %%Nd or %%0Nd conversions are allowed (found '%.*s')", option,
                     text, text[j] ? j - i + 1 : j - i, text + i);
            return VG_ERR_ARG;
        }
        if (width > 18) {
            vg_error("%s '%s': field width %d is too large", option, text, width);
            return VG_ERR_ARG;
        }
        count++;
        out->conv_begin = i;
        out->conv_end = j + 1;
        out->width = width;
        out->zero_pad = zero;
        i = j;
    }
    if (count != 1) {
        vg_error("%s '%s': needs exactly one frame-number conversion such as %%04d (found %d)", option,
                 text, count);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

/* Copies text[a, b) with %% collapsed; returns the new length or -1 on overflow. */
static int copy_literal(const char *text, int a, int b, char *out, size_t len, size_t cap)
{
    for (int i = a; i < b; i++) {
        if (text[i] == '%' && text[i + 1] == '%')
            i++;
        if (len + 1 >= cap)
            return -1;
        out[len++] = text[i];
    }
    return (int)len;
}

vg_status disp_pattern_format(const disp_pattern *p, int frame, char *out, size_t cap)
{
    int len = copy_literal(p->text, 0, p->conv_begin, out, 0, cap);
    char digits[32];
    int n = snprintf(digits, sizeof digits, p->zero_pad ? "%0*d" : "%*d", p->width, frame);
    if (len < 0 || (size_t)len + (size_t)n + 1 >= cap)
        return VG_ERR_ARG;
    memcpy(out + len, digits, (size_t)n);
    len += n;
    len = copy_literal(p->text, p->conv_end, (int)strlen(p->text), out, (size_t)len, cap);
    if (len < 0)
        return VG_ERR_ARG;
    out[len] = 0;
    return VG_OK;
}
