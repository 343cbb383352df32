/* vergence — monotonic time. */
#pragma once
#include <stdint.h>
#include <time.h>

static inline uint64_t vg_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

static inline double vg_now_ms(void)
{
    return (double)vg_now_ns() * 1e-6;
}
