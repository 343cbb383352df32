#include "texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


#include "core/log.h"

/* ------------------------------------------------------------------------- */
/* Noise                                                                     */
/* ------------------------------------------------------------------------- */

/* Integer hash (lowbias32): the same bits on every machine, unlike rand(). */
static uint32_t hash32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

static double lattice(int x, int y, int period, uint32_t seed)
{
    uint32_t ix = (uint32_t)(((x % period) + period) % period);
    uint32_t iy = (uint32_t)(((y % period) + period) % period);
    return hash32(ix * 0x9e3779b1U ^ hash32(iy + seed * 0x85ebca6bU)) / 4294967295.0;
}

/* Value noise in [0, 1] with `period` cells across the unit square, so it tiles. */
static double value_noise(double u, double v, int period, uint32_t seed)
{
    double x = u * period, y = v * period;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    double fx = x - x0, fy = y - y0;
    fx = fx * fx * (3 - 2 * fx);
    fy = fy * fy * (3 - 2 * fy);
    double a = lattice(x0, y0, period, seed), b = lattice(x0 + 1, y0, period, seed);
    double c = lattice(x0, y0 + 1, period, seed), d = lattice(x0 + 1, y0 + 1, period, seed);
    return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy;
}

/* Fractal sum of octaves, normalised to [0, 1]. */
static double fbm(double u, double v, int period, int octaves, uint32_t seed)
{
    double sum = 0, amp = 1, norm = 0;
    for (int o = 0; o < octaves; o++) {
        sum += amp * value_noise(u, v, period << o, seed + (uint32_t)o);
        norm += amp;
        amp *= 0.5;
    }
    return sum / norm;
}

/* Per-pixel grain in [-1, 1]. */
static double grain(int x, int y, uint32_t seed)
{
    return 2 * lattice(x, y, 1 << 20, seed) - 1;
}

static double mix(double a, double b, double t)
{
    return a + (b - a) * t;
}

static double clamp01(double x)
{
    return x < 0 ? 0 : x > 1 ? 1 : x;
}

/* Coverage of a line of half-width w (texels) at distance d, with a one-texel
 * soft edge so the line survives minification without shimmering. */
static double line_cover(double d, double w)
{
    return clamp01(w + 0.5 - d);
}

/* Distance in texels from x to the nearest multiple of spacing. */
static double dist_to_grid(double x, double spacing)
{
    double r = fmod(x, spacing);
    return r < spacing - r ? r : spacing - r;
}

/* ------------------------------------------------------------------------- */
/* Patterns                                                                  */
/* ------------------------------------------------------------------------- */

typedef struct rgb {
    double r, g, b;
} rgb;

static rgb rgb_mix(rgb a, rgb b, double t)
{
    return (rgb){mix(a.r, b.r, t), mix(a.g, b.g, t), mix(a.b, b.b, t)};
}

/* Meadow (balloon scene): large soft patches of two greens, a hint of dry
 * yellow, fine grain. Low contrast on purpose: the house, tree and balloon
 * are the subject, the ground only has to read as ground in depth. */
static rgb grass(int x, int y, int size)
{
    double u = (x + 0.5) / size, v = (y + 0.5) / size;
    double patches = fbm(u, v, 4, 4, 11), dry = fbm(u, v, 3, 3, 29);
    rgb dark = {82, 128, 58}, light = {118, 162, 76}, straw = {150, 160, 86};
    rgb c = rgb_mix(dark, light, clamp01((patches - 0.3) * 2.2));
    c = rgb_mix(c, straw, 0.35 * clamp01((dry - 0.55) * 4));
    double g = 7 * grain(x, y, 3);
    return (rgb){c.r + g, c.g + g * 1.2, c.b + g * 0.6};
}

/* Paving (cubes scene): one tile is 2 x 2 squares of 1 m, two close tones,
 * thin joints, faint stone mottling. */
static rgb checker(int x, int y, int size)
{
    int half = size / 2;
    bool odd = ((x / half) + (y / half)) & 1;
    double u = (x + 0.5) / size, v = (y + 0.5) / size;
    rgb a = {212, 204, 188}, b = {188, 180, 164}, joint = {150, 144, 132};
    rgb c = odd ? b : a;
    double m = fbm(u, v, 8, 3, 41) - 0.5;
    c = (rgb){c.r + 14 * m, c.g + 14 * m, c.b + 12 * m};
    double d = fmin(dist_to_grid(x + 0.5, half), dist_to_grid(y + 0.5, half));
    c = rgb_mix(c, joint, line_cover(d, 1.0));
    double g = 4 * grain(x, y, 5);
    return (rgb){c.r + g, c.g + g, c.b + g};
}

/* Sports field (arena, paper Fig. 6): a tile is 4 x 4 m; a faint line every
 * metre and a bold chalk line at the tile edges give the player a ruler on
 * the ground for judging where the ball lands. */
static rgb field(int x, int y, int size)
{
    double u = (x + 0.5) / size, v = (y + 0.5) / size, metre = size / 4.0;
    double patches = fbm(u, v, 4, 4, 53);
    rgb dark = {78, 134, 70}, light = {98, 152, 82}, minor = {140, 184, 122}, chalk = {236, 238, 226};
    rgb c = rgb_mix(dark, light, clamp01((patches - 0.3) * 2));
    double dm = fmin(dist_to_grid(x + 0.5, metre), dist_to_grid(y + 0.5, metre));
    c = rgb_mix(c, minor, 0.8 * line_cover(dm, 0.75));
    double dt = fmin(dist_to_grid(x + 0.5, size), dist_to_grid(y + 0.5, size));
    c = rgb_mix(c, chalk, line_cover(dt, 1.5));
    double g = 5 * grain(x, y, 7);
    return (rgb){c.r + g, c.g + g * 1.1, c.b + g * 0.7};
}

static uint8_t to_byte(double v)
{
    long i = lround(v);
    return (uint8_t)(i < 0 ? 0 : i > 255 ? 255 : i);
}

/* ------------------------------------------------------------------------- */
/* Public                                                                    */
/* ------------------------------------------------------------------------- */

vg_status texture_make(texture *t, texture_kind kind, int size)
{
    *t = (texture){0};
    if (size < 16 || size > 4096 || (size & (size - 1))) {
        vg_error("texture size %d is not a power of two in [16, 4096]", size);
        return VG_ERR_ARG;
    }
    t->rgb = malloc((size_t)size * (size_t)size * 3);
    if (!t->rgb)
        return VG_ERR_NOMEM;
    t->width = t->height = size;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            rgb c;
            switch (kind) {
            case TEXTURE_CHECKER: c = checker(x, y, size); break;
            case TEXTURE_FIELD: c = field(x, y, size); break;
            case TEXTURE_DEFAULT:
            case TEXTURE_GRASS:
            default: c = grass(x, y, size); break;
            }
            uint8_t *p = t->rgb + ((size_t)y * (size_t)size + (size_t)x) * 3;
            p[0] = to_byte(c.r);
            p[1] = to_byte(c.g);
            p[2] = to_byte(c.b);
        }
    return VG_OK;
}

void texture_free(texture *t)
{
    if (!t)
        return;
    free(t->rgb);
    *t = (texture){0};
}

