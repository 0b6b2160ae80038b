/* Regression: a failed recording pass must not destroy the workspace's output node
 * arc lengths (d->s), which are inputs of the next recording pass.  Solve a
 * Kirchhoff rod under an end moment (exact circle), force one recording pass to fail
 * (NaN unknowns), then record the solution again in the same workspace: the nodes
 * must be intact and the tip must be the circle's.  Exit 0 on success. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"
#include "tr_internal.h" /* reads the workspace's fields */

int main(void)
{
    const double L = 0.2, EI = 0.0112, M = 0.05;         /* m, N m^2, N m about +y */
    const double rod[6] = {L, EI, EI / 1.3, 1e9, 1e9, 1};
    const double loads[7] = {L, 0, 0, 0, 0, M, 0};
    const double dist[3] = {0, 0, 0};
    char msg[512];
    tr_options o = tr_default_options();
    tr_model *m = NULL;
    tr_data *d;
    double x[64], s_before[64], k = M / EI, tip_x, tip_z;
    int st, i, n;

    gsl_set_error_handler_off();
    if (tr_model_alloc(&m, rod, NULL, 0, loads, 1, dist, &o, msg, sizeof msg) != TR_OK) {
        fprintf(stderr, "model: %s\n", msg);
        return 1;
    }
    d = tr_data_alloc(m, &o, 11, NULL, msg, sizeof msg);
    if (!d) { fprintf(stderr, "data: %s\n", msg); return 1; }
    st = tr_solve(m, d, NULL, NULL);
    if (st < 0) { fprintf(stderr, "solve: %s\n", d->message); return 1; }
    n = d->nnode;
    memcpy(s_before, d->s, (size_t)n * sizeof(double));
    memcpy(x, d->x, (size_t)d->k * sizeof(double));
    for (i = 0; i < d->k; i++) d->x[i] = NAN;             /* poisoned unknowns */
    st = tr_record(m, d);
    if (st == TR_OK) { fprintf(stderr, "record with NaN unknowns succeeded\n"); return 1; }
    for (i = 0; i < 18 * n; i++)                            /* nothing stale handed back */
        if (!isnan(d->pos[i])) { fprintf(stderr, "stale state after failure\n"); return 1; }
    for (i = 0; i < n; i++)
        if (d->s[i] != s_before[i]) { fprintf(stderr, "node %d lost: %g\n", i, d->s[i]); return 1; }
    memcpy(d->x, x, (size_t)d->k * sizeof(double));
    st = tr_record(m, d);
    if (st < 0) { fprintf(stderr, "record: %s\n", d->message); return 1; }
    /* circle of curvature k = M/EI in the x-z plane, bending toward +x for M about +y */
    tip_x = (1 - cos(k * L)) / k;
    tip_z = sin(k * L) / k;
    if (fabs(d->pos[3 * (n - 1)] - tip_x) > 1e-9 * L || fabs(d->pos[3 * (n - 1) + 2] - tip_z) > 1e-9 * L) {
        fprintf(stderr, "tip (%.12g, %.12g), circle (%.12g, %.12g)\n",
                d->pos[3 * (n - 1)], d->pos[3 * (n - 1) + 2], tip_x, tip_z);
        return 1;
    }
    tr_data_free(d);
    tr_model_free(m);
    puts("ok");
    return 0;
}
