/*
 * batch_harness.c -- the throughput benchmark's scene through the C batch alone (no
 * Python): a three-tendon robot at a ~90 deg bend, tip force over an m x m grid of
 * +-0.1 N, one grid line per call of tr_batch_solve; prints CPU time per solve,
 * iterations and integrations per point.  Used for the "raw C batch" row of
 * bench/results/README_performance.md and for callgrind:
 *
 *   gcc -O2 -std=c99 -D_POSIX_C_SOURCE=200809L -Icsrc $(pkg-config --cflags gsl) \
 *       bench/batch_harness.c csrc/tr_*.c -o /tmp/batch_harness $(pkg-config --libs gsl) -lm
 *   /tmp/batch_harness [m=100] [steps=4] [tol=3e-9] [predict=1] [skip_record=1] [chunk=m]
 *
 * chunk: points per call of tr_batch_solve (m: one grid line per call; m*m: the whole
 * grid in one call, as solve_batch's default chunk of 1000 points does for m <= 31).
 *   valgrind --tool=callgrind /tmp/batch_harness 50 4 3e-9 1 1
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#include "tr_batch.h"

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
    const int m = argc > 1 ? atoi(argv[1]) : 100, steps = argc > 2 ? atoi(argv[2]) : 4;
    const double tol = argc > 3 ? atof(argv[3]) : 3e-9;
    const int pred = argc > 4 ? atoi(argv[4]) : 1, skip = argc > 5 ? atoi(argv[5]) : 1;
    const int chunk = argc > 6 ? atoi(argv[6]) : m;
    const double dia = 0.8e-3, A = M_PI * dia * dia / 4, I = M_PI * pow(dia, 4) / 64, L = 0.2,
                 r = 0.01;
    const double rod[6] = {L, 207e9 * I, 79.6e9 * 2 * I, 207e9 * A, 79.6e9 * A, 0};
    const double q = r * M_PI / 2;
    const double ten[24] = {r, 0,
                            0, INFINITY,
                            L, 0,
                            q, 0,
                            r, 2 * M_PI / 3,
                            0, INFINITY,
                            L, 1,
                            0, 0,
                            r, 4 * M_PI / 3,
                            0, INFINITY,
                            L, 1,
                            0, 0};
    const double load[7] = {L, 0, 0, 0, 0, 0, 0}, dist[3] = {0, 0, 0};
    const int n = m * m;
    tr_options o = tr_default_options();
    tr_model *mod;
    char msg[512];
    double *F, *pos, *rot, *t, *s, *dd, *res, t0, t1;
    int *st, *nit, *nfev, *cold, i, j, c, bad = 0;
    long sn = 0, sf = 0;
    gsl_set_error_handler_off();
    o.steps = steps;
    o.tol = tol;
    if (tr_model_alloc(&mod, rod, ten, 3, load, 1, dist, &o, msg, sizeof msg)) {
        puts(msg);
        return 1;
    }
    F = calloc((size_t)n * 6, sizeof(double));
    pos = malloc((size_t)n * 3 * sizeof(double));
    rot = malloc((size_t)n * 9 * sizeof(double));
    t = malloc((size_t)n * 3 * sizeof(double));
    s = malloc((size_t)n * 3 * sizeof(double));
    dd = malloc((size_t)n * 3 * sizeof(double));
    res = malloc((size_t)n * sizeof(double));
    st = malloc((size_t)n * sizeof(int));
    nit = malloc((size_t)n * sizeof(int));
    nfev = malloc((size_t)n * sizeof(int));
    cold = malloc((size_t)n * sizeof(int));
    for (i = 0; i < m; i++)
        for (j = 0; j < m; j++) {
            F[6 * (i * m + j)] = -0.1 + 0.2 * i / (m - 1);
            F[6 * (i * m + j) + 1] = -0.1 + 0.2 * j / (m - 1);
        }
    t0 = cpu_now();
    for (c = 0; c < n; c += chunk) {
        const int len = n - c < chunk ? n - c : chunk;
        tr_batch_in in = {len, NULL, F + 6 * c, NULL, 1, 1, pred, 0, skip, NULL, NULL};
        tr_batch_out oc = {pos + 3 * c, rot + 9 * c, t + 3 * c, s + 3 * c, dd + 3 * c,
                           res + c,     st + c,      nit + c,   nfev + c,  cold + c,
                           NULL,        0,           NULL,      NULL,      NULL};
        if (tr_batch_solve(mod, &o, &in, &oc, msg, sizeof msg) != TR_OK) {
            puts(msg);
            return 1;
        }
    }
    t1 = cpu_now();
    for (i = 0; i < n; i++) {
        sn += nit[i];
        sf += nfev[i];
        bad += st[i] < 0;
    }
    printf("%d points, rk8 x %d steps, tol %g, predict %d, skip_record %d, chunk %d: %.1f us CPU "
           "per solve (%.0f solves per CPU-second), nit %.2f, nfev %.2f, failed %d\n",
           n, steps, tol, pred, skip, chunk, (t1 - t0) / n * 1e6, n / (t1 - t0), (double)sn / n,
           (double)sf / n, bad);
    tr_model_free(mod);
    free(F);
    free(pos);
    free(rot);
    free(t);
    free(s);
    free(dd);
    free(res);
    free(st);
    free(nit);
    free(nfev);
    free(cold);
    return bad != 0;
}
