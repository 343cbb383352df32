/* vergence — game window: GLFW + swapchain + input + record/replay. */
#include "window.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "core/clock.h"
#include "core/io.h"
#include "core/log.h"

#define WINDOW_QUEUE 64

struct window {
    GLFWwindow *glfw;
    gpu *gpu;
    swapchain sc;
    bool resized;
    double fps;
    /* live input, stamped when the tick collects it */
    window_event queue[WINDOW_QUEUE];
    int queued;
    /* ticks */
    long tick;
    double last_ms, tick_seconds, wall_s;
    /* scripted input */
    window_event *script;
    int script_count, script_next;
    bool fixed_step;
    long frame_ticks;           /* per frame at a fixed step */
    FILE *record;
    char record_path[1024];
};

/* ------------------------------------------------------------------------- */
/* Key names                                                                 */
/* ------------------------------------------------------------------------- */

static const struct {
    int key;
    const char *name;
} k_named[] = {
    {GLFW_KEY_SPACE, "SPACE"}, {GLFW_KEY_ESCAPE, "ESCAPE"}, {GLFW_KEY_ENTER, "ENTER"},
    {GLFW_KEY_TAB, "TAB"},     {GLFW_KEY_LEFT, "LEFT"},     {GLFW_KEY_RIGHT, "RIGHT"},
    {GLFW_KEY_UP, "UP"},       {GLFW_KEY_DOWN, "DOWN"},
};

const char *window_key_name(int key)
{
    static const char *const letters[] = {"A", "B", "C", "D", "E", "F", "G", "H", "I", "J", "K", "L", "M",
                                          "N", "O", "P", "Q", "R", "S", "T", "U", "V", "W", "X", "Y", "Z"};
    static const char *const digits[] = {"0", "1", "2", "3", "4", "5", "6", "7", "8", "9"};
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z)
        return letters[key - GLFW_KEY_A];
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9)
        return digits[key - GLFW_KEY_0];
    for (size_t i = 0; i < sizeof k_named / sizeof k_named[0]; i++)
        if (k_named[i].key == key)
            return k_named[i].name;
    return NULL;
}

static int key_from_name(const char *name)
{
    for (int k = GLFW_KEY_SPACE; k <= GLFW_KEY_LAST; k++) {
        const char *n = window_key_name(k);
        if (n && !strcmp(n, name))
            return k;
    }
    return -1;
}

/* ------------------------------------------------------------------------- */
/* Scripted input                                                            */
/* ------------------------------------------------------------------------- */

static vg_status script_load(window *w, const char *path)
{
    uint8_t *data;
    size_t size;
    vg_status st = vg_file_read(path, &data, &size);
    if (st != VG_OK)
        return st;
    int cap = 1;
    for (size_t i = 0; i < size; i++)
        cap += data[i] == '\n';
    w->script = calloc((size_t)cap, sizeof *w->script);
    if (!w->script) {
        free(data);
        return VG_ERR_NOMEM;
    }
    char *line = (char *)data;
    long last = 0;
    for (int ln = 1; line && *line; ln++) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        char kind[16] = "", arg[32] = "";
        long tick;
        double x, y;
        int n = sscanf(line, "%ld %15s %31s", &tick, kind, arg);
        window_event ev = {.tick = tick};
        bool blank = strspn(line, " \t\r") == strlen(line);
        if (!blank) {
            bool ok = n == 3 && tick >= last;
            if (ok && !strcmp(kind, "key")) {
                ev.kind = WINDOW_EVENT_KEY;
                ev.key = key_from_name(arg);
                ok = ev.key >= 0;
            } else if (ok && !strcmp(kind, "click")) {
                ok = sscanf(line, "%ld %15s %lf %lf", &tick, kind, &x, &y) == 4 && x >= 0 && x <= 1 && y >= 0 &&
                     y <= 1;
                ev = (window_event){.kind = WINDOW_EVENT_CLICK, .x = x, .y = y, .tick = tick};
            } else {
                ok = false;
            }
            if (!ok) {
                vg_error("%s:%d: not an event ('TICK key NAME' or 'TICK click X Y', ticks in order, X and Y "
                         "in [0, 1])", path, ln);
                free(data);
                return VG_ERR_FORMAT;
            }
            last = tick;
            w->script[w->script_count++] = ev;
        }
        line = end ? end + 1 : NULL;
    }
    free(data);
    return VG_OK;
}

