#include "parallel.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <unistd.h>

#include "log.h"

/* ------------------------------------------------------------------------- */
/* Pool state                                                                */
/* ------------------------------------------------------------------------- */

struct vg_pool {
    int threads;
    pthread_t *workers; /* threads - 1; the caller is the last worker */
    pthread_mutex_t mutex;
    pthread_cond_t wake, done;
    /* The current job; written under the mutex before the generation bumps. */
    vg_block_fn fn;
    void *ctx;
    int count, block_size, blocks;
    atomic_int next_block;
    int busy;              /* workers still inside the current job */
    unsigned long generation;
    bool quit;
};

int vg_cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (int)n;
}

/* Claims blocks until none is left; the claim order varies between runs but
 * every block is run exactly once, so gathers stay deterministic. */
static void run_blocks(vg_pool *p)
{
    for (;;) {
        int b = atomic_fetch_add(&p->next_block, 1);
        if (b >= p->blocks)
            return;
        int begin = b * p->block_size;
        int end = begin + p->block_size < p->count ? begin + p->block_size : p->count;
        p->fn(p->ctx, b, begin, end);
    }
}

static void *worker_main(void *arg)
{
    vg_pool *p = arg;
    unsigned long seen = 0;
    pthread_mutex_lock(&p->mutex);
    for (;;) {
        while (!p->quit && p->generation == seen)
            pthread_cond_wait(&p->wake, &p->mutex);
        if (p->quit)
            break;
        seen = p->generation;
        pthread_mutex_unlock(&p->mutex);
        run_blocks(p);
        pthread_mutex_lock(&p->mutex);
        if (--p->busy == 0)
            pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->mutex);
    return NULL;
}

/* ------------------------------------------------------------------------- */
/* API                                                                       */
/* ------------------------------------------------------------------------- */

vg_status vg_pool_create(const vg_pool_desc *desc, vg_pool **out)
{
    *out = NULL;
    int threads = desc && desc->threads > 0 ? desc->threads : vg_cpu_count();
    vg_pool *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->threads = threads;
    pthread_mutex_init(&p->mutex, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->done, NULL);
    atomic_init(&p->next_block, 0);
    if (threads > 1) {
        p->workers = calloc((size_t)threads - 1, sizeof *p->workers);
        if (!p->workers) {
            vg_pool_destroy(p);
            return VG_ERR_NOMEM;
        }
        for (int i = 0; i < threads - 1; i++) {
            if (pthread_create(&p->workers[i], NULL, worker_main, p) != 0) {
                vg_error("thread pool: cannot start worker %d of %d", i + 1, threads - 1);
                p->threads = i + 1; /* only the started ones get joined */
                vg_pool_destroy(p);
                return VG_ERR_NOMEM;
            }
        }
    }
    *out = p;
    return VG_OK;
}

void vg_pool_destroy(vg_pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mutex);
    p->quit = true;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mutex);
    if (p->workers)
        for (int i = 0; i < p->threads - 1; i++)
            pthread_join(p->workers[i], NULL);
    free(p->workers);
    pthread_cond_destroy(&p->wake);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->mutex);
    free(p);
}

int vg_pool_threads(const vg_pool *p)
{
    return p ? p->threads : 1;
}

void vg_parallel_for(vg_pool *p, int count, int block_size, vg_block_fn fn, void *ctx)
{
    if (count <= 0)
        return;
    if (block_size <= 0)
        block_size = count;
    int blocks = vg_block_count(count, block_size);
    if (!p || p->threads == 1 || blocks == 1) {
        for (int b = 0; b < blocks; b++) {
            int begin = b * block_size;
            fn(ctx, b, begin, begin + block_size < count ? begin + block_size : count);
        }
        return;
    }
    pthread_mutex_lock(&p->mutex);
    p->fn = fn;
    p->ctx = ctx;
    p->count = count;
    p->block_size = block_size;
    p->blocks = blocks;
    atomic_store(&p->next_block, 0);
    p->busy = p->threads - 1;
    p->generation++;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mutex);

    run_blocks(p);

    pthread_mutex_lock(&p->mutex);
    while (p->busy > 0)
        pthread_cond_wait(&p->done, &p->mutex);
    pthread_mutex_unlock(&p->mutex);
}

double vg_sum_ordered(const double *partial, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += partial[i];
    return s;
}
