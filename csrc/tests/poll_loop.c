/* Ctrl-C reaches a caller's loop of short solves: the poll hook's interval
 * (TR_POLL_INTERVAL) runs across solves, so a loop of solves each shorter than it still
 * calls the hook.  A hook that counts its calls and says stop at the first:
 *   1. a loop of warm solves on one workspace, at most LOOP_MAX of them (a bound by
 *      counting: that many solves of this scene take far longer than the interval), must
 *      end TR_EINTERRUPTED, the hook called exactly once;
 *   2. a batch of BATCH_N warm points with fixed steps (each a lean solve) must return
 *      TR_EINTERRUPTED with the hook called once, every point before the interrupted one
 *      solved and every point from it on marked interrupted (which point that is depends
 *      on the clock: on a loaded machine it may be the first).
 * Prints "ok" and exits 0.  Build from the repository root:
 *   cc -std=c99 -Icsrc csrc/tests/poll_loop.c csrc/tr_*.c $(pkg-config --cflags --libs gsl) \
 *      -lm -o /tmp/poll_loop */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <gsl/gsl_errno.h>

#include "tendonrod.h"
#include "tr_batch.h"

enum { LOOP_MAX = 20000, BATCH_N = 20000 };

static int stop_at_first(void *ctx)
{
    int *calls = (int *)ctx;
    ++*calls;
    return 1;
}

int main(void)
{
    /* a planar cantilever with one displacement-controlled tendon and a tip load (SI) */
    const double L = 0.2, EI = 4.16e-3, r = 0.01;
    const double rod[6] = {L, EI, EI / 1.3, 1e5, 4e4, 1};
    double tendon[TR_TD_NCOL] = {0};
    const double loads[7] = {L, 0.0, 0.0, -0.1, 0.0, 0.0, 0.0};
    const double dist[3] = {0, 0, 0};
    char msg[TR_MSGLEN];
    tr_options o = tr_default_options();
    tr_model *m = NULL;
    tr_data *d;
    int calls = 0, st = TR_OK, i, n, k;
    double *value, *buf;
    int *ibuf;
    tr_batch_in in = {0};
    tr_batch_out out = {0};

    gsl_set_error_handler_off();
    tendon[TR_TD_OFFSET] = r, tendon[TR_TD_EA] = INFINITY, tendon[TR_TD_END] = L;
    tendon[TR_TD_CONTROL] = TR_DISPLACEMENT, tendon[TR_TD_VALUE] = 2e-3;
    o.steps = 16; /* fixed steps: the batch's warm points take the lean solve */
    if (tr_model_alloc(&m, rod, tendon, 1, loads, 1, dist, &o, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "model: %s\n", msg);
        return 1;
    }
    d = tr_data_alloc(m, &o, 2, NULL, msg, sizeof msg);
    if (!d) {
        fprintf(stderr, "data: %s\n", msg);
        return 1;
    }

    /* 1. a loop of warm solves */
    if (!TR_SUCCEEDED(tr_solve(m, d, NULL, NULL))) {
        fprintf(stderr, "first solve: %s\n", tr_data_message(d));
        return 1;
    }
    tr_set_poll(d, stop_at_first, &calls);
    for (n = 0; n < LOOP_MAX && st != TR_EINTERRUPTED; n++) st = tr_solve_warm(m, d);
    if (st != TR_EINTERRUPTED || calls != 1) {
        fprintf(stderr, "loop: %d solves, last status %d, hook called %d times\n", n, st, calls);
        return 1;
    }
    tr_data_free(d);

    /* 2. a batch of lean solves */
    value = (double *)malloc(BATCH_N * sizeof(double));
    buf = (double *)calloc((size_t)BATCH_N * 17, sizeof(double));
    ibuf = (int *)calloc((size_t)BATCH_N * 2, sizeof(int));
    if (!value || !buf || !ibuf) return 1;
    for (i = 0; i < BATCH_N; i++) value[i] = 2e-3 * (1.0 + 1e-3 * (i % 2));
    in.n = BATCH_N, in.value = value, in.warm = 1;
    in.poll = stop_at_first, in.poll_ctx = &calls;
    out.tip_pos = buf, out.tip_rot = buf + 3 * BATCH_N, out.tension = buf + 12 * BATCH_N;
    out.slack = buf + 13 * BATCH_N, out.displacement = buf + 14 * BATCH_N;
    out.residual = buf + 15 * BATCH_N;
    out.status = ibuf, out.nit = ibuf + BATCH_N, out.nfev = ibuf + BATCH_N;
    calls = 0;
    st = tr_batch_solve(m, &o, &in, &out, msg, sizeof msg);
    for (k = 0; k < BATCH_N && out.status[k] != TR_EINTERRUPTED; k++)
        if (!TR_SUCCEEDED(out.status[k])) break;
    for (i = k; i < BATCH_N && out.status[i] == TR_EINTERRUPTED; i++) {}
    if (st != TR_EINTERRUPTED || calls != 1 || k == BATCH_N || i != BATCH_N) {
        fprintf(stderr,
                "batch: status %d, hook called %d times, points solved before the first "
                "interrupted %d, status there %d, first point after it not interrupted %d\n",
                st, calls, k, k < BATCH_N ? out.status[k] : 0, i);
        return 1;
    }
    free(value), free(buf), free(ibuf);
    tr_model_free(m);
    printf("ok\n");
    return 0;
}