static void record_event(window *w, const window_event *ev)
{
    if (!w->record)
        return;
    if (ev->kind == WINDOW_EVENT_KEY && window_key_name(ev->key))
        fprintf(w->record, "%ld key %s\n", ev->tick, window_key_name(ev->key));
    else if (ev->kind == WINDOW_EVENT_CLICK)
        fprintf(w->record, "%ld click %.5f %.5f\n", ev->tick, ev->x, ev->y);
    fflush(w->record);
}

/* ------------------------------------------------------------------------- */
/* GLFW callbacks                                                            */
/* ------------------------------------------------------------------------- */

static char g_glfw_error[256];

static void on_glfw_error(int code, const char *text)
{
    (void)code;
    snprintf(g_glfw_error, sizeof g_glfw_error, "%s", text);
}

static void push(window *w, window_event ev)
{
    if (w->queued < WINDOW_QUEUE)
        w->queue[w->queued++] = ev;
}

static void on_key(GLFWwindow *gw, int key, int scancode, int action, int mods)
{
    (void)scancode, (void)mods;
    if (action == GLFW_PRESS)
        push(glfwGetWindowUserPointer(gw), (window_event){.kind = WINDOW_EVENT_KEY, .key = key});
}

static void on_button(GLFWwindow *gw, int button, int action, int mods)
{
    (void)mods;
    if (button != GLFW_MOUSE_BUTTON_LEFT || action != GLFW_PRESS)
        return;
    double x, y;
    int ww, wh;
    glfwGetCursorPos(gw, &x, &y);
    glfwGetWindowSize(gw, &ww, &wh);
    if (ww > 0 && wh > 0)
        push(glfwGetWindowUserPointer(gw), (window_event){.kind = WINDOW_EVENT_CLICK, .x = x / ww, .y = y / wh});
}

