/* bvh_threads.c — the threads the BVH build shares its work among: a job
 * run on t = 0 .. threads - 1 (the caller's thread is t = 0), and the
 * default count. Below bvh.c and bvh_wide.c, which both share work out, so
 * that neither calls back into the other. */
#include "st_bvh.h"

#include <pthread.h>
#include <unistd.h>

/* Below this many triangles the default is one thread: starting threads and
 * sharing the work out costs more than it saves. */
#define PARALLEL_MIN_TRIS 16384u

typedef struct job_thread {
    st_bvh_job *job;
    void *ctx;
    unsigned t;
} job_thread;

static void *job_main(void *arg)
{
    const job_thread *j = arg;
    j->job(j->ctx, j->t);
    return NULL;
}

void st_bvh_parallel(unsigned threads, st_bvh_job *job, void *ctx)
{
    pthread_t tid[ST_BVH_MAX_THREADS];
    job_thread arg[ST_BVH_MAX_THREADS];
    int started[ST_BVH_MAX_THREADS] = {0};
    threads = threads < 1u ? 1u : threads > ST_BVH_MAX_THREADS ? ST_BVH_MAX_THREADS : threads;
    for (unsigned t = 1; t < threads; ++t) {
        arg[t] = (job_thread){job, ctx, t};
        started[t] = pthread_create(&tid[t], NULL, job_main, &arg[t]) == 0;
    }
    job(ctx, 0);
    for (unsigned t = 1; t < threads; ++t) {
        if (started[t])
            pthread_join(tid[t], NULL);
        else
            job(ctx, t);
    }
}

unsigned st_bvh_threads(unsigned threads, st_u64 work)
{
    if (threads == 0u && work < PARALLEL_MIN_TRIS)
        threads = 1u; /* without asking: sysconf reads sysfs, a few syscalls */
    if (threads == 0u) {
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        threads = cpus < 1 ? 1u : (unsigned)cpus;
    }
    return threads > ST_BVH_MAX_THREADS ? ST_BVH_MAX_THREADS : threads;
}