static void on_resize(GLFWwindow *gw, int width, int height)
{
    (void)width, (void)height;
    ((window *)glfwGetWindowUserPointer(gw))->resized = true;
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

static vg_status open_window(window *w, const window_desc *d)
{
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        vg_error("no display to open a window on: %s (run it on a desktop, or under xvfb-run)",
                 g_glfw_error[0] ? g_glfw_error : "GLFW could not start");
        return VG_ERR_DEVICE;
    }
    if (!glfwVulkanSupported()) {
        vg_error("the window system has no Vulkan surface support (GLFW: %s)",
                 g_glfw_error[0] ? g_glfw_error : "no Vulkan loader");
        return VG_ERR_DEVICE;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    GLFWmonitor *monitor = d->fullscreen ? glfwGetPrimaryMonitor() : NULL;
    const GLFWvidmode *mode = monitor ? glfwGetVideoMode(monitor) : NULL;
    int width = mode ? mode->width : d->width > 0 ? d->width : 1280;
    int height = mode ? mode->height : d->height > 0 ? d->height : 720;
    w->glfw = glfwCreateWindow(width, height, d->title ? d->title : "vergence", monitor, NULL);
    if (!w->glfw) {
        vg_error("cannot open a %dx%d window: %s", width, height, g_glfw_error);
        return VG_ERR_DEVICE;
    }
    glfwSetWindowUserPointer(w->glfw, w);
    glfwSetKeyCallback(w->glfw, on_key);
    glfwSetMouseButtonCallback(w->glfw, on_button);
    glfwSetFramebufferSizeCallback(w->glfw, on_resize);
    return VG_OK;
}

vg_status window_create(const window_desc *d, window **out)
{
    *out = NULL;
    window *w = calloc(1, sizeof *w);
    if (!w)
        return VG_ERR_NOMEM;
    w->fps = d->fps > 0 ? d->fps : 60.0;
    vg_status st = VG_OK;
    if (d->replay) {
        st = script_load(w, d->replay);
        w->fixed_step = true;
        w->frame_ticks = d->frame_ticks > 0 ? d->frame_ticks : 1;
    }
    if (st == VG_OK && d->record) {
        snprintf(w->record_path, sizeof w->record_path, "%s", d->record);
        w->record = fopen(d->record, "w");
        if (!w->record) {
            vg_error("%s: cannot write the recording", d->record);
            st = VG_ERR_IO;
        } else {
            fprintf(w->record, "# vergence replay: TICK key NAME | TICK click X Y (ticks of 1/%g s)\n", w->fps);
        }
    }
    if (st == VG_OK)
        st = open_window(w, d);
    uint32_t ext_count = 0;
    const char **ext = st == VG_OK ? glfwGetRequiredInstanceExtensions(&ext_count) : NULL;
    if (st == VG_OK)
        st = gpu_create(&(gpu_desc){
            .validate = d->gpu->validate, .use_device = d->gpu->device >= 0, .device_index = d->gpu->device,
            .instance_extensions = ext, .instance_extension_count = ext_count, .need_swapchain = true}, &w->gpu);
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    if (st == VG_OK && glfwCreateWindowSurface(w->gpu->instance, w->glfw, NULL, &surface) != VK_SUCCESS) {
        vg_error("cannot create a Vulkan surface for the window (%s)", g_glfw_error);
        st = VG_ERR_VULKAN;
    }
    if (st == VG_OK) {
        int fw, fh;
        glfwGetFramebufferSize(w->glfw, &fw, &fh);
        st = swapchain_create(w->gpu, &(swapchain_desc){.surface = surface, .width = (uint32_t)fw,
                                                        .height = (uint32_t)fh}, &w->sc);
    }
    if (st != VG_OK) {
        gpu *g = w->gpu;
        window_destroy(w);
        gpu_destroy(g); /* after the surface it made */
        return st;
    }
    w->last_ms = vg_now_ms();
    w->tick = -1;
    *out = w;
    return VG_OK;
}

void window_destroy(window *w)
{
    if (!w)
        return;
    swapchain_destroy(&w->sc);
    /* The context is the caller's (gpu_cli_close counts validation messages):
     * take window_gpu() before destroying the window. */
    if (w->glfw)
        glfwDestroyWindow(w->glfw);
    glfwTerminate();
    if (w->record)
        fclose(w->record);
    free(w->script);
    free(w);
}

gpu *window_gpu(window *w) { return w->gpu; }
VkFormat window_format(const window *w) { return w->sc.format; }
VkExtent2D window_extent(const window *w) { return w->sc.extent; }
bool window_replaying(const window *w) { return w->script_next < w->script_count; }
bool window_closed(window *w) { return glfwWindowShouldClose(w->glfw); }
double window_tick_seconds(const window *w) { return w->tick_seconds; }

/* ------------------------------------------------------------------------- */
/* Ticks and frames                                                          */
/* ------------------------------------------------------------------------- */

void window_pump(window *w)
{
    (void)w;
    glfwPollEvents();
}

long window_tick(window *w, window_event *events, int cap, int *count)
{
    glfwPollEvents();
    /* Minimised: nothing to draw until it comes back. */
    for (int fw = 0, fh = 0; !glfwWindowShouldClose(w->glfw);) {
        glfwGetFramebufferSize(w->glfw, &fw, &fh);
        if (fw > 0 && fh > 0)
            break;
        glfwWaitEvents();
        w->last_ms = vg_now_ms();
    }
    double now = vg_now_ms();
    long steps = w->fixed_step ? w->frame_ticks : 1;
    if (!w->fixed_step) {
        /* Whole ticks of wall time, at most 6 (0.1 s) per frame so a stall
         * (making a frame for a new mode) is no jump. Game time is ticks /
         * fps either way, so a recording replays at the same game times. */
        w->wall_s += (now - w->last_ms) * 1e-3;
        steps = (long)floor(w->wall_s * w->fps);
        w->wall_s = steps > 6 ? 0.0 : w->wall_s - steps / w->fps;
        steps = steps > 6 ? 6 : steps;
    }
    w->tick += steps;
    w->tick_seconds = steps / w->fps;
    w->last_ms = now;
    int n = 0;
    while (w->script_next < w->script_count && w->script[w->script_next].tick <= w->tick && n < cap)
        events[n++] = w->script[w->script_next++];
    for (int i = 0; i < w->queued && n < cap; i++) {
        w->queue[i].tick = w->tick;
        record_event(w, &w->queue[i]);
        events[n++] = w->queue[i];
    }
    w->queued = 0;
    *count = n;
    return w->tick;
}

vg_status window_acquire(window *w, frame_target *target, bool *stale)
{
    VkSemaphore acquired = VK_NULL_HANDLE;
    *stale = w->resized;
    if (*stale)
        return VG_OK;
    vg_status st = swapchain_acquire(&w->sc, &acquired, stale);
    if (st != VG_OK || *stale)
        return st;
    *target = (frame_target){
        .image = w->sc.images[w->sc.image], .view = w->sc.views[w->sc.image],
        .wait = acquired, .signal = w->sc.rendered[w->sc.image],
    };
    return VG_OK;
}

vg_status window_present(window *w, bool *stale)
{
    vg_status st = swapchain_present(&w->sc, stale);
    *stale = *stale || w->resized;
    return st;
}

vg_status window_rebuild(window *w)
{
    int fw, fh;
    glfwGetFramebufferSize(w->glfw, &fw, &fh);
    w->resized = false;
    return swapchain_resize(&w->sc, (uint32_t)fw, (uint32_t)fh);
}
